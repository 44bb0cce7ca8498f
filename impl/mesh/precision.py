"""Where a quality mesh of doubles cannot exist: input features closer than the spacing of doubles (paper §1).

Every vertex of persistri's meshes is a pair of doubles and every decision about
them is exact, so the refinement never goes wrong *silently* near the limit of
double precision; but it can be asked for what doubles cannot hold.  Ruppert's
refinement resolves the *local feature size*: near an input vertex that lies a
distance ``d`` from a segment it is not on, the mesh needs edges about ``d``
long.  When ``d`` is below the spacing of doubles there (Triangle's own
example files have such vertices: a convex hull edge passing a tenth of an ulp
from a vertex, a split point of an earlier run read back as an input vertex),
no mesh of doubles meets the angle bound — Triangle itself fails or loops on
them — and the refiner says so, naming the vertex and the segment:

* :func:`crowded_apex` — before a subsegment is split: a vertex beside it (the
  apex of a triangle on it) that is not on the segment but lies in its
  *tolerance band* — the segment meets the vertex's box of half-width two units
  in the last place (the box in which :func:`~persistri.impl.mesh.verify.verify_mesh`
  would count a split point as on the segment; exact) — is such a feature;
* :func:`valid_split` — after a rounded split point is inserted: whether the
  new version is a valid mesh (decided exactly; the refiner tries the next nearby
  double if not, :func:`~persistri.impl.mesh.splitting.rounded_candidates`);
* :func:`nearest_features` — the text added to any
  :class:`~persistri.impl.mesh.steiner.PrecisionLimitError`: the input vertex
  nearest the place where it happened and its distance to the nearest segment
  it is not on, in metres and in units in the last place.

Costs: :func:`crowded_apex` and :func:`valid_split` O(1) / O(cavity) exact
operations; :func:`nearest_features` O(n + m) floating-point work and O(m) exact
operations, once, when the run fails.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from persistri.impl.geometry.filter import ERRBOUND_ORIENT2D, orient2d_terms
from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.cdt import SegmentGeometry
from persistri.impl.mesh.splitting import near_segment
from persistri.impl.mesh.triangulation import EXTERIOR, Insertion, constraint_of

__all__ = [
    "BAND_ULPS",
    "clear_of_band",
    "crowded_apex",
    "valid_split",
    "nearest_features",
    "segment_distance2",
]

BAND_ULPS = 2.0
"""Half-width of the tolerance band around a segment, in units in the last place (``verify_mesh``'s default)."""


def segment_distance2(P: GrowingPredicates2, v: int, a: int, b: int) -> Fraction:
    """The exact Euclidean distance from point ``v`` to the closed segment ``ab``, squared. O(1)."""
    (pv, pa, pb), e = P.integers(v, a, b)
    dx, dy = pb[0] - pa[0], pb[1] - pa[1]
    wx, wy = pv[0] - pa[0], pv[1] - pa[1]
    length2 = dx * dx + dy * dy
    along = wx * dx + wy * dy
    scale = Fraction(2) ** (2 * e)
    if length2 == 0 or along <= 0:
        return (wx * wx + wy * wy) * scale
    if along >= length2:
        ux, uy = pv[0] - pb[0], pv[1] - pb[1]
        return (ux * ux + uy * uy) * scale
    cross = dx * wy - dy * wx
    return Fraction(cross * cross, length2) * scale


def _sqrt(f: Fraction) -> float:
    """``√f`` as a double, also where ``f`` itself is below the smallest double (a distance of 1e-200). O(1)."""
    if f <= 0:
        return 0.0
    m = (f.denominator.bit_length() - f.numerator.bit_length()) // 2  # f · 4^m is near 1
    return math.ldexp(math.sqrt(f * 4**m if m >= 0 else f / 4**-m), -m)


def _ulps(P: GrowingPredicates2, v: int, a: int, b: int) -> float:
    """One unit in the last place of the largest coordinate magnitude among ``v``, ``a`` and ``b``."""
    return math.ulp(max(abs(c) for i in (v, a, b) for c in P.xy(i)))


def _describe(P: GrowingPredicates2, geo: SegmentGeometry, v: int, s: int) -> str:
    """``v`` and its distance to segment ``s``, in coordinates; an input vertex and the segment named as the user
    wrote them (input rows counted from 0; an added convex hull edge as such: ``geo.names``)."""
    a, b = geo.ends[s]
    d = _sqrt(segment_distance2(P, v, a, b))
    who = f"input vertex {geo.names.vertex(v)}" if v < geo.n_input else f"vertex {int(v)}"
    return (
        f"{who} at {_at(P, v)} lies {d:.2g} ({d / _ulps(P, v, a, b):.2g} units in the last place) from "
        f"{geo.name(P, s)}, without being on it"
    )


def _at(P: GrowingPredicates2, v: int) -> str:
    x, y = P.xy(v)
    return f"({x!r}, {y!r})"


def crowded_apex(P: GrowingPredicates2, geo: SegmentGeometry, s: int, apex: int) -> str | None:
    """A description of ``apex`` when it is off segment ``s`` but in its tolerance band (module docstring), else None.

    Exact. O(1)."""
    if apex < 0:
        return None
    a, b = geo.ends[s]
    if apex in (a, b):
        return None
    on = geo.on_segment.get(apex)
    if on is not None and on[0] == s:
        return None
    (ax, ay), (bx, by), (x, y) = P.xy(a), P.xy(b), P.xy(apex)
    if clear_of_band(P, a, b, apex, ax, ay, bx, by, x, y):
        return None
    if P.orient2d_sign(a, b, apex) == 0:
        return None
    if not near_segment(ax, ay, bx, by, x, y, BAND_ULPS):
        return None
    return _describe(P, geo, apex, s)


_FAR_SLACK = 1.0 + 2.0**-30
"""Relative slack over the few roundings of :func:`clear_of_band`'s threshold."""

_TINY = 2.0**-400
"""Below this the band's float filter is not used (its products could underflow)."""


def clear_of_band(
    P: GrowingPredicates2, a: int, b: int, v: int, ax: float, ay: float, bx: float, by: float, x: float, y: float
) -> bool:
    """True only if point ``v`` at ``(x, y)`` is certainly outside the tolerance band of segment ``ab`` (the
    segment misses its box, :func:`~persistri.impl.mesh.splitting.near_segment` with ``BAND_ULPS``): a float
    filter that decides the common case, far away, in O(1); False means "not decided".

    The box ``[x ± h_x] × [y ± h_y]`` meets the *line* ``ab`` exactly when ``|orient2d(a, b, v)| <= |Δx| h_y +
    |Δy| h_x`` (``Δ = b − a``: moving ``v`` by ``(e_x, e_y)`` moves the determinant by ``Δx e_y − Δy e_x``), and
    the segment lies on the line.  On the predicates' scaled copies (where the error model of
    :func:`~persistri.impl.geometry.filter.orient2d_terms` holds: its result is within ``ERRBOUND_ORIENT2D ·
    permanent`` of the exact determinant) the test is decided when ``|det|`` exceeds that error plus the right side
    by the slack.  NaN rows (no filter copy) and tiny values give False."""
    rows = P.filter_rows
    sax, say = rows[a]
    sbx, sby = rows[b]
    sx, sy = rows[v]
    shift = P.shift
    hx = math.ldexp(BAND_ULPS * math.ulp(max(abs(ax), abs(bx), abs(x))), shift)
    hy = math.ldexp(BAND_ULPS * math.ulp(max(abs(ay), abs(by), abs(y))), shift)
    dx, dy = abs(sbx - sax), abs(sby - say)
    if not (hx >= _TINY and hy >= _TINY and (dx == 0.0 or dx >= _TINY) and (dy == 0.0 or dy >= _TINY)):
        return False
    det, perm = orient2d_terms(sax, say, sbx, sby, sx, sy)
    reach = dx * hy + dy * hx
    return abs(det) > (ERRBOUND_ORIENT2D * perm + reach) * _FAR_SLACK


def valid_split(P: GrowingPredicates2, step: Insertion, lo: int, hi: int) -> bool:
    """Whether inserting a rounded split point of the subsegment ``{lo, hi}`` made a valid version. O(cavity).

    Every new finite triangle strictly counterclockwise (exact), the old subsegment gone from the
    domain, and no vertex lost: the triangle beyond the subsegment is removed whatever its circle says
    and the conflict search goes on from it, so a vertex near the segment can end up inside the cavity.
    """
    orient = P.orient2d_sign
    # Loops, not a comprehension and a generator: no function frame per call.
    kept: set[int] = set()
    for (a, b, c), _ in step.created:
        kept.add(a)
        kept.add(b)
        kept.add(c)
    for (a, b, c), _ in step.removed:
        if a not in kept or b not in kept or c not in kept:
            return False
    for tri, dat in step.created:
        a, b, c = tri
        if lo in tri and hi in tri and (dat[1] != EXTERIOR or constraint_of(dat, lo, hi) >= 0):
            return False
        if a >= 0 and b >= 0 and c >= 0 and orient(a, b, c) <= 0:
            return False
    return True


def nearest_features(P: GrowingPredicates2, geo: SegmentGeometry, x: float, y: float) -> str:
    """What lies closest together near ``(x, y)``: the input vertex nearest it and the nearest segment it is off.

    For the message of a :class:`~persistri.impl.mesh.steiner.PrecisionLimitError` (a report: the search
    is in floating point, the distance exact).  Empty when there is no segment."""
    n = geo.n_input
    if n == 0 or not geo.ends:
        return ""
    pts = P.points[:n]
    near = np.argsort(np.hypot(pts[:, 0] - x, pts[:, 1] - y))[:8]
    ends = np.array(geo.ends, dtype=np.intp)
    a, b = P.points[ends[:, 0]], P.points[ends[:, 1]]
    d = b - a
    length2 = np.maximum((d * d).sum(axis=1), np.finfo(float).tiny)
    best: tuple[float, int, int] | None = None
    for v in near.tolist():
        w = pts[v] - a
        t = np.clip((w * d).sum(axis=1) / length2, 0.0, 1.0)
        gap = np.hypot(w[:, 0] - t * d[:, 0], w[:, 1] - t * d[:, 1])
        for s in np.argsort(gap)[:4].tolist():
            if v in geo.ends[s] or P.orient2d_sign(geo.ends[s][0], geo.ends[s][1], v) == 0:
                continue
            ulps = _sqrt(segment_distance2(P, v, *geo.ends[s])) / _ulps(P, v, *geo.ends[s])
            if best is None or ulps < best[0]:
                best = (ulps, v, s)
    if best is None:
        return ""
    return f"; the closest input features there: {_describe(P, geo, best[1], best[2])}"
