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
    if info.name.startswith("persistri.impl.scale"):
        continue
    importlib.import_module(info.name)
    names.append(info.name)
print(json.dumps({"modules": len(names), "dask": sorted(m for m in ("dask", "distributed", "zarr", "bokeh") if m in sys.modules)}))
"""


def test_only_the_scale_package_imports_dask() -> None:
    """``import persistri`` and every ``persistri.impl`` module outside ``impl/scale`` (the CLI and the
    benchmarks included: they import Dask when a command asks for workers) leave Dask unimported."""
    out = subprocess.run([sys.executable, "-c", PROBE], check=True, capture_output=True, text=True, env=os.environ.copy())
    got = json.loads(out.stdout)
    assert got["dask"] == [] and got["modules"] > 50
    probe = "import json, sys, persistri.impl.scale.cluster; print(json.dumps('distributed' in sys.modules))"
    loads = subprocess.run([sys.executable, "-c", probe], check=True, capture_output=True, text=True, env=os.environ.copy())
    assert json.loads(loads.stdout) is True  # the probe above can see Dask when it is there
