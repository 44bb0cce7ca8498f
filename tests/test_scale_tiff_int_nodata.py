"""The tiled reader of ``persistri.impl.scale`` reads an integer GeoTIFF's no-data tag as the integer it spells.

GDAL reads an Int64/UInt64 band's ``GDAL_NODATA`` tag exactly: UInt64 max (a usual no-data) marks its cells.
Read as a double it rounded to 2^64, matched no cell, and the window was refused as holding an integer a double
cannot hold.  The no-data cells are not heights: they are not checked, they become NaN, as in the whole-file
reader (:func:`persistri.impl.terrain.grids.read_grid`).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from persistri.impl.scale.terrain_source import open_dem
from persistri.impl.terrain.grids import read_grid


@pytest.mark.parametrize(("dtype", "nodata"), [(np.uint64, 2**64 - 1), (np.int64, -(2**63) + 1)])
def test_a_window_of_an_integer_band_with_its_nodata(tmp_path: Path, dtype: type, nodata: int) -> None:
    tifffile = pytest.importorskip("tifffile")
    g = np.arange(1, 5 * 6 + 1, dtype=dtype).reshape(5, 6)
    g[2, 3] = nodata
    path = tmp_path / "dem.tif"
    tifffile.imwrite(path, g, extratags=[(42113, "s", 0, str(nodata), True)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        window = open_dem(path).source.read(1, 4, 2, 6)
        whole = read_grid(path).heights
    assert np.isnan(window[1, 1]) and int(np.isnan(window).sum()) == 1
    np.testing.assert_array_equal(window, whole[1:4, 2:6])


def test_a_height_a_double_rounds_is_still_refused_in_a_window(tmp_path: Path) -> None:
    tifffile = pytest.importorskip("tifffile")
    g = np.ones((4, 4), dtype=np.uint64)
    g[1, 2] = 2**53 + 1
    g[3, 3] = 2**64 - 1
    path = tmp_path / "dem.tif"
    tifffile.imwrite(path, g, extratags=[(42113, "s", 0, str(2**64 - 1), True)])
    with pytest.raises(ValueError, match=r"the integer height at \(row 1, col 2\) is not exactly representable"):
        open_dem(path).source.read(0, 4, 0, 4)


def test_an_exact_large_integer_is_read_in_a_window_as_whole(tmp_path: Path) -> None:
    """2^60 is a double: taken, as the whole-file reader takes it (only 2^53 + 1 and the like are refused)."""
    tifffile = pytest.importorskip("tifffile")
    g = np.ones((3, 3), dtype=np.int64)
    g[1, 1] = 2**60
    path = tmp_path / "dem.tif"
    tifffile.imwrite(path, g)
    window = open_dem(path).source.read(0, 3, 0, 3)
    assert window[1, 1] == 2.0**60
    np.testing.assert_array_equal(window, read_grid(path).heights)
