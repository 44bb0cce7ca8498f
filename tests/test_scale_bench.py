"""``persistri bench scale`` (:mod:`persistri.impl.bench.scale`): it runs, measures in the workers, checks equality."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from persistri.impl.cli.main import main


def test_bench_scale_small_as_json(tmp_path: Path) -> None:
    result = CliRunner().invoke(
        main,
        ["bench", "scale", "-n", "30000", "--chunk-size", "7500", "--workers", "2", "--terrain-size", "0", "--dir", str(tmp_path), "--json"],
    )
    assert result.exit_code == 0, result.output
    rows = json.loads(result.stdout)["hull"]
    assert [r["label"] for r in rows] == ["one process", "2 workers"]
    one, two = rows
    assert one["workers"] == 0 and one["candidates"] == 30_000 and one["speedup"] == 1.0
    assert two["workers"] == 2 and two["chunks"] == 4 and two["candidates"] < 30_000
    assert all(r["same"] for r in rows) and one["faces"] == two["faces"] > 0
    assert one["filtered"] == 0 and 0.9 * 30_000 < two["filtered"] < 30_000  # the interior filter's drops
    for r in rows:  # measured in the workers: one figure per worker, a peak at least the baseline
        assert len(r["peak"]) == len(r["baseline"]) == max(1, r["workers"])
        assert all(p >= b > 0 for p, b in zip(r["peak"], r["baseline"], strict=True))
        assert r["seconds"] > 0 and len(r["cpu"]) == len(r["peak"]) and sum(r["cpu"]) > 0
    assert (tmp_path / "inball-30000-0.npy").exists()  # the points file is kept for the next run


def test_bench_scale_rejects_bad_options(tmp_path: Path) -> None:
    runner = CliRunner()
    bad = runner.invoke(main, ["bench", "scale", "--dist", "Nowhere", "--terrain-size", "0"])
    assert bad.exit_code == 2 and "unknown distribution 'Nowhere'" in bad.stderr
    bad = runner.invoke(main, ["bench", "scale", "--workers", "0", "--terrain-size", "0"])
    assert bad.exit_code == 2


def test_the_tiled_terrain_table_shows_every_row() -> None:
    """The rows of ``bench_rows`` as the command prints them (a wrong attribute here once crashed the command
    only after minutes of measuring)."""
    from rich.console import Console

    from persistri.impl.bench.scale import terrain_table
    from persistri.impl.scale.terrain_bench import TerrainRow

    rows = [
        TerrainRow("1 worker", 1, 12.5, 1.0, (80 << 20,), (300 << 20,), 1234, 2400, 0.998),
        TerrainRow("2 workers", 2, 7.25, 1.72, (81 << 20, 82 << 20), (200 << 20, 210 << 20), 1234, 2400, 0.998),
    ]
    console = Console(width=200, record=True)
    console.print(terrain_table(rows, True, "tiled terrain"))
    text = console.export_text()
    assert "12.5" in text and "1.72×" in text and "200 / 210" in text and "1,234" in text and "0.998" in text
    assert "identical meshes: yes" in text
