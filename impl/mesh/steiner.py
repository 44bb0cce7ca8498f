"""Steiner points of Delaunay refinement, as doubles: segment split points (exactly on their segment), circumcentres and off-centres.

Every mesh vertex is a pair of doubles (the output is an ``(N, 2)`` float64
array), and the mesh is exactly the constrained Delaunay triangulation of the
points it actually holds.  Two kinds of new points:

**Split points** must lie *exactly* on their input segment ``AB``, or the
segment would no longer be a union of mesh edges.  Every vertex on ``AB`` is
``A + t (B − A)`` for a dyadic rational ``t`` (the endpoints have ``t = 0, 1``
and every split chooses a dyadic ``t``); :func:`split_parameter` looks for a
dyadic ``t`` near the wanted one, inside the middle half of the subsegment,
whose point has *both* coordinates exactly representable as doubles (tested
exactly, in rationals), from the finest candidates to the coarser ones.  Near
the limit of double precision no such ``t`` may exist (the doubles on a line
of general slope are sparse: for endpoints with full 53-bit significands of one
binade, ``t (B − A)`` must land on the grid of the binade in both coordinates);
:class:`PrecisionLimitError` then says which subsegment could not be split.

**Circumcentres and off-centres** are computed exactly (rationals from the
integer coordinates) and rounded once to the nearest doubles; the mesh then
contains the rounded point, and every later decision is exact for it.  The
off-centre (Üngör 2004, as Triangle computes it) lies on the bisector of the
triangle's shortest edge ``pq``, at distance ``k · |pq|`` from its midpoint with
``k = 0.475 · cot(θ/2)`` (Triangle's constant: 0.5 would make ``p q o`` have
angle exactly ``θ`` at ``o``; 0.475 leaves a margin); it replaces the
circumcentre when it is nearer to ``pq``, giving fewer, better-shaped
triangles.

Costs: O(1) rational operations per point (a split point tries at most
``2 · _LEVELS`` candidates).
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Final

from persistri.impl.geometry.growing import GrowingPredicates2

__all__ = [
    "PrecisionLimitError",
    "circumcenter",
    "steiner_point",
    "split_parameter",
    "point_at",
    "offcenter_constant",
]

_LEVELS: Final[int] = 64
"""Dyadic levels tried below the coarsest one that fits the middle half of a subsegment."""


class PrecisionLimitError(ValueError):
    """No double lies exactly on a subsegment where it must be split, or a new point rounds onto an old one."""


def _pow2(e: int) -> Fraction:
    return Fraction(1 << e) if e >= 0 else Fraction(1, 1 << -e)


def circumcenter(P: GrowingPredicates2, a: int, b: int, c: int) -> tuple[Fraction, Fraction]:
    """The exact circumcentre of the (non-degenerate) triangle ``a, b, c``. O(1).

    With ``d = b − a``, ``e = c − a`` and ``D = 2 (d × e)``: ``a + (e_y |d|² − d_y |e|², d_x |e|² − e_x |d|²) / D``
    (``proofs/proof_mesh.py`` checks that it is equidistant from the three points).
    """
    (pa, pb, pc), ex = P.integers(a, b, c)
    dx, dy = pb[0] - pa[0], pb[1] - pa[1]
    gx, gy = pc[0] - pa[0], pc[1] - pa[1]
    den = 2 * (dx * gy - dy * gx)
    if den == 0:
        raise ValueError(f"triangle {(a, b, c)} is flat: no circumcentre")
    d2 = dx * dx + dy * dy
    g2 = gx * gx + gy * gy
    s = _pow2(ex)
    x = (Fraction(pa[0]) + Fraction(gy * d2 - dy * g2, den)) * s
    y = (Fraction(pa[1]) + Fraction(dx * g2 - gx * d2, den)) * s
    return x, y


def offcenter_constant(min_angle: float) -> float:
    """Triangle's off-centre constant ``0.475 · cot(θ/2)`` for ``θ = min_angle`` degrees (0 for ``θ = 0``: no off-centres)."""
    if min_angle <= 0.0:
        return 0.0
    return 0.475 / math.tan(math.radians(min_angle) / 2)


def steiner_point(
    P: GrowingPredicates2, p: int, q: int, r: int, offconstant: float
) -> tuple[float, float, bool]:
    """The point inserted to split the counterclockwise triangle ``(p, q, r)`` whose shortest edge is ``pq``.

    Returns ``(x, y, off)``: the circumcentre, or the off-centre when ``offconstant > 0``
    and it is nearer to ``pq`` (``off`` True), each exact then rounded to the nearest
    doubles.  O(1).
    """
    cx, cy = circumcenter(P, p, q, r)
    if offconstant > 0.0:
        (pp, pq), ex = P.integers(p, q)
        s = _pow2(ex)
        k = Fraction(offconstant)
        mx, my = Fraction(pp[0] + pq[0], 2) * s, Fraction(pp[1] + pq[1], 2) * s
        # Left of p → q, towards r: the perpendicular (−(q − p)_y, (q − p)_x), scaled by k.
        ox = mx - k * (pq[1] - pp[1]) * s
        oy = my + k * (pq[0] - pp[0]) * s
        if (ox - mx) ** 2 + (oy - my) ** 2 < (cx - mx) ** 2 + (cy - my) ** 2:
            return float(ox), float(oy), True
    return float(cx), float(cy), False


def point_at(P: GrowingPredicates2, a: int, b: int, t: Fraction) -> tuple[Fraction, Fraction]:
    """The exact point ``a + t (b − a)``. O(1)."""
    (pa, pb), ex = P.integers(a, b)
    s = _pow2(ex)
    return (pa[0] + t * (pb[0] - pa[0])) * s, (pa[1] + t * (pb[1] - pa[1])) * s


def split_parameter(
    P: GrowingPredicates2, a: int, b: int, t_lo: Fraction, t_hi: Fraction, wanted: Fraction
) -> tuple[Fraction, float, float]:
    """A dyadic ``t`` in the middle half of ``(t_lo, t_hi)``, near ``wanted``, whose point on segment ``ab`` is two doubles.

    Returns ``(t, x, y)`` with ``(x, y) = a + t (b − a)`` exactly.  Candidates: the
    multiples of ``2^-k`` nearest to ``wanted`` (clamped to the middle half), from
    the finest level (``wanted``'s own, at most :data:`_LEVELS` below the coarsest
    that fits) to the coarsest.  :class:`PrecisionLimitError` if none is
    representable.  O(_LEVELS) rational operations.
    """
    delta = t_hi - t_lo
    if delta <= 0:
        raise ValueError(f"empty parameter interval ({t_lo}, {t_hi})")
    lo_ok, hi_ok = t_lo + delta / 4, t_hi - delta / 4
    target = min(max(wanted, lo_ok), hi_ok)
    # The coarsest level whose spacing 2^-k is at most delta / 8 (so a candidate lands in the middle half).
    k0 = max(0, math.ceil(math.log2(8 / delta)) if delta < 8 else 0)
    while Fraction(1, 1 << k0) > delta / 8:
        k0 += 1
    fine = min(k0 + _LEVELS, max(k0, target.denominator.bit_length() - 1))
    (pa, pb), ex = P.integers(a, b)
    s = _pow2(ex)
    ax, ay = Fraction(pa[0]) * s, Fraction(pa[1]) * s
    dx, dy = Fraction(pb[0] - pa[0]) * s, Fraction(pb[1] - pa[1]) * s
    tried: set[Fraction] = set()
    for k in range(fine, k0 - 1, -1):
        unit = 1 << k
        base = math.floor(target * unit)
        first, second = (base, base + 1) if target * unit - base <= Fraction(1, 2) else (base + 1, base)
        for j in (first, second):
            t = Fraction(j, unit)
            if t in tried or not lo_ok <= t <= hi_ok:
                continue
            tried.add(t)
            x = ax + t * dx
            y = ay + t * dy
            fx, fy = float(x), float(y)
            if fx == x and fy == y:
                return t, fx, fy
    raise PrecisionLimitError(
        f"no pair of doubles lies exactly on the segment between points {a} and {b} "
        f"for parameters in ({float(t_lo)!r}, {float(t_hi)!r}): the subsegment is at the limit of double precision "
        "(round the input coordinates to fewer significant bits, or ask for a coarser mesh)"
    )
