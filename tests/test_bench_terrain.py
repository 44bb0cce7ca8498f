"""persistri bench terrain --max-error/--relief/--peak-memory, the synthetic DEM, and persistri bench delaunay."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from persistri.impl.bench.delaunay import run_delaunay_bench, terrain_build
from persistri.impl.bench.terrain_target import PeakMemory, relief, run_to_error
from persistri.impl.cli.main import main
from persistri.impl.terrain.greedy import greedy_insertion
from persistri.impl.terrain.grids import jacksboro
from persistri.impl.terrain.synthetic import parse_synthetic, synthetic_dem


def test_synthetic_dem_is_deterministic_and_spans_the_relief() -> None:
    a, b, c = synthetic_dem(33, seed=4), synthetic_dem(33, seed=4), synthetic_dem(33, seed=5)
    assert a.heights.shape == (33, 33) and a.heights.dtype == np.float64
    assert np.array_equal(a.heights, b.heights) and not np.array_equal(a.heights, c.heights)
    assert float(a.heights.min()) == 0.0 and float(a.heights.max()) == 1000.0
    assert synthetic_dem(16, relief=5.0).heights.max() == 5.0
    rougher = synthetic_dem(64, hurst=0.2)
    smoother = synthetic_dem(64, hurst=0.9)
    # A rougher surface (smaller H) needs more points for the same relative error.
    assert greedy_insertion(rougher.heights, max_error=20.0).n_points > greedy_insertion(smoother.heights, max_error=20.0).n_points


@pytest.mark.parametrize(
    ("word", "expected"),
    [("synthetic", (2048, 0)), ("Synthetic:512", (512, 0)), ("synthetic:64:9", (64, 9)), ("jacksboro", None), ("a.npy", None)],
)
def test_parse_synthetic(word: str, expected: tuple[int, int] | None) -> None:
    assert parse_synthetic(word) == expected


@pytest.mark.parametrize("word", ["synthetic:x", "synthetic:1", "synthetic:8:1:2"])
def test_parse_synthetic_refuses_malformed_words(word: str) -> None:
    with pytest.raises(ValueError, match="synthetic"):
        parse_synthetic(word)


def test_bad_synthetic_dems_are_refused() -> None:
    for kwargs, message in (({"size": 1}, "at least 2"), ({"size": 8, "hurst": 1.0}, "Hurst"), ({"size": 8, "relief": 0.0}, "relief")):
        with pytest.raises(ValueError, match=message):
            synthetic_dem(**kwargs)  # type: ignore[arg-type]


def test_run_to_error_compares_equal_quality() -> None:
    h = jacksboro().heights[:70, :90]
    rec = run_to_error(h, 20.0, grid_name="crop")
    assert rec.shape == (70, 90) and rec.max_error == 20.0
    assert rec.persistri_error <= 20.0 and rec.pydelatin_error <= 20.0 + 1e-9 * relief(h)
    assert rec.persistri_points == greedy_insertion(h, max_error=20.0).n_points
    assert 4 <= rec.pydelatin_points < h.size and rec.pydelatin_s > 0 and rec.persistri_s > 0
    assert rec.time_ratio == rec.persistri_s / rec.pydelatin_s
    assert rec.peak is None and rec.as_dict()["peak"] is None


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="peak memory is read from /proc")
def test_peak_memory_is_measured_in_fresh_processes() -> None:
    h = synthetic_dem(96, seed=2).heights
    rec = run_to_error(h, 0.05 * relief(h), grid_name="synthetic:96:2", peak=True)
    m = rec.peak
    assert isinstance(m, PeakMemory)
    assert m.pydelatin is not None and m.persistri_history is not None and m.persistri_final_only is not None
    assert m.persistri_history >= m.persistri_final_only > 0
    if m.pydelatin:  # a small grid may fit in pages pydelatin's process had already touched
        assert m.ratio == m.persistri_final_only / m.pydelatin
        assert m.ratio_history == m.persistri_history / m.pydelatin
    else:
        assert np.isnan(m.ratio)


def test_bench_terrain_to_a_relative_error_on_a_synthetic_grid() -> None:
    result = CliRunner().invoke(main, ["bench", "terrain", "--grid", "synthetic:80:3", "--relief", "0.05", "--json"])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert "records" not in doc  # no vertex-count table unless --sizes is given
    (rec,) = doc["to_error"]
    h = synthetic_dem(80, seed=3).heights
    assert rec["grid"] == "synthetic:80:3" and rec["shape"] == [80, 80]
    assert rec["max_error"] == pytest.approx(0.05 * relief(h))
    assert rec["persistri_error"] <= rec["max_error"]
    assert rec["time_ratio"] == pytest.approx(rec["persistri_s"] / rec["pydelatin_s"])


def test_bench_terrain_table_with_a_target_and_sizes(tmp_path: Path) -> None:
    np.save(tmp_path / "g.npy", jacksboro().heights[:50, :60])
    result = CliRunner().invoke(main, ["bench", "terrain", "--grid", str(tmp_path / "g.npy"), "--max-error", "30", "--sizes", "20"])
    assert result.exit_code == 0, result.output
    text = " ".join(result.stdout.split())
    assert "Greedy insertion to a maximum error, against pydelatin (persistri " in text
    assert "Greedy insertion on " in text  # and the vertex-count table


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--max-error", "5", "--relief", "0.01"], "give --max-error or --relief, not both"),
        (["--peak-memory"], "--peak-memory measures a run to --max-error or --relief"),
        (["--grid", "synthetic:zz", "--relief", "0.1"], "synthetic"),
    ],
)
def test_bench_terrain_refuses_bad_options_in_one_line(args: list[str], message: str) -> None:
    result = CliRunner().invoke(main, ["bench", "terrain", *args])
    assert result.exit_code != 0
    assert message in result.stderr and len(result.stderr.strip().splitlines()) == 1


def test_bench_delaunay_against_scipy() -> None:
    bench = run_delaunay_bench([300, 40], seed=1)
    assert [r.n for r in bench.records] == [40, 300]
    for r in bench.records:
        assert r.persistri_triangles == r.scipy_triangles  # general position: one triangulation
        assert r.scipy_s > 0 and r.persistri_s > 0 and r.time_ratio == r.persistri_s / r.scipy_s
    assert bench.build == terrain_build()
    result = CliRunner().invoke(main, ["bench", "delaunay", "--sizes", "200", "--json"])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert doc["build"] in ("interpreted",) or doc["build"].startswith("compiled twin (")
    assert doc["records"][0]["n"] == 200
    table = CliRunner().invoke(main, ["bench", "delaunay", "--sizes", "100"])
    assert "Scattered Delaunay, uniform points in the unit square" in " ".join(table.stdout.split())
    bad = CliRunner().invoke(main, ["bench", "delaunay", "--sizes", "2"])
    assert bad.exit_code != 0 and "at least 3 points" in bad.stderr
