"""``persistri.Delaunay``: scipy.spatial's attributes against Qhull, and ``find_simplex`` against exact rationals."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial import Delaunay as QhullDelaunay

import persistri
from persistri.impl.complex.adjacency import triangle_neighbors, vertex_neighbor_vertices
from persistri.impl.terrain.locate import locate_points


def keys(simplices: np.ndarray) -> list[frozenset[int]]:
    return [frozenset(t) for t in simplices.tolist()]


def orient(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> int:
    """The exact sign of orient2d(p, q, r), in Fractions (the reference the float-filtered walk must match)."""
    px, py, qx, qy, rx, ry = (Fraction(float(v)) for v in (*p, *q, *r))
    d = (px - rx) * (qy - ry) - (py - ry) * (qx - rx)
    return (d > 0) - (d < 0)


def contains(points: np.ndarray, tri: np.ndarray, x: np.ndarray) -> bool:
    """Whether the counterclockwise triangle ``tri`` contains ``x``, boundary included (exactly)."""
    a, b, c = (points[i] for i in tri)
    return orient(a, b, x) >= 0 and orient(b, c, x) >= 0 and orient(c, a, x) >= 0


def outside_hull(points: np.ndarray, hull_edges: np.ndarray, x: np.ndarray) -> bool:
    """Whether ``x`` is strictly right of some counterclockwise hull edge (exactly): outside the convex hull."""
    return any(orient(points[u], points[w], x) < 0 for u, w in hull_edges.tolist())


def check_located(tri: persistri.Delaunay, xi: np.ndarray, found: np.ndarray) -> None:
    for x, k in zip(xi, found.tolist()):
        if k < 0:
            assert outside_hull(tri.points, tri.convex_hull, x), x
        else:
            assert contains(tri.points, tri.simplices[k], x), (x, k)


# -- agreement with Qhull on general-position input ------------------------------------------------


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_agrees_with_qhull(seed: int) -> None:
    pts = np.random.default_rng(seed).random((400, 2))
    ours = persistri.Delaunay(pts)
    ref = QhullDelaunay(pts)
    assert set(keys(ours.simplices)) == set(keys(ref.simplices))
    at = {k: i for i, k in enumerate(keys(ref.simplices))}
    match = np.array([at[k] for k in keys(ours.simplices)])
    for i, t in enumerate(ours.simplices.tolist()):  # the neighbour opposite each vertex, -1 at the same places
        for j, v in enumerate(t):
            k = ours.neighbors[i, j]
            rk = ref.neighbors[match[i], ref.simplices[match[i]].tolist().index(v)]
            assert (rk == -1) if k == -1 else (match[k] == rk)
    assert {frozenset(e) for e in ours.convex_hull.tolist()} == {frozenset(e) for e in ref.convex_hull.tolist()}
    ip, ix = ours.vertex_neighbor_vertices
    rp, rx = ref.vertex_neighbor_vertices
    for v in range(len(pts)):
        assert ix[ip[v] : ip[v + 1]].tolist() == sorted(rx[rp[v] : rp[v + 1]].tolist())
    # Queries away from every edge (triangle centroids, and far outside): both find the same triangle, or -1.
    xi = np.vstack([pts[ours.simplices].mean(axis=1), [[2.0, 2.0], [-1.0, 0.5], [0.5, 7.0]]])
    got = ours.find_simplex(xi)
    want = ref.find_simplex(xi)
    assert got[-3:].tolist() == want[-3:].tolist() == [-1, -1, -1]
    assert [keys(ours.simplices[g : g + 1])[0] for g in got[:-3]] == [keys(ref.simplices[w : w + 1])[0] for w in want[:-3]]


def test_arrays_have_scipys_shapes_and_dtypes_and_are_values() -> None:
    pts = np.random.default_rng(3).random((60, 2))
    tri = persistri.Delaunay(pts)
    ref = QhullDelaunay(pts)
    m = tri.nsimplex
    assert (tri.npoints, tri.ndim, m) == (60, 2, len(ref.simplices))
    for name in ("simplices", "neighbors", "convex_hull", "vertex_to_simplex", "coplanar"):
        arr, want = getattr(tri, name), getattr(ref, name)
        assert arr.dtype == want.dtype == np.intc and arr.shape == want.shape, name
    assert all(a.dtype == np.intc for a in tri.vertex_neighbor_vertices)
    assert tri.find_simplex([0.5, 0.5]).shape == () and tri.find_simplex(np.zeros((4, 5, 2))).shape == (4, 5)
    assert tri.find_simplex(np.zeros((0, 2))).shape == (0,) and tri.find_simplex(np.zeros((0, 2))).dtype == np.intc
    for arr in (tri.points, tri.simplices, tri.neighbors, tri.convex_hull, tri.vertex_to_simplex, *tri.vertex_neighbor_vertices):
        with pytest.raises(ValueError, match="read-only"):
            arr[0] = 0
    assert "60 points" in repr(tri)
    assert repr(persistri.Delaunay([[0, 0], [1, 0], [0, 1]])) == "persistri.Delaunay(3 points, 1 triangle, 3 hull edges)"


def test_simplices_are_counterclockwise_and_neighbours_consistent() -> None:
    pts = np.random.default_rng(5).random((200, 2))
    tri = persistri.Delaunay(pts)
    for t in tri.simplices:
        assert orient(*pts[t]) > 0
    assert np.array_equal(tri.neighbors, triangle_neighbors(tri.simplices))
    # The hull edges go counterclockwise around the hull, each the successor's start.
    hull = tri.convex_hull
    assert np.array_equal(hull[1:, 0], hull[:-1, 1]) and hull[-1, 1] == hull[0, 0]
    assert {tuple(e) for e in hull.tolist()} == {
        (int(t[(j + 1) % 3]), int(t[(j + 2) % 3])) for t, nb in zip(tri.simplices, tri.neighbors) for j in range(3) if nb[j] == -1
    }
    for v, k in enumerate(tri.vertex_to_simplex.tolist()):
        assert v in tri.simplices[k]


# -- find_simplex is exact -------------------------------------------------------------------------


def test_points_on_vertices_and_edges_are_inside() -> None:
    grid = np.array([[x, y] for x in range(6) for y in range(5)], dtype=float)  # cocircular everywhere
    tri = persistri.Delaunay(grid)
    edges = np.array(sorted({tuple(sorted((int(t[j]), int(t[(j + 1) % 3])))) for t in tri.simplices for j in range(3)}))
    mids = (grid[edges[:, 0]] + grid[edges[:, 1]]) / 2
    xi = np.vstack([grid, mids])
    found = tri.find_simplex(xi)
    assert (found >= 0).all()
    check_located(tri, xi, found)


def test_one_ulp_outside_the_hull_is_outside() -> None:
    """Qhull's tolerance puts these points inside; they are outside, by the least representable amount."""
    grid = np.array([[x, y] for x in range(5) for y in range(5)], dtype=float)
    tri = persistri.Delaunay(grid)
    on_edge = np.array([[0.5, 0.0], [4.0, 2.5], [2.5, 4.0], [0.0, 1.5], [0.0, 0.0], [4.0, 4.0]])
    outward = np.array([[0, -1], [1, 0], [0, 1], [-1, 0], [-1, -1], [1, 1]], dtype=float)
    just_out = np.nextafter(on_edge, np.where(outward > 0, np.inf, np.where(outward < 0, -np.inf, on_edge)))
    assert np.all((just_out != on_edge) == (outward != 0))
    assert (tri.find_simplex(on_edge) >= 0).all()
    assert tri.find_simplex(just_out).tolist() == [-1] * 6
    assert (QhullDelaunay(grid).find_simplex(just_out) >= 0).any()  # scipy answers "inside" for some of them


def test_every_point_is_a_vertex_at_utm_coordinates() -> None:
    """Centimetre spacing at UTM eastings/northings: Qhull drops most points, persistri keeps and locates all."""
    rng = np.random.default_rng(0)
    pts = np.column_stack([5e5 + rng.random(500) * 10, 4e6 + rng.random(500) * 10]).round(2)
    tri = persistri.Delaunay(pts)
    assert np.unique(tri.simplices).size == np.unique(pts, axis=0).shape[0]
    assert QhullDelaunay(pts).coplanar.shape[0] > 100
    xi = np.vstack([pts, pts[tri.simplices].mean(axis=1)[:50], pts[:20] + 0.005])
    found = tri.find_simplex(xi)
    assert (found[: len(pts)] >= 0).all()
    check_located(tri, xi, found)


@given(
    st.lists(st.tuples(st.integers(-5, 5), st.integers(-5, 5)), min_size=3, max_size=30),
    st.lists(st.tuples(st.integers(-14, 14), st.integers(-14, 14)), min_size=1, max_size=30),
)
def test_find_simplex_on_integer_sets(coords: list[tuple[int, int]], queries: list[tuple[int, int]]) -> None:
    """Degenerate sets (collinear, cocircular, duplicates), queries on half-integers (edges and vertices often)."""
    pts = np.array(coords, dtype=float)
    try:
        tri = persistri.Delaunay(pts)
    except ValueError as exc:
        assert "collinear" in str(exc) or "distinct point" in str(exc)
        return
    xi = np.array(queries, dtype=float) / 2
    found = tri.find_simplex(xi)
    check_located(tri, xi, found)
    # The walk's safety net, testing every triangle, is exact too (the walk never needs it).
    brute = locate_points(tri.points, tri.simplices, tri.neighbors, xi, max_steps=0)
    check_located(tri, xi, brute)
    assert np.array_equal(brute >= 0, found >= 0)


def test_duplicates_and_coplanar_report_merged_rows() -> None:
    pts = np.array([[0, 0], [1, 0], [0, 1], [1, 1], [0, 0], [1, 1]], dtype=float)
    tri = persistri.Delaunay(pts)
    assert tri.duplicates.tolist() == [[4, 0], [5, 3]]
    cop = tri.coplanar
    assert cop[:, 0].tolist() == [4, 5] and cop[:, 2].tolist() == [0, 3]
    assert all(v in tri.simplices[k] for k, v in zip(cop[:, 1], cop[:, 2]))
    assert tri.vertex_to_simplex[4] == tri.vertex_to_simplex[5] == -1
    ip, _ = tri.vertex_neighbor_vertices
    assert ip[5] == ip[4] == ip[6]  # merged rows have no neighbours


# -- errors ------------------------------------------------------------------------------------------


def test_errors_are_one_line() -> None:
    with pytest.raises(ValueError, match="collinear"):
        persistri.Delaunay([[0, 0], [1, 1], [2, 2]])
    with pytest.raises(ValueError, match=r"\(n, 2\)"):
        persistri.Delaunay(np.zeros((5, 3)))
    tri = persistri.Delaunay([[0, 0], [1, 0], [0, 1]])
    with pytest.raises(ValueError, match=r"shape \(\.\.\., 2\), got shape \(4, 3\)"):
        tri.find_simplex(np.zeros((4, 3)))
    with pytest.raises(ValueError, match="xi: row 1 is not finite"):
        tri.find_simplex(np.array([[0, 0], [np.nan, 0]]))
    with pytest.raises(TypeError, match="xi must be real numbers"):
        tri.find_simplex([["a", "b"]])
    with pytest.raises(ValueError, match="rectangular"):
        tri.find_simplex([[0, 0], [1]])
    with pytest.raises(TypeError, match="needs a persistri DelaunayTriangulation"):
        persistri.Delaunay.from_triangulation(tri)  # type: ignore[arg-type]
    again = persistri.Delaunay.from_triangulation(persistri.delaunay([[0, 0], [1, 0], [0, 1]]))
    assert again.simplices.tolist() == tri.simplices.tolist() and tri.seed == 0


def test_adjacency_helpers_reject_what_is_not_a_surface() -> None:
    with pytest.raises(ValueError, match=r"oriented edge \(0, 1\) is in two triangles"):
        triangle_neighbors([[0, 1, 2], [0, 1, 3]])
    with pytest.raises(ValueError, match=r"\(m, 3\) integer array"):
        triangle_neighbors(np.zeros((2, 4), dtype=int))
    with pytest.raises(ValueError, match="only 3 points"):
        vertex_neighbor_vertices([[0, 1, 3]], 3)
    assert triangle_neighbors(np.zeros((0, 3), dtype=int)).shape == (0, 3)


@pytest.mark.parametrize("restart", [False, True])
def test_add_points_errors_name_the_new_points(restart: bool) -> None:
    tri = persistri.Delaunay(np.random.default_rng(0).random((20, 2)))
    with pytest.raises(ValueError, match=r"^new points must be an \(n, 2\) array, got shape \(1, 3\)"):
        tri.add_points([[1.0, 2.0, 3.0]], restart=restart)
    with pytest.raises(ValueError, match=r"^new points: row 0 is not finite"):
        tri.add_points([[np.inf, 0.0]], restart=restart)
