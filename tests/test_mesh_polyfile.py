"""Triangle's .node/.poly/.ele/.edge files: round trips, Triangle's own files, one-line errors naming file and line."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
import triangle
from hypothesis import given, settings
from hypothesis import strategies as st

from persistri.impl.mesh.domain import PSLG, as_pslg
from persistri.impl.mesh.polyfile import (
    PolyFileError,
    read_edge,
    read_ele,
    read_mesh,
    read_node,
    read_poly,
    write_edge,
    write_ele,
    write_node,
    write_poly,
)
from persistri.impl.mesh.verify import verify_mesh

DATA = Path(triangle.__file__).parent / "data"

SQUARE_HOLE = as_pslg(
    [[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [2, 1], [2, 2], [1, 2]],
    [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]],
    holes=[[1.5, 1.5]],
    regions=[[3, 3, 2.5, 0.25]],
    vertex_markers=[1, 1, 1, 1, 2, 2, 2, 2],
    segment_markers=[1, 1, 1, 1, 2, 2, 2, 3],
    vertex_attributes=[[0.1], [0.2], [0.3], [0.4], [0.5], [0.6], [0.7], [1 / 3]],
)


def same_pslg(a: PSLG, b: PSLG) -> None:
    for name in ("vertices", "segments", "holes", "regions", "vertex_markers", "segment_markers", "vertex_attributes"):
        x, y = getattr(a, name), getattr(b, name)
        assert (x is None) == (y is None), name
        if x is not None:
            assert np.array_equal(np.asarray(x), np.asarray(y)), name


# -- round trips ------------------------------------------------------------------------------------


@pytest.mark.parametrize("first", [0, 1])
@pytest.mark.parametrize("node_file", [False, True])
def test_poly_round_trip(tmp_path: Path, first: int, node_file: bool) -> None:
    path = tmp_path / "dom.poly"
    write_poly(path, SQUARE_HOLE, first_number=first, node_file=node_file)
    assert (tmp_path / "dom.node").exists() == node_file
    same_pslg(read_poly(path), SQUARE_HOLE)
    same_pslg(read_poly(path, validate=False), SQUARE_HOLE)


@settings(max_examples=25)
@given(st.lists(st.tuples(st.floats(allow_nan=False, allow_infinity=False), st.floats(allow_nan=False, allow_infinity=False)), min_size=3, max_size=30))
def test_node_round_trip_keeps_every_double(tmp_path_factory: pytest.TempPathFactory, rows: list[tuple[float, float]]) -> None:
    path = tmp_path_factory.mktemp("node") / "p.node"
    v = np.array(rows, dtype=float)
    markers = np.arange(len(rows)) % 3
    write_node(path, v, markers=markers, attributes=v[:, :1] / 2, first_number=0)
    back = read_node(path)
    assert np.array_equal(back.vertices, v) and back.first_number == 0
    assert back.markers is not None and back.markers.tolist() == markers.tolist()
    assert back.attributes is not None and np.array_equal(back.attributes[:, 0], v[:, 0] / 2)


def test_ele_and_edge_round_trip(tmp_path: Path) -> None:
    out = triangle.triangulate(SQUARE_HOLE.to_dict(), "pq30e")
    write_node(tmp_path / "m.node", out["vertices"])
    write_ele(tmp_path / "m.ele", out["triangles"])
    write_edge(tmp_path / "m.edge", out["edges"], markers=out["edge_markers"])
    node, ele = read_mesh(tmp_path / "m")
    assert np.array_equal(node.vertices, out["vertices"]) and np.array_equal(ele.triangles, out["triangles"])
    edge = read_edge(tmp_path / "m.edge")
    assert np.array_equal(edge.edges, out["edges"])
    assert edge.markers is not None and edge.markers.tolist() == out["edge_markers"].reshape(-1).tolist()
    assert verify_mesh(SQUARE_HOLE, node.vertices, ele.triangles, min_angle=30, exact_segments=False).ok


# -- Triangle's own files -----------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["A", "box.1", "double_hex", "face", "la", "square_circle_hole", "double_hex3.1"])
def test_triangle_example_poly_files_match_the_package_reader(name: str) -> None:
    mine = read_poly(DATA / f"{name}.poly", validate=False)
    theirs = triangle.get_data(name)
    assert np.array_equal(mine.vertices, theirs["vertices"])
    assert np.array_equal(mine.segments, theirs["segments"])
    if "holes" in theirs:
        assert np.array_equal(mine.holes, theirs["holes"])
    if "segment_markers" in theirs:
        assert mine.segment_markers is not None
        assert mine.segment_markers.tolist() == theirs["segment_markers"].reshape(-1).tolist()
    read_poly(DATA / f"{name}.poly")  # and they validate


def test_region_lines_with_one_value_use_it_as_attribute_and_area() -> None:
    """la.poly's region lines have three numbers after the number: Triangle reads the last as both."""
    la = read_poly(DATA / "la.poly", validate=False)
    assert la.regions.shape == (6, 4)
    assert np.array_equal(la.regions[:, 2], la.regions[:, 3])


@pytest.mark.parametrize("stem", ["box.1", "double_hex.2", "greenland", "la.1", "spiral.q.1", "A.1"])
def test_triangle_example_meshes_read(stem: str) -> None:
    node, ele = read_mesh(DATA / stem)
    theirs = triangle.get_data(stem)
    assert np.array_equal(node.vertices, theirs["vertices"])
    assert np.array_equal(ele.triangles, theirs["triangles"])
    assert node.first_number == 1 and ele.triangles.min() == 0


def test_triangle_output_meshes_pass_the_checker() -> None:
    """Files written by Triangle: A.1 is the constrained Delaunay triangulation of A.poly, box.4 a quality mesh of box.poly."""
    a = read_poly(DATA / "A.poly")
    node, ele = read_mesh(DATA / "A.1")
    assert verify_mesh(a, node.vertices, ele.triangles).ok
    box = read_poly(DATA / "box.poly", convex=True)
    node, ele = read_mesh(DATA / "box.4")
    rep = verify_mesh(box, node.vertices, ele.triangles, exact_segments=False)
    assert rep.ok, rep.problems


def test_a_poly_with_zero_vertices_reads_the_node_beside_it(tmp_path: Path) -> None:
    p = read_poly(DATA / "box.4.poly")
    assert p.vertices.shape == (531, 2)
    (tmp_path / "lonely.poly").write_text("0 2 0 1\n0 0\n0\n")
    with pytest.raises(PolyFileError, match=r"lonely.poly:1: the .poly lists 0 vertices, so they must be in .*lonely.node, which does not exist"):
        read_poly(tmp_path / "lonely.poly")


def test_comments_blank_lines_and_defaults(tmp_path: Path) -> None:
    path = tmp_path / "c.poly"
    path.write_text(
        "# a triangle\n\n4  # four vertices, dimension and the rest defaulted\n"
        "1 0 0\n2 1 0 # trailing comment\n3 0 1\n 4   0.25   0.25\n"
        "3 1\n1 1 2 7\n2 2 3\n3 3 1 9\n\n0\n"
    )
    p = read_poly(path)
    assert p.vertices.tolist() == [[0, 0], [1, 0], [0, 1], [0.25, 0.25]]
    assert p.segments.tolist() == [[0, 1], [1, 2], [2, 0]]
    assert p.segment_markers is not None and p.segment_markers.tolist() == [7, 0, 9]  # a missing marker is 0


# -- malformed files: one line, naming the file and the line --------------------------------------------


BAD = [
    ("3 2 0 0\n1 0 0\n2 1 0\n", "node", r":3: the file ends after 2 of the 3 vertex lines"),
    ("3 2 0 0\n1 0 0\n2 1\n3 0 1\n", "node", r":3: a vertex line needs 3 numbers \(vertex number, x, y\), found 2"),
    ("3 2 0 0\n1 0 0\n2 1 zero\n3 0 1\n", "node", r":3: 'zero' is not a number"),
    ("3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n", "node", r":1: the dimension must be 2, found 3"),
    ("3 2 0 0\n1 0 0\n3 1 0\n4 0 1\n", "node", r":3: vertices must be numbered consecutively: vertex 3 where 2 was expected"),
    ("3 2 0 0\n5 0 0\n6 1 0\n7 0 1\n", "node", r":2: vertices must be numbered from 0 or 1"),
    ("3 2 0 1\n1 0 0 1\n2 1 0 1.5\n3 0 1 0\n", "node", r":3: marker '1.5' is not an integer"),
    ("3 2 0 0\n1 0 0\n2 nan 0\n3 0 1\n", "node", r":3: a vertex line has a value that is not finite"),
    ("x 2 0 0\n", "node", r":1: the vertex count line: the number of vertices must be an integer, found 'x'"),
    ("2 2 0 0\n1 0 0\n2 1 0\n", "node", r":1: a mesh needs at least 3 vertices"),
    ("", "node", r"\.node: the file is empty \(or only comments\): its first line is the vertex count$"),
    ("# a comment\n\n", "poly", r"\.poly: the file is empty \(or only comments\)"),
    ("3 2 0 0\n1 0 0\n2 0 0\n3 0 0\n0 0\n0\n", "poly", r"\.poly: only 1 distinct vertex: a region needs at least 3 not on one line$"),
    ("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 3\n3 3 4\n0\n", "poly", r":8: a segment \(3 4\) refers to vertex 4, but the vertices are numbered 1..3"),
    ("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 3\n3 3 1\n", "poly", r":8: the file ends where the hole count line was expected"),
    ("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n0\n7 7\n", "poly", r":11: unexpected content after the holes"),
    ("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 3\n3 3 1\n1\n1 0.5\n", "poly", r":10: a hole line needs 3 numbers"),
    ("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 3\n3 3 1\n1\n1 5 5\n", "poly", r"\.poly: hole 0 at \(5.0, 5.0\) lies outside the domain .*numbers from 1"),
    ("1 3 0\n1 1 2\n", "ele", r":2: a triangle line needs 4 numbers"),
    ("1 2 0\n1 1 2 3\n", "ele", r":1: a triangle has at least 3 nodes, the file says 2"),
    ("1 3 0\n1 1 2.5 3\n", "ele", r":2: node '2.5' is not an integer"),
    ("2 0\n1 1 2\n2 3 -1\n", "edge", r":3: an infinite Voronoi ray"),
]


@pytest.mark.parametrize("text, kind, message", BAD)
def test_malformed_files_are_one_line_errors(tmp_path: Path, text: str, kind: str, message: str) -> None:
    path = tmp_path / f"bad.{kind}"
    path.write_text(text)
    reader = {"node": read_node, "poly": read_poly, "ele": read_ele, "edge": read_edge}[kind]
    with pytest.raises(PolyFileError, match=message) as info:
        reader(path)
    assert str(info.value).startswith(os.fspath(path)) and "\n" not in str(info.value)


def test_ele_indices_are_checked_against_the_node_file(tmp_path: Path) -> None:
    write_node(tmp_path / "m.node", [[0, 0], [1, 0], [0, 1]])
    (tmp_path / "m.ele").write_text("1 3 0\n1 1 2 4\n")
    with pytest.raises(PolyFileError, match=r"m.ele:2: a triangle \(1 2 4\) refers to vertex 4, but the vertices are numbered 1..3"):
        read_mesh(tmp_path / "m")


def test_a_missing_file_is_one_line(tmp_path: Path) -> None:
    with pytest.raises(PolyFileError, match="nope.node: cannot read"):
        read_node(tmp_path / "nope.node")


def test_writers_refuse_bad_arrays(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"triangles must be a \(t, 3\) integer array"):
        write_ele(tmp_path / "x.ele", [[0.5, 1, 2]])
    with pytest.raises(ValueError, match="first_number must be 0 or 1"):
        write_node(tmp_path / "x.node", [[0, 0], [1, 0], [0, 1]], first_number=2)


def test_read_poly_reads_a_node_file_as_its_convex_hull(tmp_path: Path) -> None:
    """`persistri mesh dots.node` meshes the convex hull of the points; read_poly gives the same domain."""
    from persistri.impl.cli.mesh import read_domain

    path = tmp_path / "dots.node"
    write_node(path, np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.3]]), first_number=0)
    d = read_poly(path)
    assert sorted(map(sorted, d.segments.tolist())) == [[0, 1], [0, 3], [1, 2], [2, 3]]
    assert np.array_equal(d.vertices, read_domain(str(path)).vertices)
    assert read_poly(path, validate=False).segments.shape == (0, 2)
