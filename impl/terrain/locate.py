"""Exact point location in a finished Delaunay triangulation, for query points that are not its vertices.

:func:`locate_points` answers scipy's ``find_simplex`` (:class:`persistri.Delaunay`):
for each query point, a triangle that contains it — boundary included — or -1
when it is outside the convex hull.  Every decision is an exact ``orient2d``
sign (the predicates' filter, then integers; :mod:`persistri.impl.geometry.predicates`)
on the query's own coordinates, with no epsilon and no perturbation: a point
exactly on an edge or a vertex is inside, a point outside by the smallest
representable amount is outside.

The walk (paper §5 locates new points the same way) starts every query at a
triangle of its nearest vertex (a k-d tree, a heuristic only) and, all queries
at once, crosses an edge that has the query strictly on its far side, choosing
among such edges in a rotating order; a triangle with no such edge contains the
query.  Crossing a hull edge means the query is strictly outside the line of
that edge, hence outside the hull (the hull is convex).  On a Delaunay
triangulation the walk cannot cycle: crossing an edge towards the query
strictly lowers the query's power with respect to the triangles' circumcircles,
except between triangles of one circle, whose dual graph is a tree.  A walk
exceeding a linear number of steps (never seen) falls back to testing every
triangle, exactly.

Expected cost: O(q log n) for the k-d tree and a few steps per query, each step
three exact ``orient2d`` tests vectorised over the queries still walking.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.geometry.exact import orient2d_det
from persistri.impl.geometry.filter import ERRBOUND_ORIENT2D, FLOPS_ORIENT2D, orient2d_terms
from persistri.impl.geometry.points import as_points
from persistri.impl.geometry.predicates import Predicates2

__all__ = ["locate_points", "start_triangles"]

IntArray = NDArray[np.intp]
SignArray = NDArray[np.int8]


class _Located(Predicates2):
    """The triangulation's points followed by the queries, with the true orient2d sign over index arrays."""

    __slots__ = ()

    def orient2d_sign_many(self, a: ArrayLike, b: ArrayLike, c: ArrayLike) -> SignArray:
        """``[orient2d_sign(a[k], b[k], c[k]) for k …]``: true signs (0 included), arguments broadcast. O(length)."""
        idx = self._index_arrays(a, b, c)
        return self._many(idx, orient2d_terms, ERRBOUND_ORIENT2D, FLOPS_ORIENT2D, orient2d_det, self.orient2d_sign, None)


def start_triangles(points: NDArray[np.float64], triangles: IntArray, queries: NDArray[np.float64]) -> IntArray:
    """A triangle at the vertex nearest each query (scipy's k-d tree on rescaled floats): where walks begin. O(q log n)."""
    from scipy.spatial import cKDTree

    used = np.unique(triangles)
    with np.errstate(all="ignore"):
        lo = points[used].min(axis=0)
        span = points[used].max(axis=0) - lo
        span = np.where(np.isfinite(span) & (span > 0), span, 1.0)
        # Rescaled to the unit box (queries far outside are clipped: only nearness matters here).
        verts = np.clip((points[used] - lo) / span, -4.0, 5.0)
        q = np.clip((queries - lo) / span, -4.0, 5.0)
        q = np.where(np.isfinite(q), q, 0.0)
        verts = np.where(np.isfinite(verts), verts, 0.0)
    _, nearest = cKDTree(verts).query(q)
    owner = np.full(points.shape[0], -1, dtype=np.intp)
    owner[triangles.ravel()] = np.repeat(np.arange(triangles.shape[0], dtype=np.intp), 3)
    out: IntArray = owner[used[np.asarray(nearest, dtype=np.intp)]]
    return out


def locate_points(
    points: ArrayLike, triangles: ArrayLike, neighbors: ArrayLike, queries: ArrayLike, *, max_steps: int | None = None
) -> IntArray:
    """For each row of ``queries`` (``(q, 2)``), a triangle containing it (closed), or -1 outside the hull.

    ``triangles`` (``(m, 3)``, counterclockwise, indices into ``points``) must be
    a Delaunay triangulation of the points' convex hull and ``neighbors`` its
    adjacency (``neighbors[i, j]`` across the edge opposite vertex ``j``, -1 on
    the hull: :func:`persistri.impl.complex.adjacency.triangle_neighbors`).
    Exact (module docstring).  ``queries`` must be finite reals: a NaN or
    infinite row raises :class:`ValueError` naming it.  ``max_steps`` bounds the
    walk (default ``4m + 16``); a query still walking then is located by testing
    every triangle (O(m) each).
    """
    pts = as_points(points, 2)
    tri = np.asarray(triangles, dtype=np.intp)
    nbr = np.asarray(neighbors, dtype=np.intp)
    qs = as_points(queries, 2, what="xi")
    n, q = pts.shape[0], qs.shape[0]
    if q == 0 or tri.shape[0] == 0:
        return np.full(q, -1, dtype=np.intp)
    pred = _Located(np.concatenate([pts, qs]))
    result = np.full(q, -1, dtype=np.intp)
    cur = start_triangles(pts, tri, qs)
    active = np.arange(q, dtype=np.intp)
    limit = 4 * tri.shape[0] + 16 if max_steps is None else max_steps
    for step in range(limit):
        if not active.size:
            return result
        t = cur[active]
        corners = tri[t]
        move = np.full(active.size, -1, dtype=np.intp)
        undecided = np.arange(active.size)
        for k in range(3):
            j = (step + k) % 3  # the edge opposite vertex j: (corners[j+1], corners[j+2])
            u = corners[undecided, (j + 1) % 3]
            w = corners[undecided, (j + 2) % 3]
            far = pred.orient2d_sign_many(u, w, n + active[undecided]) < 0
            move[undecided[far]] = j
            undecided = undecided[~far]
        inside = move < 0
        result[active[inside]] = t[inside]
        walking = np.flatnonzero(~inside)
        nxt = nbr[t[walking], move[walking]]
        # Strictly beyond a hull edge's line: outside the (convex) hull; result stays -1.
        cur[active[walking]] = nxt
        active = active[walking[nxt >= 0]]
    # Not reached on a Delaunay triangulation (module docstring); kept exact all the same.
    for k in active.tolist():
        qk = np.full(tri.shape[0], n + k, dtype=np.intp)
        signs = [pred.orient2d_sign_many(tri[:, (j + 1) % 3], tri[:, (j + 2) % 3], qk) for j in range(3)]
        hit = np.flatnonzero((signs[0] >= 0) & (signs[1] >= 0) & (signs[2] >= 0))
        result[k] = int(hit[0]) if hit.size else -1
    return result
