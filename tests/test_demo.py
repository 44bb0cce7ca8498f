"""``persistri demo --out DIR`` at tiny sizes: the files it writes, and how stages compose."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner
from rich.console import Console

from persistri.impl.bench import maps as bench_maps
from persistri.impl.bench.maps import RECORD_FIELDS, SUBJECTS
from persistri.impl.cli import demo as demo_module
from persistri.impl.cli.demo import DemoSettings, DemoStage, StageContext, StageResult, run_demo
from persistri.impl.cli.main import main
from persistri.impl.hull.verify import verify_hull

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def test_demo_writes_the_hull_and_the_map_benchmark(tmp_path: Path) -> None:
    out = tmp_path / "results"  # created if missing
    result = CliRunner().invoke(
        main,
        ["demo", "--out", str(out), "--bench-sizes", "60,90", "--repeat", "1", "--hull-points", "300",
         "--terrain-points", "40"],
        catch_exceptions=False,
    )
    assert result.exit_code == 0, result.output
    files = {p.name for p in out.iterdir()}
    assert files == {
        "bench_maps.json", "bench_maps.txt", "bench_maps.png", "hull.npz", "hull.ply", "hull.png",
        "terrain_jacksboro.npz", "terrain_jacksboro.ply", "terrain_jacksboro.png", "mesh_comb.npz", "mesh_comb.png",
    }
    with np.load(out / "mesh_comb.npz") as quality:
        from persistri.impl.mesh.gallery import gallery_domain
        from persistri.impl.mesh.verify import verify_mesh

        assert bool(quality["min_angle_reached"]) and int(quality["undos"]) > 0
        assert verify_mesh(gallery_domain("comb").pslg, quality["vertices"], quality["triangles"], min_angle=30).ok
    assert (out / "mesh_comb.png").read_bytes().startswith(PNG_MAGIC)
    mesh = np.load(out / "terrain_jacksboro.npz")
    assert mesh["vertices"].shape == (40, 3) and float(mesh["max_error"]) > 0
    assert (out / "terrain_jacksboro.png").read_bytes().startswith(PNG_MAGIC)
    hull = np.load(out / "hull.npz")
    assert verify_hull(hull["points"], hull["simplices"]).ok
    assert hull["points"].shape == (300, 3)
    assert (out / "hull.png").read_bytes().startswith(PNG_MAGIC)

    doc = json.loads((out / "bench_maps.json").read_text(encoding="utf-8"))
    assert doc["sizes"] == [60, 90] and doc["repeat"] == 1
    assert len(doc["records"]) == 2 * len(SUBJECTS)
    assert all(tuple(r) == RECORD_FIELDS for r in doc["records"])
    assert {r["map"] for r in doc["records"] if r["status"] == "ok"} >= {"dict", "assoc_list"}

    text = (out / "bench_maps.txt").read_text(encoding="utf-8")
    assert "Persistent maps: µs per operation" in text
    assert "measured: dict" in text
    assert "\x1b[" not in text  # plain text, no terminal colour codes

    png = (out / "bench_maps.png").read_bytes()
    assert png.startswith(PNG_MAGIC)
    from matplotlib.image import imread

    height, width = imread(out / "bench_maps.png").shape[:2]
    assert width > height > 100

    for name in files:
        assert str(out / name) in result.stdout
    # The dev extra installs the adapters extra, so every peer is measured and none is "unavailable".
    assert "unavailable" not in result.stdout and "unavailable" not in text
    assert {r["map"] for r in doc["records"] if r["status"] == "ok"} == {s.name for s in SUBJECTS}
    assert not re.search(r"┃\s*┃\s*┃", result.stdout)  # the summary tables have no row of empty headers


def _stage(name: str, log: list[str], failures: list[str] | None = None) -> DemoStage:
    def run(ctx: StageContext) -> StageResult:
        log.append(name)
        ctx.progress(0, 1, "working")
        path = ctx.settings.out / f"{name}.txt"
        path.write_text(name, encoding="utf-8")
        ctx.progress(1, 1, "done")
        return StageResult([path], f"summary of {name}", failures or [])

    return DemoStage(name, f"stage {name}", run)


def test_stages_run_in_order_and_report_their_files(tmp_path: Path) -> None:
    log: list[str] = []
    with open(tmp_path / "console.txt", "w", encoding="utf-8") as fh:
        results = run_demo(DemoSettings(out=tmp_path / "o"), Console(file=fh, width=100), [_stage("a", log), _stage("b", log)])
    assert log == ["a", "b"]
    assert [r.files for r in results] == [[tmp_path / "o" / "a.txt"], [tmp_path / "o" / "b.txt"]]
    printed = (tmp_path / "console.txt").read_text(encoding="utf-8")
    assert printed.index("summary of a") < printed.index("summary of b")


def test_a_failing_stage_fails_the_demo(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    log: list[str] = []
    monkeypatch.setattr(demo_module, "STAGES", (_stage("bad", log, ["bad: it broke"]), _stage("after", log)))
    result = CliRunner().invoke(main, ["demo", "--out", str(tmp_path)], catch_exceptions=False)
    assert result.exit_code == 1
    assert log == ["bad", "after"]  # later stages still run and write their files
    assert "persistri demo: bad: it broke" in result.stderr
    assert (tmp_path / "after.txt").read_text(encoding="utf-8") == "after"


def test_bad_sizes_are_a_usage_error(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, ["demo", "--out", str(tmp_path), "--bench-sizes", "ten"])
    assert result.exit_code == 2
    assert "'ten' is not a key count" in result.output


def test_maps_not_installed_are_left_out_with_one_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def not_installed() -> Any:
        raise ModuleNotFoundError("No module named 'nosuchmap'")

    absent = bench_maps.MapSubject("nosuchmap", "peer", "a map that is not installed", not_installed)
    monkeypatch.setattr(bench_maps, "SUBJECTS", (*SUBJECTS[:2], absent))
    monkeypatch.setattr(demo_module, "STAGES", tuple(s for s in demo_module.STAGES if s.name == "maps"))
    result = CliRunner().invoke(main, ["demo", "--out", str(tmp_path), "--bench-sizes", "40"], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    note = "not compared, not installed: nosuchmap (pip install 'persistri[adapters]' to compare them)"
    text = (tmp_path / "bench_maps.txt").read_text(encoding="utf-8")
    for shown in (result.stdout, text):
        assert note in shown and "unavailable" not in shown
        assert [line for line in shown.splitlines() if "nosuchmap" in line] == [note]
    doc = json.loads((tmp_path / "bench_maps.json").read_text(encoding="utf-8"))
    assert [r["status"] for r in doc["records"] if r["map"] == "nosuchmap"] == ["unavailable"]  # the data keep it
