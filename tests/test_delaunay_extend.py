"""Continuing a scattered Delaunay run (extend_delaunay, Delaunay.add_points) and its history (DelaunayHistory).

The extension must give exactly the triangulation of the whole input computed
in one run — ties among cocircular and collinear points included, since
Simulation of Simplicity depends only on the labels' order, which the
extension keeps — and leave the old triangulation, its complex and every
version of its history as they were.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import persistri
from persistri.impl.stats import Stats
from persistri.impl.terrain.extend_delaunay import extend_delaunay
from persistri.impl.terrain.insertion import canonical_triangles
from persistri.impl.terrain.scattered import DelaunayTriangulation, delaunay


def _grid(g: int, rng: np.random.Generator) -> np.ndarray:
    """A g × g grid of integers (every unit square cocircular), shuffled, with a few rows repeated."""
    pts = np.array([[x, y] for x in range(g) for y in range(g)], dtype=float)[rng.permutation(g * g)]
    return np.vstack([pts, pts[: min(5, g * g)]])


def _fingerprint(t: DelaunayTriangulation, stride: int = 1) -> list[object]:
    """What a triangulation reads as: its arrays, its complex, and every ``stride``-th version of its history (and
    the last), each read back from the complex."""
    out: list[object] = [t.triangles.tolist(), t.hull.tolist(), t.duplicates, sorted(t.structure.items(t.complex))]
    if t.history is not None:
        last = len(t.history) - 1
        out += [t.history.simplices(k).tolist() for k in sorted({*range(0, last, stride), last})]
    return out


@pytest.mark.parametrize("kind", ["uniform", "grid", "rounded"])
@pytest.mark.parametrize("seed", range(4))
def test_extension_is_the_one_run_triangulation(kind: str, seed: int) -> None:
    rng = np.random.default_rng(seed)
    if kind == "uniform":
        pts = rng.random((300, 2))
    elif kind == "grid":
        pts = _grid(9 + seed, rng)
    else:  # many exact repeats and cocircular quadruples
        pts = np.round(rng.random((300, 2)) * 8) / 8
    n = pts.shape[0]
    cut1, cut2 = sorted(rng.integers(n // 10, n, size=2).tolist())
    a = delaunay(pts[:cut1], seed=seed, check=True)
    b = extend_delaunay(a, pts[cut1:cut2], check=True)
    c = extend_delaunay(b, pts[cut2:], check=True)
    whole = delaunay(pts, seed=seed + 11)
    assert np.array_equal(c.triangles, whole.triangles)
    assert np.array_equal(c.hull, whole.hull)
    assert sorted(c.duplicates) == sorted(whole.duplicates)
    assert np.array_equal(c.points, pts)
    assert c.seed == a.seed


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.tuples(st.integers(-4, 4), st.integers(-4, 4)), min_size=3, max_size=40),
    st.lists(st.tuples(st.integers(-4, 4), st.integers(-4, 4)), min_size=0, max_size=40),
)
def test_extension_equals_one_run_on_small_integer_points(first: list[tuple[int, int]], more: list[tuple[int, int]]) -> None:
    """Small integer points: collinear and cocircular ties everywhere, duplicates across the two batches."""
    a_pts, b_pts = np.array(first, dtype=float), np.array(more, dtype=float).reshape(-1, 2)
    try:
        a = delaunay(a_pts)
    except ValueError:  # fewer than 3 distinct points, or all collinear: nothing to extend
        return
    b = extend_delaunay(a, b_pts, check=True)
    whole = delaunay(np.vstack([a_pts, b_pts]), seed=3)
    assert np.array_equal(b.triangles, whole.triangles)
    assert sorted(b.duplicates) == sorted(whole.duplicates)


def test_old_triangulation_and_every_version_unchanged_by_two_futures() -> None:
    """Thousands of points, the history kept: two extensions of one triangulation leave it (and each other) intact."""
    rng = np.random.default_rng(7)
    pts = rng.random((3000, 2))
    a = delaunay(pts[:2000], history=True)
    before = _fingerprint(a, 13)
    left = extend_delaunay(a, pts[2000:2600])
    left_before = _fingerprint(left, 13)
    right = extend_delaunay(a, rng.random((500, 2)) * 2 - 0.5)  # a wider cloud: the hull changes too
    further = extend_delaunay(left, pts[2600:])
    assert _fingerprint(a, 13) == before
    assert _fingerprint(left, 13) == left_before
    for t in (left, right, further):
        assert t.history is not None and a.history is not None
        # The old versions are the same objects, followed by one version per new distinct point.
        assert t.history.versions[: len(a.history)] == a.history.versions
        assert len(t.history) == len(a.history) + (t.labels.size - a.labels.size)
        assert np.array_equal(t.history.simplices(len(t.history) - 1), t.triangles)
    assert np.array_equal(further.triangles, delaunay(pts).triangles)
    assert np.array_equal(right.triangles, delaunay(np.vstack([pts[:2000], right.points[2000:]])).triangles)


def test_history_versions_are_the_triangulations_of_the_prefixes() -> None:
    """Version k is the Delaunay triangulation of exactly the rows inserted[: k + 3] (every point stays a vertex)."""
    rng = np.random.default_rng(3)
    pts = np.vstack([rng.random((120, 2)), _grid(6, rng) / 5.0])
    t = delaunay(pts, history=True, seed=2)
    more = extend_delaunay(t, rng.random((40, 2)))
    h = more.history
    assert h is not None and t.history is not None
    assert len(h.inserted) == len(h) + 2
    assert sorted(h.inserted) == sorted(set(range(more.points.shape[0])) - {r for r, _ in more.duplicates})
    for k in [0, 1, 2, 10, 50, len(t.history) - 1, len(t.history), len(h) - 1]:
        rows = np.sort(np.array(h.inserted[: k + 3]))
        want = canonical_triangles(rows[delaunay(more.points[rows]).triangles])
        assert np.array_equal(h.simplices(k), want), k
        assert h.vertices(k).tolist() == rows.tolist()


def test_repeats_only_share_the_old_complex() -> None:
    a = delaunay(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]), history=True)
    b = extend_delaunay(a, [[1.0, 1.0], [0.0, 0.0], [1.0, 1.0]])
    assert b.complex is a.complex
    assert b.duplicates == ((4, 3), (5, 0), (6, 3))
    assert np.array_equal(b.triangles, a.triangles)
    assert b.history is not None and a.history is not None and b.history.versions == a.history.versions


def test_new_triangles_share_the_old_lineage_and_structure() -> None:
    rng = np.random.default_rng(5)
    a = delaunay(rng.random((200, 2)))
    b = extend_delaunay(a, rng.random((50, 2)))
    lineages = {v.lineage for tri, _ in b.structure.items(b.complex) for v in tri}
    assert lineages == {v.lineage for tri, _ in a.structure.items(a.complex) for v in tri}
    # Triangles untouched by the new points are the same data objects in both versions.
    old = {d[0]: d for _, d in a.structure.items(a.complex)}
    kept = [d for _, d in b.structure.items(b.complex) if d[0] in old]
    assert kept and all(old[d[0]] is d for d in kept)
    assert max(d[0] for _, d in b.structure.items(b.complex)) > max(old)


def test_counted_run_counts_the_extension_into_its_stats() -> None:
    rng = np.random.default_rng(2)
    stats = Stats()
    a = delaunay(rng.random((100, 2)), stats=stats)
    counted = stats.as_dict()
    b = extend_delaunay(a, rng.random((100, 2)), check=True)
    assert b.stats is stats
    after = stats.as_dict()
    assert after["faces_created"] > counted["faces_created"] and after["plane_side_tests"] > counted["plane_side_tests"]
    assert np.array_equal(b.triangles, delaunay(b.points).triangles)


@pytest.mark.parametrize(
    "bad, error, words",
    [
        ([[0.0, np.nan]], ValueError, "points"),
        ([[0.0, np.inf], [1.0, 1.0]], ValueError, "points"),
        ([[0.0, 1.0, 2.0]], ValueError, "points"),
        ("abc", TypeError, "points"),
    ],
)
def test_bad_new_points_get_one_clear_error(bad: object, error: type[Exception], words: str) -> None:
    a = delaunay(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]))
    with pytest.raises(error, match=words):
        extend_delaunay(a, bad)  # type: ignore[arg-type]  # deliberately wrong input
    with pytest.raises(TypeError, match="DelaunayTriangulation"):
        extend_delaunay(object(), [[1.0, 1.0]])  # type: ignore[arg-type]  # deliberately wrong input


def test_public_add_points_returns_a_new_triangulation() -> None:
    rng = np.random.default_rng(11)
    pts = rng.random((400, 2))
    tri = persistri.Delaunay(pts[:300], history=True)
    simplices, neighbors = tri.simplices.copy(), tri.neighbors.copy()
    more = tri.add_points(pts[300:])
    assert isinstance(more, persistri.Delaunay) and more is not tri
    assert np.array_equal(tri.simplices, simplices) and np.array_equal(tri.neighbors, neighbors)
    assert tri.npoints == 300 and more.npoints == 400
    whole = persistri.Delaunay(pts)
    assert np.array_equal(more.simplices, whole.simplices)
    assert np.array_equal(more.neighbors, whole.neighbors)
    assert np.array_equal(more.convex_hull, whole.convex_hull)
    q = rng.random((200, 2)) * 1.2 - 0.1
    assert np.array_equal(more.find_simplex(q), whole.find_simplex(q))
    assert isinstance(more.history, persistri.DelaunayHistory) and tri.history is not None
    assert len(more.history) == len(tri.history) + 100
    assert persistri.Delaunay(pts[:10]).history is None
    assert "history of" in repr(more)


def test_public_add_points_check_defaults_to_the_constructors() -> None:
    tri = persistri.Delaunay([[0, 0], [4, 0], [0, 4], [4, 4]], check=True)
    more = tri.add_points([[2, 2], [1, 3], [3, 1]])
    assert more.nsimplex == 8 and more._check
    assert not persistri.Delaunay([[0, 0], [4, 0], [0, 4]]).add_points([[1, 1]])._check


def test_sos_rank_breaks_ties_as_the_index_order_it_names() -> None:
    """Predicates2 over permuted points, ranked by their original indices, decides every test as the original."""
    from itertools import permutations

    from persistri.impl.geometry.predicates import Predicates2

    pts = np.array([[x, y] for x in range(3) for y in range(3)], dtype=float)  # cocircular and collinear everywhere
    perm = np.random.default_rng(0).permutation(len(pts))
    plain, ranked = Predicates2(pts), Predicates2(pts[perm], sos_rank=perm)
    k1, k2 = plain.kernel(), ranked.kernel()
    where = np.argsort(perm)  # original index -> index in the permuted array
    for a, b, c in permutations(range(9), 3):
        A, B, C = (int(where[i]) for i in (a, b, c))
        assert plain.orient2d(a, b, c) == ranked.orient2d(A, B, C) == k2.orient2d(A, B, C)
        for d in range(9):
            if d not in (a, b, c):
                D = int(where[d])
                assert plain.incircle(a, b, c, d) == ranked.incircle(A, B, C, D) == k2.incircle(A, B, C, D)
                assert k1.incircle(a, b, c, d) == plain.incircle(a, b, c, d)
    with pytest.raises(ValueError, match="sos_rank"):
        Predicates2(pts, sos_rank=[0] * 9)


def test_vertices_numbered_along_the_curve_share_the_maps_paths() -> None:
    """Labels follow the Hilbert curve (ranked by row for SoS), so a version adds few tree nodes: about 20 a point
    at 2,000 uniform points, where labels by input row took about 45 (an operation count, not a time)."""
    from tests.tree_helpers import nodes

    t = delaunay(np.random.default_rng(8).random((2000, 2)), history=True, backend="red_black")  # counts tree nodes
    assert t.history is not None
    assert sorted(t.labels[:-1].tolist()) == list(range(2000)) and t.labels[-1] == -1
    versions = t.history.versions
    seen: set[int] = set()
    for v in versions:
        seen.update(id(x) for x in nodes(v.rep[1]))
    per_version = len(seen) / len(versions)
    assert per_version < 32, per_version


def test_history_index_errors_name_the_range() -> None:
    t = persistri.Delaunay(np.random.default_rng(0).random((10, 2)), history=True)
    assert t.history is not None
    with pytest.raises(IndexError, match=r"version 100 of a history of 8 versions \(0 to 7\)"):
        t.history.simplices(100)
    assert t.history[-1] is t.history.versions[-1]
    hull = persistri.ConvexHull(np.random.default_rng(0).random((20, 3)), history=True)
    assert hull.history is not None
    with pytest.raises(IndexError, match="version -99 of a history of"):
        hull.history[-99]
    with pytest.raises(ValueError, match=r"^points must be an \(n, 2\) array"):
        persistri.Delaunay(np.zeros((10, 3)))


def test_histories_slice_like_tuples() -> None:
    t = persistri.Delaunay(np.random.default_rng(1).random((12, 2)), history=True)
    hull = persistri.ConvexHull(np.random.default_rng(1).random((20, 3)), history=True)
    for h in (t.history, hull.history):
        assert h is not None
        assert h[:3] == h.versions[:3] and h[-2:] == h.versions[-2:] and h[::2] == h.versions[::2]
