"""A bad field megabytes long is quoted by its first 40 characters, never whole, by every reader.

A file whose newlines were lost (or a binary file read as text) puts a whole file
in one field; a message echoing it would print megabytes.  Each reader's message
keeps the file name and the line, and quotes at most 39 characters and "…"
(``persistri.impl.file_errors.shown``).  Through the readers and through
``persistri`` in-process.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from cli_contract import invoke

from persistri.impl.file_errors import shown
from persistri.impl.files import read_points
from persistri.impl.mesh.polyfile import read_ele, read_node, read_poly
from persistri.impl.terrain.grids import read_grid

LONG = "x" * 100_000
"""A bad field: far longer than any message should be."""

LIMIT = 200
"""No message naming a bad field is longer than this (the path of tmp_path included)."""

SQUARE_SEGMENTS = "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n"
SQUARE_VERTICES = "1 0 0\n2 1 0\n3 1 1\n4 0 1\n"

# name, text, the reader, the line the message names, what the message says about the field
CASES: list[tuple[str, str, Callable[[Path], object], str, str]] = [
    ("word.poly", f"4 2 0 0\n1 0 0\n2 1 {LONG}\n3 1 1\n4 0 1\n" + SQUARE_SEGMENTS, read_poly, ":3:", "is not a number"),
    ("header.poly", f"4 {LONG} 0 0\n", read_poly, ":1:", "must be an integer"),
    ("trailing.poly", "4 2 0 0\n" + SQUARE_VERTICES + SQUARE_SEGMENTS + LONG + "\n", read_poly, ":12:", "must be an integer"),
    ("infinite.poly", f"4 2 0 0\n1 0 0\n2 1 inf{'0' * 100_000}\n3 1 1\n4 0 1\n" + SQUARE_SEGMENTS, read_poly, ":3:", "is not a number"),
    ("fraction.poly", "4 2 0 0\n" + SQUARE_VERTICES + f"4 0\n1 1 2\n2 2 3.{'5' * 100_000}\n3 3 4\n4 4 1\n0\n", read_poly, ":8:",
     "is not an integer"),
    ("after.poly", "4 2 0 0\n" + SQUARE_VERTICES + SQUARE_SEGMENTS + "0\n" + LONG + "\n", read_poly, ":13:", "unexpected content"),
    ("word.node", f"4 2 0 0\n1 0 0\n2 1 {LONG}\n3 1 1\n4 0 1\n", read_node, ":3:", "is not a number"),
    ("word.ele", f"1 3 0\n1 1 2 {LONG}\n", read_ele, ":2:", "is not a number"),
    ("body.asc", f"ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n0 {LONG}\n1 1\n", read_grid, "line 6:", "is not a number"),
    ("header.asc", f"ncols {LONG}\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n0 0\n1 1\n", read_grid, "line 1:",
     "is not a number"),
    ("row.csv", f"0,0,0\n1,{LONG},1\n1,1,1\n", read_points, "line 2:", "not a row of numbers"),
    ("header.ply", f"ply\nformat ascii 1.0\nelement vertex {LONG}\nproperty float x\nend_header\n", read_points, "",
     "damaged PLY header"),
    ("property.ply", f"ply\nformat ascii 1.0\nelement vertex 1\nproperty float {LONG}\nend_header\n0\n", read_points, "",
     "PLY vertices with the properties"),
]


@pytest.mark.parametrize(("name", "text", "reader", "where", "says"), CASES, ids=[c[0] for c in CASES])
def test_a_reader_quotes_a_long_field_by_its_start(
    tmp_path: Path, name: str, text: str, reader: Callable[[Path], object], where: str, says: str
) -> None:
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(ValueError) as caught:
        reader(path)
    message = str(caught.value)
    assert len(message) < LIMIT + len(str(path)), message[:300]
    assert str(path) in message and where in message and says in message, message[:300]
    assert "…" in message, message


@pytest.mark.parametrize(
    ("name", "command"),
    [("word.poly", ["mesh"]), ("word.node", ["mesh", "--min-angle", "0"]), ("body.asc", ["terrain", "--max-points", "4"]),
     ("header.asc", ["terrain", "--max-points", "4"]), ("row.csv", ["hull"])],
)
def test_the_command_line_prints_one_short_line(tmp_path: Path, name: str, command: list[str]) -> None:
    text = next(c[1] for c in CASES if c[0] == name)
    path = tmp_path / name
    path.write_text(text)
    result, caught = invoke([command[0], str(path), *command[1:], "-o", str(tmp_path / "out.ply")])
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert result.exit_code == 2 and len(lines) == 1, result.stderr[:300]
    assert lines[0].startswith(f"persistri: {path}") and len(lines[0]) < LIMIT + len(str(path)), lines[0][:300]
    assert not caught


def test_a_geotiff_nodata_tag_is_quoted_by_its_start(tmp_path: Path) -> None:
    tifffile = pytest.importorskip("tifffile")
    path = tmp_path / "g.tif"
    tifffile.imwrite(path, np.zeros((3, 3), dtype=np.float32), extratags=[(42113, "s", 0, "9" * 50 + LONG, False)])
    with pytest.raises(ValueError, match="GDAL_NODATA tag is not a number") as caught:
        read_grid(path)
    assert len(str(caught.value)) < LIMIT + len(str(path)) and "…" in str(caught.value)


@pytest.mark.parametrize(("text", "expected"), [("abc", "'abc'"), ("a" * 40, repr("a" * 40)), ("a" * 41, repr("a" * 39 + "…")),
                                                (LONG, repr("x" * 39 + "…"))])
def test_shown_keeps_short_fields_whole(text: str, expected: str) -> None:
    assert shown(text) == expected
