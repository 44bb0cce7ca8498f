"""The checks behind the docs' picture series of a Ruppert refinement (``docs/mesh_figures.py``).

The series draws the points the refinement tried and dropped from the run's
own record (``mesh.history.undone`` and ``.blocked``); ``checked_record`` checks
that record against the run — its counts, exact encroachment, the versions that
split the encroached subsegments — and must refuse a record that disagrees.
"""

from __future__ import annotations

import copy
import dataclasses
import importlib.util
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"


def _load(name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(f"persistri_docs_{name}", DOCS / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses resolve their module while the class is built
    spec.loader.exec_module(module)
    return module


figures = _load("mesh_figures")


@pytest.mark.parametrize(
    ("name", "angle", "area"),
    [
        ("l-shape", 30, 0.05),  # the run drawn
        ("square-hole", 33, None),  # a hole point in the point set; undos and blocked points
        ("star", 30, 0.01),  # small input angles: shells, exempt triangles
        ("crack", 30, 0.2),  # a segment inside the domain
        ("utm-tile", 30, None),  # rounded split points, off their segment by an ulp
        ("comb", 20, None),  # many undos
    ],
)
def test_the_record_agrees_with_the_run(name: str, angle: float, area: float | None) -> None:
    mesh = figures.refinement_run(name, angle, area)
    record = figures.checked_record(mesh)
    assert len(record.undone) == mesh.undos and len(record.blocked) == mesh.blocked
    for d in (*record.undone, *record.blocked):
        assert 0 <= d.version < len(mesh.history) and d.point not in mesh.history.inserted


@pytest.fixture(scope="module")
def drawn() -> Any:
    mesh = figures.refinement_run()
    return mesh, figures.checked_record(mesh)


def test_the_series_is_drawn_and_redrawn_identically(drawn: Any, tmp_path: Path) -> None:
    mesh, record = drawn
    first = figures.draw_refinement(mesh, record, tmp_path / "a").read_bytes()
    again = figures.draw_refinement(mesh, record, tmp_path / "b").read_bytes()
    assert first.startswith(b"\x89PNG") and first == again


def _with(mesh: Any, **changes: Any) -> Any:
    """``mesh`` with its history's records replaced."""
    history = copy.copy(mesh.history)
    for key, value in changes.items():
        setattr(history, key, value)
    return dataclasses.replace(mesh, history=history)


def test_counts_that_disagree_are_refused(drawn: Any) -> None:
    mesh, _ = drawn
    with pytest.raises(figures.FigureCheckError, match=r"undone insertions recorded; the run undid"):
        figures.checked_record(dataclasses.replace(mesh, undos=mesh.undos + 1))
    with pytest.raises(figures.FigureCheckError, match=r"blocked points recorded; the run blocked"):
        figures.checked_record(dataclasses.replace(mesh, blocked=mesh.blocked - 1))


def test_records_that_disagree_with_the_history_are_refused(drawn: Any) -> None:
    mesh, record = drawn
    first = record.undone[0]
    # A subsegment of that version the point does not encroach (far from it): the check is exact.
    arr = mesh.history.mesh(first.version)
    far = max(
        ((int(a), int(b)) for a, b in arr.points[arr.segments].tolist()),
        key=lambda e: sum((x - y) ** 2 for x, y in zip(mesh.history.point(e[0]), first.xy)),
    )
    lo, hi = sorted(far)
    wrong = dataclasses.replace(first, encroached=((lo, hi, 0),), split_at=first.split_at[:1])
    with pytest.raises(figures.FigureCheckError, match=rf"undone point {first.point} does not encroach"):
        figures.checked_record(_with(mesh, undone=(wrong, *record.undone[1:])))
    split = first.split_at[0]
    late = dataclasses.replace(first, split_at=(split + 1,) + first.split_at[1:])  # it was split one version earlier
    with pytest.raises(figures.FigureCheckError, match=rf"version {split + 1} adds point \d+, not splitting"):
        figures.checked_record(_with(mesh, undone=(late, *record.undone[1:])))
    kept = dataclasses.replace(first, point=mesh.history.inserted[0], xy=mesh.history.point(mesh.history.inserted[0]))
    with pytest.raises(figures.FigureCheckError, match=r"recorded as dropped, is in a kept version"):
        figures.checked_record(_with(mesh, undone=(kept, *record.undone[1:])))


def test_a_run_without_an_undo_has_nothing_to_show(tmp_path: Path) -> None:
    mesh = figures.refinement_run("circle", 20, None)  # boundary splits come first there: no circumcentre encroaches
    assert mesh.undos == 0
    with pytest.raises(figures.FigureCheckError, match="no undo to show"):
        figures.draw_refinement(mesh, figures.checked_record(mesh), tmp_path)
