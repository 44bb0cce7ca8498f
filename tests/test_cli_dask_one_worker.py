"""The commands' cluster line on a cluster of one worker: "1 worker", as the summary says, not "1 workers"."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from click.testing import CliRunner
from distributed import Client

from persistri.impl.cli.main import main
from persistri.impl.scale.cluster import connect


def test_the_cluster_line_counts_one_worker_in_the_singular(tmp_path: Path) -> None:
    np.save(tmp_path / "pts.npy", np.random.default_rng(3).standard_normal((2_000, 3)))
    with connect(workers=1) as here:
        assert here is None  # workers=1 is this process: a cluster of one worker needs a scheduler
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0") as lc, Client(lc):
        result = CliRunner().invoke(main, ["hull", str(tmp_path / "pts.npy"), "--scheduler", lc.scheduler_address])
    assert result.exit_code == 0, result.output
    first = result.stderr.splitlines()[0]
    assert first.startswith("dask: 1 worker, dashboard "), first
    assert "on 1 worker" in result.stderr and "1 workers" not in result.stderr
