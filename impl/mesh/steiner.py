"""Steiner points of Delaunay refinement, as doubles: segment split points (exactly on their segment), circumcentres and off-centres.

Every mesh vertex is a pair of doubles (the output is an ``(N, 2)`` float64
array), and the mesh is exactly the constrained Delaunay triangulation of the
points it actually holds.  Two kinds of new points:

**Split points** must lie *exactly* on their input segment ``AB``, or the
segment would no longer be a union of mesh edges.  Every vertex on ``AB`` is
``A + t (B − A)`` for a rational ``t`` (the endpoints have ``t = 0, 1``);
:func:`split_parameter` finds the point of two doubles on the subsegment
nearest the wanted one: the doubles of one binade form a grid, and the grid
points of a segment whose ends are on the grid are evenly spaced, ``gcd``
of the coordinate differences of them (a linear Diophantine equation), so the
nearest one is a division away.  Near the limit of double precision no such
point may exist (the doubles on a line of general slope are sparse: for
endpoints with full 53-bit significands in one binade the gcd is often 1);
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
    "split_parameter_within",
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


def _to_double(num: int, den: int, e: int) -> float:
    """``num / den · 2^e`` rounded once to the nearest double (``den > 0``)."""
    if e >= 0:
        return num * (1 << e) / den  # int / int: correctly rounded
    return num / (den << -e)


def steiner_point(
    P: GrowingPredicates2, p: int, q: int, r: int, offconstant: float
) -> tuple[float, float, bool]:
    """The point inserted to split the counterclockwise triangle ``(p, q, r)`` whose shortest edge is ``pq``.

    Returns ``(x, y, off)``: the circumcentre, or the off-centre when ``offconstant > 0``
    and it is nearer to ``pq`` (``off`` True), each exact (integers over a common
    denominator) then rounded once to the nearest doubles.  O(1).
    """
    (pp, pq, pr), ex = P.integers(p, q, r)
    dx, dy = pq[0] - pp[0], pq[1] - pp[1]
    gx, gy = pr[0] - pp[0], pr[1] - pp[1]
    den = 2 * (dx * gy - dy * gx)
    if den <= 0:
        raise ValueError(f"triangle {(p, q, r)} is not counterclockwise: no circumcentre to insert")
    d2, g2 = dx * dx + dy * dy, gx * gx + gy * gy
    if offconstant > 0.0:
        kn, kd = offconstant.as_integer_ratio()
        # The off-centre o = m + k (−dy, dx) is nearer to pq than c when |o − m| < |c − m|: k |pq| < |pq| |cot R| / 2
        # (c − m is perpendicular to pq; R is the angle at r), i.e. 2 k (d × g) < |(p − r) · (q − r)| with
        # d × g = den / 2 and (p − r) · (q − r) = g2 − d · g: kn den < kd |g2 − d · g|, exactly, on integers
        # a few times shorter than those of the squared distances (tested against them: test_mesh_steiner.py).
        dot_r = g2 - dx * gx - dy * gy
        if kn * den < kd * (dot_r if dot_r >= 0 else -dot_r):
            # Twice the midpoint m, in units 2^ex; o as (ox, oy) / (2 kd).
            sx, sy = pp[0] + pq[0], pp[1] + pq[1]
            ox = sx * kd - 2 * kn * dy
            oy = sy * kd + 2 * kn * dx
            kd2 = 2 * kd
            # _to_double(ox, kd2, ex), _to_double(oy, kd2, ex), inlined.
            if ex >= 0:
                x, y = ox * (1 << ex) / kd2, oy * (1 << ex) / kd2
            else:
                x, y = ox / (kd2 << -ex), oy / (kd2 << -ex)
            # _check_rounding's first test, inlined: it clears nearly every point.
            u = max(math.frexp(math.ulp(x))[1], math.frexp(math.ulp(y))[1]) - 1
            if not 2 * (u - ex) + 5 < d2.bit_length() - 1:
                _check_rounding(ox, oy, kd2, ex, x, y, d2, (p, q, r))
            return x, y, True
    # The circumcentre c = (cx, cy) / den, in units 2^ex.
    cx = pp[0] * den + gy * d2 - dy * g2
    cy = pp[1] * den + dx * g2 - gx * d2
    # _to_double(cx, den, ex), _to_double(cy, den, ex), inlined.
    if ex >= 0:
        x, y = cx * (1 << ex) / den, cy * (1 << ex) / den
    else:
        x, y = cx / (den << -ex), cy / (den << -ex)
    u = max(math.frexp(math.ulp(x))[1], math.frexp(math.ulp(y))[1]) - 1  # _check_rounding's first test, inlined
    if not 2 * (u - ex) + 5 < d2.bit_length() - 1:
        _check_rounding(cx, cy, den, ex, x, y, d2, (p, q, r))
    return x, y, False


def _check_rounding(nx: int, ny: int, den: int, e: int, x: float, y: float, d2: int, t: tuple[int, int, int]) -> None:
    """Raise :class:`PrecisionLimitError` if rounding the exact point ``(nx, ny) / den · 2^e`` to the doubles
    ``(x, y)`` moved it by an eighth of the shortest edge (``|pq|² = d2 · 4^e``) or more.

    The exact circumcentre lies at least ``|pq| / √3`` from every vertex it can see, the off-centre at least
    ``0.82 |pq|`` (its constant exceeds ``0.475 · cot 30°``): the distance that Ruppert's termination argument
    counts on.  A point that rounding moved by ``|pq| / 8`` or more no longer keeps it — where ``|pq|`` is a few
    units in the last place, the doubles near the exact point may lie on ``pq`` itself, and the refinement
    would insert points there without end.  Rounding moves a coordinate by half a unit in its last place at
    most, so an integer comparison of exponents clears every point but those within about 16 units in the
    last place of their edge; only those are measured exactly.  O(1).
    """
    u = max(math.frexp(math.ulp(x))[1], math.frexp(math.ulp(y))[1]) - 1  # the larger ulp is 2^u
    if 2 * (u - e) + 5 < d2.bit_length() - 1:  # moved² <= 2^(2u - 1) < 4^e d2 / 64
        return
    s = _pow2(e)
    mx, my = Fraction(x) - Fraction(nx, den) * s, Fraction(y) - Fraction(ny, den) * s
    if 64 * (mx * mx + my * my) >= d2 * s * s:
        raise PrecisionLimitError(
            f"the Steiner point of triangle {tuple(int(v) for v in t)} cannot be placed in doubles: rounding moves it by an eighth of the "
            "triangle's shortest edge or more, and the mesh is at the limit of double precision here"
        )


def point_at(P: GrowingPredicates2, a: int, b: int, t: Fraction) -> tuple[Fraction, Fraction]:
    """The exact point ``a + t (b − a)``. O(1)."""
    (pa, pb), ex = P.integers(a, b)
    s = _pow2(ex)
    return (pa[0] + t * (pb[0] - pa[0])) * s, (pa[1] + t * (pb[1] - pa[1])) * s


def split_parameter(
    P: GrowingPredicates2, a: int, b: int, u: int, w: int, t_u: Fraction, t_w: Fraction, wanted: Fraction
) -> tuple[Fraction, float, float]:
    """A point of two doubles exactly on the subsegment ``uw`` of segment ``ab``, strictly inside it, near ``wanted``
    (:func:`split_parameter_within` with no reach: never None). O(1) integer operations, or O(_LEVELS) for the
    fallback."""
    found = split_parameter_within(P, a, b, u, w, t_u, t_w, wanted, None)
    assert found is not None, "with no reach the search returns a point or raises"
    return found


def split_parameter_within(
    P: GrowingPredicates2,
    a: int,
    b: int,
    u: int,
    w: int,
    t_u: Fraction,
    t_w: Fraction,
    wanted: Fraction,
    reach: tuple[int, int] | None,
) -> tuple[Fraction, float, float] | None:
    """A point of two doubles exactly on the subsegment ``uw`` of segment ``ab``, strictly inside it, near ``wanted``.

    ``u = a + t_u (b − a)`` and ``w = a + t_w (b − a)`` (``t_u < t_w``); ``wanted`` is
    a parameter in ``(t_u, t_w)``.  Returns ``(t, x, y)`` with ``(x, y) = a + t (b − a)``
    exactly.

    **The lattice.**  Per axis, let ``g = 2^(e − 53)`` where ``2^e`` bounds that
    coordinate of ``u`` and ``w`` in magnitude (hence along the whole subsegment):
    every multiple of ``g`` below ``2^e`` is a double.  In integer units fine
    enough for ``u``, ``w`` and both grids, the integer points of the subsegment
    are ``u + k (w − u) / G``, ``k = 0 … G``, ``G`` the gcd of the coordinates of
    ``w − u`` (a linear Diophantine equation); those on the grid satisfy one
    congruence on ``k`` per axis modulo a power of two, which combine into
    one: ``k ≡ r (mod M)``.  The solution nearest ``wanted`` with ``0 < k < G`` is
    returned.  ``G <= 1`` means no double of that grid lies
    strictly inside.  **Otherwise** (a coordinate of ``u`` or ``w`` finer than the
    grid), dyadic parameters near ``wanted`` are tried, finest first, for points
    whose two coordinates are doubles (tested exactly).
    :class:`PrecisionLimitError` if neither finds a point.

    ``reach = (rn, rd)``: the caller can use only a point whose parameter lies within
    ``rn / rd`` of ``wanted`` (a split point at a small input angle,
    :func:`~persistri.impl.mesh.splitting.placement_tolerances`).  The fallback's points all lie
    on the grid of its level bound (below); when no point of that grid is within reach, None
    is returned at once instead of a point the caller would not use or the error.  O(1)
    integer operations, or O(_LEVELS) for the fallback.
    """
    un, ud = t_u.as_integer_ratio()
    vn, vd = t_w.as_integer_ratio()
    if not un * vd < vn * ud:  # t_u < t_w, on integers (positive denominators)
        raise ValueError(f"empty parameter interval ({t_u}, {t_w})")
    (pu, pw), ex = P.integers(u, w)
    (ux, uy), (wx, wy) = P.xy(u), P.xy(w)
    # Per axis, the grid 2^(top - 53) of the binade bounding both ends; units 2^m fine enough for both grids.
    grids = (max(math.frexp(ux)[1], math.frexp(wx)[1]) - 53, max(math.frexp(uy)[1], math.frexp(wy)[1]) - 53)
    m = min(ex, *grids)
    sh = ex - m
    xu, yu, xw, yw = pu[0] << sh, pu[1] << sh, pw[0] << sh, pw[1] << sh
    dx, dy = xw - xu, yw - yu
    G = math.gcd(dx, dy)
    if G >= 2:
        # The integer points of the subsegment are u + k (d / G), k = 0 … G; the grid asks, per axis,
        # coordinate ≡ 0 (mod 2^(grid − m)): a congruence on k modulo a power of two.
        step_x, step_y = dx // G, dy // G
        solved = _congruence(xu, step_x, grids[0] - m)
        other = _congruence(yu, step_y, grids[1] - m)
        if solved is not None and other is not None:
            (r1, m1), (r2, m2) = (solved, other) if solved[1] <= other[1] else (other, solved)
            if (r2 - r1) % m1 == 0:  # compatible: k ≡ r2 (mod m2), m1 dividing m2
                # On integers: wanted − t_u = wide / (wd ud), t_w − t_u = span / (vd ud) (span > 0), so the wanted
                # place is s* = G (wanted − t_u) / (t_w − t_u) = G wide vd / (wd span), and k the solution nearest it:
                # k = r2 + m2 · round((s* − r2) / m2), rounding half to even as round() does.
                wn, wd = wanted.as_integer_ratio()
                wide, span = wn * ud - un * wd, vn * ud - un * vd
                q, rem = divmod(G * wide * vd - r2 * wd * span, m2 * wd * span)
                twice, den = 2 * rem, m2 * wd * span
                if twice > den or (twice == den and q & 1):
                    q += 1
                k = r2 + m2 * q
                for cand in (k, k - m2, k + m2):
                    if 0 < cand < G:
                        fx = _dyadic_double(xu + cand * step_x, m)
                        fy = _dyadic_double(yu + cand * step_y, m)
                        if fx is not None and fy is not None:
                            # t_u + (cand / G) (t_w − t_u), one normalisation.
                            return Fraction(un * G * vd + cand * span, ud * G * vd), fx, fy
    return _dyadic_split(P, a, b, t_u, t_w, wanted, reach)


def _congruence(c: int, d: int, bits: int) -> tuple[int, int] | None:
    """``(r, M)`` with ``c + k d ≡ 0 (mod 2^bits)`` exactly when ``k ≡ r (mod M)`` (``M`` a power of two), or None."""
    if bits <= 0:
        return 0, 1
    mod = 1 << bits
    if d % mod == 0:
        return (0, 1) if c % mod == 0 else None
    tz = (d & -d).bit_length() - 1
    if c % (1 << tz):
        return None
    sub = mod >> tz
    r = (-(c >> tz) * pow(d >> tz, -1, sub)) % sub
    return r, sub


def _dyadic_split(
    P: GrowingPredicates2,
    a: int,
    b: int,
    t_lo: Fraction,
    t_hi: Fraction,
    wanted: Fraction,
    reach: tuple[int, int] | None = None,
) -> tuple[Fraction, float, float] | None:
    """:func:`split_parameter`'s fallback: dyadic ``t`` in the middle half of ``(t_lo, t_hi)`` near ``wanted``.

    On integers: with ``t = j / 2^k`` the point is ``(a·2^k + j (b − a)) · 2^(ex − k)`` in the units ``2^ex`` of
    ``P.integers``, and it is a double exactly when :func:`_dyadic_double` says so (no rational arithmetic)."""
    # On integers (each rational in lowest terms, as Fraction arithmetic would leave it): delta = t_hi − t_lo, the
    # middle half's ends lo_ok = t_lo + delta / 4 = (3 t_lo + t_hi) / 4 and hi_ok = (t_lo + 3 t_hi) / 4, and the
    # target: wanted clamped to them.
    a1, b1 = t_lo.as_integer_ratio()
    a2, b2 = t_hi.as_integer_ratio()
    dn, dd = _lowest(a2 * b1 - a1 * b2, b1 * b2)
    lon, lod = _lowest(3 * a1 * b2 + a2 * b1, 4 * b1 * b2)
    hin, hid = _lowest(a1 * b2 + 3 * a2 * b1, 4 * b1 * b2)
    tn, td = wanted.as_integer_ratio()
    if lon * td > tn * lod:
        tn, td = lon, lod
    if hin * td < tn * hid:
        tn, td = hin, hid
    # The coarsest level whose spacing 2^-k is at most delta / 8 (so a candidate lands in the middle half):
    # the least k >= 0 with 8 · den(delta) <= num(delta) · 2^k.
    dd8 = 8 * dd
    k0 = max(0, dd8.bit_length() - dn.bit_length() - 1)
    while (dn << k0) < dd8:
        k0 += 1
    while k0 > 0 and (dn << (k0 - 1)) >= dd8:
        k0 -= 1
    fine = min(k0 + _LEVELS, max(k0, td.bit_length() - 1))
    (pa, pb), ex = P.integers(a, b)
    ax, ay = pa
    dx, dy = pb[0] - ax, pb[1] - ay
    # A level bound per axis (below): a candidate j / 2^k' in lowest terms with k' above it is no double.
    bound = _dyadic_level_bound(ax, dx, lon, lod, hin, hid)
    other = _dyadic_level_bound(ay, dy, lon, lod, hin, hid)
    if bound is None or (other is not None and other < bound):
        bound = other
    if reach is not None and bound is not None and not _grid_within(bound, wanted, reach):
        return None  # every candidate the loop below could return is farther from wanted than the caller can use
    start = fine
    if bound is not None and 0 <= bound < fine:
        start = min(fine, max(bound, _last_reducing_level(tn, td, bound)))
    tried: set[tuple[int, int]] = set()
    for k in range(start, k0 - 1, -1):
        unit = 1 << k
        scaled = tn * unit  # target · 2^k = scaled / td
        base = scaled // td
        first, second = (base, base + 1) if 2 * (scaled - base * td) <= td else (base + 1, base)
        for j in (first, second):
            # j / 2^k in lowest terms, as the set's key.
            tz = min((j & -j).bit_length() - 1, k) if j else k
            key = (j >> tz, k - tz)
            if key in tried or not (lon * unit <= j * lod and j * hid <= hin * unit):
                continue
            tried.add(key)
            if bound is not None and key[1] > bound:
                continue  # one coordinate has more significant bits than a double
            fx = _dyadic_double((ax << k) + j * dx, ex - k)
            if fx is None:
                continue
            fy = _dyadic_double((ay << k) + j * dy, ex - k)
            if fy is not None:
                return Fraction(j, unit), fx, fy
    raise PrecisionLimitError(
        f"no pair of doubles lies exactly on the segment between points {a} and {b} "
        f"for parameters in ({float(t_lo)!r}, {float(t_hi)!r}): the subsegment is at the limit of double precision "
        "(round the input coordinates to fewer significant bits, or ask for a coarser mesh)"
    )


def _grid_within(bound: int, wanted: Fraction, reach: tuple[int, int]) -> bool:
    """Whether a multiple of ``2^-bound`` lies within ``reach = (rn, rd)`` (``rn / rd``) of ``wanted``: the candidates
    :func:`_dyadic_split` can return are ``j / 2^k`` of level at most ``bound`` in lowest terms, all on that grid (none
    when ``bound < 0``: every level is at least 0). O(1) on integers."""
    if bound < 0:
        return False
    wn, wd = wanted.as_integer_ratio()
    rn, rd = reach
    scaled = wn << bound  # wanted · 2^bound = scaled / wd
    m = scaled // wd
    lo = scaled - m * wd  # wanted − m / 2^bound = lo / (wd · 2^bound), and (m + 1) / 2^bound − wanted = hi / (…)
    hi = wd - lo
    return min(lo, hi) * rd <= rn * (wd << bound)


def _last_reducing_level(tn: int, td: int, bound: int) -> int:
    """The highest level ``k`` at which a candidate of :func:`_dyadic_split` for the target ``tn / td`` can reduce to
    a level at most ``bound >= 0`` (-1 if none; a large number if every level can).

    At level ``k > bound`` the candidates are ``j = floor(target · 2^k)`` and ``j + 1``; ``j / 2^k`` in lowest terms
    has a level at most ``bound`` exactly when ``j`` is a multiple of ``2^(k − bound)``, i.e. when a point
    ``m / 2^bound`` lies within ``2^-k`` of the target: below it (``m = floor(target · 2^bound)``) at a distance
    ``d_lo < 2^-k``, or above it (``m + 1``) at ``d_hi <= 2^-k``.  Both conditions hold for every level up to some
    ``k``, and for none above it: levels above the returned one hold only candidates that the level bound rejects
    (and that no later level could return), so :func:`_dyadic_split` starts below them, with the same result. O(1)
    on integers."""
    g = 1 << bound
    m = (tn * g) // td
    den = td * g  # d_lo = lo / den, d_hi = hi / den
    lo = tn * g - m * td
    hi = (m + 1) * td - tn * g
    if lo == 0:
        return 1 << 30  # the target is on the grid of level bound: every level can reduce
    best = -1
    k = den.bit_length() - lo.bit_length()  # the largest k with lo · 2^k < den
    if k >= 0 and (lo << k) >= den:
        k -= 1
    best = max(best, k)
    k = den.bit_length() - hi.bit_length()  # the largest k with hi · 2^k <= den
    if k >= 0 and (hi << k) > den:
        k -= 1
    return max(best, k)


def _dyadic_level_bound(a: int, d: int, ln: int, ld: int, hn: int, hd: int) -> int | None:
    """A level ``K`` such that for no ``t = j / 2^k`` in lowest terms with ``k > K`` and ``lo <= t <= hi`` is
    ``(a + t d) · 2^e`` a double, whatever ``e`` (None: no such bound found); ``lo = ln / ld`` and ``hi = hn / hd``
    (positive denominators).

    With ``v(·)`` the 2-adic valuation: ``v(t d) = v(d) − k``, which is below ``v(a)`` when ``k > v(d) − v(a)``, and
    then ``v(a + t d) = v(d) − k``.  A double of binary exponent ``E`` is a multiple of ``2^(E − 52)`` (of
    ``2^-1074`` below the normal range, a stronger condition), and ``E >= E_lo``, a lower bound of
    ``floor(log2 |a + t d|)`` on ``[lo, hi]`` where the line does not cross 0 (from the bit lengths of the smaller
    end's numerator and denominator in lowest terms).  So ``k > v(d) − E_lo + 52`` fails too.  O(1) on integers."""
    if d == 0:
        return None
    # a + lo d = nlo / ld and a + hi d = nhi / hd.
    nlo, nhi = a * ld + ln * d, a * hd + hn * d
    if (nlo <= 0) != (nhi <= 0) or nlo == 0 or nhi == 0:
        return None  # the line crosses 0 in the interval: points of any size
    alo, ahi = abs(nlo), abs(nhi)
    n, m = _lowest(ahi, hd) if ahi * ld < alo * hd else _lowest(alo, ld)  # the smaller end, in lowest terms
    e_lo = n.bit_length() - m.bit_length() - 1  # <= floor(log2(least))
    vd = (d & -d).bit_length() - 1
    bound = vd - e_lo + 52
    if a != 0:
        bound = max(bound, vd - ((a & -a).bit_length() - 1))
    return bound


def _lowest(n: int, d: int) -> tuple[int, int]:
    """``n / d`` (``d > 0``) in lowest terms, as :class:`~fractions.Fraction` keeps it. O(1) gcd."""
    g = math.gcd(n, d)
    return n // g, d // g


def _dyadic_double(n: int, e: int) -> float | None:
    """``n · 2^e`` as a double when it is one exactly (normal or subnormal), else None. O(1) on integers."""
    if n == 0:
        return 0.0
    tz = (n & -n).bit_length() - 1
    odd, e = n >> tz, e + tz
    if abs(odd).bit_length() > 53 or e < -1074 or e + abs(odd).bit_length() > 1024:
        return None
    return math.ldexp(float(odd), e)
