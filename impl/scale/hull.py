"""``parallel_hull``: the exact convex hull of points in chunks — chunk hulls on workers, merged exactly.

A point that is a vertex of the hull of a set is a vertex of the hull of every
subset that contains it.  So the hull of the union of the chunks' hull vertices
is the hull of all points, and the chunks can be reduced independently, on as
many workers as there are, then their survivors merged by a tree reduction — the
scheme of every parallel hull since Preparata and Hong (1977), and one that the
persistent hulls of paper §3 run without any coordination: each task builds its
own versions from its own points.

**Exactly the single-process hull.**  :func:`~persistri.impl.hull.api.convex_hull`
runs on points in general position *by construction*: Simulation of Simplicity
(:mod:`persistri.impl.geometry.sos`) perturbs each point symbolically by its
label, and on degenerate input (grids, coplanar faces, collinear edges) the
faces — even which coplanar points are vertices — depend on that perturbation.
The lemma above holds for the perturbed points as long as every run perturbs
each point the same way, and the perturbation depends only on the *order* of the
labels.  The single-process run labels the distinct points in Morton order over
their bounding box, equal codes in order of first occurrence
(``labels="spatial"``).  A Morton code is a function of the point and the box
alone (:func:`~persistri.impl.geometry.zorder.morton_codes`), so every task here
sorts its points by ``(code over the global box, first input row)`` and labels
them in that order (``labels="input"`` on the sorted points): any two points
compare in every task as in the single run.  The first tetrahedron, the centre
and the random insertion order differ from task to task; they decide the path,
not the final hull of the perturbed points.  The result — vertex rows, outward
triangles as input rows in the same canonical order, and duplicates — equals
``convex_hull(all points)`` exactly (tested on general and degenerate inputs).

**Duplicates.**  Equal rows are one point, labelled by its *first* row in the
whole input, and the single run reports every later row as ``(row, first
row)``.  Two equal rows may sit in different chunks, so the first pass
exchanges the rows by a hash of their coordinates (equal points meet in one
bucket, whatever chunk they came from), and each bucket reports its duplicates
exactly (:func:`~persistri.impl.geometry.points.unique_rows`).  The chunk hulls
then leave out every row that is not its point's first.

**Degenerate chunks.**  A chunk with fewer than 4 distinct points, or whose
points are coplanar (or collinear, or all one point), has no 3D hull: it passes
all its distinct points on unchanged (a coplanar chunk cannot be cut down to its
2D hull: points inside a face of the global hull can be vertices of the perturbed
hull).  If every point of the input is coplanar, the final run raises the
single run's :class:`~persistri.impl.hull.errors.DegenerateInputError`, word for word.

**The passes** (each a set of tasks, :mod:`persistri.impl.scale.tasks`):

1. *scan* — each block is read once and validated (the first bad row of the
   whole input is named), its bounding box taken, its rows cut into buckets by
   hash, and its points that are provably not hull vertices dropped by the
   interior filter (:mod:`persistri.impl.scale.prefilter`: strictly inside a
   polytope of the block's own points, proved exactly; for points uniform in a
   ball all but a fraction of a per cent); each bucket's duplicates are found.
   The only all-to-all exchange: 32 bytes a point (coordinates and row), spread
   over the workers.  The filter's survivors come back to the client.
2. *chunk hulls* — each block's survivors, its later duplicates dropped, hulled;
   only the vertices (coordinates and rows) travel on.
3. *merges* — groups of ``fan_in`` vertex sets, hull of their union, vertices
   on; level after level until at most ``fan_in`` sets remain.
4. *final* — on the client: the hull of the union of those sets, with the full
   persistent result (:class:`~persistri.impl.hull.api.Hull`, every version
   available with ``history=True``).  With ``check=True`` each block's points
   are then verified against it on the workers, exactly
   (:func:`~persistri.impl.hull.verify.verify_hull`).

The filter changes the work, never the result: a dropped point is strictly
inside the hull of points of its own block, so it is not a vertex of any hull
containing them, perturbed or not (the filter's docstring proves it) — in
particular not of the hull of all points.  (The filter sees every row of its
block, the chunk hull only the rows that are not repeats of earlier rows: a
point of the block can be strictly inside the hull of the block's rows but on
the hull of the chunk hull's, and is then dropped, rightly, as no vertex of
the whole.)

Cost for ``n`` points in ``C`` blocks on ``W`` workers: one read of the input
(two with ``check``), O(n/W) hashing and filtering per worker, a chunk hull
over each block's s survivors — s = O(h(m) + the filter's slack) for
blocks of m points whose hulls have h(m) vertices: O(lg² m) for uniform points
in a cube, O(√m) in a ball, all m on a sphere (where nothing is saved: the
filter drops nothing and the final run gets every point) — and a final hull
over the surviving vertices, O(C · h(n/C)) points.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from persistri.impl.geometry.points import unique_rows
from persistri.impl.geometry.zorder import morton_codes
from persistri.impl.hull.api import Hull, convex_hull
from persistri.impl.hull.errors import DegenerateInputError
from persistri.impl.hull.verify import HullVerificationError, verify_hull
from persistri.impl.scale.sources import DEFAULT_CHUNK_ROWS, PointSource, points_source, read_block
from persistri.impl.scale.prefilter import column_extremes, interior_filter
from persistri.impl.scale.tasks import Task, run, task

if TYPE_CHECKING:
    from distributed import Client

__all__ = [
    "Candidates", "ChunkReport", "ParallelHull", "parallel_hull", "chunk_rows_for", "DEFAULT_FAN_IN", "MAX_BUCKETS",
    "MAX_CHUNK_ROWS",
]

IntArray = NDArray[np.intp]
Box = tuple[NDArray[np.float64], NDArray[np.float64]]

DEFAULT_FAN_IN = 8
"""Vertex sets merged per task of the tree reduction (and at most this many reach the final run)."""

MAX_CHUNK_ROWS = 1 << 21
"""The largest chunk :func:`parallel_hull` makes by itself (2,097,152 points, 48 MiB of float64; a chunk hull
of it peaks near 1 GiB): the bound on a task's memory, whatever the input's size."""

MAX_BUCKETS = 64
"""At most this many hash buckets in the duplicate exchange (one per block below that): C × B small tasks."""

# Odd 64-bit multipliers (splitmix64's and two of Murmur3's): equal coordinates hash equal, others spread.
_MIX = (np.uint64(0x9E3779B97F4A7C15), np.uint64(0xBF58476D1CE4E5B9), np.uint64(0x94D049BB133111EB))


@dataclass(frozen=True)
class ChunkReport:
    """What one block did: its rows ``start:stop``, its distinct first-occurrence points, the vertices it
    passed on (``kept``), whether its hull did not exist (``degenerate``: it passed every point on), and
    the points the interior filter proved not to be vertices before the hull was built (``filtered``,
    duplicates included: :mod:`persistri.impl.scale.prefilter`)."""

    start: int
    stop: int
    distinct: int
    kept: int
    degenerate: bool
    filtered: int = 0


@dataclass(frozen=True)
class Candidates:
    """Points that may be hull vertices: coordinates, their first input rows, and how they were found.

    ``chunks`` — the blocks below this set in the reduction; ``merged`` — per level of
    merges below it, the points that went in and came out.
    """

    points: NDArray[np.float64]
    rows: NDArray[np.int64]
    chunks: tuple[ChunkReport, ...]
    merged: tuple[tuple[int, int], ...] = ()


@dataclass(frozen=True)
class ParallelHull:
    """The result of :func:`parallel_hull`, in the terms of :class:`~persistri.impl.hull.api.Hull`.

    * ``simplices``, ``vertices``, ``duplicates`` — exactly ``convex_hull(all points)``'s:
      outward triangles and vertices as rows of the whole input, and ``(row, first equal row)``
      for every later duplicate;
    * ``n`` — rows of the input;
    * ``hull`` — the final run over the surviving candidates (:class:`Hull`; its
      ``points`` are the candidates in label order, its complex and history persistent);
    * ``rows`` — the input row of each row of ``hull.points``;
    * ``chunks`` — one :class:`ChunkReport` per block; ``merges`` — per level of the tree
      reduction, the points that went in and came out; ``workers`` — the cluster's
      workers (0: the sequential path); ``source`` — the input as it was cut.
    """

    simplices: IntArray
    vertices: IntArray
    duplicates: tuple[tuple[int, int], ...]
    n: int
    hull: Hull
    rows: NDArray[np.int64]
    chunks: tuple[ChunkReport, ...]
    merges: tuple[tuple[int, int], ...]
    workers: int
    source: PointSource

    @property
    def vertex_points(self) -> NDArray[np.float64]:
        """The coordinates of :attr:`vertices`, in the same order."""
        where = np.searchsorted(self.rows, self.vertices, sorter=np.argsort(self.rows))
        order = np.argsort(self.rows)[where]
        out: NDArray[np.float64] = self.hull.points[order]
        return out

    @property
    def candidates(self) -> int:
        """The points that reached the final run."""
        return int(self.rows.size)


# --- the tasks (module-level functions: workers import them) ------------------------------------------


@dataclass(frozen=True)
class _Scan:
    start: int
    stop: int
    lo: NDArray[np.float64]
    hi: NDArray[np.float64]
    error: tuple[str, str] | None  # (exception type name, message)


def _bucket_of(points: NDArray[np.float64], buckets: int) -> IntArray:
    """A bucket in ``0 … buckets - 1`` for each row, a function of its exact coordinates (-0.0 is 0.0 already)."""
    bits = np.ascontiguousarray(points).view(np.uint64).reshape(-1, 3)
    h = (bits[:, 0] * _MIX[0]) ^ (bits[:, 1] * _MIX[1]) ^ (bits[:, 2] * _MIX[2])
    h ^= h >> np.uint64(31)
    out: IntArray = (h % np.uint64(buckets)).astype(np.intp)
    return out


def _scan(
    data: Any, start: int, stop: int, buckets: int, what: str, prefilter: bool
) -> tuple[_Scan, tuple[tuple[Any, Any], ...], tuple[NDArray[np.float64], NDArray[np.int64]]]:
    """Pass 1 on one block: validate, bounding box, rows cut into hash buckets (coordinates, input rows),
    and the rows the interior filter keeps (coordinates, input rows) for the chunk hull."""
    empty = (np.zeros((0, 3)), np.zeros(0, dtype=np.int64))
    inf = np.full(3, np.inf)
    try:
        pts = read_block(data, start, what)
    except (ValueError, TypeError) as exc:
        return _Scan(start, stop, inf, -inf, (type(exc).__name__, str(exc))), (empty,) * buckets, empty
    if pts.shape[0] != stop - start:
        message = f"a block of rows {start}:{stop} read {pts.shape[0]} rows (was the input changed while read?)"
        return _Scan(start, stop, inf, -inf, ("ValueError", message)), (empty,) * buckets, empty
    if not pts.shape[0]:
        return _Scan(start, stop, inf, -inf, None), (empty,) * buckets, empty
    rows = np.arange(start, stop, dtype=np.int64)
    # uint8 keys (at most MAX_BUCKETS buckets): numpy's stable sort is then a radix sort.
    bucket = _bucket_of(pts, buckets).astype(np.uint8)
    order = np.argsort(bucket, kind="stable")  # stable: rows stay increasing within a bucket
    cuts = np.cumsum(np.bincount(bucket, minlength=buckets))[:-1]
    pieces = tuple(zip(np.split(pts[order], cuts), np.split(rows[order], cuts), strict=True))
    keep = interior_filter(pts).keep if prefilter else np.arange(pts.shape[0])
    survivors = (np.take(pts, keep, axis=0), rows[keep])
    return _Scan(start, stop, *column_extremes(pts), None), pieces, survivors


def _item(x: Any, i: int) -> Any:
    return x[i]


def _bucket_duplicates(*pieces: tuple[NDArray[np.float64], NDArray[np.int64]]) -> NDArray[np.int64]:
    """The ``(row, first equal row)`` pairs among one bucket's rows (``pieces`` in block order). O(k lg k)."""
    pts = np.concatenate([p for p, _ in pieces]) if pieces else np.zeros((0, 3))
    rows = np.concatenate([r for _, r in pieces]) if pieces else np.zeros(0, dtype=np.int64)
    if rows.size < 2:
        return np.zeros((0, 2), dtype=np.int64)
    # Blocks are consecutive row ranges and each piece is in row order: so is the concatenation, and
    # unique_rows' first occurrences are first rows of the whole input.
    u = unique_rows(pts)
    first = u.first[u.inverse]
    later = np.flatnonzero(first != np.arange(rows.size))
    return np.stack([rows[later], rows[first[later]]], axis=1).astype(np.int64)


def _hull_candidates(pts: NDArray[np.float64], rows: NDArray[np.int64], box: Box, seed: int, backend: str) -> tuple[NDArray[np.float64], NDArray[np.int64], bool]:
    """The hull vertices of distinct ``pts`` labelled as the single run labels them; all of them if no hull."""
    codes = morton_codes(pts, box)
    order = np.lexsort((rows, codes))
    pts, rows = np.take(pts, order, axis=0), rows[order]
    if rows.size < 4:
        return pts, rows, True
    try:
        h = convex_hull(pts, labels="input", seed=seed, backend=backend)
    except DegenerateInputError:
        return pts, rows, True
    keep = h.vertices
    return np.take(pts, keep, axis=0), rows[keep], False


def _chunk_hull(
    survivors: tuple[NDArray[np.float64], NDArray[np.int64]], start: int, stop: int, later: NDArray[np.int64],
    box: Box, seed: int, backend: str,
) -> Candidates:
    """Pass 2 on one block: the hull vertices of its first-occurrence points, from the rows the interior
    filter kept (``later``: the block's rows that repeat an earlier row, left out)."""
    pts, rows = survivors
    if later.size:
        keep = ~np.isin(rows, later, assume_unique=True)
        pts, rows = pts[keep], rows[keep]
    distinct = stop - start - int(later.size)
    out, out_rows, degenerate = _hull_candidates(pts, rows, box, seed, backend)
    filtered = stop - start - int(survivors[1].size)
    return Candidates(out, out_rows, (ChunkReport(start, stop, distinct, int(out_rows.size), degenerate, filtered),))


def _union(parts: Sequence[Candidates]) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    pts = np.concatenate([c.points for c in parts]) if parts else np.zeros((0, 3))
    rows = np.concatenate([c.rows for c in parts]) if parts else np.zeros(0, dtype=np.int64)
    return pts, rows


def _merge(box: Box, seed: int, backend: str, *parts: Candidates) -> Candidates:
    """Pass 3: the hull vertices of the union of a few candidate sets (distinct points, disjoint rows)."""
    pts, rows = _union(parts)
    out, out_rows, _ = _hull_candidates(pts, rows, box, seed, backend)
    below = [c.merged for c in parts]
    depth = max((len(m) for m in below), default=0)
    merged = tuple(
        (sum(m[k][0] for m in below if k < len(m)), sum(m[k][1] for m in below if k < len(m))) for k in range(depth)
    ) + ((int(rows.size), int(out_rows.size)),)
    return Candidates(out, out_rows, tuple(r for c in parts for r in c.chunks), merged)


def _verify_block(
    data: Any, start: int, vertex_points: NDArray[np.float64], faces: NDArray[np.intp]
) -> list[str]:
    """``check=True``: the problems :func:`verify_hull` finds with one block's points and the final hull."""
    pts = read_block(data, start)
    both = np.concatenate([vertex_points, pts])
    report = verify_hull(both, faces)
    k = vertex_points.shape[0]
    outside = [int(i) - k + start for i in report.outside if int(i) >= k]
    if outside:
        return [f"input rows outside the hull: {', '.join(map(str, outside[:10]))}"]
    return list(report.problems)


# --- the driver ---------------------------------------------------------------------------------------


def _canonical(triangles: NDArray[np.int64]) -> IntArray:
    """Triangles rotated to start at their smallest row (orientation kept), sorted: ``Hull.simplices``' form."""
    if not triangles.size:
        return np.zeros((0, 3), dtype=np.intp)
    k = np.argmin(triangles, axis=1)
    idx = (k[:, None] + np.arange(3)[None, :]) % 3
    arr = np.take_along_axis(triangles, idx, axis=1).astype(np.intp)
    out: IntArray = arr[np.lexsort(arr.T[::-1])]
    return out


def _workers(client: Client | None) -> int:
    return 0 if client is None else len(client.scheduler_info(n_workers=-1)["workers"])


def chunk_rows_for(n: int, workers: int) -> int:
    """The chunk size :func:`parallel_hull` picks for ``n`` points on ``workers`` workers: one chunk per worker,
    within :data:`~persistri.impl.scale.sources.DEFAULT_CHUNK_ROWS` … :data:`MAX_CHUNK_ROWS`.

    Few chunks, because chunking adds work: a chunk of m uniform points in a ball needs
    Θ(√m) insertions, so C chunks need Θ(√(C·n)) — √C times one process's —, and all
    their vertices go on to the merge.  The bounds keep a task's memory bounded on huge
    inputs and tiny chunks out of small ones.

    >>> chunk_rows_for(4_000_000, 2), chunk_rows_for(10_000, 8), chunk_rows_for(10**9, 100)
    (2000000, 262144, 2097152)
    """
    return min(MAX_CHUNK_ROWS, max(DEFAULT_CHUNK_ROWS, -(-n // max(1, workers))))


def parallel_hull(
    points: Any,
    *,
    client: Client | None = None,
    chunk_rows: int | None = None,
    seed: int = 0,
    backend: str = "red_black",
    fan_in: int = DEFAULT_FAN_IN,
    history: bool = False,
    check: bool = False,
    progress: bool = False,
    prefilter: bool = True,
) -> ParallelHull:
    """The exact convex hull of ``points``, chunk by chunk, on ``client``'s cluster (None: in this process).

    ``points`` — anything :func:`~persistri.impl.scale.sources.points_source` reads: an
    ``(n, 3)`` array, a Dask array, a Zarr array, or the path of a ``.npy`` file (memory-mapped),
    a directory of ``.npy`` files or a Zarr store; ``chunk_rows`` — rows per block;
    ``client`` — from :func:`persistri.impl.scale.cluster.connect`; by default a Dask array keeps its own
    chunks and other inputs are cut by :func:`chunk_rows_for`; ``seed``, ``backend`` and
    ``history`` as for :func:`~persistri.impl.hull.api.convex_hull` (``history`` keeps the final
    run's versions); ``fan_in`` — vertex sets per merge; ``check`` — verify every point of the
    input against the result, exactly, block by block on the workers, and the final run's
    theorems as ``convex_hull(check=True)`` does; ``progress`` — bars on stderr; ``prefilter`` —
    drop each block's points that are provably not vertices before its hull
    (:func:`~persistri.impl.scale.prefilter.interior_filter`; the same result either way).

    The result's vertices, simplices and duplicates equal those of ``convex_hull`` on all the
    points, on every input (the module docstring says why).  Errors are ``convex_hull``'s, with
    rows of the whole input: the first NaN or infinite row, too few or coplanar distinct points
    (:class:`~persistri.impl.hull.errors.DegenerateInputError`, the same message);
    :class:`~persistri.impl.scale.cluster.ClusterError` if workers keep dying.
    """
    if fan_in < 2:
        raise ValueError(f"fan_in must be at least 2, got {fan_in}")
    source = points_source(points, chunk_rows)
    dask_array = type(points).__module__.startswith("dask")
    if chunk_rows is None and not isinstance(points, PointSource) and not dask_array:
        size = chunk_rows_for(source.n, _workers(client))
        if size != DEFAULT_CHUNK_ROWS:
            source = points_source(points, size)
    scans, later, survivors = _first_pass(client, source, progress, prefilter)
    box: Box = (np.min([s.lo for s in scans], axis=0), np.max([s.hi for s in scans], axis=0))
    if source.n == 0:
        box = (np.zeros(3), np.zeros(3))
    later_rows = np.sort(later[:, 0])
    level: list[Task] = []
    for b, kept in zip(source.blocks, survivors, strict=True):
        lo, hi = np.searchsorted(later_rows, [b.start, b.stop])
        level.append(task(_chunk_hull, kept, b.start, b.stop, later_rows[lo:hi], box, seed, backend))
    while len(level) > fan_in:
        level = [task(_merge, box, seed, backend, *level[i : i + fan_in]) for i in range(0, len(level), fan_in)]
    parts: list[Candidates] = run(client, level, progress=progress, title="chunk hulls")
    pts, rows = _union(parts)
    codes = morton_codes(pts, box)
    order = np.lexsort((rows, codes))
    pts, rows = np.take(pts, order, axis=0), rows[order]
    hull = convex_hull(pts, labels="input", seed=seed, backend=backend, history=history, check=check, progress=progress)
    simplices = _canonical(rows[hull.simplices])
    duplicates = tuple((int(a), int(b)) for a, b in later.tolist())
    result = ParallelHull(
        simplices=simplices,
        vertices=np.unique(simplices),
        duplicates=duplicates,
        n=source.n,
        hull=hull,
        rows=rows,
        chunks=tuple(r for c in parts for r in c.chunks),
        merges=_levels(parts),
        workers=_workers(client),
        source=source,
    )
    if check:
        _check(client, source, hull, progress)
    return result


def _levels(parts: Sequence[Candidates]) -> tuple[tuple[int, int], ...]:
    depth = max((len(c.merged) for c in parts), default=0)
    return tuple(
        (sum(c.merged[k][0] for c in parts if k < len(c.merged)), sum(c.merged[k][1] for c in parts if k < len(c.merged)))
        for k in range(depth)
    )


def _first_pass(
    client: Client | None, source: PointSource, progress: bool, prefilter: bool
) -> tuple[list[_Scan], NDArray[np.int64], list[tuple[NDArray[np.float64], NDArray[np.int64]]]]:
    """Pass 1: every block's scan, every ``(row, first equal row)`` pair of the input (sorted by row), and
    every block's rows that the interior filter kept (they come to the client: a few per cent of a block)."""
    buckets = max(1, min(len(source.blocks), MAX_BUCKETS))
    scans = [task(_scan, b.data, b.start, b.stop, buckets, source.what, prefilter) for b in source.blocks]
    summaries = [task(_item, s, 0) for s in scans]
    pieces = [task(_item, s, 1) for s in scans]
    kept = [task(_item, s, 2) for s in scans]
    dups = [task(_bucket_duplicates, *(task(_item, p, k) for p in pieces)) for k in range(buckets)]
    done = run(client, [*summaries, *kept, *dups], progress=progress, title="scan")
    c = len(summaries)
    found: list[_Scan] = done[:c]
    failed = [s for s in found if s.error is not None]
    if failed:
        kind, message = min(failed, key=lambda s: s.start).error or ("ValueError", "")
        raise (TypeError if kind == "TypeError" else ValueError)(message)
    pairs = [p for p in done[2 * c :] if p.size]
    later = np.concatenate(pairs) if pairs else np.zeros((0, 2), dtype=np.int64)
    later = later[np.argsort(later[:, 0], kind="stable")]
    return found, later, list(done[c : 2 * c])


def _check(client: Client | None, source: PointSource, hull: Hull, progress: bool) -> None:
    """Every block's points on or behind every face of ``hull`` (exact), on the workers."""
    vertex_rows = np.unique(hull.simplices)
    local = np.searchsorted(vertex_rows, hull.simplices)
    vertex_points = np.take(hull.points, vertex_rows, axis=0)
    jobs = [task(_verify_block, b.data, b.start, vertex_points, local) for b in source.blocks]
    for b, problems in zip(source.blocks, run(client, jobs, progress=progress, title="verify"), strict=True):
        if problems:
            raise HullVerificationError(f"rows {b.start}:{b.stop}: " + "; ".join(problems))
