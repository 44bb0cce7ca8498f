"""Rounded split points that must keep the mesh valid, and features closer than doubles can resolve.

Where no double lies on a subsegment, its split point is rounded to nearby
doubles (``exact_segments=False``, the default).  Off the segment's line by an
ulp, the nearest one can fall on the wrong side of an edge of its cavity when a
vertex lies about as close to the segment: the refiner then drops that version
and inserts the next nearby double (:func:`~persistri.impl.mesh.splitting.rounded_candidates`,
decided exactly).  An input vertex *inside the domain* that close to a segment
cannot be resolved by any mesh of doubles: the refiner says so, naming it.
The exact searches behind the rounding, each against a plain rational
reference, are in ``test_mesh_rounding_searches.py``.
"""

from __future__ import annotations

import math
import re
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from mesh_helpers import ring
from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.api import triangulate
from persistri.impl.mesh.chains import in_tolerance_box
from persistri.impl.mesh.domain import PSLG, DomainError, as_pslg
from persistri.impl.mesh.polyfile import read_poly
from persistri.impl.mesh.splitting import rounded_candidates
from persistri.impl.mesh.steiner import PrecisionLimitError
from persistri.impl.mesh.verify import verify_mesh
from rounding_helpers import A, B, X0, Y0, exact_on


def _slot(v: tuple[float, float]) -> PSLG:
    """A box with a slot cut in from the right: its lower side is A–B, its upper side A–v–(far right), and ``v``
    lies within an ulp of A–B, *in the slot*: outside the domain."""
    pts = [(X0 - 10, Y0 - 20), (X0 + 60, Y0 - 20), (X0 + 60, Y0 + 10.03), B, A, v, (X0 + 60, Y0 + 25), (X0 + 60, Y0 + 50), (X0 - 10, Y0 + 50)]
    return as_pslg(np.array(pts), ring(len(pts)))


def test_rounded_candidates_lie_near_the_segment_nearest_first() -> None:
    P = GrowingPredicates2(np.array([A, B]))
    tried = list(rounded_candidates(P, 0, 1, 0, 1, Fraction(0), Fraction(1), Fraction(1, 2)))
    assert len(tried) > 8 and len({(x, y) for _, x, y in tried}) == len(tried)
    ex, ey = exact_on(Fraction(1, 2))
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
    ex, ey = exact_on(Fraction(1, 2))
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
