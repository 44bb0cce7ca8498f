"""Where Ruppert's refinement splits a subsegment: the midpoint, a concentric shell, exactly on the segment (paper §1).

:func:`split_point` chooses the point that splits an encroached subsegment
``uw`` of input segment ``AB`` and returns it as a pair of doubles with its exact
parameter on ``AB``:

* **where**: at the midpoint, or on the *concentric shell* around an end ``o``:
  at the distance ``2^k`` from ``o`` with ``1.5 · 2^k <= |uw| < 3 · 2^k`` (the power
  of two that splits it most evenly; the worst case is 2 : 1).  Shells keep the
  splits of two segments meeting at ``o`` at the same distances from ``o``, which
  is what stops a small input angle from making the refinement split its two
  sides in turn forever (Ruppert 1995; Shewchuk 2002, §4).  The centre ``o``: the
  end that is an input vertex where another segment meets this one at less than
  60° (decided exactly), when exactly one end is; otherwise Triangle's rule —
  an end where a triangle beside the subsegment has a second constrained edge
  (two segments meet at that corner), the second end when both are, else the
  midpoint;
* **exactly**: the point is the double nearest the wanted one *exactly on the
  subsegment* (:func:`~persistri.impl.mesh.steiner.split_parameter`: the lattice
  of doubles on the segment).  Where no double lies on the subsegment — or, on a
  segment at a small input angle, none near enough the wanted place for the
  shells to pair up (:func:`placement_tolerances`) — the exact point is rounded to
  the nearest doubles instead, as Triangle's split
  points are (``exact_segments=False``, the default; reported as *rounded*), or
  :class:`~persistri.impl.mesh.steiner.PrecisionLimitError` is raised
  (``exact_segments=True``).  A rounded point lies off the segment's line, and
  near a vertex that lies itself within an ulp of the segment it can fall on the
  wrong side of a cavity edge; :func:`rounded_candidates` lists the nearby
  doubles (and other parameters) in order of preference, for the refiner to
  insert in turn until the new version is valid (decided exactly).

Costs: O(1) exact operations, plus O(segments at the vertex) once per pair (vertex, segment)
for the small-angle test (memoised by the caller).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from fractions import Fraction
from typing import Final

from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.angles import angle_at_least
from persistri.impl.mesh.cdt import SegmentGeometry, param_on_segment
from persistri.impl.mesh.steiner import PrecisionLimitError, _to_double, split_parameter_within
from persistri.impl.mesh.triangulation import MeshDatum, Tri, constraint_of

__all__ = [
    "SplitPoint",
    "split_point",
    "rounded_candidates",
    "near_segment",
    "small_angle_at",
    "placement_tolerances",
    "placed_well",
    "shell_exponent",
]

SplitPoint = tuple[Fraction, float, float, "tuple[int, int] | None", bool]
"""``(t, x, y, shell, rounded)``: the parameter on the segment, the point, the shell ``(o, k)`` it lies on (or
None) and whether it was rounded off the subsegment."""


def small_angle_at(P: GrowingPredicates2, geo: SegmentGeometry, o: int, s: int) -> bool:
    """Whether input vertex ``o`` is an end of segment ``s`` where another segment meets ``s`` at less than 60° (exact).

    O(segments at ``o``): the caller memoises it."""
    if o >= geo.n_input or geo.incident[o] < 2:
        return False
    for d1, d2 in _arms(P, geo, o, s):
        if not angle_at_least(d1[0] * d2[0] + d1[1] * d2[1], d1[0] ** 2 + d1[1] ** 2, d2[0] ** 2 + d2[1] ** 2, 60.0):
            return True
    return False


def _arms(P: GrowingPredicates2, geo: SegmentGeometry, o: int, s: int) -> Iterator[tuple[tuple[int, int], tuple[int, int]]]:
    """For every other segment at ``o``: the exact integer vectors from ``o`` along ``s`` and along it. O(segments at
    ``o``)."""
    a, b = geo.ends[s]
    far = b if a == o else a
    ends = geo.ends
    for t in geo.segments_at(o):
        if t == s:
            continue
        c, d = ends[t]
        other = d if c == o else c
        (io, ip, iq), _ = P.integers(o, far, other)
        yield (ip[0] - io[0], ip[1] - io[1]), (iq[0] - io[0], iq[1] - io[1])


def placement_tolerances(
    P: GrowingPredicates2, geo: SegmentGeometry, s: int, small: Callable[[int, int], bool] | None = None
) -> tuple[tuple[int, float], ...]:
    """For each end ``o`` of segment ``s`` where another segment meets it at less than 60°: ``(o, τ)`` with
    ``τ = min(α² / 4, 2^-12)``, ``α`` the smallest such angle in radians (a float: it sets a tolerance, decides no
    predicate).  A split point of ``s`` is *placed well* when it lies within ``τ · r`` of its wanted place, ``r``
    the wanted place's distance from ``o`` (:func:`placed_well`).

    Why: a split point off its wanted place by ``δ`` (along the segment) is ``δ`` farther from or nearer to ``o``.
    Its twin on the other segment — the split point at the same distance ``r`` from ``o`` — lies ``r sin α`` off
    this segment and ``r (1 − cos α) ≈ r α² / 2`` back from the foot of the split point; it stays outside the
    diametral circle of the subsegment of length ``L <= r`` ending there only while the split point is not farther
    than that, ``δ / r`` below about ``α² / 2``.  Triangle's exemption asks the two distances to agree within a
    factor 1.001 on their squares, 5e-4 on the distances.  ``τ`` keeps both, with a margin.  On a needle of 1e-6
    rad the doubles lying exactly on a segment can be 5e-4 apart, relatively: the nearest one is then not placed
    well.  ``small(o, s)``: a memoised :func:`small_angle_at` (None: computed here).  O(segments at its ends): the
    caller memoises it.
    """
    out: list[tuple[int, float]] = []
    for o in geo.ends[s]:
        if o >= geo.n_input or geo.incident[o] < 2:
            continue
        if not (small_angle_at(P, geo, o, s) if small is None else small(o, s)):
            continue
        smallest = math.pi
        for d1, d2 in _arms(P, geo, o, s):
            cross, dot = d1[0] * d2[1] - d1[1] * d2[0], d1[0] * d2[0] + d1[1] * d2[1]
            # int / int divides exactly rounded, without overflow; atan2 stays accurate for tiny angles.
            big = max(abs(cross), abs(dot))
            smallest = min(smallest, abs(math.atan2(cross / big, dot / big)))
        out.append((o, min(2.0**-12, smallest * smallest / 4.0)))
    return tuple(out)


def placed_well(t: Fraction, wanted: Fraction, ends: Sequence[tuple[Fraction, float]]) -> bool:
    """Whether parameter ``t`` is within ``τ · |wanted − t_o|`` of ``wanted`` for every ``(t_o, τ)`` in ``ends``:
    the split point is as near its wanted place, relative to its distance from each small input angle's apex, as
    :func:`placement_tolerances` asks (exact, on rationals). O(1)."""
    off = abs(t - wanted)
    return all(off <= Fraction(tau) * abs(wanted - t_o) for t_o, tau in ends)


def _placed_well_at_ends(t: Fraction, wanted: Fraction, a: int, near: Sequence[tuple[int, float]]) -> bool:
    """:func:`placed_well` for ``near`` as :func:`placement_tolerances` gives it (``(o, τ)``, ``o`` the segment's
    first end ``a``, at parameter 0, or its second, at 1), on integers: ``|t − wanted| <= τ · r`` with ``r =
    |wanted|`` or ``|1 − wanted|``, cross-multiplied over positive denominators. O(1)."""
    tn_, td_ = t.as_integer_ratio()
    wn, wd = wanted.as_integer_ratio()
    on, od = abs(tn_ * wd - wn * td_), td_ * wd  # |t − wanted| = on / od (not in lowest terms: cross-multiplied below)
    for o, tau in near:
        tn, td = tau.as_integer_ratio()
        rn = abs(wn) if o == a else abs(wd - wn)  # r = |wanted − t_o| = rn / wd
        if on * td * wd > tn * rn * od:
            return False
    return True


def _reach(wanted: Fraction, a: int, near: Sequence[tuple[int, float]]) -> tuple[int, int]:
    """``min τ · r`` over ``near`` (as :func:`_placed_well_at_ends` reads it) as an integer pair ``(n, d)``: a split
    parameter is placed well exactly when it is within ``n / d`` of ``wanted``. O(len(near)) on integers."""
    wn, wd = wanted.as_integer_ratio()
    best: tuple[int, int] | None = None
    for o, tau in near:
        tn, td = tau.as_integer_ratio()
        rn = abs(wn) if o == a else abs(wd - wn)  # r = rn / wd
        cand = (tn * rn, td * wd)
        if best is None or cand[0] * best[1] < best[0] * cand[1]:
            best = cand
    assert best is not None, "near is not empty"
    return best


def shell_exponent(length: float) -> int:
    """The ``k`` with ``1.5 · 2^k <= length < 3 · 2^k`` (``length`` positive and finite). O(1)."""
    k = math.floor(math.log2(length / 3.0)) + 1
    while length < 1.5 * 2.0**k:
        k -= 1
    while length >= 3.0 * 2.0**k:
        k += 1
    return k


def _corner_ends(lo: int, hi: int, sides: Sequence[tuple[Tri, MeshDatum] | None]) -> tuple[bool, bool]:
    """Triangle's test, on both sides of the subsegment ``{lo, hi}``: whether a triangle beside it has a second
    constrained edge at ``lo`` / at ``hi``."""
    at_lo = at_hi = False
    for side in sides:
        if side is None:
            continue
        (z0, z1, apex), d = side
        if apex < 0 or len(d[2]) < 2:
            continue
        for x, y in ((z1, apex), (apex, z0)):
            if constraint_of(d, x, y) >= 0:
                end = y if x == apex else x
                if end == lo:
                    at_lo = True
                elif end == hi:
                    at_hi = True
    return at_lo, at_hi


def split_point(
    P: GrowingPredicates2,
    geo: SegmentGeometry,
    lo: int,
    hi: int,
    s: int,
    sides: Sequence[tuple[Tri, MeshDatum] | None],
    small: Callable[[int, int], bool],
    exact_segments: bool,
    tolerances: Callable[[int], tuple[tuple[int, float], ...]] | None = None,
) -> SplitPoint:
    """The point splitting the subsegment ``{lo, hi}`` of segment ``s`` (module docstring).

    ``sides``: the triangles beside it (None where there is none); ``small(o, s)``: the memoised
    :func:`small_angle_at`; ``tolerances(s)``: the memoised :func:`placement_tolerances` (None: none asked).  A
    lattice point not placed well is rounded off instead unless ``exact_segments`` (strict mode keeps it: exactness
    was asked first, and the refinement may then need ``max_steiner`` at a tiny input angle).
    :class:`PrecisionLimitError` in strict mode where no double lies on the subsegment,
    or when even the rounded point falls on an end.  O(1).
    """
    tu, tw = param_on_segment(P, geo, s, lo), param_on_segment(P, geo, s, hi)
    (un, ud), (wn, wd) = tu.as_integer_ratio(), tw.as_integer_ratio()
    if un * wd < wn * ud:  # tu < tw (positive denominators)
        first, second, t_first, t_second = lo, hi, tu, tw
    else:
        first, second, t_first, t_second = hi, lo, tw, tu
    a, b = geo.ends[s]
    small_lo, small_hi = small(lo, s), small(hi, s)
    if small_lo != small_hi:
        centre: int | None = lo if small_lo else hi
    else:
        at_lo, at_hi = _corner_ends(lo, hi, sides)
        centre = hi if at_hi else lo if at_lo else None
    wanted: Fraction | None = None
    shell: tuple[int, int] | None = None
    if centre is not None:
        other = hi if centre == lo else lo
        (po, pt), e = P.integers(centre, other)
        length = math.hypot(po[0] - pt[0], po[1] - pt[1]) * 2.0**e
        (pa, pb), e2 = P.integers(a, b)
        total = math.hypot(pa[0] - pb[0], pa[1] - pb[1]) * 2.0**e2
        if length > 0 and total > 0 and math.isfinite(length) and math.isfinite(total):
            k = shell_exponent(length)
            # dt = 2^k / total as a float, exactly a rational; the shell's centre is an end of the subsegment (its
            # parameter tu or tw): wanted = t_first + dt or t_second − dt, summed on integers, normalised once.
            dn, dd = (2.0**k / total).as_integer_ratio()
            if centre == first:
                fn, fd = t_first.as_integer_ratio()
                wanted = Fraction(fn * dd + dn * fd, fd * dd)
            else:
                fn, fd = t_second.as_integer_ratio()
                wanted = Fraction(fn * dd - dn * fd, fd * dd)
            shell = (centre, k)
    if wanted is None:
        # (t_first + t_second) / 2, normalised once.
        wanted = Fraction(un * wd + wn * ud, 2 * ud * wd)
    near = () if tolerances is None else tolerances(s)
    try:
        # Only a point placed well can be used at a small input angle (unless exactness was asked first): the
        # search is told how far from wanted that is, and skips a fallback whose points are all farther.
        reach = None if exact_segments or not near else _reach(wanted, a, near)
        found = split_parameter_within(P, a, b, first, second, t_first, t_second, wanted, reach)
        if found is not None:
            t, x, y = found
            if exact_segments or not near:
                return t, x, y, shell, False
            if _placed_well_at_ends(t, wanted, a, near):
                return t, x, y, shell, False
        # The doubles exactly on the segment are too sparse here: the nearest is farther from the shell than a
        # small input angle tolerates, and the refinement would split on forever.  Rounded, as Triangle's are.
    except PrecisionLimitError as exc:
        if exact_segments:
            raise PrecisionLimitError(
                f"splitting the subsegment {int(lo)}–{int(hi)} (mesh vertices) of {geo.name(P, s)}: {exc}; "
                "the default, exact_segments=False, rounds split points to the nearest doubles there, as Triangle does"
            ) from None
    for t, x, y in rounded_candidates(P, a, b, lo, hi, t_first, t_second, wanted):
        return t, x, y, shell, True
    raise PrecisionLimitError(
        f"no pair of doubles lies strictly inside the subsegment {int(lo)}–{int(hi)} (mesh vertices) of {geo.name(P, s)}: "
        "the mesh is at the limit of double precision here"
    )


def rounded_candidates(
    P: GrowingPredicates2,
    a: int,
    b: int,
    u: int,
    w: int,
    tu: Fraction,
    tw: Fraction,
    wanted: Fraction,
) -> Iterator[tuple[Fraction, float, float]]:
    """Pairs of doubles near the subsegment ``uw`` of segment ``ab``, for a split where no double lies on it: best first.

    ``(t, x, y)``: a point near ``a + t (b − a)``.  Parameters: ``wanted`` clamped to the
    middle half of ``(tu, tw)`` first, then ``tu + k (tw − tu) / 16`` for ``k = 4 … 12``,
    nearest it first; around each exact point, the doubles up to :data:`_WINDOW` steps
    away on each axis, nearest first (exact squared distance), keeping those
    *near the segment* — the closed segment ``ab`` meets the closed box of half-width one
    unit in the last place of the largest magnitude among the point's and the segment's
    coordinates, axis by axis (exact clipping in rationals; ``verify_mesh``'s
    ``exact_segments=False`` accepts two) — whose projection lies strictly inside ``uw``.
    The first is the rounding to nearest of the exact point whenever that fits.

    Which of them makes a valid mesh depends on the cavity, so the caller inserts them in
    turn and keeps the first version that is valid (:meth:`~persistri.impl.mesh.ruppert.Refiner._split`).
    O(_WINDOW²) rational operations per parameter.
    """
    # first = wanted clamped to the middle half [(3 tu + tw) / 4, (tu + 3 tw) / 4], compared on integers (a Fraction
    # made only for a clamped end).
    un, ud = tu.as_integer_ratio()
    vn, vd = tw.as_integer_ratio()
    wn, wd = wanted.as_integer_ratio()
    first = wanted
    if (3 * un * vd + vn * ud) * wd > wn * 4 * ud * vd:
        first = Fraction(3 * un * vd + vn * ud, 4 * ud * vd)
    elif (un * vd + 3 * vn * ud) * wd < wn * 4 * ud * vd:
        first = Fraction(un * vd + 3 * vn * ud, 4 * ud * vd)
    (ia, ib, iu, iw), ex = P.integers(a, b, u, w)
    (fax, fay), (fbx, fby) = P.xy(a), P.xy(b)
    seen: set[tuple[float, float]] = set()
    for t in _parameters(first, tu, tw):
        # The exact point a + t (b − a) = (nx, ny) / t.den · 2^ex, and its nearest doubles (int / int rounds once).
        tn, td = t.as_integer_ratio()
        nx = ia[0] * td + tn * (ib[0] - ia[0])
        ny = ia[1] * td + tn * (ib[1] - ia[1])
        x0, y0 = _to_double(nx, td, ex), _to_double(ny, td, ex)
        skip: tuple[float, float] | None = None
        if not seen and _uniquely_nearest(nx, td, ex, x0) and _uniquely_nearest(ny, td, ex, y0):
            # (x0, y0) is then the strict minimum of the squared distance below, hence first in its order: when it
            # passes both tests it is the first candidate yielded, and the window is only needed if more are asked.
            r0x, r0y = x0.as_integer_ratio(), y0.as_integer_ratio()
            den0 = max(r0x[1], r0y[1], 1 << max(0, -ex))
            up0 = den0.bit_length() - 1 + ex
            along0 = ((r0x[0] * (den0 // r0x[1])) - (iu[0] << up0)) * ((iw[0] - iu[0]) << up0) + (
                (r0y[0] * (den0 // r0y[1])) - (iu[1] << up0)
            ) * ((iw[1] - iu[1]) << up0)
            span0 = ((iw[0] - iu[0]) << up0) ** 2 + ((iw[1] - iu[1]) << up0) ** 2
            # near_segment(fax, fay, fbx, fby, x0, y0) holds without a test when 0 <= t <= 1: the exact point
            # a + t (b − a) is then on the closed segment, and each coordinate's rounding to nearest is within half
            # the spacing of doubles there, at most ulp(x0) (resp. ulp(y0)), which is at most the box's half-width.
            if 0 < along0 < span0 and (0 <= tn <= td or near_segment(fax, fay, fbx, fby, x0, y0)):
                yield t, x0, y0
                skip = (x0, y0)
        xs, ys = _window(x0), _window(y0)
        # Everything in integer units 2^-J, J large enough for the window's doubles and for 2^ex.
        ratios_x = [v.as_integer_ratio() for v in xs]
        ratios_y = [v.as_integer_ratio() for v in ys]
        den = max(max(d for _, d in ratios_x), max(d for _, d in ratios_y), 1 << max(0, -ex))
        up = den.bit_length() - 1 + ex  # 2^ex in units 2^-J is 2^up, up >= 0
        ux, uy = iu[0] << up, iu[1] << up
        vx, vy = (iw[0] - iu[0]) << up, (iw[1] - iu[1]) << up
        px, py = nx << up, ny << up  # the exact point times td
        span = vx * vx + vy * vy
        near: list[tuple[int, float, float]] = []
        for x, (xn, xd) in zip(xs, ratios_x):
            ix = xn * (den // xd)
            for y, (yn, yd) in zip(ys, ratios_y):
                if (x, y) in seen:
                    continue
                seen.add((x, y))
                iy = yn * (den // yd)
                along = (ix - ux) * vx + (iy - uy) * vy
                if not 0 < along < span:
                    continue
                ex_, ey_ = ix * td - px, iy * td - py
                near.append((ex_ * ex_ + ey_ * ey_, x, y))
        near.sort()
        # The box test is the costly one: run it lazily, nearest first (the caller usually takes the first).
        for _, x, y in near:
            if skip is not None and (x, y) == skip:
                continue  # yielded above (the first of this order that passes)
            if near_segment(fax, fay, fbx, fby, x, y):
                yield t, x, y


def _uniquely_nearest(num: int, den: int, e: int, f: float) -> bool:
    """Whether the double ``f`` (the rounding of ``num / den · 2^e``, ``den > 0``) is strictly nearer to that value
    than both its neighbours: the value is no midpoint between ``f`` and one of them (exact, on integers). O(1)."""
    fn, fd = f.as_integer_ratio()
    for g in (math.nextafter(f, -math.inf), math.nextafter(f, math.inf)):
        if not math.isfinite(g):
            return False  # not decided here (the caller's window meets the same limit)
        gn, gd = g.as_integer_ratio()
        d = max(fd, gd)  # powers of two
        mid2 = fn * (d // fd) + gn * (d // gd)  # (f + g) = mid2 / d; a tie is 2 · num / den · 2^e = mid2 / d
        if e >= 0:
            if 2 * num * d << e == mid2 * den:
                return False
        elif 2 * num * d == (mid2 * den) << -e:
            return False
    return True


def _parameters(first: Fraction, tu: Fraction, tw: Fraction) -> Iterator[Fraction]:
    """:func:`_candidate_parameters` with ``delta = tw − tu`` computed only if a second parameter is asked for."""
    yield first
    rest = _candidate_parameters(first, tu, tw - tu)
    next(rest)  # first, yielded above
    yield from rest


def _candidate_parameters(first: Fraction, tu: Fraction, delta: Fraction) -> Iterator[Fraction]:
    """:func:`rounded_candidates`' parameters: ``first``, then ``tu + k · delta / 16`` for ``k = 4 … 12``, nearest
    ``first`` first (computed only if the caller asks beyond the first)."""
    yield first
    # |t_k − first| = (delta / 16) |k − c| with c = 16 (first − tu) / delta = cn / cd: the order of |k cd − cn|, on
    # integers (the parameters' denominators can be long), then of k (t_k grows with k); t_k = first when k = c.
    c = 16 * (first - tu) / delta
    cn, cd = c.numerator, c.denominator
    for k in sorted(range(4, 13), key=lambda k: (abs(k * cd - cn), k)):
        if k * cd != cn:
            yield tu + delta * k / 16


_WINDOW: Final[int] = 3
"""Doubles tried on each side of the nearest one, per axis, around a rounded split point."""


def _window(f: float) -> list[float]:
    """The double ``f``, then up to :data:`_WINDOW` more on each side, in increasing order."""
    below, above = [f], [f]
    for _ in range(_WINDOW):
        below.append(math.nextafter(below[-1], -math.inf))
        above.append(math.nextafter(above[-1], math.inf))
    return below[:0:-1] + above


def near_segment(ax: float, ay: float, bx: float, by: float, x: float, y: float, ulps: float = 1.0) -> bool:
    """Whether the closed segment ``ab`` meets the closed box of half-width ``ulps`` units in the last place of the
    largest magnitude per axis around ``(x, y)`` (parametric clipping, exact on integers). O(1).

    The box is :func:`~persistri.impl.mesh.verify.verify_mesh`'s tolerance box (its default is two units): a split
    point in it counts as on the segment there with ``exact_segments=False``.  Every number involved is a double
    (or ``ulps`` times a power of two), so all of them are integers over one power of two: the clipping
    parameters ``(c ± h − a) / (b − a)`` are compared as integer fractions, with no rational arithmetic."""
    # Integers over one common power of two (every double, and ulps · ulp exactly, is m / 2^j).
    un_, ud_ = ulps.as_integer_ratio()
    # Written out, without comprehensions (each would make a function frame per call).
    (nax, dax), (nbx, dbx), (nx, dx) = ax.as_integer_ratio(), bx.as_integer_ratio(), x.as_integer_ratio()
    (nay, day), (nby, dby), (ny, dy) = ay.as_integer_ratio(), by.as_integer_ratio(), y.as_integer_ratio()
    ux_, uxd = math.ulp(max(abs(ax), abs(bx), abs(x))).as_integer_ratio()
    uy_, uyd = math.ulp(max(abs(ay), abs(by), abs(y))).as_integer_ratio()
    hrx, hry = (un_ * ux_, ud_ * uxd), (un_ * uy_, ud_ * uyd)
    den = max(dax, dbx, dx, day, dby, dy, hrx[1], hry[1])
    iax, ibx, ix = nax * (den // dax), nbx * (den // dbx), nx * (den // dx)
    iay, iby, iy = nay * (den // day), nby * (den // dby), ny * (den // dy)
    ihx, ihy = hrx[0] * (den // hrx[1]), hry[0] * (den // hry[1])
    # lower = ln / ld, upper = un / ud (denominators positive), starting at [0, 1].
    ln, ld, un, ud = 0, 1, 1, 1
    for a, b, c, h in ((iax, ibx, ix, ihx), (iay, iby, iy, ihy)):
        lo, hi = c - h, c + h
        d = b - a
        if d == 0:
            if not lo <= a <= hi:
                return False
            continue
        if d > 0:
            tn_min, tn_max, td = lo - a, hi - a, d
        else:
            tn_min, tn_max, td = a - hi, a - lo, -d
        if tn_min * ld > ln * td:
            ln, ld = tn_min, td
        if tn_max * ud < un * td:
            un, ud = tn_max, td
    return ln * ud <= un * ld

