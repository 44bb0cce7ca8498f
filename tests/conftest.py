"""Shared pytest configuration: the hypothesis profiles, and which build of persistri is under test.

``HYPOTHESIS_PROFILE=ci`` (set by ``make test`` under CI) is thorough;
``dev`` (the default) is quick.  Neither has a deadline: persistri's tests check
results and operation counts, never wall-clock time.
"""

from __future__ import annotations

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


def pytest_report_header() -> str:
    """Which persistri the suite runs on: interpreted, or the compiled twin (``make test`` runs both)."""
    from persistri.impl.bench.hull import persistri_build

    return f"persistri: {persistri_build()}"


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
