"""The sweep of Figs. 6 and 7 as Dask tasks (:mod:`persistri.impl.experiments.sweep`): the same counts as in one process.

One real ``distributed.LocalCluster`` of two worker processes serves the module (no mocks).  Nothing is
timed: the records' counts and the written files are compared with the sequential run's.
"""

from __future__ import annotations

import csv
import json
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from click.testing import CliRunner
from distributed import Client

from persistri.impl.cli.main import main
from persistri.impl.experiments.counts import HullCountCache, hull_counts
from persistri.impl.experiments.suite import run_experiments
from persistri.impl.experiments.sweep import count_runs, hull_runs
from persistri.impl.scale.cluster import connect

SIZES = {"fig6": (256, 512), "fig7": (512,)}
SEEDS = (0, 1)
MEASURED = {"cpu_seconds"}  # a measurement, not a count: differs between any two runs


@pytest.fixture(scope="module")
def client() -> Iterator[Client]:
    with connect(workers=2) as c:
        assert c is not None
        yield c


def rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as fh:
        return list(csv.DictReader(fh))


def counts(path: Path) -> list[dict[str, str]]:
    """The CSV's records without the measured columns (the ratio column is counts only)."""
    out = [{k: v for k, v in r.items() if k not in MEASURED} for r in rows(path)]
    assert out and all(int(r["key_comparisons"]) > 0 and int(r["flops"]) > 0 for r in out)
    return out


def parameters(path: Path) -> dict[str, str]:
    """A figure's run parameters as saved beside it (sizes, seeds, backend, runs reused), times left out."""
    out: dict[str, str] = json.loads(path.read_text())["parameters"]
    return out


def test_the_sweep_on_two_workers_gives_the_sequential_counts_and_files(client: Client, tmp_path: Path) -> None:
    here = run_experiments(["fig6", "fig7"], tmp_path / "here", sizes=SIZES, seeds=SEEDS)
    seen: list[tuple[int, int]] = []

    def progress(name: str) -> Callable[[int, int, str], None]:
        def update(done: int, total: int, what: str) -> None:
            if name == "fig6":
                seen.append((done, total))

        return update

    there = run_experiments(["fig6", "fig7"], tmp_path / "there", sizes=SIZES, seeds=SEEDS, client=client, progress=progress)
    for name in ("fig6", "fig7"):
        assert counts(tmp_path / "there" / f"{name}.csv") == counts(tmp_path / "here" / f"{name}.csv"), name
        assert (tmp_path / "there" / f"{name}.png").stat().st_size > 10_000
    # Fig. 7 still reports the runs it shares with Fig. 6 as reused (4), not all it took from the sweep (10).
    for key in ("fig6.json", "fig7.json"):
        assert parameters(tmp_path / "there" / key) == parameters(tmp_path / "here" / key)
    assert parameters(tmp_path / "there" / "fig7.json")["runs reused from Fig. 6"] == "4"
    # 2 dists × 2 sizes × 2 seeds for Fig. 6, 5 dists × 2 seeds for Fig. 7, 4 runs in both: 14 tasks.
    assert there.notes[0].startswith("fig6, fig7: their 14 counted hull runs were made first as Dask tasks")
    assert not here.notes
    points = 2 * 2 * (256 + 512) + 3 * 2 * 512
    assert seen[0] == (0, points) and (points, points) in seen  # the sweep's progress, on Fig. 6's callback


def test_count_runs_prefills_and_figures_take(client: Client) -> None:
    cache = HullCountCache()
    runs = hull_runs({"fig7": (64,)}, (3,))
    assert [r[0] for r in runs] == ["OnSphere", "EqHeavy", "PolHeavy", "InBall", "BordHeavy"]
    assert count_runs(client, runs, backend="red_black", cache=cache) == 5
    assert len(cache) == 0 and cache.get("InBall", 64, 3, "red_black") is None  # made ahead, not yet taken
    taken = hull_counts("InBall", 64, 3, cache=cache)
    assert cache.get("InBall", 64, 3, "red_black") is taken
    here = hull_counts("InBall", 64, 3)
    assert (taken.key_comparisons, taken.dict_ops, taken.flops, taken.plane_side_tests, taken.faces_created) == (
        here.key_comparisons, here.dict_ops, here.flops, here.plane_side_tests, here.faces_created
    )
    assert count_runs(client, [("InBall", 64, 3)], backend="red_black", cache=cache) == 0  # made already
    with pytest.raises(ValueError, match="unknown distribution"):  # a task's error is itself, raised here
        count_runs(client, [("Cube", 64, 0)], backend="red_black", cache=cache)


def test_the_command_with_a_scheduler(client: Client, tmp_path: Path) -> None:
    address = str(client.scheduler_info()["address"])
    base = ["experiments", "fig6", "--sizes", "128,256", "--seeds", "0,1"]
    here = CliRunner().invoke(main, [*base, "--out", str(tmp_path / "here")])
    there = CliRunner().invoke(main, [*base, "--out", str(tmp_path / "there"), "--scheduler", address])
    assert here.exit_code == 0 and there.exit_code == 0, there.output
    assert "dask: 2 workers" in there.output and "dask:" not in here.output
    assert counts(tmp_path / "there" / "fig6.csv") == counts(tmp_path / "here" / "fig6.csv")
    assert "8 counted hull runs were made first as Dask tasks" in (tmp_path / "there" / "summary.md").read_text()


def test_the_command_rejects_what_does_not_apply(tmp_path: Path) -> None:
    both = CliRunner().invoke(main, ["experiments", "fig6", "--quick", "--out", str(tmp_path), "--workers", "2", "--scheduler", "tcp://x:1"])
    assert both.exit_code == 2 and "not both" in both.output
    replot = CliRunner().invoke(main, ["experiments", "fig6", "--out", str(tmp_path), "--replot", "--workers", "2"])
    assert replot.exit_code == 2 and "--replot measures nothing" in replot.output
    # One worker is this process: no cluster, no note.
    one = CliRunner().invoke(main, ["experiments", "fig6", "--sizes", "64", "--out", str(tmp_path / "one"), "--workers", "1"])
    assert one.exit_code == 0 and "dask:" not in one.output, one.output
