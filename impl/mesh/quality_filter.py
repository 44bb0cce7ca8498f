"""The refinement's quality and encroachment tests, float stage first, exact when it cannot tell (paper §1).

:class:`QualityTests` is what Ruppert's refinement (:mod:`persistri.impl.mesh.ruppert`) asks of every new
triangle — its smallest angle against the bound, its area against the area bound — and of every apex beside a
subsegment (encroachment, with or without the lens).  Each answer is the exact one of
:mod:`persistri.impl.mesh.quality` (:func:`~persistri.impl.mesh.quality.shape`,
:func:`~persistri.impl.mesh.quality.area_exceeds`, :func:`~persistri.impl.mesh.quality.inside_lens`) or of the
predicates (``dot_sign``); a float stage on the predicates' filter copy of the points decides first when its result
is clear of the bound by more than its proved error (the argument in :class:`QualityTests`' docstring; its constants,
kept in :mod:`~persistri.impl.mesh.quality` with the exact tests' own float stages, are checked in exact rationals
in ``proofs/proof_mesh.py``).  :mod:`~persistri.impl.mesh.quality` is the exact side, what the checker and the
tests compare with; this module the refinement's fast path over it.

Costs: O(1) float operations per test when the float stage decides, O(1) big-integer operations otherwise.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from fractions import Fraction
from typing import TypeVar

from persistri.impl.geometry.filter import ERRBOUND_ORIENT2D
from persistri.impl.geometry.growing import ERRBOUND_DOT, GrowingPredicates2
from persistri.impl.mesh.datum import EXTERIOR, MeshDatum
from persistri.impl.mesh.quality import (
    _LENS_MARGIN,
    _MARGIN,
    _SEPARATE,
    _SLACK,
    AngleBound,
    _cos2,
    area_exceeds,
    inside_lens,
    shape,
)

__all__ = ["BadShape", "QualityTests"]

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

