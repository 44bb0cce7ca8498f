"""Ruppert's refinement with undo by persistence (impl/mesh/ruppert.py): bounds reached exactly, undos, Triangle's counts."""

from __future__ import annotations

import math
import re
from fractions import Fraction

import numpy as np
import pytest
import triangle as tr
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from mesh_helpers import (
    check_mesh,
    check_quality,
    check_verified,
    circle,
    hole_square_area2,
    l_shape,
    polygon_area2,
    pslgs,
    ring,
    square_with_hole,
    star,
)
from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.api import QualityMesh, triangulate
from persistri.impl.mesh.domain import PSLG, as_pslg
from persistri.impl.mesh.errors import DomainError
from persistri.impl.mesh.steiner import PrecisionLimitError, split_parameter

DOMAINS = {
    "square-hole": (square_with_hole, 0.05),
    "L": (l_shape, 0.01),
    "star": (star, None),
    "circle": (circle, None),
}


def _checked(d: PSLG, m: QualityMesh) -> None:
    check_quality(m.vertices, m.triangles, m.min_angle, m.max_area, exempt=m.exempt)
    if m.rounded_splits:
        # Split points rounded where no double lies on the segment: the checker's tolerance box, and nothing less.
        from persistri.impl.mesh.verify import verify_mesh

        loose = verify_mesh(d, m.vertices, m.triangles, min_angle=m.min_angle, max_area=m.max_area, exact_segments=False)
        assert loose.ok and loose.rounded_split_vertices == m.rounded_splits, loose.problems[:3]
        strict = verify_mesh(d, m.vertices, m.triangles, exact_segments=True)
        assert "segment-rounding" in strict.kinds()
        return
    check_mesh(d, m.vertices, m.triangles, m.segments, m.segment_of)
    check_verified(d, m)


@pytest.mark.parametrize("name", sorted(DOMAINS))
@pytest.mark.parametrize("angle", [20.0, 30.0, 33.0])
def test_bound_reached_exactly(name: str, angle: float) -> None:
    make, area = DOMAINS[name]
    d = make()
    m = triangulate(d, min_angle=angle, max_area=area)
    assert m.min_angle_reached and m.max_area_reached
    _checked(d, m)
    assert m.insertions == m.segment_splits + m.circumcenters + m.offcenters == len(m.history) - 1


def test_square_with_hole_area_is_kept() -> None:
    d = square_with_hole()
    m = triangulate(d, min_angle=30, max_area=0.1)
    check_mesh(d, m.vertices, m.triangles, m.segments, m.segment_of, area2=hole_square_area2(d))


def test_l_shape_area_is_kept() -> None:
    d = l_shape()
    m = triangulate(d, min_angle=33, max_area=0.02)
    check_mesh(d, m.vertices, m.triangles, m.segments, m.segment_of, area2=polygon_area2(d.vertices, list(range(6))))


def test_circumcentres_near_the_boundary_are_undone() -> None:
    # The L's reflex corner and its long edges make circumcentres fall near segments: the undo path is taken.
    m = triangulate(l_shape(), min_angle=30, max_area=0.01)
    assert m.undos > 0
    # Undone points are in the point set but in no version of the history.
    used = {int(v) for c in m.history for t, _ in m.history.structure.items(c) for v in t}
    undone = set(range(len(m._run.T.pred))) - used - set(range(m.domain.vertices.shape[0]))
    assert len(undone) >= m.undos


def test_without_undo_a_thin_domain_needs_none() -> None:
    # A square refined by area alone, far from its boundary after the first splits: a control for the count.
    m = triangulate(as_pslg([[0, 0], [1, 0], [1, 1], [0, 1]], ring(4)), min_angle=0.0, max_area=0.3)
    assert m.max_area_reached and m.triangles.shape[0] >= 4


def test_small_input_angles_are_exempt_and_terminate() -> None:
    d = star()
    m = triangulate(d, min_angle=33)
    assert m.exempt > 0 and m.min_angle_reached
    _checked(d, m)
    # The exempt triangles sit at the tips: their small angle is the input angle there, nothing smaller.
    assert m.smallest_angle() >= 15.9


def test_offcentres_are_optional() -> None:
    d = circle()
    with_off = triangulate(d, min_angle=30)
    without = triangulate(d, min_angle=30, offcenters=False)
    assert with_off.offcenters > 0 and without.offcenters == 0
    _checked(d, without)


def test_max_steiner_stops_early() -> None:
    m = triangulate(l_shape(), min_angle=33, max_area=0.001, max_steiner=10)
    assert m.insertions == 10 and not m.max_area_reached


def test_region_area_bounds() -> None:
    # Two squares side by side, the right one with its own area bound.
    d = as_pslg(
        [[0, 0], [1, 0], [2, 0], [2, 1], [1, 1], [0, 1]],
        ring(6) + [[1, 4]],
        regions=[[1.5, 0.5, 7.0, 0.01]],
    )
    m = triangulate(d, min_angle=20, region_areas=True)  # Triangle's -a without a number
    right = m.regions == 1
    e1 = m.vertices[m.triangles[:, 1]] - m.vertices[m.triangles[:, 0]]
    e2 = m.vertices[m.triangles[:, 2]] - m.vertices[m.triangles[:, 0]]
    areas = (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]) / 2
    assert right.any() and areas[right].max() <= 0.01 and areas[~right].max() > 0.01
    # Without it the regional bound is read but not applied, as in Triangle ('pq20' against 'pq20a').
    import triangle as tr

    plain = triangulate(d, min_angle=20)
    assert len(plain.triangles) < len(m.triangles) / 10
    ours, theirs = len(plain.triangles), len(tr.triangulate(d.to_dict(), "pq20")["triangles"])
    assert ours <= 1.1 * theirs and theirs <= 1.1 * ours, (ours, theirs)
    assert len(tr.triangulate(d.to_dict(), "pq20a")["triangles"]) > 10 * theirs
    assert len(triangulate(d).vertices) == 6  # the CDT, whatever the regions' bounds
    with pytest.raises(TypeError, match="region_areas"):
        triangulate(d, min_angle=20, region_areas="yes")  # type: ignore[arg-type]


def test_full_precision_segment_is_a_clear_error() -> None:
    # Ends in one binade using all 53 bits, differences (in ulps) coprime: no double lies strictly between.
    u = 2.0**-53
    P = GrowingPredicates2([[0.5 + 3 * u, 0.75], [0.875 - 5 * u, 0.5 + 7 * u]])
    with pytest.raises(PrecisionLimitError, match="limit of double precision"):
        split_parameter(P, 0, 1, 0, 1, Fraction(0), Fraction(1), Fraction(1, 2))


def test_split_points_lie_exactly_on_oblique_segments() -> None:
    # Vertices on a 2^-20 grid: the lattice of doubles on each segment is dense, every split exact.
    pts = np.round(np.array([[0.0, 0.0], [1.0, 0.3], [0.7, 1.1], [-0.2, 0.6]]) * 2**20) / 2**20
    d = as_pslg(pts, ring(4))
    m = triangulate(d, min_angle=30, max_area=0.005)
    _checked(d, m)
    assert m.segment_splits > 10


@pytest.mark.parametrize("name", sorted(DOMAINS))
@pytest.mark.parametrize("angle", [20, 30, 33])
def test_triangle_counts_within_ten_percent(name: str, angle: int) -> None:
    make, area = DOMAINS[name]
    d = make()
    opts = f"pq{angle}" + (f"a{area}" if area else "")
    ref = tr.triangulate(d.to_dict(), opts)
    m = triangulate(d, min_angle=angle, max_area=area)
    assert m.triangles.shape[0] <= 1.1 * ref["triangles"].shape[0]


@pytest.mark.parametrize("encroachment", ["lens", "circle"])
def test_lens_and_circle_encroachment_both_reach_the_bound(encroachment: str) -> None:
    d = l_shape()
    m = triangulate(d, min_angle=30, max_area=0.02, encroachment=encroachment)
    assert m.min_angle_reached and m.max_area_reached
    _checked(d, m)


GALLERY_REACHED = [
    (name, angle)
    for name in ("square-hole", "l-shape", "star", "circle", "crack", "utm-tile", "comb")
    for angle in (20, 30, 33)
]


@pytest.mark.parametrize("name, angle", GALLERY_REACHED)
def test_gallery_domains_reach_the_bound_and_pass_the_checker(name: str, angle: int) -> None:
    from persistri.impl.mesh.gallery import gallery_domain

    d = gallery_domain(name).pslg
    m = triangulate(d, min_angle=angle)
    assert m.min_angle_reached
    _checked(d, m)


def test_utm_tile_oblique_segment_has_no_double_on_it() -> None:
    # Its segment from (500040, 4000025) to (500017.63, 4000024.18): the differences in ulps are coprime, so no
    # pair of doubles lies strictly between the ends; in strict mode a split there is refused, in one line.
    from persistri.impl.mesh.gallery import gallery_domain

    with pytest.raises(PrecisionLimitError, match="segment 6") as info:
        triangulate(gallery_domain("utm-tile").pslg, min_angle=30, exact_segments=True)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("name, angle", GALLERY_REACHED)
def test_gallery_counts_within_ten_percent_of_triangle(name: str, angle: int) -> None:
    """Issue 16's target: triangles within 1.1x of Triangle's ``pq<angle>`` on every gallery domain, the bound reached."""
    from persistri.impl.mesh.gallery import gallery_domain

    d = gallery_domain(name).pslg
    ref = tr.triangulate(d.to_dict(), f"pq{angle}")
    m = triangulate(d, min_angle=angle)
    assert m.min_angle_reached
    assert m.triangles.shape[0] <= 1.1 * ref["triangles"].shape[0]


def test_chew_deletes_free_vertices_before_splits_and_every_version_stays_valid() -> None:
    # The comb's thin teeth: circumcentres near a tooth's side are deleted when the side is split (Triangle's rule).
    from persistri.impl.mesh.gallery import gallery_domain
    from persistri.impl.mesh.verify import verify_mesh

    d = gallery_domain("comb").pslg
    m = triangulate(d, min_angle=20)
    assert m.deletions > 0 and m.deletions == sum(map(len, m.history.deleted))
    for k in range(len(m.history)):
        a = m.history.mesh(k)
        assert verify_mesh(d, a.vertices, a.triangles).ok
        if k and m.history.deleted[k - 1]:
            before = set(m.history.mesh(k - 1).points.tolist())
            gone = set(m.history.deleted[k - 1])
            assert gone <= before and not gone & set(a.points.tolist())  # deleted in that very step
            assert m.history.inserted[k - 1] in m._run.geo.on_segment  # ... before a segment split
    # Ruppert's variant (diametral circles, Triangle's -D) deletes nothing.
    assert triangulate(d, min_angle=20, encroachment="circle").deletions == 0


@pytest.mark.parametrize("angle", [30, 33])
def test_rounded_splits_by_default_where_no_double_lies(angle: int) -> None:
    # The default: where no double lies on a subsegment, the split point is rounded (Triangle's way), counted and
    # noted; every other split point lies exactly on its segment.
    from persistri.impl.mesh.gallery import gallery_domain
    from persistri.impl.mesh.verify import verify_mesh

    d = gallery_domain("utm-tile").pslg
    m = triangulate(d, min_angle=angle, check=True)
    assert m.rounded_splits > 0 and m.min_angle_reached and not m.exact_segments
    assert len(m.notes) == 1 and re.search(r"segments? (\d+, )*6\b", m.notes[0]) and "rounded" in m.notes[0]
    report = verify_mesh(d, m.vertices, m.triangles, min_angle=angle, exact_segments=False)
    assert report.ok and report.rounded_split_vertices == m.rounded_splits
    # Only the rounded points are off their segment: each other split point is on it, exactly.
    strict = verify_mesh(d, m.vertices, m.triangles, exact_segments=True, max_problems=1000)
    assert {p.kind for p in strict.problems} == {"segment-rounding"}


def test_no_rounding_where_doubles_lie_on_the_segments() -> None:
    # The default rounds nothing when the lattice of doubles on each segment is dense: the strict check passes.
    from persistri.impl.mesh.gallery import gallery_domain

    d = gallery_domain("crack").pslg
    m = triangulate(d, min_angle=30, max_area=0.05)
    assert m.rounded_splits == 0 and m.notes == () and m.segment_splits > 0
    check_verified(d, m)


@settings(max_examples=15)
@given(pslgs(), st.sampled_from([20.0, 30.0]), st.sampled_from([4.0, 1.0, 0.5]))
def test_random_pslgs_refine_to_verified_meshes(data: tuple[np.ndarray, np.ndarray], angle: float, area: float) -> None:
    # Random segments among integer points: small input angles everywhere; shells and exemptions must terminate it.
    verts, segs = data
    d = as_pslg(verts, segs, convex=True)
    m = triangulate(d, min_angle=angle, max_area=area)
    assert m.min_angle_reached and m.max_area_reached
    _checked(d, m)


@settings(max_examples=200)
@given(
    st.tuples(*[st.integers(-(2**60), 2**60)] * 4),
    st.sampled_from([20.0, 30.0, 33.0, 20.7, 45.0]),
)
def test_filtered_angle_test_equals_the_exact_one(v: tuple[int, int, int, int], theta: float) -> None:
    from persistri.impl.mesh.angles import angle_at_least
    from persistri.impl.mesh.quality import at_least

    ux, uy, wx, wy = v
    nu, nw = ux * ux + uy * uy, wx * wx + wy * wy
    if nu == 0 or nw == 0:
        return
    dot = ux * wx + uy * wy
    assert at_least(dot, nu, nw, theta) == angle_at_least(dot, nu, nw, theta)


def test_filtered_angle_test_at_the_bound() -> None:
    # A 30-60-90 triangle has exactly 30 degrees: cos² = 3/4 exactly, inside the float stage's margin.
    from persistri.impl.mesh.quality import at_least

    dot, nu, nw = 3, 3, 4  # (u·w)² = 9 = 3/4 · |u|² |w|²: cos² of exactly 30°
    assert at_least(dot, nu, nw, 30.0) and not at_least(dot, nu, nw, 30.000001)


_coord = st.one_of(
    st.integers(-6, 6).map(float),
    st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False),
    st.integers(-8, 8).map(lambda k: 4.0e6 + k * 2.0**-31),  # UTM northings a few ulps apart
)


@settings(max_examples=300)
@given(
    st.lists(st.tuples(_coord, _coord), min_size=3, max_size=3, unique=True),
    st.sampled_from([20.0, 30.0, 33.0, 20.7, 45.0, 0.0]),
    st.sampled_from([None, 0.5, 1.0, 2.0, 1e-3]),
    st.booleans(),
)
def test_quality_tests_float_stage_equals_the_exact_tests(
    pts: list[tuple[float, float]], theta: float, area: float | None, lens: bool
) -> None:
    # QualityTests decides in floats when clear of the bound by its proved error, else exactly: always the exact answer.
    from persistri.impl.mesh.quality import AngleBound, area_exceeds, inside_lens, shape
    from persistri.impl.mesh.quality_filter import QualityTests

    P = GrowingPredicates2(np.array(pts))
    a, b, c = (0, 1, 2) if P.orient2d_sign(0, 1, 2) > 0 else (0, 2, 1)
    if P.orient2d_sign(a, b, c) == 0:
        return
    bound = AngleBound.of(theta)
    limit = Fraction(area) if area is not None else None
    tests = QualityTests(P, bound, limit, {3: Fraction(1, 4)}, lens)
    for region in (0, 3):
        got = tests.assess(a, b, c, region)
        sh = shape(P, a, b, c, bound)
        bound_here = Fraction(1, 4) if region == 3 else limit
        area_bad = bound_here is not None and area_exceeds(P, a, b, c, bound_here)
        if sh.good_angle and not area_bad:
            assert got is None
        else:
            assert got is not None and got[4] == sh.good_angle and got[:3] == (sh.p, sh.q, sh.r)
            assert math.isclose(got[3], sh.edge2, rel_tol=1e-12)  # the queue key: nearly |pq|²
    for u, w, x in ((a, b, c), (b, c, a), (c, a, b)):
        exact = P.dot_sign(u, w, x) < 0 and (not lens or inside_lens(P, u, w, x, theta))
        assert tests.encroaches(u, w, x) == exact


def test_quality_tests_at_ties() -> None:
    # Two equal shortest edges (isosceles), an area exactly at the bound, a point on a diametral circle.
    from persistri.impl.mesh.quality import AngleBound
    from persistri.impl.mesh.quality_filter import QualityTests

    P = GrowingPredicates2(np.array([[0.0, 0.0], [4.0, 0.0], [2.0, 7.0], [2.0, 2.0], [2.0, -2.0]]))
    tests = QualityTests(P, AngleBound.of(30.0), Fraction(14), {}, lens=False)
    assert tests.assess(0, 1, 2, 0) is None  # area exactly 14: not above the bound; smallest angle about 31.9°
    assert tests.assess(0, 1, 2, 0) is None and not tests.area_bad(0, 1, 2, 0)
    tight = QualityTests(P, AngleBound.of(30.0), Fraction(13.999999999999998), {}, lens=False)
    assert tight.assess(0, 1, 2, 0) is not None and tight.area_bad(0, 1, 2, 0)
    assert not tests.encroaches(0, 1, 3) and not tests.encroaches(0, 1, 4)  # on the circle: not strictly inside


def _survey_lot(n: int, seed: int) -> PSLG:
    """A star-shaped lot of ``n`` corners given to the centimetre near UTM (5.1e5, 4.1e6): slanted edges with no
    double between their ends are common."""
    rng = np.random.default_rng(seed)
    ang = np.sort(rng.uniform(0, 2 * math.pi, n))
    rad = rng.uniform(10, 40, n)
    pts = np.round(np.c_[512_345.0 + rad * np.cos(ang), 4_123_456.0 + rad * np.sin(ang)], 2)
    return as_pslg(pts, ring(n))


@pytest.mark.parametrize("seed, area", [(57, 50.0), (2, 50.0), (26, 10.0)])
def test_rounded_splits_on_hull_segments_keep_the_mesh_valid(seed: int, area: float) -> None:
    # Rounded split points inside the hull (the sliver between the chain and the old hull edge joins the exterior),
    # outside it (the hull grows by a hair), and splits of the pieces between them: every version stays valid.
    from persistri.impl.mesh.verify import verify_mesh

    d = _survey_lot(5, seed)
    m = triangulate(d, min_angle=20, max_area=area, check=True)
    assert m.rounded_splits > 0 and m.min_angle_reached and m.max_area_reached
    for k in range(len(m.history)):
        a = m.history.mesh(k)
        assert verify_mesh(d, a.vertices, a.triangles, exact_segments=False).ok


@settings(max_examples=20)
@given(st.integers(5, 12), st.integers(0, 10**6), st.sampled_from([20.0, 30.0, 33.0]), st.sampled_from([None, 50.0, 10.0]))
def test_survey_lots_mesh_by_default(n: int, seed: int, angle: float, area: float | None) -> None:
    from persistri.impl.mesh.verify import verify_mesh

    try:
        d = _survey_lot(n, seed)
    except DomainError:  # an angular gap above 180° can make the ring cross itself: not a lot
        assume(False)
    m = triangulate(d, min_angle=angle, max_area=area)
    assert m.min_angle_reached and m.max_area_reached
    report = verify_mesh(d, m.vertices, m.triangles, min_angle=angle, max_area=area, exact_segments=m.rounded_splits == 0)
    assert report.ok, report.problems[:2]
    assert report.rounded_split_vertices == m.rounded_splits


def _equidistant_exact(pts: np.ndarray) -> bool:
    (ox, oy), (px, py), (qx, qy) = ([Fraction(v) for v in row] for row in pts.tolist())
    dp, dq = (px - ox) ** 2 + (py - oy) ** 2, (qx - ox) ** 2 + (qy - oy) ** 2
    return 999 * dq < 1000 * dp < 1001 * dq


@settings(max_examples=400, deadline=None)
@given(
    st.floats(-1e6, 1e6), st.floats(-1e6, 1e6), st.floats(1e-9, 1e3), st.floats(0, 2 * math.pi),
    st.floats(0, 2 * math.pi), st.sampled_from([1.0, 1000 / 1001, 1001 / 1000, 999 / 1000, 1000 / 999, 0.9, 1.1]),
    st.integers(-3, 3),
)
def test_equal_distance_filter_equals_the_exact_test(
    ox: float, oy: float, r: float, a: float, b: float, ratio: float, nudge: int
) -> None:
    # Triangle's 1.001 rule with its float stage against rationals, at and near both boundaries of the factor.
    from persistri.impl.mesh.quality import equidistant

    rq = r * math.sqrt(ratio)
    q = (ox + rq * math.cos(b), oy + rq * math.sin(b))
    q = (q[0], q[1] + nudge * math.ulp(q[1]))
    pts = np.array([(ox, oy), (ox + r * math.cos(a), oy + r * math.sin(a)), q])
    assume(not np.array_equal(pts[0], pts[1]) and not np.array_equal(pts[0], pts[2]))
    assert equidistant(GrowingPredicates2(pts), 0, 1, 2) == _equidistant_exact(pts)
