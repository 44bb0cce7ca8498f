"""``interior_filter``: the points of a chunk that provably are not hull vertices, found before the hull is built.

Akl and Toussaint (1978) observed that a few extreme points of a point set span
a polytope ``P`` and that a point strictly inside ``P`` cannot be a vertex of
the hull: dropping it first changes nothing.  For a chunk of ``m`` points
uniform in a ball, all but a few thousand are such points, and the bulldozer
(§3) would otherwise carry every one of them through its conflict lists — most
of a chunk hull's time (``docs/scale-out.md``, cost model).  This module finds
them with vectorised float arithmetic and *proves* each drop exactly; a point
the float arithmetic cannot decide is kept.

**The polytope.**  The points are cut into a grid of ``G³`` cells by float
arithmetic (any assignment would do: nothing below relies on it) and each
occupied cell gets the exact bounding box of its points.  The *candidates* are
the points that attain a coordinate extreme of a cell on the grid's outer
layer (an occupied cell with an empty or missing face neighbour; on a grid of
:data:`GRID_MAX` cells per axis, of the grid one level coarser, for fewer
triangles); Qhull
(``scipy.spatial.ConvexHull``) triangulates their hull.  Qhull computes in
floating point and none of its geometry is trusted: only its triangles, as
index triples, are used, and only after checking that they form a closed,
consistently oriented surface ``Σ`` (every directed edge in exactly one
triangle and its reverse in exactly one).  The vertices of ``Σ`` are a set
``E`` of the chunk's points.

**Why a point below every triangle of Σ is strictly inside conv(E).**  Let
``x`` satisfy ``orient3d(a, b, c, x) > 0`` — strictly, exactly — for every
triangle ``(a, b, c)`` of ``Σ``.  The signed solid angle under which ``x``
sees a triangle has the sign of ``orient3d(a, b, c, x)``, so the sum over
``Σ`` is positive; for a closed oriented surface that sum is ``4π`` times the
winding number of ``Σ`` around ``x``, which is therefore at least 1.  A point
outside ``conv(E)``, or on its boundary but not on ``Σ``, has winding number
0 (a plane through it leaves all of ``E`` on one closed side, and ``x`` can be
moved off to the other side without crossing ``Σ``); a point on ``Σ`` lies in
the plane of some triangle (``orient3d = 0``).  So ``x`` is in the interior of
``conv(E)``.  This holds whether or not Qhull's surface is convex.

**Why dropping such a point is exact, also under Simulation of Simplicity.**
``x`` strictly inside ``conv(E)`` is not a vertex of the hull of any set that
contains ``E`` — in particular of the chunk and of the whole input.  The hulls
of :mod:`persistri.impl.scale.hull` are those of the points perturbed
symbolically (:mod:`persistri.impl.geometry.sos`); the perturbation is
infinitesimal, the finitely many strict inequalities above persist for all
small enough perturbations, so the perturbed ``x`` is strictly inside the hull
of the perturbed ``E`` and is not a vertex either, whatever the labels.  A point
*on* the boundary of ``P`` — a vertex of ``E``, a duplicate of one, a point on a
face or an edge, as on grids and coplanar faces — makes some ``orient3d``
zero and is kept: on degenerate input the perturbation decides whether such a
point is a vertex, and the filter leaves that to the hull.  Every hull vertex
of the chunk (and of the whole input) survives the filter, and the hull of the
survivors has exactly the chunk's hull vertices: the filter changes the work,
not the result.

**The signs, exactly.**  Each test is one of the proved floating-point
filters of :mod:`persistri.impl.geometry.filter`, evaluated by the very
functions the proof covers, on copies of the points scaled by a power of two
(exact, :func:`~persistri.impl.geometry.filter.choose_scaling`, chosen from
every coordinate the tests read; a set whose dynamic range needs per-test
grain checks is not filtered at all):

* a triangle's plane by :func:`~persistri.impl.geometry.filter.plane_terms`
  and a point's side by :func:`~persistri.impl.geometry.filter.plane_side_det`,
  decided when the determinant exceeds the semi-static threshold of the
  chunk's box (:func:`~persistri.impl.geometry.filter.plane_side_box_threshold`,
  valid for planes through points of the box and query points in it);
  anything else counts as undecided, hence kept;
* a whole cell at once: a plane-side determinant is linear in the query point,
  so it is positive on a box if it is positive at the box's corner farthest
  along the normal.  Each normal component's sign is the sign of a 2D
  orientation of the triangle's projection — :func:`plane_terms` computes it
  in the operations of :func:`~persistri.impl.geometry.filter.orient2d_terms`,
  with its permanent — and is certified by the orient2d filter
  (:data:`~persistri.impl.geometry.filter.ERRBOUND_ORIENT2D`); with all three
  certified one corner is tested, else all eight.  The corners' coordinates
  are coordinates of the cell's points, so they are in the box and share the
  points' grains.

**The search.**  Cells are tested against triangles level by level, from
``4³`` cells to ``G³``, each cell's bounding box covering its points: a pair
(cell, triangle) positive over the box is settled for all the cell's points,
the others go down to the cell's eight children.  A cell with no pair left
has every point strictly inside; the points of the cells left are tested one
by one against their cell's remaining triangles.  For points uniform in a
ball the cells near the surface keep a few triangles each.  First, though,
:data:`_SAMPLE` points spread over the input are tested against every
triangle in plain float arithmetic: if fewer than half seem inside (points on
a sphere, where all of them are on the surface), the search is skipped and
nothing is dropped — an estimate that decides the work, never a drop.

Cost for ``m`` points: O(m) vectorised (cells, boxes, candidates, the points
tested one by one), Qhull on O(G²) candidates, and per level O(pairs) plane
tests — about ``64·F`` at the first level for a surface of ``F`` triangles,
then the pairs near the surface.  Measured on 2M points uniform in a ball: about
0.4 s of CPU, 99.4 % of the points dropped (12,744 kept for 6,318 hull vertices;
``docs/scale-out.md``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from persistri.impl.geometry.exact import grain_span
from persistri.impl.geometry.filter import (
    ERRBOUND_ORIENT2D,
    GRAIN_MIN,
    TOP_MAX,
    choose_scaling,
    plane_side_box_threshold,
    plane_side_det,
    plane_terms,
)

__all__ = ["Prefilter", "interior_filter", "column_extremes", "MIN_POINTS", "GRID_MAX"]

IntArray = NDArray[np.intp]
FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

MIN_POINTS = 1024
"""Below this many points :func:`interior_filter` drops nothing: the hull itself is as quick."""

GRID_MAX = 64
"""The finest grid has at most ``GRID_MAX³`` cells (about eight points a cell up to there)."""

_FIRST_LEVEL = 4
"""Cells per axis of the first level of the search."""

_SAMPLE = 256
"""Points of a chunk tested first, in plain float arithmetic, to estimate what the search would drop."""

_WORTH = 0.5
"""The search runs only if at least this fraction of the sample seems strictly inside the surface."""

_BATCH = 1 << 18
"""Plane-side tests evaluated at once: bounds the filter's temporaries (a few MiB each)."""


@dataclass(frozen=True)
class Prefilter:
    """What :func:`interior_filter` found for ``points`` points.

    ``keep`` — the indices of the points not proved interior, increasing (every hull
    vertex among them); ``faces`` — triangles of the filter surface (0: no surface,
    nothing dropped); ``tested`` — points tested one by one (the others were settled
    with their cell).
    """

    points: int
    keep: IntArray
    faces: int
    tested: int

    @property
    def dropped(self) -> int:
        """The points proved strictly inside the filter surface, hence not hull vertices."""
        return self.points - int(self.keep.size)


@dataclass(frozen=True)
class _Faces:
    """The triangles of the surface Σ, scaled, prepared for plane-side tests (one entry per triangle)."""

    ax: FloatArray
    ay: FloatArray
    az: FloatArray
    nx: FloatArray
    ny: FloatArray
    nz: FloatArray
    certified: BoolArray  # all three normal components' signs proved
    threshold: float  # the semi-static plane-side threshold of the chunk's box

    @property
    def count(self) -> int:
        return int(self.ax.size)

    def inner_on_boxes(self, f: IntArray, cells: IntArray, bmin: FloatArray, bmax: FloatArray) -> BoolArray:
        """For each pair ``(f[i], cells[i])``: is ``orient3d(a, b, c, q) > 0`` proved for every ``q`` of the
        cell's box (``bmin``, ``bmax``: all the level's boxes)?  In batches of :data:`_BATCH` pairs."""
        ok = np.empty(f.size, dtype=bool)
        for lo in range(0, f.size, _BATCH):
            part = slice(lo, lo + _BATCH)
            c = cells[part]
            ok[part] = self._inner_on_boxes(f[part], bmin[:, c], bmax[:, c])
        return ok

    def _inner_on_boxes(self, f: IntArray, bmin: FloatArray, bmax: FloatArray) -> BoolArray:
        nx, ny, nz = self.nx[f], self.ny[f], self.nz[f]
        ax, ay, az = self.ax[f], self.ay[f], self.az[f]
        # The corner farthest along the normal: where the determinant (a - q)·n is least.
        qx = np.where(nx > 0, bmax[0], bmin[0])
        qy = np.where(ny > 0, bmax[1], bmin[1])
        qz = np.where(nz > 0, bmax[2], bmin[2])
        ok: BoolArray = (plane_side_det(nx, ny, nz, ax, ay, az, qx, qy, qz) > self.threshold) & self.certified[f]
        loose = np.flatnonzero(~self.certified[f])
        if loose.size:
            # A normal component whose sign is not proved: every corner of those boxes.
            lo, hi = bmin[:, loose], bmax[:, loose]
            nx, ny, nz, ax, ay, az = nx[loose], ny[loose], nz[loose], ax[loose], ay[loose], az[loose]
            every = np.ones(loose.size, dtype=bool)
            for cx in (lo[0], hi[0]):
                for cy in (lo[1], hi[1]):
                    for cz in (lo[2], hi[2]):
                        every &= plane_side_det(nx, ny, nz, ax, ay, az, cx, cy, cz) > self.threshold
            ok[loose] = every
        return ok


def interior_filter(points: FloatArray, *, min_points: int = MIN_POINTS) -> Prefilter:
    """The points of ``points`` (validated, ``(m, 3)`` finite float64) not proved strictly inside their hull.

    Every hull vertex of ``points`` is kept, under any Simulation of Simplicity
    labelling, and so is every point the float filters cannot decide (module
    docstring); duplicates of kept points are kept.  Below ``min_points`` points, for
    coplanar points, when Qhull or the surface check fails, or when a sample of the points suggests that
    fewer than half would be dropped (points on a sphere), nothing is dropped.
    O(m) vectorised plus the search (module docstring).
    """
    pts = np.asarray(points, dtype=np.float64)
    m = pts.shape[0]
    nothing = Prefilter(m, np.arange(m, dtype=np.intp), 0, 0)
    if m < max(min_points, 5):
        return nothing
    lo, hi = column_extremes(pts)
    side = hi - lo
    if not bool(np.all(side > 0)):  # flat: no interior at all
        return nothing
    grid = _grid(m)
    cell = _cells(pts, lo, side, grid)
    boxes = _pyramid(*_boxes(pts, cell, grid))
    cmin, cmax = boxes[grid]
    occupied = cmin[0] <= cmax[0]
    # On the finest grids, candidates from the cells one level up: a quarter of the triangles for a slightly
    # looser surface, which the search pays for in proportion (measured on 2M points in a ball: the filter
    # and the hull of the survivors together take least time so).
    coarse = grid // 2 if grid >= GRID_MAX else grid
    k = grid // coarse
    i, rest = np.divmod(cell, grid * grid)
    j, kk = np.divmod(rest, grid)
    up = ((i // k) * coarse + j // k) * coarse + kk // k
    candidates = _candidates(pts, up, *boxes[coarse], coarse)
    triangles = _surface(pts, candidates)
    if triangles is None or not _closed_oriented(triangles, m):
        return nothing
    corners = np.concatenate([cmin[:, occupied].ravel(), cmax[:, occupied].ravel()])
    shift = _shift(np.concatenate([corners, np.take(pts, np.unique(triangles), axis=0).ravel()]))
    if shift is None:
        return nothing
    slo, shi = np.ldexp(lo, shift), np.ldexp(hi, shift)
    threshold = plane_side_box_threshold(*(float(v) for v in shi - slo))
    if not np.isfinite(threshold):
        return nothing
    faces = _prepare(np.ldexp(np.take(pts, triangles, axis=0), shift), threshold)
    if _likely_inside(faces, np.ldexp(pts[:: max(1, m // _SAMPLE)][:_SAMPLE], shift)) < _WORTH:
        return nothing  # points on a sphere: nearly all on the surface, the search would cost and save nothing
    left, left_faces = _search(faces, {n: (np.ldexp(a, shift), np.ldexp(b, shift)) for n, (a, b) in boxes.items()}, grid)
    # Points of cells with no triangle left are inside; the others are tested one by one.
    open_cell = np.zeros(grid**3, dtype=bool)
    open_cell[left] = True
    tested = np.flatnonzero(open_cell[cell])
    inner = _inner_points(faces, np.take(pts, tested, axis=0), shift, cell[tested], left, left_faces, grid)
    drop = ~open_cell[cell]
    drop[tested[inner]] = True
    return Prefilter(m, np.flatnonzero(~drop), faces.count, int(tested.size))


def column_extremes(pts: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Each column's minimum and maximum (exact), column by column: ten times quicker than
    ``pts.min(axis=0)`` on a C-ordered ``(m, 3)`` array.  O(m)."""
    lo = np.array([pts[:, j].min() for j in range(pts.shape[1])])
    hi = np.array([pts[:, j].max() for j in range(pts.shape[1])])
    return lo, hi


def _grid(m: int) -> int:
    """Cells per axis: a power of two near ``(m / 4)^(1/3)``, from 4 to :data:`GRID_MAX`."""
    g = _FIRST_LEVEL
    while g < GRID_MAX and 4 * (2 * g) ** 3 <= m:
        g *= 2
    return g


def _cells(pts: FloatArray, lo: FloatArray, side: FloatArray, grid: int) -> IntArray:
    """Each point's cell ``(i·G + j)·G + k`` by float arithmetic (any assignment keeps the filter exact)."""
    cell = np.zeros(pts.shape[0], dtype=np.intp)
    for j in range(3):
        c = pts[:, j] - lo[j]
        c *= grid / side[j]
        np.clip(c, 0, grid - 1, out=c)
        cell *= grid
        cell += c.astype(np.intp)
    return cell


def _boxes(pts: FloatArray, cell: IntArray, grid: int) -> tuple[FloatArray, FloatArray]:
    """Each cell's exact bounding box, ``(3, G³)`` arrays of minima and maxima (``+inf``/``-inf`` if empty)."""
    n = grid**3
    cmin = np.full((3, n), np.inf)
    cmax = np.full((3, n), -np.inf)
    for j in range(3):
        np.minimum.at(cmin[j], cell, pts[:, j])
        np.maximum.at(cmax[j], cell, pts[:, j])
    return cmin, cmax


def _pyramid(cmin: FloatArray, cmax: FloatArray) -> dict[int, tuple[FloatArray, FloatArray]]:
    """The cells' boxes at every level, ``{cells per axis: (minima, maxima)}``, each level from the one below."""
    grid = round(cmin.shape[1] ** (1 / 3))
    out = {grid: (cmin, cmax)}
    while grid > _FIRST_LEVEL:
        half = grid // 2
        cmin, cmax = _halve(cmin, half, np.minimum), _halve(cmax, half, np.maximum)
        grid = half
        out[grid] = (cmin, cmax)
    return out


def _halve(a: FloatArray, half: int, op: np.ufunc) -> FloatArray:
    """``op`` over each 2 × 2 × 2 block of cells: three elementwise passes (a reduction over the three
    strided axes at once is several times slower)."""
    b = a.reshape(3, half, 2, half, 2, half, 2)
    b = op(b[:, :, 0], b[:, :, 1])  # (3, half, half, 2, half, 2)
    b = op(b[:, :, :, 0], b[:, :, :, 1])  # (3, half, half, half, 2)
    out: FloatArray = op(b[..., 0], b[..., 1]).reshape(3, -1)
    return out


def _candidates(pts: FloatArray, cell: IntArray, cmin: FloatArray, cmax: FloatArray, grid: int) -> IntArray:
    """The points attaining a coordinate extreme of an outer cell (occupied, with a face neighbour empty or missing)."""
    occ = (cmin[0] <= cmax[0]).reshape(grid, grid, grid)
    pad = np.pad(occ, 1, constant_values=False)
    inner = (
        pad[2:, 1:-1, 1:-1] & pad[:-2, 1:-1, 1:-1] & pad[1:-1, 2:, 1:-1]
        & pad[1:-1, :-2, 1:-1] & pad[1:-1, 1:-1, 2:] & pad[1:-1, 1:-1, :-2]
    )
    outer = (occ & ~inner).ravel()
    idx = np.flatnonzero(outer[cell])
    c = cell[idx]
    hit = np.zeros(idx.size, dtype=bool)
    for j in range(3):
        x = pts[idx, j]
        hit |= x == cmin[j, c]
        hit |= x == cmax[j, c]
    out: IntArray = idx[hit]
    return out


def _surface(pts: FloatArray, candidates: IntArray) -> IntArray | None:
    """Qhull's triangles of the candidates' hull, as point indices oriented outward (by Qhull's float normals:
    a choice, which :func:`_closed_oriented` then checks); None if Qhull fails."""
    if candidates.size < 4:
        return None
    from scipy.spatial import ConvexHull, QhullError

    sub = np.take(pts, candidates, axis=0)
    try:
        qh = ConvexHull(sub)
    except (QhullError, ValueError):
        return None
    simplices = np.asarray(qh.simplices, dtype=np.intp)
    a, b, c = (sub[simplices[:, k]] for k in range(3))
    # Orientation from Qhull's outward facet normals (float: only a choice, checked below).
    flip = np.einsum("ij,ij->i", np.cross(b - a, c - a), qh.equations[:, :3]) < 0
    simplices[flip] = simplices[flip][:, ::-1]
    tri: IntArray = candidates[simplices]
    return tri


def _closed_oriented(tri: IntArray, n: int) -> bool:
    """Whether every directed edge of ``tri`` occurs once and its reverse once (a closed oriented surface)."""
    if tri.shape[0] < 4:
        return False
    u = np.concatenate([tri[:, 0], tri[:, 1], tri[:, 2]]).astype(np.int64)
    v = np.concatenate([tri[:, 1], tri[:, 2], tri[:, 0]]).astype(np.int64)
    if bool(np.any(u == v)):
        return False
    edges = np.sort(u * n + v)
    if bool(np.any(edges[1:] == edges[:-1])):
        return False
    return bool(np.array_equal(edges, np.sort(v * n + u)))


def _shift(values: FloatArray) -> int | None:
    """The power-of-two scale the filters need for ``values`` (:func:`choose_scaling`); None if no single
    scale makes every grain and magnitude valid (the set is then not filtered)."""
    span = grain_span(values)
    if span is None:
        return None
    scaling = choose_scaling(np.array([span[0]], dtype=np.int64), np.array([span[1]], dtype=np.int64))
    return scaling.shift if scaling.uniform else None


def _prepare(corners: FloatArray, threshold: float) -> _Faces:
    """The triangles' planes by :func:`plane_terms`, and which normals have all three signs proved."""
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    nx, ny, nz, px, py, pz = plane_terms(a[:, 0], a[:, 1], a[:, 2], b[:, 0], b[:, 1], b[:, 2], c[:, 0], c[:, 1], c[:, 2])
    # Each component is an orient2d of the projected triangle, computed as orient2d_terms does, with its permanent.
    certified = (np.abs(nx) > ERRBOUND_ORIENT2D * px) & (np.abs(ny) > ERRBOUND_ORIENT2D * py) & (np.abs(nz) > ERRBOUND_ORIENT2D * pz)
    return _Faces(
        np.ascontiguousarray(a[:, 0]), np.ascontiguousarray(a[:, 1]), np.ascontiguousarray(a[:, 2]),
        nx, ny, nz, certified, threshold,
    )


def _likely_inside(faces: _Faces, sample: FloatArray) -> float:
    """The fraction of ``sample`` (scaled) strictly inside every triangle in plain float arithmetic: an
    estimate that decides whether to search, never what is dropped.  O(len(sample) · triangles)."""
    if not sample.shape[0]:
        return 0.0
    inside = np.ones(sample.shape[0], dtype=bool)
    step = max(1, _BATCH // faces.count)
    for lo in range(0, sample.shape[0], step):
        q = sample[lo : lo + step, :, None]
        det = plane_side_det(faces.nx, faces.ny, faces.nz, faces.ax, faces.ay, faces.az, q[:, 0], q[:, 1], q[:, 2])
        inside[lo : lo + step] = np.all(det > 0, axis=1)
    return float(inside.mean())


def _search(faces: _Faces, boxes: dict[int, tuple[FloatArray, FloatArray]], grid: int) -> tuple[IntArray, IntArray]:
    """The (cell, triangle) pairs of the finest grid not settled over the cell's box, sorted by cell.

    Level by level from :data:`_FIRST_LEVEL` cells per axis to ``grid`` (``boxes``, scaled, from
    :func:`_pyramid`): a pair settled for a cell is settled for its children; the others are tested
    again on each child's (smaller) box.
    """
    level = min(_FIRST_LEVEL, grid)
    pc: IntArray = np.zeros(0, dtype=np.intp)
    pf: IntArray = np.zeros(0, dtype=np.intp)
    parent = 0
    while True:
        lmin, lmax = boxes[level]
        occupied = np.flatnonzero(lmin[0] <= lmax[0])
        if parent == 0:
            pc = np.repeat(occupied, faces.count)
            pf = np.tile(np.arange(faces.count, dtype=np.intp), occupied.size)
        else:
            i, rest = np.divmod(occupied, level * level)
            j, k = np.divmod(rest, level)
            up = ((i // 2) * parent + j // 2) * parent + k // 2
            pc, pf = _expand(pc, pf, parent**3, occupied, up)
        ok = faces.inner_on_boxes(pf, pc, lmin, lmax)
        pc, pf = pc[~ok], pf[~ok]
        if level == grid:
            return pc, pf
        parent, level = level, 2 * level


def _expand(pc: IntArray, pf: IntArray, cells: int, children: IntArray, up: IntArray) -> tuple[IntArray, IntArray]:
    """Each child's pairs: its parent's (``pc`` sorted by cell, ``up`` each child's parent), children in order."""
    count = np.bincount(pc, minlength=cells)
    start = np.cumsum(count) - count
    n = count[up]
    has = n > 0
    children, up, n = children[has], up[has], n[has]
    total = int(n.sum())
    child = np.repeat(children, n)
    offset = np.repeat(start[up] - (np.cumsum(n) - n), n) + np.arange(total, dtype=np.intp)
    return child, pf[offset]


def _inner_points(
    faces: _Faces, q: FloatArray, shift: int, qcell: IntArray, pc: IntArray, pf: IntArray, grid: int
) -> BoolArray:
    """For each point of ``q`` (in cell ``qcell``): is it proved strictly inside every triangle its cell kept?"""
    if not q.shape[0]:
        return np.zeros(0, dtype=bool)
    span = grain_span(q)
    if span is not None and (span[0] + shift < GRAIN_MIN or span[1] + shift > TOP_MAX):
        return np.zeros(q.shape[0], dtype=bool)  # outside the scale the filters hold for: decide nothing
    count = np.bincount(pc, minlength=grid**3)
    start = np.cumsum(count) - count
    inner = np.empty(q.shape[0], dtype=bool)
    step = max(1, _BATCH // max(1, int(count.max())))  # points per batch: at most _BATCH pairs
    for lo in range(0, q.shape[0], step):
        part = slice(lo, lo + step)
        s = np.ldexp(q[part], shift)
        qc = qcell[part]
        n = count[qc]  # at least 1: the cell was kept for a pair
        first = np.cumsum(n) - n
        point = np.repeat(np.arange(s.shape[0], dtype=np.intp), n)
        offset = np.repeat(start[qc] - first, n) + np.arange(int(n.sum()), dtype=np.intp)
        f = pf[offset]
        det = plane_side_det(faces.nx[f], faces.ny[f], faces.nz[f], faces.ax[f], faces.ay[f], faces.az[f],
                             s[point, 0], s[point, 1], s[point, 2])
        inner[part] = np.logical_and.reduceat(det > faces.threshold, first)
    return inner
