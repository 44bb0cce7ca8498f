"""Every command that reads a file × every malformed input, every command that writes × every bad output.

The contract (``persistri.impl.cli.errors``): exit status 2, exactly one
non-empty line on stderr that names the file, no traceback, no warning, no
output file left behind, and nothing computed — the command's compute function
is replaced by one that fails the test if it is called.  The matrix is generated
from the tables below; the positive tests check that the text reader's
variations (headers, delimiters, comments, blank lines, CRLF, BOM) read the
same points as the ``.npy``.
"""

from __future__ import annotations

import itertools
import os
import re
import subprocess
import sys
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner, Result

from persistri.impl.cli.main import main
from persistri.impl.complex.trace import save_trace
from persistri.impl.files import read_points
from persistri.impl.terrain.grids import write_asc

IS_ROOT = hasattr(os, "geteuid") and os.geteuid() == 0
"""Root reads and writes through permission bits: chmod cases are replaced, not dropped (see the cases)."""

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


class Computed(BaseException):
    """A command computed although its input or output was bad.

    Not an :class:`Exception`, so that no handler of the command line turns it
    into a one-line message: it ends the test where it is raised.
    """


def forbid(monkeypatch: pytest.MonkeyPatch, target: str) -> None:
    """Replace ``module:attribute`` by a function that fails the test when called."""
    module, attr = target.split(":")

    def called(*args: object, **kwargs: object) -> None:
        raise Computed(f"{target} was called")

    monkeypatch.setattr(f"{module}.{attr}", called)


def files_under(root: Path) -> set[str]:
    """Every path under ``root`` (hidden files included), relative."""
    return {str(p.relative_to(root)) for p in root.rglob("*")}


def invoke(args: list[str]) -> tuple[Result, list[str]]:
    """Run ``persistri ARGS`` in-process; the result and the warnings raised meanwhile."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = CliRunner().invoke(main, args)
    return result, [f"{w.category.__name__}: {w.message}" for w in caught]


def assert_one_line_failure(result: Result, caught: list[str], name: str, pattern: str) -> str:
    """Exit 2, one non-empty stderr line ``persistri: …`` naming ``name`` and matching ``pattern``; no noise."""
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert result.exit_code == 2, (result.exit_code, result.output, result.exception)
    assert len(lines) == 1, result.stderr
    line = lines[0]
    assert line.startswith("persistri: "), line
    assert name in line, line
    assert re.search(pattern, line), (pattern, line)
    assert "Traceback" not in result.output and "Aborted" not in result.output
    assert "Usage:" not in result.output
    assert not caught, caught
    return line


# -- malformed inputs -------------------------------------------------------------------------


POINTS = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.25, 0.25, 0.25]])


def _garbage(path: Path) -> Path:
    path.write_bytes(bytes(np.random.default_rng(7).integers(0, 256, 600, dtype=np.uint8)))
    return path


def _unreadable(path: Path, content: bytes) -> Path:
    path.write_bytes(content)
    path.chmod(0)
    return path


@dataclass(frozen=True)
class Case:
    """A malformed input: how to make it for a kind of input, and what the one line must say."""

    name: str
    make: Callable[[str, Path], Path]
    pattern: str


def _text_ext(kind: str) -> str:
    return {"points": ".csv", "grid": ".asc", "trace": ".json"}[kind]


def _binary_ext(kind: str) -> str:
    return {"points": ".npy", "grid": ".npy", "trace": ".npz"}[kind]


def _empty_file(kind: str, d: Path) -> Path:
    p = d / f"empty{_binary_ext(kind)}"
    p.write_bytes(b"")
    return p


def _empty_text(kind: str, d: Path) -> Path:
    p = d / f"empty{_text_ext(kind)}"
    p.write_text("")
    return p


def _empty_array(kind: str, d: Path) -> Path:
    p = d / "none.npy"
    np.save(p, np.zeros((0, 3)) if kind == "points" else np.zeros((0, 0)))
    return p


def _wrong_shape(kind: str, d: Path) -> Path:
    p = d / "flat.npy"
    np.save(p, np.arange(12.0))
    return p


def _wrong_columns(kind: str, d: Path) -> Path:
    if kind == "points":
        p = d / "four.csv"
        p.write_text("1,2,3,4\n5,6,7,8\n9,1,2,3\n")
    else:
        p = d / "row.npy"
        np.save(p, np.zeros((1, 9)))
    return p


def _nan(kind: str, d: Path) -> Path:
    if kind == "points":
        p = d / "nan.csv"
        p.write_text("0,0,0\n1,0,0\nnan,1,0\n0,0,1\n")
    else:
        p = d / "nan.npy"
        np.save(p, np.full((4, 5), np.nan))
    return p


def _inf(kind: str, d: Path) -> Path:
    p = d / "inf.npy"
    a = POINTS.copy() if kind == "points" else np.zeros((4, 5))
    a[2, 1] = np.inf
    np.save(p, a)
    return p


def _garbage_binary(kind: str, d: Path) -> Path:
    return _garbage(d / f"garbage{_binary_ext(kind)}")


def _garbage_text(kind: str, d: Path) -> Path:
    return _garbage(d / f"garbage{_text_ext(kind)}")


def _not_utf8(kind: str, d: Path) -> Path:
    p = d / f"latin1{_text_ext(kind)}"
    p.write_bytes("h\xf6he,breite,l\xe4nge\n1,2,3\n".encode("latin-1"))
    return p


def _unreadable_file(kind: str, d: Path) -> Path:
    if IS_ROOT:
        pytest.skip("root reads a chmod 000 file (the directory and dangling-symlink cases stand in)")
    return _unreadable(d / f"locked{_binary_ext(kind)}", b"\x93NUMPY")


def _directory(kind: str, d: Path) -> Path:
    p = d / f"folder{_binary_ext(kind)}"
    p.mkdir()
    return p


def _dangling(kind: str, d: Path) -> Path:
    p = d / f"link{_binary_ext(kind)}"
    p.symlink_to(d / "gone.npy")
    return p


def _missing(kind: str, d: Path) -> Path:
    return d / f"missing{_binary_ext(kind)}"


def _unknown_extension(kind: str, d: Path) -> Path:
    p = d / "points.dat"
    p.write_text("0 0 0\n1 0 0\n0 1 0\n0 0 1\n")
    return p


def _header_only(kind: str, d: Path) -> Path:
    p = d / f"header{_text_ext(kind)}"
    if kind == "points":
        p.write_text("x,y,z\n")
    elif kind == "grid":
        p.write_text("ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n")
    else:
        p.write_text('{"format": "persistri-trace"}')
    return p


def _ragged(kind: str, d: Path) -> Path:
    p = d / f"ragged{_text_ext(kind)}"
    if kind == "points":
        p.write_text("x,y,z\n0,0,0\n1,0,0\n\n# a comment\n0,1\n0,0,1\n")
    elif kind == "grid":
        p.write_text("ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 5\n")
    else:
        p.write_text('{"format": "persistri-trace", "format_version": 1, "n": 2, "operations": [], "events": [[1, 2], [3]]}')
    return p


def _pickled(kind: str, d: Path) -> Path:
    p = d / "objects.npy"
    np.save(p, np.array([[1, 2], [3]], dtype=object), allow_pickle=True)
    return p


def _truncated(kind: str, d: Path) -> Path:
    p = d / "cut.npy"
    np.save(p, np.zeros((50, 3)))
    p.write_bytes(p.read_bytes()[:300])
    return p


def _strings(kind: str, d: Path) -> Path:
    p = d / "words.npy"
    np.save(p, np.array([["a", "b", "c"], ["d", "e", "f"]]))
    return p


def _npz_keys(kind: str, d: Path) -> Path:
    p = d / "keys.npz"
    np.savez(p, first=np.zeros((3, 3)), second=np.ones((3, 3)))
    return p


CASES: dict[str, Case] = {
    c.name: c
    for c in (
        Case("empty file", _empty_file, r"empty|no data"),
        Case("empty text", _empty_text, r"empty|no points|not a readable|no ncols"),
        Case("empty array", _empty_array, r"no points|at least 2 rows"),
        Case("wrong shape", _wrong_shape, r"shape|2D array"),
        Case("wrong columns", _wrong_columns, r"line 1: expected 3 numbers, got 4|at least 2 rows and 2 columns"),
        Case("nan", _nan, r"line 3: a coordinate is not finite|every cell is no-data"),
        Case("inf", _inf, r"not finite|infinite"),
        Case("binary garbage", _garbage_binary, r"not a \.npy file|not a \.npz archive"),
        Case("text garbage", _garbage_text, r"binary|not UTF-8|not an ESRI|not a readable"),
        Case("not utf-8", _not_utf8, r"not UTF-8|not an ESRI|not a readable"),
        Case("unreadable", _unreadable_file, r"permission denied"),
        Case("directory", _directory, r"a directory"),
        Case("dangling symlink", _dangling, r"broken symbolic link"),
        Case("missing", _missing, r"no such file"),
        Case("unknown extension", _unknown_extension, r"unknown \w+ format \.dat"),
        Case("header only", _header_only, r"no points: a header line|holds 0 values|not a persistri trace|version"),
        Case("ragged", _ragged, r"line 6: expected 3 numbers, got 2|2 rows × 3 columns but the file holds 5|event 0 is not"),
        Case("pickled", _pickled, r"Python objects"),
        Case("truncated", _truncated, r"truncated"),
        Case("strings", _strings, r"not real numbers|not numbers"),
        Case("npz keys", _npz_keys, r"cannot tell which array holds the heights \(its 2D arrays are first, second\)"),
    )
}

_ALL_FILES = [
    "empty file", "empty text", "binary garbage", "text garbage", "unreadable", "directory", "dangling symlink",
    "missing", "unknown extension", "header only", "ragged",
]
_ARRAYS = ["empty array", "wrong shape", "nan", "inf", "pickled", "truncated", "strings"]
KIND_CASES: dict[str, list[str]] = {
    "points": [*_ALL_FILES, *_ARRAYS, "wrong columns", "not utf-8"],
    "grid": [*_ALL_FILES, *_ARRAYS, "wrong columns", "npz keys"],
    "trace": _ALL_FILES,
}


@dataclass(frozen=True)
class Reader:
    """A command that reads a file: how to call it on ``INPUT`` writing into ``OUT``, and what it computes."""

    name: str
    kind: str
    argv: Callable[[Path, Path], list[str]]
    compute: tuple[str, ...]


READERS = (
    Reader(
        "hull",
        "points",
        lambda i, o: ["hull", str(i), "-o", str(o / "hull.ply"), "--plot", str(o / "hull.png"), "--quiet"],
        ("persistri.impl.cli.hull:convex_hull",),
    ),
    Reader(
        "delaunay",
        "points",
        lambda i, o: ["delaunay", str(i), "-o", str(o / "tin.npz"), "--plot", str(o / "tin.png"), "--quiet"],
        ("persistri.impl.terrain.scattered:delaunay",),
    ),
    Reader(
        "terrain",
        "grid",
        lambda i, o: ["terrain", str(i), "--max-points", "10", "-o", str(o / "t.ply"), "--plot", str(o / "t.png"), "--quiet"],
        ("persistri.impl.terrain.greedy:greedy_insertion",),
    ),
    Reader(
        "bench terrain",
        "grid",
        lambda i, o: ["bench", "terrain", "--grid", str(i), "--sizes", "8"],
        ("persistri.impl.bench.terrain:run_terrain_bench",),
    ),
    Reader(
        "bench complex",
        "trace",
        lambda i, o: ["bench", "complex", "--trace", str(i), "--sizes", "40"],
        ("persistri.impl.bench.complex:run_complex_bench",),
    ),
)

# The delaunay reader takes 2 or 3 columns: its wrong-columns case is 4 columns, its ragged case reads
# "expected 3 numbers, got 2" on line 6 as the hull's does (the first data line has 3).
INPUT_MATRIX = [
    pytest.param(reader, CASES[case], id=f"{reader.name}-{case}")
    for reader in READERS
    for case in KIND_CASES[reader.kind]
]


@pytest.mark.parametrize(("reader", "case"), INPUT_MATRIX)
def test_malformed_input_is_one_line_and_nothing_is_computed(
    reader: Reader, case: Case, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    for target in reader.compute:
        forbid(monkeypatch, target)
    inputs, out = tmp_path / "in", tmp_path / "out"
    inputs.mkdir()
    out.mkdir()
    path = case.make(reader.kind, inputs)
    pattern = case.pattern
    if reader.name == "delaunay" and case.name == "wrong columns":
        pattern = r"line 1: expected 2 or 3 numbers, got 4"
    result, caught = invoke(reader.argv(path, out))
    assert_one_line_failure(result, caught, path.name, pattern)
    assert files_under(out) == set()


def test_the_matrix_covers_every_reader_and_case() -> None:
    """The generated matrix is the full product of the tables (a case dropped by mistake would shrink it)."""
    assert len(INPUT_MATRIX) == sum(len(KIND_CASES[r.kind]) for r in READERS)
    assert {c for cases in KIND_CASES.values() for c in cases} == set(CASES)


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


# -- text files read like the .npy ------------------------------------------------------------------


def _numbers() -> np.ndarray:
    rng = np.random.default_rng(11)
    return np.vstack([rng.random((40, 3)) * 2 - 1, [[1e-300, -2.5, 1e300], [0.1, 0.2, 0.3]]])


def _rows(points: np.ndarray, sep: str) -> list[str]:
    return [sep.join(repr(float(v)) for v in row) for row in points]


def _variants(points: np.ndarray) -> Iterator[tuple[str, bytes]]:
    rows = _rows(points, ",")
    yield "plain", ("\n".join(rows) + "\n").encode()
    yield "header", ("x,y,z\n" + "\n".join(rows) + "\n").encode()
    yield "two headers", ("survey 2024\nx,y,z\n" + "\n".join(rows)).encode()
    yield "quoted header", ('"x","y","z"\n' + "\n".join(rows) + "\n").encode()
    yield "semicolons", ("x;y;z\n" + "\n".join(_rows(points, ";")) + "\n").encode()
    yield "tabs", ("x\ty\tz\n" + "\n".join(_rows(points, "\t")) + "\n").encode()
    yield "spaces", ("\n".join("  " + r + "  " for r in _rows(points, "   ")) + "\n").encode()
    yield "comments", ("# exported\nx,y,z\n# units: m\n" + "\n".join(r + " # ok" for r in rows) + "\n# end\n").encode()
    yield "blank lines", ("\n\nx,y,z\n\n" + "\n\n".join(rows) + "\n\n\n").encode()
    yield "crlf", ("x,y,z\r\n" + "\r\n".join(rows) + "\r\n").encode()
    yield "bom", b"\xef\xbb\xbf" + ("x,y,z\n" + "\n".join(rows) + "\n").encode()
    yield "bom crlf comments", b"\xef\xbb\xbf" + ("# a\r\nx;y;z\r\n\r\n" + "\r\n".join(_rows(points, ";")) + "\r\n").encode()


VARIANTS = [pytest.param(name, content, id=name) for name, content in _variants(_numbers())]


@pytest.mark.parametrize(("name", "content"), VARIANTS)
@pytest.mark.parametrize("suffix", [".csv", ".txt", ".xyz"])
def test_text_variants_read_the_same_points_as_the_npy(tmp_path: Path, name: str, content: bytes, suffix: str) -> None:
    src = tmp_path / f"points{suffix}"
    src.write_bytes(content)
    np.save(tmp_path / "points.npy", _numbers())
    assert np.array_equal(read_points(src, (3,)), read_points(tmp_path / "points.npy", (3,)))


@pytest.mark.parametrize(("name", "content"), VARIANTS[:1] + VARIANTS[-2:])
def test_the_hull_of_a_text_file_is_the_hull_of_the_npy(tmp_path: Path, name: str, content: bytes) -> None:
    (tmp_path / "p.csv").write_bytes(content)
    np.save(tmp_path / "p.npy", _numbers())
    for src in ("p.csv", "p.npy"):
        result, caught = invoke(["hull", str(tmp_path / src), "-o", str(tmp_path / f"{src}.npz"), "--quiet"])
        assert result.exit_code == 0 and not caught, (result.output, caught)
    with np.load(tmp_path / "p.csv.npz") as a, np.load(tmp_path / "p.npy.npz") as b:
        assert np.array_equal(a["points"], b["points"]) and np.array_equal(a["simplices"], b["simplices"])


@pytest.mark.parametrize(
    ("content", "line", "what"),
    [
        ("x,y,z\n0,0,0\n\n# c\n1,2\n", 5, "expected 3 numbers, got 2"),
        ("# c\nx y z\n1 2 3\n4 5 six\n", 4, '"six" is not a number'),
        ("1;2;3\n4;5;6;\n", 2, 'an empty field: "4;5;6;"'),
        ("1,2,3\n4 5 6\n", 2, '"4 5 6" is not a number'),
        ("1,2,x\n3,4,5\n", 1, '"x" is not a number'),
        ("\r\n".join(["a,b,c"] + ["1,2,3"] * 5000 + ["1,2,inf"]) + "\r\n", 5002, r"a coordinate is not finite \(1\.0, 2\.0, inf\)"),
        ("\n".join(["a,b,c"] + ["1,2,3"] * 3000 + ["1,2"] + ["1,2,3"] * 3000), 3002, "expected 3 numbers, got 2"),
    ],
)
def test_a_bad_row_is_named_by_its_line_in_the_file(tmp_path: Path, content: str, line: int, what: str) -> None:
    src = tmp_path / "rows.csv"
    src.write_text(content, newline="")
    with pytest.raises(ValueError, match=f"^{re.escape(str(src))}: line {line}: {what}"):
        read_points(src, (3,))


# -- real processes: what a shell user sees ---------------------------------------------------------


def _persistri() -> list[str]:
    script = Path(sys.executable).with_name("persistri")
    return [str(script)] if script.exists() else [sys.executable, "-c", "from persistri.impl.cli.main import main; main()"]


@pytest.mark.parametrize(
    ("files", "argv", "name"),
    [
        ({"points.csv": b"x,y,z\n0,0,0\n1,0,0\n0,1,0\n0,0,1\n"}, ["hull", "points.csv", "-o", "no/such/dir/x.ply"], "x.ply"),
        ({"empty.npy": b""}, ["hull", "empty.npy"], "empty.npy"),
        ({"junk.npy": bytes(range(256)) * 3}, ["terrain", "junk.npy", "--max-points", "9"], "junk.npy"),
        ({"rows.csv": b"1,2,3\n4,5\n"}, ["delaunay", "rows.csv"], "rows.csv"),
    ],
)
def test_in_a_real_process_one_line_and_no_traceback(tmp_path: Path, files: dict[str, bytes], argv: list[str], name: str) -> None:
    for file, content in files.items():
        (tmp_path / file).write_bytes(content)
    run = subprocess.run([*_persistri(), *argv], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert run.returncode == 2, run.stderr
    assert run.stderr.count("\n") == 1 and run.stderr.startswith("persistri: ") and name in run.stderr, run.stderr
    assert run.stdout == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(files)


def test_in_a_real_process_extreme_coordinates_print_no_warning(tmp_path: Path) -> None:
    """Coordinates near ±1e308 and subnormal ones: correct answers, and nothing on stderr (warnings would print there)."""
    big = np.finfo(np.float64).max
    cube = np.array(list(itertools.product([-big, big], repeat=3)))
    np.save(tmp_path / "huge.npy", np.vstack([np.random.default_rng(5).random((30, 3)) * 2 - 1, cube]))
    np.save(tmp_path / "tiny.npy", np.random.default_rng(6).integers(-4, 5, (40, 3)) * 5e-324)
    np.save(tmp_path / "huge2.npy", np.vstack([np.random.default_rng(5).random((30, 2)), cube[::2, :2]]))
    np.save(tmp_path / "tiny2.npy", np.unique(np.random.default_rng(6).integers(-4, 5, (40, 2)) * 5e-324, axis=0))
    np.save(tmp_path / "relief.npy", np.random.default_rng(8).integers(-3, 4, (12, 13)) * 5e-324)
    np.save(tmp_path / "alps.npy", np.random.default_rng(9).random((12, 13)) * 2e250 - 1e250)
    runs = [
        ["hull", "huge.npy", "--check", "-o", "a.stl", "--plot", "a.png"],
        ["hull", "tiny.npy", "--check", "-o", "b.stl", "--plot", "b.png"],
        ["delaunay", "huge2.npy", "--check", "-o", "c.ply", "--plot", "c.png"],
        ["delaunay", "tiny2.npy", "--check", "-o", "d.stl", "--plot", "d.png"],
        ["terrain", "relief.npy", "--max-points", "30", "--check", "-o", "e.stl", "--plot", "e.png"],
        ["terrain", "alps.npy", "--max-points", "30", "--check", "-o", "f.npz", "--plot", "f.png"],
    ]
    for argv in runs:
        run = subprocess.run([*_persistri(), *argv, "--quiet"], cwd=tmp_path, capture_output=True, text=True, timeout=300)
        assert run.returncode == 0 and run.stderr == "", (argv, run.stderr)
    hull = [ln for ln in (tmp_path / "a.stl").read_text().splitlines() if "facet normal" in ln]
    assert len(hull) == 12 and not any("nan" in ln or "inf" in ln for ln in hull)  # the cube's 12 triangles
    rms = float(np.load(tmp_path / "f.npz")["rms_error"])
    assert 0 < rms < np.inf


def test_a_saved_trace_passes_the_checks_the_malformed_ones_fail(tmp_path: Path) -> None:
    from persistri.impl.bench.complex import hull_trace

    path = save_trace(hull_trace(20, seed=1), tmp_path / "t.json")
    result, caught = invoke(["bench", "complex", "--trace", str(path), "--only", "hamt", "--repeat", "1", "--json"])
    assert result.exit_code == 0 and not caught, (result.output, caught)
