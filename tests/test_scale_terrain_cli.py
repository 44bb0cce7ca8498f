"""``persistri terrain --tile/--workers/--scheduler``: the tiled path from the command line, its outputs and its errors."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from persistri.impl.cli.main import main
from persistri.impl.scale.terrain import tiled_terrain
from persistri.impl.terrain.synthetic import synthetic_dem

pytest.importorskip("distributed")


def invoke(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, list(args))
    return result.exit_code, result.output


def one_error_line(text: str, pattern: str) -> None:
    lines = [ln for ln in text.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("persistri: "), text
    assert re.search(pattern, lines[0]), lines[0]


@pytest.fixture
def dem(tmp_path: Path) -> Path:
    path = tmp_path / "dem.npy"
    np.save(path, synthetic_dem(90, seed=5, relief=200.0).heights[:71, :83])
    return path


def test_tiles_in_this_process_write_the_python_api_s_mesh(dem: Path, tmp_path: Path) -> None:
    out = tmp_path / "tin.npz"
    code, text = invoke("terrain", str(dem), "--max-error", "3", "--tile", "30", "--workers", "1", "-o", str(out))
    assert code == 0, text
    assert "in 3 × 3 tiles of 30" in text
    data = np.load(out)
    tin = tiled_terrain(str(dem), max_error=3.0, tile=30)
    assert np.array_equal(data["vertices"], tin.vertices) and np.array_equal(data["triangles"], tin.triangles)
    assert np.array_equal(data["samples"], tin.samples) and float(data["max_error"]) == tin.max_error <= 3.0
    assert data["grid_shape"].tolist() == [71, 83]


def test_two_workers_give_the_same_file_and_name_the_cluster(dem: Path, tmp_path: Path) -> None:
    one, two = tmp_path / "one.npz", tmp_path / "two.npz"
    code, text = invoke("terrain", str(dem), "--max-error", "3", "--tile", "30", "--workers", "1", "-o", str(one))
    assert code == 0, text
    code, text = invoke("terrain", str(dem), "--max-error", "3", "--tile", "30", "--workers", "2", "-o", str(two),
                        "--tile-output", str(tmp_path / "tiles"))
    assert code == 0, text
    assert "dask: 2 workers" in text
    a, b = np.load(one), np.load(two)
    assert sorted(a.files) == sorted(b.files)
    for key in a.files:
        assert np.array_equal(a[key], b[key]), key
    assert len(list((tmp_path / "tiles").glob("tile_*.npz"))) == 9


def test_quiet_prints_one_summary_line(dem: Path) -> None:
    code, text = invoke("terrain", str(dem), "--max-error", "3", "--tile", "30", "--workers", "1", "--quiet")
    assert code == 0, text
    assert re.fullmatch(r"\d+ points, \d+ triangles, max error [0-9.e+-]+\n", text), text


@pytest.mark.parametrize(
    ("extra", "pattern"),
    [
        (["--max-points", "50"], "needs --max-error and no --max-points"),
        (["--plot", "x.png"], "--plot is not available when meshing by tiles"),
        (["--check"], "--check is not available"),
        (["--stats"], "--stats is not available"),
        (["--workers", "2", "--scheduler", "tcp://127.0.0.1:9"], "either --workers or --scheduler"),
        (["--world", "-o", "x.npz"], "--world needs georeferencing"),
        (["--backend", "nope"], "--backend nope"),
    ],
)
def test_bad_requests_are_one_line_before_any_work(dem: Path, extra: list[str], pattern: str) -> None:
    code, text = invoke("terrain", str(dem), "--max-error", "3", "--tile", "30", *extra)
    assert code == 2
    one_error_line(text, pattern)


def test_no_data_is_refused_unless_a_rule_is_given(tmp_path: Path) -> None:
    h = synthetic_dem(40, seed=1).heights
    h[5, 7] = np.nan
    path = tmp_path / "holes.npy"
    np.save(path, h)
    code, text = invoke("terrain", str(path), "--max-error", "5", "--tile", "17", "--workers", "1")
    assert code == 2
    one_error_line(text, r"holes\.npy: 1 no-data cell \(NaN\), the first at \(row 5, col 7\); .*--nodata fill, min")
    assert "nodata=" not in text  # the command's words, not the API's
    code, text = invoke("terrain", str(path), "--max-error", "5", "--tile", "17", "--workers", "1", "--nodata", "fill")
    assert code == 0, text


def test_a_zarr_store_and_a_missing_one(tmp_path: Path) -> None:
    zarr = pytest.importorskip("zarr")
    h = synthetic_dem(40, seed=2).heights
    zarr.create_array(str(tmp_path / "dem.zarr"), data=h, chunks=(16, 16))
    code, text = invoke("terrain", str(tmp_path / "dem.zarr"), "--max-error", "9", "--tile", "17", "--workers", "1",
                        "-o", str(tmp_path / "z.npz"))
    assert code == 0, text
    code, text = invoke("terrain", str(tmp_path / "none.zarr"), "--max-error", "9", "--tile", "17")
    assert code == 2
    one_error_line(text, r"none\.zarr: no such file$")


def test_an_unreachable_scheduler_is_one_line(dem: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from persistri.impl.scale import cluster

    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT", 1.0)
    code, text = invoke("terrain", str(dem), "--max-error", "3", "--scheduler", "tcp://127.0.0.1:9")
    assert code == 2
    one_error_line(text, "cannot reach the Dask scheduler at tcp://127.0.0.1:9")


def test_without_tile_options_the_one_process_path_is_unchanged(dem: Path, tmp_path: Path) -> None:
    from persistri.impl.terrain.grids import read_grid
    from persistri.impl.terrain.greedy import greedy_insertion

    out = tmp_path / "plain.npz"
    code, text = invoke("terrain", str(dem), "--max-error", "3", "--workers", "1", "-o", str(out))
    assert code == 0, text
    assert "tiles" not in text
    tin = greedy_insertion(read_grid(dem).heights, max_error=3.0)
    assert len(np.load(out)["triangles"]) == len(tin.triangles)
