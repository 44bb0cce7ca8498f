"""Exact 2D predicates over a point set that grows: the Steiner points of Delaunay refinement.

:class:`~persistri.impl.geometry.predicates.Predicates2` is built once over a
fixed array: its filter's power-of-two scale and its exact integer scale are
computed from *all* the points.  Ruppert's refinement adds points as it goes
(segment split points, circumcentres, off-centres), so
:class:`GrowingPredicates2` answers the same tests over an **append-only**
point set:

* **indices are stable** — :meth:`GrowingPredicates2.append` gives the new
  point the next index; no point is ever removed or moved, so the Simulation of
  Simplicity order (by index) of the points already there never changes, and a
  decision made over old points stays the decision over them forever (old mesh
  versions stay exactly what they were);
* **the filter's scale is fixed** from the initial points (the same
  :func:`~persistri.impl.geometry.filter.choose_scaling` as ``Predicates2``);
  each appended point is checked against it on arrival: a point whose scaled
  coordinates have too fine a grain or too large a magnitude for the proved
  filter (``GRAIN_MIN``, ``TOP_MAX``) gets a NaN float copy, which no filter
  comparison accepts, so every test that involves it is decided exactly.  A
  Steiner point lies in the domain's bounding box and has the precision of a
  double there, so in practice every point is filtered;
* **the exact scale is per test** — each point is stored as integers times a
  power of two of its own (``x = X · 2^e``, ``y = Y · 2^e``); a test brings
  its few points to their least exponent, which is a positive common scaling
  that changes no determinant's sign (nor any SoS minor's).  No global scale
  has to be recomputed when a finer point arrives.

The tests are those of ``Predicates2`` (``orient2d``, ``incircle``, with SoS,
and their ``*_sign`` true-sign variants, same conventions), plus
:meth:`GrowingPredicates2.dot_sign`, the sign of ``(a − p) · (b − p)``:
negative exactly when the angle at ``p`` in triangle ``a p b`` is obtuse, i.e.
when ``p`` lies strictly inside the circle with diameter ``ab`` (Thales;
``proofs/proof_mesh.py``) — the *encroachment* test of Delaunay refinement.
Its filter has orient2d's structure (two products of differences, summed
instead of subtracted) and orient2d's constant, proved sufficient in
``proofs/proof_mesh.py`` with the same forward error analysis.

Costs: every test O(1) (a filtered float expression; Python integers when it
cannot decide); :meth:`GrowingPredicates2.append` O(1) amortised;
:attr:`GrowingPredicates2.points` O(n) when the set has grown since the last call.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.geometry.exact import ZERO_LOW, incircle_det, orient2d_det
from persistri.impl.geometry.filter import (
    ERRBOUND_INCIRCLE,
    ERRBOUND_ORIENT2D,
    GRAIN_MIN,
    TOP_MAX,
    T,
    _abs,
    choose_scaling,
)
from persistri.impl.geometry.points import as_points
from persistri.impl.geometry.sos import sort_with_parity, sos_orient2d, sos_orient3d
from persistri.impl.stats import Stats

__all__ = ["GrowingPredicates2", "ERRBOUND_DOT", "dot_terms", "exact_parts"]

ERRBOUND_DOT: Final[float] = ERRBOUND_ORIENT2D
"""Filter constant of :func:`dot_terms`: orient2d's, proved sufficient for the sum form in ``proofs/proof_mesh.py``."""

_NAN: Final[tuple[float, float]] = (math.nan, math.nan)

def dot_terms(ax: T, ay: T, bx: T, by: T, px: T, py: T) -> tuple[T, T]:
    """``(det, permanent)`` of the dot product ``(a − p) · (b − p)`` in floating point. O(1).

    The same operations as :func:`~persistri.impl.geometry.filter.orient2d_terms`
    with the last difference a sum: negative exactly when ``p`` is strictly inside
    the diametral circle of ``ab``.
    """
    apx = ax - px
    bpx = bx - px
    apy = ay - py
    bpy = by - py
    left = apx * bpx
    right = apy * bpy
    det = left + right
    permanent = _abs(left) + _abs(right)
    return det, permanent


def exact_parts(x: float) -> tuple[int, int]:
    """``(m, e)`` with ``x = m · 2^e`` and ``m`` odd (``(0, ZERO_LOW)`` for 0): a double as an exact integer pair. O(1)."""
    if x == 0.0:
        return 0, ZERO_LOW
    num, den = x.as_integer_ratio()
    low = (num & -num).bit_length() - 1
    return num >> low, low - (den.bit_length() - 1)


def _sign(v: int) -> int:
    return (v > 0) - (v < 0)


class GrowingPredicates2:
    """Exact ``orient2d``, ``incircle`` and the encroachment sign over an append-only 2D point set (module docstring).

    ``GrowingPredicates2(points, stats=None)`` validates ``points`` like
    ``Predicates2`` (an ``(n, 2)`` array of finite reals, exactly
    representable) and fixes the filter's scale from them; :meth:`append`
    adds one point (a pair of finite doubles) and returns its index.  Tests
    take indices; equal indices in a perturbed test raise :class:`ValueError`.
    ``stats`` (a :class:`~persistri.impl.stats.Stats`, or None) counts the
    tests (``plane_side_tests``) and the exact fallbacks (``filter_failures``).
    """

    __slots__ = ("_xy", "_rows", "_exact", "_shift", "_array", "stats")

    _xy: list[tuple[float, float]]
    _rows: list[tuple[float, float]]
    _exact: list[tuple[int, int, int]]
    _shift: int
    _array: NDArray[np.float64] | None
    stats: Stats | None

    def __init__(self, points: ArrayLike, *, stats: Stats | None = None) -> None:
        pts = as_points(points, 2)
        self.stats = stats
        # One pass over the coordinates: each one's exact parts (exact_parts, written out), the point's integers at
        # its least exponent (as append stores them), and the extremes the scale comes from (the grain of a nonzero x
        # is the exponent of its odd multiple, its magnitude frexp's exponent, as exact.binary_exponents has them).
        # A zero gets the grain ZERO_LOW and the magnitude -ZERO_LOW: it passes both filter checks below, as in append.
        xy: list[tuple[float, float]] = []
        exact: list[tuple[int, int, int]] = []
        exps: list[tuple[int, int, int, int]] = []
        frexp = math.frexp
        grain = ZERO_LOW
        top = -ZERO_LOW
        for x, y in pts.tolist():
            if x == 0.0:
                mx, ex, hx = 0, ZERO_LOW, -ZERO_LOW
            else:
                num, den = x.as_integer_ratio()
                low = (num & -num).bit_length() - 1
                mx, ex, hx = num >> low, low - (den.bit_length() - 1), frexp(x)[1]
                if ex < grain:
                    grain = ex
                if hx > top:
                    top = hx
            if y == 0.0:
                my, ey, hy = 0, ZERO_LOW, -ZERO_LOW
            else:
                num, den = y.as_integer_ratio()
                low = (num & -num).bit_length() - 1
                my, ey, hy = num >> low, low - (den.bit_length() - 1), frexp(y)[1]
                if ey < grain:
                    grain = ey
                if hy > top:
                    top = hy
            e = ex if ex < ey else ey
            if e == ZERO_LOW:
                e = 0
            exact.append((mx << (ex - e) if mx else 0, my << (ey - e) if my else 0, e))
            xy.append((x, y))
            exps.append((ex, hx, ey, hy))
        if grain != ZERO_LOW:
            shift = choose_scaling(np.array([grain]), np.array([top])).shift
        else:
            shift = choose_scaling(np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)).shift
        ldexp = math.ldexp
        # A filter copy only if each coordinate has a grain and a magnitude the proved filters take (append's test).
        self._rows = [
            (ldexp(x, shift), ldexp(y, shift))
            if ex + shift >= GRAIN_MIN and hx + shift <= TOP_MAX and ey + shift >= GRAIN_MIN and hy + shift <= TOP_MAX
            else _NAN
            for (x, y), (ex, hx, ey, hy) in zip(xy, exps)
        ]
        self._shift = shift
        self._xy = xy
        self._exact = exact
        self._array = None

    def __repr__(self) -> str:
        return f"GrowingPredicates2(n={len(self._xy)})"

    def __len__(self) -> int:
        """The number of points (initial and appended)."""
        return len(self._xy)

    # -- the point set -------------------------------------------------------------------

    def append(self, x: float, y: float) -> int:
        """Add the point ``(x, y)`` (finite doubles) and return its index, ``len(self)`` before the call. O(1).

        :class:`ValueError` for a NaN or infinite coordinate.  The point may equal
        an existing one: indices, not coordinates, identify points (the caller
        decides whether a duplicate is acceptable; :meth:`same` tests it).
        """
        x, y = float(x), float(y)
        if not (math.isfinite(x) and math.isfinite(y)):
            raise ValueError(f"a point must have finite coordinates, got ({x!r}, {y!r})")
        x, y = x + 0.0, y + 0.0
        # exact_parts(x), exact_parts(y) and the point stored, inlined (one call per new point instead of three).
        if x == 0.0:
            mx, ex = 0, ZERO_LOW
        else:
            num, den = x.as_integer_ratio()
            low = (num & -num).bit_length() - 1
            mx, ex = num >> low, low - (den.bit_length() - 1)
        if y == 0.0:
            my, ey = 0, ZERO_LOW
        else:
            num, den = y.as_integer_ratio()
            low = (num & -num).bit_length() - 1
            my, ey = num >> low, low - (den.bit_length() - 1)
        e = ex if ex < ey else ey
        if e == ZERO_LOW:
            e = 0
        self._exact.append((mx << (ex - e) if mx else 0, my << (ey - e) if my else 0, e))
        xy = self._xy
        xy.append((x, y))
        shift = self._shift
        ok = (x == 0.0 or (ex + shift >= GRAIN_MIN and math.frexp(x)[1] + shift <= TOP_MAX)) and (
            y == 0.0 or (ey + shift >= GRAIN_MIN and math.frexp(y)[1] + shift <= TOP_MAX)
        )
        self._rows.append((math.ldexp(x, shift), math.ldexp(y, shift)) if ok else _NAN)
        self._array = None
        return len(xy) - 1

    @property
    def points(self) -> NDArray[np.float64]:
        """All points as an ``(n, 2)`` float64 array (read-only; rebuilt when the set has grown). O(n)."""
        if self._array is None or self._array.shape[0] != len(self._xy):
            arr = np.array(self._xy, dtype=np.float64).reshape(-1, 2)
            arr.setflags(write=False)
            self._array = arr
        return self._array

    @property
    def filter_rows(self) -> list[tuple[float, float]]:
        """The filter's copy of the points, ``(x · 2^shift, y · 2^shift)`` exactly, or ``(nan, nan)`` for a point
        the proved filters cannot take (module docstring).  The list itself, which :meth:`append` extends: a caller
        that inlines a filter over it (the refinement's quality and conflict tests) must read it, never write it,
        and must decide exactly whenever a comparison involves a NaN. O(1)."""
        return self._rows

    def filter_columns(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """:attr:`filter_rows` as two float64 columns ``(x · 2^shift, y · 2^shift)``, NaN where a row is, for a
        vectorised filter over many tests at once (a new pair of arrays each call; the caller may keep them while
        the set does not grow). O(n)."""
        arr = np.array(self._rows, dtype=np.float64).reshape(-1, 2)
        return arr[:, 0], arr[:, 1]

    @property
    def shift(self) -> int:
        """The filter's fixed power-of-two scale: :attr:`filter_rows` are the points times ``2^shift``. O(1)."""
        return self._shift

    def xy(self, i: int) -> tuple[float, float]:
        """Point ``i`` as a pair of floats. O(1)."""
        return self._xy[i]

    def same(self, i: int, j: int) -> bool:
        """Whether points ``i`` and ``j`` are exactly equal. O(1)."""
        return self._xy[i] == self._xy[j]

    def same_as_any(self, i: int, others: tuple[int, ...]) -> int | None:
        """The first of the points ``others`` exactly equal to point ``i``, or None. O(len(others))."""
        xy = self._xy
        q = xy[i]
        for j in others:
            if xy[j] == q:
                return j
        return None

    def integers(self, *indices: int) -> tuple[list[tuple[int, int]], int]:
        """The points ``indices`` as exact integer pairs at their least common exponent ``E``: ``(pairs, E)``.

        Point ``i`` is ``pairs[k] · 2^E`` exactly.  O(bits).
        """
        if len(indices) == 3:
            # The common case (a triangle, an orientation), written out: the same pairs.
            ex = self._exact
            xa, ya, ea = ex[indices[0]]
            xb, yb, eb = ex[indices[1]]
            xc, yc, ec = ex[indices[2]]
            e = ea if ea < eb else eb
            if ec < e:
                e = ec
            return [
                (xa, ya) if ea == e else (xa << (ea - e), ya << (ea - e)),
                (xb, yb) if eb == e else (xb << (eb - e), yb << (eb - e)),
                (xc, yc) if ec == e else (xc << (ec - e), yc << (ec - e)),
            ], e
        parts = list(map(self._exact.__getitem__, indices))  # no comprehension: no function frame per call
        e = parts[0][2]
        for part in parts:
            if part[2] < e:
                e = part[2]
        pairs: list[tuple[int, int]] = []
        for x, y, pe in parts:
            pairs.append((x, y) if pe == e else (x << (pe - e), y << (pe - e)))
        return pairs, e

    # -- counting ------------------------------------------------------------------------

    def _count(self, failed: bool) -> None:
        st = self.stats
        if st is not None:
            st.plane_side_tests += 1
            if failed:
                st.filter_failures += 1

    # -- orient2d ------------------------------------------------------------------------

    def orient2d(self, a: int, b: int, c: int) -> int:
        """±1: the SoS sign of ``det[[a, 1], [b, 1], [c, 1]]`` (+1: counterclockwise), as ``Predicates2.orient2d``. O(1)."""
        s = self.orient2d_sign(a, b, c)
        if s:
            return s
        order, parity = sort_with_parity((a, b, c))
        pts, _ = self.integers(*order)
        return parity * sos_orient2d(*pts)

    def orient2d_sign(self, a: int, b: int, c: int) -> int:
        """The true sign of the orient2d determinant: -1, 0 or +1. O(1)."""
        rows = self._rows
        ax, ay = rows[a]
        bx, by = rows[b]
        cx, cy = rows[c]
        # orient2d_terms(ax, ay, bx, by, cx, cy), operation for operation (its proved bound holds); counted only
        # when a Stats is attached.
        acx = ax - cx
        bcx = bx - cx
        acy = ay - cy
        bcy = by - cy
        detleft = acx * bcy
        detright = acy * bcx
        det = detleft - detright
        thr = ERRBOUND_ORIENT2D * (abs(detleft) + abs(detright))
        if det > thr:
            if self.stats is not None:
                self._count(False)
            return 1
        if det < -thr:
            if self.stats is not None:
                self._count(False)
            return -1
        self._count(True)
        (pa, pb, pc), _ = self.integers(a, b, c)
        return _sign(orient2d_det(*pa, *pb, *pc))

    # -- incircle ------------------------------------------------------------------------

    def incircle(self, a: int, b: int, c: int, d: int) -> int:
        """±1: the SoS sign of the lifted orientation (+1: ``d`` inside the circle through ccw ``a, b, c``). O(1).

        Exact zeros are broken as ``Predicates2.incircle`` breaks them (Λ4 on the
        lifted points, the lift perturbed as an independent coordinate), so the
        two predicates see one perturbed point set.
        """
        s = self.incircle_sign(a, b, c, d)
        if s:
            return s
        order, parity = sort_with_parity((a, b, c, d))
        pts, _ = self.integers(*order)
        return parity * sos_orient3d(*((x, y, x * x + y * y) for x, y in pts))

    def incircle_sign(self, a: int, b: int, c: int, d: int) -> int:
        """The true sign of the incircle determinant: -1, 0 (cocircular) or +1. O(1)."""
        rows = self._rows
        ax, ay = rows[a]
        bx, by = rows[b]
        cx, cy = rows[c]
        dx, dy = rows[d]
        # incircle_terms(ax, ay, bx, by, cx, cy, dx, dy), operation for operation (its proved bound holds).
        adx = ax - dx
        bdx = bx - dx
        cdx = cx - dx
        ady = ay - dy
        bdy = by - dy
        cdy = cy - dy
        bdxcdy = bdx * cdy
        cdxbdy = cdx * bdy
        alift = adx * adx + ady * ady
        cdxady = cdx * ady
        adxcdy = adx * cdy
        blift = bdx * bdx + bdy * bdy
        adxbdy = adx * bdy
        bdxady = bdx * ady
        clift = cdx * cdx + cdy * cdy
        det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady)
        thr = ERRBOUND_INCIRCLE * (
            (abs(bdxcdy) + abs(cdxbdy)) * alift + (abs(cdxady) + abs(adxcdy)) * blift + (abs(adxbdy) + abs(bdxady)) * clift
        )
        if det > thr:
            if self.stats is not None:
                self._count(False)
            return 1
        if det < -thr:
            if self.stats is not None:
                self._count(False)
            return -1
        self._count(True)
        (pa, pb, pc, pd), _ = self.integers(a, b, c, d)
        return _sign(incircle_det(*pa, *pb, *pc, *pd))

    # -- encroachment --------------------------------------------------------------------

    def dot_sign(self, a: int, b: int, p: int) -> int:
        """The exact sign of ``(a − p) · (b − p)``: -1 iff ``p`` lies strictly inside the circle with diameter ``ab``. O(1).

        0: ``p`` on that circle (or equal to ``a`` or ``b``); +1 outside.
        """
        rows = self._rows
        ax, ay = rows[a]
        bx, by = rows[b]
        px, py = rows[p]
        # dot_terms(ax, ay, bx, by, px, py), operation for operation (its proved bound holds).
        apx = ax - px
        bpx = bx - px
        apy = ay - py
        bpy = by - py
        left = apx * bpx
        right = apy * bpy
        det = left + right
        thr = ERRBOUND_DOT * (abs(left) + abs(right))
        if det > thr:
            if self.stats is not None:
                self._count(False)
            return 1
        if det < -thr:
            if self.stats is not None:
                self._count(False)
            return -1
        self._count(True)
        ((iax, iay), (ibx, iby), (ipx, ipy)), _ = self.integers(a, b, p)
        return _sign((iax - ipx) * (ibx - ipx) + (iay - ipy) * (iby - ipy))

    def between(self, u: int, w: int, p: int) -> bool:
        """Whether ``p``, known to lie on the line ``uw``, lies strictly between ``u`` and ``w`` (exact comparisons). O(1)."""
        (ux, uy), (wx, wy), (px, py) = self._xy[u], self._xy[w], self._xy[p]
        if ux != wx:
            return min(ux, wx) < px < max(ux, wx)
        return min(uy, wy) < py < max(uy, wy)

