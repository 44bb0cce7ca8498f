"""Integers a double would round, in grid and ``.poly`` files: refused naming the number, never rounded.

``9007199254740993`` (2^53 + 1) read as a double is 2^53: an ESRI grid or a text grid then meshed
other heights than the file's, and a ``.poly`` vertex moved off its place (the mesher then failed
deep inside, at the limit of double precision).  Integers that doubles hold are read as they are.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from persistri.impl.mesh.polyfile import read_poly
from persistri.impl.terrain.grids import read_grid

B = 2**53
ROUNDED = r"9007199254740993 is not exactly representable as float64 \(an integer beyond 2\^53 that is not a double"


def test_an_esri_grid_height_a_double_cannot_hold(tmp_path: Path) -> None:
    src = tmp_path / "big.asc"
    src.write_text(f"ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\n0 0 0\n0 {B + 1} 0\n0 0 0\n")
    with pytest.raises(ValueError, match=r"big\.asc: the height " + ROUNDED):
        read_grid(src)
    src.write_text(f"ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n0 {B}\n{-B} 0\n")
    assert read_grid(src).heights.tolist() == [[0.0, float(B)], [float(-B), 0.0]]


def test_a_text_grid_height_a_double_cannot_hold(tmp_path: Path) -> None:
    src = tmp_path / "grid.csv"
    src.write_text(f"0,0,0\n0,{B + 1},0\n0,0,0\n")
    with pytest.raises(ValueError, match=r"grid\.csv: the height " + ROUNDED):
        read_grid(src)
    src.write_text(f"0,0\n0,{B}\n")
    assert np.array_equal(read_grid(src).heights, np.array([[0.0, 0.0], [0.0, float(B)]]))


def test_a_poly_vertex_a_double_cannot_hold(tmp_path: Path) -> None:
    src = tmp_path / "big.poly"
    body = "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n"
    src.write_text(f"4 2 0 0\n1 0 0\n2 {B + 1} 0\n3 {B + 1} 1.5\n4 0 1\n" + body)
    with pytest.raises(ValueError, match=r"big\.poly:3: vertex 2: " + ROUNDED):
        read_poly(src)
    src.write_text(f"4 2 0 0\n1 0 0\n2 {B} 0\n3 {B} 1.5\n4 0 1\n" + body)
    assert read_poly(src).vertices[1].tolist() == [float(B), 0.0]
