"""Exact comparison of a triangle's angle with a bound in degrees: squared cosines, no ``acos``.

An angle ``A`` at a vertex with edge vectors ``u`` and ``v`` (exact integers)
is at least ``θ`` (``0 < θ <= 90°``) exactly when ``u · v <= 0`` or
``(u · v)² <= cos²θ · |u|² |v|²``: the cosine decreases on ``[0°, 180°]``.  The
left side is an integer; ``cos²θ`` is rational only for ``θ`` in {30°, 45°,
60°, 90°} among the rational angles in degrees (Niven's theorem, since
``cos²θ = (1 + cos 2θ) / 2``), and a float bound is a rational number of
degrees.  So for every other bound the two sides are never equal, and
:func:`angle_at_least` brackets ``cos²θ`` between rationals
(:func:`cos2_bounds`) and narrows the bracket until it decides.

The bracket is rigorous: π from Machin's formula ``π = 16 atan(1/5) - 4
atan(1/239)`` and ``cos`` from its Taylor series, both alternating series whose
terms shrink, so each partial sum is within the first omitted term of the
limit.  ``proofs``-style cross-checks against sympy live in the tests.  Used by
the mesh checker (:mod:`~persistri.impl.mesh.verify`) for Ruppert's angle bound.
"""

from __future__ import annotations

import functools
import math
from fractions import Fraction

__all__ = ["cos2_bounds", "angle_at_least", "EXACT_COS2"]

EXACT_COS2: dict[float, Fraction] = {
    0.0: Fraction(1),
    30.0: Fraction(3, 4),
    45.0: Fraction(1, 2),
    60.0: Fraction(1, 4),
    90.0: Fraction(0),
}
"""The bounds (degrees) whose squared cosine is rational, and its value."""


def _atan_inv(k: int, terms: int) -> tuple[Fraction, Fraction]:
    """Rational bounds on ``atan(1/k)`` (k >= 2) from ``terms`` terms of its alternating series."""
    total = Fraction(0)
    k2 = k * k
    power = k  # k^(2j+1)
    for j in range(terms):
        term = Fraction(1, (2 * j + 1) * power)
        total += term if j % 2 == 0 else -term
        power *= k2
    rest = Fraction(1, (2 * terms + 1) * power)
    return (total - rest, total) if terms % 2 == 1 else (total, total + rest)


@functools.lru_cache(maxsize=64)
def cos2_bounds(theta: float, bits: int = 128) -> tuple[Fraction, Fraction]:
    """Rationals ``lo <= cos²(θ°) <= hi`` with ``hi - lo`` below about ``2^-bits`` (equal for :data:`EXACT_COS2`).

    ``θ`` must be in ``[0, 90]``.  O(bits²) big-rational work, cached.
    """
    if not 0.0 <= theta <= 90.0:
        raise ValueError(f"an angle bound must be between 0 and 90 degrees, got {theta}")
    exact = EXACT_COS2.get(theta)
    if exact is not None:
        return exact, exact
    # atan(1/5) terms shrink by 25 each: bits / log2(25) terms, plus slack.
    a5_lo, a5_hi = _atan_inv(5, bits // 4 + 4)
    a239_lo, a239_hi = _atan_inv(239, bits // 15 + 4)
    pi_lo, pi_hi = 16 * a5_lo - 4 * a239_hi, 16 * a5_hi - 4 * a239_lo
    t = Fraction(theta)
    x_lo, x_hi = t * pi_lo / 180, t * pi_hi / 180
    c_lo = _cos_bounds(x_hi, bits)[0]
    c_hi = _cos_bounds(x_lo, bits)[1]
    c_lo = max(c_lo, Fraction(0))
    return c_lo * c_lo, min(c_hi, Fraction(1)) ** 2


def _cos_bounds(x: Fraction, bits: int) -> tuple[Fraction, Fraction]:
    """Rational bounds on ``cos x`` for ``0 <= x <= 2`` (its Taylor terms shrink from the second on)."""
    total = Fraction(0)
    term = Fraction(1)
    x2 = x * x
    j = 0
    limit = Fraction(1, 1 << (bits + 8))
    while True:
        total += term if j % 2 == 0 else -term
        j += 1
        term = term * x2 / ((2 * j - 1) * (2 * j))
        if j >= 2 and term < limit:
            break
    # The first omitted term bounds the remainder and carries its sign.
    return (total - term, total) if j % 2 == 1 else (total, total + term)


def angle_at_least(dot: int, norm_u: int, norm_v: int, theta: float) -> bool:
    """Whether the angle between ``u`` and ``v`` is at least ``θ`` degrees, exactly.

    ``dot = u · v``, ``norm_u = |u|²``, ``norm_v = |v|²`` as exact integers (both
    norms positive); ``0 <= θ <= 90``.  Narrows :func:`cos2_bounds` until it decides
    (always, for a bound whose ``cos²`` is irrational).  O(1) usually.
    """
    if theta <= 0.0 or dot <= 0:
        return True
    lhs = dot * dot
    rhs = norm_u * norm_v
    bits = 128
    while True:
        lo, hi = cos2_bounds(theta, bits)
        if lhs * lo.denominator <= lo.numerator * rhs:
            return True  # cos²A <= lo <= cos²θ
        if lhs * hi.denominator > hi.numerator * rhs:
            return False  # cos²A > hi >= cos²θ
        if lo == hi:  # pragma: no cover - an exact bound always decides above
            return True
        bits *= 2


def cos_bound(theta: float) -> float:
    """``cos θ`` in float for the checker's filter (error far below its 1e-9 margin)."""
    return math.cos(math.radians(theta))
