"""The refinement's record of the points it dropped: ``mesh.history.undone`` and ``mesh.history.blocked``.

The paper's undo is a return to an older version.  Each record names the version
the point was tried on; these tests check, independently of the refiner, that
the point does encroach the subsegments recorded (exact predicates over the
recorded coordinates), that those were subsegments of that version and were
split in the versions recorded, and that the version the run returned to is
exactly what it was when the point was tried.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

import numpy as np
import pytest

from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.mesh.api import QualityMesh, refine, triangulate
from persistri.impl.mesh.gallery import gallery_domain
from persistri.impl.mesh.quality import inside_lens
from persistri.impl.mesh.ruppert import Refiner

RUNS = [
    ("l-shape", 30.0, 0.05, "lens"),
    ("comb", 20.0, None, "lens"),
    ("utm-tile", 30.0, None, "lens"),
    ("star", 30.0, 0.01, "lens"),
    ("square-hole", 33.0, None, "circle"),
    ("crack", 30.0, 0.2, "circle"),
]


def _subsegments(mesh: QualityMesh, k: int) -> dict[tuple[int, int], int]:
    """Version ``k``'s subsegments as point-index pairs ``(lo, hi)``, with their input segment."""
    arr = mesh.history.mesh(k)
    ends = arr.points[arr.segments]
    return {(int(min(a, b)), int(max(a, b))): int(s) for (a, b), s in zip(ends.tolist(), arr.segment_of.tolist())}


def _finite_triangles(mesh: QualityMesh, k: int) -> set[tuple[int, int, int]]:
    out: set[tuple[int, int, int]] = set()
    for t, _ in mesh.history.structure.items(mesh.history[k]):
        a, b, c = (int(v) for v in t)
        if min(a, b, c) >= 0:
            out |= {(a, b, c), (b, c, a), (c, a, b)}
    return out


def _encroaches(mesh: QualityMesh, lo: int, hi: int, p: int, lens: bool) -> bool:
    """Exact, over the three recorded points only: strictly inside the diametral circle (Thales: an obtuse angle at
    ``p``, a negative dot product in rationals), and inside the lens at the run's bound when the run used lenses."""
    (ax, ay), (bx, by), (px, py) = ((Fraction(x), Fraction(y)) for x, y in (mesh.history.point(v) for v in (lo, hi, p)))
    if (ax - px) * (bx - px) + (ay - py) * (by - py) >= 0:
        return False
    G = GrowingPredicates2(np.array([mesh.history.point(v) for v in (lo, hi, p)]))
    return not lens or inside_lens(G, 0, 1, 2, mesh.min_angle)


@pytest.fixture(scope="module", params=RUNS, ids=[f"{r[0]}-{r[1]:g}-{r[3]}" for r in RUNS])
def run(request: pytest.FixtureRequest) -> tuple[QualityMesh, bool]:
    name, angle, area, encroachment = request.param
    mesh = triangulate(gallery_domain(name).pslg, min_angle=angle, max_area=area, encroachment=encroachment)
    return mesh, encroachment == "lens"


def test_one_record_per_undo_and_per_blocked_point(run: tuple[QualityMesh, bool]) -> None:
    mesh, _ = run
    assert len(mesh.history.undone) == mesh.undos and len(mesh.history.blocked) == mesh.blocked
    kept = set(mesh.history.inserted)
    for d in (*mesh.history.undone, *mesh.history.blocked):
        assert 0 <= d.version < len(mesh.history) and d.point not in kept
        assert mesh.history.point(d.point) == d.xy
        # The bad triangle it was to split is a triangle of the version it was tried on.
        assert d.triangle in _finite_triangles(mesh, d.version)


def test_each_undone_point_encroaches_what_it_records_and_that_is_split(run: tuple[QualityMesh, bool]) -> None:
    mesh, lens = run
    if not mesh.history.undone:
        pytest.fail("every run here has undos")
    for d in mesh.history.undone:
        segs = _subsegments(mesh, d.version)
        assert d.encroached and len(d.split_at) == len(d.encroached)
        assert set(d.cavity) <= _finite_triangles(mesh, d.version)
        deleted: list[int] = []
        for (lo, hi, s), at in zip(d.encroached, d.split_at):
            assert segs.get((lo, hi)) == s, f"({lo}, {hi}) is not a subsegment of segment {s} in version {d.version}"
            assert _encroaches(mesh, lo, hi, d.point, lens)
            assert at is not None and d.version < at < len(mesh.history)
            assert (lo, hi) in _subsegments(mesh, at - 1) and (lo, hi) not in _subsegments(mesh, at)
            q = mesh.history.inserted[at - 1]
            after = _subsegments(mesh, at)
            assert after.get((min(lo, q), max(lo, q))) == s and after.get((min(q, hi), max(q, hi))) == s
            deleted += mesh.history.deleted[at - 1]
        assert d.deleted == tuple(dict.fromkeys(deleted))


def test_each_blocked_point_lies_beyond_or_on_its_subsegment(run: tuple[QualityMesh, bool]) -> None:
    mesh, _ = run
    for d in mesh.history.blocked:
        lo, hi, s = d.segment
        assert _subsegments(mesh, d.version).get((lo, hi)) == s
        P = Predicates2(np.array([mesh.history.point(v) for v in (lo, hi, d.point, *d.triangle)]))
        side = P.orient2d_sign(0, 1, 2)
        # The segment's line separates the point from a vertex of its triangle, or the point lies on it.
        assert side == 0 or any(P.orient2d_sign(0, 1, k) == -side for k in (3, 4, 5))
        assert d.split_at is not None and (lo, hi) not in _subsegments(mesh, d.split_at)


def test_the_version_an_undo_returns_to_is_unchanged(monkeypatch: pytest.MonkeyPatch) -> None:
    # Snapshot the version the refinement stands at each time it tries a point; after the whole run, every version
    # an undo returned to must still hold exactly the triangles (and data) it held then.
    seen: dict[int, frozenset[Any]] = {}
    original = Refiner._split_triangle

    def spy(self: Refiner, c: Any, bad: Any) -> Any:
        seen.setdefault(self._version, frozenset(self.S.items(c)))
        return original(self, c, bad)

    monkeypatch.setattr(Refiner, "_split_triangle", spy)
    mesh = triangulate(gallery_domain("comb").pslg, min_angle=20)
    assert mesh.undos > 0
    for d in mesh.history.undone:
        now = frozenset(mesh.history.structure.items(mesh.history[d.version]))
        assert now == seen[d.version]
        assert d.point not in {int(v) for t, _ in now for v in t}


def test_two_futures_keep_their_own_records() -> None:
    cdt = triangulate(gallery_domain("l-shape").pslg)
    a = refine(cdt, min_angle=30, max_area=0.05)
    b = refine(cdt, min_angle=20, max_area=0.01)
    assert len(a.history.undone) == a.undos and len(b.history.undone) == b.undos
    assert cdt.history.undone == () and cdt.history.blocked == ()
    # Each future's records name its own versions: no point of one is a record of the other.
    assert not {d.point for d in a.history.undone} & {d.point for d in b.history.undone}


def test_a_stopped_run_leaves_the_later_splits_unrecorded() -> None:
    # On the star an undone point encroaches two subsegments, split one after the other; a run stopped by
    # max_steiner between the two splits records the first and None for the second.
    full = triangulate(gallery_domain("star").pslg, min_angle=30, max_area=0.01)
    d = next(d for d in full.history.undone if len(d.split_at) == 2)
    first, second = d.split_at
    assert first is not None and second is not None and first < second
    stopped = triangulate(gallery_domain("star").pslg, min_angle=30, max_area=0.01, max_steiner=first)
    again = next(r for r in stopped.history.undone if r.point == d.point)
    assert again.version == d.version and again.encroached == d.encroached and again.split_at == (first, None)


def test_records_are_made_when_first_read_and_pickle_either_way() -> None:
    # The run hands its log to the history, which makes the records on the first read of undone or blocked: a history
    # pickled before that read (its log: vertices, cavities) and one pickled after it give the same records, and a
    # record set by hand stays as set when the other is read.
    import copy
    import pickle

    fresh = triangulate(gallery_domain("square-hole").pslg, min_angle=33)
    read = triangulate(gallery_domain("square-hole").pslg, min_angle=33)
    expected = (tuple(map(repr, read.history.undone)), tuple(map(repr, read.history.blocked)))
    assert len(expected[0]) == read.undos > 0 and len(expected[1]) == read.blocked > 0
    assert "undone" not in vars(fresh.history)
    for history in (pickle.loads(pickle.dumps(fresh.history)), pickle.loads(pickle.dumps(read.history)), fresh.history):
        assert (tuple(map(repr, history.undone)), tuple(map(repr, history.blocked))) == expected
    again = triangulate(gallery_domain("square-hole").pslg, min_angle=33)
    twin = copy.copy(again.history)
    twin.undone = ()
    assert twin.undone == () and tuple(map(repr, twin.blocked)) == expected[1]
    with pytest.raises(AttributeError):
        _ = again.history.no_such_record
