"""``persistri hull --workers/--scheduler/--chunk-size``: the same files as one process, the same one-line errors."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
import zarr
from click.testing import CliRunner
from distributed import Client
from numpy.typing import NDArray

from persistri.impl.cli import hull as hull_cli
from persistri.impl.cli.main import main
from persistri.impl.hull.distributions import generate
from persistri.impl.scale import cluster
from persistri.impl.scale.cluster import connect


@pytest.fixture(scope="module")
def address() -> Iterator[str]:
    """The scheduler of a local cluster of two worker processes, shared by the module."""
    with connect(workers=2) as client:
        assert isinstance(client, Client)
        yield str(client.scheduler_info()["address"])


def run(*args: str) -> tuple[int, str, str]:
    result = CliRunner().invoke(main, ["hull", *args])
    return result.exit_code, result.stdout, result.stderr


def points(n: int = 3_000, seed: int = 4) -> NDArray[np.float64]:
    """A ball of points with a grid's ties and duplicates mixed in (some in every chunk of 500)."""
    pts = np.round(generate("InBall", n, seed) * 4) / 4  # coarse: coplanar and collinear points, duplicates
    return pts


def same_npz(a: Path, b: Path) -> None:
    x, y = np.load(a), np.load(b)
    assert x.files == y.files == ["points", "simplices", "vertices"]
    for k in x.files:
        assert x[k].dtype == y[k].dtype and np.array_equal(x[k], y[k]), k


def test_on_a_cluster_the_same_npz_as_one_process(address: str, tmp_path: Path) -> None:
    np.save(tmp_path / "pts.npy", points())
    one = run(str(tmp_path / "pts.npy"), "--workers", "1", "-o", str(tmp_path / "one.npz"))
    many = run(str(tmp_path / "pts.npy"), "--scheduler", address, "--chunk-size", "500", "-o", str(tmp_path / "many.npz"), "--check")
    assert one[0] == many[0] == 0, many
    same_npz(tmp_path / "one.npz", tmp_path / "many.npz")
    assert "dask: 2 workers, dashboard " in many[2] and "dask" not in one[2]
    assert "duplicate rows merged (verified exactly); 6 chunks" in many[2] and "on 2 workers" in many[2]
    assert many[2].count("\n") == 2  # the cluster line and the summary: no warnings, no logs


def test_mesh_formats_hold_the_hull_vertices(address: str, tmp_path: Path) -> None:
    import meshio

    pts = points(2_000, 5)
    np.save(tmp_path / "pts.npy", pts)
    code, _, err = run(str(tmp_path / "pts.npy"), "--scheduler", address, "--chunk-size", "400", "-o", str(tmp_path / "h.ply"), "--quiet")
    assert code == 0 and err == ""
    assert run(str(tmp_path / "pts.npy"), "--workers", "1", "-o", str(tmp_path / "one.ply"), "--quiet")[0] == 0
    a, b = meshio.read(tmp_path / "h.ply"), meshio.read(tmp_path / "one.ply")
    assert np.array_equal(a.points, b.points) and np.array_equal(a.cells[0].data, b.cells[0].data)


def test_a_directory_of_npy_files_and_a_zarr_store(address: str, tmp_path: Path) -> None:
    pts = points(1_500, 6)
    np.save(tmp_path / "whole.npy", pts)
    (tmp_path / "parts").mkdir()
    for i, (a, b) in enumerate([(0, 700), (700, 701), (701, 1_500)]):
        np.save(tmp_path / "parts" / f"{i:02d}.npy", pts[a:b])
    z = zarr.create_array(store=str(tmp_path / "pts.zarr"), shape=pts.shape, chunks=(256, 3), dtype="f8")
    z[:] = pts
    assert run(str(tmp_path / "whole.npy"), "--workers", "1", "-o", str(tmp_path / "want.npz"), "--quiet")[0] == 0
    for name, source in [("dir", tmp_path / "parts"), ("zarr", tmp_path / "pts.zarr")]:
        for where in (["--workers", "1"], ["--scheduler", address]):
            out = tmp_path / f"{name}-{where[0][2:]}.npz"
            code, _, err = run(str(source), *where, "--chunk-size", "300", "-o", str(out))
            assert code == 0, err
            same_npz(tmp_path / "want.npz", out)
            assert ("in this process" in err) == (where[0] == "--workers")


def test_small_inputs_stay_in_this_process_by_default(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def no_cluster(*args: object, **kwargs: object) -> None:
        raise AssertionError("a cluster was started for one chunk")

    monkeypatch.setattr(cluster, "connect", no_cluster)
    np.save(tmp_path / "pts.npy", points(800))
    code, _, err = run(str(tmp_path / "pts.npy"), "-o", str(tmp_path / "h.npz"))
    assert code == 0 and "dask" not in err and "chunks" not in err


def test_the_default_uses_the_scheduler_of_the_environment(address: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(cluster.ENV_SCHEDULER, address)
    np.save(tmp_path / "pts.npy", points(1_200))
    code, _, err = run(str(tmp_path / "pts.npy"), "--chunk-size", "500", "-o", str(tmp_path / "h.npz"))
    assert code == 0 and "3 chunks" in err and "on 2 workers" in err


def test_a_local_cluster_of_its_own_with_its_dashboard(tmp_path: Path) -> None:
    code, _, err = run("--dist", "InBall", "-n", "4000", "--workers", "2", "--chunk-size", "1000", "-o", str(tmp_path / "h.npz"))
    assert code == 0, err
    first = err.splitlines()[0]
    assert first.startswith("dask: 2 workers, dashboard http://127.0.0.1:") and first.endswith("/status")
    assert run("--dist", "InBall", "-n", "4000", "--workers", "1", "-o", str(tmp_path / "one.npz"), "--quiet")[0] == 0
    same_npz(tmp_path / "one.npz", tmp_path / "h.npz")


def one_line(err: str) -> str:
    assert err.count("\n") == 1 and err.startswith("persistri: "), err
    return err.strip()


def test_bad_rows_are_the_same_line_on_both_paths(address: str, tmp_path: Path) -> None:
    pts = points(1_000)
    pts[777, 1] = np.inf
    np.save(tmp_path / "pts.npy", pts)
    one = run(str(tmp_path / "pts.npy"), "--workers", "1")
    many = run(str(tmp_path / "pts.npy"), "--scheduler", address, "--chunk-size", "100", "--quiet")
    assert one[0] == many[0] == 2
    assert one_line(one[2]) == one_line(many[2])
    assert f"pts.npy: row 777 is not finite: {pts[777].tolist()}" in one[2]
    flat = np.c_[pts[:600, :2], np.zeros(600)]
    np.save(tmp_path / "flat.npy", flat)
    one = run(str(tmp_path / "flat.npy"), "--workers", "1")
    many = run(str(tmp_path / "flat.npy"), "--scheduler", address, "--chunk-size", "100", "--quiet")
    assert one_line(one[2]) == one_line(many[2]) and "no 3D convex hull" in one[2]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--workers", "2", "--scheduler", "tcp://127.0.0.1:9"], "not both"),
        (["--workers", "2", "--stats"], "--stats counts the operations of one process"),
        (["--scheduler", "tcp://127.0.0.1:9", "--stats"], "--stats counts the operations of one process"),
        (["--workers", "0"], "0 is not in the range x>=1"),
        (["--chunk-size", "0"], "0 is not in the range x>=1"),
        (["--scheduler", " "], "not an empty string"),
    ],
)
def test_bad_options_are_usage_errors(args: list[str], message: str) -> None:
    result = CliRunner().invoke(main, ["hull", "--dist", "InBall", "-n", "10", *args])
    assert result.exit_code == 2 and message in result.stderr


def test_an_unreachable_scheduler_is_one_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT", 1.0)
    code, _, err = run("--dist", "InBall", "-n", "100", "--scheduler", "tcp://127.0.0.1:9", "-o", str(tmp_path / "h.npz"))
    assert code == 2
    assert one_line(err).startswith("persistri: cannot reach the Dask scheduler at tcp://127.0.0.1:9: ")
    assert not (tmp_path / "h.npz").exists()


def test_outputs_are_checked_before_any_cluster(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def no_cluster(*args: object, **kwargs: object) -> None:
        raise AssertionError("a cluster was started although the output is bad")

    monkeypatch.setattr(cluster, "connect", no_cluster)
    code, _, err = run("--dist", "InBall", "-n", "100", "--workers", "2", "-o", str(tmp_path / "no" / "such" / "h.npz"))
    assert code == 2 and "does not exist" in one_line(err)


def test_without_the_extra(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """No Dask: asking for workers is one line saying what to install; the default runs in this process."""
    monkeypatch.setattr(hull_cli, "dask_missing", lambda: "dask not installed: the parallel path needs persistri[dask] (pip install 'persistri[dask]')")
    code, _, err = run("--dist", "InBall", "-n", "100", "--workers", "2")
    assert code == 2 and one_line(err) == "persistri: dask not installed: the parallel path needs persistri[dask] (pip install 'persistri[dask]')"
    code, _, err = run("--dist", "InBall", "-n", "2000", "--chunk-size", "500", "-o", str(tmp_path / "h.npz"))
    assert code == 0 and "chunks" not in err
