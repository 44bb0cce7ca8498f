"""Domains: as_pslg's validation and repairs, the dict form, the exact faces and point location."""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np
import pytest
import triangle
from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.mesh.domain import PSLG, DomainError, as_pslg, domain_of
from persistri.impl.mesh.faces import UNBOUNDED, planar_faces

OUTER = [[0, 0], [4, 0], [4, 4], [0, 4]]
INNER = [[1, 1], [2, 1], [2, 2], [1, 2]]
RING4 = [[0, 1], [1, 2], [2, 3], [3, 0]]
RING8 = RING4 + [[4, 5], [5, 6], [6, 7], [7, 4]]


def refused(match: str, *args: object, **kwargs: object) -> str:
    with pytest.raises(DomainError, match=match) as info:
        as_pslg(*args, **kwargs)  # type: ignore[arg-type]
    message = str(info.value)
    assert "\n" not in message
    return message


# -- refused -----------------------------------------------------------------------------------


def test_bad_arrays_are_one_line_errors() -> None:
    refused("row 2 is not finite", [[0, 0], [1, 0], [np.nan, 1]])
    refused("row 1 is not finite", [[0, 0], [np.inf, 0], [0, 1]])
    refused(r"must be an \(n, 2\) array", [[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    refused(r"segments must be a \(k, 2\) array", OUTER, [0, 1, 2])
    refused("segments must be integers", OUTER, [[0, 1.5]])
    refused(r"segment 1 \(1, 4\): a vertex index is outside 0..3", OUTER, [[0, 1], [1, 4]])
    refused(r"segment 0 \(-1, 2\)", OUTER, [[-1, 2]])
    refused("segment 2 joins vertex 3 to itself", OUTER, [[0, 1], [1, 2], [3, 3]])
    refused(r"holes: row 0 is not finite", OUTER, RING4, [[np.nan, 1]])
    refused(r"regions must be an \(r, 4\) array", OUTER, RING4, regions=[[1, 1, 0]])
    refused("vertex_markers has 2 entries for 4 vertices", OUTER, RING4, vertex_markers=[1, 2])
    refused("collinear", [[0, 0], [1, 1], [2, 2], [3, 3]], [[0, 3]])
    refused("only 2 distinct vertices: a region needs at least 3 not on one line", [[0, 0], [1, 1], [0, 0]])
    refused("only 1 distinct vertex: a region", [[0, 0], [0, 0], [0, 0]])


def test_crossing_segments_are_refused_naming_both() -> None:
    msg = refused(r"segment 4 \(0–2\) and segment 5 \(1–3\) cross at about \(2, 2\)", OUTER, RING4 + [[0, 2], [1, 3]])
    assert "without a shared vertex" in msg


def test_holes_and_regions_must_be_in_the_domain() -> None:
    refused(r"hole 0 at \(5.0, 5.0\) lies outside the domain \(outside the convex hull", OUTER, RING4, [[5, 5]])
    refused(r"hole 0 at \(2.0, 0.0\) lies on segment 0 between \(0.0, 0.0\) and \(4.0, 0.0\)$", OUTER, RING4, [[2, 0]])
    refused(r"hole 0 at \(4.0, 4.0\) is on vertex 2$", OUTER, RING4, [[4, 4]])
    # Named as the caller wrote them: vertex 3 merged into 0 (so 4 became row 3), segment 1 repeated segment 0, and
    # the convex hull's edges added.
    refused(r"hole 0 at \(4.0, 2.0\) lies on segment 2 between \(4.0, 0.0\) and \(4.0, 4.0\)$",
            OUTER[:3] + [[0, 0], [0, 4]], [[0, 1], [1, 0], [1, 2], [2, 4], [4, 0]], [[4, 2]])
    refused(r"hole 0 at \(0.0, 4.0\) is on vertex 4$", OUTER[:3] + [[0, 0], [0, 4]], [[0, 1], [1, 2], [2, 4], [4, 0]], [[0, 4]])
    refused(r"hole 0 at \(2.0, 0.0\) lies on the convex hull edge \(0.0, 0.0\)–\(4.0, 0.0\) \(a \.node file, or "
            r"convex=True, is meshed as its convex hull\)$", OUTER + [[1, 1]], holes=[[2, 0]], convex=True)
    refused(r"region 0 at \(1.5, 1.5\) lies in a hole", OUTER + INNER, RING8, [[1.5, 1.5]], [[1.5, 1.5, 1, 0]])
    refused(r"region 0 at \(9.0, 1.0\) lies outside", OUTER, RING4, regions=[[9, 1, 1, 0]])


def test_an_unclosed_boundary_around_a_hole_is_named() -> None:
    # Both boundaries open: the hole's flood fill reaches the outside of the hull.
    refused("is not enclosed by segments: its flood fill reaches the outside of the convex hull", OUTER + INNER, RING8[:3] + RING8[4:7], [[1.5, 1.5]])
    # The hole's own boundary open: the hole point is in the outer face, which it eats whole.
    refused(r"the domain is empty: hole 0 .* eats the region bounded by vertices 0–1–2–3, the only region .*closed", OUTER + INNER, RING8[:7], [[1.5, 1.5]])
    # The outer boundary open: the hole eats the inner square, and nothing else is enclosed.
    refused(r"the domain is empty: hole 0 .* eats the region bounded by vertices 4–5–6–7, the only region", OUTER + INNER, RING8[:3] + RING8[4:], [[1.5, 1.5]])


def test_an_empty_domain_is_refused() -> None:
    refused("the segments enclose no region", OUTER, [[0, 1], [1, 2]])
    refused("the segments enclose no region", OUTER)


# -- repaired (or refused with repair=False) ------------------------------------------------------


def test_duplicate_vertices_are_merged_and_reported() -> None:
    p = as_pslg(OUTER + [[4, 4]], RING4 + [[1, 4]])
    assert p.vertices.shape == (4, 2) and p.vertex_map is not None and p.vertex_map.tolist() == [0, 1, 2, 3, 2]
    assert p.segments.shape == (4, 2)  # (1, 4) became (1, 2), a repeat of segment 1
    assert any("vertices 2 and 4 are the same point (4.0, 4.0)" in n for n in p.notes)
    refused("vertices 2 and 4 are the same point", OUTER + [[4, 4]], RING4, repair=False)
    refused(r"segment 4 \(2–4\) has both ends at the same point", OUTER + [[4, 4]], RING4 + [[2, 4]])


def test_repeated_segments_merge() -> None:
    p = as_pslg(OUTER, RING4 + [[1, 0], [0, 1]])
    assert p.segments.tolist() == RING4
    assert any("repeats segment 0" in n for n in p.notes)


def test_a_vertex_on_a_segment_splits_it() -> None:
    p = as_pslg(OUTER + [[2, 0]], RING4)
    assert sorted(map(sorted, p.segments.tolist())) == [[0, 3], [0, 4], [1, 2], [1, 4], [2, 3]]
    assert p.notes == ("vertex 4 at (2.0, 0.0) lies on the interior of segment 0 (0–1): split there",)
    refused(r"vertex 4 at \(2.0, 0.0\) lies on the interior of segment 0 \(0–1\)", OUTER + [[2, 0]], RING4, repair=False)


def test_overlapping_collinear_segments_become_their_pieces() -> None:
    pts = [[0, 0], [4, 0], [4, 4], [0, 4], [1, 0], [3, 0]]
    p = as_pslg(pts, [[0, 5], [4, 1], [1, 2], [2, 3], [3, 0]])  # 0–5 and 4–1 overlap on [1, 3]
    pieces = sorted(map(sorted, p.segments.tolist()))
    assert [0, 4] in pieces and [4, 5] in pieces and [1, 5] in pieces and len(pieces) == 6
    assert domain_of(p).area == 16
    refused("lies on the interior of segment 0", pts, [[0, 5], [4, 1], [1, 2], [2, 3], [3, 0]], repair=False)


def test_vertices_outside_the_domain_are_noted() -> None:
    p = as_pslg(OUTER + [[9, 9]], RING4)
    assert p.notes == ("vertex 4 at (9.0, 9.0) lies outside the domain: it cannot be a mesh vertex",)
    assert domain_of(p).vertex_inside.tolist() == [True] * 4 + [False]


def test_convex_meshes_the_hull() -> None:
    p = as_pslg([[0, 0], [2, 0], [1, 0], [0, 2], [0.5, 0.5]], convex=True)
    assert domain_of(p).area == 2
    assert sorted(map(sorted, p.segments.tolist())) == [[0, 2], [0, 3], [1, 2], [1, 3]]  # split at (1, 0)


def test_segment_origin_names_each_segment_s_input_row() -> None:
    # Repeats merge into the first, a split segment's pieces keep its row, added hull edges are -1.
    p = as_pslg(OUTER + [[2, 0], [4, 4]], [[1, 2], [0, 1], [2, 1], [5, 3], [3, 0]])
    assert p.segment_origin is not None
    named = {tuple(sorted(e)): o for e, o in zip(p.segments.tolist(), p.segment_origin.tolist())}
    assert named == {(1, 2): 0, (0, 4): 1, (1, 4): 1, (2, 3): 3, (0, 3): 4}
    q = as_pslg([[0, 0], [2, 0], [1, 0], [0, 2], [0.5, 0.5]], [[4, 3]], convex=True)
    assert q.segment_origin is not None
    assert sorted(q.segment_origin.tolist()) == [-1, -1, -1, -1, 0]
    assert PSLG(np.array(OUTER, dtype=float), np.array(RING4)).segment_origin is None  # not validated: rows as given


def test_the_dict_form_has_no_origins_and_names_its_own_rows() -> None:
    # Triangle's form has no key for origins (triangle.triangulate refuses unknown keys): read back, the hull edges
    # are segments of the dictionary, named by their rows in it, which is what its reader can find.
    p = as_pslg(OUTER + [[1, 1]], [[0, 4]], convex=True)
    d = p.to_dict()
    assert "segment_origin" not in d
    back = PSLG.from_dict(d)
    assert back.segment_origin is not None and back.segment_origin.tolist() == list(range(len(d["segments"])))
    assert np.array_equal(back.segments, p.segments) and triangle.triangulate(d, "p")["triangles"].shape[0] > 0
    with pytest.raises(DomainError, match="unknown PSLG key 'segment_origin'"):
        PSLG.from_dict({**d, "segment_origin": p.segment_origin})


def test_input_names() -> None:
    from persistri.impl.mesh.naming import InputNames

    p = as_pslg(OUTER + [[4, 4], [1, 1]], [[0, 5]], convex=True)  # row 4 repeats row 2; row 5 is vertex 4
    names = InputNames.of(p.segment_origin, p.vertex_map)
    assert [names.vertex(v) for v in range(p.vertices.shape[0])] == [0, 1, 2, 3, 5]
    assert p.segment_origin is not None
    inner = p.segment_origin.tolist().index(0)
    assert names.segment(inner, "(0.0, 0.0)", "(1.0, 1.0)") == "segment 0 between (0.0, 0.0) and (1.0, 1.0)"
    hull = p.segment_origin.tolist().index(-1)
    assert names.is_hull_edge(hull) and not names.is_hull_edge(inner)
    assert names.segment(hull, "(0.0, 0.0)", "(4.0, 0.0)") == (
        "the convex hull edge (0.0, 0.0)–(4.0, 0.0) (a .node file, or convex=True, is meshed as its convex hull)"
    )
    plain = InputNames.of(np.arange(4), np.arange(4))  # nothing renumbered
    assert plain == InputNames() and plain.vertex(3) == 3 and plain.segment(2, "a", "b") == "segment 2 between a and b"


# -- exactness at UTM offsets ---------------------------------------------------------------------


def test_utm_offsets_decide_exactly() -> None:
    x0, y0 = 500_000.0, 4_000_000.0
    pts = np.array([[x0, y0], [x0 + 10, y0 + 10], [x0 + 10, y0], [x0, y0 + 10]])
    on = np.vstack([pts, [[x0 + 5, y0 + 5]]])  # exactly on the diagonal 0–1
    p = as_pslg(on, [[0, 2], [2, 1], [1, 3], [3, 0], [0, 1]])
    assert any("lies on the interior of segment 4" in n for n in p.notes)
    off = np.vstack([pts, [[x0 + 5, np.nextafter(y0 + 5, np.inf)]]])  # one ulp above it
    q = as_pslg(off, [[0, 2], [2, 1], [1, 3], [3, 0], [0, 1]])
    assert not any("split" in n for n in q.notes)
    # Two segments that miss each other by one ulp do not cross; one more ulp and they do.
    a = np.array([[x0, y0], [x0 + 2, y0 + 2], [x0 + 2, y0], [x0, y0 + 2]])
    base = [[0, 2], [2, 1], [1, 3], [3, 0]]
    touching = np.vstack([a, [[x0 + 1, y0 + 1], [x0 + 1, y0 + 1.5]]])
    refused("lies on the interior", touching, base + [[0, 1], [4, 5]], repair=False)
    below = np.vstack([a, [[x0 + 1, np.nextafter(y0 + 1, np.inf)], [x0 + 1, y0 + 1.5]]])
    as_pslg(below, base + [[0, 1], [4, 5]])
    across = np.vstack([a, [[x0 + 1, np.nextafter(y0 + 1, -np.inf)], [x0 + 1, y0 + 1.5]]])
    refused("cross", across, base + [[0, 1], [4, 5]])


# -- the dict form ---------------------------------------------------------------------------------


def test_dict_round_trip_and_triangle_accepts_it() -> None:
    d = {
        "vertices": np.array(OUTER + INNER, dtype=float),
        "segments": np.array(RING8, dtype=np.int32),
        "holes": np.array([[1.5, 1.5]]),
        "regions": np.array([[3, 3, 7, 0.5]]),
        "vertex_markers": np.arange(8).reshape(-1, 1),
        "segment_markers": np.arange(8).reshape(-1, 1),
    }
    p = PSLG.from_dict(d)
    back = p.to_dict()
    for key, value in d.items():
        assert np.array_equal(back[key], value), key
    assert back["segments"].dtype == np.intc
    out = triangle.triangulate(back, "pq")
    assert out["triangles"].shape[0] > 0


def test_dict_errors() -> None:
    with pytest.raises(DomainError, match="unknown PSLG key 'triangles'"):
        PSLG.from_dict({"vertices": OUTER, "triangles": [[0, 1, 2]]})
    with pytest.raises(DomainError, match="needs 'vertices'"):
        PSLG.from_dict({"segments": RING4})
    assert "holes" not in as_pslg(OUTER, RING4).to_dict()


def test_triangle_example_domains_validate() -> None:
    for name in ("A", "face", "double_hex", "la", "square_circle_hole"):
        data = triangle.get_data(name)
        p = PSLG.from_dict({k: data[k] for k in ("vertices", "segments", "holes", "regions") if k in data})
        assert domain_of(p).area > 0


# -- faces -----------------------------------------------------------------------------------------


def test_faces_of_nested_components_cracks_and_holes() -> None:
    v = np.array(OUTER + INNER + [[3, 3], [3.5, 3.5], [6, 0], [7, 0], [7, 1]], dtype=float)
    s = np.array(RING8 + [[8, 9], [10, 11], [11, 12], [12, 10]])
    f = planar_faces(v, s)
    assert f.n_faces == 3
    areas = sorted(f.face_area(k) for k in range(3))
    assert areas == [Fraction(1, 2), 1, 15]
    assert f.locate(0.5, 0.5).face == f.locate(3.9, 0.1).face
    assert f.locate(1.5, 1.5).face != f.locate(0.5, 0.5).face
    assert f.locate(5, 5).face == UNBOUNDED and not f.locate(5, 5).on_graph
    assert f.locate(3.25, 3.25).segment == 8  # on the crack
    assert f.locate(Fraction(1, 3), 0).segment == 0 and f.locate(4, 4).vertex == 2
    assert f.locate(Fraction(7, 3), Fraction(7, 3)).face == f.locate(0.5, 0.5).face


@st.composite
def star_polygons(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray]:
    n = draw(st.integers(3, 12))
    angles = sorted(set(draw(st.lists(st.integers(0, 359), min_size=n, max_size=n))))
    if len(angles) < 3:
        angles = [0, 120, 240]
    radii = [draw(st.integers(1, 20)) for _ in angles]
    offset = draw(st.sampled_from([0.0, 5e5, 4e6]))
    pts = np.array([[offset + r * np.cos(np.radians(a)), offset + r * np.sin(np.radians(a))] for a, r in zip(angles, radii)])
    return pts, np.array([[k, (k + 1) % len(angles)] for k in range(len(angles))])


@given(star_polygons())
def test_the_area_of_a_star_polygon_is_its_exact_shoelace(poly: tuple[np.ndarray, np.ndarray]) -> None:
    pts, seg = poly
    try:
        p = as_pslg(pts, seg)
    except DomainError as exc:
        assert "collinear" in str(exc) or "cross" in str(exc)
        return
    exact = [(Fraction(x), Fraction(y)) for x, y in p.vertices]
    ring = [int(a) for a, _ in p.segments]
    if len(set(ring)) == len(ring) and len(ring) == len(exact):
        shoelace = sum(exact[a][0] * exact[b][1] - exact[b][0] * exact[a][1] for a, b in p.segments.tolist()) / 2
        assert domain_of(p).area == abs(shoelace)


def _brute_crossing(pts: list[tuple[Fraction, Fraction]], segs: list[tuple[int, int]]) -> bool:
    def orient(a: tuple[Fraction, Fraction], b: tuple[Fraction, Fraction], c: tuple[Fraction, Fraction]) -> int:
        d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        return (d > 0) - (d < 0)

    for (a, b), (c, d) in itertools.combinations(segs, 2):
        if len({a, b, c, d}) < 4:
            continue
        if orient(pts[a], pts[b], pts[c]) * orient(pts[a], pts[b], pts[d]) < 0 and (
            orient(pts[c], pts[d], pts[a]) * orient(pts[c], pts[d], pts[b]) < 0
        ):
            return True
    return False


def _pieces(pts: list[tuple[Fraction, Fraction]], segs: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """Reference: each segment split at the vertices exactly on its interior."""
    out = []
    for a, b in segs:
        (ax, ay), (bx, by) = pts[a], pts[b]
        on = [
            v
            for v, (x, y) in enumerate(pts)
            if v not in (a, b)
            and (bx - ax) * (y - ay) == (by - ay) * (x - ax)
            and min(ax, bx) <= x <= max(ax, bx)
            and min(ay, by) <= y <= max(ay, by)
        ]
        chain = [a] + sorted(on, key=lambda v: (pts[v][0] - ax) * (bx - ax) + (pts[v][1] - ay) * (by - ay)) + [b]
        out += list(zip(chain[:-1], chain[1:]))
    return out


@given(
    st.lists(st.tuples(st.integers(0, 6), st.integers(0, 6)), min_size=4, max_size=9, unique=True),
    st.lists(st.tuples(st.integers(0, 8), st.integers(0, 8)), min_size=1, max_size=8),
)
def test_crossings_are_found_exactly_as_by_brute_force(vertices: list[tuple[int, int]], pairs: list[tuple[int, int]]) -> None:
    box = [(0, 0), (7, 0), (7, 7), (0, 7)]
    pts = box + [v for v in vertices if v not in box]
    segs = [(a % len(pts), b % len(pts)) for a, b in pairs]
    segs = [(a, b) for a, b in segs if a != b] + [(0, 1), (1, 2), (2, 3), (3, 0)]
    exact = [(Fraction(x), Fraction(y)) for x, y in pts]
    crossing = _brute_crossing(exact, _pieces(exact, segs))
    try:
        p = as_pslg(np.array(pts, dtype=float), np.array(segs))
    except DomainError as exc:
        assert "cross" in str(exc) and crossing
        return
    assert not crossing
    kept = [(int(a), int(b)) for a, b in p.segments]
    assert sorted(tuple(sorted(q)) for q in kept) == sorted({tuple(sorted(q)) for q in _pieces(exact, segs)})


def test_a_large_polygon_validates() -> None:
    n = 20_000
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    pts = np.stack([np.cos(t) * (1 + 0.1 * np.cos(7 * t)), np.sin(t) * (1 + 0.1 * np.cos(7 * t))], axis=1)
    p = as_pslg(pts, np.stack([np.arange(n), (np.arange(n) + 1) % n], axis=1))
    assert p.segments.shape == (n, 2) and not p.notes


def test_coordinates_too_large_for_the_refinement_are_refused_clearly() -> None:
    from persistri.impl.mesh.api import triangulate
    from persistri.impl.mesh.domain import COORDINATE_LIMIT
    from persistri.impl.mesh.verify import verify_mesh

    big = 3.35e153  # just below 2^510: squared lengths and circumcentres stay doubles
    square = [[-big, -big], [big, -big], [big, big], [-big, big]]
    ring = [[0, 1], [1, 2], [2, 3], [3, 0]]
    mesh = triangulate(as_pslg(square, ring), min_angle=30, max_area=1e306)
    assert verify_mesh(mesh.domain, mesh.vertices, mesh.triangles, min_angle=30).ok
    for bad in ([[COORDINATE_LIMIT, 0.0]], [[0.0, -1e300]]):
        with pytest.raises(DomainError, match=r"vertices row 4 .*2\^510.*scale the domain down"):
            as_pslg(square + bad, ring)
    with pytest.raises(DomainError, match=r"holes row 0 .*2\^510"):
        as_pslg(square, ring, holes=[[1e200, 0.0]])


# -- the validation's candidate blocks and its predicates ---------------------------------------------


def test_blocks_of_candidate_pairs_change_nothing(monkeypatch: pytest.MonkeyPatch) -> None:
    """Splitting and the crossing sweep give the same PSLG, notes and first crossing in blocks of one pair."""
    from persistri.impl.mesh import segments

    # A square whose sides carry vertices (splits), an overlapping repeat, a crack and a cross-free interior.
    verts = [[0, 0], [4, 0], [4, 4], [0, 4], [1, 0], [2, 0], [4, 2], [1, 1], [3, 3], [2, 2], [0, 2]]
    segs = [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [7, 9], [9, 8], [6, 9]]
    crossing = segs + [[10, 8], [7, 3]]

    def outcome() -> tuple[object, ...]:
        p = as_pslg(verts, segs)
        with pytest.raises(DomainError) as info:
            as_pslg(verts, crossing)
        return p.segments.tolist(), p.segment_origin.tolist() if p.segment_origin is not None else None, p.notes, str(info.value)

    whole = outcome()
    assert len(whole[2]) >= 3  # the sides were split and the repeat merged: the blocks have work to do
    monkeypatch.setattr(segments, "_PAIR_BUDGET", 1)
    assert outcome() == whole


def test_validation_hands_its_predicates_to_the_mesher() -> None:
    """``validate_dict``'s predicates are the vertices' (nothing appended), and a dictionary meshes as its PSLG."""
    from persistri.impl.mesh.api import triangulate
    from persistri.impl.mesh.domain import validate_dict

    data = {"vertices": OUTER + INNER, "segments": RING8, "holes": [[1.5, 1.5]]}
    pslg, pred = validate_dict(data)
    assert len(pred) == pslg.vertices.shape[0] and np.array_equal(pred.points, pslg.vertices)
    a, b = triangulate(data, min_angle=30), triangulate(pslg, min_angle=30)
    assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.triangles, b.triangles)
