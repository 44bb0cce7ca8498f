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
the mesh checker (:mod:`~persistri.impl.mesh.verify`) for Ruppert's angle bound, with
:func:`below_bound` (every triangle at once: a float filter, exact where it cannot
tell) and :func:`subtends_small_input_angle` (Ruppert's exemption).
"""

from __future__ import annotations

import functools
import math
from fractions import Fraction

import numpy as np
from numpy.typing import NDArray

__all__ = ["cos2_bounds", "angle_at_least", "EXACT_COS2", "smallest_corner", "below_bound", "subtends_small_input_angle"]

COS_MARGIN = 1e-9
"""The float filter's margin on a cosine: computed from rounded differences, products and a
square root, its error is below 1e-14 for coordinates whose squares neither overflow nor
underflow (the filter checks that), so a cosine farther than this from ``cos θ`` is decided."""

EXACT_COS2: dict[float, Fraction] = {
    0.0: Fraction(1),
    30.0: Fraction(3, 4),
    45.0: Fraction(1, 2),
    60.0: Fraction(1, 4),
    90.0: Fraction(0),
}
"""The bounds (degrees) whose squared cosine is rational, and its value."""

_EXACT_RATIO: dict[float, tuple[int, int]] = {t: (c.numerator, c.denominator) for t, c in EXACT_COS2.items()}
""":data:`EXACT_COS2` as ``(numerator, denominator)`` pairs of ints (no ``Fraction`` property per test)."""


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
    exact = _EXACT_RATIO.get(theta)
    if exact is not None:
        # A rational cos²θ = n / d (60°: the small-angle tests): one comparison of integers.
        return lhs * exact[1] <= exact[0] * rhs
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


def smallest_corner(xs: list[int], ys: list[int], triangle: NDArray[np.intp]) -> int:
    """The corner (0, 1 or 2) opposite the shortest edge — the smallest angle's — from exact squared lengths. O(1)."""
    a, b, c = (int(v) for v in triangle)

    def length2(p: int, q: int) -> int:
        return (xs[p] - xs[q]) ** 2 + (ys[p] - ys[q]) ** 2

    lengths = [length2(b, c), length2(c, a), length2(a, b)]
    return lengths.index(min(lengths))


def below_bound(pts: NDArray[np.float64], tri: NDArray[np.intp], xs: list[int], ys: list[int], theta: float) -> list[int]:
    """The triangles whose smallest angle is below ``θ`` degrees, exactly.

    A vectorised float filter decides every triangle whose smallest angle's cosine
    is farther than :data:`COS_MARGIN` from ``cos θ``; :func:`angle_at_least` on the
    exact integer coordinates ``xs``, ``ys`` decides the rest. O(t).
    """
    P = pts[tri]
    with np.errstate(all="ignore"):
        e = np.stack([P[:, 2] - P[:, 1], P[:, 0] - P[:, 2], P[:, 1] - P[:, 0]], axis=1)  # edge opposite corner i
        l2 = np.einsum("ijk,ijk->ij", e, e)
        corner = np.argmin(l2, axis=1)
        rows = np.arange(tri.shape[0])
        u = -e[rows, (corner + 2) % 3]  # from the corner to the next vertex
        v = e[rows, (corner + 1) % 3]  # from the corner to the previous vertex
        nu, nv = np.einsum("ij,ij->i", u, u), np.einsum("ij,ij->i", v, v)
        cos = np.einsum("ij,ij->i", u, v) / np.sqrt(nu * nv)
        c = math.cos(math.radians(theta))
        sure = np.isfinite(cos) & (nu > 1e-280) & (nv > 1e-280) & np.isfinite(nu * nv)
        fine = sure & (cos < c - COS_MARGIN)
        below = sure & (cos > c + COS_MARGIN)
    out = np.flatnonzero(below).tolist()
    for k in np.flatnonzero(~fine & ~below).tolist():
        i = smallest_corner(xs, ys, tri[k])
        o, p, q = (int(tri[k, (i + j) % 3]) for j in range(3))
        ux, uy, vx, vy = xs[p] - xs[o], ys[p] - ys[o], xs[q] - xs[o], ys[q] - ys[o]
        if not angle_at_least(ux * vx + uy * vy, ux * ux + uy * uy, vx * vx + vy * vy, theta):
            out.append(k)
    return sorted(out)


def subtends_small_input_angle(
    p: int, q: int, on_segments: dict[int, list[int]], ends: list[tuple[int, int]], xs: list[int], ys: list[int]
) -> bool:
    """Ruppert's exemption: whether the edge ``p–q`` joins two distinct segments meeting below 60°.

    ``on_segments[w]``: the segments mesh vertex ``w`` lies on; ``ends[s]``: segment
    ``s``'s end vertices (mesh indices).  True when ``p`` is on a segment and ``q`` on
    another that share an end ``o`` (neither ``p`` nor ``q``) where they meet at an
    angle below 60°: ``u · v > 0`` and ``4 (u · v)² > |u|² |v|²`` (cos² > 1/4), exact.
    The rule of Miller, Pav and Walkington as Triangle applies it, without Triangle's
    equal-distance (concentric shell) condition. O(segments at p × segments at q).
    """
    for s1 in on_segments.get(p, []):
        for s2 in on_segments.get(q, []):
            if s1 == s2:
                continue
            ends1, ends2 = set(ends[s1]), set(ends[s2])
            for o in ends1 & ends2:
                if o in (p, q):
                    continue
                (f1,), (f2,) = ends1 - {o}, ends2 - {o}
                ux, uy, vx, vy = xs[f1] - xs[o], ys[f1] - ys[o], xs[f2] - xs[o], ys[f2] - ys[o]
                dot = ux * vx + uy * vy
                if dot > 0 and 4 * dot * dot > (ux * ux + uy * uy) * (vx * vx + vy * vy):
                    return True
    return False
