"""Every command that writes × every bad output: one line naming the path, exit 2, before any computation.

Also: a missing last directory is created, a failure while writing leaves no
file (nor a half-replaced one), and failures that come from the computation or
from a bug in persistri are one line too.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from cli_contract import IS_ROOT, PNG_MAGIC, assert_one_line_failure, files_under, forbid, invoke

# -- bad outputs -------------------------------------------------------------------------------


def _valid_inputs(d: Path) -> dict[str, Path]:
    d.mkdir()
    np.savetxt(d / "cloud.csv", np.random.default_rng(3).random((30, 3)), delimiter=",", header="x,y,z", fmt="%.17g")
    np.save(d / "grid.npy", np.cumsum(np.random.default_rng(4).normal(size=(9, 11)), axis=1))
    return {"points": d / "cloud.csv", "grid": d / "grid.npy"}


@dataclass(frozen=True)
class Writer:
    """A command that writes a file (``option`` names it), with a valid input otherwise."""

    name: str
    argv: Callable[[dict[str, Path], str, Path], list[str]]  # (inputs, option, bad path) -> argv
    options: tuple[str, ...]
    suffix: dict[str, str]  # option -> a valid extension
    compute: tuple[str, ...]


WRITERS = (
    Writer(
        "hull",
        lambda i, opt, p: ["hull", str(i["points"]), opt, str(p), "--quiet"],
        ("-o", "--plot"),
        {"-o": ".ply", "--plot": ".png"},
        ("persistri.impl.cli.hull:convex_hull",),
    ),
    Writer(
        "hull --dist",
        lambda i, opt, p: ["hull", "--dist", "InBall", "-n", "10000000", opt, str(p), "--quiet"],
        ("-o", "--plot"),
        {"-o": ".npz", "--plot": ".png"},
        ("persistri.impl.cli.hull:convex_hull", "persistri.impl.cli.hull:generate"),
    ),
    Writer(
        "delaunay",
        lambda i, opt, p: ["delaunay", str(i["points"]), opt, str(p), "--quiet"],
        ("-o", "--plot"),
        {"-o": ".obj", "--plot": ".svg"},
        ("persistri.impl.terrain.scattered:delaunay",),
    ),
    Writer(
        "terrain",
        lambda i, opt, p: ["terrain", str(i["grid"]), "--max-points", "10", opt, str(p), "--quiet"],
        ("-o", "--plot"),
        {"-o": ".stl", "--plot": ".png"},
        ("persistri.impl.terrain.greedy:greedy_insertion",),
    ),
    Writer(
        "mesh",
        lambda i, opt, p: ["mesh", "star", "-q", "30", opt, str(p), "--check", "--quiet"],
        ("-o", "--plot"),
        {"-o": ".ele", "--plot": ".svg"},
        ("persistri.impl.mesh.api:triangulate",),
    ),
)

DIR_WRITERS = (
    Writer(
        "experiments",
        lambda i, opt, p: ["experiments", "fig8", "--quick", opt, str(p)],
        ("--out",),
        {},
        ("persistri.impl.cli.experiments:run_experiments",),
    ),
    Writer(
        "experiments --replot",
        lambda i, opt, p: ["experiments", "fig8", "--replot", opt, str(p)],
        ("--out",),
        {},
        ("persistri.impl.cli.experiments:replot",),
    ),
    Writer(
        "demo",
        lambda i, opt, p: ["demo", opt, str(p)],
        ("--out",),
        {},
        ("persistri.impl.cli.demo:run_demo",),
    ),
)


def _unwritable_dir(d: Path) -> tuple[Path, str]:
    """A directory no file can be created in, and the reason the message gives.

    Root writes through permission bits: a regular file standing where the
    directory should be is unwritable for root too.
    """
    if IS_ROOT:
        blocker = d / "plain-file"
        blocker.write_text("not a directory\n")
        return blocker, "is not a directory|no such directory"
    locked = d / "locked"
    locked.mkdir()
    locked.chmod(0o555)
    return locked, "permission denied"


@dataclass(frozen=True)
class BadOutput:
    name: str
    make: Callable[[Path, str], tuple[Path, str]]  # (scratch dir, valid suffix) -> (path, pattern)


BAD_FILES = (
    BadOutput("missing directory", lambda d, s: (d / "no" / "such" / "dir" / f"x{s}", r"directory .*no/such/dir does not exist")),
    BadOutput("directory as path", lambda d, s: (_mkdir(d / f"taken{s}"), r"a directory; give a file name")),
    BadOutput("unwritable directory", lambda d, s: _inside(_unwritable_dir(d), f"x{s}")),
    BadOutput("unknown extension", lambda d, s: (d / "x.bmpx", r"unknown \w+ format \.bmpx; use one of")),
    BadOutput("no extension", lambda d, s: (d / "result", r"unknown \w+ format \(no extension\)")),
)

BAD_DIRS = (
    BadOutput("missing parent", lambda d, s: (d / "no" / "such" / "out", r"directory .*no/such does not exist|no such directory")),
    BadOutput("a file", lambda d, s: (_touch(d / "out.txt"), r"not a directory|no such directory")),
    BadOutput("unwritable parent", lambda d, s: _inside(_unwritable_dir(d), "out")),
)
# --replot reads --out: a missing or unusable directory is "no such directory" there.


def _mkdir(p: Path) -> Path:
    p.mkdir()
    return p


def _touch(p: Path) -> Path:
    p.write_text("x\n")
    return p


def _inside(made: tuple[Path, str], name: str) -> tuple[Path, str]:
    directory, reason = made
    return directory / name, reason


OUTPUT_MATRIX = [
    pytest.param(writer, option, bad, id=f"{writer.name}-{option}-{bad.name}")
    for writer in WRITERS
    for option in writer.options
    for bad in BAD_FILES
] + [
    pytest.param(writer, "--out", bad, id=f"{writer.name}-{bad.name}")
    for writer in DIR_WRITERS
    for bad in BAD_DIRS
]


@pytest.mark.parametrize(("writer", "option", "bad"), OUTPUT_MATRIX)
def test_bad_output_fails_before_computing(
    writer: Writer, option: str, bad: BadOutput, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    for target in writer.compute:
        forbid(monkeypatch, target)
    inputs = _valid_inputs(tmp_path / "in")
    scratch = tmp_path / "scratch"
    scratch.mkdir()
    path, pattern = bad.make(scratch, writer.suffix.get(option, ""))
    before = files_under(tmp_path)
    result, caught = invoke(writer.argv(inputs, option, path))
    assert_one_line_failure(result, caught, path.name, pattern)
    assert files_under(tmp_path) == before


def test_the_output_matrix_is_the_full_product() -> None:
    expected = sum(len(w.options) for w in WRITERS) * len(BAD_FILES) + len(DIR_WRITERS) * len(BAD_DIRS)
    assert len(OUTPUT_MATRIX) == expected


def test_an_output_named_twice_is_refused(tmp_path: Path) -> None:
    """No two options of one command share an extension today; the check stands for the day two do."""
    from persistri.impl.cli.checks import Outputs
    from persistri.impl.cli.errors import CliError

    outputs = Outputs()
    outputs.file(tmp_path / "a.png", (".png",), what="plot")
    with pytest.raises(CliError, match="a.png: named as two outputs"):
        outputs.file(tmp_path / "." / "a.png", (".png",), what="plot")


# -- writing: all or nothing ----------------------------------------------------------------------


def test_a_missing_last_directory_is_created(tmp_path: Path) -> None:
    inputs = _valid_inputs(tmp_path / "in")
    result, caught = invoke(["hull", str(inputs["points"]), "-o", str(tmp_path / "new" / "h.ply"), "--plot", str(tmp_path / "new" / "h.png"), "--quiet"])
    assert result.exit_code == 0, result.output
    assert not caught, caught
    assert sorted(files_under(tmp_path / "new")) == ["h.ply", "h.png"]
    assert (tmp_path / "new" / "h.png").read_bytes().startswith(PNG_MAGIC)


def test_a_failure_while_writing_leaves_no_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The mesh is written, then the plot fails: neither appears, the made directory is removed, one line names the plot."""
    inputs = _valid_inputs(tmp_path / "in")

    def broken_plot(points: object, simplices: object, path: Path, **kwargs: object) -> Path:
        Path(path).write_bytes(b"half a png")
        raise OSError(28, "No space left on device", str(path))

    monkeypatch.setattr("persistri.impl.hull.plot.plot_hull", broken_plot)
    new = tmp_path / "new"
    result, caught = invoke(["hull", str(inputs["points"]), "-o", str(new / "h.ply"), "--plot", str(new / "h.png"), "--quiet"])
    line = assert_one_line_failure(result, caught, "h.png", r"cannot write it \(No space left on device\)$")
    assert ".partial" not in line  # the temporary file is not what the user named
    assert not new.exists()


def test_an_existing_output_is_replaced_only_when_all_is_written(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    inputs = _valid_inputs(tmp_path / "in")
    old = tmp_path / "h.ply"
    old.write_text("the previous mesh\n")

    def broken_plot(points: object, simplices: object, path: Path, **kwargs: object) -> Path:
        raise OSError(5, "Input/output error")

    monkeypatch.setattr("persistri.impl.hull.plot.plot_hull", broken_plot)
    result, caught = invoke(["hull", str(inputs["points"]), "-o", str(old), "--plot", str(tmp_path / "h.png"), "--quiet"])
    assert_one_line_failure(result, caught, "h.png", "input/output error|Input/output error")
    assert old.read_text() == "the previous mesh\n"
    assert sorted(files_under(tmp_path)) == sorted(["h.ply", "in", "in/cloud.csv", "in/grid.npy"])


# -- failures that come from the computation ------------------------------------------------------


def test_a_degenerate_input_names_the_file(tmp_path: Path) -> None:
    flat = tmp_path / "flat.csv"
    flat.write_text("x y z\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n")
    result, caught = invoke(["hull", str(flat), "-o", str(tmp_path / "h.ply"), "--quiet"])
    assert_one_line_failure(result, caught, "flat.csv", r"flat\.csv: .*coplanar")
    assert not (tmp_path / "h.ply").exists()


def test_a_bug_is_one_line_and_its_traceback_on_request(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    inputs = _valid_inputs(tmp_path / "in")

    def buggy(*args: object, **kwargs: object) -> None:
        raise ZeroDivisionError("division by zero")

    monkeypatch.setattr("persistri.impl.cli.hull.convex_hull", buggy)
    result, caught = invoke(["hull", str(inputs["points"]), "--quiet"])
    assert_one_line_failure(result, caught, "internal error", r"ZeroDivisionError: division by zero \(a bug in persistri; PERSISTRI_DEBUG=1")
    monkeypatch.setenv("PERSISTRI_DEBUG", "1")
    result, _ = invoke(["hull", str(inputs["points"]), "--quiet"])
    assert isinstance(result.exception, ZeroDivisionError)


def test_usage_errors_keep_clicks_form(tmp_path: Path) -> None:
    """A mistake in the command line itself (not in a file) is click's usage error, status 2, without Python syntax."""
    result, _ = invoke(["terrain", "jacksboro", "--max-points", "10", "--nodata", "foo"])
    assert result.exit_code == 2
    assert "Invalid value for '--nodata': foo is neither error, fill, min nor a height" in result.stderr
    assert "'foo'" not in result.stderr
