"""Choosing the columns of a point file: by the header's x, y, z, by number, by name (``fields``, ``--columns``).

A file with more columns than the coordinates (an id, a name, a date, an intensity)
must give its coordinates, not the first two or three columns; every bad choice is
one line naming the file.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from cli_contract import assert_one_line_failure, invoke

from persistri.impl.files import InputFileError, read_points

XYZ = np.array([[0.5, 0.0, 1.0], [1.0, 0.25, 2.0], [0.0, 1.0, 3.0], [1.0, 1.0, 4.0], [0.25, 0.75, 5.0]])


def table(header: str, rows: list[list[str]], sep: str = ",") -> str:
    return header + "\n" + "\n".join(sep.join(r) for r in rows) + "\n"


def with_extra(first: list[str], last: list[str] | None = None) -> list[list[str]]:
    """The rows of XYZ with a column before them (``first``) and optionally after (``last``)."""
    return [[f, *map(repr, p.tolist()), *([last[i]] if last else [])] for i, (f, p) in enumerate(zip(first, XYZ))]


@pytest.mark.parametrize(
    ("header", "rows", "sep", "want"),
    [
        ("id,x,y,z", with_extra(["7", "8", "9", "10", "11"]), ",", XYZ),  # a numeric id first: skipped by name
        ("name;X;Y;Z", with_extra(list("abcde")), ";", XYZ),  # a text column first: not a header on every line
        ("x y z intensity", [[*map(repr, p), "9"] for p in XYZ.tolist()], " ", XYZ),
        ('"ID","x","y"', [[str(i), repr(p[0]), repr(p[1])] for i, p in enumerate(XYZ.tolist())], ",", XYZ[:, :2]),
        ("z,y,x", [[repr(p[2]), repr(p[1]), repr(p[0])] for p in XYZ.tolist()], ",", XYZ),  # named out of order
    ],
)
def test_a_header_naming_x_y_z_picks_them(tmp_path: Path, header: str, rows: list[list[str]], sep: str, want: np.ndarray) -> None:
    src = tmp_path / "p.csv"
    src.write_text(table(header, rows, sep))
    assert np.array_equal(read_points(src), want)


def test_plain_files_and_full_headers_read_every_column(tmp_path: Path) -> None:
    src = tmp_path / "p.csv"
    src.write_text(table("x,y,z", [list(map(repr, p)) for p in XYZ.tolist()]))
    assert np.array_equal(read_points(src), XYZ)
    src.write_text(table("a,b,c,d", with_extra(["1", "2", "3", "4", "5"])))  # no x, y named: every column
    assert read_points(src).shape == (5, 4)
    src.write_text(table("x,y,z", with_extra(["1", "2", "3", "4", "5"])))  # the header does not describe 4 columns
    with pytest.raises(InputFileError, match="expected 3 numbers, got 4"):
        read_points(src, (3,))


def test_fields_by_number_and_by_name(tmp_path: Path) -> None:
    src = tmp_path / "p.csv"
    dates = ["2024-01-0" + str(i) for i in range(1, 6)]
    src.write_text(table("Date,East,North,Height,Note", with_extra(dates, list("vwxyz"))))
    assert np.array_equal(read_points(src, (3,), fields=["east", "NORTH", "Height"]), XYZ)
    assert np.array_equal(read_points(src, (2, 3), fields=[2, 1]), XYZ[:, [1, 0]])
    np.save(tmp_path / "p.npy", np.column_stack([np.arange(5.0), XYZ]))
    assert np.array_equal(read_points(tmp_path / "p.npy", (3,), fields=[1, 2, 3]), XYZ)


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        (["east", "up"], "no column 'up' in the header (date, east, north, height, note)"),
        (["up", "down"], "no columns 'up', 'down' in the header (date, east, north, height, note)"),
        ([0, 1], "column 0 holds no number on any line"),
        ([1, 9], "line 2: no column 9: the line has 5 fields"),
        ([1, 1], "a column is selected twice"),
        ([-1, 2], "column numbers count from 0"),
        ([4, 1], "column 4 holds no number on any line"),
        ([1, 4], 'line 2: "v" is not a number'),
    ],
)
def test_bad_fields_are_one_line_naming_the_file(tmp_path: Path, fields: list[str | int], message: str) -> None:
    src = tmp_path / "p.csv"
    src.write_text(table("Date,East,North,Height,Note", with_extra(["d1", "d2", "d3", "d4", "d5"], list("vwxyz"))))
    with pytest.raises(InputFileError) as info:
        read_points(src, (2, 3), fields=fields)
    assert str(info.value).startswith(str(src)) and message in str(info.value) and "\n" not in str(info.value)


def test_npy_columns_by_number_only(tmp_path: Path) -> None:
    np.save(tmp_path / "p.npy", XYZ)
    for fields, message in ((["x"], "no header to name columns by"), ([0, 3], "no column 3: the array has 3")):
        with pytest.raises(InputFileError, match=message):
            read_points(tmp_path / "p.npy", (2, 3), fields=fields)


def test_the_commands_take_columns(tmp_path: Path) -> None:
    src = tmp_path / "p.csv"
    src.write_text(table("when,e,n,h", with_extra(["mon", "tue", "wed", "thu", "fri"])))
    result, caught = invoke(["delaunay", str(src), "--columns", "e,n", "-o", str(tmp_path / "d.npz"), "--quiet"])
    assert result.exit_code == 0 and not caught, result.output
    with np.load(tmp_path / "d.npz") as d:
        assert np.array_equal(d["points"], XYZ[:, :2])
    result, caught = invoke(["hull", str(src), "--columns", "1,2,3", "-o", str(tmp_path / "h.npz"), "--quiet"])
    assert result.exit_code == 0 and not caught, result.output
    with np.load(tmp_path / "h.npz") as h:
        assert np.array_equal(h["points"], XYZ)
    np.save(tmp_path / "p.npy", np.column_stack([XYZ, np.arange(5.0)]))
    result, caught = invoke(["hull", str(tmp_path / "p.npy"), "--columns", "0,1,2", "-o", str(tmp_path / "n.npz"), "--quiet"])
    assert result.exit_code == 0 and not caught, result.output
    with np.load(tmp_path / "n.npz") as h:
        assert np.array_equal(h["points"], XYZ)


def test_the_commands_refuse_bad_columns_in_one_line(tmp_path: Path) -> None:
    src = tmp_path / "p.csv"
    src.write_text(table("when,e,n,h", with_extra(["mon", "tue", "wed", "thu", "fri"])))
    result, caught = invoke(["delaunay", str(src), "--columns", "e,up"])
    assert_one_line_failure(result, caught, "p.csv", r"no column 'up' in the header \(when, e, n, h\)")
    result, _ = invoke(["delaunay", str(src), "--columns", "e,,n"])
    assert result.exit_code == 2 and "--columns" in result.stderr
    result, _ = invoke(["hull", "--dist", "InBall", "--columns", "1,2,3"])
    assert result.exit_code == 2 and "--columns" in result.stderr
