"""An integer in a text file that a double would round is refused, never rounded.

``9007199254740993`` (2^53 + 1) read as a double is 2^53: here that moves a point onto the plane of
the others, and ``persistri hull`` reported a tetrahedron as coplanar input.  Decimals (``0.1``) are
read as the nearest double, as every reader of decimal text does; an integer is meant exactly.
"""

from __future__ import annotations

import gzip
from pathlib import Path

import numpy as np
import pytest

from persistri.impl.file_errors import InputFileError
from persistri.impl.files import read_points

B = 2**53
TETRA = f"0,0,0\n0,1,0\n{B},0,{B}\n{B + 1},5,{B}\n0.5,0,0.5\n"


def test_an_integer_a_double_cannot_hold_is_refused_naming_line_and_number(tmp_path: Path) -> None:
    src = tmp_path / "big.csv"
    src.write_text(TETRA)
    with pytest.raises(InputFileError, match=r"big\.csv: line 4: 9007199254740993 is not exactly representable as float64"):
        read_points(src, (3,))
    gz = tmp_path / "big.xyz.gz"
    gz.write_bytes(gzip.compress(TETRA.replace(",", " ").encode()))
    with pytest.raises(InputFileError, match=r"line 4: 9007199254740993 is not exactly representable"):
        read_points(gz, (3,))


def test_big_integers_that_are_doubles_and_unselected_columns_are_read(tmp_path: Path) -> None:
    src = tmp_path / "ok.csv"
    src.write_text(f"id,x,y,z\n{B + 1},0,0,0\n2,0,1,0\n3,{B},0,0\n4,0,0,-{B}\n")  # the id column is not read
    got = read_points(src, (3,))
    assert np.array_equal(got, np.array([[0, 0, 0], [0, 1, 0], [B, 0, 0], [0, 0, -B]], dtype=np.float64))
    decimal = tmp_path / "decimal.txt"
    decimal.write_text("0 0 0\n0 1 0\n1 0 0\n9.007199254740993e15 0 1\n")  # a decimal: the nearest double
    assert read_points(decimal, (3,))[3, 0] == float(B)
