"""A new user's pass over the command line (H7, 2026-11-28): each case failed before its fix.

Inputs the user did not write (files of other programs, hostile variants of them) must give one line
naming the file and exit status 2, or the right answer: never a traceback, an exit from inside a
library, or an answer computed on part of the input.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_contract import assert_one_line_failure, invoke

_HEADER = "ply\nformat ascii 1.0\nelement vertex {n}\n{props}end_header\n"
_XYZ = "property float x\nproperty float y\nproperty float z\n"


@pytest.mark.parametrize(
    ("name", "content", "pattern"),
    [
        # meshio.read printed "Expected ply" and called sys.exit(1): two lines, exit status 1.
        ("garbage.ply", "garbage\n", r"not a PLY file"),
        ("empty.ply", "", r"not a PLY file"),
        # meshio's ASCII reader returned the 2 vertices present: the hull of part of the file.
        ("truncated.ply", _HEADER.format(n=4, props=_XYZ) + "0 0 0\n1 0 0\n", r"truncated: .* announces 4 vertices, .* holds 2"),
        # 'max_rows' must be at least 1 (numpy's words).
        ("zero.ply", _HEADER.format(n=0, props=_XYZ), r"no points: .* 0 vertices"),
        # list index out of range (meshio's words).
        ("xy.ply", _HEADER.format(n=3, props="property float x\nproperty float y\n") + "0 0\n1 0\n0 1\n", r"properties x, y: .*x, y, z"),
        ("noend.ply", "ply\nformat ascii 1.0\nelement vertex 4\n" + _XYZ, r"no end_header"),
    ],
)
def test_bad_ply_is_one_line(tmp_path: Path, name: str, content: str, pattern: str) -> None:
    path = tmp_path / name
    path.write_text(content)
    for command in (["hull", str(path), "-o", str(tmp_path / "h.obj")], ["delaunay", str(path), "-o", str(tmp_path / "d.obj")]):
        result, caught = invoke(command)
        assert_one_line_failure(result, caught, name, pattern)
    assert not (tmp_path / "h.obj").exists() and not (tmp_path / "d.obj").exists()


def test_complete_ply_still_reads(tmp_path: Path) -> None:
    path = tmp_path / "tet.ply"
    path.write_text(_HEADER.format(n=4, props=_XYZ + "property uchar red\n") + "0 0 0 1\n1 0 0 2\n0 1 0 3\n0 0 1 4\n")
    result, caught = invoke(["hull", str(path), "-o", str(tmp_path / "h.npz")])
    assert result.exit_code == 0, result.output
    assert "4 faces, 4 vertices" in result.stderr


@pytest.mark.parametrize(
    "command",
    [
        ["hull", "--dist", "onsphere", "-n", "10", "--seed", "-5"],
        ["delaunay", "{points}", "--seed", "-1"],
        ["bench", "hull", "--sizes", "10", "--dists", "OnSphere", "--seed", "-1"],
        ["bench", "delaunay", "--sizes", "10", "--seed", "-1"],
        ["experiments", "fig6", "--quick", "--out", "{out}", "--seeds", "-1"],
    ],
)
def test_negative_seed_is_a_usage_error_naming_the_option(tmp_path: Path, command: list[str]) -> None:
    """numpy's "expected non-negative integer" came after the input was read, blamed on the input file
    (``persistri: points.csv: expected non-negative integer``), or on nothing at all."""
    points = tmp_path / "points.csv"
    points.write_text("0,0\n1,0\n0,1\n")
    args = [a.format(points=points, out=tmp_path / "out") for a in command]
    result, _ = invoke(args)
    assert result.exit_code == 2, result.output
    assert "--seed" in result.stderr, result.stderr
    assert "points.csv" not in result.stderr and "Traceback" not in result.output
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("value", ["nan", "inf", "-inf"])
def test_terrain_max_error_not_finite_is_a_usage_error(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, value: str) -> None:
    """It was ``persistri: grid.csv: max_error must be a finite number >= 0, got nan``, found after reading the
    grid and blamed on it; click's own range check already named the option for -1."""
    from cli_contract import forbid

    grid = tmp_path / "grid.csv"
    grid.write_text("1,2,3\n4,5,6\n7,8,10\n")
    forbid(monkeypatch, "persistri.impl.cli.terrain:read_grid")
    result, _ = invoke(["terrain", str(grid), "--max-error", value, "-o", str(tmp_path / "t.ply")])
    assert result.exit_code == 2, result.output
    assert "--max-error" in result.stderr and "grid.csv" not in result.stderr, result.stderr


def test_terrain_help_says_every_geotiff_needs_the_extra() -> None:
    """The help said that compressed GeoTIFFs need persistri[geotiff]; an uncompressed one needs it too
    (tifffile reads them all), so a user without the extra met 'reading GeoTIFF needs tifffile'."""
    result, _ = invoke(["terrain", "--help"])
    text = " ".join(result.output.split())
    assert "GeoTIFFs may be compressed" not in text
    assert "GeoTIFFs, compressed or not" in text and "persistri[geotiff]" in text


def test_bench_terrain_without_pydelatin_names_the_package(monkeypatch: pytest.MonkeyPatch) -> None:
    """It was ``internal error: ModuleNotFoundError: No module named 'pydelatin' (a bug in persistri; …)``
    after reading the grid; ``bench mesh`` already named its missing peer (Triangle) in one line."""
    import sys

    monkeypatch.setitem(sys.modules, "pydelatin", None)  # import pydelatin now raises ImportError
    result, caught = invoke(["bench", "terrain", "--sizes", "10"])
    line = assert_one_line_failure(result, caught, "pydelatin", r"not installed: pip install pydelatin")
    assert "internal error" not in line


@pytest.mark.parametrize(
    ("command", "option", "pattern"),
    [
        # Was "four.csv: line 1: expected 3 numbers, got 2": the file blamed for the option's count.
        (["hull", "{tet}", "--columns", "0,1"], True, r"0,1 names 2 columns; give 3 \(x,y,z\)"),
        (["delaunay", "{tet}", "--columns", "0,1,2,0"], True, r"names 4 columns; give 2 or 3"),
        # Was "no column '-1' in the header (0, 0, 0)": a number read as a name, a data line as the header.
        (["hull", "{tet}", "--columns", "-1,0,1"], True, r"count from 0, got -1"),
        # Was "no columns 'a', 'b', 'c' in the header (0, 0, 0)": the file has no header at all.
        (["hull", "{tet}", "--columns", "a,b,c"], False, r"tet.csv: has no header line to name columns by"),
    ],
)
def test_columns_mistakes_name_what_is_wrong(tmp_path: Path, command: list[str], option: bool, pattern: str) -> None:
    import re

    tet = tmp_path / "tet.csv"
    tet.write_text("0,0,0\n1,0,0\n0,1,0\n0,0,1\n")
    result, _ = invoke([a.format(tet=tet) for a in command] + ["-o", str(tmp_path / "m.obj")])
    assert result.exit_code == 2, result.output
    assert re.search(pattern, result.stderr), result.stderr
    assert ("--columns" in result.stderr) == option and "line 1" not in result.stderr, result.stderr
    assert "in the header (0, 0, 0)" not in result.stderr


def test_columns_by_name_still_pick_from_a_real_header(tmp_path: Path) -> None:
    survey = tmp_path / "survey.csv"
    survey.write_text("# survey\nid;east;north;height;note\n1;0;0;0;a\n2;1;0;0;b\n3;0;1;0;c\n4;0;0;1;d\n")
    result, _ = invoke(["hull", str(survey), "--columns", "east,north,height", "-o", str(tmp_path / "h.npz")])
    assert result.exit_code == 0, result.output
    result, _ = invoke(["hull", str(survey), "--columns", "east,north,heigth", "-o", str(tmp_path / "h.npz")])
    assert "no column 'heigth' in the header (id, east, north, height, note)" in result.stderr, result.stderr


def test_delaunay_warns_when_merged_rows_have_another_z(tmp_path: Path) -> None:
    """Rows with equal x, y but different z were merged as "exactly equal rows", the second z dropped in
    silence: a TIN with a height the survey did not measure there, and nothing said."""
    survey = tmp_path / "xyzi.csv"
    survey.write_text("X,Y,Z,intensity\n0,0,0,5\n1,0,0,6\n0,1,0,7\n0,0,1,8\n")
    for quiet in ([], ["--quiet"]):
        result, _ = invoke(["delaunay", str(survey), "-o", str(tmp_path / "t.npz"), *quiet])
        assert result.exit_code == 0, result.output
        assert "warning: " in result.stderr and "row 3 has the x, y of row 0 but another z (1.0, not 0.0)" in result.stderr
        assert ("delaunay of" in result.stderr) == (not quiet)
    result, _ = invoke(["delaunay", str(survey), "-o", str(tmp_path / "t.npz")])
    said = " ".join(result.stderr.split())
    assert "1 triangle, 3 vertices" in said and "1 duplicate row merged (row 3 = row 0)" in said, said


def test_delaunay_equal_rows_merge_without_a_warning(tmp_path: Path) -> None:
    pts = tmp_path / "p.csv"
    pts.write_text("0,0,5\n1,0,6\n0,1,7\n0,0,5\n")
    result, _ = invoke(["delaunay", str(pts), "-o", str(tmp_path / "t.npz")])
    assert result.exit_code == 0 and "warning" not in result.stderr, result.stderr


def test_command_list_shows_whole_short_helps() -> None:
    """``persistri --help`` listed ``experiments  Regenerate the paper's Fig.``: click cuts the first sentence
    at "Fig." (a period and a space)."""
    result, _ = invoke(["--help"])
    line = next(ln for ln in result.output.splitlines() if ln.strip().startswith("experiments"))
    assert not line.rstrip().endswith("Fig."), line
    assert "11" in line, line


def test_hull_summary_counts_one_duplicate_in_the_singular(tmp_path: Path) -> None:
    pts = tmp_path / "p.csv"
    pts.write_text("0,0,0\n-0.0,0,0\n1,0,0\n0,1,0\n0,0,1\n")
    result, _ = invoke(["hull", str(pts), "-o", str(tmp_path / "h.npz")])
    assert "4 faces, 4 vertices, 1 duplicate row merged" in result.stderr, result.stderr


_WKT = (
    'PROJCS["WGS_1984_UTM_Zone_14N",GEOGCS["GCS_WGS_1984",DATUM["D_WGS_1984",SPHEROID["WGS_1984",6378137.0,'
    '298.257223563]],PRIMEM["Greenwich",0.0],UNIT["Degree",0.0174532925199433]],PROJECTION["Transverse_Mercator"],'
    'PARAMETER["False_Easting",500000.0],PARAMETER["False_Northing",0.0],PARAMETER["Central_Meridian",-99.0],'
    'PARAMETER["Scale_Factor",0.9996],PARAMETER["Latitude_Of_Origin",0.0],UNIT["Meter",1.0]]'
)


def test_terrain_world_checks_its_prj_before_the_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """``terrain dem.tif --world -o tin.ply`` with a directory tin.prj computed the mesh, then failed on the
    .prj after renaming tin.ply into place: exit 2, and a tin.ply left behind."""
    from cli_contract import forbid

    (tmp_path / "dem.asc").write_text(
        "ncols 3\nnrows 3\nxllcorner 500000\nyllcorner 4000000\ncellsize 10\n1 2 3\n4 5 6\n7 8 10\n"
    )
    (tmp_path / "dem.prj").write_text(_WKT)
    out = tmp_path / "out"
    out.mkdir()
    (out / "tin.prj").mkdir()
    forbid(monkeypatch, "persistri.impl.terrain.greedy:greedy_insertion")
    result, caught = invoke(["terrain", str(tmp_path / "dem.asc"), "--max-points", "4", "--world", "-o", str(out / "tin.ply")])
    assert_one_line_failure(result, caught, "tin.prj", r"a directory")
    assert sorted(p.name for p in out.iterdir()) == ["tin.prj"]


def test_outputs_are_renamed_all_or_none(tmp_path: Path) -> None:
    """A target that became a directory after the checks: the other outputs stay unwritten too."""
    from click import ClickException

    from persistri.impl.cli.checks import Outputs

    outputs = Outputs()
    first, second = tmp_path / "a.ply", tmp_path / "b.png"
    outputs.file(first, (".ply",), what="mesh")
    outputs.file(second, (".png",), what="plot")
    with pytest.raises(ClickException, match="b.png: cannot write it"):
        with outputs.staged() as stage:
            stage(first).write_text("mesh")
            stage(second).write_text("plot")
            second.mkdir()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.png"]


@pytest.mark.parametrize(
    ("extra", "pattern"),
    [
        # Both ran the suite and reported law failures (exit 1): "FAILED isolation — error: the structure raised …".
        (["--state", "json:dumps"], r"--state json:dumps: calling it with no arguments failed \(TypeError"),
        (["--state", "persistri.impl.complex.vertex:VertexState.initial", "--dims", "2,7"], r"--dims 2,7: .* refuses new\(7\); the dimensions it makes: 2"),
    ],
)
def test_conformance_complex_usage_mistakes_exit_2(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, extra: list[str], pattern: str) -> None:
    pytest.importorskip("hypothesis")
    (tmp_path / "h7_complexes.py").write_text(
        "from persistri.impl.complex import complex_structure\nC2 = complex_structure(2, 'red_black')\n"
    )
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    args = ["conformance", "complex", "h7_complexes:C2", *extra, "--max-examples", "2", "--workload-size", "0", "--stateful-steps", "0"]
    result, caught = invoke(args)
    assert_one_line_failure(result, caught, "--", pattern)
    assert "FAILED" not in result.output


@pytest.mark.parametrize(
    "text",
    [
        '"x","y","z"\n"0","0","0"\n"1","0","0"\n"0","1","0"\n"0","0","1"\n',  # a spreadsheet's export
        '"0","0","0"\n"1","0","0"\n"0","1","0"\n"0","0","1"\n',
        'x,y,z\n0,0,0\n"1",0,0\n0,"1",0\n0,0,"1"\n',
    ],
)
def test_quoted_numbers_are_read(tmp_path: Path, text: str) -> None:
    """Was ``no points: 5 lines of text and no row of numbers``: every quoted row taken for a header."""
    path = tmp_path / "quoted.csv"
    path.write_text(text)
    result, _ = invoke(["hull", str(path), "-o", str(tmp_path / "h.npz")])
    assert result.exit_code == 0, result.output
    assert "4 faces, 4 vertices" in result.stderr


def test_a_quoted_word_in_the_data_is_still_named(tmp_path: Path) -> None:
    path = tmp_path / "quoted.csv"
    path.write_text('"x","y","z"\n"0","0","0"\n"1","0","0"\n"0","1","0"\n"0","0","q"\n')
    result, caught = invoke(["hull", str(path), "-o", str(tmp_path / "h.npz")])
    assert_one_line_failure(result, caught, "quoted.csv", r'line 5: "q" is not a number')


def test_tiled_terrain_world_checks_its_prj_before_the_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The tiled path too meshed every tile before failing on a directory tin.prj."""
    pytest.importorskip("dask")
    from cli_contract import forbid

    (tmp_path / "dem.asc").write_text(
        "ncols 3\nnrows 3\nxllcorner 500000\nyllcorner 4000000\ncellsize 10\n1 2 3\n4 5 6\n7 8 10\n"
    )
    (tmp_path / "dem.prj").write_text(_WKT)
    (tmp_path / "tin.prj").mkdir()
    forbid(monkeypatch, "persistri.impl.scale.terrain:tiled_terrain")
    args = ["terrain", str(tmp_path / "dem.asc"), "--tile", "3", "--workers", "1", "--max-error", "1", "--world", "-o", str(tmp_path / "tin.ply")]
    result, caught = invoke(args)
    assert_one_line_failure(result, caught, "tin.prj", r"a directory")
    assert not (tmp_path / "tin.ply").exists()


def test_an_output_named_only_by_its_extension_is_refused_plainly(tmp_path: Path) -> None:
    result, caught = invoke(["hull", "--dist", "inball", "-n", "100", "-o", str(tmp_path / ".ply")])
    assert_one_line_failure(result, caught, ".ply", r"a name that is only an extension; give a file name, such as mesh\.ply")


def test_a_file_name_with_a_newline_stays_one_error_line(tmp_path: Path) -> None:
    name = "a\nb.csv"
    result, caught = invoke(["hull", str(tmp_path / name), "-o", str(tmp_path / "h.ply")])
    assert_one_line_failure(result, caught, "a\\nb.csv", r"no such file")
