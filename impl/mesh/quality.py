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

**The float stage** (:class:`QualityTests`, what the refinement calls for every
new triangle): the same tests on the predicates' filter copy of the points
(:attr:`~persistri.impl.geometry.growing.GrowingPredicates2.filter_rows`, the
doubles times a power of two), each with a proved error bound, and the exact test
above whenever the float result is not clear of the bound by that margin (or a
point has no filter copy).  The answers are the exact ones; the float stage only
makes the common case cheap.  The arguments are in :class:`QualityTests`' docstring,
and the tests compare both stages on random and adversarial inputs.

Costs: O(1) big-integer operations per triangle (the bracket of ``cos²θ`` is
computed once per bound and cached); O(1) float operations when the float stage decides.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterable
from dataclasses import dataclass
from fractions import Fraction
from typing import Final, TypeVar

from persistri.impl.geometry.filter import ERRBOUND_ORIENT2D
from persistri.impl.geometry.growing import ERRBOUND_DOT, GrowingPredicates2
from persistri.impl.mesh.angles import EXACT_COS2, angle_at_least, cos2_bounds
from persistri.impl.mesh.datum import EXTERIOR, MeshDatum

__all__ = [
    "AngleBound",
    "Shape",
    "shape",
    "area_exceeds",
    "twice_area",
    "inside_lens",
    "at_least",
    "equidistant",
    "QualityTests",
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


_SEPARATE: Final[float] = 1.0 - 2.0**-40
"""A float squared length below another times this is certainly the smaller (each is within 4.01u of its value)."""

_SLACK: Final[float] = 2.0**-40
"""Relative slack on the area threshold (covers the roundings of the threshold's own sum and product)."""

_LENS_MARGIN: Final[float] = 1e-9
"""Absolute margin on a cosine in the float lens test (its error is below 2e-15)."""

def equidistant(P: GrowingPredicates2, o: int, p: int, q: int) -> bool:
    """Triangle's equal-distance test (``testtriangle()``, Miller–Pav–Walkington's exemption): whether the squared
    distances ``dp = |p − o|²`` and ``dq = |q − o|²`` satisfy ``999 dq < 1000 dp < 1001 dq``.  Exact. O(1).

    **Float stage**, on the predicates' filter copy (:class:`QualityTests`' setting: the model ``fl(x ∘ y) = (x ∘
    y)(1 + δ)``, ``|δ| <= u = 2^-53``, holds there): the computed squared lengths ``Dp``, ``Dq`` are within
    ``4.01u`` of the exact ones, relatively (:class:`QualityTests`), and ``fl(k · D)`` for ``k`` in {999, 1000, 1001}
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

BadShape = tuple[int, int, int, float, bool]
"""``(p, q, r, edge2, good_angle)`` as in :class:`Shape`: the triangle rotated to its shortest edge ``pq``."""

_T = TypeVar("_T", bound=tuple[int, int, int])


class QualityTests:
    """The quality and encroachment tests of one refinement, float stage first, exact when it cannot tell.

    ``QualityTests(P, bound, max_area, region_area, lens)``; :meth:`assess` judges a
    triangle (angle and area), :meth:`encroaches` a point against a subsegment.  Every
    answer equals the exact test's (:func:`shape`, :func:`area_exceeds`,
    :func:`inside_lens`, ``dot_sign``); the float stage decides when its result is
    clear of the bound by more than its proved error.  With ``u = 2^-53``, on the
    filter copy of the points (exact multiples of the doubles by ``2^shift``, whose
    grain and magnitude keep every product of degree at most 4 a normal number:
    the model ``fl(x ∘ y) = (x ∘ y)(1 + δ)``, ``|δ| <= u``, holds):

    * **squared lengths** ``fl(fl(dx²) + fl(dy²))`` of rounded differences are within
      ``(1 + u)^4 − 1 < 4.01u`` of the exact value, relatively (no cancellation:
      sums of squares).  A length below another times ``1 − 2^-40`` is therefore
      certainly the smaller; the *candidates* for the shortest edge are the edges
      not certainly longer than another — the shortest is among them, and the
      others are within a factor ``1 + 2^-39`` of it (two of them for the isosceles
      triangles a circumcentre makes);
    * **the smallest angle** is opposite the shortest edge, so it is at least ``θ``
      when the angle opposite every candidate is.  Such an angle is below 60° (or
      above it by a relative hair, for a near tie), so with ``d``, ``e`` its edge
      vectors ``d·e >= 0.49 |d||e| > 0``.  The computed dot product is within
      ``4.01u (|dx ex| + |dy ey|) <= 4.01u |d||e| <= 8.2u d·e`` of it
      (Cauchy–Schwarz), so the computed ``(d·e)² / (|d|²|e|²)`` is within about
      ``31u`` of the exact one, relatively — far inside :func:`at_least`'s margin
      ``1e-9`` around the float enclosure of ``cos²θ``: below it the angle is at
      least ``θ``; above it, with a unique candidate, the triangle's smallest
      angle is below ``θ``.  Anything else (a near tie with a bad or unclear
      angle) is decided exactly, and a bad triangle's shortest edge is always the
      exact one (the unique candidate, or :func:`shape`'s);
    * **twice the area** is orient2d's determinant, computed by
      :func:`~persistri.impl.geometry.filter.orient2d_terms` (the filter of the
      predicates).  ``proofs/proof_predicates.py`` proves that its value before the
      last rounding is within ``thr = fl(ERRBOUND_ORIENT2D · permanent)`` of the exact
      one; the last rounding and the threshold's own are covered by the slack
      ``2^-40``: ``det > (T + thr)(1 + 2^-40)`` proves ``det > T`` and ``det < (T −
      thr)(1 − 2^-40)`` proves ``det < T``, ``T`` twice the bound in filter units
      (``2 A · 4^shift``, exact);
    * **encroachment**: ``(u − x)·(w − x)`` by the same operations as
      :func:`~persistri.impl.geometry.growing.dot_terms`, whose constant
      ``ERRBOUND_DOT`` is proved in ``proofs/proof_mesh.py``: outside the diametral
      circle, or inside it, when clear of 0; for the lens, the cosine of the
      supplementary angle ``−(u − x)·(w − x) / sqrt(|u − x|² |w − x|²)`` is within
      ``2e-15`` of the exact one and is compared with ``cos 2θ`` (the square root of
      its float enclosure) with the margin ``1e-9``.

    A point without a filter copy makes every comparison false (NaN), which sends
    the test to the exact path.  O(1) per test.
    """

    __slots__ = ("P", "rows", "shift", "bound", "theta", "_lo", "_hi", "_area", "_lens", "_lens_lo", "_lens_hi")

    def __init__(
        self,
        P: GrowingPredicates2,
        bound: AngleBound,
        max_area: Fraction | None,
        region_area: dict[int, Fraction],
        lens: bool,
    ) -> None:
        self.P = P
        self.rows = P.filter_rows
        self.shift = P.shift
        self.bound = bound
        self.theta = bound.degrees
        self._lo = self._hi = 0.0
        if self.theta > 0.0:
            lo, hi = _cos2(self.theta)
            self._lo, self._hi = lo * (1.0 - _MARGIN), hi * (1.0 + _MARGIN)
        self._area: dict[int, tuple[Fraction, float]] = {}
        for region, limit in [(-2, max_area), *region_area.items()]:
            if limit is None:
                continue
            try:
                twice = math.ldexp(float(2 * limit), 2 * self.shift)
            except OverflowError:
                twice = math.nan
            # Outside the normal range the float threshold is not exact: NaN sends every test to the exact path.
            if not (2.0**-1000 < twice < 2.0**1000) or Fraction(twice) != 2 * limit * Fraction(4) ** self.shift:
                twice = math.nan
            self._area[region] = (limit, twice)
        self._lens = lens and 0.0 < self.theta < 45.0
        self._lens_lo = self._lens_hi = 0.0
        if self._lens:
            lo2, hi2 = _cos2(2.0 * self.theta)
            self._lens_lo = math.sqrt(lo2) - _LENS_MARGIN
            self._lens_hi = math.sqrt(hi2) + _LENS_MARGIN

    def assess(self, a: int, b: int, c: int, region: int) -> BadShape | None:
        """None if the counterclockwise triangle ``(a, b, c)`` of ``region`` meets the angle and area bounds, else its
        shape ``(p, q, r, edge2, good_angle)`` (:class:`Shape`'s fields).  Exact. O(1)."""
        found = self.assess_all((((a, b, c), (0, region, ())),), exterior=True)
        return found[0][2] if found else None

    def assess_all(
        self, items: Iterable[tuple[_T, MeshDatum]], exterior: bool = False
    ) -> list[tuple[_T, MeshDatum, BadShape]]:
        """:meth:`assess` of every triangle ``(t, datum)`` of ``items`` (of the region ``datum[1]``; exterior ones
        skipped unless ``exterior``): ``(t, datum, shape)`` for each that does not meet the bounds, in their order.

        One call for a step's new triangles (:meth:`~persistri.impl.mesh.refine_state.RefinerState._adopt`) instead
        of a call each: the same tests, operation for operation.  Exact. O(1) per triangle."""
        out: list[tuple[_T, MeshDatum, BadShape]] = []
        rows = self.rows
        theta = self.theta
        lo, hi = self._lo, self._hi
        areas = self._area
        scale = -2 * self.shift
        for t, d in items:
            region = d[1]
            if region == EXTERIOR and not exterior:
                continue
            a, b, c = t
            ax, ay = rows[a]
            bx, by = rows[b]
            cx, cy = rows[c]
            abx, aby = ax - bx, ay - by
            bcx, bcy = bx - cx, by - cy
            cax, cay = cx - ax, cy - ay
            lab = abx * abx + aby * aby
            lbc = bcx * bcx + bcy * bcy
            lca = cax * cax + cay * cay
            # An edge is a candidate for the shortest unless another is certainly shorter (NaN: a candidate).
            sab, sbc, sca = lab * _SEPARATE, lbc * _SEPARATE, lca * _SEPARATE
            on_ab = not (sab > lbc or sab > lca)
            on_bc = not (sbc > lab or sbc > lca)
            on_ca = not (sca > lab or sca > lbc)
            unique = on_ab + on_bc + on_ca == 1
            good = True
            if theta != 0.0:
                # The angle opposite each candidate edge (at c for ab, at a for bc, at b for ca); each is below about
                # 60°: clearly above the bound (ratio < lo), clearly below it (ratio > hi, the shortest edge known), or
                # exact.  Unrolled (the same operations for each edge), and computed for the candidates only.
                if on_ab:
                    dot = -(cax * bcx + cay * bcy)
                    den = lca * lbc
                    ratio = dot * dot / den if dot > 0.0 and den > 0.0 else math.nan
                    if not ratio < lo:
                        if ratio > hi and unique:
                            good = False
                        else:
                            found = self._assess_exact(a, b, c, region)
                            if found is not None:
                                out.append((t, d, found))
                            continue
                if on_bc:
                    dot = -(abx * cax + aby * cay)
                    den = lab * lca
                    ratio = dot * dot / den if dot > 0.0 and den > 0.0 else math.nan
                    if not ratio < lo:
                        if ratio > hi and unique:
                            good = False
                        else:
                            found = self._assess_exact(a, b, c, region)
                            if found is not None:
                                out.append((t, d, found))
                            continue
                if on_ca:
                    dot = -(bcx * abx + bcy * aby)
                    den = lbc * lab
                    ratio = dot * dot / den if dot > 0.0 and den > 0.0 else math.nan
                    if not ratio < lo:
                        if ratio > hi and unique:
                            good = False
                        else:
                            found = self._assess_exact(a, b, c, region)
                            if found is not None:
                                out.append((t, d, found))
                            continue
            if good:
                if not areas:
                    continue
                limit = areas.get(region) or areas.get(-2)
                if limit is None:
                    continue
                twice = limit[1]
                # orient2d_terms(ax, ay, bx, by, cx, cy), operation for operation (its proved bound holds).
                acx = ax - cx
                bcx = bx - cx
                acy = ay - cy
                bcy = by - cy
                detleft = acx * bcy
                detright = acy * bcx
                det = detleft - detright
                thr = ERRBOUND_ORIENT2D * (abs(detleft) + abs(detright))
                if det < (twice - thr) * (1.0 - _SLACK):
                    continue
                if not det > (twice + thr) * (1.0 + _SLACK) and not area_exceeds(self.P, a, b, c, limit[0]):
                    continue
            # Bad: the shape, with the shortest edge known exactly.
            if not unique:
                found = self._assess_exact(a, b, c, region)
                if found is not None:
                    out.append((t, d, found))
            elif on_ab:
                out.append((t, d, (a, b, c, math.ldexp(lab, scale), good)))
            elif on_bc:
                out.append((t, d, (b, c, a, math.ldexp(lbc, scale), good)))
            else:
                out.append((t, d, (c, a, b, math.ldexp(lca, scale), good)))
        return out

    def _assess_exact(self, a: int, b: int, c: int, region: int) -> BadShape | None:
        sh = shape(self.P, a, b, c, self.bound)
        limit = self._area.get(region) or self._area.get(-2)
        if sh.good_angle and (limit is None or not area_exceeds(self.P, a, b, c, limit[0])):
            return None
        return sh.p, sh.q, sh.r, sh.edge2, sh.good_angle

    def area_bad(self, a: int, b: int, c: int, region: int) -> bool:
        """Whether the triangle's area exceeds its region's bound (or the global one). Exact. O(1)."""
        limit = self._area.get(region) or self._area.get(-2)
        return limit is not None and area_exceeds(self.P, a, b, c, limit[0])

    def encroaches(self, u: int, w: int, x: int) -> bool:
        """Whether point ``x`` encroaches the subsegment ``uw``: strictly inside its diametral circle and, with
        lenses, inside the lens of the bound (:func:`inside_lens`).  Exact. O(1)."""
        rows = self.rows
        ux, uy = rows[u]
        wx, wy = rows[w]
        px, py = rows[x]
        # dot_terms(u, w, x), operation for operation.
        apx = ux - px
        bpx = wx - px
        apy = uy - py
        bpy = wy - py
        left = apx * bpx
        right = apy * bpy
        det = left + right
        thr = ERRBOUND_DOT * (abs(left) + abs(right))
        if det > thr:
            return False
        if not det < -thr:
            if self.P.dot_sign(u, w, x) >= 0:
                return False
        if not self._lens:
            return True
        den = math.sqrt((apx * apx + apy * apy) * (bpx * bpx + bpy * bpy))
        if den > 0.0:
            cos_b = -det / den
            if cos_b >= self._lens_hi:
                return True
            if cos_b <= self._lens_lo:
                return False
        return inside_lens(self.P, u, w, x, self.theta)

