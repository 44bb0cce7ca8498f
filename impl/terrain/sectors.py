"""Which fan triangle holds each sample: sorting a cavity's samples into the sectors around the new point (paper §5).

After inserting ``p`` (:mod:`persistri.impl.terrain.delaunay`) the cavity's
boundary vertices ``r_0, r_1, …`` lie counterclockwise around ``p`` and the new
triangle ``i`` is ``(r_i, r_{i+1}, p)``.  A sample ``q`` of the cavity lies in
triangle ``i`` iff it lies in the *sector* between the rays ``p → r_i`` and
``p → r_{i+1}``: left of the first (``orient2d(p, r_i, q) > 0``) and right of
the second (``< 0``).  Because every fan angle is below π, the signs
``s_i = sign orient2d(p, r_i, q)`` of one sample, read around the ring, change
from + to − exactly once — at its sector — and from − to + once, at the
opposite ray.  :func:`sector_of` returns that position; :func:`fan_sectors`, used
by the triangulator, computes the signs and the positions in one pass and
returns the samples already grouped by triangle.

No tie-breaking is needed, so the *true* signs are used, and a zero may be read
as either sign: ``s_i = 0`` means ``q`` is on the line ``p r_i``.  On the ray
itself (between ``p`` and ``r_i``; the cavity is star-shaped, so not beyond),
``q`` lies on the edge shared by triangles ``i − 1`` and ``i`` and the pattern
``s_{i−1}, s_i, s_{i+1} = +, ?, −`` has its one + → − change at ``i − 1`` or ``i``:
either triangle, closed, holds it.  On the opposite ray the pattern is
``−, ?, +``, which has no + → − change whatever ``?`` is.  Two zeros of one
sample are never neighbours (consecutive rays differ by less than π and are
not equal), so the argument applies to each.  Zeros are read as +.

The signs are exact.  :func:`small_integer_points` recognises point sets whose
coordinates are integers of magnitude at most :data:`EXACT_LIMIT` = 2^25 — every
height grid: ``x`` = column, ``y`` = row — for which :func:`sector_signs`
evaluates ``(r − p) × (q − p)`` in float64 *exactly* (:func:`sector_sides`): the differences are
integers below 2^26, their products below 2^52 and the final difference below
2^53, all representable, so no operation rounds.  This costs about 1/20 of a
filtered predicate call per test; for any other point set the signs come from
:meth:`~persistri.impl.geometry.predicates.Predicates2.orient2d_sign_batch`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from persistri.impl.geometry.grid_predicates import GridPredicates2
from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.stats import Stats

__all__ = [
    "EXACT_LIMIT", "FLOPS_SECTOR_TEST", "SECTOR_BLOCK", "small_integer_points", "sector_sides", "sector_of", "fan_sectors",
    "fan_lists", "fan_small", "small_buckets", "COMPILED", "PYTHON_SECTORS", "FLAT_CHANGES",
]

EXACT_LIMIT: Final[float] = float(2**25)
"""Largest coordinate magnitude for which :func:`sector_signs` evaluates orient2d exactly in float64."""

FLOPS_SECTOR_TEST: Final[int] = 5
"""Floating-point operations per sign on the exact small-integer path: two differences, two products, one difference."""

SECTOR_BLOCK: Final[int] = 1 << 15
"""Samples per block of the exact float path (:func:`fan_sectors`, :func:`fan_lists`): the ``(rays, samples)``
float64 arrays of a block stay a few megabytes (2^18 samples against ten rays made 20 MB each, measured on
the first insertions of a 2,048² grid, where they set the mesher's peak; smaller blocks cost nothing measurable)."""

COMPILED: Final[bool] = not __file__.endswith(".py")
"""Whether this module runs compiled (the twin, docs/performance.md): then its loops cost nanoseconds a step."""

PYTHON_SECTORS: Final[int] = 64 if COMPILED else 10
"""Up to this many samples on a grid, :func:`fan_sectors`' exact float path runs as one loop over them
(:func:`fan_small`), above it as a dozen numpy calls over whole arrays (:func:`_fan_block`); the same
answers.  Measured in instructions a call on 20,000 replayed calls of a Jacksboro run (2026-11-28): the
numpy calls about 100–130 K up to 64 samples whatever the size; the loop, compiled, 30 K up to 10
samples, 55 K at 11–32, 95 K at 33–48 and 127 K at 49–64 (numpy 118 K and 126 K there); interpreted,
78 K up to 10 and 177 K at 11–32: hence a bound for each build."""

FLAT_CHANGES: Final[int] = 256
"""Above this many samples :func:`_fan_block` finds the + → − changes by their flat positions and one
division (see there): 1.42 M → 0.96 M instructions a call above 1,024 samples, 254 K → about 230 K at
257–1,024; at 97–256 the 2D ``nonzero`` costs less (159 K against 161 K)."""

IntArray = NDArray[np.intp]
Samples = NDArray[np.signedinteger[Any]]
"""Point indices of any signed integer dtype (a triangulator's sample lists are ``int32`` or ``intp``)."""
BoolArray = NDArray[np.bool_]


def small_integer_points(points: NDArray[np.float64]) -> bool:
    """Whether every coordinate is an integer of magnitude at most :data:`EXACT_LIMIT`. O(n)."""
    if points.size == 0:
        return True
    return bool(np.all(np.abs(points) <= EXACT_LIMIT) and np.all(points == np.floor(points)))


def sector_sides(
    pred: Predicates2,
    p: int,
    ring: IntArray,
    samples: Samples,
    *,
    exact_floats: bool,
    columns: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
    stats: Stats | None = None,
) -> BoolArray:
    """``sign orient2d(p, ring[i], samples[j]) >= 0`` as a ``(len(samples), len(ring))`` boolean array (exact).

    ``exact_floats`` — the caller has established :func:`small_integer_points` for
    ``pred``'s points, so the float64 evaluation is exact (module docstring);
    otherwise each column is one exact ``orient2d_sign_batch``.  ``columns`` —
    ``pred``'s x and y coordinates as contiguous arrays, if the caller keeps them
    (saves gathering from the 2D array).  ``stats``
    counts the tests of the float path as plane-side tests (the predicates count
    their own).  O(len(samples) · len(ring)).
    """
    m, k = samples.size, ring.size
    if not exact_floats:
        out = np.empty((m, k), dtype=bool)
        for i in range(k):
            out[:, i] = pred.orient2d_sign_batch(int(p), int(ring[i]), samples) >= 0
        return out
    xr, yr, xq, yq, px, py = _coordinates(pred, p, ring, samples, columns)
    rx = xr - px
    ry = yr - py
    qx = xq - px
    qy = yq - py
    # orient2d(p, r, q) = (r - p) × (q - p) = rx·qy − ry·qx, exact here.
    det = np.multiply.outer(qy, rx)
    det -= np.multiply.outer(qx, ry)
    if stats is not None:
        stats.plane_side_tests += m * k
        stats.flops += FLOPS_SECTOR_TEST * m * k
    sides: BoolArray = det >= 0
    return sides


def sector_of(sides: BoolArray, closed: bool, *, check: bool = False) -> IntArray:
    """For each row of ``sides`` (see :func:`sector_sides`), the sector ``i`` where the sides change from + to −.

    ``closed`` — the ring goes all the way round ``p``; otherwise it is an open
    chain whose end rays point in opposite directions along a hull edge that
    ``p`` split, every sample lies on their inner side, and the sides of the two
    ends are taken as + and − (``sides`` then holds only the inner vertices).
    Zeros count as + (module docstring).  ``check`` — raise :class:`ValueError`
    naming the first row that does not have exactly one change (the argument
    above excludes it).  O(size).
    """
    m, k = sides.shape
    if closed:
        rays = np.empty((m, k + 1), dtype=bool)
        rays[:, :k] = sides
        rays[:, k] = sides[:, 0]
    else:
        rays = np.empty((m, k + 2), dtype=bool)
        rays[:, 0] = True
        rays[:, 1 : k + 1] = sides
        rays[:, k + 1] = False
    return _first_change(rays, check)


def _first_change(rays: BoolArray, check: bool) -> IntArray:
    """For each row of ``rays`` (sides against rays ``0 … k``, bounding sectors ``0 … k−1``), where + turns to −.

    ``True > False`` is the one pair a comparison of neighbours marks, so the
    change at sector ``i`` is ``rays[:, i] > rays[:, i + 1]``; the first one wins
    (``argmax``).  ``check`` — :class:`ValueError` unless every row has exactly one.
    """
    hit = rays[:, :-1] > rays[:, 1:]
    if check:
        changes = hit.sum(axis=1)
        if bool(np.any(changes != 1)):
            row = int(np.argmax(changes != 1))
            raise ValueError(f"sample row {row} changes side from + to - {int(changes[row])} times around the fan")
    sector: IntArray = hit.argmax(axis=1)
    return sector


def fan_sectors(
    pred: Predicates2,
    p: int,
    rays: IntArray,
    samples: Samples,
    closed: bool,
    *,
    exact_floats: bool,
    columns: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
    stats: Stats | None = None,
    check: bool = False,
) -> tuple[IntArray, IntArray]:
    """The samples sorted into the fan's triangles: ``(order, sector)``, ``samples[order]`` grouped by triangle.

    Triangle ``i`` of the fan lies between the rays ``p → rays[i]`` and
    ``p → rays[i+1]``; ``rays`` are the fan's boundary vertices in order, the
    first repeated at the end when the fan is ``closed`` (so ``len(rays) − 1``
    triangles either way; the two ends of an open chain are known, + and −, and
    not tested).  ``sector[j]`` is the triangle of ``samples[order[j]]``,
    nondecreasing; within a triangle the samples keep their order (stable).
    The same answers as :func:`sector_sides` then :func:`sector_of` and a stable
    sort, and ``stats`` counts the same tests.

    On the exact float path (``exact_floats``, ``columns`` as in
    :func:`sector_sides`) the work is laid out ray by ray — a ``(rays, samples)``
    array — so that every numpy operation runs over contiguous rows: the signs,
    the + → − changes (``True > False`` of neighbouring rays), and their
    positions in one ``nonzero``, which lists them sector by sector, i.e. already
    sorted.  A sample without exactly one change (excluded by the module
    docstring's argument) raises :class:`ValueError`, ``check`` or not.
    O(len(samples) · len(rays)).
    """
    k = rays.size - 1
    if not exact_floats:
        inner = rays[:-1] if closed else rays[1:-1]
        sides = sector_sides(pred, p, inner, samples, exact_floats=False, stats=stats)
        found = sector_of(sides, closed, check=check)
        order: IntArray = np.argsort(found, kind="stable")
        return order, found[order]
    m = samples.size
    tested = k if closed else k - 1
    if stats is not None:
        stats.plane_side_tests += m * tested
        stats.flops += FLOPS_SECTOR_TEST * m * tested
    if m <= PYTHON_SECTORS and columns is None and isinstance(pred, GridPredicates2):
        return fan_small(pred.shape[1], p, rays, samples, closed)
    if m > SECTOR_BLOCK:
        blocked = _blocked_sectors(pred, p, rays, samples, closed, columns)
        by_sector: IntArray = np.argsort(blocked, kind="stable")  # int16: numpy's stable sort is a radix sort
        out: IntArray = blocked[by_sector].astype(np.intp)
        return by_sector, out
    return _fan_block(pred, p, rays, samples, closed, columns)


def fan_lists(
    pred: Predicates2,
    p: int,
    rays: IntArray,
    samples: Sequence[Samples],
    closed: bool,
    *,
    exact_floats: bool,
    stats: Stats | None = None,
    check: bool = False,
    block: int = SECTOR_BLOCK,
) -> list[Samples]:
    """The samples of each fan triangle, as one array per triangle, from a pool given as several arrays.

    The pool is the arrays of ``samples`` one after the other (a cavity's sample lists), without ``p``
    itself wherever it occurs; each triangle's array keeps the pool's order and its dtype.  The same
    answers and counts as :func:`fan_sectors` on the concatenated pool cut at the sector
    boundaries, for large pools: the exact float path runs over ``block`` samples at a time
    (default :data:`SECTOR_BLOCK`) and makes neither the concatenated pool nor a permutation of
    it — a ``(rays, samples)`` array of millions of samples would take hundreds of megabytes, and
    the pool, once without ``p``, would be two more copies of the samples.  It keeps the sector
    of each sample (2 bytes) and then fills each triangle's array block by block: the only arrays of
    the pool's size are the result and the sectors.  O(pool size · len(rays)).
    """
    k = rays.size - 1
    total = sum(int(s.size) for s in samples)
    if not exact_floats or total <= block:
        joined = np.concatenate(list(samples)) if len(samples) != 1 else samples[0]
        pooled = joined[joined != p]
        order, sector = fan_sectors(pred, p, rays, pooled, closed, exact_floats=exact_floats, stats=stats, check=check)
        ends = np.searchsorted(sector, np.arange(k + 1))
        ordered = pooled[order]
        return [ordered[ends[i] : ends[i + 1]].copy() for i in range(k)]
    kind = np.int16 if k < 2**15 else np.intp
    found: list[NDArray[np.integer[Any]]] = []
    counts = np.zeros(k, dtype=np.intp)
    m = 0
    for s in samples:
        # The sector of each sample of this array, and −1 at p (in no sector).
        f: NDArray[np.integer[Any]] = np.empty(s.size, dtype=kind)
        for lo in range(0, s.size, block):
            hi = min(s.size, lo + block)
            part = s[lo:hi]
            keep = part != p
            kept = part if bool(keep.all()) else part[keep]
            part_order, part_sector = _fan_block(pred, p, rays, kept, closed, None)
            into = f[lo:hi]
            if kept is part:
                into[part_order] = part_sector
            else:
                at = np.flatnonzero(keep)
                into[~keep] = -1
                into[at[part_order]] = part_sector
            counts += np.bincount(part_sector, minlength=k)
            m += kept.size
        found.append(f)
    tested = k if closed else k - 1
    if stats is not None:
        stats.plane_side_tests += m * tested
        stats.flops += FLOPS_SECTOR_TEST * m * tested
    dtype = samples[0].dtype if samples else np.dtype(np.intp)
    out: list[Samples] = [np.empty(int(c), dtype=dtype) for c in counts]
    filled = [0] * k
    for s, f in zip(samples, found):
        for lo in range(0, s.size, block):
            hi = min(s.size, lo + block)
            part, where = s[lo:hi], f[lo:hi]
            for i in range(k):
                got = part[where == i]
                if got.size:
                    out[i][filled[i] : filled[i] + got.size] = got
                    filled[i] += got.size
    return out


def _blocked_sectors(
    pred: Predicates2,
    p: int,
    rays: IntArray,
    samples: Samples,
    closed: bool,
    columns: tuple[NDArray[np.float64], NDArray[np.float64]] | None,
) -> NDArray[np.integer[Any]]:
    """The sector of each sample (the exact float path), :data:`SECTOR_BLOCK` samples at a time; int16 when it fits."""
    k = rays.size - 1
    m = samples.size
    found: NDArray[np.integer[Any]] = np.empty(m, dtype=np.int16 if k < 2**15 else np.intp)
    for lo in range(0, m, SECTOR_BLOCK):
        hi = min(m, lo + SECTOR_BLOCK)
        part_order, part_sector = _fan_block(pred, p, rays, samples[lo:hi], closed, columns)
        found[lo + part_order] = part_sector
    return found


def _coordinates(
    pred: Predicates2,
    p: int,
    rays: IntArray,
    samples: Samples,
    columns: tuple[NDArray[np.float64], NDArray[np.float64]] | None,
) -> tuple[NDArray[Any], NDArray[Any], NDArray[Any], NDArray[Any], float, float]:
    """The coordinates of ``rays`` and ``samples`` (gathered from ``columns`` when given, else the predicates'
    :meth:`~persistri.impl.geometry.predicates.Predicates2.coordinates`) and ``p``'s as floats."""
    if columns is not None:
        x, y = columns
        return x[rays], y[rays], x[samples], y[samples], float(x[p]), float(y[p])
    xr, yr = pred.coordinates(rays)
    xq, yq = pred.coordinates(samples)
    px, py = pred.xy(p)
    return xr, yr, xq, yq, float(px), float(py)


def fan_small(cols: int, p: int, rays: IntArray, samples: Samples, closed: bool) -> tuple[IntArray, IntArray]:
    """:func:`fan_sectors` over the points of a grid with ``cols`` columns, as one loop over a few samples.

    Point ``i`` is ``(i mod cols, i div cols)`` (:class:`~persistri.impl.geometry.grid_predicates.GridPredicates2`).
    The same tests as :func:`_fan_block`, ``rx·qy ≥ ry·qx``, on float64 differences of the integer
    coordinates (exact, as :func:`_fan_block`'s are: the module docstring; compiled, a float product is
    one machine instruction, where a product of two integers of which one is negative takes mypyc's
    general path, an object each), and the same answer ``(order, sector)``: the samples' positions grouped
    by sector, in their order within a sector; the same :class:`ValueError` for a sample without exactly
    one change of side.  Nothing counted here (as :func:`_fan_block`).  O(len(samples) · len(rays)).
    """
    # Typed lists: compiled, the loop then runs on machine floats and integers (tolist is Any).
    ring: list[int] = rays.tolist()
    qs: list[int] = samples.tolist()
    buckets = small_buckets(cols, p, ring, qs, closed, True)
    order: list[int] = []
    sector: list[int] = []
    for i in range(len(buckets)):
        b = buckets[i]
        if b:
            order += b
            sector += [i] * len(b)
    return np.array(order, dtype=np.intp), np.array(sector, dtype=np.intp)


def small_buckets(cols: int, p: int, ring: Sequence[int], qs: list[Any], closed: bool, positions: bool) -> list[list[Any]]:
    """The samples ``qs`` of each fan triangle, as one list per triangle, over the points of a grid with ``cols``
    columns: :func:`fan_small`'s loop on Python lists.

    ``ring`` — the fan's boundary vertices (as ``rays``: ``len(ring) − 1`` triangles, a closed ring's first
    vertex repeated at the end); list ``i`` holds, in the order of ``qs``, the samples of triangle ``i``
    (``positions``: their positions in ``qs``).  The same tests and answers as :func:`fan_small`, which it
    serves, and the same :class:`ValueError` for a sample without exactly one change of side; the
    triangulator's few-sample insertions (:func:`~persistri.impl.terrain.insertion.fan_samples`) call it on
    their lists directly, without the arrays in between.  Nothing counted here.  O(len(qs) · len(ring)).
    """
    k: int = len(ring) - 1
    p = int(p)
    py = p // cols
    px = p - py * cols
    rays_xy: list[tuple[float, float]] = []
    for v in ring:
        y = v // cols
        rays_xy.append((float(v - y * cols - px), float(y - py)))
    # The sides against the rays 0 … k (a closed ring's ray k is its ray 0 again, tested again as in
    # _fan_block); an open chain's two ends are known, + and −, and not tested: the rays tested after
    # ray 0 are 1 … k closed, 1 … k − 1 open (and ray k is − there).
    rx0, ry0 = rays_xy[0]
    tested = rays_xy[1:] if closed else rays_xy[1:k]
    buckets: list[list[Any]] = [[] for _ in range(k)]
    j = 0
    for qo in qs:
        # The sample as the list's own object (appended as it is: compiled, an int read from a typed list and
        # appended would be boxed anew), its value unboxed once for the arithmetic.
        q: int = qo
        y = q // cols
        qx = float(q - y * cols - px)
        qy = float(y - py)
        at = -1
        changes = 0
        before = rx0 * qy >= ry0 * qx if closed else True
        i = 0
        for rx, ry in tested:
            after = rx * qy >= ry * qx
            if before and not after:
                changes += 1
                at = i
            before = after
            i += 1
        if before and not closed:
            changes += 1
            at = i
        if changes != 1:
            raise ValueError(f"sample row {j} changes side from + to - {changes} times around the fan")
        buckets[at].append(j if positions else qo)
        j += 1
    return buckets


def _fan_block(
    pred: Predicates2,
    p: int,
    rays: IntArray,
    samples: Samples,
    closed: bool,
    columns: tuple[NDArray[np.float64], NDArray[np.float64]] | None,
) -> tuple[IntArray, IntArray]:
    """:func:`fan_sectors`' exact float path on one block of samples (nothing counted here)."""
    k = rays.size - 1
    m = samples.size
    # The predicates' coordinates (a grid's are small integers): p's as Python floats, so that every
    # difference is float64 whatever the coordinates' type (exact: module docstring).
    xr, yr, xq, yq, px, py = _coordinates(pred, p, rays, samples, columns)
    rx = xr - px
    ry = yr - py
    qx = xq - px
    qy = yq - py
    # orient2d(p, r, q) = (r − p) × (q − p) = rx·qy − ry·qx ≥ 0, i.e. rx·qy ≥ ry·qx: both products and their
    # difference are exact here (module docstring), so comparing the products decides the same sign.
    signs = np.multiply.outer(rx, qy) >= np.multiply.outer(ry, qx)
    if not closed:
        signs[0] = True
        signs[k] = False
    # The + → − changes, listed sector by sector (row-major), i.e. already sorted.  numpy's nonzero of a 2D
    # array walks it with a multi-index (about 25 instructions an entry): for many samples the flat positions
    # and one division by the row length cost less (a third less per block of 10^3 samples and more); for
    # few, the one call does.
    hit = signs[:-1] > signs[1:]
    sector: IntArray
    order: IntArray
    if m > FLAT_CHANGES:
        sector, order = np.divmod(np.flatnonzero(hit), m)
    else:
        sector, order = hit.nonzero()
    if sector.size != m:
        row = int(np.argmax(hit.sum(axis=0) != 1))
        raise ValueError(f"sample row {row} changes side from + to - {int(hit[:, row].sum())} times around the fan")
    return order, sector
