"""Every command that reads a file × every malformed input: one line naming the file, exit 2, nothing computed.

The matrix is generated from the tables below (:data:`READERS` × the cases of
each reader's kind of input) and checked against the contract of
``persistri.impl.cli.errors`` (:mod:`cli_contract`): exit status 2, exactly one
non-empty stderr line that names the file and says what is wrong, no
traceback, no warning, no output file, and the compute function never called.
The bad outputs are in ``test_cli_inputs_outputs.py``, the text reader's
variations and real processes in ``test_cli_inputs_text.py``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from cli_contract import IS_ROOT, assert_one_line_failure, files_under, forbid, invoke

from persistri.impl.complex.trace import save_trace

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
    return {"points": ".csv", "grid": ".asc", "trace": ".json", "domain": ".poly"}[kind]


def _binary_ext(kind: str) -> str:
    return {"points": ".npy", "grid": ".npy", "trace": ".npz", "domain": ".node"}[kind]


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
    if kind == "domain":
        p = d / "nan.node"
        p.write_text("4 2 0 0\n1 0 0\n2 1 0\nnan 1 1\n4 0 1\n")
        return p
    if kind == "points":
        p = d / "nan.csv"
        p.write_text("0,0,0\n1,0,0\nnan,1,0\n0,0,1\n")
    else:
        p = d / "nan.npy"
        np.save(p, np.full((4, 5), np.nan))
    return p


def _inf(kind: str, d: Path) -> Path:
    if kind == "domain":
        p = d / "inf.poly"
        p.write_text("4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 -inf\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n")
        return p
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
    elif kind == "domain":
        p.write_text("# a square, the vertices missing\n4 2 0 0\n")
    elif kind == "grid":
        p.write_text("ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n")
    else:
        p.write_text('{"format": "persistri-trace"}')
    return p


def _ragged(kind: str, d: Path) -> Path:
    p = d / f"ragged{_text_ext(kind)}"
    if kind == "points":
        p.write_text("x,y,z\n0,0,0\n1,0,0\n\n# a comment\n0,1\n0,0,1\n")
    elif kind == "domain":
        p.write_text("4 2 0 0\n1 0 0\n2 1 0\n\n# a comment\n3 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n")
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


def _third_format(kind: str, d: Path) -> Path:
    """The reader's format that goes through a library of its own: a PLY for points, a GeoTIFF for grids."""
    if kind == "points":
        p = d / "mesh.ply"
        p.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 0\n")
    else:
        p = d / "dem.tif"
        p.write_bytes(b"II*\x00\x08\x00\x00\x00")  # a TIFF header whose first page is missing
    return p


# Domains (Triangle's .poly and .node files): what only a domain can get wrong.
_SQUARE = "4 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 0 4\n"
_FRAME = _SQUARE + "5 1 1\n6 3 1\n7 3 3\n8 1 3\n"


def _poly(d: Path, name: str, text: str) -> Path:
    p = d / name
    p.write_text(text)
    return p


def _crossing(kind: str, d: Path) -> Path:
    return _poly(d, "crossing.poly", _SQUARE + "2 0\n1 1 3\n2 2 4\n0\n")


def _segment_out_of_range(kind: str, d: Path) -> Path:
    return _poly(d, "range.poly", _SQUARE + "4 0\n1 1 2\n2 2 3\n3 3 9\n4 4 1\n0\n")


def _self_segment(kind: str, d: Path) -> Path:
    return _poly(d, "loop.poly", _SQUARE + "4 0\n1 1 1\n2 2 3\n3 3 4\n4 4 1\n0\n")


def _hole_outside(kind: str, d: Path) -> Path:
    return _poly(d, "far.poly", _SQUARE + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n1\n1 5 5\n")


def _unclosed_hole(kind: str, d: Path) -> Path:
    """The square hole's boundary lacks its last side: the hole point's flood fill eats the whole square."""
    frame = _FRAME.replace("4 2 0 0", "8 2 0 0")
    return _poly(d, "open.poly", frame + "7 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 5 6\n6 6 7\n7 7 8\n1\n1 2 2\n")


def _node_file_missing(kind: str, d: Path) -> Path:
    return _poly(d, "vertices-elsewhere.poly", "0 2 0 0\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n")


def _collinear(kind: str, d: Path) -> Path:
    return _poly(d, "line.node", "3 2 0 0\n1 0 0\n2 1 1\n3 2 2\n")


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
        Case("nan", _nan, r"line 3: a coordinate is not finite|every cell is no-data|nan\.node:4: a vertex line has a value that is not finite"),
        Case("inf", _inf, r"not finite|infinite"),
        Case("binary garbage", _garbage_binary, r"not a \.npy file|not a \.npz archive|garbage\.node: not a Triangle file: binary data \(a NUL byte at offset \d+\)"),
        Case("text garbage", _garbage_text, r"binary|not UTF-8|not an ESRI|not a readable|garbage\.poly:1: the vertex count line: .* must be an integer"),
        Case("not utf-8", _not_utf8, r"not UTF-8|not an ESRI|not a readable"),
        Case("unreadable", _unreadable_file, r"permission denied"),
        Case("directory", _directory, r"a directory"),
        Case("dangling symlink", _dangling, r"broken symbolic link"),
        Case("missing", _missing, r"no such file"),
        Case("unknown extension", _unknown_extension, r"unknown \w+ format \.dat"),
        Case("header only", _header_only, r"no points: a header line|holds 0 values|not a persistri trace|version|header\.poly:2: the file ends after 0 of the 4 vertex lines"),
        Case(
            "ragged",
            _ragged,
            r"line 6: expected 3 numbers, got 2|2 rows × 3 columns but the file holds 5|event 0 is not|ragged\.poly:6: a vertex line needs 3 numbers",
        ),
        Case("pickled", _pickled, r"Python objects"),
        Case("truncated", _truncated, r"truncated"),
        Case("strings", _strings, r"not real numbers|not numbers"),
        Case("damaged ply or tiff", _third_format, r"cannot read PLY|holds no image|cannot read TIFF|needs tifffile"),
        Case("npz keys", _npz_keys, r"cannot tell which array holds the heights \(its 2D arrays are first, second\)"),
        Case("crossing segments", _crossing, r"segment 0 \(0–2\) and segment 1 \(1–3\) cross at about \(2, 2\) without a shared vertex"),
        Case("segment out of range", _segment_out_of_range, r"range\.poly:9: a segment \(3 9\) refers to vertex 9, but the vertices are numbered 1\.\.4"),
        Case("self segment", _self_segment, r"segment 0 joins vertex 0 to itself \(rows counted from 0; the file numbers from 1\)"),
        Case("hole outside", _hole_outside, r"hole 0 at \(5\.0, 5\.0\) lies outside the domain"),
        Case("unclosed hole", _unclosed_hole, r"the domain is empty: hole 0 at \(2\.0, 2\.0\) eats .*is every boundary closed\?"),
        Case("node file missing", _node_file_missing, r"lists 0 vertices, so they must be in .*vertices-elsewhere\.node, which does not exist"),
        Case("collinear", _collinear, r"line\.node: the 3 distinct vertices are collinear"),
    )
}

_ALL_FILES = [
    "empty file", "empty text", "binary garbage", "text garbage", "unreadable", "directory", "dangling symlink",
    "missing", "unknown extension", "header only", "ragged",
]
_ARRAYS = ["empty array", "wrong shape", "nan", "inf", "pickled", "truncated", "strings"]
KIND_CASES: dict[str, list[str]] = {
    "points": [*_ALL_FILES, *_ARRAYS, "wrong columns", "not utf-8", "damaged ply or tiff"],
    "grid": [*_ALL_FILES, *_ARRAYS, "wrong columns", "npz keys", "damaged ply or tiff"],
    "trace": _ALL_FILES,
    "domain": [
        *_ALL_FILES, "nan", "inf", "crossing segments", "segment out of range", "self segment", "hole outside",
        "unclosed hole", "node file missing", "collinear",
    ],
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
        "mesh",
        "domain",
        lambda i, o: ["mesh", str(i), "-q", "30", "-o", str(o / "m.ele"), "--plot", str(o / "m.png"), "--check", "--quiet"],
        ("persistri.impl.mesh.api:triangulate",),
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


def test_a_saved_trace_passes_the_checks_the_malformed_ones_fail(tmp_path: Path) -> None:
    from persistri.impl.bench.complex import hull_trace

    path = save_trace(hull_trace(20, seed=1), tmp_path / "t.json")
    result, caught = invoke(["bench", "complex", "--trace", str(path), "--only", "hamt", "--repeat", "1", "--json"])
    assert result.exit_code == 0 and not caught, (result.output, caught)
