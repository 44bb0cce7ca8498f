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
  of doubles on the segment).  Where no double lies on the subsegment the
  exact point is rounded to the nearest doubles instead, as Triangle's split
  points are (``exact_segments=False``, the default; reported as *rounded*), or
  :class:`~persistri.impl.mesh.steiner.PrecisionLimitError` is raised
  (``exact_segments=True``).

Costs: O(1) exact operations, plus O(segments) once per pair (vertex, segment)
for the small-angle test (memoised by the caller).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from fractions import Fraction

from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.angles import angle_at_least
from persistri.impl.mesh.cdt import SegmentGeometry, param_on_segment
from persistri.impl.mesh.steiner import PrecisionLimitError, point_at, split_parameter
from persistri.impl.mesh.triangulation import MeshDatum, Tri, constraint_of

__all__ = ["SplitPoint", "split_point", "small_angle_at", "shell_exponent"]

SplitPoint = tuple[Fraction, float, float, "tuple[int, int] | None", bool]
"""``(t, x, y, shell, rounded)``: the parameter on the segment, the point, the shell ``(o, k)`` it lies on (or
None) and whether it was rounded off the subsegment."""


def small_angle_at(P: GrowingPredicates2, geo: SegmentGeometry, o: int, s: int) -> bool:
    """Whether input vertex ``o`` is an end of segment ``s`` where another segment meets ``s`` at less than 60° (exact).

    O(segments): the caller memoises it."""
    if o >= geo.n_input or geo.incident[o] < 2:
        return False
    a, b = geo.ends[s]
    far = b if a == o else a
    for t, (c, d) in enumerate(geo.ends):
        if t == s or o not in (c, d) or c == d:
            continue
        other = d if c == o else c
        (io, ip, iq), _ = P.integers(o, far, other)
        d1, d2 = (ip[0] - io[0], ip[1] - io[1]), (iq[0] - io[0], iq[1] - io[1])
        if not angle_at_least(d1[0] * d2[0] + d1[1] * d2[1], d1[0] ** 2 + d1[1] ** 2, d2[0] ** 2 + d2[1] ** 2, 60.0):
            return True
    return False


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
) -> SplitPoint:
    """The point splitting the subsegment ``{lo, hi}`` of segment ``s`` (module docstring).

    ``sides``: the triangles beside it (None where there is none); ``small(o, s)``: the memoised
    :func:`small_angle_at`.  :class:`PrecisionLimitError` in strict mode where no double lies on the subsegment,
    or when even the rounded point falls on an end.  O(1).
    """
    tu, tw = param_on_segment(P, geo, s, lo), param_on_segment(P, geo, s, hi)
    first, second = (lo, hi) if tu < tw else (hi, lo)
    t_first, t_second = min(tu, tw), max(tu, tw)
    a, b = geo.ends[s]
    small_lo, small_hi = small(lo, s), small(hi, s)
    if small_lo != small_hi:
        centre: int | None = lo if small_lo else hi
    else:
        at_lo, at_hi = _corner_ends(lo, hi, sides)
        centre = hi if at_hi else lo if at_lo else None
    wanted = (t_first + t_second) / 2
    shell: tuple[int, int] | None = None
    if centre is not None:
        other = hi if centre == lo else lo
        (po, pt), e = P.integers(centre, other)
        length = math.hypot(po[0] - pt[0], po[1] - pt[1]) * 2.0**e
        (pa, pb), e2 = P.integers(a, b)
        total = math.hypot(pa[0] - pb[0], pa[1] - pb[1]) * 2.0**e2
        if length > 0 and total > 0 and math.isfinite(length) and math.isfinite(total):
            k = shell_exponent(length)
            dt = Fraction(2.0**k / total)
            t_o = param_on_segment(P, geo, s, centre)
            wanted = t_o + dt if t_o == t_first else t_o - dt
            shell = (centre, k)
    try:
        t, x, y = split_parameter(P, a, b, first, second, t_first, t_second, wanted)
        return t, x, y, shell, False
    except PrecisionLimitError as exc:
        if exact_segments:
            raise PrecisionLimitError(
                f"splitting segment {s} between vertices {int(lo)} and {int(hi)}: {exc}; "
                "the default, exact_segments=False, rounds split points to the nearest doubles there, as Triangle does"
            ) from None
    t, x, y = _rounded(P, a, b, lo, hi, t_first, t_second, wanted)
    return t, x, y, shell, True


def _neighbours(v: Fraction) -> list[float]:
    """The doubles nearest ``v`` from below and above (one if ``v`` is a double)."""
    f = float(v)
    if Fraction(f) == v:
        return [f]
    return [f, math.nextafter(f, math.inf)] if Fraction(f) < v else [math.nextafter(f, -math.inf), f]


def _rounded(
    P: GrowingPredicates2,
    a: int,
    b: int,
    u: int,
    w: int,
    tu: Fraction,
    tw: Fraction,
    wanted: Fraction,
) -> tuple[Fraction, float, float]:
    """The point of segment ``ab`` at parameter ``wanted`` (clamped to the middle half of ``(tu, tw)``), rounded to
    the nearest pair of doubles — off the segment by at most half an ulp per coordinate, as Triangle's split points
    are — or, if that is an end of the subsegment, the next nearest of the four around it.
    :class:`PrecisionLimitError` if all four fall on an end."""
    delta = tw - tu
    t = min(max(wanted, tu + delta / 4), tw - delta / 4)
    ex, ey = point_at(P, a, b, t)
    ends = {P.xy(u), P.xy(w)}
    candidates = sorted(
        ((x, y) for x in _neighbours(ex) for y in _neighbours(ey)),
        key=lambda q: (Fraction(q[0]) - ex) ** 2 + (Fraction(q[1]) - ey) ** 2,
    )
    for x, y in candidates:
        if (x, y) not in ends:
            return t, x, y
    raise PrecisionLimitError(
        f"every pair of doubles next to the split point of the subsegment between vertices {int(u)} and {int(w)} "
        "is one of its ends: the mesh is at the limit of double precision here"
    )
