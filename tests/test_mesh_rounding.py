"""Rounded split points that must keep the mesh valid, and features closer than doubles can resolve.

Where no double lies on a subsegment, its split point is rounded to nearby
doubles (``exact_segments=False``, the default).  Off the segment's line by an
ulp, the nearest one can fall on the wrong side of an edge of its cavity when a
vertex lies about as close to the segment: the refiner then drops that version
and inserts the next nearby double (:func:`~persistri.impl.mesh.splitting.rounded_candidates`,
decided exactly).  An input vertex *inside the domain* that close to a segment
cannot be resolved by any mesh of doubles: the refiner says so, naming it.
"""

from __future__ import annotations

import math
import re
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from mesh_helpers import ring
from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.api import triangulate
from persistri.impl.mesh.chains import in_tolerance_box
from persistri.impl.mesh.domain import PSLG, DomainError, as_pslg
from persistri.impl.mesh.polyfile import read_poly
from persistri.impl.mesh.precision import BAND_ULPS, clear_of_band
from persistri.impl.mesh.splitting import _candidate_parameters, near_segment, rounded_candidates
from persistri.impl.mesh.steiner import PrecisionLimitError, _dyadic_double, _dyadic_split, _last_reducing_level
from persistri.impl.mesh.verify import verify_mesh

X0, Y0 = 512_345.0, 4_123_456.0
A, B = (X0, Y0), (X0 + 40.01, Y0 + 10.03)  # given to the centimetre: few doubles lie on A–B


def _exact_on(t: Fraction) -> tuple[Fraction, Fraction]:
    return Fraction(A[0]) + t * (Fraction(B[0]) - Fraction(A[0])), Fraction(A[1]) + t * (Fraction(B[1]) - Fraction(A[1]))


def _slot(v: tuple[float, float]) -> PSLG:
    """A box with a slot cut in from the right: its lower side is A–B, its upper side A–v–(far right), and ``v``
    lies within an ulp of A–B, *in the slot*: outside the domain."""
    pts = [(X0 - 10, Y0 - 20), (X0 + 60, Y0 - 20), (X0 + 60, Y0 + 10.03), B, A, v, (X0 + 60, Y0 + 25), (X0 + 60, Y0 + 50), (X0 - 10, Y0 + 50)]
    return as_pslg(np.array(pts), ring(len(pts)))


def test_rounded_candidates_lie_near_the_segment_nearest_first() -> None:
    P = GrowingPredicates2(np.array([A, B]))
    tried = list(rounded_candidates(P, 0, 1, 0, 1, Fraction(0), Fraction(1), Fraction(1, 2)))
    assert len(tried) > 8 and len({(x, y) for _, x, y in tried}) == len(tried)
    ex, ey = _exact_on(Fraction(1, 2))
    assert tried[0][1:] == (float(ex), float(ey))  # the rounding to nearest comes first
    a, b = np.array(A), np.array(B)
    for t, x, y in tried:
        # Within the checker's own tolerance box of one ulp (verify_mesh allows two), strictly between the ends.
        assert in_tolerance_box(np.array([x, y]), a, b, 1.0)
        along = (Fraction(x) - Fraction(A[0])) * (Fraction(B[0]) - Fraction(A[0])) + (Fraction(y) - Fraction(A[1])) * (
            Fraction(B[1]) - Fraction(A[1])
        )
        assert 0 < along < (Fraction(B[0]) - Fraction(A[0])) ** 2 + (Fraction(B[1]) - Fraction(A[1])) ** 2
    first = [(x, y) for t, x, y in tried if t == Fraction(1, 2)]
    gaps = [(Fraction(x) - ex) ** 2 + (Fraction(y) - ey) ** 2 for x, y in first]
    assert gaps == sorted(gaps)  # nearest first around each parameter
    assert {t for t, _, _ in tried} > {Fraction(1, 2)}  # then other parameters of the middle half


def test_a_rounded_split_that_would_invert_a_triangle_takes_another_double() -> None:
    # The slot's sides A–B and A–v are within an ulp of each other near v (v is an ulp from A–B's midpoint):
    # a split point of one, rounded to the nearest doubles, can fall beyond a split point of the other and invert a
    # triangle of the slot.  The refiner drops that version and inserts the next candidate; the mesh and every
    # version of its history are valid.
    v = (512365.005, 4123461.015)
    assert in_tolerance_box(np.array(v), np.array(A), np.array(B), 1.0)
    assert GrowingPredicates2(np.array([A, B, v])).orient2d_sign(0, 1, 2) > 0  # left of A → B: in the slot
    d = _slot(v)
    mesh = triangulate(d, min_angle=30, max_area=50.0)
    assert mesh.rounding_retries > 0 and mesh.rounded_splits > 0
    assert mesh.min_angle_reached and mesh.max_area_reached
    report = verify_mesh(d, mesh.vertices, mesh.triangles, min_angle=30, max_area=50.0, exact_segments=False)
    assert report.ok, report.problems[:3]
    for k in range(len(mesh.history)):
        arr = mesh.history.mesh(k)
        assert verify_mesh(d, arr.vertices, arr.triangles, exact_segments=False).ok, k


def _crowded(offset_ulps: float) -> tuple[PSLG, int]:
    """A quadrilateral lot with one side A–B and an input vertex inside it, ``offset_ulps`` y-ulps below A–B's
    midpoint (the nearest double there): its row."""
    ex, ey = _exact_on(Fraction(1, 2))
    x, y = float(ex), float(ey) - offset_ulps * math.ulp(float(ey))
    pts = np.array([(X0, Y0 - 30), (X0 + 45, Y0 - 30), B, A, (x, y)])
    return as_pslg(pts, ring(4)), 4


def test_an_input_vertex_within_an_ulp_of_a_segment_is_named() -> None:
    d, v = _crowded(1)
    cdt = triangulate(d, check=True)  # the constrained Delaunay triangulation holds it
    assert len(cdt.triangles) > 0
    with pytest.raises(PrecisionLimitError) as info:
        triangulate(d, min_angle=20)
    message = str(info.value)
    x, y = (float(c) for c in d.vertices[v])
    a, b = (f"({float(c[0])!r}, {float(c[1])!r})" for c in (B, A))
    assert message.startswith(f"input vertex {v} at ({x!r}, {y!r}) lies ")
    assert f"from segment 2 between {a} and {b}, without being on it" in message
    assert "units in the last place" in message and "\n" not in message


def _point(p: tuple[float, float]) -> str:
    return f"({float(p[0])!r}, {float(p[1])!r})"


def test_a_poly_file_s_segment_is_named_by_its_own_number(tmp_path: Path) -> None:
    # The lot of _crowded as a .poly numbered from 1 whose validation renumbers: a repeated corner (merged), a
    # vertex on the bottom side (which splits it in two) and a repeated side (merged).  The message names the
    # crowded vertex and segment by their rows in the file (counted from 0), not by the validated ones.
    lot, _ = _crowded(1)
    p0, p1, b, a, v = (tuple(float(c) for c in row) for row in lot.vertices)
    rows = [p0, p1, b, a, p0, (X0 + 20.0, Y0 - 30.0), v]  # row 4 repeats row 0; row 5 lies on p0–p1
    segs = [(0, 1), (1, 2), (2, 3), (3, 4), (1, 2)]  # row 2 is the crowded side B–A; row 4 repeats row 1
    text = [f"{len(rows)} 2 0 0"] + [f"{k + 1} {x!r} {y!r}" for k, (x, y) in enumerate(rows)]
    text += [f"{len(segs)} 0"] + [f"{k + 1} {i + 1} {j + 1}" for k, (i, j) in enumerate(segs)] + ["0"]
    path = tmp_path / "lot.poly"
    path.write_text("\n".join(text) + "\n")
    d = read_poly(path)
    assert d.vertices.shape[0] == 6 and d.segments.shape[0] == 5  # renumbered: v is row 5, B–A row 3
    assert d.segment_origin is not None and d.segment_origin.tolist() == [0, 0, 1, 2, 3]
    with pytest.raises(PrecisionLimitError) as info:
        triangulate(d, min_angle=20)
    message = str(info.value)
    assert message.startswith(f"input vertex 6 at {_point(v)} lies "), message
    assert f"from segment 2 between {_point(b)} and {_point(a)}, without being on it" in message, message
    assert "segment 3" not in message and "convex hull" not in message


def test_an_added_convex_hull_edge_is_named_as_such() -> None:
    # The same points with no segments, meshed as their convex hull (convex=True): the crowded side is an edge of
    # the hull that validation added; the message says so, and names no segment the caller never gave.
    lot, v = _crowded(1)
    d = as_pslg(lot.vertices, convex=True)
    hull = d.segment_origin
    assert hull is not None and hull.tolist() == [-1] * 4
    with pytest.raises(PrecisionLimitError) as info:
        triangulate(d, min_angle=20)
    message = str(info.value)
    x, y = (float(c) for c in d.vertices[v])
    assert message.startswith(f"input vertex {v} at ({x!r}, {y!r}) lies "), message
    ends = {f"{_point(B)}–{_point(A)}", f"{_point(A)}–{_point(B)}"}
    named = re.search(r"from the convex hull edge (\(.*?\)–\(.*?\)) \(a \.node file, or convex=True, is meshed as its "
                      r"convex hull\), without being on it", message)
    assert named is not None and named.group(1) in ends, message
    assert not re.search(r"segment \d", message)


def test_a_vertex_a_few_ulps_further_away_is_meshed() -> None:
    # Outside the band of two ulps the refinement resolves it (with edges of a few ulps).
    d, _ = _crowded(64)
    mesh = triangulate(d, min_angle=20)
    assert mesh.min_angle_reached
    assert verify_mesh(d, mesh.vertices, mesh.triangles, min_angle=20, exact_segments=mesh.rounded_splits == 0).ok


# -- fuzz: survey lots at UTM offsets ------------------------------------------------------------


@st.composite
def utm_lots(draw: st.DrawFn) -> PSLG:
    """A star-shaped lot of 5–9 corners given to the centimetre at a random UTM offset (slanted edges with no double
    between their ends are common), with 0–2 holes (buildings) and maybe a slanted internal crack (a fence)."""
    x0 = draw(st.integers(160_000, 830_000)) + draw(st.integers(0, 99)) / 100
    y0 = draw(st.integers(0, 9_300_000)) + draw(st.integers(0, 99)) / 100
    n = draw(st.integers(5, 9))
    gaps = draw(st.lists(st.floats(0.5, 1.0), min_size=n, max_size=n))
    turn = np.cumsum(gaps) / sum(gaps) * 2 * math.pi
    # No gap above 90°: every edge then stays beyond 0.7 of the smallest radius from the centre.
    assume(float(np.max(np.diff(np.r_[0.0, turn]))) <= math.pi / 2)
    rmin = 20.0
    rad = np.array(draw(st.lists(st.floats(rmin, 50.0), min_size=n, max_size=n)))
    outer = np.c_[rad * np.cos(turn), rad * np.sin(turn)]
    pts, segs, holes = [outer], ring(n), []
    for k in range(draw(st.integers(0, 2))):
        m = draw(st.integers(3, 6))
        centre = 0.45 * rmin * np.array([math.cos(math.pi * k), math.sin(math.pi * k)])
        ang = np.sort(np.array(draw(st.lists(st.floats(0, 2 * math.pi), min_size=m, max_size=m, unique=True))))
        assume(float(np.max(np.diff(np.r_[ang, ang[0] + 2 * math.pi]))) < math.pi * 0.9)  # the centre inside it
        r = np.array(draw(st.lists(st.floats(0.05 * rmin, 0.2 * rmin), min_size=m, max_size=m)))
        base = sum(len(p) for p in pts)
        pts.append(centre + np.c_[r * np.cos(ang), r * np.sin(ang)])
        segs += [[base + a, base + b] for a, b in ring(m)]
        holes.append(centre)
    if draw(st.booleans()):
        theta = math.pi / 2 + draw(st.floats(-0.5, 0.5))
        base = sum(len(p) for p in pts)
        pts.append(np.array([[0.1 * rmin * math.cos(theta), 0.1 * rmin * math.sin(theta)],
                             [0.6 * rmin * math.cos(theta), 0.6 * rmin * math.sin(theta)]]))
        segs.append([base, base + 1])
    verts = np.round(np.vstack(pts) + [x0, y0], 2)
    hole_pts = np.round(np.array(holes).reshape(-1, 2) + [x0, y0], 2)
    try:
        return as_pslg(verts, segs, holes=hole_pts)
    except DomainError:  # corners of a small hole that round to the same centimetre: not a lot
        assume(False)
        raise


@settings(max_examples=16)
@given(utm_lots(), st.sampled_from([20.0, 30.0, 33.0]), st.sampled_from([None, 40.0, 10.0, 4.0]))
def test_utm_lots_with_holes_refine_to_verified_meshes(domain: PSLG, angle: float, area: float | None) -> None:
    mesh = triangulate(domain, min_angle=angle, max_area=area)
    assert mesh.min_angle_reached and mesh.max_area_reached
    strict = mesh.rounded_splits == 0
    report = verify_mesh(domain, mesh.vertices, mesh.triangles, min_angle=angle, max_area=area, exact_segments=strict)
    assert report.ok, report.problems[:3]
    assert report.rounded_split_vertices == mesh.rounded_splits
    middle = mesh.history.mesh(len(mesh.history) // 2)  # an older version, still valid
    assert verify_mesh(domain, middle.vertices, middle.triangles, exact_segments=False).ok


def _near_segment_rational(ax: float, ay: float, bx: float, by: float, x: float, y: float, ulps: float) -> bool:
    """The tolerance-box clipping of :func:`near_segment`, in rationals: the checker's reference, ``in_tolerance_box``."""
    return in_tolerance_box(np.array([x, y]), np.array([ax, ay]), np.array([bx, by]), ulps)


_any_double = st.one_of(
    st.floats(-1e7, 1e7, allow_nan=False),
    st.floats(allow_nan=False, allow_infinity=False),
    st.sampled_from([0.0, -0.0, 5e-324, -5e-324, 2.2250738585072014e-308, 1.7976931348623157e308]),
)


@settings(max_examples=400, deadline=None)
@given(
    _any_double, _any_double, _any_double, _any_double, st.floats(0, 1), st.integers(-3, 3), st.integers(-3, 3),
    st.sampled_from([0.3, 0.5, 1.0, 1.5, 2.0]), st.booleans(),
)
def test_near_segment_on_integers_agrees_with_rationals(
    ax: float, ay: float, bx: float, by: float, t: float, sx: int, sy: int, ulps: float, vertical: bool
) -> None:
    """The integer clipping decides exactly as the rational one, near the segment (a few ulps off a point on it),
    on degenerate axes and on subnormal and huge coordinates, where ``ulps · ulp`` underflows a double."""
    if vertical:
        bx = ax
    x, y = ax + t * (bx - ax), ay + t * (by - ay)
    assume(math.isfinite(x) and math.isfinite(y))
    for _ in range(abs(sx)):
        x = math.nextafter(x, math.copysign(math.inf, sx))
    for _ in range(abs(sy)):
        y = math.nextafter(y, math.copysign(math.inf, sy))
    assume(math.isfinite(x) and math.isfinite(y))
    assert near_segment(ax, ay, bx, by, x, y, ulps) == _near_segment_rational(ax, ay, bx, by, x, y, ulps)
    assert near_segment(ax, ay, bx, by, bx, ay, ulps) == _near_segment_rational(ax, ay, bx, by, bx, ay, ulps)


@settings(max_examples=400, deadline=None)
@given(_any_double, _any_double, _any_double, _any_double, st.integers(0, 1 << 62), st.integers(0, 62))
@example(5e-324, -5e-324, 2.2250738585072014e-308, 1e-310, 1, 1)
@example(X0, Y0, X0 + 40.01, Y0 + 10.03, 1, 1)
@example(1.0, 1.0, 2.0, 2.0, (1 << 62) - 1, 62)  # rounds up onto the power of two 2.0: its ulp is twice as wide
def test_the_nearest_doubles_to_a_point_on_a_segment_pass_the_box_test(
    ax: float, ay: float, bx: float, by: float, num: int, bits: int
) -> None:
    """``rounded_candidates`` yields the rounding to nearest of a point of the closed segment without the box test:
    each coordinate's rounding error is at most ``ulp`` of the rounded value, the box's half-width at least that
    (subnormal, huge and UTM coordinates; a rounding onto a power of two)."""
    t = Fraction(min(num, 1 << bits), 1 << bits)  # in [0, 1]
    px, py = Fraction(ax) + t * (Fraction(bx) - Fraction(ax)), Fraction(ay) + t * (Fraction(by) - Fraction(ay))
    try:
        x, y = float(px), float(py)  # Fraction -> float rounds to nearest
    except OverflowError:
        return
    assume(math.isfinite(x) and math.isfinite(y))
    assert near_segment(ax, ay, bx, by, x, y)
    assert _near_segment_rational(ax, ay, bx, by, x, y, 1.0)


def test_dyadic_double_is_exact() -> None:
    """``n · 2^e`` is returned exactly when it is a double: 53-bit odd parts, subnormals down to 2^-1074, no overflow."""
    assert _dyadic_double(0, 5) == 0.0
    assert _dyadic_double(3, -1) == 1.5 and _dyadic_double(-12, -3) == -1.5
    assert _dyadic_double((1 << 53) - 1, 0) == float((1 << 53) - 1)
    assert _dyadic_double((1 << 53) + 1, 0) is None  # 54 significant bits
    assert _dyadic_double(1, -1074) == 5e-324 and _dyadic_double(1, -1075) is None
    assert _dyadic_double(3, -1075) is None and _dyadic_double(6, -1075) == 1.5e-323
    assert _dyadic_double(1, 1023) == 2.0**1023 and _dyadic_double(1, 1024) is None
    for n, e in ((5, 7), (-(2**52) - 1, -1100), (2**60, -2000)):
        got = _dyadic_double(n, e)
        exact = Fraction(n) * Fraction(2) ** e
        assert (got is not None) == (Fraction(float(exact)) == exact if abs(exact) < 2**1024 else False)
        if got is not None:
            assert Fraction(got) == exact


def _dyadic_split_rational(
    P: GrowingPredicates2, a: int, b: int, t_lo: Fraction, t_hi: Fraction, wanted: Fraction
) -> tuple[Fraction, float, float] | None:
    """The dyadic fallback of ``split_parameter`` written plainly in rationals, every candidate tried (the reference)."""
    delta = t_hi - t_lo
    lo_ok, hi_ok = t_lo + delta / 4, t_hi - delta / 4
    target = min(max(wanted, lo_ok), hi_ok)
    k0 = 0
    while Fraction(1, 1 << k0) > delta / 8:
        k0 += 1
    fine = min(k0 + 64, max(k0, target.denominator.bit_length() - 1))
    (xa, ya), (xb, yb) = (Fraction(v) for v in P.xy(a)), (Fraction(v) for v in P.xy(b))
    tried: set[Fraction] = set()
    for k in range(fine, k0 - 1, -1):
        unit = 1 << k
        base = math.floor(target * unit)
        for j in (base, base + 1) if target * unit - base <= Fraction(1, 2) else (base + 1, base):
            t = Fraction(j, unit)
            if t in tried or not lo_ok <= t <= hi_ok:
                continue
            tried.add(t)
            x, y = xa + t * (xb - xa), ya + t * (yb - ya)
            try:
                fx, fy = float(x), float(y)
            except OverflowError:
                continue
            if fx == x and fy == y:
                return t, fx, fy
    return None


@settings(max_examples=300, deadline=None)
@given(
    st.floats(-1e6, 1e6), st.floats(-1e6, 1e6), st.floats(-1e6, 1e6), st.floats(-1e6, 1e6),
    st.integers(0, 2**20), st.integers(1, 2**20), st.integers(0, 60), st.integers(0, 1000),
)
def test_dyadic_split_agrees_with_the_plain_search(
    xa: float, ya: float, xb: float, yb: float, lo_num: int, width: int, shift: int, at: int
) -> None:
    """The dyadic fallback on integers, with its levels skipped where a coordinate cannot be a double, returns the
    candidate the plain rational search returns (the first that is a pair of doubles), or fails where it fails."""
    assume((xa, ya) != (xb, yb))
    P = GrowingPredicates2(np.array([[xa, ya], [xb, yb]]))
    denominator = 2**21 << shift
    t_lo = Fraction(lo_num, denominator)
    t_hi = t_lo + Fraction(width, denominator)
    assume(t_hi <= 1)
    wanted = t_lo + (t_hi - t_lo) * Fraction(at, 1000)
    expected = _dyadic_split_rational(P, 0, 1, t_lo, t_hi, wanted)
    if expected is None:
        with pytest.raises(PrecisionLimitError):
            _dyadic_split(P, 0, 1, t_lo, t_hi, wanted)
    else:
        assert _dyadic_split(P, 0, 1, t_lo, t_hi, wanted) == expected


@settings(max_examples=300)
@given(st.integers(0, 2**70), st.integers(1, 2**70), st.integers(0, 40))
@example(1, 4, 0)  # 2^-k at exactly the distance below the target: the strict side
@example(3, 4, 0)  # and above it: the side that counts equality
@example(5, 16, 1)
@example(0, 7, 3)  # on the grid: every level
def test_last_reducing_level_is_the_highest_level_with_a_reducing_candidate(tn: int, td: int, bound: int) -> None:
    """Above the returned level no candidate (floor(target · 2^k) or one more) reduces to a level at most ``bound``;
    at every level from ``bound`` up to it one does: checked level by level against the definition."""
    assume(tn <= td)
    top = _last_reducing_level(tn, td, bound)

    def reduces(k: int) -> bool:
        j = (tn << k) // td
        return any(c % (1 << (k - bound)) == 0 for c in (j, j + 1))

    for k in range(bound + 1, bound + 90):
        assert reduces(k) == (k <= top), (k, top)


def test_dyadic_split_on_the_needle_agrees_with_the_plain_search(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every call the needle's refinement makes (coordinates not snapped, sides 1e-6 rad apart: the lattice of
    doubles on a side is sparse, and the fallback runs), and the same intervals shifted along the sides."""
    import persistri.impl.mesh.steiner as steiner
    from persistri.impl.mesh.gallery import gallery_domain

    calls: list[tuple[GrowingPredicates2, int, int, Fraction, Fraction, Fraction]] = []
    real = steiner._dyadic_split

    def spy(
        P: GrowingPredicates2, a: int, b: int, t_lo: Fraction, t_hi: Fraction, wanted: Fraction, reach: Any = None
    ) -> tuple[Fraction, float, float] | None:
        calls.append((P, a, b, t_lo, t_hi, wanted))  # the search itself is checked below without a reach
        return real(P, a, b, t_lo, t_hi, wanted, reach)

    monkeypatch.setattr(steiner, "_dyadic_split", spy)
    triangulate(gallery_domain("needle").pslg, min_angle=30)
    assert len(calls) > 10
    found = failed = 0
    for P, a, b, t_lo, t_hi, wanted in calls:
        for shift in (Fraction(0), (t_hi - t_lo) / 3, -(t_hi - t_lo) / 7):
            lo, hi, w = t_lo + shift, t_hi + shift, wanted + shift
            if not 0 <= lo < hi <= 1:
                continue
            expected = _dyadic_split_rational(P, a, b, lo, hi, w)
            if expected is None:
                with pytest.raises(PrecisionLimitError):
                    real(P, a, b, lo, hi, w)
                failed += 1
            else:
                assert real(P, a, b, lo, hi, w) == expected
                found += 1
    assert found >= 1 and failed > 10  # on the needle the search mostly fails: the split point is then rounded


@settings(max_examples=300, deadline=None)
@given(
    st.floats(-1e7, 1e7), st.floats(-1e7, 1e7), st.floats(-1e7, 1e7), st.floats(-1e7, 1e7), st.floats(-0.5, 1.5),
    st.integers(-6, 6), st.integers(-6, 6), st.sampled_from([0.0, 1e-12, 1e-9, 1e-3, 1.0]),
)
def test_band_filter_never_clears_a_point_in_the_band(
    xa: float, ya: float, xb: float, yb: float, t: float, sx: int, sy: int, away: float
) -> None:
    """``clear_of_band`` (the float filter before the exact tolerance-band test) says "outside" only where
    ``near_segment`` says so too: points a few ulps off the segment, and farther off its line."""
    assume((xa, ya) != (xb, yb))
    x, y = xa + t * (xb - xa) - away * (yb - ya), ya + t * (yb - ya) + away * (xb - xa)
    for _ in range(abs(sx)):
        x = math.nextafter(x, math.copysign(math.inf, sx))
    for _ in range(abs(sy)):
        y = math.nextafter(y, math.copysign(math.inf, sy))
    P = GrowingPredicates2(np.array([[xa, ya], [xb, yb], [x, y]]))
    if clear_of_band(P, 0, 1, 2, xa, ya, xb, yb, x, y):
        assert not near_segment(xa, ya, xb, yb, x, y, BAND_ULPS)


def test_band_filter_decides_the_far_points() -> None:
    """The filter is what the refiner meets first for every apex beside a subsegment: far apexes are cleared
    without exact arithmetic, and an apex an ulp off a UTM segment is left to the exact test."""
    P = GrowingPredicates2(np.array([A, B, (X0 + 20.0, Y0 + 9.0), (X0 + 20.005, Y0 + 5.015)]))
    (xa, ya), (xb, yb) = A, B
    assert clear_of_band(P, 0, 1, 2, xa, ya, xb, yb, *P.xy(2))
    ex, ey = _exact_on(Fraction(1, 2))
    near = GrowingPredicates2(np.array([A, B, (float(ex), float(ey))]))
    assert not clear_of_band(near, 0, 1, 2, xa, ya, xb, yb, float(ex), float(ey))


@settings(max_examples=200, deadline=None)
@given(st.fractions(0, 1), st.fractions(Fraction(1, 10**30), 1), st.fractions(0, 1))
def test_candidate_parameters_in_the_order_of_their_distance(tu: Fraction, delta: Fraction, at: Fraction) -> None:
    """The parameters after the first come nearest it first (ties: the smaller), as a plain sort of the rationals
    orders them — the order is computed on integers, the parameters' denominators can be long."""
    first = min(max(tu + delta * at, tu + delta / 4), tu + delta - delta / 4)
    plain = [t for t in sorted((tu + delta * k / 16 for k in range(4, 13)), key=lambda t: (abs(t - first), t)) if t != first]
    assert list(_candidate_parameters(first, tu, delta)) == [first, *plain]


def _reference_candidates(
    P: GrowingPredicates2, a: int, b: int, u: int, w: int, tu: Fraction, tw: Fraction, wanted: Fraction
) -> list[tuple[Fraction, float, float]]:
    """``rounded_candidates`` written plainly in rationals: for each parameter, the window of doubles around the
    exact point, those strictly between u and w, nearest first, that pass the box test."""
    delta = tw - tu
    first = min(max(wanted, tu + delta / 4), tw - delta / 4)
    (ax, ay), (bx, by), (ux, uy), (wx, wy) = ([Fraction(v) for v in P.xy(i)] for i in (a, b, u, w))
    seen: set[tuple[float, float]] = set()
    out: list[tuple[Fraction, float, float]] = []
    for t in _candidate_parameters(first, tu, delta):
        px, py = ax + t * (bx - ax), ay + t * (by - ay)
        xs, ys = [float(px)], [float(py)]  # Fraction -> float rounds to nearest
        for v in (xs, ys):
            for step in (-math.inf, math.inf):
                f = v[0]
                for _ in range(3):
                    f = math.nextafter(f, step)
                    v.append(f)
        near = []
        for x in sorted(xs):
            for y in sorted(ys):
                if (x, y) in seen:
                    continue
                seen.add((x, y))
                along = (Fraction(x) - ux) * (wx - ux) + (Fraction(y) - uy) * (wy - uy)
                if 0 < along < (wx - ux) ** 2 + (wy - uy) ** 2:
                    near.append(((Fraction(x) - px) ** 2 + (Fraction(y) - py) ** 2, x, y))
        near.sort()
        fa, fb = P.xy(a), P.xy(b)
        out += [(t, x, y) for _, x, y in near if near_segment(fa[0], fa[1], fb[0], fb[1], x, y)]
    return out


@settings(max_examples=150, deadline=None)
@given(
    st.integers(-50, 50), st.integers(-50, 50), st.integers(-50, 50), st.integers(-50, 50),
    st.sampled_from([1.0, 3.0, 1e5, 4e6]), st.integers(1, 15), st.integers(1, 15),
)
def test_rounded_candidates_agree_with_the_plain_search(
    i: int, j: int, k: int, m: int, base: float, num: int, den_bits: int
) -> None:
    # Ends a few ulps apart at several magnitudes, and dyadic parameters: exact points that are doubles, midpoints
    # between two doubles (ties of the nearest) and neither.  The whole sequence must agree, not only the first.
    ulp = math.ulp(base)
    A_, B_ = (base + i * ulp, base + j * ulp), (base + (k + 400) * ulp, base + (m + 900) * ulp)
    P = GrowingPredicates2(np.array([A_, B_]))
    wanted = Fraction(num % (1 << den_bits) or 1, 1 << den_bits)
    assert list(rounded_candidates(P, 0, 1, 0, 1, Fraction(0), Fraction(1), wanted)) == _reference_candidates(
        P, 0, 1, 0, 1, Fraction(0), Fraction(1), wanted
    )


def test_rounded_candidates_agree_on_the_gallery_utm_edge() -> None:
    P = GrowingPredicates2(np.array([A, B]))
    for wanted in (Fraction(1, 2), Fraction(1, 3), Fraction(5, 8), Fraction(1, 2) + Fraction(1, 1 << 60)):
        assert list(rounded_candidates(P, 0, 1, 0, 1, Fraction(0), Fraction(1), wanted)) == _reference_candidates(
            P, 0, 1, 0, 1, Fraction(0), Fraction(1), wanted
        )


@pytest.mark.parametrize("apex", [1e-30, 1e-150, 1e-200, 1e-300])
def test_a_steiner_point_that_rounding_moves_far_is_refused_at_once(apex: float) -> None:
    # A thin triangle whose apex is `apex` above its base: the off-centres of its needles lie a few `apex` from
    # the base's midpoint, and the doubles nearest them are on the line x = 0.5 itself.  Without the check the
    # refiner inserted points on that line without end from 1e-150 down (H7's report); at 1e-30 it stopped only
    # after 55 insertions, when one rounded onto a vertex.
    d = {"vertices": np.array([[0.0, 0.0], [1.0, 0.0], [0.5, apex]]), "segments": np.array([[0, 1], [1, 2], [2, 0]])}
    with pytest.raises(PrecisionLimitError) as info:
        triangulate(d, min_angle=20, max_steiner=500)
    message = str(info.value)
    assert "rounding moves it by an eighth of the triangle's shortest edge" in message
    # The distance in the message is the exact one, not a square root that underflowed to 0.
    assert f"lies {apex:.2g} (" in message, message


@pytest.mark.parametrize("apex", [1e-3, 1e-10])
def test_thin_triangles_that_doubles_resolve_are_meshed(apex: float) -> None:
    d = {"vertices": np.array([[0.0, 0.0], [1.0, 0.0], [0.5, apex]]), "segments": np.array([[0, 1], [1, 2], [2, 0]])}
    m = triangulate(d, min_angle=20)
    assert m.min_angle_reached
    assert verify_mesh(d, m.vertices, m.triangles, min_angle=20, exact_segments=m.rounded_splits == 0).ok
