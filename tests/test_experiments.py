"""``persistri experiments``: the --quick run end to end (files, records, shared runs), redrawing, and the parts.

The quick run is made once per test process (module fixture): ~15 s of CPU.
Nothing here is timed; the checks are on counts, shapes and files.
"""

from __future__ import annotations

import csv
import math
import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path
from typing import Any

import click
import numpy as np
import pytest
from click.testing import CliRunner

from persistri.impl.cli.experiments import parse_size_options
from persistri.impl.cli.main import main
from persistri.impl.experiments import dems as dems_module
from persistri.impl.experiments.counts import HullCount, HullCountCache, hull_counts
from persistri.impl.experiments.dems import DemUnavailableError, dem_missing, lidar_dem, load_dem
from persistri.impl.experiments.fig8 import Fig8Record
from persistri.impl.experiments.fig11 import Fig11Record, choose_dems, count_dem
from persistri.impl.experiments.output import Comparison, markdown_table, parse_size, parse_sizes, read_records, write_csv
from persistri.impl.experiments.suite import QUICK, sizes_for

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def quick(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("experiments")
    result = CliRunner().invoke(main, ["experiments", "all", "--quick", "--out", str(out)])
    assert result.exit_code == 0, result.output
    return out


def _rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as fh:
        return list(csv.DictReader(fh))


def test_quick_writes_every_file(quick: Path) -> None:
    for name in ("fig6", "fig7", "fig8", "fig11"):
        png = (quick / f"{name}.png").read_bytes()
        assert png.startswith(PNG_MAGIC) and len(png) > 10_000, name
        page = (quick / f"{name}.md").read_text()
        assert "## The paper's report next to ours" in page and "![" in page and f"({name}.png)" in page
        assert _rows(quick / f"{name}.csv"), name
    summary = (quick / "summary.md").read_text()
    for name in ("fig6", "fig7", "fig8", "fig11"):
        assert f"[{name}]({name}.md)" in summary


def test_fig6_records(quick: Path) -> None:
    recs = read_records(quick / "fig6.csv", HullCount)
    assert sorted((r.dist, r.n) for r in recs) == sorted((d, n) for d in ("OnSphere", "BordHeavy") for n in QUICK["fig6"])
    for r in recs:
        assert r.key_comparisons > 0 and r.flops > 0 and r.plane_side_tests > 0 and r.dict_ops > 0
        if r.dist == "OnSphere":
            assert r.hull_vertices == r.n  # every point of the sphere is extreme
        else:
            assert r.hull_vertices < r.n
    # Both counts grow with n on each distribution.
    for d in ("OnSphere", "BordHeavy"):
        rs = sorted((r for r in recs if r.dist == d), key=lambda r: r.n)
        assert all(a.key_comparisons < b.key_comparisons and a.flops < b.flops for a, b in zip(rs, rs[1:]))


def test_fig7_shares_runs_with_fig6_and_orders_distributions(quick: Path) -> None:
    six = {(r.dist, r.n, r.seed): r for r in read_records(quick / "fig6.csv", HullCount)}
    seven = read_records(quick / "fig7.csv", HullCount)
    assert [r.dist for r in seven] == ["OnSphere", "EqHeavy", "PolHeavy", "InBall", "BordHeavy"]
    (size,) = QUICK["fig7"]
    assert {r.n for r in seven} == {size}
    for r in seven:
        if (r.dist, r.n, r.seed) in six:
            assert r == six[(r.dist, r.n, r.seed)]  # the same run, reused (CPU time included)
    ratio = {r.dist: r.flops / r.key_comparisons for r in seven}
    # The paper's qualitative shape: points inside the hull cost tests, not complex work.
    assert ratio["InBall"] > ratio["OnSphere"] and ratio["BordHeavy"] > ratio["OnSphere"]
    assert "runs reused from Fig. 6" in (quick / "fig7.md").read_text()


def test_fig8_records(quick: Path) -> None:
    recs = read_records(quick / "fig8.csv", Fig8Record)
    for n in QUICK["fig8"]:
        at = [r for r in recs if r.n == n]
        assert {r.subject for r in at} == {"Qhull (scipy)", "persistri hull", "ephemeral", "red_black", "hamt", "immutables", "pyrsistent"}
        assert all(r.status == "ok" and r.seconds is not None and r.seconds > 0 for r in at)
        assert {r.triangles for r in at} == {2 * n - 4}  # a closed hull of n points in convex position
        replays = [r for r in at if r.what == "complex_replay"]
        assert len({r.events for r in replays}) == 1 and replays[0].events > 10 * n  # one trace for all
        eph = next(r for r in replays if r.subject == "ephemeral")
        assert eph.vs_ephemeral == 1.0
        q = next(r for r in at if r.what == "qhull_total")
        for r in replays:
            assert r.vs_qhull is not None and r.seconds is not None and q.seconds is not None
            assert math.isclose(r.vs_qhull, r.seconds / q.seconds)


def test_fig11_records(quick: Path) -> None:
    recs = read_records(quick / "fig11.csv", Fig11Record)
    assert sorted({r.dem for r in recs}) == ["jacksboro", "lidar"]
    for d in ("jacksboro", "lidar"):
        rs = [r for r in recs if r.dem == d]
        assert [r.points for r in rs] == list(QUICK["fig11"])
        assert all(a.key_comparisons < b.key_comparisons and a.flops < b.flops for a, b in zip(rs, rs[1:]))
        assert all(a.max_error >= b.max_error * 0.5 for a, b in zip(rs, rs[1:]))  # errors fall, roughly
        assert rs[0].flops > rs[0].key_comparisons
    assert {(r.rows, r.cols) for r in recs if r.dem == "lidar"} == {(400, 400)}
    assert {(r.rows, r.cols) for r in recs if r.dem == "jacksboro"} == {(344, 403)}


def test_replot_rewrites_pages_from_csv(quick: Path, tmp_path: Path) -> None:
    for name in ("fig6", "fig8", "fig11"):
        for ext in ("csv", "json"):
            (tmp_path / f"{name}.{ext}").write_bytes((quick / f"{name}.{ext}").read_bytes())
    result = CliRunner().invoke(main, ["experiments", "fig6", "--out", str(tmp_path), "--replot"])
    assert result.exit_code == 0, result.output
    assert (tmp_path / "fig6.md").read_text() == (quick / "fig6.md").read_text()
    assert (tmp_path / "fig6.png").read_bytes().startswith(PNG_MAGIC)
    result = CliRunner().invoke(main, ["experiments", "fig7", "--out", str(tmp_path), "--replot"])
    assert result.exit_code != 0 and "fig7.csv" in result.output


def test_hull_counts_deterministic_and_cached() -> None:
    a = hull_counts("OnSphere", 64, 3)
    b = hull_counts("OnSphere", 64, 3)
    assert (a.key_comparisons, a.flops, a.dict_ops, a.plane_side_tests) == (b.key_comparisons, b.flops, b.dict_ops, b.plane_side_tests)
    cache = HullCountCache()
    seen: list[int] = []
    c = hull_counts("InBall", 100, 1, cache=cache, on_points=seen.append)
    assert sum(seen) == 100 and len(cache) == 1
    seen.clear()
    assert hull_counts("InBall", 100, 1, cache=cache, on_points=seen.append) is c and seen == [100]
    with pytest.raises(ValueError, match="at least 4"):
        hull_counts("InBall", 3)
    with pytest.raises(ValueError, match="unknown distribution"):
        hull_counts("Cube", 10)


def test_sizes() -> None:
    assert parse_size("128K") == 131_072 and parse_size("1600") == 1600 and parse_size("1e4") == 10_000
    assert parse_size("1_600") == 1600
    assert parse_sizes("512K, 128K,256K,128K") == (131_072, 262_144, 524_288)
    for bad in ("0", "-3", "1.5", "abc", "K"):
        with pytest.raises(ValueError):
            parse_size(bad)
    with pytest.raises(ValueError):
        parse_sizes(" , ")
    assert sizes_for("fig7", quick=False, override={"fig7": (4096, 1024)}) == (4096,)
    assert sizes_for("fig8", quick=False) == (16_384, 32_768, 65_536)
    with pytest.raises(ValueError, match="unknown figure"):
        sizes_for("fig9", quick=True)


def test_size_options() -> None:
    every = ("fig6", "fig7", "fig8", "fig11")
    assert parse_size_options(["fig6"], ("1K,2K",)) == {"fig6": (1024, 2048)}
    assert parse_size_options(every, ("fig6=1K", "fig11=100,200")) == {"fig6": (1024,), "fig11": (100, 200)}
    bad: tuple[tuple[tuple[str, ...], tuple[str, ...]], ...] = (
        (every, ("1K",)),
        (("fig6", "fig7"), ("1K",)),
        (("fig6",), ("fig8=1K",)),
        (every, ("fig9=1K",)),
        (("fig6",), ("1K", "2K")),
        (("fig6",), ("x",)),
    )
    for names, values in bad:
        with pytest.raises(click.BadParameter):
            parse_size_options(names, values)


def test_cli_rejects_bad_options(tmp_path: Path) -> None:
    runner = CliRunner()
    for args in (
        ["experiments", "all", "--quick", "--out", str(tmp_path), "--sizes", "1K"],
        ["experiments", "fig11", "--quick", "--out", str(tmp_path), "--dems", "everest"],
        ["experiments", "fig8", "--quick", "--out", str(tmp_path), "--seeds", "a"],
        ["experiments", "fig12", "--out", str(tmp_path)],
    ):
        result = runner.invoke(main, args)
        assert result.exit_code == 2, (args, result.output)
    result = runner.invoke(main, ["experiments", "fig8", "--out", str(tmp_path), "--sizes", "64", "--backends", "btree"])
    assert result.exit_code == 2 and "unknown complex 'btree'" in result.output
    assert not list(tmp_path.iterdir())  # nothing was written


def test_lidar_dem_is_the_shipped_file() -> None:
    dem = lidar_dem()
    assert dem.shape == (400, 400)
    assert np.isfinite(dem.heights).all()
    assert 379 < dem.heights.min() < dem.heights.max() < 411
    assert "lidar==0.8.4" in dem.source
    assert load_dem("jacksboro").shape == (344, 403)
    with pytest.raises(ValueError, match="unknown DEM"):
        load_dem("everest")


def test_missing_lidar_package_says_how_to_install(monkeypatch: pytest.MonkeyPatch) -> None:
    import importlib.metadata

    def missing(name: str) -> None:
        raise importlib.metadata.PackageNotFoundError(name)

    monkeypatch.setattr(importlib.metadata, "distribution", missing)
    with pytest.raises(DemUnavailableError, match="pip install --no-deps lidar==0.8.4"):
        dems_module.lidar_dem()


def test_count_dem_rejects_sizes_beyond_the_grid() -> None:
    tiny = dems_module.Dem("tiny", "tiny", np.arange(16.0).reshape(4, 4) ** 2, "made here", "1")
    with pytest.raises(ValueError, match="16 samples"):
        count_dem(tiny, [20])
    with pytest.raises(ValueError, match="at least 4"):
        count_dem(tiny, [3])
    recs = count_dem(tiny, [4, 6, 8])
    assert [r.points for r in recs] == [4, 6, 8]
    assert recs[0].key_comparisons == 0 and recs[-1].key_comparisons > recs[1].key_comparisons > 0


def test_output_helpers(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="must say why"):
        Comparison("c", "p", "o", "differs")
    with pytest.raises(ValueError, match="verdict"):
        Comparison("c", "p", "o", "maybe", "x")  # type: ignore[arg-type]
    assert markdown_table(("a", "b"), [("1|2", "x")], "lr").splitlines() == ["| a | b |", "| --- | ---: |", "| 1\\|2 | x |"]
    with pytest.raises(ValueError):
        write_csv(tmp_path / "x.csv", [])
    with pytest.raises(ValueError, match="record 1"):
        write_csv(tmp_path / "x.csv", [{"a": 1}, {"b": 2}])
    rec = Fig8Record(8, 0, "red_black", "complex_replay", None, 10, 12, None, 1.5, "skipped", "why, with a comma")
    path = write_csv(tmp_path / "r.csv", [rec.row(), rec.row()])
    assert read_records(path, Fig8Record) == [rec, rec]
    (tmp_path / "bad.csv").write_text("n,seed\n1,2\n")
    with pytest.raises(ValueError, match="missing columns"):
        read_records(tmp_path / "bad.csv", Fig8Record)


def _without_lidar(monkeypatch: pytest.MonkeyPatch) -> None:
    """As where the PyPI package that ships the second DEM is not installed (an installed wheel's venv)."""
    import importlib.metadata

    real = importlib.metadata.distribution

    def distribution(name: str) -> importlib.metadata.Distribution:
        if name == "lidar":
            raise importlib.metadata.PackageNotFoundError(name)
        return real(name)

    monkeypatch.setattr(importlib.metadata, "distribution", distribution)


def test_default_dems_leave_out_a_missing_lidar_with_a_note(monkeypatch: pytest.MonkeyPatch) -> None:
    assert choose_dems() == (("jacksboro", "lidar"), ())  # the dev extra installs both
    assert choose_dems(["lidar", "lidar"]) == (("lidar",), ())
    _without_lidar(monkeypatch)
    assert dem_missing("jacksboro") is None
    names, notes = choose_dems()
    assert names == ("jacksboro",)
    assert len(notes) == 1 and notes[0].startswith("the lidar DEM is left out: ")
    assert "pip install --no-deps lidar==0.8.4" in notes[0]
    with pytest.raises(DemUnavailableError, match="pip install --no-deps lidar==0.8.4"):
        choose_dems(["jacksboro", "lidar"])  # asked for by name: an error, not a note
    with pytest.raises(ValueError, match="unknown DEM"):
        choose_dems(["everest"])
    with pytest.raises(ValueError, match="at least one"):
        choose_dems([])


def test_lidar_without_a_geotiff_reader_is_missing_too(monkeypatch: pytest.MonkeyPatch) -> None:
    import importlib.util

    real = importlib.util.find_spec

    def find_spec(name: str, package: str | None = None) -> Any:
        return None if name == "tifffile" else real(name, package)

    monkeypatch.setattr(importlib.util, "find_spec", find_spec)
    why = dem_missing("lidar")
    assert why is not None and "pip install 'persistri[geotiff]'" in why
    assert choose_dems()[0] == ("jacksboro",)
    with pytest.raises(DemUnavailableError, match="tifffile"):
        lidar_dem()


def test_cli_runs_fig11_without_lidar_and_says_so(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    _without_lidar(monkeypatch)
    out = tmp_path / "run"
    result = CliRunner().invoke(main, ["experiments", "fig11", "--quick", "--out", str(out)])
    assert result.exit_code == 0, result.output
    notes = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(notes) == 1 and notes[0].startswith("note: fig11: the lidar DEM is left out: ")
    assert notes[0].endswith("pip install --no-deps lidar==0.8.4")
    recs = read_records(out / "fig11.csv", Fig11Record)
    assert {r.dem for r in recs} == {"jacksboro"} and [r.points for r in recs] == list(QUICK["fig11"])
    page = (out / "fig11.md").read_text()
    assert "on one real DEM" in page and "left out: the lidar DEM is left out" in page
    assert "Note — fig11: the lidar DEM is left out" in (out / "summary.md").read_text()
    assert "Traceback" not in result.output


def test_cli_asked_for_a_missing_dem_fails_before_any_work(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    _without_lidar(monkeypatch)
    out = tmp_path / "run"
    result = CliRunner().invoke(main, ["experiments", "all", "--quick", "--out", str(out), "--dems", "jacksboro,lidar"])
    assert result.exit_code == 2
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("persistri: ") and "pip install --no-deps lidar==0.8.4" in lines[0]
    assert not out.exists()  # checked before Fig. 6 started


_REPO = Path(__file__).resolve().parents[1]
_NOT_IN_A_USERS_VENV = ("persistri", "__editable__", "lidar")
"""Entries of the dev venv's site-packages the wheel's venv does not see: the editable persistri, and the
package that ships Fig. 11's second DEM (``make install-dev`` adds it; a user's ``pip install`` does not)."""


def _run(args: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "COLUMNS", "PERSISTRI_TWIN")}
    return subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True, timeout=600, check=False)


@pytest.mark.skipif(bool(os.environ.get("PERSISTRI_TWIN")), reason="packaging is the same for the compiled twin")
def test_quick_experiments_from_an_installed_wheel(tmp_path: Path) -> None:
    """Build the wheel from the source tree, install it (offline) into a fresh venv that has persistri's
    dependencies but not the checkout, and run ``persistri experiments all --quick`` from outside the checkout.

    The venv is made without pip and given the dev venv's packages by links (no download), minus
    :data:`_NOT_IN_A_USERS_VENV`.  ~30 s: a wheel build, an install, the quick run.
    """
    # The sources the wheel is built from, copied (a build in the checkout would write its build/).
    src = tmp_path / "src"
    src.mkdir()
    with (_REPO / "pyproject.toml").open("rb") as fh:
        project = tomllib.load(fh)
    for name in sorted({d.split("/")[0] for d in project["tool"]["setuptools"]["package-dir"].values()}):
        shutil.copytree(_REPO / name, src / name, ignore=shutil.ignore_patterns("__pycache__", "*.so", "*.pyd"))
    for name in ("pyproject.toml", project["project"]["readme"], "LICENSE"):
        shutil.copy2(_REPO / name, src / name)
    wheels = tmp_path / "wheels"
    py = sys.executable
    built = _run([py, "-m", "pip", "wheel", "-q", "--no-deps", "--no-index", "--no-build-isolation", str(src), "-w", str(wheels)], tmp_path)
    assert built.returncode == 0, built.stderr
    (wheel,) = wheels.glob("persistri-*.whl")

    venv = tmp_path / "venv"
    made = _run([py, "-m", "venv", "--without-pip", str(venv)], tmp_path)
    assert made.returncode == 0, made.stderr
    vpy = venv / "bin" / "python"
    purelib = "import sysconfig; print(sysconfig.get_paths()['purelib'])"
    site = Path(_run([str(vpy), "-c", purelib], tmp_path).stdout.strip())
    dev_site = Path(_run([py, "-c", purelib], tmp_path).stdout.strip())
    assert site.is_dir() and dev_site.is_dir() and site != dev_site
    for entry in dev_site.iterdir():
        if not entry.name.lower().startswith(_NOT_IN_A_USERS_VENV):
            (site / entry.name).symlink_to(entry)
    installed = _run([str(vpy), "-m", "pip", "install", "-q", "--no-index", "--no-deps", str(wheel)], tmp_path)
    assert installed.returncode == 0, installed.stderr

    where = _run([str(vpy), "-c", "import persistri.impl, persistri.spec; print(persistri.impl.__file__)"], tmp_path)
    assert Path(where.stdout.strip()).is_relative_to(site), where.stdout + where.stderr  # the wheel, not the checkout
    assert (site / "persistri" / "impl" / "py.typed").is_file() and (site / "persistri" / "spec" / "py.typed").is_file()

    out = tmp_path / "exq"
    run = _run([str(venv / "bin" / "persistri"), "experiments", "all", "--quick", "--out", str(out)], tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "Traceback" not in run.stderr and "Warning" not in run.stderr
    assert [line for line in run.stderr.splitlines() if line.strip()] == [
        "note: fig11: the lidar DEM is left out: the second DEM of Fig. 11 ships in the PyPI package 'lidar' "
        "(lidar/data/dem.tif), which is not installed: pip install --no-deps lidar==0.8.4"
    ]
    for name in ("fig6", "fig7", "fig8", "fig11"):
        assert (out / f"{name}.png").read_bytes().startswith(PNG_MAGIC) and _rows(out / f"{name}.csv"), name
        assert f"[{name}]({name}.md)" in (out / "summary.md").read_text()
    assert {r.dem for r in read_records(out / "fig11.csv", Fig11Record)} == {"jacksboro"}
    assert f"summary: {out / 'summary.md'}" in run.stdout
