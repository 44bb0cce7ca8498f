"""Integer files beyond 2^53: an int64/uint64 array is exact in numpy, its float64 is not.

Grids (.npy, .npz, GeoTIFF) and point files (.npy, PLY) holding such an integer are refused naming the
cell or row, without a numpy warning escaping; a GeoTIFF's integer no-data tag is read exactly.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from persistri.impl.files import InputFileError, read_points
from persistri.impl.terrain.grids import read_grid

B = 2**53


def _grid(dtype: type, value: int, at: tuple[int, int] = (1, 2)) -> np.ndarray:
    g = np.arange(12, dtype=dtype).reshape(3, 4)
    g[at] = value
    return g


@pytest.mark.parametrize(
    ("dtype", "value"), [(np.int64, B + 1), (np.int64, 2**63 - 1), (np.uint64, 2**64 - 1), (np.int64, -(2**63) + 1)]
)
@pytest.mark.parametrize("suffix", [".npy", ".npz", ".tif"])
def test_a_grid_integer_a_double_rounds_is_refused_naming_the_cell(tmp_path: Path, dtype: type, value: int, suffix: str) -> None:
    path = tmp_path / f"g{suffix}"
    g = _grid(dtype, value)
    if suffix == ".npy":
        np.save(path, g)
    elif suffix == ".npz":
        np.savez(path, heights=g)
    else:
        tifffile = pytest.importorskip("tifffile")
        tifffile.imwrite(path, g)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # 2^63 - 1 became 2^63, whose cast back to int64 warned "invalid value"
        with pytest.raises(ValueError, match=rf"{path.name}: an integer height is not exactly representable as "
                           rf"float64: cell \(row 1, col 2\) is {value} \(beyond 2\^53"):
            read_grid(path)


def test_a_grid_of_exact_large_integers_is_read(tmp_path: Path) -> None:
    path = tmp_path / "g.npy"
    np.save(path, _grid(np.int64, 2**60))  # a double holds 2^60 exactly
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        heights = read_grid(path).heights
    assert heights[1, 2] == 2**60 and heights[0, 1] == 1.0


@pytest.mark.parametrize(("dtype", "nodata"), [(np.uint64, 2**64 - 1), (np.int64, B + 1), (np.int64, -(2**63) + 1)])
def test_a_geotiff_integer_nodata_tag_is_read_exactly(tmp_path: Path, dtype: type, nodata: int) -> None:
    """GDAL reads an Int64/UInt64 band's GDAL_NODATA tag as an integer: UInt64 max, a usual no-data, marks its
    cells (as a double it rounded to 2^64, matched nothing, and the grid was refused as inexact); and a tag of
    2^53 + 1 marks the cells holding it, not a cell holding the valid height 2^53 (its rounding)."""
    tifffile = pytest.importorskip("tifffile")
    path = tmp_path / "dem.tif"
    g = _grid(dtype, nodata, at=(2, 3))
    g[0, 0] = B  # a valid height, the double the tag 2^53 + 1 rounds to
    tifffile.imwrite(path, g, extratags=[(42113, "s", 0, str(nodata), True)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        heights = read_grid(path).heights
    assert np.isnan(heights[2, 3]) and int(np.isnan(heights).sum()) == 1
    assert heights[0, 0] == B and heights[1, 1] == 5.0


@pytest.mark.parametrize(("dtype", "value"), [(np.int64, B + 1), (np.int64, 2**63 - 1), (np.uint64, 2**64 - 1)])
def test_a_npy_point_file_integer_a_double_rounds_is_refused_naming_the_row(tmp_path: Path, dtype: type, value: int) -> None:
    path = tmp_path / "p.npy"
    np.save(path, np.array([[0, 0, 0], [1, 0, 0], [value, 5, 0], [0, 1, 3]], dtype=dtype))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(InputFileError, match=rf"p.npy: row 2 is not exactly representable as float64: \[{value}, 5, 0\]"):
            read_points(path, (3,))


def _ascii_ply(path: Path, kind: str, rows: list[str], before: str = "") -> None:
    head = ["ply", "format ascii 1.0", *([before] if before else []), "element vertex 4"]
    head += [f"property {kind} {c}" for c in "xyz"] + ["end_header"]
    path.write_text("\n".join(head + rows) + "\n")


@pytest.mark.parametrize(
    ("kind", "token", "read_as", "line", "before"),
    [
        ("double", str(B + 1), B, 10, ""),
        ("double", str(-(B + 3)), -(B + 4), 10, ""),
        ("float", "16777217", 16777216, 12, "element face 0\nproperty list uchar int vertex_indices"),
    ],
)
def test_an_ascii_ply_integer_its_type_rounds_is_refused_naming_the_line(
    tmp_path: Path, kind: str, token: str, read_as: int, line: int, before: str
) -> None:
    """meshio reads an ASCII PLY's numbers in the declared type: 2^53 + 1 as a double was 2^53, and four points
    off a plane could land on it."""
    path = tmp_path / "p.ply"
    _ascii_ply(path, kind, ["0 0 0", f"1 0 {B}", f"0 {token} 0", "1 1 3"], before)
    with pytest.raises(InputFileError, match=rf"p.ply: line {line}: {token} is not exactly representable as "
                       rf"float(64|32, its PLY property's type): reading it would round it to {read_as}"):
        read_points(path, (3,))


def test_an_ascii_ply_of_exact_large_numbers_is_read(tmp_path: Path) -> None:
    path = tmp_path / "p.ply"
    _ascii_ply(path, "double", ["0 0 0", f"1 0 {B}", "0 1 1e300", f"{2**60} 1 3"])
    assert read_points(path, (3,)).tolist() == [[0, 0, 0], [1, 0, B], [0, 1, 1e300], [2**60, 1, 3]]
