"""Adjacency of a consistently oriented triangle array: neighbours across edges, vertex neighbourhoods.

The array form of what the complex answers one query at a time
(:meth:`~persistri.impl.complex.two_complex.TwoComplex.neighbour`, paper §2): in a
consistently oriented surface each oriented edge ``(u, w)`` belongs to exactly
one triangle, and the triangle across it is the one holding ``(w, u)``
(``find(c, flip(e))``).  Here whole ``(m, 3)`` arrays of vertex indices are
answered at once, with sorting instead of a map, for the public
``neighbors`` and ``vertex_neighbor_vertices`` arrays in scipy.spatial's
conventions (:mod:`persistri`).

>>> import numpy as np
>>> square = np.array([[0, 1, 2], [0, 2, 3]])     # two counterclockwise triangles
>>> triangle_neighbors(square).tolist()             # entry j: across the edge opposite vertex j
[[-1, 1, -1], [-1, -1, 0]]
>>> indptr, indices = vertex_neighbor_vertices(square, 5)
>>> indices[indptr[0]:indptr[1]].tolist(), indptr[4:].tolist()    # vertex 4 is in no triangle
([1, 2, 3], [10, 10])
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["triangle_neighbors", "vertex_neighbor_vertices", "vertex_to_simplex"]

IntArray = NDArray[np.intp]


def _triangles(simplices: ArrayLike) -> IntArray:
    tri = np.asarray(simplices)
    if tri.ndim != 2 or tri.shape[1] != 3 or (tri.size and tri.dtype.kind not in "iu"):
        raise ValueError(f"simplices must be an (m, 3) integer array, got shape {tri.shape} of {tri.dtype}")
    if tri.size and int(tri.min()) < 0:
        raise ValueError(f"simplices must hold vertex indices >= 0, got {int(tri.min())}")
    out: IntArray = tri.astype(np.intp, copy=False)
    return out


def triangle_neighbors(simplices: ArrayLike) -> IntArray:
    """``neighbors[i, j]``: the triangle across the edge of triangle ``i`` opposite its vertex ``j``, or -1.

    The edge opposite vertex ``j`` of ``(a, b, c)`` is the oriented edge
    ``(s[j+1], s[j+2])`` (indices mod 3); its neighbour is the triangle holding
    the reverse edge.  -1 where no triangle holds it (a boundary edge).  Raises
    :class:`ValueError` when an oriented edge occurs twice (the triangles are not
    a consistently oriented surface).  O(m log m), vectorised.
    """
    tri = _triangles(simplices)
    m = tri.shape[0]
    if m == 0:
        return np.zeros((0, 3), dtype=np.intp)
    base = np.int64(tri.max()) + 1
    # The edge opposite vertex j, as the key u·base + w of its orientation, for every (triangle, j).
    u = np.roll(tri, -1, axis=1).astype(np.int64)
    w = np.roll(tri, -2, axis=1).astype(np.int64)
    keys = (u * base + w).ravel()
    order = np.argsort(keys, kind="stable")
    ranked = keys[order]
    repeated = np.flatnonzero(ranked[1:] == ranked[:-1])
    if repeated.size:
        k = int(ranked[repeated[0]])
        raise ValueError(
            f"oriented edge ({k // int(base)}, {k % int(base)}) is in two triangles: not a consistently oriented surface"
        )
    reverse = (w * base + u).ravel()
    pos = np.minimum(np.searchsorted(ranked, reverse), ranked.size - 1)
    found = ranked[pos] == reverse
    out = np.where(found, order[pos] // 3, -1).astype(np.intp).reshape(m, 3)
    return out


def vertex_neighbor_vertices(simplices: ArrayLike, n_points: int) -> tuple[IntArray, IntArray]:
    """``(indptr, indices)``: the vertices joined to vertex ``k`` by an edge are ``indices[indptr[k]:indptr[k+1]]``.

    scipy.spatial's compressed-sparse-row convention, each vertex's neighbours
    sorted; a point in no triangle has none.  ``n_points`` must exceed every
    index.  O(m log m), vectorised.
    """
    tri = _triangles(simplices)
    if tri.size and int(tri.max()) >= n_points:
        raise ValueError(f"simplices refer to vertex {int(tri.max())}, but there are only {n_points} points")
    a = tri.ravel()
    b = np.roll(tri, -1, axis=1).ravel()
    # Both directions of every edge, each once (an interior edge is in two triangles).
    pairs = np.unique(np.stack([np.concatenate([a, b]), np.concatenate([b, a])], axis=1), axis=0)
    indptr = np.zeros(n_points + 1, dtype=np.intp)
    np.cumsum(np.bincount(pairs[:, 0], minlength=n_points), out=indptr[1:])
    indices: IntArray = pairs[:, 1].astype(np.intp)
    return indptr, indices


def vertex_to_simplex(simplices: ArrayLike, n_points: int) -> IntArray:
    """For each of ``n_points`` points, some triangle having it as a vertex, or -1. O(m)."""
    tri = _triangles(simplices)
    out = np.full(n_points, -1, dtype=np.intp)
    out[tri.ravel()] = np.repeat(np.arange(tri.shape[0], dtype=np.intp), 3)
    return out
