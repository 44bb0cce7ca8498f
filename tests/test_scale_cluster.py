"""Where the parallel work runs (:mod:`persistri.impl.scale.cluster`), and that only the scale package imports Dask."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from persistri.impl.scale import cluster
from persistri.impl.scale.cluster import ENV_SCHEDULER, ClusterError, connect, default_workers, plan


def test_one_worker_is_the_sequential_path_whatever_the_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(ENV_SCHEDULER, "tcp://127.0.0.1:8786")
    assert plan(workers=1) == ("sequential", None)
    with connect(workers=1) as client:
        assert client is None


def test_the_rules_in_order(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(ENV_SCHEDULER, raising=False)
    assert plan(workers=5) == ("local", 5)
    assert plan(scheduler=" tcp://h:8786 ") == ("scheduler", "tcp://h:8786")
    cores = default_workers()
    assert plan() == (("sequential", None) if cores == 1 else ("local", cores))
    monkeypatch.setenv(ENV_SCHEDULER, "tcp://from-env:8786")
    assert plan() == ("scheduler", "tcp://from-env:8786")
    assert plan(workers=3) == ("local", 3)  # an explicit count beats the environment
    assert plan(scheduler="tcp://given:1") == ("scheduler", "tcp://given:1")
    assert plan(tasks=1) == ("sequential", None)  # one task: nothing to share, even with a scheduler named
    assert plan(tasks=2) == ("scheduler", "tcp://from-env:8786")
    assert plan(workers=2, tasks=1) == ("local", 2) and plan(scheduler="tcp://s:1", tasks=1) == ("scheduler", "tcp://s:1")
    monkeypatch.setenv(ENV_SCHEDULER, "  ")
    assert plan() == (("sequential", None) if cores == 1 else ("local", cores))


@pytest.mark.parametrize(
    ("workers", "scheduler", "message"),
    [
        (0, None, "at least 1"),
        (-2, None, "at least 1"),
        (True, None, "whole number"),
        (2.5, None, "whole number"),
        (None, "", "empty"),
        (2, "tcp://h:1", "not both"),
        (1, "tcp://h:1", "not both"),
    ],
)
def test_bad_requests_are_one_clear_error(workers: object, scheduler: str | None, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        plan(workers, scheduler)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=message):
        with connect(workers, scheduler):  # type: ignore[arg-type]
            pass


def test_an_unreachable_scheduler_is_a_cluster_error(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT", 1.0)
    with pytest.raises(ClusterError, match=r"^cannot reach the Dask scheduler at tcp://127\.0\.0\.1:9: ") as info:
        with connect(scheduler="tcp://127.0.0.1:9"):
            pass
    assert "\n" not in str(info.value)


def test_dask_missing_says_what_to_install(monkeypatch: pytest.MonkeyPatch) -> None:
    import persistri.impl.scale as scale

    assert scale.dask_missing() is None
    monkeypatch.setattr(scale, "find_spec", lambda name: None if name == "distributed" else object())
    assert scale.dask_missing() == (
        "distributed not installed: the parallel path needs persistri[dask] (pip install 'persistri[dask]')"
    )


def _pid() -> int:
    return os.getpid()


def test_a_local_cluster_is_processes_of_one_thread_and_closes_with_the_block(monkeypatch: pytest.MonkeyPatch) -> None:
    with connect(workers=2) as client:
        assert client is not None
        threads = client.nthreads()
        assert sorted(threads.values()) == [1, 1]
        pids = set(client.run(_pid).values())
        assert len(pids) == 2 and os.getpid() not in pids
        assert client.dashboard_link is None or "127.0.0.1" in client.dashboard_link
        scheduler = str(client.scheduler_info()["address"])
        assert scheduler.startswith("tcp://127.0.0.1:")
    assert client.status == "closed"
    # The same address, now gone, is an existing cluster that no longer answers.
    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT", 1.0)
    with pytest.raises(ClusterError):
        with connect(scheduler=scheduler):
            pass


PROBE = """
import importlib, json, pkgutil, sys
import persistri, persistri.impl
names = []
for info in pkgutil.walk_packages(persistri.impl.__path__, "persistri.impl."):
    importlib.import_module(info.name)
    names.append(info.name)
heavy = sorted(m for m in ("dask", "distributed", "zarr", "bokeh") if m in sys.modules)
{after}
print(json.dumps({{"modules": len(names), "dask": heavy}}))
"""


def test_only_running_on_a_cluster_imports_dask() -> None:
    """``import persistri`` and every ``persistri.impl`` module (the CLI, the benchmarks and the scale
    package included) leave Dask unimported: it is imported when a cluster is asked for."""
    env = os.environ.copy()
    out = subprocess.run([sys.executable, "-c", PROBE.format(after="")], check=True, capture_output=True, text=True, env=env)
    got = json.loads(out.stdout)
    assert got["dask"] == [] and got["modules"] > 50
    # The probe sees Dask when it is there: the scale package's parallel path imports it.
    after = "import dask.array; heavy = sorted(m for m in ('dask', 'distributed') if m in sys.modules)"
    out = subprocess.run([sys.executable, "-c", PROBE.format(after=after)], check=True, capture_output=True, text=True, env=env)
    assert "dask" in json.loads(out.stdout)["dask"]
