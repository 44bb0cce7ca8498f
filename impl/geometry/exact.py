"""Exact arithmetic on doubles: every finite double is an integer times a power of two.

A finite double is ``m · 2^e`` with an integer ``m``.  Over a set of doubles,
let ``E`` be the smallest exponent of a lowest set bit (the smallest *grain*,
:func:`binary_exponents`); then every one of them times ``2^-E`` is an exact
integer.  Orientation signs are invariant under this common positive scaling
(each determinant and each minor of it is homogeneous of positive degree), so
the predicates are decided exactly on Python integers, with no rounding and no
epsilon.  :class:`IntegerScale` performs the conversion, point by point when a
test needs it (:meth:`IntegerScale.to_int`) or for many points at once on numpy
object arrays (:meth:`IntegerScale.to_ints`).

The determinant expressions below are written once, generically over any ring
(Python ints, object arrays of ints), so the scalar and the vectorised exact
paths evaluate the same formula.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final, Protocol, Self, TypeVar

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "ZERO_LOW",
    "Ring",
    "binary_exponents",
    "grain_span",
    "IntegerScale",
    "orient2d_det",
    "orient3d_det",
    "incircle_det",
]

ZERO_LOW: Final[int] = 1 << 20
"""The grain reported for 0 (a multiple of every power of two): larger than any real grain."""

_MANTISSA: Final[float] = 2.0**53


class Ring(Protocol):
    """Numbers with exact ``+``, ``-``, ``×``: Python ints, numpy object arrays of ints."""

    def __add__(self, other: Self, /) -> Self: ...

    def __sub__(self, other: Self, /) -> Self: ...

    def __mul__(self, other: Self, /) -> Self: ...


R = TypeVar("R", bound=Ring)


def binary_exponents(values: NDArray[np.float64]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """``(low, high)`` elementwise: ``x = odd · 2^low`` and ``2^(high-1) <= |x| < 2^high``.

    ``low`` is the *grain* of ``x``.  For ``x = 0``, ``low`` is :data:`ZERO_LOW`
    and ``high`` is ``-ZERO_LOW``.  Exact for every finite double, subnormals
    included (``frexp`` normalises them).  O(size), vectorised.
    """
    frac, exp = np.frexp(values)
    mant = (frac * _MANTISSA).astype(np.int64)  # exact: 53 significant bits at most
    lowest_bit = mant & -mant  # 2^t, the lowest set bit of |mant| (0 for 0)
    _, tz = np.frexp(lowest_bit.astype(np.float64))  # 2^t = 0.5 · 2^(t+1)
    exp64 = exp.astype(np.int64)
    zero = mant == 0
    low = np.where(zero, ZERO_LOW, exp64 - 53 + tz.astype(np.int64) - 1)
    high = np.where(zero, -ZERO_LOW, exp64)
    return low.astype(np.int64, copy=False), high.astype(np.int64, copy=False)


def grain_span(values: NDArray[np.float64]) -> tuple[int, int] | None:
    """``(least low, greatest high)`` of :func:`binary_exponents` over the nonzero entries, or None if all are 0.

    The two extremes without the per-entry arrays.  Let ``e`` be the least
    ``frexp`` exponent of a nonzero entry; every nonzero entry is an integer
    multiple of ``2^(e - 53)`` (a 53-bit significand at an exponent ``>= e``),
    and the least grain is ``e - 53`` plus the fewest trailing zero bits among
    these quotients: the trailing zeros of their bitwise OR.  Only each
    quotient's residue modulo ``2^53`` matters for that, and an entry of
    exponent ``e`` has a nonzero residue (its quotient is its significand,
    below ``2^53``), so the OR of the residues decides.  The quotients are exact
    (``ldexp`` by a power of two) and so are the residues; if the
    quotients could overflow (entries spanning some 970 binades) the
    per-entry :func:`binary_exponents` decides instead.  O(size), about half
    the vectorised passes of :func:`binary_exponents`.
    """
    flat = np.asarray(values, dtype=np.float64).ravel()
    # The frexp exponent grows with the magnitude, so the least and greatest exponents of the nonzero entries
    # are those of the least nonzero and the greatest magnitude: three cheap passes, not frexp's (about 30
    # instructions an entry) and its masked reductions.
    mags = np.abs(flat)
    if not mags.size:
        return None
    greatest = float(mags.max())
    if greatest == 0:
        return None
    least = float(mags.min())
    if least == 0:
        least = float(mags.min(where=mags != 0, initial=math.inf))
    e = math.frexp(least)[1]
    h = math.frexp(greatest)[1]
    shift = 53 - e
    if h + shift > 1024:  # a quotient could reach 2^1024: decide entry by entry
        low, high = binary_exponents(flat[flat != 0])
        return int(low.min()), int(high.max())
    # Each product is an integer below 2^1024, so multiplying by 2^shift is exact, and it costs a fraction
    # of ldexp's per-entry work (about 48 instructions an entry); 2^shift must itself be a normal double.
    residues = flat * (2.0**shift) if -1022 <= shift <= 1023 else np.ldexp(flat, shift)
    # Each quotient minus its multiple of 2^53 toward zero: every step exact (powers of two, truncation,
    # and a difference that is an integer below 2^53).  np.fmod is exact too but ten times slower.
    above = residues * (1 / _MANTISSA)
    np.trunc(above, out=above)
    above *= _MANTISSA
    residues -= above
    bits = int(np.bitwise_or.reduce(residues.astype(np.int64)))
    return e - 53 + (bits & -bits).bit_length() - 1, h


@dataclass(frozen=True, slots=True)
class IntegerScale:
    """The common power-of-two scale ``2^-exponent`` that makes every coordinate an integer.

    ``exponent`` is the smallest grain over the coordinates (0 if they are all 0);
    ``extra`` multiplies every integer by a further ``2^extra`` (the exact
    centroid of four points needs ``extra = 2``: it is their sum at scale ×4).
    """

    exponent: int
    extra: int = 0

    @staticmethod
    def of(low: NDArray[np.int64], extra: int = 0) -> IntegerScale:
        """The scale for coordinates whose grains are ``low`` (:func:`binary_exponents`). O(n)."""
        real = low[low < ZERO_LOW]
        return IntegerScale(int(real.min()) if real.size else 0, extra)

    def to_int(self, x: float) -> int:
        """``x · 2^(extra - exponent)`` as an exact int (``x`` finite, grain ``>= exponent``). O(bits)."""
        num, den = x.as_integer_ratio()
        shift = self.extra - self.exponent - (den.bit_length() - 1)
        return num << shift if shift >= 0 else num >> -shift  # exact: 2^-shift divides num

    def to_ints(self, values: NDArray[np.float64]) -> NDArray[np.object_]:
        """:meth:`to_int` elementwise, as an object array of Python ints (same shape). O(size)."""
        frac, exp = np.frexp(values)
        mant = (frac * _MANTISSA).astype(np.int64).astype(object)
        shift = exp.astype(np.int64) - 53 + self.extra - self.exponent
        left = np.maximum(shift, 0).astype(object)
        right = np.maximum(-shift, 0).astype(object)
        out: NDArray[np.object_] = (mant << left) >> right
        return out


def orient2d_det(ax: R, ay: R, bx: R, by: R, cx: R, cy: R) -> R:
    """The exact orient2d determinant ``det[[ax, ay, 1], [bx, by, 1], [cx, cy, 1]]``. O(1)."""
    return (ax - cx) * (by - cy) - (ay - cy) * (bx - cx)


def orient3d_det(ax: R, ay: R, az: R, bx: R, by: R, bz: R, cx: R, cy: R, cz: R, dx: R, dy: R, dz: R) -> R:
    """The exact orient3d determinant: rows ``(x, y, z, 1)`` of ``a, b, c, d``. O(1)."""
    adx = ax - dx
    bdx = bx - dx
    cdx = cx - dx
    ady = ay - dy
    bdy = by - dy
    cdy = cy - dy
    adz = az - dz
    bdz = bz - dz
    cdz = cz - dz
    return (
        adz * (bdx * cdy - cdx * bdy)
        + bdz * (cdx * ady - adx * cdy)
        + cdz * (adx * bdy - bdx * ady)
    )


def incircle_det(ax: R, ay: R, bx: R, by: R, cx: R, cy: R, dx: R, dy: R) -> R:
    """The exact incircle determinant: rows ``(x, y, x² + y², 1)`` of ``a, b, c, d``. O(1)."""
    adx = ax - dx
    bdx = bx - dx
    cdx = cx - dx
    ady = ay - dy
    bdy = by - dy
    cdy = cy - dy
    alift = adx * adx + ady * ady
    blift = bdx * bdx + bdy * bdy
    clift = cdx * cdx + cdy * cdy
    return (
        alift * (bdx * cdy - cdx * bdy)
        + blift * (cdx * ady - adx * cdy)
        + clift * (adx * bdy - bdx * ady)
    )
