"""An ESRI ASCII grid without a ``NODATA_value`` line: -9999 is its no-data value (the format's default).

A DEM exported with the line left out marks its holes -9999 all the same; read as
heights they would be meshed as pits 9,999 units deep, a mesh through the hole.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from cli_contract import invoke

from persistri.impl.terrain.grids import read_grid

HEADER = "ncols 4\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
BODY = "1 2 3 4\n5 -9999 7 8\n9 10 11 12\n"


def test_minus_9999_is_nodata_without_a_nodata_line(tmp_path: Path) -> None:
    (tmp_path / "g.asc").write_text(HEADER + BODY)
    h = read_grid(tmp_path / "g.asc").heights
    assert np.isnan(h[1, 1]) and int(np.isnan(h).sum()) == 1
    assert h[0].tolist() == [1, 2, 3, 4] and h[2, 3] == 12


def test_a_nodata_line_replaces_the_default(tmp_path: Path) -> None:
    (tmp_path / "g.asc").write_text(HEADER + "NODATA_value -32768\n" + BODY.replace("1 2", "-32768 2"))
    h = read_grid(tmp_path / "g.asc").heights
    assert h[1, 1] == -9999.0 and np.isnan(h[0, 0]) and int(np.isnan(h).sum()) == 1


def test_the_command_refuses_the_hole_and_fills_it_when_told(tmp_path: Path) -> None:
    (tmp_path / "g.asc").write_text(HEADER + BODY)
    result, _ = invoke(["terrain", str(tmp_path / "g.asc"), "--max-points", "12", "-o", str(tmp_path / "m.npz"), "--quiet"])
    assert result.exit_code == 2 and "1 no-data cell (NaN)" in result.stderr and "(row 1, col 1)" in result.stderr, result.stderr
    assert not (tmp_path / "m.npz").exists()
    result, _ = invoke(["terrain", str(tmp_path / "g.asc"), "--max-points", "12", "--nodata", "min", "-o", str(tmp_path / "m.npz"),
                        "--quiet"])
    assert result.exit_code == 0, result.stderr
    assert np.load(tmp_path / "m.npz")["vertices"][:, 2].min() == 1.0  # the hole at the lowest valid height, not -9999


def test_a_grid_of_minus_9999_only_is_all_nodata(tmp_path: Path) -> None:
    (tmp_path / "g.asc").write_text(HEADER + " ".join(["-9999"] * 12) + "\n")
    result, _ = invoke(["terrain", str(tmp_path / "g.asc"), "--max-points", "4", "--nodata", "fill", "-o", str(tmp_path / "m.npz")])
    assert result.exit_code == 2 and "every cell is no-data" in result.stderr, result.stderr
