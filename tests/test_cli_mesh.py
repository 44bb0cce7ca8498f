"""``persistri mesh``: quality meshes from the command line, each output read back and checked exactly.

The malformed domains and bad outputs are rows of the CLI contract matrix
(``test_cli_inputs.py``, ``test_cli_inputs_outputs.py``); here: what a
successful run writes and prints, and the failures only this command has.
"""

from __future__ import annotations

import os
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import meshio
import numpy as np
import pytest
import triangle
from cli_contract import PNG_MAGIC, assert_one_line_failure, files_under, invoke

from persistri.impl.mesh.api import triangulate
from persistri.impl.mesh.domain import as_pslg
from persistri.impl.mesh.gallery import gallery_domain
from persistri.impl.mesh.polyfile import read_mesh, read_poly, write_node, write_poly
from persistri.impl.mesh.verify import verify_mesh

# A 4 × 4 square with a square hole and a segment marker per ring, numbered from 0 as some users write them.
FRAME_POLY = """# a frame
8 2 0 1
0 0 0 1
1 4 0 1
2 4 4 1
3 0 4 1
4 1 1 2
5 3 1 2
6 3 3 2
7 1 3 2
8 1
0 0 1 5
1 1 2 5
2 2 3 5
3 3 0 5
4 4 5 7
5 5 6 7
6 6 7 7
7 7 4 7
1
0 2 2
"""


def _ok(args: list[str]) -> str:
    result, caught = invoke(args)
    assert result.exit_code == 0, (result.output, result.exception)
    assert not caught, caught
    return result.stdout


def _npz(path: Path) -> dict[str, np.ndarray]:
    """The arrays of an .npz output, the file closed again."""
    with np.load(path) as data:
        return dict(data)


def _twice_area(vertices: np.ndarray, triangles: np.ndarray) -> list[Fraction]:
    out = []
    for a, b, c in triangles.tolist():
        (ax, ay), (bx, by), (cx, cy) = (tuple(map(Fraction, vertices[i].tolist())) for i in (a, b, c))
        out.append((bx - ax) * (cy - ay) - (by - ay) * (cx - ax))
    return out


def test_gallery_domain_to_npz_is_the_apis_mesh_and_passes_the_checker(tmp_path: Path) -> None:
    out = tmp_path / "star.npz"
    stdout = _ok(["mesh", "star", "--min-angle", "30", "-o", str(out), "--check", "--stats"])
    domain = gallery_domain("star").pslg
    api = triangulate(domain, min_angle=30)
    mesh = _npz(out)
    assert mesh["vertices"].dtype == np.float64 and mesh["vertices"].shape == (len(api.vertices), 2)
    assert np.array_equal(mesh["vertices"], api.vertices) and np.array_equal(mesh["triangles"], api.triangles)
    assert mesh["triangles"].shape == (len(api.triangles), 3)
    assert all(a > 0 for a in _twice_area(mesh["vertices"], mesh["triangles"]))  # counterclockwise, exactly
    # segments: mesh edges, each on its input segment, covering the input segments.
    edges = {frozenset(e) for t in mesh["triangles"].tolist() for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
    assert all(frozenset(s) in edges for s in mesh["segments"].tolist())
    assert mesh["segment_of"].shape == (len(mesh["segments"]),)
    assert set(mesh["segment_of"].tolist()) == set(range(len(domain.segments)))
    for key in ("insertions", "segment_splits", "circumcenters", "offcenters", "undos", "blocked", "deletions", "exempt"):
        assert int(mesh[key]) == getattr(api, key), key
    assert bool(mesh["min_angle_reached"]) and float(mesh["min_angle"]) == 30.0
    assert int(mesh["n_triangles"]) == len(api.triangles) and int(mesh["undos"]) > 0
    report = verify_mesh(domain, mesh["vertices"], mesh["triangles"], min_angle=30)
    assert report.ok and report.exempt == api.exempt > 0
    assert float(mesh["smallest_angle"]) == pytest.approx(report.min_angle)
    # --stats: the paper's point, said in numbers.
    lines = {ln.split("│")[1].strip(): ln.split("│")[2].strip() for ln in stdout.splitlines() if ln.count("│") == 3}
    assert lines["undos (insertion dropped, previous version kept)"] == str(api.undos)
    assert lines["segment splits"] == str(api.segment_splits)
    assert lines["triangles"] == str(len(api.triangles))
    assert lines["exact check (verify_mesh)"] == "passed"
    assert float(lines["min angle reached (°)"]) == pytest.approx(report.min_angle_unexempt, abs=1e-4)


def test_poly_file_to_triangles_files_side_by_side(tmp_path: Path) -> None:
    """-o mesh.ele writes Triangle's .node/.ele/.poly, numbered like the input (from 0 here), markers carried."""
    poly = tmp_path / "frame.poly"
    poly.write_text(FRAME_POLY)
    out = tmp_path / "result" / "mesh.ele"  # a missing last directory is made
    _ok(["mesh", str(poly), "-q", "33", "-a", "0.25", "-o", str(out), "--check", "--quiet"])
    assert files_under(tmp_path / "result") == {"mesh.ele", "mesh.node", "mesh.poly"}
    assert out.read_text().splitlines()[2].split()[0] == "0"  # first triangle numbered 0, as the input's vertices
    node, ele = read_mesh(tmp_path / "result" / "mesh")
    domain = read_poly(poly)
    api = triangulate(domain, min_angle=33, max_area=0.25)
    assert np.array_equal(node.vertices, api.vertices) and np.array_equal(ele.triangles, api.triangles)
    assert verify_mesh(domain, node.vertices, ele.triangles, min_angle=33, max_area=0.25).ok
    segs = read_poly(tmp_path / "result" / "mesh.poly", validate=False)
    assert np.array_equal(segs.segments, api.segments)
    assert segs.segment_markers is not None
    assert segs.segment_markers.tolist() == [5 if s < 4 else 7 for s in api.segment_of.tolist()]
    assert segs.holes.tolist() == [[2.0, 2.0]]


def test_node_file_is_meshed_as_the_convex_hull_of_its_points(tmp_path: Path) -> None:
    points = np.array([[0.0, 0.0], [3.0, 0.0], [4.0, 2.0], [1.0, 3.0], [1.5, 1.0], [2.0, 2.0]])
    write_node(tmp_path / "cloud.node", points)
    out = tmp_path / "hull.npz"
    _ok(["mesh", str(tmp_path / "cloud.node"), "-q", "25", "-o", str(out), "--check", "--quiet"])
    mesh = _npz(out)
    assert sum(_twice_area(mesh["vertices"], mesh["triangles"])) == 16  # twice the hull's area, (0,0)–(3,0)–(4,2)–(1,3)
    assert np.array_equal(mesh["vertices"][:6], points)  # every point a vertex (interior ones too)
    assert triangulate(as_pslg(points, convex=True), min_angle=25).triangles.tolist() == mesh["triangles"].tolist()


def test_min_angle_zero_is_the_constrained_delaunay_triangulation(tmp_path: Path) -> None:
    out = tmp_path / "cdt.npz"
    _ok(["mesh", "comb", "--min-angle", "0", "-o", str(out), "--check", "--quiet"])
    mesh = _npz(out)
    domain = gallery_domain("comb").pslg
    peer = triangle.triangulate(domain.to_dict(), "p")
    assert len(mesh["triangles"]) == len(peer["triangles"])  # a CDT of the same vertices: the same size
    assert int(mesh["insertions"]) == 0 and len(mesh["vertices"]) == len(domain.vertices)
    assert float(mesh["min_angle"]) == 0.0


@pytest.mark.parametrize("suffix", [".ply", ".obj", ".off"])
def test_mesh_files_with_z_zero_and_plots(tmp_path: Path, suffix: str) -> None:
    out, png, svg = tmp_path / f"crack{suffix}", tmp_path / "crack.png", tmp_path / "crack.svg"
    _ok(["mesh", "crack", "-q", "30", "-o", str(out), "--plot", str(png), "--quiet"])
    api = triangulate(gallery_domain("crack").pslg, min_angle=30)
    read = meshio.read(out)
    assert read.points.shape == (len(api.vertices), 3) and not read.points[:, 2].any()
    assert np.array_equal(read.points[:, :2], api.vertices)
    assert len(read.cells_dict["triangle"]) == len(api.triangles)
    assert png.read_bytes().startswith(PNG_MAGIC)
    _ok(["mesh", "crack", "-q", "30", "--plot", str(svg), "--quiet"])
    assert svg.read_text().lstrip().startswith("<?xml")


def test_options_reach_the_refiner(tmp_path: Path) -> None:
    out = tmp_path / "m.npz"
    _ok(["mesh", "square-hole", "-q", "30", "--encroachment", "circle", "--no-offcenters", "--max-steiner", "7", "-o", str(out), "--quiet"])
    api = triangulate(gallery_domain("square-hole").pslg, min_angle=30, encroachment="circle", offcenters=False, max_steiner=7)
    mesh = _npz(out)
    assert np.array_equal(mesh["triangles"], api.triangles)
    assert int(mesh["insertions"]) == api.insertions <= 7 and int(mesh["offcenters"]) == 0


def test_region_area_bounds_apply_and_are_checked(tmp_path: Path) -> None:
    """A .poly region with an area bound: with --region-areas (Triangle's -a without a number) every triangle in it
    meets the bound, and --check checks it; without, the bound is read but not applied, as in Triangle."""
    poly = tmp_path / "regions.poly"
    poly.write_text(FRAME_POLY.replace("1\n0 2 2\n", "0\n1\n0 0.5 2 3 0.05\n"))
    out = tmp_path / "r.npz"
    _ok(["mesh", str(poly), "-q", "20", "--region-areas", "-o", str(out), "--check", "--quiet"])
    mesh = _npz(out)
    areas = _twice_area(mesh["vertices"], mesh["triangles"])
    inside = [a for a, r in zip(areas, mesh["regions"].tolist()) if r == 1]  # the frame; the inner square is region 0
    assert sum(inside) == 2 * 12 and max(inside) <= 2 * Fraction(0.05)
    assert sum(areas) == 2 * 16 and max(a for a, r in zip(areas, mesh["regions"].tolist()) if r == 0) > 2 * Fraction(0.05)
    _ok(["mesh", str(poly), "-q", "20", "-o", str(out), "--check", "--quiet"])
    plain = _npz(out)
    inside = [a for a, r in zip(_twice_area(plain["vertices"], plain["triangles"]), plain["regions"].tolist()) if r == 1]
    assert max(inside) > 2 * Fraction(0.05) and len(plain["triangles"]) < len(mesh["triangles"])
    _ok(["mesh", str(poly), "-q", "0", "-o", str(out), "--quiet"])  # the plain CDT: nothing inserted
    assert len(_npz(out)["vertices"]) == len(read_poly(poly).vertices)


def test_precision_limit_names_the_command_line_option(tmp_path: Path) -> None:
    """The UTM tile's slanted edge holds no double where a split must go: exact splits fail in one line naming the
    option that rounds them, and the rounded mesh passes the checker with rounding allowed."""
    result, caught = invoke(["mesh", "utm-tile", "-q", "30", "--exact-segments", "-o", str(tmp_path / "u.npz")])
    assert_one_line_failure(result, caught, "utm-tile", r"no pair of doubles lies exactly on the segment.*--rounded-segments")
    assert files_under(tmp_path) == set()
    _ok(["mesh", "utm-tile", "-q", "30", "--rounded-segments", "-o", str(tmp_path / "u.npz"), "--quiet"])
    mesh = _npz(tmp_path / "u.npz")
    assert int(mesh["rounded_splits"]) > 0 and not bool(mesh["exact_segments"])
    domain = gallery_domain("utm-tile").pslg
    assert verify_mesh(domain, mesh["vertices"], mesh["triangles"], min_angle=30, exact_segments=False).ok


def test_check_fails_when_the_bound_is_not_reached_and_nothing_is_written(tmp_path: Path) -> None:
    out = tmp_path / "comb.npz"
    result, caught = invoke(["mesh", "comb", "-q", "30", "--max-steiner", "3", "--check", "-o", str(out), "--quiet"])
    assert_one_line_failure(result, caught, "comb", r"--check: the mesh fails the exact checker \(\d+ problems; first: angle: ")
    assert files_under(tmp_path) == set()
    result, caught = invoke(["mesh", "comb", "-q", "30", "--max-steiner", "3"])  # without --check: said, not failed
    assert result.exit_code == 0 and "(bound 30° NOT reached: stopped at --max-steiner 3)" in result.stderr


def test_the_summary_says_what_the_undo_did() -> None:
    api = triangulate(gallery_domain("crack").pslg, min_angle=30)
    result, caught = invoke(["mesh", "crack", "-q", "30", "--check"])
    assert result.exit_code == 0 and not caught
    (line,) = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert line.startswith(f"mesh of crack: {len(api.triangles)} triangles, {len(api.vertices)} vertices, min angle ")
    assert f"{api.undos} undone by returning to the previous version" in line and line.endswith("(verified exactly)")
    quiet, _ = invoke(["mesh", "crack", "-q", "30", "--quiet"])
    assert quiet.stdout == f"{len(api.triangles)} triangles, {len(api.vertices)} vertices, {api.undos} undos\n"
    assert quiet.stderr == ""


def test_the_summary_counts_one_triangle_in_the_singular(tmp_path: Path) -> None:
    poly = tmp_path / "tri.poly"
    poly.write_text("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n")
    result, caught = invoke(["mesh", str(poly), "-q", "0"])
    assert result.exit_code == 0 and not caught
    (line,) = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert line.startswith(f"mesh of {poly}: 1 triangle, 3 vertices"), line


def test_an_output_never_overwrites_the_input(tmp_path: Path) -> None:
    poly = tmp_path / "frame.poly"
    poly.write_text(FRAME_POLY)
    result, caught = invoke(["mesh", str(poly), "-o", str(tmp_path / "frame.ele")])
    assert_one_line_failure(result, caught, "frame.poly", r"is an input of this run; name the output otherwise")
    assert poly.read_text() == FRAME_POLY and files_under(tmp_path) == {"frame.poly"}
    # A .poly listing 0 vertices reads them from the .node beside it: that one is protected too.
    write_poly(tmp_path / "split.poly", read_poly(poly), node_file=True)
    before = (tmp_path / "split.node").read_text()
    result, caught = invoke(["mesh", str(tmp_path / "split.poly"), "-o", str(tmp_path / "split.ele")])
    assert_one_line_failure(result, caught, "split.node", r"is an input of this run")
    assert (tmp_path / "split.node").read_text() == before


def test_ele_companions_are_checked_before_computing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from cli_contract import forbid

    forbid(monkeypatch, "persistri.impl.mesh.api:triangulate")
    (tmp_path / "m.node").mkdir()
    result, caught = invoke(["mesh", "star", "-o", str(tmp_path / "m.ele")])
    assert_one_line_failure(result, caught, "m.node", r"a directory; give a file name")
    assert files_under(tmp_path) == {"m.node"}


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--min-angle", "60"], "Invalid value for '-q' / '--min-angle'"),
        (["--min-angle", "nan"], "nan is not a finite number"),
        (["--max-area", "0"], "Invalid value for '-a' / '--max-area'"),
        (["--max-area", "inf"], "inf is not a finite number"),
        (["--encroachment", "disc"], "Invalid value for '--encroachment'"),
        (["--max-steiner", "-1"], "Invalid value for '--max-steiner'"),
    ],
)
def test_bad_option_values_are_usage_errors(args: list[str], message: str) -> None:
    result, _ = invoke(["mesh", "star", *args])
    assert result.exit_code == 2 and message in result.stderr and "Traceback" not in result.output


def test_unknown_gallery_name_or_format_is_one_line(tmp_path: Path) -> None:
    result, caught = invoke(["mesh", "hexagon"])
    assert_one_line_failure(result, caught, "hexagon", r"hexagon: no such file, nor a gallery domain \(square-hole, l-shape, star")
    shape = tmp_path / "shape.svg"
    shape.write_text("<svg/>")
    result, caught = invoke(["mesh", str(shape)])
    assert_one_line_failure(result, caught, "shape.svg", r"unknown domain format \.svg; use one of \.poly, \.node or square-hole, l-shape")


def test_in_a_real_process_one_summary_line_and_no_warning(tmp_path: Path) -> None:
    exe = Path(sys.executable).with_name("persistri")
    run = subprocess.run(
        [str(exe), "mesh", "utm-tile", "-q", "33", "-o", str(tmp_path / "u.ele"), "--plot", str(tmp_path / "u.png"), "--check"],
        capture_output=True, text=True, env={**os.environ, "PYTHONWARNINGS": "error"}, timeout=300,
    )
    assert run.returncode == 0, run.stderr
    lines = [ln for ln in run.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("mesh of utm-tile: ") and "(verified exactly)" in lines[0], run.stderr
    assert run.stdout == ""
    assert files_under(tmp_path) == {"u.ele", "u.node", "u.poly", "u.png"}


def test_an_unenclosed_domain_points_to_convex(tmp_path: Path) -> None:
    """Triangle's own box.poly: the outer box has one segment, so the hole eats everything; --convex closes it."""
    poly = tmp_path / "box.poly"
    poly.write_text(
        "8 2 0 1\n1 0 0 0\n2 0 3 0\n3 3 0 0\n4 3 3 33\n5 1 1 0\n6 1 2 0\n7 2 1 0\n8 2 2 0\n"
        "5 1\n1 1 2 5\n2 5 7 0\n3 7 8 0\n4 8 6 10\n5 6 5 0\n1\n1 1.5 1.5\n"
    )
    result, caught = invoke(["mesh", str(poly)])
    assert_one_line_failure(result, caught, "box.poly", r"the domain is empty: .*; --convex meshes the convex hull, as Triangle's -c$")
    out = tmp_path / "box.npz"
    _ok(["mesh", str(poly), "--convex", "-q", "30", "-o", str(out), "--check", "--quiet"])
    mesh = _npz(out)
    assert sum(_twice_area(mesh["vertices"], mesh["triangles"])) == 2 * 8  # the 3 × 3 box less the unit hole


def test_npz_holds_the_record_of_the_undone_points(tmp_path: Path) -> None:
    out = tmp_path / "l.npz"
    stdout = _ok(["mesh", "l-shape", "-q", "30", "-a", "0.05", "-o", str(out), "--stats", "--quiet"])
    api = triangulate(gallery_domain("l-shape").pslg, min_angle=30, max_area=0.05)
    mesh = _npz(out)
    undone = api.history.undone
    assert len(undone) == api.undos > 0 and mesh["undone_xy"].shape == (api.undos, 2)
    assert mesh["undone_xy"].tolist() == [list(d.xy) for d in undone]
    assert mesh["undone_version"].tolist() == [d.version for d in undone]
    assert mesh["blocked_xy"].shape == (api.blocked, 2) and mesh["blocked_version"].tolist() == [d.version for d in api.history.blocked]
    # Each encroached subsegment by the rows of its ends in the output's vertices: the recorded coordinates.
    rows = mesh["undone_encroached"]
    assert rows.shape == (sum(len(d.encroached) for d in undone), 3)
    written = sorted((i, tuple(mesh["vertices"][a]), tuple(mesh["vertices"][b])) for i, a, b in rows.tolist())
    recorded = sorted((i, api.history.point(lo), api.history.point(hi)) for i, d in enumerate(undone) for lo, hi, _ in d.encroached)
    assert written == recorded
    lines = {ln.split("│")[1].strip(): ln.split("│")[2].strip() for ln in stdout.splitlines() if ln.count("│") == 3}
    first = min(d.version for d in undone)
    assert lines["versions an undo returned to (history.undone)"].startswith(
        f"{len({d.version for d in undone})} (history[{first}]"
    )


def test_a_vertex_closer_than_doubles_resolve_is_named_in_one_line(tmp_path: Path) -> None:
    # Triangle's own spiral.q.1.node: its 17th vertex (row 16) lies 0.001 ulp from a convex hull edge, named as
    # such (the file lists no segments), in the command's words (--convex, not the API's convex=True).
    source = Path(triangle.__file__).parent / "data" / "spiral.q.1.node"
    result, caught = invoke(["mesh", str(source), "-q", "30", "-o", str(tmp_path / "s.npz"), "--quiet"])
    assert_one_line_failure(
        result, caught, "spiral.q.1.node",
        r"input vertex 16 at \(-0\.6725000000000001, 1\.1995\) lies [\d.e-]+ \([\d.e-]+ units in the last place\) "
        r"from the convex hull edge \(0\.004999999999999942, 1\.963\)–\(-1\.35, 0\.436\) \(a \.node file, or "
        r"--convex, is meshed as its convex hull\), without being on it: .* \(rows counted from 0; the file numbers "
        r"from 1\)$",
    )
    assert files_under(tmp_path) == set()
    _ok(["mesh", str(source), "-q", "0", "--check", "--quiet"])  # its constrained Delaunay triangulation is fine


def test_refinement_messages_in_the_commands_words(tmp_path: Path) -> None:
    # A precision failure naming a segment (not only an input vertex) gets the numbering tail when the file numbers
    # from 1, and the API's convex=True reads --convex.
    from persistri.impl.cli.mesh import _in_command_words

    body = "4 2 0 0\n{0} 0 0\n{1} 1 0\n{2} 1 1\n{3} 0 1\n4 0\n{0} {0} {1}\n{1} {1} {2}\n{2} {2} {3}\n{3} {3} {0}\n0\n"
    one, zero = tmp_path / "one.poly", tmp_path / "zero.poly"
    one.write_text(body.format(1, 2, 3, 4))
    zero.write_text(body.format(0, 1, 2, 3))
    msg = "no pair of doubles lies on the subsegment 5–9 (mesh vertices) of segment 2 between (0.0, 1.0) and (1.0, 1.0)"
    assert _in_command_words(msg, str(one)) == msg + " (rows counted from 0; the file numbers from 1)"
    assert _in_command_words(msg, str(zero)) == msg
    assert _in_command_words("the mesh is fine", str(one)) == "the mesh is fine"
    hull = "from the convex hull edge (0, 0)–(1, 0) (a .node file, or convex=True, is meshed as its convex hull)"
    assert "or --convex, is meshed" in _in_command_words(hull, str(zero))


def test_without_the_checker_the_summary_does_not_call_the_smallest_angle_one_outside_the_exemption() -> None:
    # The needle's 30° mesh leaves triangles below the bound at its tiny input angle (exempt).  Without --check the
    # summary only knows the smallest angle of all, which lies in an exempt triangle: it said "min angle 0.00°
    # outside 37 exempt triangles" beside "bound 30° reached", a contradiction; with --check the checker's figure.
    api = triangulate(gallery_domain("needle").pslg, min_angle=30)
    assert api.exempt > 0 and api.min_angle_reached and api.smallest_angle() < 30
    plain, _ = invoke(["mesh", "needle", "-q", "30"])
    assert plain.exit_code == 0
    exempt = f"{api.exempt} exempt triangles at small input angles"
    assert f"min angle {api.smallest_angle():.2f}° counting {exempt}, ≥ 30° outside them (bound 30° reached)" in plain.stderr
    assert f"min angle {api.smallest_angle():.2f}° outside" not in plain.stderr
    checked, _ = invoke(["mesh", "needle", "-q", "30", "--check"])
    report = verify_mesh(api.domain, api.vertices, api.triangles, min_angle=30, exact_segments=api.exact_segments)
    assert report.min_angle_unexempt is not None and report.min_angle_unexempt >= 30
    assert f"min angle {report.min_angle_unexempt:.2f}° outside {exempt} (bound 30° reached)" in checked.stderr
