"""Code ported from scipy.spatial: what ``persistri.ConvexHull`` / ``persistri.Delaunay`` give on scipy's inputs.

What the classes' docstrings promise a porting user, checked against scipy on the same
points: in general position the same triangles, neighbours, vertex neighbours, hull edges
and located triangles (as sets); on a grid (cocircular ties) another Delaunay triangulation,
equally valid; of equal rows the first kept; NaN queries refused.
"""

from __future__ import annotations

import numpy as np
import pytest

import persistri

spatial = pytest.importorskip("scipy.spatial")


def _tris(simplices: np.ndarray) -> set[tuple[int, ...]]:
    return {tuple(sorted(t)) for t in simplices.tolist()}


def _neighbours(tri: object) -> dict[tuple[int, ...], frozenset[tuple[int, ...] | None]]:
    s = tri.simplices.tolist()  # type: ignore[attr-defined]
    nb = tri.neighbors  # type: ignore[attr-defined]
    return {tuple(sorted(s[i])): frozenset(tuple(sorted(s[j])) if j != -1 else None for j in nb[i]) for i in range(len(s))}


def _vertex_neighbours(tri: object) -> list[list[int]]:
    indptr, indices = tri.vertex_neighbor_vertices  # type: ignore[attr-defined]
    return [sorted(indices[indptr[k] : indptr[k + 1]].tolist()) for k in range(len(indptr) - 1)]


@pytest.mark.parametrize("offset", [0.0, 1000.0])
def test_delaunay_in_general_position_is_scipys(offset: float) -> None:
    rng = np.random.default_rng(5)
    pts = rng.random((300, 2)) * 100 + offset
    ours, theirs = persistri.Delaunay(pts), spatial.Delaunay(pts)
    assert _tris(ours.simplices) == _tris(theirs.simplices)
    assert _neighbours(ours) == _neighbours(theirs)
    assert _vertex_neighbours(ours) == _vertex_neighbours(theirs)
    assert {frozenset(e) for e in ours.convex_hull.tolist()} == {frozenset(e) for e in theirs.convex_hull.tolist()}
    queries = rng.random((500, 2)) * 120 - 10 + offset
    a, b = ours.find_simplex(queries), theirs.find_simplex(queries)
    assert a.dtype == b.dtype == np.intc and ((a == -1) == (b == -1)).all()
    inside = np.flatnonzero(a != -1)
    assert all(sorted(ours.simplices[a[i]]) == sorted(theirs.simplices[b[i]]) for i in inside)


def test_delaunay_on_a_grid_is_another_valid_triangulation() -> None:
    grid = np.array([[x, y] for x in range(6) for y in range(6)], dtype=float)
    ours, theirs = persistri.Delaunay(grid), spatial.Delaunay(grid)
    assert ours.nsimplex == theirs.nsimplex == 50
    assert _tris(ours.simplices) != _tris(theirs.simplices)  # the ties broken otherwise: what the docstring warns of
    for t in ours.simplices:  # still Delaunay: no grid point strictly inside a (counterclockwise) triangle's circumcircle
        for q in grid:
            rows = [[*(grid[v] - q), float(((grid[v] - q) ** 2).sum())] for v in t]
            assert round(float(np.linalg.det(np.array(rows)))) <= 0  # small integers: the determinant is an integer


def test_of_equal_rows_the_first_is_kept() -> None:
    rng = np.random.default_rng(5)
    base = rng.random((40, 3))
    pts = np.vstack([base, base])
    hull = persistri.ConvexHull(pts)
    assert (hull.vertices < 40).all() and len(hull.vertices) == len(spatial.ConvexHull(pts).vertices)
    assert sorted(hull.duplicates[:, 0].tolist()) == list(range(40, 80))
    tri = persistri.Delaunay(pts[:, :2])
    assert (tri.simplices < 40).all() and tri.nsimplex == spatial.Delaunay(pts[:, :2]).nsimplex


def test_a_nan_query_is_refused() -> None:
    tri = persistri.Delaunay([[0, 0], [1, 0], [0, 1]])
    with pytest.raises(ValueError, match="not finite"):
        tri.find_simplex([[np.nan, 0.5]])
    assert spatial.Delaunay([[0, 0], [1, 0], [0, 1]]).find_simplex([[np.nan, 0.5]]).tolist() == [-1]
