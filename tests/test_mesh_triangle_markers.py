"""Boundary markers and vertex attributes in persistri's Triangle files, against Triangle's own outputs.

Triangle's rules (``triangle.markers.html``, ``triangle.node.html``; :mod:`persistri.impl.mesh.markers`):
markers are a function of where a vertex or an edge lies, so every vertex and segment the two meshes share
must carry the same marker, on every mesh; attributes of input vertices are copied, and split points'
interpolated along their segment (the same line in both programs: equal up to rounding); circumcentres'
depend on the bad triangle each was split from, so they agree exactly only where the two refinements took
the same steps (the square below) and otherwise only for a linear field, up to rounding.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest
from cli_contract import invoke

from persistri.impl.mesh.api import refine, triangulate
from persistri.impl.mesh.domain import PSLG, as_pslg
from persistri.impl.mesh.gallery import GALLERY, gallery_domain
from persistri.impl.mesh.markers import triangle_markers, vertex_attributes
from persistri.impl.mesh.polyfile import read_node, read_poly

triangle = pytest.importorskip("triangle")

DATA = Path(triangle.__file__).parent / "data"


def _shared(mine: Any, theirs: dict[str, Any]) -> tuple[np.ndarray, np.ndarray]:
    """The rows of the vertices both meshes have (the same doubles): mine, theirs."""
    where = {tuple(x): i for i, x in enumerate(np.asarray(theirs["vertices"]).tolist())}
    pairs = [(i, where[tuple(x)]) for i, x in enumerate(np.asarray(mine).tolist()) if tuple(x) in where]
    rows = np.array(pairs, dtype=np.intp).reshape(-1, 2)
    return rows[:, 0], rows[:, 1]


def _segment_marks(vertices: Any, segments: Any, markers: Any) -> dict[tuple[tuple[float, float], ...], int]:
    v = np.asarray(vertices).tolist()
    return {tuple(sorted((tuple(v[a]), tuple(v[b])))): int(k) for (a, b), k in zip(np.asarray(segments).tolist(), np.asarray(markers).reshape(-1).tolist())}


def _compare(mesh: Any, theirs: dict[str, Any], *, all_shared: bool) -> None:
    marks = triangle_markers(mesh)
    mi, ti = _shared(mesh.vertices, theirs)
    if all_shared:
        assert len(mi) == len(mesh.vertices) == len(theirs["vertices"])
    assert len(mi) >= mesh.domain.vertices.shape[0]  # every input vertex, in both
    # Vertices of no triangle (in a hole) are left out: Triangle marks such a vertex 1 or not depending on the order
    # it eats the hole's triangles (a segment in the hole is a boundary until its other side is eaten too).
    used = np.zeros(len(mesh.vertices), dtype=bool)
    used[mesh.triangles.reshape(-1)] = True
    mi, ti = mi[used[mi]], ti[used[mi]]
    assert marks.vertex[mi].tolist() == np.asarray(theirs["vertex_markers"]).reshape(-1)[ti].tolist()
    mine_s = _segment_marks(mesh.vertices, mesh.segments[marks.kept], marks.segment[marks.kept])
    their_s = _segment_marks(theirs["vertices"], theirs["segments"], theirs["segment_markers"])
    common = mine_s.keys() & their_s.keys()
    assert {k: mine_s[k] for k in common} == {k: their_s[k] for k in common}
    if all_shared:
        assert mine_s == their_s


@pytest.mark.parametrize("name", GALLERY)
@pytest.mark.parametrize("angle", [0, 30])
def test_gallery_markers_and_segment_attributes_match_triangles(name: str, angle: int) -> None:
    d = gallery_domain(name).pslg
    n = d.vertices.shape[0]
    rng = np.random.default_rng(16)
    attrs = np.column_stack([3 + 2 * d.vertices[:, 0] - d.vertices[:, 1], rng.random(n)])
    dom = as_pslg(d.vertices, d.segments, d.holes, d.regions, vertex_attributes=attrs)
    mesh = triangulate(dom, min_angle=angle)
    theirs = triangle.triangulate(dom.to_dict(), "p" + (f"q{angle}" if angle else ""))
    _compare(mesh, theirs, all_shared=angle == 0)
    mine_a = vertex_attributes(mesh)
    assert mine_a is not None and mine_a.shape == (len(mesh.vertices), 2)
    assert np.array_equal(mine_a[:n], attrs)  # copied unchanged
    mi, ti = _shared(mesh.vertices, theirs)
    on_segment = triangle_markers(mesh).vertex[mi] != 0  # every gallery boundary is marked 1: on a segment
    scale = np.abs(attrs).max(axis=0)
    their_a = np.asarray(theirs["vertex_attributes"])
    # Split points: interpolated along the same segment by both, equal up to rounding (a few ulps of the largest).
    assert (np.abs(mine_a[mi][on_segment] - their_a[ti][on_segment]) <= 4 * np.spacing(scale)).all()


@pytest.mark.parametrize(
    ("stem", "opts"),
    [("A", "p"), ("A", "pq30"), ("box", "pc"), ("box", "pcq30"), ("face", "pq30"), ("double_hex3", "pq30"),
     ("diamond_02_00009", "c"), ("diamond_02_00009", "cq30"), ("spiral", "cq30")],
)
def test_triangles_example_files_markers_and_attributes(stem: str, opts: str) -> None:
    """Triangle's bundled examples (A.poly carries an attribute per vertex, box.poly markers 5, 10, 33)."""
    suffix = ".poly" if "p" in opts else ".node"
    dom = read_poly(DATA / f"{stem}{suffix}", convex="c" in opts)
    angle = 30 if "q30" in opts else 0
    mesh = triangulate(dom, min_angle=angle)
    theirs = triangle.triangulate(triangle.load(str(DATA), stem), opts)
    _compare(mesh, theirs, all_shared=angle == 0)
    attrs = vertex_attributes(mesh)
    if "vertex_attributes" in theirs:
        assert attrs is not None
        mi, ti = _shared(mesh.vertices, theirs)
        their_a = np.asarray(theirs["vertex_attributes"])
        if angle == 0:
            assert np.array_equal(attrs, their_a[ti])
        assert np.allclose(attrs[mi], their_a[ti], rtol=0, atol=4 * float(np.spacing(np.abs(their_a).max())))
    else:
        assert attrs is None


def test_a_square_refined_step_for_step_as_triangle_carries_its_attributes_exactly() -> None:
    """Where both refinements take the same steps, every value agrees exactly, circumcentres' too (extrapolated
    in the bad triangle, not read off the final mesh: vertex (0.5, 0.5) gets 1 + 0.5·4 + 0.5·6 = 6, not 3.75)."""
    v = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    s = [[0, 1], [1, 2], [2, 3], [3, 0]]
    attrs = [[1.0], [5.0], [2.0], [7.0]]
    mesh = triangulate(as_pslg(v, s, segment_markers=[0, 3, 0, 0], vertex_attributes=attrs), min_angle=30, max_area=0.05)
    theirs = triangle.triangulate(
        {"vertices": v, "segments": s, "vertex_attributes": attrs, "segment_markers": [[0], [3], [0], [0]]}, "pq30a0.05"
    )
    _compare(mesh, theirs, all_shared=False)
    mi, ti = _shared(mesh.vertices, theirs)
    mine_a = vertex_attributes(mesh)
    assert mine_a is not None and len(mi) >= 19
    assert mine_a[mi].tolist() == np.asarray(theirs["vertex_attributes"])[ti].tolist()
    assert mine_a[mesh.vertices.tolist().index([0.5, 0.5])].tolist() == [6.0]


@pytest.mark.parametrize(
    ("markers", "expected"),
    [([4, 9, 0, 0], 4), ([0, 9, 0, 4], 9), ([7, 0, 0, 0], 7), ([0, 0, 0, 0], 1)],
)
def test_a_vertex_between_two_marked_segments_takes_the_first_ones_marker(markers: list[int], expected: int) -> None:
    """Vertex 1 ends segments 0 and 1: the first in the file with a nonzero marker marks it (both programs)."""
    v = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]
    s = [[0, 1], [1, 2], [2, 3], [3, 0]]
    mesh = triangulate(as_pslg(v, s, segment_markers=markers))
    theirs = triangle.triangulate({"vertices": v, "segments": s, "segment_markers": np.array(markers).reshape(-1, 1)}, "p")
    _compare(mesh, theirs, all_shared=True)
    assert triangle_markers(mesh).vertex[1] == expected


def test_interior_segments_keep_0_and_segments_inside_holes_are_not_written() -> None:
    """A segment with the domain on both sides is 0 (not a boundary); one inside a hole is deleted by Triangle, and
    not written by persistri; a marked vertex keeps its marker wherever it is."""
    v = [[0, 0], [6, 0], [6, 6], [0, 6], [1, 1], [1, 5], [4, 2], [5, 2], [4, 4], [5, 4], [4.5, 2.5], [4.5, 3.5]]
    s = [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [6, 7], [7, 9], [9, 8], [8, 6], [10, 11]]
    vm = [0] * 11 + [8]
    mesh = triangulate(as_pslg(v, s, [[4.2, 3.0]], vertex_markers=vm), min_angle=25)
    marks = triangle_markers(mesh)
    assert marks.kept.sum() == len(mesh.segments) - 1 and not marks.kept[mesh.segment_of == 9].any()
    assert set(marks.segment[mesh.segment_of == 4].tolist()) == {0}
    assert marks.vertex[11] == 8 and marks.vertex[10] == 0 and marks.vertex[4] == 0
    theirs = triangle.triangulate(
        {"vertices": v, "segments": s, "holes": [[4.2, 3.0]], "vertex_markers": np.array(vm).reshape(-1, 1)}, "pq25"
    )
    _compare(mesh, theirs, all_shared=False)
    cdt = triangulate(as_pslg(v, s, [[4.2, 3.0]], vertex_markers=vm))
    cdt_theirs = triangle.triangulate(
        {"vertices": v, "segments": s, "holes": [[4.2, 3.0]], "vertex_markers": np.array(vm).reshape(-1, 1)}, "p"
    )
    _compare(cdt, cdt_theirs, all_shared=True)  # the same segments written, the one in the hole left out by both


def test_a_second_future_interpolates_from_its_own_steps() -> None:
    """refine() continues a mesh as another future: its Steiner points' attributes come from its own bad triangles."""
    v = [[0.0, 0.0], [4.0, 0.0], [4.0, 1.0], [0.0, 1.0]]
    s = [[0, 1], [1, 2], [2, 3], [3, 0]]
    attrs = [[0.0], [8.0], [9.0], [1.0]]  # 2x + y: linear, so every interpolation gives it back
    base = triangulate(as_pslg(v, s, vertex_attributes=attrs), min_angle=20)
    for mesh in (base, refine(base, min_angle=30, max_area=0.1), refine(base, min_angle=25)):
        got = vertex_attributes(mesh)
        assert got is not None
        assert np.allclose(got[:, 0], 2 * mesh.vertices[:, 0] + mesh.vertices[:, 1], rtol=0, atol=1e-14)


def test_cli_files_read_back_by_persistri_and_by_triangle(tmp_path: Path) -> None:
    """``persistri mesh A.poly -q 30 -o m.ele``: the .node carries attributes and markers, the .poly segment markers;
    triangle.load and persistri's readers read them back as written."""
    out = tmp_path / "m.ele"
    result, caught = invoke(["mesh", str(DATA / "A.poly"), "-q", "30", "-o", str(out), "--quiet"])
    assert result.exit_code == 0, (result.output, result.exception)
    assert not caught, caught
    mesh = triangulate(read_poly(DATA / "A.poly"), min_angle=30)
    marks = triangle_markers(mesh)
    attrs = vertex_attributes(mesh)
    assert attrs is not None
    node = read_node(tmp_path / "m.node")
    assert node.first_number == 1 and np.array_equal(node.vertices, mesh.vertices)
    assert node.markers is not None and node.markers.tolist() == marks.vertex.tolist()
    assert node.attributes is not None and np.array_equal(node.attributes, attrs)
    segs = read_poly(tmp_path / "m.poly", validate=False)
    assert segs.segment_markers is not None and segs.segment_markers.tolist() == marks.segment[marks.kept].tolist()
    loaded = triangle.load(str(tmp_path), "m")
    assert np.array_equal(loaded["vertex_markers"].reshape(-1), marks.vertex)
    assert np.array_equal(loaded["vertex_attributes"], attrs)
    assert np.array_equal(loaded["segments"], mesh.segments[marks.kept])
    assert np.array_equal(loaded["triangles"], mesh.triangles)
    theirs = triangle.triangulate(triangle.load(str(DATA), "A"), "pq30")
    mi, ti = _shared(loaded["vertices"], theirs)
    assert loaded["vertex_markers"].reshape(-1)[mi].tolist() == theirs["vertex_markers"].reshape(-1)[ti].tolist()


def test_pslg_without_markers_gets_triangles_0_and_1() -> None:
    dom: PSLG = gallery_domain("square-hole").pslg
    mesh = triangulate(dom, min_angle=30)
    marks = triangle_markers(mesh)
    assert set(marks.vertex.tolist()) == {0, 1} and set(marks.segment.tolist()) == {1}
    assert vertex_attributes(mesh) is None


def test_npz_output_holds_the_markers_and_attributes(tmp_path: Path) -> None:
    out = tmp_path / "m.npz"
    result, caught = invoke(["mesh", str(DATA / "A.poly"), "-q", "25", "-o", str(out), "--quiet"])
    assert result.exit_code == 0, (result.output, result.exception)
    mesh = triangulate(read_poly(DATA / "A.poly"), min_angle=25)
    marks = triangle_markers(mesh)
    with np.load(out) as saved:
        assert saved["vertex_markers"].tolist() == marks.vertex.tolist()
        assert saved["segment_markers"].tolist() == marks.segment.tolist()
        assert np.array_equal(saved["vertex_attributes"], vertex_attributes(mesh))
        assert saved["segment_markers"].shape[0] == saved["segments"].shape[0]
