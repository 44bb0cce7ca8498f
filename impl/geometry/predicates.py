"""Exact geometric predicates over indexed points: the public API.

:class:`Predicates3` (3D: ``orient3d``, the plane-side test of the bulldozer,
paper §3 and Appendix A) and :class:`Predicates2` (2D: ``orient2d`` and
``incircle``, for the Delaunay terrain of §5) are built once from an ``(n, d)``
float64 array and answer tests by point *index*, as the algorithms need.

Every test is exact, in three stages:

1. **Filter** (:mod:`.filter`): the determinant and its permanent in float64
   on a copy of the points scaled by a power of two (exact); if
   ``|det| > ERRBOUND · permanent`` the sign is proved right.  Almost every
   test stops here.
2. **Exact** (:mod:`.exact`): the determinant on Python integers — the input
   doubles times a common power of two, with no rounding anywhere.
3. **Simulation of Simplicity** (:mod:`.sos`): an exact zero is broken by the
   symbolic perturbation indexed by point, so ``orient3d``, ``orient2d`` and
   ``incircle`` return ±1, never 0, and are antisymmetric in their arguments.
   The ``*_sign`` methods stop after stage 2 and return the true sign,
   0 included (for verification: "on or behind a face").

Sign conventions (Shewchuk's; all are determinants with a last column of ones):

* ``orient2d(a, b, c) = sign det[[a, 1], [b, 1], [c, 1]]``: +1 when ``a, b, c``
  turn counterclockwise.
* ``orient3d(a, b, c, d) = sign det[[a, 1], [b, 1], [c, 1], [d, 1]]``: +1 when
  ``d`` is *below* the plane of ``a, b, c``, "above" being where ``a, b, c``
  look counterclockwise.  For a face ``(a, b, c)`` of a convex polytope,
  outward-oriented by the right-hand rule, interior points give +1 and points
  that see the face (beyond its plane) give -1.  Moving one argument to
  another place permutes rows: ``orient3d(d, a, b, c) == -orient3d(a, b, c, d)``.
* ``incircle(a, b, c, d) = orient3d`` of the lifted points ``(x, y, x² + y²)``:
  +1 when ``d`` is inside the circle through ``a, b, c`` (counterclockwise).

Batches: ``*_batch(a, b, c, qs)`` tests many query points against fixed
points (a conflict list against a plane); ``*_many(a, b, c, d)`` takes any
mix of indices and index arrays, broadcast together (e.g. every (face, point)
pair of a visible region at once).  Both return int8 arrays equal, entry for
entry, to the scalar test; below :data:`SMALL_BATCH` entries they loop over
the scalar test, above it the filter runs vectorised and only the undecided
entries go to exact (vectorised) integer arithmetic and SoS.

Counting: with a :class:`~persistri.impl.stats.Stats` attached (``stats=``),
each test adds 1 to ``plane_side_tests`` (orient2d and incircle count as
orientation tests too), its filter's ``FLOPS_*`` to ``flops`` (the filter runs
for every test; integer work is not counted as flops), and 1 to
``filter_failures`` when exact arithmetic had to decide; batches add these per
query point.  With no ``Stats`` attached nothing is counted.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any, Final, Protocol

import itertools
import math
import struct

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.geometry.exact import (
    ZERO_LOW,
    IntegerScale,
    binary_exponents,
    grain_span,
    incircle_det,
    orient2d_det,
    orient3d_det,
)
from persistri.impl.geometry.filter import (
    ERRBOUND_INCIRCLE,
    ERRBOUND_ORIENT2D,
    ERRBOUND_ORIENT3D,
    FLOPS_INCIRCLE,
    FLOPS_ORIENT2D,
    FLOPS_ORIENT3D,
    GRAIN_MIN,
    choose_scaling,
    incircle_terms,
    orient2d_terms,
    orient3d_terms,
)
from persistri.impl.geometry.kernel import Indices, Orient3dKernel
from persistri.impl.geometry.kernel2d import Delaunay2Kernel
from persistri.impl.geometry.points import as_points
from persistri.impl.geometry.sos import sort_with_parity, sos_orient2d, sos_orient3d
from persistri.impl.stats import Stats

__all__ = ["Predicates2", "Predicates3", "Orient3dKernel", "Indices", "RowTable", "affine_dimension"]

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


def _sign(v: int) -> int:
    return (v > 0) - (v < 0)


class RowTable(Protocol):
    """The predicates' table of float rows, as its readers use it: point ``i``'s row by index.

    ``rows[i]`` is point ``i`` of the filter copy as a tuple of floats, or, for a
    lazy table, possibly ``()`` until :meth:`_IndexedPoints._row` has made it
    (unpacking it then raises :class:`ValueError`, which the fast paths catch);
    an index out of range raises :class:`IndexError`.  A list for
    :class:`Predicates3` and :class:`Predicates2` (:meth:`_IndexedPoints._setup`);
    a grid's table is a dict that makes each row on first use
    (:class:`~persistri.impl.geometry.grid_predicates.GridPredicates2`).  Compiled
    readers (the twin's kernels, docs/performance.md) check an attribute's
    declared type when they read it, so the declaration says only this.
    """

    def __getitem__(self, i: int, /) -> tuple[float, ...]: ...


class _IndexedPoints:
    """What both dimensions share: validation, the filter's scaled copy, exact integers,
    counting, and the batch engine.

    The attribute ``stats`` is the :class:`~persistri.impl.stats.Stats` that tests
    report to, or None (nothing is counted); it may be reassigned at any time.
    Everything else is fixed at construction (memos aside: exact integer
    coordinates, and for :class:`Predicates3` each point's tuple of floats,
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


class Predicates3(_IndexedPoints):
    """Exact 3D predicates over the rows of an ``(n, 3)`` array, by point index.

    Build once (O(n)): ``Predicates3(points, stats=None)``.  ``points`` must be
    an ``(n, 3)`` array of real numbers; NaN or inf raises :class:`ValueError`
    naming the first bad row, non-numeric input :class:`TypeError`, a wrong
    shape :class:`ValueError`.  Tests take point indices ``0 <= i < len(self)``;
    a bad index raises :class:`IndexError` or :class:`TypeError`.

    The bulldozer's centre point is added by :meth:`with_centroid`, which returns
    a new object in which the centre has index ``len(points)``.
    """

    __slots__ = ("_centre", "_centre_exact")

    _rows: list[tuple[float, ...]]
    """Always :meth:`_setup`'s list here (or :meth:`_with_row`'s copy of it): the compiled
    :class:`~persistri.impl.geometry.kernel.Orient3dKernel` indexes it as a list."""
    _centre: int | None
    _centre_exact: tuple[int, ...] | None

    def __init__(self, points: ArrayLike, *, stats: Stats | None = None) -> None:
        pts = as_points(points, 3)
        self._centre = None
        self._centre_exact = None
        self._setup(pts, exact_rows=pts.shape[0], extra=0, stats=stats, lazy_rows=True)

    def __repr__(self) -> str:
        centre = "" if self._centre is None else f", centre={self._centre}"
        return f"Predicates3(n={self._n}{centre})"

    # -- the centre --------------------------------------------------------------------

    @property
    def centre(self) -> int | None:
        """The index of the constructed centre point, or None before :meth:`with_centroid`."""
        return self._centre

    @property
    def centre_is_float(self) -> bool:
        """Whether the centre is a double (filtered like any point) rather than the exact centroid."""
        return self._centre is not None and self._centre_exact is None

    def with_centroid(self, a: int, b: int, c: int, d: int) -> Predicates3:
        """A new ``Predicates3`` with a point strictly inside tetrahedron ``a, b, c, d`` at index ``len(self)``.

        The centre is the float centroid ``fl((p_a + p_b + p_c + p_d) / 4)``
        when it is *exactly* verified to lie strictly inside (four exact
        orientation signs, all equal to the tetrahedron's).  It is then an
        ordinary input double: it takes part in the integer scale and the
        filter like any point, so tests involving it stay fast.  When the float
        centroid is not strictly inside (a needle-thin tetrahedron, or
        overflow), the centre is the exact centroid: every integer coordinate
        is multiplied by 4 and the centre is the exact sum of the four points;
        tests involving it are then always decided exactly (its float copy is
        NaN, which the filter never accepts), and row ``len(self)`` of
        :attr:`points` holds only the nearest doubles.  Either way the centre
        is indexed for SoS like any point (the largest index: the least
        perturbed).  Stats and everything else carry over.

        Raises :class:`ValueError` if the tetrahedron is flat (exact sign 0),
        the indices repeat, or a centre was already added. O(n) (copies the arrays).
        """
        if self._centre is not None:
            raise ValueError("this point set already has a centre")
        self._fixed(a, b, c, d)
        tetra = (int(a), int(b), int(c), int(d))
        if len(set(tetra)) != 4:
            raise ValueError(f"a tetrahedron needs four distinct points, got {tetra}")
        s = self.orient3d_sign(*tetra)
        if s == 0:
            raise ValueError(f"points {tetra} are coplanar: no interior centre")
        p = self._points[list(tetra)]
        with np.errstate(all="ignore"):
            guess = ((p[0] + p[1]) + (p[2] + p[3])) * 0.25
        n = self._n
        if np.all(np.isfinite(guess)):
            guess = guess + 0.0
            cand = self._with_row(guess)
            if cand is None:
                cand = Predicates3.__new__(Predicates3)
                cand._setup(np.vstack([self._points, guess[None, :]]), exact_rows=n + 1, extra=0, stats=self.stats, lazy_rows=True)
            cand._centre = n
            cand._centre_exact = None
            if cand._strictly_inside(tetra, n, s):
                return cand
        # The exact centroid: at the integer scale ×4 it is the sum of the four points.
        ints = [self._int(i) for i in tetra]
        exact = tuple(ints[0][j] + ints[1][j] + ints[2][j] + ints[3][j] for j in range(3))
        unit = Fraction(2) ** (self._scale.exponent - 2)  # the value of 1 at the scale ×4
        nearest = np.array([[float(v * unit) for v in exact]])
        out = Predicates3.__new__(Predicates3)
        out._centre = n
        out._centre_exact = None
        out._setup(np.vstack([self._points, nearest]), exact_rows=n, extra=2, stats=self.stats, lazy_rows=True)
        out._centre_exact = exact
        out._ints[n] = exact  # the memo of exact integers serves the centre's from the start
        assert out._strictly_inside(tetra, n, s), "the exact centroid of a tetrahedron is interior"
        return out

    def _with_row(self, row: NDArray[np.float64]) -> Predicates3 | None:
        """A copy with ``row`` appended as an ordinary exact point, or None if that changes the filter scaling.

        What :meth:`_setup` would build for the ``n + 1`` rows, without redoing it
        for the first ``n``: when the power-of-two scale of the filter copy stays
        the same (the usual case: a centroid's exponents lie within the data's),
        the filter rows and columns are the parent's plus one.  O(n) copying, no
        per-point Python work.
        """
        if self._span is None or not self._uniform:
            return None
        low, high = binary_exponents(row[None, :])
        nonzero = low < ZERO_LOW
        g, h = self._span
        if nonzero.any():
            g, h = min(g, int(low[nonzero].min())), max(h, int(high[nonzero].max()))
        scaling = choose_scaling(np.array([g], dtype=np.int64), np.array([h], dtype=np.int64))
        if not scaling.uniform or scaling.shift != self._shift:
            return None
        shift = self._shift
        scaled = np.ldexp(row, shift)
        out = Predicates3.__new__(Predicates3)
        pts = np.vstack([self._points, row[None, :]])
        pts.setflags(write=False)
        out._points = pts
        out._n = self._n + 1
        out._dim = self._dim
        out.stats = self.stats
        out._shift = shift
        out._span = (g, h)
        out._scale = IntegerScale(min(self._scale.exponent, g), 0)
        out._grain = None  # the scaling is uniform: every grain, the new one's included, is >= GRAIN_MIN
        out._uniform = True
        out._cols = tuple(np.append(col, x) for col, x in zip(self._cols, scaled.tolist()))
        out._rows = self._rows + [tuple(scaled.tolist())]
        out._ints = dict(self._ints) if out._scale == self._scale else {}
        return out

    def _strictly_inside(self, tetra: tuple[int, int, int, int], c: int, s: int) -> bool:
        """Whether ``c`` has positive barycentric coordinates in ``tetra`` (orientation ``s``), exactly."""
        for k in range(4):
            replaced = list(tetra)
            replaced[k] = c
            if self.orient3d_sign(*replaced) != s:
                return False
        return True

    def _int_columns(self, q: IntArray) -> list[NDArray[np.object_]]:
        cols = super()._int_columns(q)
        if self._centre_exact is not None:
            at = np.flatnonzero(q == self._centre)
            for j in range(3):
                cols[j][at] = self._centre_exact[j]
        return cols

    # -- orient3d ------------------------------------------------------------------------

    def orient3d(self, a: int, b: int, c: int, d: int) -> int:
        """±1: the SoS sign of ``det[[a, 1], [b, 1], [c, 1], [d, 1]]`` (see the module docstring).

        Never 0; ``d`` below the plane of ``a, b, c`` gives +1.  Raises
        :class:`ValueError` if two indices are equal.  O(1): one float filter
        (:data:`~persistri.impl.geometry.filter.FLOPS_ORIENT3D` flops), exact
        integers when it cannot decide.
        """
        row = self._row
        try:
            if (a | b | c | d) < 0:
                raise IndexError
            ax, ay, az = row(a)
            bx, by, bz = row(b)
            cx, cy, cz = row(c)
            dx, dy, dz = row(d)
        except (IndexError, TypeError):
            raise self._bad_index((a, b, c, d)) from None
        det, perm = orient3d_terms(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz)
        st = self.stats
        if st is not None:
            st.plane_side_tests += 1
            st.flops += FLOPS_ORIENT3D
        if self._uniform or self._grain_ok(a, b, c, d):
            thr = ERRBOUND_ORIENT3D * perm
            if det > thr:
                return 1
            if det < -thr:
                return -1
        if st is not None:
            st.filter_failures += 1
        return self._orient3d_exact(a, b, c, d, True)

    def orient3d_sign(self, a: int, b: int, c: int, d: int) -> int:
        """The true sign of the orient3d determinant: -1, 0 or +1 (no perturbation). O(1)."""
        self._fixed(a, b, c, d)
        if self._uniform or self._grain_ok(a, b, c, d):
            row = self._row
            ax, ay, az = row(a)
            bx, by, bz = row(b)
            cx, cy, cz = row(c)
            dx, dy, dz = row(d)
            det, perm = orient3d_terms(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz)
            thr = ERRBOUND_ORIENT3D * perm
            if det > thr or det < -thr:
                self._count(1, FLOPS_ORIENT3D, 0)
                return 1 if det > 0 else -1
        self._count(1, FLOPS_ORIENT3D, 1)
        return self._orient3d_exact(a, b, c, d, False)

    def _orient3d_exact(self, a: int, b: int, c: int, d: int, perturb: bool) -> int:
        det = orient3d_det(*self._int(a), *self._int(b), *self._int(c), *self._int(d))
        if det or not perturb:
            return _sign(det)
        return self._sos3(a, b, c, d)

    def _sos3(self, a: int, b: int, c: int, d: int) -> int:
        order, parity = sort_with_parity((int(a), int(b), int(c), int(d)))
        return parity * sos_orient3d(*(self._int(i) for i in order))

    def orient3d_batch(self, a: int, b: int, c: int, qs: ArrayLike) -> SignArray:
        """``[orient3d(a, b, c, q) for q in qs]`` as an int8 array of ±1.

        For conflict lists: the plane-side test of every pending point ``q``
        against one plane.  The filter runs vectorised; the entries it cannot
        decide go to exact integer arithmetic (vectorised on object arrays), and
        their exact zeros to SoS.  ``q`` equal to ``a``, ``b`` or ``c`` raises
        :class:`ValueError`.  O(len(qs)).
        """
        self._fixed(a, b, c)
        return self.orient3d_many(a, b, c, qs)

    def orient3d_sign_batch(self, a: int, b: int, c: int, qs: ArrayLike) -> SignArray:
        """``[orient3d_sign(a, b, c, q) for q in qs]``: true signs, 0 included. O(len(qs))."""
        self._fixed(a, b, c)
        idx = self._index_arrays(a, b, c, qs)
        return self._many(idx, orient3d_terms, ERRBOUND_ORIENT3D, FLOPS_ORIENT3D, orient3d_det, self.orient3d_sign, None)

    def orient3d_many(self, a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike) -> SignArray:
        """``[orient3d(a[k], b[k], c[k], d[k]) for k …]``: each argument an index or a 1-D index array.

        The arrays are broadcast together, so any mix of fixed points and
        per-entry points works — e.g. every (face, pending point) pair of a
        whole visible region in one call.  ±1 entries; O(length).
        """
        idx = self._index_arrays(a, b, c, d)
        return self._many(idx, orient3d_terms, ERRBOUND_ORIENT3D, FLOPS_ORIENT3D, orient3d_det, self.orient3d, self._sos3)

    def kernel(self) -> Orient3dKernel:
        """The trusted fast path of :meth:`orient3d` for internal algorithms (the bulldozer): no validation.

        See :class:`Orient3dKernel`.  O(1); make it once per run.
        """
        return Orient3dKernel(self)

    # -- affine structure -----------------------------------------------------------------

    def collinear(self, a: int, b: int, c: int) -> bool:
        """Whether points ``a, b, c`` lie on one line (exact; repeated points count as collinear). O(1)."""
        self._fixed(a, b, c)
        return bool(self._collinear_batch(int(a), int(b), np.array([c], dtype=np.intp))[0])

    def _collinear_batch(self, a: int, b: int, q: IntArray) -> NDArray[np.bool_]:
        """Exact collinearity of ``a, b, q`` for each ``q``: the three projected orient2d vanish."""
        m = q.size
        undecided = np.ones(m, dtype=bool)
        cols = self._cols
        grain_ok = np.ones(m, dtype=bool)
        if not self._uniform:
            grains = self._grain
            assert grains is not None, "a non-uniform set keeps its per-point grains"
            grain_ok = np.minimum(grains[q], min(int(grains[a]), int(grains[b]))) >= GRAIN_MIN
        for u, v in ((0, 1), (1, 2), (2, 0)):
            au, av = np.full(m, cols[u][a]), np.full(m, cols[v][a])
            bu, bv = np.full(m, cols[u][b]), np.full(m, cols[v][b])
            with np.errstate(all="ignore"):
                det, perm = orient2d_terms(au, av, bu, bv, cols[u][q], cols[v][q])
                thr = ERRBOUND_ORIENT2D * perm
                undecided &= ~(((det > thr) | (det < -thr)) & grain_ok)
        self._count(3 * m, FLOPS_ORIENT2D, 0)
        out = np.zeros(m, dtype=bool)
        todo = np.flatnonzero(undecided)
        if todo.size:
            self._count(0, 0, int(todo.size))
            pa, pb = self._int(a), self._int(b)
            iq = self._int_columns(q[todo])
            zero = np.ones(todo.size, dtype=bool)
            for u, v in ((0, 1), (1, 2), (2, 0)):
                fau, fav, fbu, fbv = (np.full(todo.size, x, dtype=object) for x in (pa[u], pa[v], pb[u], pb[v]))
                zero &= orient2d_det(fau, fav, fbu, fbv, iq[u], iq[v]) == 0
            out[todo] = zero
        return out

    def affine_basis(self, order: ArrayLike | None = None) -> tuple[int, ...]:
        """A maximal affinely independent subset, as indices, chosen greedily in ``order``.

        Scanning ``order`` (default: every input row in index order, the centre
        excluded), the result is ``(p0,)`` plus the first point different from
        ``p0``, then the first not on their line, then the first not on their
        plane — as far as such points exist.  Its length minus one is the
        affine dimension of the scanned points (exact): 0 all identical,
        1 collinear, 2 coplanar, 3 spanning space; ``()`` for no points.  The
        hull's first tetrahedron can be the 4-point result.  O(n) filtered
        tests, done in growing chunks so that typical inputs stop after a few points.
        """
        if order is None:
            n_input = self._n if self._centre is None else self._centre
            idx = np.arange(n_input, dtype=np.intp)
        else:
            (first,), _ = self._index_arrays(order)
            idx = np.array([first], dtype=np.intp) if isinstance(first, int) else first
            if self._centre is not None and bool(np.any(idx == self._centre)):
                raise ValueError("the affine basis is taken over input points, not the centre")
        if idx.size == 0:
            return ()
        p0 = int(idx[0])
        rows = self._points
        p1 = self._first(idx, lambda q: np.any(rows[q] != rows[p0], axis=1))
        if p1 is None:
            return (p0,)
        p2 = self._first(idx, lambda q: ~self._collinear_batch(p0, p1, q))
        if p2 is None:
            return (p0, p1)
        p3 = self._first(idx, lambda q: self.orient3d_sign_batch(p0, p1, p2, q) != 0)
        if p3 is None:
            return (p0, p1, p2)
        return (p0, p1, p2, p3)

    @staticmethod
    def _first(idx: IntArray, hit: Callable[[IntArray], NDArray[np.bool_]]) -> int | None:
        """The first index in ``idx`` where ``hit`` is True, testing chunks of growing size."""
        start = 0
        size = 16
        while start < idx.size:
            chunk = idx[start : start + size]
            found = np.flatnonzero(hit(chunk))
            if found.size:
                return int(chunk[found[0]])
            start += size
            size *= 8
        return None


def affine_dimension(points: ArrayLike | Predicates3) -> int:
    """The exact dimension of the affine hull of 3D points: 0, 1, 2 or 3 (-1 for no points).

    0: all points identical; 1: collinear; 2: coplanar; 3: spanning space.
    Accepts an ``(n, 3)`` array (validated as by :class:`Predicates3`) or a
    :class:`Predicates3` (its input points, the centre excluded). O(n).
    """
    preds = points if isinstance(points, Predicates3) else Predicates3(points)
    return len(preds.affine_basis()) - 1


class Predicates2(_IndexedPoints):
    """Exact 2D predicates over the rows of an ``(n, 2)`` array, by point index.

    ``orient2d`` and ``incircle`` with their batch and true-sign variants, for
    the Delaunay terrain (paper §5).  Validation and errors as
    :class:`Predicates3`.
    """

    __slots__ = ()

    def __init__(self, points: ArrayLike, *, stats: Stats | None = None) -> None:
        pts = as_points(points, 2)
        # Lazy rows: a height grid has millions of points and only its vertices are ever tested one by one.
        self._setup(pts, exact_rows=pts.shape[0], extra=0, stats=stats, lazy_rows=True)

    def __repr__(self) -> str:
        return f"Predicates2(n={self._n})"

    def coordinates(self, q: IntArray) -> tuple[NDArray[Any], NDArray[Any]]:
        """The input coordinates ``(x, y)`` of points ``q`` (an index array), as two arrays of real numbers
        (float64 here; a grid's are small integers). O(len(q))."""
        pts = self._points[q]
        return pts[:, 0], pts[:, 1]

    def coordinate_columns(self) -> tuple[NDArray[Any], NDArray[Any]]:
        """The ``x`` and ``y`` of every point, as two columns (views of :attr:`points`; a grid's are small integers). O(1)."""
        return self._points[:, 0], self._points[:, 1]

    def xy(self, i: int) -> tuple[float, float]:
        """The input coordinates ``(x, y)`` of point ``i``. O(1)."""
        x, y = self._points[i].tolist()
        return x, y

    def kernel(self) -> Delaunay2Kernel:
        """The trusted fast path of :meth:`orient2d`, :meth:`orient2d_sign` and :meth:`incircle`: no validation.

        For the incremental Delaunay triangulation's loops; see
        :class:`~persistri.impl.geometry.kernel2d.Delaunay2Kernel`.  O(n) once (the
        point set's extents); make it once per run.
        """
        return Delaunay2Kernel(self)

    # -- orient2d ------------------------------------------------------------------------

    def orient2d(self, a: int, b: int, c: int) -> int:
        """±1: the SoS sign of ``det[[a, 1], [b, 1], [c, 1]]``; +1 when ``a, b, c`` turn counterclockwise.

        Never 0; equal indices raise :class:`ValueError`.  The perturbation is
        Λ3 of Edelsbrunner–Mücke with ``δ = 2``.  O(1).
        """
        rows = self._rows
        try:
            if (a | b | c) < 0:
                raise IndexError
            ax, ay = rows[a]
            bx, by = rows[b]
            cx, cy = rows[c]
        except (IndexError, TypeError):
            raise self._bad_index((a, b, c)) from None
        except ValueError:  # a lazy row not made yet
            (ax, ay), (bx, by), (cx, cy) = self._row(a), self._row(b), self._row(c)
        det, perm = orient2d_terms(ax, ay, bx, by, cx, cy)
        st = self.stats
        if st is not None:
            st.plane_side_tests += 1
            st.flops += FLOPS_ORIENT2D
        if self._uniform or self._grain_ok(a, b, c):
            thr = ERRBOUND_ORIENT2D * perm
            if det > thr:
                return 1
            if det < -thr:
                return -1
        if st is not None:
            st.filter_failures += 1
        return self._orient2d_exact(a, b, c, True)

    def orient2d_sign(self, a: int, b: int, c: int) -> int:
        """The true sign of the orient2d determinant: -1, 0 or +1. O(1)."""
        self._fixed(a, b, c)
        if self._uniform or self._grain_ok(a, b, c):
            row = self._row
            ax, ay = row(a)
            bx, by = row(b)
            cx, cy = row(c)
            det, perm = orient2d_terms(ax, ay, bx, by, cx, cy)
            thr = ERRBOUND_ORIENT2D * perm
            if det > thr or det < -thr:
                self._count(1, FLOPS_ORIENT2D, 0)
                return 1 if det > 0 else -1
        self._count(1, FLOPS_ORIENT2D, 1)
        return self._orient2d_exact(a, b, c, False)

    def _orient2d_exact(self, a: int, b: int, c: int, perturb: bool) -> int:
        det = orient2d_det(*self._int(a), *self._int(b), *self._int(c))
        if det or not perturb:
            return _sign(det)
        return self._sos2(a, b, c)

    def _sos2(self, a: int, b: int, c: int) -> int:
        order, parity = sort_with_parity((int(a), int(b), int(c)))
        return parity * sos_orient2d(*(self._int(i) for i in order))

    def orient2d_batch(self, a: int, b: int, qs: ArrayLike) -> SignArray:
        """``[orient2d(a, b, q) for q in qs]`` as an int8 array of ±1. O(len(qs))."""
        self._fixed(a, b)
        return self.orient2d_many(a, b, qs)

    def orient2d_sign_batch(self, a: int, b: int, qs: ArrayLike) -> SignArray:
        """``[orient2d_sign(a, b, q) for q in qs]``: true signs, 0 included. O(len(qs))."""
        self._fixed(a, b)
        idx = self._index_arrays(a, b, qs)
        return self._many(idx, orient2d_terms, ERRBOUND_ORIENT2D, FLOPS_ORIENT2D, orient2d_det, self.orient2d_sign, None)

    def orient2d_many(self, a: ArrayLike, b: ArrayLike, c: ArrayLike) -> SignArray:
        """``[orient2d(a[k], b[k], c[k]) for k …]``, the arguments broadcast together. ±1 entries; O(length)."""
        idx = self._index_arrays(a, b, c)
        return self._many(idx, orient2d_terms, ERRBOUND_ORIENT2D, FLOPS_ORIENT2D, orient2d_det, self.orient2d, self._sos2)

    # -- incircle ------------------------------------------------------------------------

    def incircle(self, a: int, b: int, c: int, d: int) -> int:
        """±1: the SoS sign of the lifted orientation ``det[[a, |a|², 1], …, [d, |d|², 1]]``.

        +1 when ``d`` is inside the circle through ``a, b, c`` taken
        counterclockwise (Shewchuk's convention); it equals ``orient3d`` of the
        lifted points ``(x, y, x² + y²)`` (``proofs/proof_predicates.py``).

        Exact zeros (cocircular points) are broken by Λ4 on the lifted points,
        the lift perturbed as an independent third coordinate, least
        significant per point.  Why this choice: restricted to ``x, y`` the
        perturbation orders the entries exactly as :meth:`orient2d`'s (x_0,
        y_0, x_1, y_1, … from most to least significant), and SoS signs
        depend only on that order, so both predicates see *one* perturbed
        point set; perturbing the lift independently of ``x² + y²`` is giving
        each point an infinitesimal weight, so the triangulation these signs
        define is the regular triangulation of the perturbed weighted points —
        the Delaunay triangulation of the input wherever it is unique, with
        ties among cocircular points broken consistently.  Never 0; equal
        indices raise :class:`ValueError`.  O(1).
        """
        rows = self._rows
        try:
            if (a | b | c | d) < 0:
                raise IndexError
            ax, ay = rows[a]
            bx, by = rows[b]
            cx, cy = rows[c]
            dx, dy = rows[d]
        except (IndexError, TypeError):
            raise self._bad_index((a, b, c, d)) from None
        except ValueError:  # a lazy row not made yet
            (ax, ay), (bx, by), (cx, cy), (dx, dy) = self._row(a), self._row(b), self._row(c), self._row(d)
        det, perm = incircle_terms(ax, ay, bx, by, cx, cy, dx, dy)
        st = self.stats
        if st is not None:
            st.plane_side_tests += 1
            st.flops += FLOPS_INCIRCLE
        if self._uniform or self._grain_ok(a, b, c, d):
            thr = ERRBOUND_INCIRCLE * perm
            if det > thr:
                return 1
            if det < -thr:
                return -1
        if st is not None:
            st.filter_failures += 1
        return self._incircle_exact(a, b, c, d, True)

    def incircle_sign(self, a: int, b: int, c: int, d: int) -> int:
        """The true sign of the incircle determinant: -1, 0 (cocircular) or +1. O(1)."""
        self._fixed(a, b, c, d)
        if self._uniform or self._grain_ok(a, b, c, d):
            row = self._row
            ax, ay = row(a)
            bx, by = row(b)
            cx, cy = row(c)
            dx, dy = row(d)
            det, perm = incircle_terms(ax, ay, bx, by, cx, cy, dx, dy)
            thr = ERRBOUND_INCIRCLE * perm
            if det > thr or det < -thr:
                self._count(1, FLOPS_INCIRCLE, 0)
                return 1 if det > 0 else -1
        self._count(1, FLOPS_INCIRCLE, 1)
        return self._incircle_exact(a, b, c, d, False)

    def _incircle_exact(self, a: int, b: int, c: int, d: int, perturb: bool) -> int:
        det = incircle_det(*self._int(a), *self._int(b), *self._int(c), *self._int(d))
        if det or not perturb:
            return _sign(det)
        return self._sos_incircle(a, b, c, d)

    def _lifted(self, i: int) -> tuple[int, int, int]:
        x, y = self._int(i)
        return (x, y, x * x + y * y)

    def _sos_incircle(self, a: int, b: int, c: int, d: int) -> int:
        order, parity = sort_with_parity((int(a), int(b), int(c), int(d)))
        return parity * sos_orient3d(*(self._lifted(i) for i in order))

    def incircle_batch(self, a: int, b: int, c: int, qs: ArrayLike) -> SignArray:
        """``[incircle(a, b, c, q) for q in qs]`` as an int8 array of ±1. O(len(qs))."""
        self._fixed(a, b, c)
        return self.incircle_many(a, b, c, qs)

    def incircle_sign_batch(self, a: int, b: int, c: int, qs: ArrayLike) -> SignArray:
        """``[incircle_sign(a, b, c, q) for q in qs]``: true signs, 0 included. O(len(qs))."""
        self._fixed(a, b, c)
        idx = self._index_arrays(a, b, c, qs)
        return self._many(idx, incircle_terms, ERRBOUND_INCIRCLE, FLOPS_INCIRCLE, incircle_det, self.incircle_sign, None)

    def incircle_many(self, a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike) -> SignArray:
        """``[incircle(a[k], b[k], c[k], d[k]) for k …]``, the arguments broadcast together. ±1; O(length)."""
        idx = self._index_arrays(a, b, c, d)
        return self._many(idx, incircle_terms, ERRBOUND_INCIRCLE, FLOPS_INCIRCLE, incircle_det, self.incircle, self._sos_incircle)
