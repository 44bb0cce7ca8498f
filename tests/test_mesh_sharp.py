"""Very sharp input angles (issue 16): needles, a vee inside a domain, a fan of segments at one vertex; vs Triangle.

The refinement must terminate there with the bound reached outside the exempt triangles, every mesh must pass the
exact checker, and the triangle counts must stay near Triangle's ``pq<angle>`` (within 1.1x where the issue asks it).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
import triangle as tr

import persistri.impl.mesh.input_angles as input_angles
from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.api import QualityMesh, triangulate
from persistri.impl.mesh.cdt import SegmentGeometry
from persistri.impl.mesh.domain import PSLG, as_pslg
from persistri.impl.mesh.gallery import fan, gallery_domain, needle
from persistri.impl.mesh.splitting import _placed_well_at_ends, placed_well, placement_tolerances
from persistri.impl.mesh.verify import verify_mesh

TIPS = {"1deg": math.radians(1.0), "0.1deg": math.radians(0.1), "1e-3rad": 1e-3, "1e-6rad": 1e-6}


def vee(tip: float) -> PSLG:
    """Two segments of length about 0.5 meeting at the origin at ``tip`` radians, inside [−1, 2] × [−1, 1]."""
    h = math.tan(tip / 2) / 2
    pts = [[-1.0, -1.0], [2.0, -1.0], [2.0, 1.0], [-1.0, 1.0], [0.0, 0.0], [0.5, -h], [0.5, h]]
    return as_pslg(pts, [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [4, 6]])


def _verified(d: PSLG, m: QualityMesh, angle: int) -> None:
    assert m.min_angle_reached, "the bound is reached outside the exempt triangles"
    report = verify_mesh(d, m.vertices, m.triangles, min_angle=angle, exact_segments=m.rounded_splits == 0)
    assert report.ok, report.problems[:3]
    assert report.min_angle_unexempt is not None and report.min_angle_unexempt >= angle
    assert report.exempt > 0  # the input angle forces skinny triangles, and they are reported, not hidden


def _compare(d: PSLG, angle: int) -> tuple[int, int]:
    ref = tr.triangulate(d.to_dict(), f"pq{angle}")["triangles"].shape[0]
    # max_steiner only guards the test against an endless run: a run cut short does not reach the bound.
    m = triangulate(d, min_angle=angle, max_steiner=20_000)
    _verified(d, m, angle)
    return int(m.triangles.shape[0]), int(ref)


@pytest.mark.parametrize("angle", [20, 30, 33])
@pytest.mark.parametrize("tip", sorted(TIPS))
def test_needle_counts_within_ten_percent_of_triangle(tip: str, angle: int) -> None:
    ours, ref = _compare(needle(math.tan(TIPS[tip] / 2)), angle)
    assert ours <= 1.1 * ref, (ours, ref)


@pytest.mark.parametrize("angle", [20, 30, 33])
def test_vee_inside_a_domain_within_ten_percent_of_triangle(angle: int) -> None:
    ours, ref = _compare(vee(1e-6), angle)
    assert ours <= 1.1 * ref, (ours, ref)


# Measured: fan q33 3,740 against 2,643 (1.42x); fan(gap=1e-3) q30 484 against 376 (1.29x); vee(1e-3) q33 714
# against 570 (1.25x).  Near a cluster both programs' counts swing by tens of percent with the order of the
# work (Triangle's own: 376 at 1e-3 rad, 412 at 0.1°, 185 at 1° for the same fan at q30), and the refinement
# reorders nothing the exemption decides; these stay known gaps, not loosened bounds.  persistri has each of
# Triangle's small-angle rules (checkseg4encroach's lens, splitencsegs' shells and deletions, testtriangle's
# 1.001 exemption: docs/meshing.md, "What Triangle does at a cluster"); over 8 gaps from g to 2g the ratio's
# geometric mean is 0.88-1.15 and its range 0.56-1.46, so each case here is one sample of the order's swings.
# Measured again (2026-11-28, fifth session; docs/meshing.md, "The three open rows, measured"): the extra
# triangles lie around the spokes' free ends, from cascades of spoke splits across the bundle (84 per spoke
# against Triangle's 65); the same points numbered in reverse give 1.17x and 1.03x on the two fans; none of twelve
# queue orders brings the three within 1.1x without giving a gallery row more triangles.
FAN_CASES = [
    pytest.param("fan", 20, id="fan-q20"),
    pytest.param("fan", 30, id="fan-q30"),
    pytest.param("fan", 33, id="fan-q33", marks=pytest.mark.xfail(strict=True, reason="1.42x Triangle: open gap")),
    pytest.param("fan-1e-3", 20, id="fan-1e-3-q20"),
    pytest.param("fan-1e-3", 30, id="fan-1e-3-q30", marks=pytest.mark.xfail(strict=True, reason="1.29x: open gap")),
    pytest.param("fan-1e-3", 33, id="fan-1e-3-q33"),
    pytest.param("vee-1e-3", 33, id="vee-1e-3-q33", marks=pytest.mark.xfail(strict=True, reason="1.25x: open gap")),
]


@pytest.mark.parametrize("name, angle", FAN_CASES)
def test_sharp_clusters_within_ten_percent_of_triangle(name: str, angle: int) -> None:
    d = {"fan": gallery_domain("fan").pslg, "fan-1e-3": fan(gap=1e-3), "vee-1e-3": vee(1e-3)}[name]
    ours, ref = _compare(d, angle)
    assert ours <= 1.1 * ref, (ours, ref)


@pytest.mark.parametrize("angle", [20, 30, 33])
def test_sharp_clusters_terminate_verified(angle: int) -> None:
    # Whatever the count, every cluster terminates with the bound reached and an exact, valid mesh.
    for d in (gallery_domain("fan").pslg, fan(gap=1e-3), fan(3, math.radians(0.1)), vee(1e-3)):
        m = triangulate(d, min_angle=angle, max_steiner=20_000)
        _verified(d, m, angle)


CLUSTER_FAMILIES = [
    pytest.param(lambda g: fan(gap=g), 33, id="fan-1e-6-q33"),
    pytest.param(lambda g: fan(gap=g * 1e3), 30, id="fan-1e-3-q30"),
    pytest.param(lambda g: vee(g * 1e3), 33, id="vee-1e-3-q33"),
]


@pytest.mark.parametrize("build, angle", CLUSTER_FAMILIES)
def test_cluster_counts_over_eight_gaps_within_ten_percent_of_triangle(
    build: Callable[[float], PSLG], angle: int
) -> None:
    # The three open rows above are single gaps; near a cluster both programs' counts swing by up to 2x with a
    # change of the gap (docs/meshing.md, "The three open rows, measured").  Over the eight gaps from 0.7 g to
    # 1.4 g the totals are what the order of the work cannot move by luck: measured 0.99x, 1.08x and 0.97x.
    ours = ref = 0
    for k in range(8):
        d = build(0.7e-6 * 2 ** (k / 8))
        m = triangulate(d, min_angle=angle, max_steiner=20_000)
        assert m.min_angle_reached
        ours += int(m.triangles.shape[0])
        ref += int(tr.triangulate(d.to_dict(), f"pq{angle}")["triangles"].shape[0])
    assert ours <= 1.1 * ref, (ours, ref)


def test_needle_split_points_pair_up_at_equal_distances_from_the_tip() -> None:
    # The cause of issue 16's 60x: on a needle's segments the doubles lying exactly on the segment are sparse, and
    # the one nearest a shell point was 5e-4 off it, so the two sides' splits stopped pairing up.  Now every split
    # point of one side has a twin on the other within the squared-distance factor of Triangle's exemption.
    d = needle()
    m = triangulate(d, min_angle=30)
    pts = [tuple(map(Fraction, v)) for v in m.vertices.tolist()[3:]]
    lower = sorted(x * x + y * y for x, y in pts if y < 0)
    upper = sorted(x * x + y * y for x, y in pts if y > 0)
    assert len(lower) == len(upper) >= 15 and m.rounded_splits > 0
    for a, b in zip(lower, upper):
        assert 999 * b < 1000 * a < 1001 * b


def test_without_the_placement_rule_the_needle_splits_on() -> None:
    # The same run with exact-but-far split points (the rule switched off): far more splits than Triangle's 41
    # triangles need, and the bound still not reached after 400 of them.
    d = needle()
    m = triangulate(d, min_angle=30, max_steiner=400)
    assert m.min_angle_reached and m.triangles.shape[0] == 41
    patch = pytest.MonkeyPatch()
    try:
        patch.setattr(input_angles, "placement_tolerances", lambda P, geo, s, small=None: ())
        stuck = triangulate(d, min_angle=30, max_steiner=400)
    finally:
        patch.undo()
    assert not stuck.min_angle_reached and stuck.segment_splits == 400


def test_placement_tolerance_is_a_quarter_of_the_squared_angle() -> None:
    d = needle()
    P = GrowingPredicates2(d.vertices)
    ends = [(int(a), int(b)) for a, b in d.segments]
    geo = SegmentGeometry(ends, {}, {}, 3, [2, 2, 2])
    tip_segments = [s for s, e in enumerate(ends) if 0 in e]
    for s in tip_segments:
        ((o, tau),) = placement_tolerances(P, geo, s)
        alpha = 2 * math.atan2(5e-7, 1.0)
        assert o == 0 and tau == pytest.approx(alpha * alpha / 4, rel=1e-9)
    back = next(s for s in range(3) if s not in tip_segments)
    assert placement_tolerances(P, geo, back) == ()  # 90° corners: no constraint on placement
    # A square's segments meet at 90°: nothing asked.
    sq = as_pslg([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]])
    gsq = SegmentGeometry([(0, 1), (1, 2), (2, 3), (3, 0)], {}, {}, 4, [2, 2, 2, 2])
    assert placement_tolerances(GrowingPredicates2(sq.vertices), gsq, 0) == ()


def test_placed_well_is_relative_to_the_distance_from_the_apex() -> None:
    wanted = Fraction(7, 8)
    # From the apex at t = 0: distance 7/8, tolerance 1e-3 of it.
    assert placed_well(wanted + Fraction(1, 2000), wanted, [(Fraction(0), 1e-3)])
    assert not placed_well(wanted + Fraction(1, 1000), wanted, [(Fraction(0), 1e-3)])
    # From the apex at t = 1: distance 1/8, so a tighter absolute bound.
    assert not placed_well(wanted + Fraction(1, 2000), wanted, [(Fraction(1), 1e-3)])
    assert placed_well(wanted, wanted, [(Fraction(0), 0.0), (Fraction(1), 0.0)])
    assert placed_well(Fraction(1, 3), wanted, [])


@settings(max_examples=300, deadline=None)
@given(
    st.fractions(min_value=Fraction(-1, 4), max_value=Fraction(5, 4), max_denominator=1 << 40),
    st.fractions(min_value=Fraction(1, 1 << 30), max_value=1 - Fraction(1, 1 << 30), max_denominator=1 << 40),
    st.lists(st.tuples(st.sampled_from([7, 9]), st.sampled_from([0.0, 2.0**-12, 1e-3, 2.5e-13, 0.25])), max_size=2),
)
def test_placed_well_on_integers_is_placed_well(t: Fraction, wanted: Fraction, near: list[tuple[int, float]]) -> None:
    # The splitter's integer form (ends by vertex: 7 is the segment's first end, at t = 0) against the rational one,
    # at the boundary too (t exactly tau * r away).
    ends = [(Fraction(0) if o == 7 else Fraction(1), tau) for o, tau in near]
    assert _placed_well_at_ends(t, wanted, 7, near) == placed_well(t, wanted, ends)
    for o, tau in near:
        edge = wanted + Fraction(tau) * abs(wanted - (0 if o == 7 else 1))
        assert _placed_well_at_ends(edge, wanted, 7, near) == placed_well(edge, wanted, ends)


def test_strict_segments_never_round_near_a_sharp_angle() -> None:
    # exact_segments=True never rounds: the placement rule yields to it.  On the full-precision needle no double lies
    # on a subsegment soon: one clear line, naming the segment, as for any other segment.
    from persistri.impl.mesh.steiner import PrecisionLimitError

    named = r"splitting the subsegment \d+–\d+ \(mesh vertices\) of segment 0 between \("
    with pytest.raises(PrecisionLimitError, match=named) as info:
        triangulate(needle(), min_angle=20, exact_segments=True)
    assert "\n" not in str(info.value)
    # Where doubles lie densely on the segments (a needle on a 2^-40 grid) strict mode meshes it, every split exact.
    d = needle(round(5e-7 * 2**40) / 2**40)
    m = triangulate(d, min_angle=20, exact_segments=True, max_steiner=2000)
    assert m.rounded_splits == 0 and m.min_angle_reached
    assert verify_mesh(d, m.vertices, m.triangles, min_angle=20, exact_segments=True).ok


def test_gallery_needle_matches_triangle_exactly() -> None:
    d = gallery_domain("needle").pslg
    for angle in (20, 30, 33):
        ours, ref = _compare(d, angle)
        assert ours == ref  # the needle is symmetric: both programs pair every split, one exempt sliver per pair
    assert np.array_equal(d.vertices, needle().vertices)
