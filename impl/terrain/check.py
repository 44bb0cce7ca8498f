"""Exact verification of Delaunay triangulations and terrain meshes (``check=True``; paper §5).

:func:`verify_triangulation` decides, with exact predicates and independently of
how the mesh was built, that triangles over a point set form a Delaunay
triangulation of a given region:

1. every triangle is strictly counterclockwise (exact ``orient2d_sign > 0``:
   no zero-area triangle);
2. every directed edge is used once; an edge used in both directions is
   *interior*, one used in one direction is on the *boundary*;
3. the boundary is one closed cycle and equals the expected one — the
   rectangle's perimeter through every vertex on it (grids), or the exact convex
   hull of the points with every point on it (scattered points, computed here by
   Andrew's monotone chain with exact ``orient2d_sign``);
4. every interior edge is locally Delaunay: exact ``incircle_sign ≤ 0`` of the
   opposite vertex (0 = cocircular, allowed);
5. the vertices are exactly the expected points.

(1)–(3) make the triangles a triangulation of the region: the boundary chain
winds once around each point of the region, each positively oriented triangle
adds one to the winding count of its interior, so each point is covered exactly
once.  With (4), local Delaunay everywhere, the triangulation is Delaunay.

:func:`verify_tin` adds, for a :class:`~persistri.impl.terrain.greedy.Tin`:
every sample of the grid is a vertex or in the conflict list of exactly one
triangle and inside that (closed) triangle, exactly; and the maximum and RMS
errors recomputed from scratch by :func:`mesh_errors`, which rasterises the
triangles over the grid (exact inclusion tests on integer coordinates,
barycentric interpolation) — a different route from the run's plane errors.
The two float computations must agree to :data:`ERROR_RTOL` of the height
range: the error is a measurement in floating point, not a predicate.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.geometry.predicates import Predicates2

if TYPE_CHECKING:
    from persistri.impl.terrain.greedy import Tin

__all__ = [
    "TerrainCheckError",
    "CheckReport",
    "ERROR_RTOL",
    "verify_triangulation",
    "verify_tin",
    "mesh_errors",
    "root_mean_square",
    "ScaledSquares",
    "largest_magnitude",
    "RMS_BLOCK",
    "exact_hull",
]

IntArray = NDArray[np.intp]
FloatArray = NDArray[np.float64]

ERROR_RTOL: Final = 1e-9
"""Agreement required between two float evaluations of the vertical error, relative to max(1, height range)."""

_SHOWN: Final = 5


class TerrainCheckError(AssertionError):
    """A terrain or Delaunay mesh failed verification; the message lists what failed."""


@dataclass
class CheckReport:
    """The outcome of a verification: ``failures`` (empty when everything holds) and what was counted."""

    failures: list[str] = field(default_factory=list)
    counts: dict[str, int] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        """Whether every check passed."""
        return not self.failures

    def fail(self, message: str) -> None:
        """Record one failure."""
        self.failures.append(message)

    def raise_if_failed(self) -> None:
        """Raise :class:`TerrainCheckError` listing the failures, if any."""
        if self.failures:
            raise TerrainCheckError("; ".join(self.failures))


def exact_hull(pred: Predicates2, indices: IntArray) -> list[int]:
    """The convex hull of points ``indices`` of ``pred``, counterclockwise, with every point on its boundary.

    Andrew's monotone chain on exact ``orient2d_sign``: collinear boundary points
    are kept (a turn of sign 0 does not pop).  Starts at the lexicographically
    smallest point.  Points must be distinct.  O(n log n).
    """
    pts = pred.points
    idx = np.asarray(indices, dtype=np.intp)
    if idx.size < 3:
        return [int(i) for i in idx[np.lexsort((pts[idx, 1], pts[idx, 0]))]]
    order = [int(i) for i in idx[np.lexsort((pts[idx, 1], pts[idx, 0]))]]
    sign = pred.orient2d_sign

    def chain(seq: list[int]) -> list[int]:
        out: list[int] = []
        for q in seq:
            while len(out) >= 2 and sign(out[-2], out[-1], q) < 0:
                out.pop()
            out.append(q)
        return out

    lower = chain(order)
    upper = chain(order[::-1])
    if len(lower) == len(order) and all(sign(order[0], order[-1], q) == 0 for q in order):
        return order  # all collinear: no hull polygon
    return lower[:-1] + upper[:-1]


def _edges(tri: IntArray) -> tuple[dict[tuple[int, int], tuple[int, int]], list[str]]:
    """Directed edge → (triangle row, opposite vertex); failures for edges used twice in one direction."""
    table: dict[tuple[int, int], tuple[int, int]] = {}
    bad: list[str] = []
    for r, (a, b, c) in enumerate(tri.tolist()):
        for u, w, x in ((a, b, c), (b, c, a), (c, a, b)):
            if (u, w) in table:
                bad.append(f"edge {(u, w)} is used twice in the same direction (triangles {table[(u, w)][0]} and {r})")
            table[(u, w)] = (r, x)
    return table, bad


def verify_triangulation(
    pred: Predicates2,
    triangles: ArrayLike,
    *,
    vertices: ArrayLike | None = None,
    boundary: list[int] | None = None,
    report: CheckReport | None = None,
) -> CheckReport:
    """Verify that ``triangles`` (indices of ``pred``'s points) form a Delaunay triangulation (module docstring).

    ``vertices`` — the points that must be exactly the vertices (default: all of
    ``pred``'s points); ``boundary`` — the expected boundary cycle, counterclockwise
    (default: the exact convex hull of ``vertices`` with collinear points kept).
    Returns a :class:`CheckReport`; O(m log m) plus O(m) exact tests.
    """
    rep = report if report is not None else CheckReport()
    tri = np.asarray(triangles, dtype=np.intp).reshape(-1, 3)
    n = len(pred)
    verts = np.arange(n, dtype=np.intp) if vertices is None else np.unique(np.asarray(vertices, dtype=np.intp))
    rep.counts["triangles"] = int(tri.shape[0])
    if tri.size and (int(tri.min()) < 0 or int(tri.max()) >= n):
        rep.fail(f"triangle indices out of range 0..{n - 1}")
        return rep
    used = np.unique(tri)
    if not np.array_equal(used, verts):
        missing = np.setdiff1d(verts, used)
        extra = np.setdiff1d(used, verts)
        rep.fail(
            f"vertices differ from the expected points: {missing.size} missing (e.g. {missing[:_SHOWN].tolist()}), "
            f"{extra.size} unexpected (e.g. {extra[:_SHOWN].tolist()})"
        )
    # (1) strictly counterclockwise, exactly.
    sign = pred.orient2d_sign
    flat = [r for r, (a, b, c) in enumerate(tri.tolist()) if len({a, b, c}) < 3 or sign(a, b, c) <= 0]
    if flat:
        rep.fail(f"{len(flat)} triangles are not strictly counterclockwise (zero area or inverted), e.g. "
                 f"{[tri[r].tolist() for r in flat[:_SHOWN]]}")
    # (2) edges.
    table, bad = _edges(tri)
    for message in bad[:_SHOWN]:
        rep.fail(message)
    border = [(u, w) for (u, w) in table if (w, u) not in table]
    interior = [(u, w) for (u, w) in table if (w, u) in table and u < w]
    rep.counts["interior_edges"] = len(interior)
    rep.counts["boundary_edges"] = len(border)
    # (3) the boundary is one cycle, the expected one.
    succ: dict[int, int] = {}
    for u, w in border:
        if u in succ:
            rep.fail(f"boundary vertex {u} starts two boundary edges: the mesh is not a disc")
        succ[u] = w
    expected = boundary if boundary is not None else exact_hull(pred, verts)
    if border and not rep.failures:
        start = min(succ)
        cycle = [start]
        v = succ[start]
        while v != start and len(cycle) <= len(succ):
            cycle.append(v)
            v = succ.get(v, start)
        if len(cycle) != len(succ):
            rep.fail(f"the boundary is not one cycle ({len(succ)} boundary edges, a cycle of {len(cycle)})")
        elif not _same_cycle(cycle, list(expected)):
            rep.fail(
                f"the boundary ({len(cycle)} vertices) is not the expected {len(expected)}-vertex boundary "
                f"(convex hull / rectangle with every point on it)"
            )
    elif not border and tri.size:
        rep.fail("the triangles have no boundary (not a disc)")
    # (4) locally Delaunay, exactly.
    incircle_sign = pred.incircle_sign
    bad_edges = []
    for u, w in interior:
        _, x = table[(u, w)]
        _, y = table[(w, u)]
        if incircle_sign(u, w, x, y) > 0:
            bad_edges.append((u, w))
    if bad_edges:
        rep.fail(f"{len(bad_edges)} interior edges are not Delaunay (exact incircle > 0), e.g. {bad_edges[:_SHOWN]}")
    return rep


def _same_cycle(a: list[int], b: list[int]) -> bool:
    if len(a) != len(b):
        return False
    if not a:
        return True
    try:
        k = b.index(a[0])
    except ValueError:
        return False
    return b[k:] + b[:k] == a


RMS_BLOCK: Final = 1 << 18
"""Errors per block of :func:`root_mean_square`'s sum (blocks start at multiples of it): 2 MB of squares at a time."""


class ScaledSquares:
    """The sum of ``(e / largest)²`` over errors given a part at a time, as :func:`root_mean_square` sums them.

    ``add`` takes the next errors in order; the sum is made :data:`RMS_BLOCK` errors at a time, blocks
    starting at multiples of it in the whole sequence, each one ``float(np.dot(scaled, scaled))``, so
    that the total is bit for bit :func:`root_mean_square`'s over the concatenated errors whatever the
    parts (a whole block comes from the part itself, a block across parts is gathered into a buffer
    of its own).  Memory O(RMS_BLOCK); O(size) in all.
    """

    __slots__ = ("largest", "total", "_buf", "_fill")

    def __init__(self, largest: float) -> None:
        self.largest = largest
        self.total = 0.0
        self._buf: FloatArray | None = None
        self._fill = 0

    def add(self, errors: FloatArray) -> None:
        """Add the next errors (in the order of the whole sequence). O(len(errors))."""
        i, m = 0, errors.size
        while i < m:
            if not self._fill and m - i >= RMS_BLOCK:
                self._square(errors[i : i + RMS_BLOCK])
                i += RMS_BLOCK
                continue
            buf = self._buf
            if buf is None:
                buf = self._buf = np.empty(RMS_BLOCK, dtype=np.float64)
            take = min(RMS_BLOCK - self._fill, m - i)
            buf[self._fill : self._fill + take] = errors[i : i + take]
            self._fill += take
            i += take
            if self._fill == RMS_BLOCK:
                self._flush()

    def _square(self, block: FloatArray) -> None:
        scaled = block / self.largest
        self.total += float(np.dot(scaled, scaled))

    def _flush(self) -> None:
        if self._fill and self._buf is not None:
            self._square(self._buf[: self._fill])
            self._fill = 0

    def rms(self, count: int) -> float:
        """``largest · sqrt(total / count)`` once every error is added (the last, partial block summed now)."""
        self._flush()
        return self.largest * float(np.sqrt(self.total / count))


def largest_magnitude(errors: FloatArray) -> float:
    """``max(|errors|)`` as ``np.max(np.abs(errors))`` gives it (NaN if one is; 0 for none), a block at a time:
    no temporary of the errors' size. O(size)."""
    out = 0.0
    for lo in range(0, errors.size, RMS_BLOCK):
        v = float(np.max(np.abs(errors[lo : lo + RMS_BLOCK])))
        if v != v:
            return v
        if v > out:
            out = v
    return out


def root_mean_square(errors: FloatArray, count: int) -> float:
    """``sqrt(sum(errors²) / count)`` without overflow or underflow: the errors are scaled by the largest first.

    (Squaring overflows for errors beyond about 1e154 and flushes subnormal ones
    to zero; the scaled form holds for every finite error.)  ``count`` may exceed
    ``errors.size`` (samples with no error).  In blocks (:class:`ScaledSquares`): the
    squares of a whole grid's errors would double its memory for a moment.  O(size).
    """
    if errors.size == 0 or count <= 0:
        return 0.0
    largest = largest_magnitude(errors)
    if largest == 0.0 or not np.isfinite(largest):
        return largest
    acc = ScaledSquares(largest)
    acc.add(errors)
    return acc.rms(count)


def mesh_errors(heights: ArrayLike, vertices: ArrayLike, triangles: ArrayLike) -> tuple[FloatArray, IntArray]:
    """Per grid sample: the vertical error of the mesh there, and how many (closed) triangles cover it.

    ``vertices`` is ``(k, 3)``: ``x`` = column, ``y`` = row (integer-valued), ``z``;
    ``triangles`` indices into it, either orientation.  Independent of how the
    mesh was built: every triangle is rasterised over the grid samples of its
    bounding box, inclusion is decided exactly (integer cross products, computed
    exactly in float64 for coordinates below 2^25), and the height there is the
    barycentric interpolation ``(A_a z_a + A_b z_b + A_c z_c) / A``.  A sample
    covered by several triangles (on a shared edge) gets the largest of their
    errors; an uncovered sample gets NaN.  Vectorised; O(Σ bounding-box areas).
    """
    h = np.asarray(heights, dtype=np.float64)
    rows, cols = h.shape
    v = np.asarray(vertices, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.intp).reshape(-1, 3)
    if not np.array_equal(v[:, :2], np.round(v[:, :2])):
        raise ValueError("mesh_errors: vertex x and y must be grid positions (integers)")
    if v.size and (v[:, 0].min() < 0 or v[:, 1].min() < 0 or v[:, 0].max() > cols - 1 or v[:, 1].max() > rows - 1):
        raise ValueError("mesh_errors: a vertex lies outside the grid")
    err = np.full(rows * cols, -1.0)
    cover = np.zeros(rows * cols, dtype=np.intp)
    if t.size == 0:
        return np.full(rows * cols, np.nan), cover
    xs, ys, zs = v[t, 0], v[t, 1], v[t, 2]
    x0, x1 = xs.min(axis=1).astype(np.intp), xs.max(axis=1).astype(np.intp)
    y0, y1 = ys.min(axis=1).astype(np.intp), ys.max(axis=1).astype(np.intp)
    bw, bh = x1 - x0 + 1, y1 - y0 + 1
    sizes = bw * bh
    # In chunks of triangles, so the candidate arrays stay small.
    budget = 4_000_000
    start = 0
    m = t.shape[0]
    while start < m:
        csum = np.cumsum(sizes[start:])
        stop = start + max(1, int(np.searchsorted(csum, budget)))
        sl = slice(start, min(stop, m))
        n_i = sizes[sl]
        owner = np.repeat(np.arange(sl.start, sl.stop), n_i)
        offs = np.arange(int(n_i.sum())) - np.repeat(np.cumsum(n_i) - n_i, n_i)
        px = (x0[owner] + offs % bw[owner]).astype(np.float64)
        py = (y0[owner] + offs // bw[owner]).astype(np.float64)
        ax, ay, bx, by, cx, cy = xs[owner, 0], ys[owner, 0], xs[owner, 1], ys[owner, 1], xs[owner, 2], ys[owner, 2]
        area = (bx - ax) * (cy - ay) - (cx - ax) * (by - ay)
        wa = (bx - px) * (cy - py) - (cx - px) * (by - py)
        wb = (cx - px) * (ay - py) - (ax - px) * (cy - py)
        wc = (ax - px) * (by - py) - (bx - px) * (ay - py)
        sgn = np.sign(area)
        inside = (area != 0) & (wa * sgn >= 0) & (wb * sgn >= 0) & (wc * sgn >= 0)
        q = (py[inside] * cols + px[inside]).astype(np.intp)
        o = owner[inside]
        with np.errstate(invalid="ignore", divide="ignore"):
            zi = (wa[inside] * zs[o, 0] + wb[inside] * zs[o, 1] + wc[inside] * zs[o, 2]) / area[inside]
        e = np.abs(h.ravel()[q] - zi)
        np.maximum.at(err, q, e)
        np.add.at(cover, q, 1)
        start = sl.stop
    err[cover == 0] = np.nan
    return err, cover


def verify_tin(tin: Tin, heights: ArrayLike, *, report: CheckReport | None = None) -> CheckReport:
    """Verify a terrain mesh exactly and recompute its errors (module docstring).  O(samples + mesh)."""
    rep = report if report is not None else CheckReport()
    h = np.asarray(heights, dtype=np.float64)
    rows, cols = h.shape
    if (rows, cols) != tin.shape:
        rep.fail(f"the grid is {h.shape} but the mesh was made for {tin.shape}")
        return rep
    from persistri.impl.terrain.greedy import grid_points

    xy = grid_points(tin.shape)
    pred = Predicates2(xy)
    samples = tin.samples
    tri = samples[tin.triangles]
    # The expected boundary: the rectangle, counterclockwise from (0, 0), through every vertex on it.
    on = set(samples.tolist())
    n = rows * cols
    bottom = [c for c in range(cols)]
    right = [r * cols + cols - 1 for r in range(1, rows)]
    top = [(rows - 1) * cols + c for c in range(cols - 2, -1, -1)]
    left = [r * cols for r in range(rows - 2, 0, -1)]
    perimeter = [i for i in bottom + right + top + left if i in on]
    verify_triangulation(pred, tri, vertices=samples, boundary=perimeter, report=rep)
    if not np.array_equal(np.unique(samples), np.sort(samples)):
        rep.fail("a sample is a vertex twice")

    # Every sample: a vertex, or in exactly one conflict list, inside that closed triangle.
    inf = n  # the symbolic vertex's label
    # One pass over the complex (iter_items: no list of its (triangle, datum) pairs).
    labels: list[int] = []
    lists: list[NDArray[np.integer[Any]]] = []
    ghost_samples = False
    for t, d in tin.structure.iter_items(tin.complex):
        if inf in t:
            ghost_samples = ghost_samples or d[1].size > 0
        else:
            labels.extend(t)
            lists.append(d[1])
    if ghost_samples:
        rep.fail("a ghost triangle holds samples")
    counts = np.array([s.size for s in lists], dtype=np.intp)
    listed = np.concatenate(lists) if lists else np.zeros(0, dtype=np.intp)
    seen = np.bincount(np.concatenate([listed, samples]), minlength=n)
    if seen.size != n or not bool(np.all(seen == 1)):
        twice = np.flatnonzero(seen > 1)
        never = np.flatnonzero(seen == 0)
        rep.fail(
            f"samples not in exactly one place: {twice.size} in two or more (e.g. {twice[:_SHOWN].tolist()}), "
            f"{never.size} in none (e.g. {never[:_SHOWN].tolist()})"
        )
    if listed.size:
        owner = np.repeat(np.fromiter(labels, dtype=np.intp, count=len(labels)).reshape(-1, 3), counts, axis=0)
        outside: list[int] = []
        for k in range(3):
            u, w = owner[:, k], owner[:, (k + 1) % 3]
            s = pred.orient2d_many(u, w, listed)
            for j in np.flatnonzero(s < 0).tolist():
                if pred.orient2d_sign(int(u[j]), int(w[j]), int(listed[j])) < 0:
                    outside.append(int(listed[j]))
        if outside:
            rep.fail(f"{len(outside)} samples lie outside the triangle whose list holds them, e.g. {outside[:_SHOWN]}")
    rep.counts["samples"] = int(listed.size)

    # The errors, from scratch.
    err, cover = mesh_errors(h, tin.vertices, tin.triangles)
    if bool(np.any(cover == 0)):
        bad = np.flatnonzero(cover == 0)
        rep.fail(f"{bad.size} samples are covered by no triangle, e.g. {bad[:_SHOWN].tolist()}")
    else:
        scale = max(1.0, float(h.max() - h.min()))
        worst = float(err.max())
        rms = root_mean_square(err, err.size)
        if abs(worst - tin.max_error) > ERROR_RTOL * scale:
            rep.fail(f"maximum error recomputed as {worst!r}, reported {tin.max_error!r}")
        if abs(rms - tin.rms_error) > ERROR_RTOL * scale:
            rep.fail(f"RMS error recomputed as {rms!r}, reported {tin.rms_error!r}")
    return rep
