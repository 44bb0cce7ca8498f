"""Shared pytest configuration: the hypothesis profiles, and which build of persistri is under test.

``HYPOTHESIS_PROFILE=ci`` (set by ``make test`` under CI) is thorough;
``dev`` (the default) is quick.  Neither has a deadline: persistri's tests check
results and operation counts, never wall-clock time.
"""

from __future__ import annotations

import gc
import os
from collections.abc import Iterator

import pytest
from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci",
    max_examples=100,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    print_blob=True,
)
settings.register_profile(
    "dev",
    max_examples=40,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "dev"))


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """On the compiled twin (``PERSISTRI_TWIN`` set), leave out the tests marked ``build_independent``.

    Their subject is code the twin does not compile (``tools/compiled_twin.py`` lists what it does): the
    conformance engine of ``persistri.spec`` run against broken outsider structures, the backends kept
    pure Python (association list, HAMT, the adapters of immutables and pyrsistent).  The same Python
    statements would run again under the same tests; every test of a compiled module runs on both builds.
    """
    if not os.environ.get("PERSISTRI_TWIN"):
        return
    kept, dropped = [], []
    for item in items:
        (dropped if item.get_closest_marker("build_independent") else kept).append(item)
    if dropped:
        config.hook.pytest_deselected(items=dropped)
        items[:] = kept


def pytest_report_header() -> str:
    """Which persistri the suite runs on: interpreted, or the compiled twin (``make test`` runs both)."""
    from persistri.impl.bench.hull import persistri_build

    build = persistri_build()
    if os.environ.get("PERSISTRI_TWIN"):
        return f"persistri: {build} (tests marked build_independent left to the interpreted run)"
    return f"persistri: {build}"


@pytest.fixture(autouse=True)
def _frozen_heap() -> Iterator[None]:
    """Each test starts with the objects of earlier tests frozen (:func:`gc.freeze`), unfrozen when it ends.

    A collection then walks only what the test itself allocated.  Without this, a worker that has run a
    thousand tests holds millions of live objects, and every full collection (the automatic ones, and the
    ``gc.collect()`` a benchmark makes before it times a run) walked all of them: in a process holding 4.5
    million objects, one ``persistri bench hull`` call at test size took 16 s, 0.25 s with them frozen; the
    whole interpreted suite uses 15 % less CPU.  Frozen objects are neither moved nor freed while frozen;
    unfreezing returns them to the oldest generation, whose next collection sees them as before.
    """
    gc.freeze()
    yield
    gc.unfreeze()


@pytest.fixture(autouse=True)
def _no_columns(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """Every test starts without ``COLUMNS``, as output to a user's pipe or file does.

    pytest-xdist sets ``COLUMNS`` to its terminal's width in its workers, and
    persistri's consoles lay tables out to ``COLUMNS`` when it is set
    (:mod:`persistri.impl.cli.console`): without this, a table would be squeezed
    under ``-n 2`` and not in a single process.  Tests about ``COLUMNS`` set it.
    """
    monkeypatch.delenv("COLUMNS", raising=False)
    yield
