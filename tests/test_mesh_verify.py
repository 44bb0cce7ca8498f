"""verify_mesh: Triangle's meshes pass, broken meshes fail with the right problem named, every decision exact."""

from __future__ import annotations

import math
import re
from fractions import Fraction

import numpy as np
import pytest
import sympy
import triangle
from hypothesis import given
from hypothesis import strategies as st
from numpy.typing import NDArray

from persistri.impl.mesh.angles import EXACT_COS2, angle_at_least, cos2_bounds
from persistri.impl.mesh.domain import PSLG, as_pslg
from persistri.impl.mesh.verify import PROBLEM_KINDS, MeshVerificationError, verify_mesh

SQUARE_HOLE = as_pslg(
    [[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [2, 1], [2, 2], [1, 2]],
    [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]],
    holes=[[1.5, 1.5]],
)
UNIT_SQUARE = as_pslg([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]])


def mesh(pslg: PSLG, opts: str) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    out = triangle.triangulate(pslg.to_dict(), opts)
    return out["vertices"], out["triangles"].astype(np.intp)


def edges_of(tri: NDArray[np.intp]) -> dict[tuple[int, int], int]:
    return {(int(t[i]), int(t[(i + 1) % 3])): k for k, t in enumerate(tri) for i in range(3)}


# -- meshes that must pass ------------------------------------------------------------------


@pytest.mark.parametrize("opts, bound", [("p", None), ("pq20", 20.0), ("pq30", 30.0), ("pq33a0.05", 33.0)])
def test_triangle_meshes_of_a_square_with_a_hole_pass(opts: str, bound: float | None) -> None:
    v, t = mesh(SQUARE_HOLE, opts)
    rep = verify_mesh(SQUARE_HOLE, v, t, min_angle=bound, max_area=0.05 if "a" in opts else None)
    assert rep.ok, rep.problems
    assert rep.mesh_area == rep.domain_area == 15
    assert rep.triangles == len(t) and rep.min_angle is not None
    if bound is not None:
        assert rep.min_angle >= bound
    assert str(rep).startswith("valid mesh:") and "\n" not in str(rep)
    rep.raise_if_failed()


@pytest.mark.parametrize("name", ["A", "face", "double_hex", "la", "square_circle_hole", "double_hex2"])
def test_triangle_meshes_of_its_own_example_domains_pass(name: str) -> None:
    data = triangle.get_data(name)
    pslg = PSLG.from_dict({k: data[k] for k in ("vertices", "segments", "holes", "regions") if k in data})
    for opts, bound in (("p", None), ("pq25", 25.0), ("pq25a", 25.0)):
        v, t = mesh(pslg, opts)
        rep = verify_mesh(pslg, v, t, min_angle=bound, exact_segments=False, region_areas=opts.endswith("a"))
        assert rep.ok, (name, opts, rep.problems)
        # The triangles tile the region bounded by the chains through the rounded split points.
        assert rep.mesh_area is not None and rep.domain_area is not None
        assert abs(rep.mesh_area - rep.domain_area) == rep.area_rounding
        if rep.rounded_split_vertices == 0:
            assert rep.mesh_area == rep.domain_area


def test_regional_area_bounds_are_checked_per_face() -> None:
    d = as_pslg(
        [[0, 0], [2, 0], [2, 1], [0, 1], [1, 0], [1, 1]],
        [[0, 4], [4, 1], [1, 2], [2, 5], [5, 3], [3, 0], [4, 5]],
        regions=[[0.5, 0.5, 1, 0.01], [1.5, 0.5, 2, 0.2]],
    )
    v, t = mesh(d, "pqa")
    assert verify_mesh(d, v, t, region_areas=True).ok
    v2, t2 = mesh(d, "pq")  # ignores the regional bounds
    assert verify_mesh(d, v2, t2).ok
    rep = verify_mesh(d, v2, t2, region_areas=True)
    assert rep.kinds() == {"area-bound"} and "above the bound 0.01" in rep.problems[0].message


def test_an_exact_hand_made_mesh_and_its_quality() -> None:
    v = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    t = np.array([[0, 1, 2], [0, 2, 3]])
    rep = verify_mesh(UNIT_SQUARE, v, t, min_angle=45.0, max_area=0.5)
    assert rep.ok and rep.min_angle == pytest.approx(45.0) and rep.max_area == 0.5
    assert rep.mesh_area == rep.domain_area == 1
    # The bounds are exact: 45° and area 1/2 are met with equality, a hair more is not.
    assert verify_mesh(UNIT_SQUARE, v, t, min_angle=math.nextafter(45.0, 90.0)).kinds() == {"angle"}
    assert verify_mesh(UNIT_SQUARE, v, t, max_area=math.nextafter(0.5, 0.0)).kinds() == {"area-bound"}


def test_utm_offsets_are_exact() -> None:
    x0, y0 = 500_000.0, 4_000_000.0
    ring = np.array([[x0, y0], [x0 + 40, y0], [x0 + 40, y0 + 25], [x0, y0 + 25]])
    d = as_pslg(ring, [[0, 1], [1, 2], [2, 3], [3, 0]])
    v, t = mesh(d, "pq30a20")
    rep = verify_mesh(d, v, t, min_angle=30.0, max_area=20.0)
    assert rep.ok, rep.problems
    assert rep.domain_area == rep.mesh_area == 1000 and rep.split_vertices > 0
    # A split vertex one ulp off the bottom edge is off the segment, exactly; within tolerance otherwise.
    k = int(np.flatnonzero((v[:, 1] == y0) & (v[:, 0] > x0) & (v[:, 0] < x0 + 40))[0])
    moved = v.copy()
    moved[k, 1] = math.nextafter(y0, 0.0)
    assert verify_mesh(d, moved, t).kinds() == {"segment-rounding"}
    relaxed = verify_mesh(d, moved, t, exact_segments=False)
    assert relaxed.ok and relaxed.rounded_split_vertices == 1
    assert relaxed.area_rounding > 0 and relaxed.mesh_area == 1000 + relaxed.area_rounding
    moved[k, 1] = y0 - 1e-6  # a micrometre: far beyond rounding
    assert "segment" in verify_mesh(d, moved, t, exact_segments=False).kinds()


# -- broken meshes: each detected, the right problem named ---------------------------------------


@pytest.fixture(scope="module")
def good() -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    return mesh(SQUARE_HOLE, "pq30a0.2")


def test_a_missing_triangle(good: tuple[NDArray[np.float64], NDArray[np.intp]]) -> None:
    v, t = good
    interior = next(k for k in range(len(t)) if all(i >= 8 for i in t[k]))  # touches no input vertex
    rep = verify_mesh(SQUARE_HOLE, v, np.delete(t, interior, axis=0))
    assert "boundary" in rep.kinds() and not rep.ok
    assert any("no triangle on its other side" in p.message for p in rep.problems)


def test_an_extra_overlapping_triangle(good: tuple[NDArray[np.float64], NDArray[np.intp]]) -> None:
    v, t = good
    rep = verify_mesh(SQUARE_HOLE, v, np.vstack([t, t[3:4]]))
    assert "edge" in rep.kinds()
    assert any("overlap" in p.message for p in rep.problems if p.kind == "edge")
    # An extra triangle over two neighbours (the other diagonal of their quadrilateral).
    e = edges_of(t)
    for (a, b), k in e.items():
        if (b, a) in e:
            c = next(int(x) for x in t[k] if x not in (a, b))
            d = next(int(x) for x in t[e[(b, a)]] if x not in (a, b))
            rep = verify_mesh(SQUARE_HOLE, v, np.vstack([t, [[a, d, c]]]))
            assert not rep.ok and rep.kinds() & {"edge", "boundary", "orientation"}
            break


def test_a_vertex_moved_off_its_segment(good: tuple[NDArray[np.float64], NDArray[np.intp]]) -> None:
    v, t = good
    on_bottom = np.flatnonzero((v[:, 1] == 0) & (v[:, 0] > 0) & (v[:, 0] < 4))
    moved = v.copy()
    moved[on_bottom[0], 1] = 1e-3
    rep = verify_mesh(SQUARE_HOLE, moved, t)
    assert "segment" in rep.kinds()
    assert any("is not a union of mesh edges" in p.message for p in rep.problems)
    # Off by one ulp: a rounding problem, accepted with exact_segments=False.
    moved[on_bottom[0], 1] = 5e-324
    rep = verify_mesh(SQUARE_HOLE, moved, t)
    assert "segment-rounding" in rep.kinds() and "segment" not in rep.kinds()
    relaxed = verify_mesh(SQUARE_HOLE, moved, t, exact_segments=False)
    assert "segment" not in relaxed.kinds() and relaxed.rounded_split_vertices == 1


def test_a_non_delaunay_edge(good: tuple[NDArray[np.float64], NDArray[np.intp]]) -> None:
    v, t = good
    e = edges_of(t)
    on_segment = {(0, 1), (1, 2), (2, 3), (3, 0)}
    for (a, b), k in e.items():
        if (b, a) not in e or a > b or (a, b) in on_segment:
            continue
        c = next(int(x) for x in t[k] if x not in (a, b))
        k2 = e[(b, a)]
        d = next(int(x) for x in t[k2] if x not in (a, b))
        flipped = t.copy()
        flipped[k], flipped[k2] = [c, a, d], [d, b, c]
        orient = [(v[y, 0] - v[x, 0]) * (v[z, 1] - v[x, 1]) - (v[y, 1] - v[x, 1]) * (v[z, 0] - v[x, 0]) for x, y, z in (flipped[k], flipped[k2])]
        if min(orient) <= 0:
            continue  # a non-convex quadrilateral cannot be flipped
        rep = verify_mesh(SQUARE_HOLE, v, flipped)
        if rep.ok:
            continue  # the two diagonals were cocircular
        assert rep.kinds() == {"delaunay"}, rep.problems
        assert any(f"edge ({min(c, d)}, {max(c, d)}) is not locally Delaunay" in p.message for p in rep.problems)
        return
    pytest.fail("no flippable edge found")


def test_a_clockwise_triangle(good: tuple[NDArray[np.float64], NDArray[np.intp]]) -> None:
    v, t = good
    bad = t.copy()
    bad[5] = bad[5][::-1]
    rep = verify_mesh(SQUARE_HOLE, v, bad)
    assert "orientation" in rep.kinds()
    assert any("triangle 5" in p.message and "clockwise" in p.message for p in rep.problems)


def test_a_missing_input_vertex() -> None:
    d = as_pslg([[0, 0], [1, 0], [1, 1], [0, 1], [0.25, 0.5]], [[0, 1], [1, 2], [2, 3], [3, 0]])
    v, t = mesh(UNIT_SQUARE, "p")  # a mesh of the square without the interior vertex
    rep = verify_mesh(d, v, t)
    assert rep.kinds() == {"missing-vertex"}
    assert "input vertex 4" in rep.problems[0].message


def test_a_triangle_inside_a_hole(good: tuple[NDArray[np.float64], NDArray[np.intp]]) -> None:
    v, t = good
    filled = np.vstack([t, [[4, 5, 6], [4, 6, 7]]])
    rep = verify_mesh(SQUARE_HOLE, v, filled)
    assert "outside" in rep.kinds()
    assert any("hole 0" in p.message for p in rep.problems)


def test_a_mesh_of_the_wrong_region() -> None:
    """A whole mesh of the hole alone: boundary edges on segments, but the domain is on their other side."""
    v = SQUARE_HOLE.vertices
    rep = verify_mesh(SQUARE_HOLE, v, np.array([[4, 5, 6], [4, 6, 7]]))
    assert {"outside", "missing-vertex"} <= rep.kinds()


def test_problems_are_capped_per_kind_and_counted(good: tuple[NDArray[np.float64], NDArray[np.intp]]) -> None:
    v, t = good
    rep = verify_mesh(SQUARE_HOLE, v, t[:, ::-1], max_problems=3)
    assert rep.counts["orientation"] == len(t)
    assert sum(p.kind == "orientation" for p in rep.problems) == 3
    assert str(rep).startswith(f"not a valid mesh (") and "\n" not in str(rep)
    with pytest.raises(MeshVerificationError, match="orientation"):
        rep.raise_if_failed()
    assert set(rep.kinds()) <= set(PROBLEM_KINDS)


def test_bad_arguments_are_input_problems_or_one_line_errors() -> None:
    v = UNIT_SQUARE.vertices
    assert verify_mesh(UNIT_SQUARE, v, np.array([[0, 1, 9]])).kinds() == {"input"}
    assert verify_mesh(UNIT_SQUARE, v, np.array([[0, 1, 1]])).kinds() == {"input"}
    assert verify_mesh(UNIT_SQUARE, v, np.array([0, 1, 2])).kinds() == {"input"}
    assert verify_mesh(UNIT_SQUARE, [[0, np.nan]], np.zeros((0, 3), int)).kinds() == {"input"}
    broken = PSLG(np.array([[0, 0], [1, 0], [0, 1], [1, 1.0]]), np.array([[0, 3], [1, 2]]))
    rep = verify_mesh(broken, broken.vertices, np.array([[0, 1, 3]]))
    assert rep.kinds() == {"domain"} and "cross" in rep.problems[0].message
    with pytest.raises(ValueError, match="min_angle"):
        verify_mesh(UNIT_SQUARE, v, np.array([[0, 1, 2]]), min_angle=61)
    with pytest.raises(ValueError, match="max_area"):
        verify_mesh(UNIT_SQUARE, v, np.array([[0, 1, 2]]), max_area=0)


def test_small_input_angles_are_exempt_not_failed() -> None:
    """A 20° wedge: at q30 Triangle keeps the 20° corner and the triangles nested in it."""
    tip = np.array([[0, 0], [1, 0], [math.cos(math.radians(20)), math.sin(math.radians(20))]])
    d = as_pslg(tip, [[0, 1], [1, 2], [2, 0]])
    v, t = mesh(d, "pq30")
    rep = verify_mesh(d, v, t, min_angle=30.0, exact_segments=False)
    assert rep.ok, rep.problems
    assert rep.exempt >= 1 and rep.min_angle is not None and rep.min_angle < 30
    assert rep.min_angle_unexempt is not None and rep.min_angle_unexempt >= 30


# -- exact angle comparison ----------------------------------------------------------------------


@given(st.floats(min_value=0.0, max_value=90.0))
def test_cos2_bounds_bracket_the_true_value(theta: float) -> None:
    lo, hi = cos2_bounds(theta)
    exact = Fraction(theta)
    true = (sympy.cos(sympy.Rational(exact.numerator, exact.denominator) * sympy.pi / 180) ** 2).evalf(150)
    assert sympy.Rational(lo.numerator, lo.denominator).evalf(150) <= true
    assert true <= sympy.Rational(hi.numerator, hi.denominator).evalf(150)
    assert hi - lo < Fraction(1, 1 << 100)


def test_the_rational_bounds_are_exact() -> None:
    for theta, c2 in EXACT_COS2.items():
        assert cos2_bounds(theta) == (c2, c2)
    # (0,0)-(1,0)-(1,1): 45° exactly; (0,0)-(2,0)-(1, √3) is not representable, but 60° via cos² 1/4:
    assert angle_at_least(1, 1, 2, 45.0) and not angle_at_least(1, 1, 2, math.nextafter(45.0, 90))
    assert angle_at_least(1, 1, 4, 60.0)  # cos² = 1/4 exactly
    assert not angle_at_least(1, 1, 4, math.nextafter(60.0, 90))


@given(st.integers(-50, 50), st.integers(-50, 50), st.integers(-50, 50), st.integers(-50, 50), st.floats(1.0, 60.0))
def test_angle_at_least_agrees_with_high_precision(ux: int, uy: int, vx: int, vy: int, theta: float) -> None:
    if (ux, uy) == (0, 0) or (vx, vy) == (0, 0):
        return
    got = angle_at_least(ux * vx + uy * vy, ux * ux + uy * uy, vx * vx + vy * vy, theta)
    angle = sympy.acos(sympy.Rational(ux * vx + uy * vy) / sympy.sqrt((ux * ux + uy * uy) * (vx * vx + vy * vy)))
    bound = sympy.Rational(Fraction(theta).numerator, Fraction(theta).denominator) * sympy.pi / 180
    diff = (angle - bound).evalf(60)
    if diff != 0:
        assert got == (diff > 0)


# -- the tolerance box ------------------------------------------------------------------------------


def test_the_tolerance_box_is_exact_and_closed() -> None:
    from persistri.impl.mesh.chains import in_tolerance_box

    a, b = np.array([0.0, 0.0]), np.array([1.0, 3.0])
    # The midpoint of a segment between doubles is often a tie between two doubles: both count.
    mid = np.array([0.5, 1.5])
    assert in_tolerance_box(mid, a, b, 0.0)
    u = 2.0**-53  # the y tolerance is measured in ulps of 3 (4u), the x tolerance in ulps of 1 (2u)
    assert in_tolerance_box(np.array([0.5, 1.5 + 2 * u]), a, b, 0.5)  # half an ulp of 3 above the line: on the box edge
    assert not in_tolerance_box(np.array([0.5, 1.5 + 8 * u]), a, b, 0.5)
    assert in_tolerance_box(np.array([0.5, 1.5 + 8 * u]), a, b, 2.0)
    assert not in_tolerance_box(np.array([0.5, 1.5 + 64 * u]), a, b, 2.0)
    # Beyond the segment's end it does not count, however close to its line.
    assert not in_tolerance_box(np.array([1.0 + 2 * u, 3.0 + 6 * u]), a, b, 0.5)


def test_the_domain_may_be_triangles_dictionary(good: tuple[NDArray[np.float64], NDArray[np.intp]]) -> None:
    """``verify_mesh`` takes the dictionary ``triangulate`` takes, with the same verdicts as the PSLG."""
    v, t = good
    as_dict = SQUARE_HOLE.to_dict()
    assert verify_mesh(as_dict, v, t, min_angle=30).ok
    assert verify_mesh(as_dict, v, t[1:]).kinds() == verify_mesh(SQUARE_HOLE, v, t[1:]).kinds() != set()
    flat = verify_mesh({"vertices": [[0, 0], [1, 0]]}, v, t)
    assert flat.kinds() == {"domain"} and "only 2 distinct vertices" in flat.problems[0].message


def test_problems_name_segments_as_the_caller_wrote_them() -> None:
    # Validation renumbers: segment 0 is split at (2, 0), so input segment 4 (the diagonal) is validated row 5.
    # A mesh without the diagonal (its two triangles flipped) is named by the caller's row, with its ends.
    d = as_pslg([[0, 0], [4, 0], [4, 4], [0, 4], [2, 0], [1, 1.5], [3, 2.5]], [[0, 1], [1, 2], [2, 3], [3, 0], [5, 6]])
    assert d.segment_origin is not None and d.segment_origin.tolist()[-1] == 4 and d.segments.shape[0] == 6
    from persistri.impl.mesh.api import triangulate

    m = triangulate(d)
    tri = m.triangles.copy()
    pair = [k for k, t in enumerate(tri.tolist()) if 5 in t and 6 in t]
    assert len(pair) == 2
    (a, b), (c, e) = ([v for v in tri[k].tolist() if v not in (5, 6)] + [k] for k in pair)
    first = tri[b].tolist()
    i = first.index(a)
    u, w = first[(i + 1) % 3], first[(i + 2) % 3]  # a, u, w counterclockwise; c is across u–w
    tri[b], tri[e] = [a, u, c], [a, c, w]
    rep = verify_mesh(d, m.vertices, tri)
    assert any("segment 4 between (1.0, 1.5) and (3.0, 2.5) is not a union of mesh edges" in p.message for p in rep.problems)
    assert not any("segment 5" in p.message for p in rep.problems)
    # An added convex hull edge is named as such: a mesh of the hull less the triangle on the edge (0, 0)–(4, 0).
    h = as_pslg([[0, 0], [4, 0], [4, 4], [0, 4], [2, 1]], convex=True)
    hm = triangulate(h)
    kept = np.array([t for t in hm.triangles.tolist() if not {0, 1} <= set(t)])
    messages = [p.message for p in verify_mesh(h, hm.vertices, kept).problems]
    assert any(
        s.startswith("the convex hull edge (0.0, 0.0)–(4.0, 0.0) (a .node file, or convex=True, is meshed as its convex "
                     "hull) is not a union of mesh edges")
        for s in messages
    ), messages
    assert not any(re.search(r"segment \d", s) for s in messages), messages
