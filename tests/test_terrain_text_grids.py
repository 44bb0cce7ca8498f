"""Height grids in text (``.csv``/``.txt``): read exactly, ragged and empty files and x-y-z tables refused by name."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from persistri.impl.cli.main import main
from persistri.impl.terrain.greedy import greedy_insertion
from persistri.impl.terrain.grids import as_heights, read_grid


def test_a_csv_grid_reads_as_its_rows(tmp_path: Path) -> None:
    z = np.arange(20.0).reshape(4, 5) * 0.25 - 1.0
    p = tmp_path / "dem.csv"
    np.savetxt(p, z, delimiter=",", header="heights in metres", fmt="%.17g")
    grid = read_grid(p)
    assert grid.transform is None
    assert np.array_equal(grid.heights, z)


def test_a_txt_grid_with_comments_semicolons_and_nodata(tmp_path: Path) -> None:
    p = tmp_path / "dem.txt"
    p.write_text("# a survey\n1;2;3;4\n\n5;nan;7;8  # a gap\r\n9;10;11;12\n")
    heights = read_grid(p).heights
    assert heights.shape == (3, 4) and np.isnan(heights[1, 1])
    assert np.array_equal(np.nan_to_num(heights, nan=-1), [[1, 2, 3, 4], [5, -1, 7, 8], [9, 10, 11, 12]])
    filled = as_heights(heights, nodata="min")
    assert filled[1, 1] == 1.0


def test_a_text_grid_meshes_like_the_same_array(tmp_path: Path) -> None:
    z = np.cumsum(np.random.default_rng(7).normal(size=(24, 31)), axis=0)
    p = tmp_path / "dem.csv"
    np.savetxt(p, z, delimiter=",", fmt="%.17g")
    from_file = greedy_insertion(read_grid(p).heights, max_error=0.5)
    from_array = greedy_insertion(z, max_error=0.5)
    assert np.array_equal(from_file.triangles, from_array.triangles)
    assert from_file.max_error == from_array.max_error


@pytest.mark.parametrize(
    ("text", "pattern"),
    [
        ("1 2 3 4\n5 6 7\n", r"ragged\.txt: line 2: expected 4 numbers, got 3"),
        ("", r"ragged\.txt: no heights: the file is empty"),
        ("# only a comment\n", r"ragged\.txt: no heights: only comments"),
        ("1 2 x 4\n", r'ragged\.txt: line 1: "x" is not a number'),
        ("\n".join("1 2 3" for _ in range(10)) + "\n", r"10 rows of 3 numbers look like x y z points"),
    ],
    ids=["ragged", "empty", "comments", "field", "xyz"],
)
def test_bad_text_grids_fail_with_one_line_naming_the_file(tmp_path: Path, text: str, pattern: str) -> None:
    p = tmp_path / "ragged.txt"
    p.write_text(text)
    with pytest.raises(ValueError, match=pattern):
        read_grid(p)
    result = CliRunner().invoke(main, ["terrain", str(p), "--max-error", "1", "-o", str(tmp_path / "t.ply")])
    assert result.exit_code == 2
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and "ragged.txt" in lines[0]
    assert not (tmp_path / "t.ply").exists()


def test_a_text_grid_of_infinite_height_is_refused(tmp_path: Path) -> None:
    p = tmp_path / "inf.csv"
    p.write_text("1,2,3,4\n5,inf,7,8\n")
    with pytest.raises(ValueError, match=r"inf\.csv: .*(infinite|not finite)"):
        read_grid(p)
