"""One tile of a tiled terrain: greedy insertion of its interior samples, with its border vertices laid in.

Paper §5 (Garland–Heckbert greedy insertion on the persistent Delaunay
triangulation), run on one tile of :mod:`persistri.impl.scale.terrain`.  The
mesh starts as the tile's rectangle split along its Delaunay diagonal, holding
the tile's *interior* samples; the worst interior sample is inserted until every
one is within ``max_error``; then the tile's border vertices — those its four
seams chose (:mod:`persistri.impl.scale.terrain_seams`) — are laid in, each
fan measured and queued as an insertion's is; then greedy insertion goes on
until every interior sample is within ``max_error`` again.  The samples on the
tile's rim that are not border vertices are never inserted and never measured
here: their error is their seam's.  (Laying the border vertices first gives the
same guarantee, but their triangulation is long thin triangles across the tile
whose circumcircles hold most samples, so each early insertion re-sorts nearly
all of them: measured, twice the time and three times the memory.)

Why the tile's rim is exactly the seams' polylines.  Every interior sample lies
strictly inside the rectangle, in conflict with no ghost (no hull edge), so no
interior insertion changes the hull: before the border vertices it is the
rectangle of the corners, with the border vertices laid so far.  Each border
vertex lies on the open segment of one hull edge — from the last vertex laid
on its side to the side's far corner — which it *splits*
(:mod:`persistri.impl.terrain.delaunay`: a point exactly on a hull edge is in
conflict with the ghost there, and no zero-area triangle is ever made).  So
once they are all laid the hull is the rectangle with every border vertex on
it, its hull edges join consecutive border vertices of each side, and the
interior insertions after them leave it so.  The mesh's boundary is the four
seams' polylines, vertex for vertex.

Measured as :mod:`persistri.impl.terrain.greedy` measures: the float vertical
error against each triangle's plane written around its *apex* (its newest
vertex), a priority queue of one candidate per triangle, dead triangles skipped
lazily.  The module drives the :class:`~persistri.impl.terrain.delaunay.Triangulator`
itself because :func:`~persistri.impl.terrain.greedy.greedy_insertion` cannot
start from given vertices nor restrict its candidates to part of the grid.

Cost: as greedy insertion on the tile's ``h × w`` samples — per insertion O(k)
complex operations and exact tests for a cavity of k triangles, O(m·k) orient2d
tests and O(m) float work for the m samples that move — plus one hull-edge split
per border vertex, into a mesh already fine near the rim (a small cavity).  Memory: O(h·w) (the heights and the sample lists; the points are their indices)
plus the complex's versions, none of them the grid's.
"""

from __future__ import annotations

import gc
import heapq
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.geometry.grid_predicates import GridPredicates2
from persistri.impl.maps import backend as map_backend
from persistri.impl.terrain.delaunay import Insertion, TriDatum, Triangulator

__all__ = ["TileMesh", "mesh_tile", "tile_plane_errors"]

IntArray = NDArray[np.intp]
FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class TileMesh:
    """The mesh of one tile, in the tile's own sample indices (``row · w + col`` of its ``h × w`` window).

    * ``vertices`` — the sample index of each vertex, in insertion order (corners,
      interior samples by error, border vertices side by side, interior samples again);
    * ``triangles`` — ``(m, 3)`` sample indices, counterclockwise in ``(x, y) = (col, row)``;
    * ``max_error``, ``scale``, ``scaled_squares`` — over the tile's *interior*
      samples: the largest error, and the sum of squared errors as
      ``scale² · scaled_squares``;
    * ``interior`` — how many interior samples the tile has.
    """

    vertices: IntArray
    triangles: IntArray
    max_error: float
    scale: float
    scaled_squares: float
    interior: int


def tile_plane_errors(w: int, z: FloatArray, tri: IntArray, counts: IntArray, samples: IntArray) -> FloatArray:
    """``|z[s] − plane(t)(x[s], y[s])|`` for samples grouped by triangle: ``counts[i]`` consecutive ones in ``tri[i]``.

    Points are the samples of a grid ``w`` columns wide: ``x = s mod w``, ``y = s div w``
    (small integers, exact in float64).  Each row of ``tri`` starts at the apex
    the plane is written around: ``z_a + g_x (x − x_a) + g_y (y − y_a)``, the
    gradient by Cramer's rule.  The fans of insertions and the final mesh are
    measured by this one function, so the queue's errors and the reported ones
    are the same floats.  O(k + len(samples)).
    """
    def xy(i: IntArray) -> tuple[FloatArray, FloatArray]:
        q, r = np.divmod(i, w)
        return r.astype(np.float64), q.astype(np.float64)

    (xa, ya), (xb, yb), (xc, yc) = xy(tri[:, 0]), xy(tri[:, 1]), xy(tri[:, 2])
    za = z[tri[:, 0]]
    dx1, dy1, dz1 = xb - xa, yb - ya, z[tri[:, 1]] - za
    dx2, dy2, dz2 = xc - xa, yc - ya, z[tri[:, 2]] - za
    det = dx1 * dy2 - dx2 * dy1
    gx = (dz1 * dy2 - dz2 * dy1) / det
    gy = (dx1 * dz2 - dx2 * dz1) / det
    rep = np.repeat(np.arange(tri.shape[0]), counts)
    xs, ys = xy(samples)
    err: FloatArray = np.abs(z[samples] - (za[rep] + gx[rep] * (xs - xa[rep]) + gy[rep] * (ys - ya[rep])))
    return err


def _apex_first(tri: IntArray, rank: IntArray) -> IntArray:
    """Each triangle rotated (orientation kept) to start at its vertex of largest ``rank`` (the newest)."""
    k = np.argmax(rank[tri], axis=1)
    out: IntArray = np.take_along_axis(tri, (k[:, None] + np.arange(3)[None, :]) % 3, axis=1)
    return out


class _TileRun:
    """The state of one tile's greedy insertion: the triangulator, the queue, the insertion ranks."""

    def __init__(self, z: FloatArray, shape: tuple[int, int], backend: str) -> None:
        h, w = shape
        self.z = z
        self.w = w
        self.pred = GridPredicates2((h, w))  # the points (col, row) from their indices: no per-sample coordinates
        self.structure: TwoComplex[TriDatum] = TwoComplex(map_backend(backend))
        # Greedy insertion's conflict rule: a sample on a circumcircle is not in conflict (strict=True; the
        # triangulator's module docstring says why), as in the untiled run.
        self.T = Triangulator(self.pred, self.structure, strict=True)
        self.rank = np.full(h * w, -1, dtype=np.intp)
        self.order: list[int] = []
        self.heap: list[tuple[float, int, int]] = []

    def _ranked(self, p: int) -> None:
        self.rank[p] = len(self.order)
        self.order.append(p)

    def begin(self, corners: tuple[int, int, int, int], interior: IntArray) -> None:
        """The rectangle of the corners (counterclockwise) split along its Delaunay diagonal, holding ``interior``."""
        a, b, c, d = corners
        P = self.pred
        for v in corners:
            self._ranked(v)
        # The corners are cocircular: the predicates' tie-breaking picks the diagonal, as greedy insertion does.
        if P.incircle(a, b, c, d) < 0:
            t1, t2, u, v = (a, b, c), (a, c, d), a, c
        else:
            t1, t2, u, v = (b, c, d), (a, b, d), b, d
        side = P.orient2d_batch(u, v, interior) if interior.size else np.zeros(0, dtype=np.int8)
        # t1 is right of the diagonal u → v, t2 left of it (a sample on the diagonal goes by SoS).
        self.T.begin([(t1, interior[side < 0]), (t2, interior[side > 0])])

    def split_hull_edge(self, p: int, u: int, w: int) -> None:
        """Insert ``p``, which lies on the open segment of the hull edge ``u → w`` (counterclockwise), splitting it."""
        V = self.T.vertex
        found = self.structure.neighbour(self.T.complex, (V(w), V(u)))  # the ghost outside the edge
        if found is None or found[0][2] != self.T.infinite:
            raise AssertionError(f"tile: {(u, w)} is not a hull edge when inserting border vertex {p}")
        ins = self.T.insert(p, found[1][0])
        self._ranked(p)
        self._assess(ins)

    def assess_all(self) -> None:
        """Queue the candidate of every finite triangle (the first two)."""
        tids, tris, lists = [], [], []
        for tri, (tid, samples) in self.T.finite_triangles():
            if samples.size:
                tids.append(tid)
                tris.append(tri)
                lists.append(samples)
        if not tids:
            return
        tri_arr = _apex_first(np.array(tris, dtype=np.intp).reshape(-1, 3), self.rank)
        counts = np.fromiter(map(len, lists), dtype=np.intp, count=len(lists))
        samples = np.concatenate(lists)
        err = tile_plane_errors(self.w, self.z, tri_arr, counts, samples)
        self._queue(tids, counts.tolist(), samples, err)

    def _queue(self, tids: list[int], counts: list[int], samples: IntArray, err: FloatArray) -> None:
        start = 0
        for tid, cnt in zip(tids, counts):
            if cnt:
                part = err[start : start + cnt]
                i = int(part.argmax())
                e = float(part[i])
                if e > 0.0:
                    heapq.heappush(self.heap, (-e, tid, int(samples[start + i])))
                start += cnt

    def _assess(self, ins: Insertion) -> None:
        """Measure the samples of the insertion's fan (apex: the new point) and queue their triangles' candidates."""
        if not sum(ins.counts):
            return
        # A large fan reports one array per triangle and no pooled one (Triangulator.insert).
        samples = ins.samples if ins.samples is not None else np.concatenate(ins.lists)
        p = ins.point
        ring = np.fromiter(ins.rays, dtype=np.intp, count=len(ins.rays))
        tri = np.empty((ring.size - 1, 3), dtype=np.intp)
        tri[:, 0] = p  # the apex: every fan triangle's newest vertex
        tri[:, 1] = ring[:-1]
        tri[:, 2] = ring[1:]
        err = tile_plane_errors(self.w, self.z, tri, np.asarray(ins.counts, dtype=np.intp), samples)
        self._queue([tid for tid, _ in ins.created], ins.counts, samples, err)

    def worst(self) -> float:
        """The largest error of the current mesh (0 when every interior sample is a vertex)."""
        heap, alive = self.heap, self.T.tri_of
        while heap and heap[0][1] not in alive:
            heapq.heappop(heap)
        return -heap[0][0] if heap else 0.0

    def step(self) -> None:
        _, tid, p = heapq.heappop(self.heap)
        self._ranked(p)
        self._assess(self.T.insert(p, tid))


def mesh_tile(
    z: FloatArray,
    top: IntArray,
    right: IntArray,
    bottom: IntArray,
    left: IntArray,
    max_error: float,
    *,
    backend: str = "red_black",
) -> TileMesh:
    """Mesh the ``h × w`` heights ``z`` of one tile from its border vertices (module docstring).

    ``top``, ``bottom`` are the chosen columns on rows ``0`` and ``h − 1``; ``left``,
    ``right`` the chosen rows on columns ``0`` and ``w − 1`` — each increasing,
    from ``0`` to ``w − 1`` (``h − 1``), ends included, as
    :func:`~persistri.impl.scale.terrain_seams.seam_vertices` returns them.
    Greedy insertion of interior samples stops when the worst one is within
    ``max_error``.  Deterministic: the same inputs give the same mesh in any process.
    """
    z = np.ascontiguousarray(z, dtype=np.float64)
    h, w = (int(v) for v in z.shape)
    for name, pos, n in (("top", top, w), ("bottom", bottom, w), ("left", left, h), ("right", right, h)):
        if pos.size < 2 or int(pos[0]) != 0 or int(pos[-1]) != n - 1 or bool(np.any(np.diff(pos) <= 0)):
            raise ValueError(f"mesh_tile: the {name} seam's vertices must increase from 0 to {n - 1}")
    flat = z.ravel()
    collector = gc.isenabled()
    gc.disable()  # persistent nodes make no reference cycles: the cyclic collector would only cost time (as greedy insertion)
    try:
        return _mesh(flat, (h, w), top, right, bottom, left, float(max_error), backend)
    finally:
        if collector:
            gc.enable()


def _mesh(flat: FloatArray, shape: tuple[int, int], top: IntArray, right: IntArray, bottom: IntArray, left: IntArray,
          e: float, backend: str) -> TileMesh:
    h, w = shape
    run = _TileRun(flat, (h, w), backend)
    inner = np.zeros((h, w), dtype=bool)
    inner[1:-1, 1:-1] = True
    a, b, c, d = 0, w - 1, h * w - 1, (h - 1) * w  # counterclockwise in (x, y) = (col, row)
    run.begin((a, b, c, d), np.flatnonzero(inner.ravel()).astype(np.intp))
    run.assess_all()
    # Interior first: laid first, the border vertices would make long thin triangles across the tile whose
    # huge circumcircles put most samples in the cavity of each early insertion (measured: twice the time,
    # three times the memory).  Laid into the refined mesh, each splits a short hull edge.
    while run.worst() > e:
        run.step()
    # Each side's inner vertices in counterclockwise order; each splits the hull edge from the last one to the side's end.
    sides = (
        ([int(k) for k in top[1:-1]], a, b),  # row 0, columns increasing
        ([int(k) * w + w - 1 for k in right[1:-1]], b, c),  # column w-1, rows increasing
        ([(h - 1) * w + int(k) for k in bottom[-2:0:-1]], c, d),  # row h-1, columns decreasing
        ([int(k) * w for k in left[-2:0:-1]], d, a),  # column 0, rows decreasing
    )
    for points, start, end in sides:
        u = start
        for p in points:
            run.split_hull_edge(p, u, end)
            u = p
    while run.worst() > e:
        run.step()
    # The final mesh, measured over its triangles' sample lists with the queue's formula.
    items = run.T.finite_triangles()
    tri = np.array([t for t, _ in items], dtype=np.intp).reshape(-1, 3)
    lists = [datum[1] for _, datum in items]
    counts = np.fromiter(map(len, lists), dtype=np.intp, count=len(lists))
    if counts.sum():
        err = tile_plane_errors(w, flat, _apex_first(tri, run.rank), counts, np.concatenate(lists))
        top_err = float(err.max())
        squares = float(np.sum((err / top_err) ** 2)) if top_err > 0 else 0.0
    else:
        top_err = squares = 0.0
    return TileMesh(
        vertices=np.array(run.order, dtype=np.intp),
        triangles=tri,
        max_error=top_err,
        scale=top_err,
        scaled_squares=squares,
        interior=(h - 2) * (w - 2),
    )
