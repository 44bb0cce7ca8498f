"""``delaunay``: the exact Delaunay triangulation of arbitrary 2D points (LiDAR returns, survey points; paper §5).

The same machinery as the terrain: the incremental Delaunay triangulation of
:mod:`persistri.impl.terrain.delaunay` on the persistent 2-complex, every test
an exact predicate (``incircle`` through the lifting map, ``orient2d``), ties
among cocircular points broken by Simulation of Simplicity.  Here the points
have no conflict lists; each is located by a walk from the fan of the previous
insertion (:meth:`~persistri.impl.terrain.delaunay.Triangulator.locate_after`),
in a *biased randomised insertion order* (Amenta, Choi and Rote's BRIO: rounds
of doubling size in random order, each round sorted along a Hilbert curve),
which keeps the walks short and the expected work O(n log n).

The vertices are numbered along the same Hilbert curve: the vertices whose
stars one insertion changes are then near one another in the complex's ordered
map, so the map's updates share their search paths — about 20 new tree nodes a
version instead of 45 when numbered by input row (2,000 uniform points), −12 %
instructions a 10,000-point run, −6 % on the compiled twin (docs/performance.md).  Ties are broken by input row all the same: the
predicates rank the points by row for Simulation of Simplicity
(``Predicates2(sos_rank=…)``), so the triangulation is the one the input's order
defines, whatever the numbering.

Exactness is what this adds over floating-point triangulators: at real-world
coordinates (UTM eastings near 5·10^5 m, northings near 4·10^6 m, points
centimetres apart) every input double is taken at its exact value and every
decision is exact, so every distinct input point is a vertex — Qhull, which
works in floating point, silently drops points of such inputs.  Exactly equal
input rows are merged (and reported).  Collinear points on the convex hull are
vertices with no zero-area triangle (:mod:`persistri.impl.terrain.delaunay`
explains the hull-edge rule).

>>> import numpy as np
>>> d = delaunay(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [0.0, 0.0]]))
>>> d.triangles.shape, d.duplicates
((2, 3), ((4, 0),))
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cache
from itertools import chain

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.collector import collector_paused
from persistri.impl.complex.structure import Complex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.flags import flag
from persistri.impl.geometry.points import as_points, unique_rows
from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.maps import backend as map_backend
from persistri.impl.stats import Stats
from persistri.impl.terrain.cavity import insert_linked
from persistri.impl.terrain.delaunay import EMPTY, Insertion, Triangle, TriDatum, Triangulator, canonical_triangles
from persistri.impl.terrain.delaunay_history import DelaunayHistory, read_labels
from persistri.impl.terrain.errors import DegenerateInputError, TriangulationCheckError
from persistri.impl.terrain.walk import walk_from_fan

__all__ = ["delaunay", "DelaunayTriangulation", "insertion_order", "hilbert_keys", "run_insertions", "hull_rows", "verify_result"]

IntArray = NDArray[np.intp]


@dataclass(frozen=True, eq=False)
class DelaunayTriangulation:
    """The result of :func:`delaunay`.

    * ``points`` — the input as validated (``(n, 2)`` float64);
    * ``triangles`` — ``(m, 3)`` input row indices, counterclockwise (each rotated to
      start at its smallest row, rows sorted);
    * ``hull`` — the convex hull as input rows, counterclockwise, every input point
      on the hull's boundary included (collinear ones too);
    * ``duplicates`` — ``(row, earlier equal row)`` for every merged duplicate; the
      later row is not a vertex (its earlier twin is);
    * ``complex`` / ``structure`` — the final persistent complex (ghost triangles
      on the hull edges included) and the structure that reads it;
    * ``seed``, ``backend`` — the run's insertion order and ``ORD_MAP`` backend;
    * ``stats`` — the counts, when a :class:`Stats` was given;
    * ``labels`` — the input row of each vertex label of the complex (``-1`` at the
      label of the symbolic infinite vertex, ``infinite``): what reading a version, and
      continuing the run (:func:`~persistri.impl.terrain.extend_delaunay.extend_delaunay`), need;
    * ``history`` — every version (``history=True``), else None.
    """

    points: NDArray[np.float64]
    triangles: IntArray
    hull: IntArray
    duplicates: tuple[tuple[int, int], ...]
    complex: Complex[TriDatum]
    structure: TwoComplex[TriDatum]
    seed: int
    backend: str
    labels: IntArray
    infinite: int
    stats: Stats | None = field(default=None, compare=False)
    history: DelaunayHistory | None = field(default=None, compare=False)


_CHUNK = 4
"""Levels of the Hilbert curve that :func:`hilbert_keys` takes in one table look-up (4 levels: 8 bits of ``x``
and ``y``, 8 bits of key)."""


@cache
def _hilbert_tables() -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """The key bits and the next state of :data:`_CHUNK` levels of the Hilbert curve, by ``state · 4^C + x bits · 2^C + y bits``.

    The curve's recursion (``xy2d``: at each level the quadrant's digit ``(3·rx) ^ ry``,
    then the point's remaining bits swapped, and complemented first when ``rx = 1, ry =
    0``, if ``ry = 0``) acts on every lower level alike, so what it has done to the bits
    below is one of four states: bit 0 swap, bit 1 complement (they commute).  The
    tables apply :data:`_CHUNK` levels from each state at once, computed by those same
    steps over every entry (4 · 4^C).  O(4^C · C), once.
    """
    c = _CHUNK
    entry = np.arange(4 << (2 * c), dtype=np.int64)
    state = entry >> (2 * c)
    xs = (entry >> c) & ((1 << c) - 1)
    ys = entry & ((1 << c) - 1)
    digits = np.zeros_like(entry)
    for level in range(c - 1, -1, -1):
        ox, oy = (xs >> level) & 1, (ys >> level) & 1
        swap, comp = state & 1, state >> 1
        rx = np.where(swap == 1, oy, ox) ^ comp
        ry = np.where(swap == 1, ox, oy) ^ comp
        digits = (digits << 2) | ((3 * rx) ^ ry)
        turn = ry == 0
        state = np.where(turn, state ^ 1 ^ np.where(rx == 1, 2, 0), state)
    return digits, state


def _quantised(col: NDArray[np.float64], side: int) -> NDArray[np.int64]:
    """The coordinates ``col`` scaled from their range to the integers ``0 … side`` (all 0 when they are equal). O(n)."""
    lo, hi = float(col.min()), float(col.max())
    # Halve an axis whose extent overflows (coordinates near ±1e308): only the order matters here.
    half = 1.0 if math.isfinite(hi - lo) else 0.5
    lo, span = lo * half, hi * half - lo * half
    if not span > 0:
        return np.zeros(col.size, dtype=np.int64)
    q = (col * half - lo) / span
    return np.minimum((q * side).astype(np.int64), side)


def hilbert_keys(points: NDArray[np.float64], bits: int = 16) -> NDArray[np.int64]:
    """The index of each point along a Hilbert curve over its bounding box (``bits`` per axis).

    Only an *order* for the insertion (locality of successive points), so
    floating-point quantisation is harmless here.  The curve's levels are taken
    :data:`_CHUNK` at a time by table look-up (:func:`_hilbert_tables`): the same
    keys as the level-by-level recursion (``xy2d``), in a quarter of the array
    passes.  O(n · bits), vectorised.
    """
    if bits < 1:
        raise ValueError(f"bits must be at least 1, not {bits}")
    n = points.shape[0]
    if n == 0:
        return np.zeros(0, dtype=np.int64)
    side = (1 << bits) - 1
    # Each axis as a contiguous column (numpy reduces an (n, 2) array along its rows slowly).
    x, y = (_quantised(col, side) for col in np.ascontiguousarray(points.T))
    digits, after = _hilbert_tables()
    c = _CHUNK
    chunks = -(-bits // c)
    # Padded to whole chunks with leading zero levels; each swaps, so start from the state that
    # leaves the real top level untouched (an odd number of them: swapped).
    pad = chunks * c - bits
    state = np.full(n, pad & 1, dtype=np.int64)
    d = np.zeros(n, dtype=np.int64)
    mask = (1 << c) - 1
    for k in range(chunks - 1, -1, -1):
        idx = (state << (2 * c)) | (((x >> (k * c)) & mask) << c) | ((y >> (k * c)) & mask)
        d = (d << (2 * c)) | digits[idx]
        state = after[idx]
    return d


def insertion_order(points: NDArray[np.float64], seed: int, keys: NDArray[np.int64] | None = None) -> IntArray:
    """A biased randomised insertion order (BRIO) of ``points``: rounds of doubling size, Hilbert-sorted within.

    A random permutation from ``seed`` is cut into rounds of sizes 8, 8, 16, 32, …
    (the last takes the rest); each round is sorted by :func:`hilbert_keys` (``keys``,
    if the caller has them already).  O(n log n).
    """
    n = points.shape[0]
    perm = np.random.default_rng(seed).permutation(n).astype(np.intp)
    if keys is None:
        keys = hilbert_keys(points)
    out: list[IntArray] = []
    start, size = 0, 8
    while start < n:
        stop = n if n - start < 2 * size else start + size
        chunk = perm[start:stop]
        out.append(chunk[np.argsort(keys[chunk], kind="stable")])
        start = stop
        size = max(size, stop)
    return np.concatenate(out) if out else np.zeros(0, dtype=np.intp)


def _first_triangle(pred: Predicates2, order: IntArray) -> tuple[int, int, int]:
    """Three points of ``order``, counterclockwise, not on one line: the first two and the first off their line."""
    a, b = int(order[0]), int(order[1])
    start, size = 2, 64
    while start < order.size:
        chunk = order[start : start + size]
        off = np.flatnonzero(pred.orient2d_sign_batch(a, b, chunk) != 0)
        if off.size:
            c = int(chunk[off[0]])
            return (a, b, c) if pred.orient2d_sign(a, b, c) > 0 else (b, a, c)
        start += size
        size *= 8
    raise DegenerateInputError(
        f"all {order.size} distinct points are collinear: they have no triangulation", distinct=int(order.size)
    )


def run_insertions(
    T: Triangulator, order: list[int], versions: list[Complex[TriDatum]] | None, *, check: bool
) -> tuple[IntArray, IntArray]:
    """Insert the labels ``order`` into the begun triangulation ``T``, each walk starting in the fan of the one before.

    Appends each new version to ``versions`` (when kept).  Returns the final
    version's finite triangles (``(m, 3)`` vertex labels, counterclockwise) and its
    hull (labels, counterclockwise).  The cyclic collector is off meanwhile
    (:func:`~persistri.impl.collector.collector_paused`).  Expected O(k log n) for ``k`` labels.
    """
    with collector_paused():
        hint = next(tid for tid, tri in T.tri_of.items() if T.infinite not in tri)
        ins: Insertion | None = None
        adj = T.adj
        if order and adj is not None and versions is None and not check:
            # T.insert and T.locate_after, called as the functions they are (the records' insertion and the
            # walk from the last fan): the same steps, two calls fewer a point (check=True runs call the methods).
            it = iter(order)
            q = next(it)
            ins = insert_linked(T, adj, q, T.locate(q, hint))
            for q in it:
                # Each walk starts in the fan of the previous point, its predecessor along the curve.
                ins = insert_linked(T, adj, q, walk_from_fan(T, q, ins))
        else:
            for q in order:
                # Each walk starts in the fan of the previous point, its predecessor along the curve.
                ins = T.insert(q, T.locate(q, hint) if ins is None else T.locate_after(q, ins))
                if versions is not None:
                    versions.append(T.complex)
        every = _final_labels(T, check)
    at_inf = every == int(T.infinite)
    ghost = at_inf.any(axis=1)
    # A ghost (u, w, ∞) sits on the hull edge (w, u) of the finite triangle beside it (counterclockwise).
    k = np.argmax(at_inf[ghost], axis=1)
    ghosts = every[ghost]
    rows_g = np.arange(ghosts.shape[0])
    succ: dict[int, int] = dict(zip(ghosts[rows_g, (k + 2) % 3].tolist(), ghosts[rows_g, (k + 1) % 3].tolist()))
    start = min(succ)
    cycle = [start]
    v = succ[start]
    while v != start:
        cycle.append(v)
        v = succ[v]
    return every[~ghost], np.array(cycle, dtype=np.intp)


def hull_rows(labels: IntArray, cycle: IntArray) -> IntArray:
    """The hull cycle ``cycle`` (vertex labels, counterclockwise) as input rows ``labels[cycle]``, rotated to start at
    its smallest row. O(h)."""
    out = labels[cycle]
    return np.roll(out, -int(np.argmin(out)))


def _final_labels(T: Triangulator, check: bool) -> IntArray:
    """The final version's triangles, ghosts included, as one ``(m, 3)`` array of vertex labels. O(m).

    Uncounted, from the triangulator's index of the live triangles (``tri_of``,
    which every insertion updates with the complex): about a tenth of a compiled
    run less than reading the complex's maps.  A counted run reads the complex, as
    it always has (its counts include the read).  ``check=True`` compares the two.
    """
    structure = T.S
    counted = structure.stats is not None
    adj = T.adj
    live: list[Triangle]
    if adj is not None:  # the records, in id order (tri_of's order), without tri_of's dictionary
        live = [R[0] for R in adj if R is not None]
    else:
        live = list(T.tri_of.values())
    every = (
        read_labels(structure, T.complex)
        if counted
        else np.fromiter(chain.from_iterable(live), dtype=np.intp, count=3 * len(live)).reshape(-1, 3)
    )
    if check:
        other = np.array(live, dtype=np.intp) if counted else read_labels(structure, T.complex)
        if not np.array_equal(canonical_triangles(other.reshape(-1, 3)), canonical_triangles(every)):
            raise TriangulationCheckError("delaunay: the final version's triangles are not the triangulator's")
    return every


def verify_result(result: DelaunayTriangulation) -> None:
    """``check=True``'s final verification of ``result``: its complex a closed surface (ghosts included), and its
    triangles the exact Delaunay triangulation of its distinct points
    (:func:`persistri.impl.terrain.check.verify_triangulation`).  Raises on the first failure. O(n log n)."""
    from persistri.impl.complex.checks import check_closed_surface
    from persistri.impl.terrain.check import verify_triangulation

    check_closed_surface(result.complex)
    # The distinct points, each once, in row order; the triangles renumbered to them (SoS by row, as the run ranked them).
    vertex_rows = np.sort(result.labels[result.labels >= 0])
    tris = np.searchsorted(vertex_rows, result.triangles)
    verify_triangulation(Predicates2(result.points[vertex_rows]), tris).raise_if_failed()


def delaunay(
    points_xy: ArrayLike,
    *,
    backend: str = "int_trie",
    check: bool = False,
    stats: Stats | None = None,
    seed: int = 0,
    history: bool = False,
) -> DelaunayTriangulation:
    """The exact Delaunay triangulation of the 2D points ``points_xy`` (``(n, 2)``; module docstring).

    * ``backend`` — the ``ORD_MAP`` backend of the complex;
    * ``check`` — assert the insertion invariants at every step, then verify the
      result exactly (:func:`persistri.impl.terrain.check.verify_triangulation`: every
      triangle strictly counterclockwise, the boundary the exact convex hull with
      every point on it, every interior edge Delaunay by exact ``incircle``, every
      distinct point a vertex) and the complex a closed surface (ghosts included);
    * ``stats`` — a :class:`Stats` for the operation counts;
    * ``seed`` — the random insertion order (the triangulation is the same for every
      seed wherever the Delaunay triangulation is unique; ties among cocircular
      points are broken by SoS, independently of the order);
    * ``history`` — keep every version (:class:`~persistri.impl.terrain.delaunay_history.DelaunayHistory`:
      one per inserted point, sharing structure), else ``history`` is None.

    Errors: :class:`TypeError`/:class:`ValueError` for input that is not an
    ``(n, 2)`` array of finite reals; :class:`DegenerateInputError` (a
    ``ValueError``) for fewer than 3 distinct points or all of them collinear.
    Expected O(n log n).
    """
    check, history = flag("check", check), flag("history", history)
    arr = as_points(points_xy, 2, what="points_xy")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise TypeError(f"seed must be an integer, not {type(seed).__name__}")
    if seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed}")
    uniq = unique_rows(arr)
    rows = uniq.first
    n_rows = arr.shape[0]
    merged = tuple(
        (int(i), int(rows[uniq.inverse[i]])) for i in np.flatnonzero(rows[uniq.inverse] != np.arange(n_rows))
    )
    m = int(rows.size)
    if m < 3:
        raise DegenerateInputError(
            f"{m} distinct point{'s' if m != 1 else ''}: a triangulation needs at least 3 not on one line", distinct=m
        )
    pts = arr[rows]
    # Vertex labels follow the Hilbert curve: the vertices whose stars one insertion changes are then near one
    # another in the complex's ordered map, whose updates share more of their search paths (fewer new nodes per
    # version).  Ties are still broken by input row: the predicates rank the points by row for Simulation of
    # Simplicity, so the triangulation is the one the input's own order defines, whatever the labels.
    keys = hilbert_keys(pts)
    by_curve = np.argsort(keys, kind="stable")  # label -> distinct point
    label_of = np.empty_like(by_curve)
    label_of[by_curve] = np.arange(m, dtype=by_curve.dtype)
    vertex_rows = rows[by_curve].astype(np.intp)  # label -> input row
    pred = Predicates2(pts[by_curve], stats=stats, sos_rank=vertex_rows)
    structure: TwoComplex[TriDatum] = TwoComplex(map_backend(backend), stats)
    order = label_of[insertion_order(pts, int(seed), keys)]
    first = _first_triangle(pred, order)
    rest = [q for q in order.tolist() if q not in first]
    T = Triangulator(pred, structure, check=check, edge_index=True)
    T.begin([(first, EMPTY)])
    versions: list[Complex[TriDatum]] | None = [T.complex] if history else None
    # The symbolic infinite vertex takes label m (no row).
    labels = np.append(vertex_rows, -1)
    triangles, cycle = run_insertions(T, rest, versions, check=check)
    result = DelaunayTriangulation(
        points=arr,
        triangles=canonical_triangles(labels[triangles]),
        hull=hull_rows(labels, cycle),
        duplicates=merged,
        complex=T.complex,
        structure=structure,
        seed=int(seed),
        backend=backend,
        labels=labels,
        infinite=int(T.infinite),
        stats=stats,
        history=None
        if versions is None
        else DelaunayHistory(structure, tuple(versions), tuple(labels[list(first) + rest].tolist()), labels, m),
    )
    if check:
        verify_result(result)
    return result
