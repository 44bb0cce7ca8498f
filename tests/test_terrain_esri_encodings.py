"""ESRI ASCII grids as editors save them: CRLF, a UTF-8 byte order mark, UTF-16: the same heights as the plain file.

A byte order mark used to make the first keyword unreadable ("not an ESRI ASCII grid (no ncols in the header)").
"""

from __future__ import annotations

import codecs
from pathlib import Path

import numpy as np
import pytest

from persistri.impl.terrain.grids import read_grid

GRID = "ncols 3\nnrows 3\nxllcorner 10\nyllcorner 20\ncellsize 2\nNODATA_value -1\n1 2 3\n4 -1 6\n7 8 9\n"


@pytest.mark.parametrize(
    "data",
    [GRID.replace("\n", "\r\n").encode(), codecs.BOM_UTF8 + GRID.encode(), GRID.encode("utf-16"), codecs.BOM_UTF16_BE + GRID.encode("utf-16-be")],
    ids=["crlf", "utf-8 bom", "utf-16 le", "utf-16 be"],
)
def test_an_encoded_grid_reads_as_the_plain_one(tmp_path: Path, data: bytes) -> None:
    (tmp_path / "plain.asc").write_text(GRID)
    (tmp_path / "other.asc").write_bytes(data)
    plain, other = read_grid(tmp_path / "plain.asc"), read_grid(tmp_path / "other.asc")
    assert np.array_equal(plain.heights, other.heights, equal_nan=True) and plain.transform == other.transform
    assert int(np.isnan(other.heights).sum()) == 1
