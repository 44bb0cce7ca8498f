"""What the exact predicates of both dimensions share: :class:`IndexedPoints` (paper §3 and §5).

The validation of point indices, the filter's copy of the points scaled by a
power of two and its table of float rows (:class:`RowTable`), the exact
integers, the counting, and the batch engine that runs a filter vectorised and
settles the undecided entries exactly: the base of
:class:`~persistri.impl.geometry.predicates3.Predicates3` and
:class:`~persistri.impl.geometry.predicates2.Predicates2`.  The three stages of
every test, the sign conventions and the counting are described in
:mod:`persistri.impl.geometry.predicates`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Final, Protocol

import itertools
import math
import struct

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.geometry.exact import ZERO_LOW, IntegerScale, binary_exponents, grain_span
from persistri.impl.geometry.filter import GRAIN_MIN, choose_scaling
from persistri.impl.stats import Stats

__all__ = ["IndexedPoints", "RowTable", "SMALL_BATCH"]

_INVALID_GRAIN: Final[int] = -ZERO_LOW
"""Grain of a point with no valid float copy: fails every grain check."""

_UNMADE: Final[tuple[float, ...]] = ()
"""A lazy row not made yet: unpacking it raises ValueError, which the hot paths catch to make it."""

_ROW_BLOCK: Final[int] = 32
"""Lazy rows are made this many consecutive points at a time (a block's points are mostly near
in space with z-order labels, and a block costs one call per axis)."""

SMALL_BATCH: Final[int] = 32
"""Below this many entries a batch loops over the scalar test: numpy's fixed cost per
call (some twenty array operations) outweighs the scalar tests it would replace.  Measured
for the kernel's ``partition`` (CPU time, 256K-point InBall set): the scalar loop costs about
0.4 µs per point plus 0.6 µs, the vectorised path about 20 µs whatever the length up to a
hundred points, so the two meet near 48 points; whole hull runs (OnSphere 8K, InBall 64K)
measured the same, within noise, for every threshold from 32 to 96."""

IntArray = NDArray[np.intp]
SignArray = NDArray[np.int8]
_Terms = Callable[..., tuple[NDArray[np.float64], NDArray[np.float64]]]
_ExactDet = Callable[..., NDArray[np.object_]]


def sign_of(v: int) -> int:
    """-1, 0 or +1: the sign of the integer ``v`` (an exact determinant). O(1)."""
    return (v > 0) - (v < 0)


class RowTable(Protocol):
    """The predicates' table of float rows, as its readers use it: point ``i``'s row by index.

    ``rows[i]`` is point ``i`` of the filter copy as a tuple of floats, or, for a
    lazy table, possibly ``()`` until :meth:`IndexedPoints._row` has made it
    (unpacking it then raises :class:`ValueError`, which the fast paths catch);
    an index out of range raises :class:`IndexError`.  A list for
    :class:`~persistri.impl.geometry.predicates3.Predicates3` and :class:`~persistri.impl.geometry.predicates2.Predicates2` (:meth:`IndexedPoints._setup`);
    a grid's table is a dict that makes each row on first use
    (:class:`~persistri.impl.geometry.grid_predicates.GridPredicates2`).  Compiled
    readers (the twin's kernels, docs/performance.md) check an attribute's
    declared type when they read it, so the declaration says only this.
    """

    def __getitem__(self, i: int, /) -> tuple[float, ...]: ...


class IndexedPoints:
    """What both dimensions share: validation, the filter's scaled copy, exact integers,
    counting, and the batch engine.

    The attribute ``stats`` is the :class:`~persistri.impl.stats.Stats` that tests
    report to, or None (nothing is counted); it may be reassigned at any time.
    Everything else is fixed at construction (memos aside: exact integer
    coordinates, and for :class:`~persistri.impl.geometry.predicates3.Predicates3` each point's tuple of floats,
    made on first use).
    """

    __slots__ = (
        "_points", "_n", "_dim", "_cols", "_rows", "_grain", "_uniform", "_shift", "_scale", "_span", "_ints", "stats"
    )

    _points: NDArray[np.float64]
    _n: int
    _dim: int
    _cols: tuple[NDArray[np.float64], ...]
    _rows: RowTable
    _grain: NDArray[np.int64] | None
    _uniform: bool
    _shift: int
    _scale: IntegerScale
    _span: tuple[int, int] | None
    _ints: dict[int, tuple[int, ...]]
    stats: Stats | None

    def _setup(
        self, pts: NDArray[np.float64], *, exact_rows: int, extra: int, stats: Stats | None, lazy_rows: bool = False
    ) -> None:
        """Build the filter copy and the integer scale from the first ``exact_rows`` rows.

        Rows from ``exact_rows`` on (the exact centroid, if any) get no float copy
        (NaN: every filter comparison rejects it) and their integers from :meth:`_int`.
        ``lazy_rows``: each point's tuple of floats is made on first use (:meth:`_row`).
        """
        n, dim = pts.shape
        pts.setflags(write=False)
        self._points = pts
        self._n = n
        self._dim = dim
        self.stats = stats
        span = self._span = grain_span(pts[:exact_rows]) if exact_rows else None
        # The least grain and the greatest magnitude of the nonzero coordinates decide the scale.
        lows = np.array([span[0]] if span else [], dtype=np.int64)
        highs = np.array([span[1]] if span else [], dtype=np.int64)
        scaling = choose_scaling(lows, highs)
        shift = self._shift = scaling.shift
        self._scale = IntegerScale(span[0] if span else 0, extra)
        fl = np.full((n, dim), np.nan)
        if scaling.uniform:
            # The usual case, decided from the extremes alone: after the shift every grain is >= GRAIN_MIN and
            # every magnitude <= TOP_MAX, so every row scales exactly and every filtered test is valid; the
            # rows' grains are never read (None).
            if exact_rows:
                if -1022 <= shift <= 1023:
                    # Every scaled coordinate is a double, so the product by the double 2^shift is exact: ldexp's
                    # values, written in place, without ldexp's per-entry cost (about 48 instructions an entry).
                    np.multiply(pts[:exact_rows], 2.0**shift, out=fl[:exact_rows])
                else:
                    fl[:exact_rows] = np.ldexp(pts[:exact_rows], shift)
            self._grain = None
        else:
            # Some grains are too fine for the filters: each row's grain decides whether its tests may be
            # filtered.  A row's scaled copy is exact unless a coordinate would lose bits (grain below
            # 2^-1074) or overflow (magnitude 2^1024 or more); such rows stay NaN.
            low, high = binary_exponents(pts[:exact_rows])
            # A row's grain: the least over its coordinates (a zero's, ZERO_LOW, is never the least unless
            # the row is all zeros).  Column by column: a reduction along rows of length 3 is slow.
            row_low = low[:, 0].copy()
            for j in range(1, dim):
                np.minimum(row_low, low[:, j], out=row_low)
            lost = ((low + shift < -1074) & (low < ZERO_LOW)) | (high + shift > 1024)
            valid = ~lost.any(axis=1)
            fl[:exact_rows][valid] = np.ldexp(pts[:exact_rows][valid], shift)
            grain = np.full(n, _INVALID_GRAIN, dtype=np.int64)
            grain[:exact_rows] = np.where(valid, row_low + shift, _INVALID_GRAIN)
            self._grain = grain
        self._uniform = scaling.uniform
        self._cols = tuple(np.ascontiguousarray(fl[:, j]) for j in range(dim))
        # One tuple per point: a test touches a few points, and a point's coordinates
        # then sit together in memory (a quarter faster than one list per axis at 10^5 points).
        if lazy_rows:
            # Made on first use, a block at a time (_row): a hull of points in a ball tests only the
            # points near its surface one by one, and a tuple per point costs 0.3 µs to build.
            self._rows = [_UNMADE] * n
        else:
            # Unpacked from the rows' bytes (a third faster than zipping three lists; the same floats).
            self._rows = list(struct.iter_unpack(f"{dim}d", fl.data))
        self._ints = {}

    def _row(self, i: int) -> tuple[float, ...]:
        """Point ``i`` of the filter copy as a tuple of floats, made with its block of :data:`_ROW_BLOCK`
        points if not made yet (lazy rows).  ``i`` must be a valid index. O(1) amortised."""
        rows = self._rows
        row = rows[i]
        if row:
            return row
        # Only _setup's lazy list has unmade rows; a table of another kind makes its rows itself.
        assert isinstance(rows, list), "a row table with unmade rows is _setup's lazy list"
        lazy: list[tuple[float, ...]] = rows
        start = i - i % _ROW_BLOCK
        block = [col[start : start + _ROW_BLOCK].tolist() for col in self._cols]
        lazy[start : start + len(block[0])] = zip(*block)
        return lazy[i]

    def _filter_columns(self, i: int | IntArray) -> list[NDArray[np.float64]]:
        """The filter copy's coordinates of point ``i`` (0-d arrays) or of points ``i`` (one array per axis)."""
        if isinstance(i, int):
            return [np.asarray(col[i]) for col in self._cols]
        return [col[i] for col in self._cols]

    def _extents(self) -> list[tuple[float, float]]:
        """``(least, greatest)`` input coordinate along each axis (the bounding box; NaN twice for no points). O(n)."""
        pts = self._points
        if pts.shape[0] == 0:
            return [(math.nan, math.nan)] * self._dim
        return [(float(pts[:, j].min()), float(pts[:, j].max())) for j in range(self._dim)]

    # -- sizes and data ----------------------------------------------------------------

    def __len__(self) -> int:
        """The number of indexed points (a constructed centre included)."""
        return self._n

    @property
    def points(self) -> NDArray[np.float64]:
        """The points as validated float64 rows (read-only)."""
        return self._points

    @property
    def filter_scale(self) -> tuple[int, bool]:
        """``(shift, uniform)``: the filters see ``points · 2^shift``; ``uniform`` if no test needs a grain check."""
        return self._shift, self._uniform

    # -- index validation --------------------------------------------------------------

    def _bad_index(self, indices: Sequence[object]) -> Exception:
        for i in indices:
            if isinstance(i, bool) or not isinstance(i, (int, np.integer)):
                return TypeError(f"point indices must be integers, got {i!r}")
            if not 0 <= i < self._n:
                return IndexError(f"point index {i} out of range for {self._n} points")
        return ValueError(f"invalid point indices {tuple(indices)!r}")

    def _fixed(self, *indices: int) -> None:
        for i in indices:
            if isinstance(i, bool) or not isinstance(i, (int, np.integer)) or not 0 <= i < self._n:
                raise self._bad_index(indices)

    def _index_arrays(self, *args: ArrayLike) -> tuple[list[int | IntArray], int]:
        """Validate point indices and their common length: ``(arguments, length)``.

        Each argument is an index (kept as an ``int``: a fixed point) or a 1-D
        integer array; the arrays must have one length (a 1-element array counts
        as a fixed point).  With no array the length is 1.
        """
        out: list[int | IntArray] = []
        m = -1
        for arg in args:
            if isinstance(arg, (int, np.integer)) and not isinstance(arg, (bool, np.bool_)):
                if not 0 <= arg < self._n:
                    raise IndexError(f"point index {arg} out of range for {self._n} points")
                out.append(int(arg))
                continue
            q = np.asarray(arg)
            if q.ndim > 1:
                raise ValueError(f"point indices must be an int or a 1-D array, got shape {q.shape}")
            if q.size and q.dtype.kind not in "iu":
                raise TypeError(f"point indices must be integers, got dtype {q.dtype}")
            if q.size:
                lo, hi = int(q.min()), int(q.max())
                if lo < 0 or hi >= self._n:
                    raise IndexError(f"point index {lo if lo < 0 else hi} out of range for {self._n} points")
            if q.ndim == 0 or q.size == 1:
                out.append(int(q.reshape(-1)[0]))
                continue
            if m >= 0 and q.size != m:
                raise ValueError(f"index arrays of different lengths: {m} and {q.size}")
            m = q.size
            out.append(q.astype(np.intp, copy=False))
        return out, max(m, 1) if m != 0 else 0

    # -- exact integers ------------------------------------------------------------------

    def _int(self, i: int) -> tuple[int, ...]:
        """The exact integer coordinates of point ``i`` (memoised; the exact centre is preset). O(bits)."""
        p = self._ints.get(i)
        if p is None:
            to_int = self._scale.to_int
            p = tuple(to_int(float(v)) for v in self._points[i])
            self._ints[i] = p
        return p

    def _int_columns(self, q: IntArray) -> list[NDArray[np.object_]]:
        """The exact integer coordinates of points ``q``, one object array per axis."""
        ints = self._scale.to_ints(self._points[q])
        return [ints[:, j] for j in range(self._dim)]

    # -- counting ------------------------------------------------------------------------

    def _count(self, tests: int, flops: int, failures: int) -> None:
        st = self.stats
        if st is not None:
            st.plane_side_tests += tests
            st.flops += flops * tests
            st.filter_failures += failures

    def _grain_ok(self, *indices: int) -> bool:
        """Whether every point of ``indices`` has a grain the filters hold for (a non-uniform set only)."""
        g = self._grain
        assert g is not None, "a uniform set keeps no per-point grains"
        return min(int(g[i]) for i in indices) >= GRAIN_MIN

    # -- the batch engine ----------------------------------------------------------------

    def _many(
        self,
        args: tuple[list[int | IntArray], int],
        terms: _Terms,
        errbound: float,
        flops: int,
        exact_det: _ExactDet,
        scalar: Callable[..., int],
        sos: Callable[..., int] | None,
    ) -> SignArray:
        """Signs of one predicate over validated arguments (:meth:`_index_arrays`): ints are fixed points.

        ``scalar`` decides one entry (used below :data:`SMALL_BATCH` entries);
        ``sos`` breaks exact zeros, or None for true signs.

        A fixed point enters the filter as 0-d arrays, not gathered copies.  The
        filter expressions translate every point by their *last* argument, so
        when some argument is fixed and the last is not, the filter is run with
        that fixed point moved to the end (and the sign corrected by the parity
        of the move): the products among fixed points are then computed once
        instead of once per entry.  The error bound is proved for every
        assignment of inputs, so any order of the arguments is sound.
        """
        idx, m = args
        if m < SMALL_BATCH:
            columns = [itertools.repeat(i, m) if isinstance(i, int) else i.tolist() for i in idx]
            return np.array([scalar(*entry) for entry in zip(*columns)], dtype=np.int8)
        fixed = [isinstance(i, int) for i in idx]
        order = list(range(len(idx)))
        flip = False
        if not fixed[-1] and any(fixed):
            j = max(k for k, f in enumerate(fixed) if f)
            order = order[:j] + order[j + 1 :] + [j]
            flip = (len(idx) - 1 - j) % 2 == 1  # moving j to the end takes len - 1 - j transpositions
        coords: list[NDArray[np.float64]] = []
        for k in order:
            coords.extend(self._filter_columns(idx[k]))
        if self._uniform:
            # No overflow is possible (magnitudes <= 2^TOP_MAX) and NaN is quiet: no warnings to silence.
            det, perm = terms(*coords)
            thr = errbound * perm
            out = (det > thr).view(np.int8) - (det < -thr).view(np.int8)
        else:
            with np.errstate(all="ignore"):
                det, perm = terms(*coords)
                thr = errbound * perm
                out = (det > thr).view(np.int8) - (det < -thr).view(np.int8)
        if flip:
            np.negative(out, out=out)
        if not self._uniform:
            grains = self._grain
            assert grains is not None, "a non-uniform set keeps its per-point grains"
            grain = np.full(m, ZERO_LOW, dtype=np.int64)
            for i in idx:
                grain = np.minimum(grain, grains[i])
            out[grain < GRAIN_MIN] = 0
        todo = np.flatnonzero(out == 0)
        self._count(m, flops, int(todo.size))
        if todo.size:
            sub = [np.full(todo.size, i, dtype=np.intp) if isinstance(i, int) else i[todo] for i in idx]
            exact = exact_det(*[c for i in sub for c in self._int_columns(i)])
            signs = (exact > 0).view(np.int8) - (exact < 0).view(np.int8)
            if sos is not None:
                for z in np.flatnonzero(signs == 0):
                    signs[z] = sos(*(int(i[z]) for i in sub))
            out[todo] = signs
        return out
