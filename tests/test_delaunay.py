"""Scattered-point Delaunay (issue item 7): Qhull where it is reliable, the exact check where it is not."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numpy.typing import NDArray

from persistri.impl.complex.checks import check_closed_surface
from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.stats import Stats
from persistri.impl.terrain.check import exact_hull, verify_triangulation
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.maps import backend as map_backend
from persistri.impl.terrain.delaunay import EMPTY, Triangulator, canonical_triangles
from persistri.impl.terrain.insertion import third
from persistri.impl.terrain.errors import DegenerateInputError, TriangulationCheckError
from persistri.impl.terrain.scattered import (
    DelaunayTriangulation,
    _first_triangle,
    delaunay,
    hilbert_keys,
    insertion_order,
)


def qhull_ccw(points: NDArray[np.float64]) -> NDArray[np.intp]:
    from scipy.spatial import Delaunay

    s = Delaunay(points).simplices.astype(np.intp)
    a, b, c = points[s[:, 0]], points[s[:, 1]], points[s[:, 2]]
    turn = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    s[turn < 0] = s[turn < 0][:, [0, 2, 1]]
    return canonical_triangles(s)


def assert_exact_delaunay(d: DelaunayTriangulation) -> None:
    """Every distinct point a vertex, the exact hull as boundary, every edge Delaunay, no flat triangle."""
    rows = np.array(sorted({r for r in range(len(d.points))} - {r for r, _ in d.duplicates}), dtype=np.intp)
    pred = Predicates2(d.points)
    verify_triangulation(pred, d.triangles, vertices=rows).raise_if_failed()
    check_closed_surface(d.complex)
    h = len(exact_hull(pred, rows))
    assert len(d.triangles) == 2 * rows.size - h - 2  # Euler, with h points on the hull's boundary
    assert sorted(d.hull.tolist()) == sorted(exact_hull(pred, rows))


@pytest.mark.parametrize("n", [3, 10, 500])
@pytest.mark.parametrize("seed", [0, 1])
def test_same_triangles_as_qhull_in_general_position(n: int, seed: int) -> None:
    pts = np.random.default_rng(seed).random((n, 2))
    d = delaunay(pts, check=True)
    assert np.array_equal(d.triangles, qhull_ccw(pts))
    assert_exact_delaunay(d)


def test_the_utm_tile_comes_out_complete_and_exact() -> None:
    # 300 random points in a 10 m square at easting 5e5, northing 4e6 (a LiDAR tile in UTM metres).
    pts = np.random.default_rng(2024).random((300, 2)) * 10.0 + np.array([5e5, 4e6])
    d = delaunay(pts, check=True)
    assert np.unique(d.triangles).size == 300
    assert_exact_delaunay(d)
    # The same points translated to the origin (exactly, power-of-two offsets aside) give the same
    # combinatorics wherever the Delaunay triangulation is unique: compare with Qhull there.
    local = (pts - np.array([5e5, 4e6]))
    assert np.array_equal(delaunay(local).triangles, qhull_ccw(local))


def test_stats_and_seeds() -> None:
    pts = np.random.default_rng(9).random((200, 2))
    stats = Stats()
    a = delaunay(pts, stats=stats)
    assert stats.plane_side_tests > 0 and stats.key_comparisons > 0
    assert a.stats is stats
    for seed in (1, 2, 3):
        assert np.array_equal(delaunay(pts, seed=seed).triangles, a.triangles)


@st.composite
def integer_clouds(draw: st.DrawFn) -> NDArray[np.float64]:
    n = draw(st.integers(3, 40))
    side = draw(st.integers(1, 6))
    pts = draw(st.lists(st.tuples(st.integers(0, side), st.integers(0, side)), min_size=n, max_size=n))
    return np.array(pts, dtype=np.float64)


@given(integer_clouds(), st.integers(0, 3))
def test_integer_clouds_cocircular_and_collinear_everywhere(pts: NDArray[np.float64], seed: int) -> None:
    distinct = np.unique(pts, axis=0)
    collinear = len(distinct) < 3 or all(
        (b[0] - distinct[0][0]) * (distinct[-1][1] - distinct[0][1]) == (b[1] - distinct[0][1]) * (distinct[-1][0] - distinct[0][0])
        for b in distinct
    )
    if collinear:
        with pytest.raises(DegenerateInputError):
            delaunay(pts)
        return
    d = delaunay(pts, check=True, seed=seed)
    assert_exact_delaunay(d)
    # The triangulation does not depend on the insertion order (SoS breaks ties the same way).
    assert np.array_equal(delaunay(pts, seed=seed + 7).triangles, d.triangles)


def test_full_grid_and_collinear_hull_points() -> None:
    grid = np.array([[x, y] for x in range(7) for y in range(6)], dtype=float)
    d = delaunay(grid, check=True)
    assert len(d.triangles) == 2 * 6 * 5  # every unit square split in two: 2n - h - 2 with h = 22
    assert len(d.hull) == 22
    line_plus_apex = np.array([[0, 0], [1, 0], [2, 0], [3, 0], [1.5, 1.0]])
    d = delaunay(line_plus_apex, check=True)
    assert d.triangles.tolist() == [[0, 1, 4], [1, 2, 4], [2, 3, 4]]
    assert d.hull.tolist() == [0, 1, 2, 3, 4]


def test_duplicates_are_merged_and_reported() -> None:
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 0.0], [0.0, 0.0], [1.0, 1.0]])
    d = delaunay(pts, check=True)
    assert d.duplicates == ((3, 1), (4, 0))
    assert set(np.unique(d.triangles).tolist()) == {0, 1, 2, 5}


def test_tiny_and_huge_scales_and_offsets() -> None:
    base = np.random.default_rng(11).random((60, 2))
    for scale, offset in ((1e-200, 0.0), (1e200, 0.0), (1.0, 1e15), (2.0**-30, 7.0)):
        d = delaunay(base * scale + offset, check=True)
        assert np.unique(d.triangles).size == len(np.unique(base * scale + offset, axis=0))


@pytest.mark.parametrize(
    ("points", "kind", "message"),
    [
        (np.zeros((0, 2)), DegenerateInputError, "0 distinct points"),
        (np.array([[1.0, 1.0], [1.0, 1.0]]), DegenerateInputError, "1 distinct point:"),
        (np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [5.0, 5.0]]), DegenerateInputError, "collinear"),
        (np.array([[0.0, 0.0, 0.0]]), ValueError, r"\(n, 2\)"),
        (np.array([[0.0, np.nan], [1.0, 0.0], [0.0, 1.0]]), ValueError, "row 0 is not finite"),
        ("points", TypeError, "array of real numbers"),
    ],
)
def test_bad_input(points: object, kind: type[Exception], message: str) -> None:
    with pytest.raises(kind, match=message):
        delaunay(points)  # type: ignore[arg-type]


def test_bad_options() -> None:
    pts = np.random.default_rng(0).random((5, 2))
    with pytest.raises(TypeError, match="seed"):
        delaunay(pts, seed=1.5)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="unknown map backend"):
        delaunay(pts, backend="nope")


def test_insertion_order_is_a_permutation_with_locality() -> None:
    pts = np.random.default_rng(3).random((1000, 2))
    order = insertion_order(pts, 5)
    assert np.array_equal(np.sort(order), np.arange(1000))
    keys = hilbert_keys(pts)
    assert keys.min() >= 0 and len(np.unique(keys)) > 900
    # Consecutive points of the last round are close: the Hilbert sort gives locality.
    last = order[-488:]
    steps = np.linalg.norm(np.diff(pts[last], axis=0), axis=1)
    assert float(np.median(steps)) < 0.1


def _hilbert_reference(points: NDArray[np.float64], bits: int) -> NDArray[np.int64]:
    """The level-by-level recursion (xy2d) that hilbert_keys' tables take four levels at a time."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    with np.errstate(over="ignore"):
        half = np.where(np.isfinite(hi - lo), 1.0, 0.5)
    lo, span = lo * half, hi * half - lo * half
    side = (1 << bits) - 1
    with np.errstate(invalid="ignore", divide="ignore"):
        q = np.where(span > 0, (points * half - lo) / np.where(span > 0, span, 1.0), 0.0)
    x = np.minimum((q[:, 0] * side).astype(np.int64), side)
    y = np.minimum((q[:, 1] * side).astype(np.int64), side)
    d = np.zeros(points.shape[0], dtype=np.int64)
    s = 1 << (bits - 1)
    while s > 0:
        rx = ((x & s) > 0).astype(np.int64)
        ry = ((y & s) > 0).astype(np.int64)
        d += s * s * ((3 * rx) ^ ry)
        flip = ry == 0
        swap_x = np.where(flip & (rx == 1), side - x, x)
        swap_y = np.where(flip & (rx == 1), side - y, y)
        x, y = np.where(flip, swap_y, swap_x), np.where(flip, swap_x, swap_y)
        s >>= 1
    return d


@pytest.mark.parametrize("bits", [1, 2, 3, 4, 5, 7, 8, 13, 16, 21])
def test_hilbert_keys_are_the_level_by_level_curve(bits: int) -> None:
    rng = np.random.default_rng(bits)
    for scale in (1.0, 1e-300, 1e300, 3.0):
        pts = rng.random((500, 2)) * scale
        assert np.array_equal(hilbert_keys(pts, bits), _hilbert_reference(pts, bits))
    huge = np.array([[-1.7e308, 1.7e308], [1.7e308, -1.7e308], [0.0, 0.0], [5.0, 5.0]])
    assert np.array_equal(hilbert_keys(huge, bits), _hilbert_reference(huge, bits))
    same_x = np.column_stack([np.full(50, 2.0), rng.random(50)])
    assert np.array_equal(hilbert_keys(same_x, bits), _hilbert_reference(same_x, bits))


def test_hilbert_keys_walk_a_grid_cell_by_cell() -> None:
    # On the 2^k × 2^k grid with k bits the keys are a permutation, and cells of successive keys are adjacent.
    k = 6
    g = np.stack(np.meshgrid(np.arange(2.0**k), np.arange(2.0**k)), -1).reshape(-1, 2)
    keys = hilbert_keys(g, k)
    assert np.array_equal(np.sort(keys), np.arange(4**k))
    path = g[np.argsort(keys)]
    assert np.all(np.abs(np.diff(path, axis=0)).sum(axis=1) == 1)
    with pytest.raises(ValueError, match="bits"):
        hilbert_keys(g, 0)


def test_all_points_cocircular() -> None:
    # Every integer point on the circle x² + y² = 65² (Pythagorean triples): all cocircular, SoS decides.
    r = 65
    pts = sorted({(x, y) for x in range(-r, r + 1) for y in (-int((r * r - x * x) ** 0.5), int((r * r - x * x) ** 0.5))
                  if x * x + y * y == r * r})
    circle = np.array(pts, dtype=np.float64)
    d = delaunay(circle, check=True)
    assert_exact_delaunay(d)
    assert len(d.triangles) == len(circle) - 2 and len(d.hull) == len(circle)
    with_centre = np.vstack([circle, [[0.0, 0.0]]])
    d = delaunay(with_centre, check=True)
    assert_exact_delaunay(d)
    assert len(d.triangles) == len(circle)  # the fan from the centre


def _triangulator_after(pts: NDArray[np.float64], seed: int, edge_index: bool = True) -> tuple[Triangulator, list[int]]:
    """A Triangulator with the first triangle of ``pts``'s insertion order laid, and the rest of that order."""
    pred = Predicates2(pts)
    T = Triangulator(pred, TwoComplex(map_backend("red_black")), check=True, edge_index=edge_index)
    order = insertion_order(pts, seed)
    first = _first_triangle(pred, order)
    T.begin([(first, EMPTY)])
    return T, [q for q in order.tolist() if q not in first]


@given(integer_clouds(), st.integers(0, 3))
def test_locate_after_finds_a_triangle_in_conflict(pts: NDArray[np.float64], seed: int) -> None:
    # From the fan of every insertion (interior and hull points, cocircular and collinear ones), the walk
    # ends in a live triangle in conflict with the next point, the one the cavity grows from.
    pts = np.unique(pts, axis=0)
    distinct = pts
    if len(distinct) < 3 or all(
        (b[0] - distinct[0][0]) * (distinct[-1][1] - distinct[0][1]) == (b[1] - distinct[0][1]) * (distinct[-1][0] - distinct[0][0])
        for b in distinct
    ):
        return
    T, rest = _triangulator_after(pts, seed)
    last = None
    for q in rest:
        tid = T.locate(q, next(iter(T.tri_of))) if last is None else T.locate_after(q, last)
        assert tid in T.tri_of and T.conflicts(T.tri_of[tid], q)
        last = T.insert(q, tid)


def test_locate_after_walks_the_fan_without_reading_the_complex() -> None:
    # A point inside a triangle of the last fan is found by orient2d tests alone: no look-up in the complex.
    pts = np.array([[0.0, 0.0], [4.0, 0.0], [0.0, 4.0], [1.0, 1.0], [1.5, 0.5], [3.0, 0.5]])
    T = Triangulator(Predicates2(pts), TwoComplex(map_backend("red_black")))
    T.begin([((0, 1, 2), EMPTY)])
    last = T.insert(3, T.locate(3, 0))
    assert not last.hull_vertex and len(last.created) == 3
    reads: list[object] = []
    lookup = T.neighbours()

    def counted(s: object) -> object:
        reads.append(s)
        return lookup(s)

    T._read = counted
    tid = T.locate_after(4, last)
    assert reads == [] and tid in [t for t, _ in last.created] and T.conflicts(T.tri_of[tid], 4)
    # A stale insertion (its version no longer the current one): the walk from its first triangle, still right.
    T.insert(4, tid)
    tid = T.locate_after(5, last)
    assert tid in T.tri_of and T.conflicts(T.tri_of[tid], 5)


def _edges_of_complex(T: Triangulator) -> dict[tuple[int, int], tuple[int, int]]:
    """Every directed edge (u, w) of T's current version, read from the complex: (x, id) of its triangle (u, w, x)."""
    out: dict[tuple[int, int], tuple[int, int]] = {}
    for (a, b, c), datum in T.S.items(T.complex):
        for u, w, x in ((a, b, c), (b, c, a), (c, a, b)):
            out[(int(u), int(w))] = (int(x), int(datum[0]))
    return out


def test_the_neighbour_records_are_the_current_versions_and_spare_every_read_of_the_complex() -> None:
    # With the neighbour records, the walks and the cavities read no edge from the complex, the records are the
    # current version's triangles and neighbours after every insertion (the complex's triangles, and its datum
    # objects), and the triangulation is the same as without them (check=True, which reads the complex for every
    # answer of the records, is off here so that the reads are counted; the other tests run with it on).
    pts = np.random.default_rng(5).random((300, 2))
    found: dict[bool, tuple[int, list[tuple[int, ...]]]] = {}
    for indexed in (False, True):
        T, rest = _triangulator_after(pts, 0, edge_index=indexed)
        assert (T.adj is not None) == indexed
        T.check = False
        reads = 0
        last = None
        for k, q in enumerate(rest):
            lookup = T.neighbours()

            def counted(s: object, lookup: Callable[[object], object] = lookup) -> object:
                nonlocal reads
                reads += 1
                return lookup(s)

            T._read = counted
            last = T.insert(q, T.locate(q, next(iter(T.tri_of))) if last is None else T.locate_after(q, last))
            if indexed and (k % 10 == 0 or k == len(rest) - 1):
                adj = T.adj
                assert adj is not None and len(adj) == T._next_id
                live = {i: R for i, R in enumerate(adj) if R is not None}
                assert set(live) == {int(d[0]) for _, d in T.S.items(T.complex)}
                edges = _edges_of_complex(T)
                data = {int(d[0]): (t, d) for t, d in T.S.items(T.complex)}
                for i, R in live.items():
                    tri, d = R[0], R[1]
                    ct = data[i][0]  # the complex's triangle, in the rotation its items give
                    assert tri in (ct, (ct[1], ct[2], ct[0]), (ct[2], ct[0], ct[1]))
                    assert data[i][1] is d and T.tri_of[i] is tri and int(d[0]) == i
                    for j in range(3):
                        u, w = int(tri[j]), int(tri[(j + 1) % 3])
                        # The record's edge j is (u, w); the triangle across it holds (w, u).
                        assert edges[(w, u)][1] == int(R[2 + j])
        found[indexed] = (reads, sorted(tuple(sorted(t)) for t, _ in T.finite_triangles()))
    assert found[True][1] == found[False][1]
    assert found[True][0] == 0 < found[False][0]


@pytest.mark.parametrize("wrong", ["datum", "vertex"])
def test_check_compares_every_indexed_answer_with_the_complex(wrong: str) -> None:
    # check=True compares each answer of the neighbour records with the complex's: a record with an equal datum
    # that is not the complex's object, or whose triangle has another third vertex, is caught at the next look-up.
    pts = np.random.default_rng(7).random((60, 2))
    T, rest = _triangulator_after(pts, 1)
    last = None
    for q in rest[:30]:
        last = T.insert(q, T.locate(q, next(iter(T.tri_of))) if last is None else T.locate_after(q, last))
    adj = T.adj
    assert adj is not None and last is not None
    for R in adj:
        if R is not None:
            t, d = R[0], R[1]
            if wrong == "datum":
                R[1] = (d[0], d[1])
            else:
                R[0] = (t[0], t[2], t[1])
    q = rest[30]
    with pytest.raises(TriangulationCheckError, match="indexed neighbour"):
        T.insert(q, T.locate_after(q, last))


@pytest.mark.parametrize("counted", [False, True])
def test_check_compares_the_live_index_with_the_complex(counted: bool, monkeypatch: pytest.MonkeyPatch) -> None:
    # Uncounted, delaunay reads its result from the triangulator's index of live triangles, not the complex;
    # check=True must notice when the two disagree (here: the index loses a triangle after the last insertion).
    pts = np.random.default_rng(5).random((40, 2))
    real_insert = Triangulator.insert
    calls = [0]

    def insert_then_forget(self: Triangulator, *args: Any) -> Any:
        out = real_insert(self, *args)
        calls[0] += 1
        if calls[0] == len(pts) - 3:  # the last insertion (the first triangle's three points are not inserted)
            if self.adj is None:
                self.tri_of.pop(next(iter(self.tri_of)))
            else:  # uncounted: the neighbour records are the index of the live triangles
                self.adj[next(i for i, R in enumerate(self.adj) if R is not None)] = None
        return out

    monkeypatch.setattr(Triangulator, "insert", insert_then_forget)
    stats = Stats() if counted else None
    with pytest.raises(TriangulationCheckError, match="not the triangulator's"):
        delaunay(pts, check=True, stats=stats)


def test_the_triangulator_s_vertices_are_those_vertex_makes() -> None:
    """Vertex i (made directly as its lineage's class after the first): the object ``Vertex(i, i, lineage)`` is —
    its class, label, point and lineage — and memoised; the infinite vertex has no point; a resumed
    triangulator makes its new vertices in the resumed complex's lineage."""
    from persistri.impl.complex.vertex import Vertex

    pts = np.random.default_rng(6).random((40, 2))
    T = Triangulator(Predicates2(pts), TwoComplex(map_backend("red_black")))
    for i in (3, 0, 17, 39, 3):
        v = T.vertex(i)
        want = Vertex(i, i, T.lineage)
        assert type(v) is type(want) and v == want == i and v.point == i and v.lineage is T.lineage
        assert T.vertex(i) is v
    inf = T.vertex(40)
    assert inf is T.infinite and inf.point is None and type(inf) is not type(T.vertex(0))
    d = delaunay(pts[:20], seed=0)
    R = Triangulator.resume(Predicates2(pts), d.structure, d.complex, d.infinite)
    v = R.vertex(30)
    assert R.lineage is not T.lineage and v.lineage is R.lineage and type(v) is type(Vertex(30, 30, R.lineage))
    assert R.vertex(31).lineage is R.lineage
