"""The checks behind the docs' picture series of a Ruppert refinement (``docs/mesh_figures.py``).

The series marks the points the refinement tried and dropped, which the
refiner does not record: ``dropped_points`` recomputes them from the history
and the append-only point set and must agree with the refiner's own counts on
every run — and refuse a run or a history that disagrees.
"""

from __future__ import annotations

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
def test_the_dropped_points_are_the_runs_undos_and_blocked_points(name: str, angle: float, area: float | None) -> None:
    mesh = figures.refinement_run(name, angle, area)
    dropped = figures.dropped_points(mesh)
    assert sum(d.undone for d in dropped) == mesh.undos and sum(not d.undone for d in dropped) == mesh.blocked
    for d in dropped:
        assert 0 <= d.k < len(mesh.history) and int(d.point) not in mesh.history.inserted
        assert bool(d.encroached) == bool(d.cavity) == d.undone


@pytest.fixture(scope="module")
def drawn() -> Any:
    mesh = figures.refinement_run()
    return mesh, figures.dropped_points(mesh)


def test_the_series_is_drawn_and_redrawn_identically(drawn: Any, tmp_path: Path) -> None:
    mesh, dropped = drawn
    first = figures.draw_refinement(mesh, dropped, tmp_path / "a").read_bytes()
    again = figures.draw_refinement(mesh, dropped, tmp_path / "b").read_bytes()
    assert first.startswith(b"\x89PNG") and first == again


def test_counts_that_disagree_are_refused(drawn: Any) -> None:
    mesh, _ = drawn
    with pytest.raises(figures.FigureCheckError, match=r"encroach a subsegment of their cavity; the run undid"):
        figures.dropped_points(dataclasses.replace(mesh, undos=mesh.undos + 1))
    with pytest.raises(figures.FigureCheckError, match=r"look blocked; the run blocked"):
        figures.dropped_points(dataclasses.replace(mesh, blocked=mesh.blocked - 1))


class _Stale:
    """A history that reads version ``k`` where version ``k + 1`` was asked for: the split after an undo goes missing."""

    def __init__(self, history: Any, k: int) -> None:
        self._history, self._k = history, k
        self.inserted = history.inserted

    def __len__(self) -> int:
        return len(self._history)

    def mesh(self, j: int) -> Any:
        return self._history.mesh(self._k if j == self._k + 1 else j)


def test_a_history_whose_split_does_not_follow_its_undo_is_refused(drawn: Any) -> None:
    mesh, dropped = drawn
    tried = {d.k for d in dropped}
    undo = next(d for d in dropped if d.undone and d.k + 1 not in tried)  # nothing else was tried from version k + 1
    stale = dataclasses.replace(mesh, history=_Stale(mesh.history, undo.k))
    with pytest.raises(figures.FigureCheckError, match=rf"version {undo.k + 1} adds point \d+, splitting none of the subsegments"):
        figures.dropped_points(stale)


def test_a_run_without_an_undo_has_nothing_to_show(tmp_path: Path) -> None:
    mesh = figures.refinement_run("circle", 20, None)  # boundary splits come first there: no circumcentre encroaches
    assert mesh.undos == 0
    with pytest.raises(figures.FigureCheckError, match="no undo to show"):
        figures.draw_refinement(mesh, figures.dropped_points(mesh), tmp_path)
