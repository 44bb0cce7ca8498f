"""Text points whose rows start with a name (``p1,5.1,40.2,12``), or with a thousands separator: the line says why.

Before, both read as "no points: 21 lines of text and no row of numbers", as if the file
held no numbers at all.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from persistri.impl.files import InputFileError, read_points


def test_rows_that_start_with_a_name_point_to_the_header(tmp_path: Path) -> None:
    path = tmp_path / "stations.csv"
    path.write_text("name,lon,lat,elev\np0,5.1,40.2,12\np1,5.2,40.3,13\np2,5.0,40.1,11\n")
    with pytest.raises(InputFileError) as caught:
        read_points(path, (2, 3))
    assert str(caught.value) == (
        f'{path}: line 2: "p0" is not a number, nor is the first field of any line; choose the columns by the '
        "header's names (name, lon, lat, elev): --columns, or fields= in Python"
    )
    assert read_points(path, (2, 3), fields=["lon", "lat"]).tolist() == [[5.1, 40.2], [5.2, 40.3], [5.0, 40.1]]


def test_a_thousands_separator_is_named(tmp_path: Path) -> None:
    path = tmp_path / "t.csv"
    path.write_text("x;y;z\n500,012.5;4000000;3\n500,013.5;4000001;4\n500,014.5;4000003;5\n")
    with pytest.raises(InputFileError, match=r'line 2: "500,012.5" is not a number \(a thousands separator\? persistri reads 500012.5\)$'):
        read_points(path, (3,))


def test_text_alone_still_says_no_points(tmp_path: Path) -> None:
    path = tmp_path / "w.txt"
    path.write_text("a b\nc d\n")
    with pytest.raises(InputFileError, match="no points: 2 lines of text and no row of numbers"):
        read_points(path)
