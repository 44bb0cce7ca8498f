"""A new user's pass over the command line, second round (H7, 2026-11-28): each case failed before its fix.

Option values a user may well type (a size in scientific notation, a distribution in lower case, a list that
names nothing) must be a usage error naming the option, never an internal error or a message that names
another option.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_contract import assert_one_line_failure, invoke


@pytest.mark.parametrize(
    ("command", "option", "noun"),
    [
        (["bench", "maps"], "--sizes", "key count"),
        (["bench", "complex"], "--sizes", "triangle count"),
        (["bench", "hull"], "--sizes", "point count"),
        (["bench", "delaunay"], "--sizes", "point count"),
        (["bench", "terrain"], "--sizes", "vertex count"),
        (["bench", "scale"], "--workers", "worker count"),
    ],
)
def test_bench_sizes_name_what_they_count_and_overflow_is_a_usage_error(command: list[str], option: str, noun: str) -> None:
    # '1e400' is inf as a float: int() of it raised OverflowError, reported as an internal error (a bug).
    result, _ = invoke([*command, option, "1e400"])
    assert result.exit_code == 2 and "internal error" not in result.output
    assert f"Invalid value for '{option}': '1e400' is not a positive integer" in result.output
    # 'x' was "not a key count" in every benchmark, whatever its list counts.
    result, _ = invoke([*command, option, "x"])
    assert result.exit_code == 2
    assert f"Invalid value for '{option}': 'x' is not a {noun} (give integers separated by commas)" in result.output


@pytest.mark.parametrize(
    ("args", "message"),
    [
        # ValueError from inside the benchmark: one line, but naming no option.
        (["--sizes", "3"], "Invalid value for '--sizes': 3: a 3D hull needs at least 4 points"),
        (["--sizes", "100", "--dists", "nosuch"], "Invalid value for '--dists': unknown distribution 'nosuch'; known: OnSphere"),
        (["--sizes", "100", "--dists", ","], "Invalid value for '--dists': give at least one distribution"),
        (["--sizes", "100", "--memory", "--memory-dist", "x"], "Invalid value for '--memory-dist': unknown distribution 'x'"),
        (["--sizes", "100", "--backends", ","], "Invalid value for '--backends': give at least one backend"),
        # the option is --backends; the line named --backend.
        (["--sizes", "100", "--backends", "nosuch"], "persistri: --backends nosuch: unknown map backend 'nosuch'"),
    ],
)
def test_bench_hull_option_mistakes_name_the_option(args: list[str], message: str) -> None:
    result, _ = invoke(["bench", "hull", *args])
    assert result.exit_code == 2
    assert message in result.output, result.output
    assert "Traceback" not in result.output


def test_bench_hull_takes_distributions_in_any_case_as_hull_does() -> None:
    # `persistri hull --dist inball` works; `bench hull --dists inball` said "unknown distribution 'inball'".
    result, _ = invoke(["bench", "hull", "--sizes", "8", "--dists", "inball", "--json"])
    assert result.exit_code == 0, result.output
    assert '"InBall"' in result.stdout


def test_hull_n_below_four_is_a_usage_error_naming_the_option() -> None:
    # -n 0..3 was accepted and failed after the run started ("no 3D convex hull: 3 distinct points"), naming no option.
    result, _ = invoke(["hull", "--dist", "inball", "-n", "3"])
    assert result.exit_code == 2
    assert "Invalid value for '-n' / '--points': 3 is not in the range x>=4" in result.output


def test_helps_name_every_format_the_command_takes() -> None:
    # hull wrote .stl but its description listed .ply, .obj, .off and .npz; delaunay read .ply without saying so.
    import re

    from persistri.impl.files import MESH_FORMATS, POINT_FORMATS

    def description(command: str) -> str:
        result, _ = invoke([command, "--help"])
        text = result.output.split("Options:")[0]
        return re.sub(r"\s+", " ", text)

    hull_text, delaunay_text = description("hull"), description("delaunay")
    for suffix in MESH_FORMATS:
        assert suffix in hull_text and suffix in delaunay_text, suffix
    for suffix in POINT_FORMATS:
        assert suffix in hull_text and suffix in delaunay_text, suffix


def test_square_brackets_in_file_names_are_printed_as_they_are(tmp_path: Path) -> None:
    # rich read '[final]' as markup and dropped it: "hull of survey.csv", "Ruppert's refinement of lotpoly".
    points = tmp_path / "survey[final].csv"
    points.write_text("0 0 0\n1 0 0\n0 1 0\n0 0 1\n")
    result, _ = invoke(["hull", str(points), "-o", str(tmp_path / "h.ply")])
    assert result.exit_code == 0, result.output
    assert f"hull of {points}: 4 faces" in result.stderr
    domain = tmp_path / "lot[b].poly"
    domain.write_text("4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n")
    result, _ = invoke(["mesh", str(domain), "--stats"])
    assert result.exit_code == 0, result.output
    assert f"Ruppert's refinement of {domain}, undone by persistence" in result.stdout


def test_a_file_name_with_a_newline_stays_one_summary_line(tmp_path: Path) -> None:
    # Errors escaped it already; the summaries of a successful run printed it raw, breaking the line in two.
    stem = "a\nb"
    (tmp_path / f"{stem}.csv").write_text("0 0 0\n1 0 0\n0 1 0\n0 0 1\n")
    (tmp_path / f"{stem}.2.csv").write_text("0 0\n1 0\n0 1\n1 1\n")
    (tmp_path / f"{stem}.poly").write_text("4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n")
    (tmp_path / f"{stem}.txt").write_text("1 2 3\n4 5 6\n7 8 9\n")
    runs = [
        (["hull", str(tmp_path / f"{stem}.csv"), "-o", str(tmp_path / "h.ply")], "hull of "),
        (["delaunay", str(tmp_path / f"{stem}.2.csv"), "-o", str(tmp_path / "d.ply")], "delaunay of "),
        (["mesh", str(tmp_path / f"{stem}.poly")], "mesh of "),
        (["terrain", str(tmp_path / f"{stem}.txt"), "--max-points", "4", "-o", str(tmp_path / f"{stem}.npz")], "terrain "),
    ]
    for args, start in runs:
        result, _ = invoke(args)
        assert result.exit_code == 0, result.output
        lines = result.stderr.splitlines()
        assert lines and all("a\\nb" in line for line in lines), lines
        assert lines[0].startswith(start), lines


@pytest.mark.parametrize("group", [[], ["bench"], ["conformance"]])
def test_command_lists_show_whole_short_helps_in_80_columns(group: list[str]) -> None:
    # `persistri --help` listed "delaunay  The exact Delaunay triangulation of the points in INPUT..." and
    # `persistri bench --help` "delaunay  Exact 2D Delaunay of uniform random points against...": cut by click.
    from click.testing import CliRunner

    from persistri.impl.cli.main import main

    output = CliRunner().invoke(main, [*group, "--help"], terminal_width=80).output
    listed = output.split("Commands:")[1].splitlines()[1:]
    assert len(listed) >= 2
    for line in listed:
        assert not line.rstrip().endswith("..."), line
        assert len(line) <= 80 and line.startswith("  ") and len(line.split()) >= 3, line


@pytest.mark.parametrize("workers", [[], ["--workers", "1"]])
def test_tiles_without_dask_say_what_to_install(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, workers: list[str]) -> None:
    # Without the [dask] extra, `terrain --tile` was "internal error: ModuleNotFoundError: No module named
    # 'distributed'" (and 'dask' with --workers 1): the tiled modules import Dask only when they run.
    import sys
    from importlib.util import find_spec

    import numpy as np

    import persistri.impl.scale as scale

    for name in ("dask", "distributed"):
        monkeypatch.setitem(sys.modules, name, None)  # `import dask` now raises ImportError
    monkeypatch.setattr(scale, "find_spec", lambda name: None if name in ("dask", "distributed") else find_spec(name))
    grid = tmp_path / "g.npy"
    np.save(grid, np.add.outer(np.arange(12.0), np.arange(12.0)) ** 1.5)
    result, _ = invoke(["terrain", str(grid), "--tile", "6", "--max-error", "1", "-o", str(tmp_path / "t.npz"), *workers])
    assert result.exit_code == 2, result.output
    assert result.stderr == (
        "persistri: meshing by tiles needs Dask: dask and distributed not installed: the parallel path needs "
        "persistri[dask] (pip install 'persistri[dask]')\n"
    )
    assert not (tmp_path / "t.npz").exists()


def test_ply_columns_by_name_are_its_vertex_properties(tmp_path: Path) -> None:
    # `--columns x,y,z` on a PLY said "has no header to name columns by", though a PLY names x, y, z.
    ply = tmp_path / "p.ply"
    ply.write_text(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
    )
    result, _ = invoke(["hull", str(ply), "--columns", "X,y,z", "-o", str(tmp_path / "h.npz")])
    assert result.exit_code == 0, result.output
    result, _ = invoke(["delaunay", str(ply), "--columns", "z,y", "-o", str(tmp_path / "d.npz")])
    assert result.exit_code == 0, result.output
    import numpy as np

    with np.load(tmp_path / "d.npz") as d:
        assert d["points"].tolist() == [[0, 0], [0, 0], [0, 1], [1, 0]]
    result, caught = invoke(["hull", str(ply), "--columns", "x,y,w", "-o", str(tmp_path / "w.npz")])
    assert_one_line_failure(result, caught, "p.ply", r"no column 'w': PLY vertices are read as x, y, z$")


@pytest.mark.parametrize(
    ("text", "line"),
    [
        ("x;y;z\n0,5;0;0\n1;0;0\n0;1;0\n0;0;1\n", 2),  # was '"5;0;0" is not a number': split at the comma
        ("x;y;z\n1;0;0\n0;1;0\n0;0;1\n0;0;0,5\n", 5),
        ("0,5;0;0\n1;0;0\n0;1;0\n0;0;1\n", 1),
    ],
)
def test_decimal_commas_are_named_never_skipped(tmp_path: Path, text: str, line: int) -> None:
    # A spreadsheet's CSV where the comma is the decimal sign: fields separated by semicolons, numbers with
    # commas.  Such a row must be named for what it is, and a first row must not be skipped as a header.
    path = tmp_path / "eu.csv"
    path.write_text(text)
    result, caught = invoke(["hull", str(path), "-o", str(tmp_path / "h.npz")])
    assert_one_line_failure(
        result, caught, "eu.csv", rf'eu\.csv: line {line}: "0,5" is not a number \(a decimal comma: persistri reads decimal points, 0\.5\)$'
    )
    path.write_text(text.replace("0,5", "0.5"))
    result, _ = invoke(["hull", str(path), "-o", str(tmp_path / "h.npz")])
    assert result.exit_code == 0 and "hull of" in result.stderr and ": 4 faces, 4 vertices" in result.stderr, result.output


def test_a_comment_holding_a_semicolon_does_not_change_the_delimiter(tmp_path: Path) -> None:
    # With the semicolon taken first, '0,0,0 # origin; first' was split at ';' and its row dropped as a header.
    path = tmp_path / "c.csv"
    path.write_text("0,0,0 # origin; first\n1,0,0\n0,1,0\n0,0,1\n")
    result, _ = invoke(["hull", str(path), "-o", str(tmp_path / "h.npz")])
    assert result.exit_code == 0, result.output
    assert ": 4 faces, 4 vertices, 0 duplicate rows merged" in result.stderr


def test_a_number_too_large_for_a_double_is_named_as_written(tmp_path: Path) -> None:
    # '1e400' was reported as "a coordinate is not finite (0.0, 0.0, inf)": no inf is in the file.
    path = tmp_path / "big.csv"
    path.write_text("0 0 0\n1 0 0\n0 1 0\n0 0 1e400\n")
    result, caught = invoke(["hull", str(path), "-o", str(tmp_path / "h.npz")])
    assert_one_line_failure(
        result, caught, "big.csv",
        r'line 4: a coordinate is not finite \(0\.0, 0\.0, inf\): a number beyond the largest double \(about 1\.8e308\) in "0 0 1e400"$',
    )
    path.write_text("0 0 0\n1 0 0\n0 1 0\n0 0 -Inf\n")  # written as an infinity: no note
    result, caught = invoke(["hull", str(path), "-o", str(tmp_path / "h.npz")])
    assert_one_line_failure(result, caught, "big.csv", r"line 4: a coordinate is not finite \(0\.0, 0\.0, -inf\)$")
