"""Triangle quality, decided exactly: the smallest angle against a bound, and the area against a bound.

Delaunay refinement (:mod:`persistri.impl.mesh.ruppert`) splits a triangle whose
smallest angle is below ``min_angle`` or whose area exceeds ``max_area``.  Both
tests are exact here, on the integer coordinates of the predicates
(:meth:`~persistri.impl.geometry.growing.GrowingPredicates2.integers`), so a mesh
reported as meeting its bounds meets them — no epsilon.

**The angle.**  The smallest angle of a triangle is the one opposite its
shortest edge (law of sines).  At vertex ``r`` opposite the edge ``pq``, with
``d = p − r`` and ``e = q − r``, ``A >= θ`` exactly when ``d·e <= 0`` or
``(d·e)² <= cos²θ · |d|² |e|²`` (``proofs/proof_mesh.py``): squared cosines of
exact integers, decided by :func:`~persistri.impl.mesh.angles.angle_at_least`,
which brackets the irrational ``cos²θ`` between rationals and narrows the
bracket until it decides — the same exact test as the mesh checker's.

**The area.**  Twice the area is the orient2d determinant: ``area > max_area``
is decided on integers, ``max_area`` being a double (an exact rational).

**The float stage** (:class:`~persistri.impl.mesh.quality_filter.QualityTests`, what
the refinement calls for every new triangle; its constants are here, with those of
:func:`at_least`'s and :func:`equidistant`'s own float stages): the same tests on the
predicates' filter copy of the points
(:attr:`~persistri.impl.geometry.growing.GrowingPredicates2.filter_rows`, the
doubles times a power of two), each with a proved error bound, and the exact test
above whenever the float result is not clear of the bound by that margin (or a
point has no filter copy).  The answers are the exact ones; the float stage only
makes the common case cheap.  The arguments are in ``QualityTests``' docstring
(``proofs/proof_mesh.py`` checks the constants), and the tests compare both stages
on random and adversarial inputs.

Costs: O(1) big-integer operations per triangle (the bracket of ``cos²θ`` is
computed once per bound and cached); O(1) float operations when the float stage decides.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Final

from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.angles import EXACT_COS2, angle_at_least, cos2_bounds

__all__ = [
    "AngleBound",
    "Shape",
    "shape",
    "area_exceeds",
    "twice_area",
    "inside_lens",
    "at_least",
    "equidistant",
]

_MARGIN = 1e-9
"""The float stage of :func:`at_least` decides only outside ``cos²θ · (1 ± _MARGIN)``."""


@functools.lru_cache(maxsize=64)
def _cos2(theta: float) -> tuple[float, float]:
    """Floats ``lo <= cos²θ <= hi``: a rational enclosure of :func:`~persistri.impl.mesh.angles.cos2_bounds`, rounded
    outward.  56 bits: the floats need no more, and it costs a millisecond where the 128 of the exact test cost 20."""
    lo, hi = cos2_bounds(theta, 56)
    return math.nextafter(float(lo), -math.inf), math.nextafter(float(hi), math.inf)


def at_least(dot: int, norm_u: int, norm_v: int, theta: float) -> bool:
    """:func:`~persistri.impl.mesh.angles.angle_at_least`, with a float stage first: exact, and fast when far from ``θ``.

    For ``dot > 0`` the float quotient ``q = fl(dot² / (|u|² |v|²))`` has relative
    error below ``2^-49`` (three conversions of exact integers and three
    operations, each within ``2^-53``; no overflow or underflow, checked), and
    ``cos²θ`` lies between two floats from its rational enclosure rounded outward;
    the margin ``1e-9`` dwarfs the quotient's error, so ``q`` below ``lo · (1 − 1e-9)``
    proves the angle above ``θ`` and ``q`` above ``hi · (1 + 1e-9)`` proves it below.
    Between them, the exact test decides.  O(1).
    """
    if theta <= 0.0 or dot <= 0:
        return True
    try:
        q = (float(dot) * float(dot)) / (float(norm_u) * float(norm_v))
    except (OverflowError, ZeroDivisionError):
        return angle_at_least(dot, norm_u, norm_v, theta)
    if 1e-300 < q < 1e300:
        lo, hi = _cos2(theta)
        if q < lo * (1.0 - _MARGIN):
            return True
        if q > hi * (1.0 + _MARGIN):
            return False
    return angle_at_least(dot, norm_u, norm_v, theta)


@dataclass(frozen=True, slots=True)
class AngleBound:
    """A minimum-angle bound in degrees: ``AngleBound.of(θ)`` for ``0 <= θ < 60`` (no triangle has a
    smallest angle above 60°); ``θ = 0`` means no bound."""

    degrees: float

    @staticmethod
    def of(degrees: float) -> AngleBound:
        """The bound for ``degrees`` (validated: a real in ``[0, 60)``). O(1)."""
        if isinstance(degrees, bool) or not isinstance(degrees, (int, float)):
            raise TypeError(f"min_angle must be a real number of degrees, not {type(degrees).__name__}")
        d = float(degrees)
        if not 0.0 <= d < 60.0:
            raise ValueError(
                f"min_angle must be within [0, 60) degrees (no triangle has a smallest angle above 60), got {degrees!r}"
            )
        return AngleBound(d)


@dataclass(frozen=True, slots=True)
class Shape:
    """A triangle's shortest edge and smallest angle, exactly.

    ``(p, q, r)`` is the triangle rotated (orientation kept) so that ``pq`` is its
    shortest edge and ``r`` the vertex of its smallest angle; ``edge2`` is
    ``|pq|²`` as a float (the queue key); ``good_angle`` whether that angle is at
    least the bound.
    """

    p: int
    q: int
    r: int
    edge2: float
    good_angle: bool


def shape(P: GrowingPredicates2, a: int, b: int, c: int, bound: AngleBound) -> Shape:
    """The :class:`Shape` of triangle ``(a, b, c)`` against ``bound`` (module docstring). O(1) exact."""
    (pa, pb, pc), e = P.integers(a, b, c)
    lab = (pa[0] - pb[0]) ** 2 + (pa[1] - pb[1]) ** 2
    lbc = (pb[0] - pc[0]) ** 2 + (pb[1] - pc[1]) ** 2
    lca = (pc[0] - pa[0]) ** 2 + (pc[1] - pa[1]) ** 2
    if lab <= lbc and lab <= lca:
        p, q, r, pp, pq, pr, short, d2, e2 = a, b, c, pa, pb, pc, lab, lca, lbc
    elif lbc <= lca:
        p, q, r, pp, pq, pr, short, d2, e2 = b, c, a, pb, pc, pa, lbc, lab, lca
    else:
        p, q, r, pp, pq, pr, short, d2, e2 = c, a, b, pc, pa, pb, lca, lbc, lab
    if bound.degrees == 0.0:
        good = True
    else:
        dot = (pp[0] - pr[0]) * (pq[0] - pr[0]) + (pp[1] - pr[1]) * (pq[1] - pr[1])
        good = at_least(dot, d2, e2, bound.degrees)
    return Shape(p, q, r, _scaled_float(short, 2 * e), good)


def _scaled_float(v: int, e: int) -> float:
    """``v · 2^e`` as a float, nearly (a queue key only; inf on overflow)."""
    try:
        return math.ldexp(float(v), e)
    except OverflowError:
        return math.inf


def twice_area(P: GrowingPredicates2, a: int, b: int, c: int) -> Fraction:
    """Twice the signed area of ``(a, b, c)``, exactly (positive when counterclockwise). O(1)."""
    (pa, pb, pc), e = P.integers(a, b, c)
    det = (pa[0] - pc[0]) * (pb[1] - pc[1]) - (pa[1] - pc[1]) * (pb[0] - pc[0])
    return Fraction(det) * Fraction(2) ** (2 * e)


def area_exceeds(P: GrowingPredicates2, a: int, b: int, c: int, max_area: Fraction) -> bool:
    """Whether the area of counterclockwise ``(a, b, c)`` is strictly above ``max_area`` (exact). O(1)."""
    (pa, pb, pc), e = P.integers(a, b, c)
    det = (pa[0] - pc[0]) * (pb[1] - pc[1]) - (pa[1] - pc[1]) * (pb[0] - pc[0])
    # area = det · 2^(2e) / 2 > max_area = n / d  ⇔  det · 2^(2e) · d > 2 n
    num, den = max_area.numerator, max_area.denominator
    if e >= 0:
        return (det << (2 * e)) * den > 2 * num
    return det * den > (2 * num) << (-2 * e)


def inside_lens(P: GrowingPredicates2, u: int, w: int, x: int, min_angle: float) -> bool:
    """Whether ``x`` lies in the diametral *lens* of the segment ``uw`` for the bound ``min_angle`` (Chew; Triangle's default).

    The lens is the part of the diametral circle where the angle ``u x w`` is at
    least ``180° − 2θ``: the region from which ``x`` would make, with ``uw``, a
    triangle whose two base angles are below ``θ``.  For ``θ >= 45°`` or ``θ = 0`` it
    is the diametral circle itself (strictly inside: ``(u − x)·(w − x) < 0``).
    Exactly: with ``a = u − x``, ``b = w − x`` and ``a·b < 0``, the supplementary
    angle ``B = 180° − ∠uxw`` has ``cos B = −a·b / (|a| |b|) > 0``, and ``∠uxw >=
    180° − 2θ`` iff ``B <= 2θ`` — the negation of ``B > 2θ``, decided by
    :func:`~persistri.impl.mesh.angles.angle_at_least` (and exact equality when
    ``cos² 2θ`` is rational).  O(1).
    """
    if P.dot_sign(u, w, x) >= 0:
        return False
    if min_angle == 0.0 or min_angle >= 45.0:
        return True
    (pu, pw, px), _ = P.integers(u, w, x)
    ax, ay, bx, by = pu[0] - px[0], pu[1] - px[1], pw[0] - px[0], pw[1] - px[1]
    dot_b = -(ax * bx + ay * by)
    na, nb = ax * ax + ay * ay, bx * bx + by * by
    phi = 2.0 * min_angle
    if not at_least(dot_b, na, nb, phi):
        return True  # B < 2θ
    exact = EXACT_COS2.get(phi)
    return exact is not None and dot_b * dot_b * exact.denominator == exact.numerator * na * nb  # B == 2θ


# The float stage's constants of QualityTests (persistri.impl.mesh.quality_filter), checked in proofs/proof_mesh.py.

_SEPARATE: Final[float] = 1.0 - 2.0**-40
"""A float squared length below another times this is certainly the smaller (each is within 4.01u of its value)."""

_SLACK: Final[float] = 2.0**-40
"""Relative slack on the area threshold (covers the roundings of the threshold's own sum and product)."""

_LENS_MARGIN: Final[float] = 1e-9
"""Absolute margin on a cosine in the float lens test (its error is below 2e-15)."""

def equidistant(P: GrowingPredicates2, o: int, p: int, q: int) -> bool:
    """Triangle's equal-distance test (``testtriangle()``, Miller–Pav–Walkington's exemption): whether the squared
    distances ``dp = |p − o|²`` and ``dq = |q − o|²`` satisfy ``999 dq < 1000 dp < 1001 dq``.  Exact. O(1).

    **Float stage**, on the predicates' filter copy (the setting of
    :class:`~persistri.impl.mesh.quality_filter.QualityTests`: the model ``fl(x ∘ y) = (x ∘ y)(1 + δ)``,
    ``|δ| <= u = 2^-53``, holds there): the computed squared lengths ``Dp``, ``Dq`` are within
    ``4.01u`` of the exact ones, relatively (``QualityTests``), and ``fl(k · D)`` for ``k`` in {999, 1000, 1001}
    adds one rounding, so each side of either comparison is within ``(1 + u)^5 − 1 < 5.1u`` of its exact value,
    relatively (squares below ``2^502`` and above ``2^-480`` on the filter copy: no overflow, no subnormal).
    ``L < fl(R · (1 − 2^-40))`` for the computed sides then proves ``L < R`` for the exact ones, since ``(1 − 2^-40)
    (1 + u) (1 + 5.1u) / (1 − 5.1u) < 1``, and ``L > fl(R · (1 + 2^-40))`` proves ``L > R`` likewise; both
    comparisons proved true decide, one proved false decides, anything else (a near tie, a point without a filter
    copy: NaN compares false) is decided on integers.
    """
    rows = P.filter_rows
    ox, oy = rows[o]
    px, py = rows[p]
    qx, qy = rows[q]
    dpx, dpy, dqx, dqy = px - ox, py - oy, qx - ox, qy - oy
    dp = dpx * dpx + dpy * dpy
    dq = dqx * dqx + dqy * dqy
    upper = 1000.0 * dp  # the middle term
    low, high = 999.0 * dq, 1001.0 * dq
    if upper > high * _WIDE or low > upper * _WIDE:
        return False  # 1000 dp >= 1001 dq, or 999 dq >= 1000 dp
    if low < upper * _NARROW and upper < high * _NARROW:
        return True
    (io, ip, iq), _ = P.integers(o, p, q)
    ep = (ip[0] - io[0]) ** 2 + (ip[1] - io[1]) ** 2
    eq = (iq[0] - io[0]) ** 2 + (iq[1] - io[1]) ** 2
    return 999 * eq < 1000 * ep < 1001 * eq


_NARROW: Final[float] = 1.0 - 2.0**-40
"""``L < R · _NARROW`` on :func:`equidistant`'s computed sides proves ``L < R`` exactly."""

_WIDE: Final[float] = 1.0 + 2.0**-40
"""``L > R · _WIDE`` on :func:`equidistant`'s computed sides proves ``L > R`` exactly."""
