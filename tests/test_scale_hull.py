"""The parallel exact hull (:mod:`persistri.impl.scale.hull`) equals the one-process hull, on every input.

One real ``distributed.LocalCluster`` of two worker processes serves the whole module (no mocks);
the in-process path (``client=None``) runs the same tasks and takes the many hypothesis examples.
"""

from __future__ import annotations

import os
import pickle
import signal
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import cloudpickle
import dask
import dask.array as da
from dask.delayed import delayed
import numpy as np
import pytest
import zarr
from distributed import Client
from hypothesis import given
from hypothesis import strategies as st
from numpy.typing import NDArray

from persistri.impl.hull.api import Hull, convex_hull
from persistri.impl.hull.errors import DegenerateInputError
from persistri.impl.scale.cluster import ClusterError, connect
from persistri.impl.scale.hull import ParallelHull, parallel_hull
from persistri.impl.scale.sources import NpyRows, points_source

# The workers cannot import this file (tests/ is not on their path): its functions travel by value.
cloudpickle.register_pickle_by_value(sys.modules[__name__])


@pytest.fixture(scope="module")
def client() -> Iterator[Client]:
    # One failure allowed per task: the killed-worker tests then need two deaths, not four.
    with dask.config.set({"distributed.scheduler.allowed-failures": 1}):
        with connect(workers=2) as c:
            assert c is not None
            yield c


def assert_same(got: ParallelHull, want: Hull) -> None:
    assert np.array_equal(got.simplices, want.simplices)
    assert np.array_equal(got.vertices, want.vertices)
    assert got.duplicates == want.duplicates
    assert got.n == want.points.shape[0]


def grid(k: int) -> NDArray[np.float64]:
    """The k × k × k integer grid: every face coplanar, every edge collinear — ties everywhere."""
    return np.array([[x, y, z] for x in range(k) for y in range(k) for z in range(k)], dtype=np.float64)


def degenerate_mix(seed: int = 0) -> NDArray[np.float64]:
    """324 rows: a shuffled 6³ grid with 60 duplicate rows (spread over chunks: rows 0:276), 46 rows on the
    plane z = 7 (the hull's top face, duplicates among them: rows 276:322) and two last rows, one a duplicate."""
    rng = np.random.default_rng(seed)
    g = grid(6)
    g = np.concatenate([g, g[rng.integers(0, len(g), 60)]])
    g = g[rng.permutation(len(g))]
    plane = np.c_[rng.integers(0, 5, size=(46, 2)), np.full(46, 7)].astype(np.float64)
    tail = np.array([[0.0, 0.0, 0.0], [2.5, 2.5, 9.0]])
    return np.concatenate([g, plane, tail])


# --- in-process: the same tasks, many inputs ---------------------------------------------------------


@given(
    coords=st.lists(st.tuples(*[st.integers(0, 3)] * 3), min_size=4, max_size=90),
    chunk_rows=st.integers(1, 40),
    fan_in=st.integers(2, 5),
    seed=st.integers(0, 3),
)
def test_equals_the_one_process_hull_on_integer_grids(
    coords: list[tuple[int, int, int]], chunk_rows: int, fan_in: int, seed: int
) -> None:
    pts = np.array(coords, dtype=np.float64)
    try:
        want = convex_hull(pts, seed=seed)
    except DegenerateInputError as exc:
        with pytest.raises(DegenerateInputError) as info:
            parallel_hull(pts, chunk_rows=chunk_rows, fan_in=fan_in, seed=seed)
        assert str(info.value) == str(exc)
        return
    assert_same(parallel_hull(pts, chunk_rows=chunk_rows, fan_in=fan_in, seed=seed), want)


@given(
    lines=st.lists(st.tuples(*[st.integers(-1, 1)] * 3, *[st.integers(0, 2)] * 3), min_size=2, max_size=5),
    ts=st.lists(st.tuples(st.integers(0, 4), st.integers(0, 6)), min_size=6, max_size=80),
    chunk_rows=st.integers(2, 30),
)
def test_equals_it_on_points_along_a_few_lines(
    lines: list[tuple[int, ...]], ts: list[tuple[int, int]], chunk_rows: int
) -> None:
    """Many collinear points on hull edges: zero-area triangles that the final run flips away."""
    pts = np.array([[o + t * d for o, d in zip(ln[3:], ln[:3], strict=True)] for k, t in ts for ln in [lines[k % len(lines)]]], dtype=np.float64)
    try:
        want = convex_hull(pts)
    except DegenerateInputError:
        with pytest.raises(DegenerateInputError):
            parallel_hull(pts, chunk_rows=chunk_rows)
        return
    assert_same(parallel_hull(pts, chunk_rows=chunk_rows, fan_in=2), want)


def test_degenerate_chunks_pass_their_points_on() -> None:
    pts = degenerate_mix()
    got = parallel_hull(pts, chunk_rows=46, fan_in=3)
    assert_same(got, convex_hull(pts))
    coplanar, tail = got.chunks[6], got.chunks[7]
    assert (coplanar.start, coplanar.stop) == (276, 322) and coplanar.degenerate
    assert coplanar.kept == coplanar.distinct == len(np.unique(pts[276:322], axis=0))
    assert (tail.start, tail.stop, tail.distinct, tail.kept, tail.degenerate) == (322, 324, 1, 1, True)
    assert not any(c.degenerate for c in got.chunks[:6])
    assert [m[0] for m in got.merges] == [sum(c.kept for c in got.chunks)]  # one level: 8 sets, 3 per merge


def test_general_position_and_the_results_parts() -> None:
    pts = np.random.default_rng(3).normal(size=(3000, 3))
    got = parallel_hull(pts, chunk_rows=250, fan_in=4, history=True)
    want = convex_hull(pts)
    assert_same(got, want)
    assert got.workers == 0 and len(got.chunks) == 12
    assert sum(c.kept for c in got.chunks) < 3000 and got.candidates < sum(c.kept for c in got.chunks)
    assert np.array_equal(got.vertex_points, pts[got.vertices])
    assert got.hull.history is not None and len(got.hull.history) == got.hull.insertions + 1


def test_bad_input_is_named_by_its_row_in_the_whole_input() -> None:
    pts = np.random.default_rng(0).normal(size=(500, 3))
    pts[437] = [0.0, np.inf, 1.0]
    pts[301, 2] = np.nan
    with pytest.raises(ValueError) as want:
        convex_hull(pts)
    with pytest.raises(ValueError) as got:
        parallel_hull(pts, chunk_rows=64)
    assert str(got.value) == str(want.value) == "points: row 301 is not finite: [" + ", ".join(map(str, pts[301].tolist())) + "]"
    with pytest.raises(ValueError, match=r"\(n, 3\) array, got shape \(5, 2\)"):
        parallel_hull(np.zeros((5, 2)))
    with pytest.raises(ValueError, match="fan_in"):
        parallel_hull(pts, fan_in=1)
    with pytest.raises(ValueError, match="at least 1 row"):
        parallel_hull(pts, chunk_rows=0)


@pytest.mark.parametrize("pts", [np.zeros((0, 3)), np.eye(3), np.c_[np.random.default_rng(1).normal(size=(50, 2)), np.zeros(50)]])
def test_no_hull_is_the_same_error(pts: NDArray[np.float64]) -> None:
    with pytest.raises(DegenerateInputError) as want:
        convex_hull(pts)
    with pytest.raises(DegenerateInputError) as got:
        parallel_hull(pts, chunk_rows=7)
    assert str(got.value) == str(want.value)


# --- the inputs: files, directories, Zarr, Dask -----------------------------------------------------


def test_a_memory_mapped_npy_is_read_by_row_ranges(tmp_path: Path) -> None:
    pts = degenerate_mix(2)
    path = tmp_path / "pts.npy"
    np.save(path, pts)
    source = points_source(path, 50)
    assert all(isinstance(b.data, NpyRows) for b in source.blocks) and source.n == len(pts)
    assert max(len(pickle.dumps(b.data)) for b in source.blocks) < 300  # a path and two numbers, not rows
    assert_same(parallel_hull(str(path), chunk_rows=50), convex_hull(pts))


def test_a_directory_of_npy_files_is_one_input_in_name_order(tmp_path: Path) -> None:
    pts = degenerate_mix(3)
    cuts = [0, 17, 150, 151, 300, len(pts)]
    for i, (a, b) in enumerate(zip(cuts, cuts[1:])):
        np.save(tmp_path / f"part-{i:03d}.npy", pts[a:b])
    (tmp_path / "notes.txt").write_text("not points")
    got = parallel_hull(tmp_path, chunk_rows=64)
    assert [(c.start, c.stop) for c in got.chunks][:4] == [(0, 17), (17, 81), (81, 145), (145, 150)]
    assert_same(got, convex_hull(pts))


def test_zarr_stores_and_arrays(tmp_path: Path) -> None:
    pts = degenerate_mix(4)
    z = zarr.create_array(store=str(tmp_path / "pts.zarr"), shape=pts.shape, chunks=(64, 3), dtype="f8")
    z[:] = pts
    want = convex_hull(pts)
    assert_same(parallel_hull(tmp_path / "pts.zarr", chunk_rows=64), want)
    assert_same(parallel_hull(z, chunk_rows=100), want)


def test_bad_files_are_one_clear_error(tmp_path: Path) -> None:
    np.save(tmp_path / "flat.npy", np.zeros((4, 2)))
    with pytest.raises(ValueError, match=r"flat\.npy: points must be an \(n, 3\) array, got shape \(4, 2\)"):
        parallel_hull(tmp_path / "flat.npy")
    (tmp_path / "empty").mkdir()
    with pytest.raises(ValueError, match="holds none"):
        parallel_hull(tmp_path / "empty")
    with pytest.raises(FileNotFoundError):
        parallel_hull(tmp_path / "missing.npy")
    np.save(tmp_path / "words.npy", np.array([["a", "b", "c"]]))
    with pytest.raises(ValueError, match=r"words\.npy: holds <U1 values, not real numbers"):
        parallel_hull(tmp_path / "words.npy")
    np.save(tmp_path / "pts.npy", np.eye(3)[[0, 1, 2, 0]])
    (tmp_path / "pts.npy").write_bytes((tmp_path / "pts.npy").read_bytes()[:-8])
    with pytest.raises(ValueError, match=r"pts\.npy: truncated"):
        parallel_hull(tmp_path / "pts.npy")


# --- on the cluster -----------------------------------------------------------------------------------


def test_on_two_workers_general_and_degenerate(client: Client) -> None:
    ball = np.random.default_rng(5).normal(size=(10_000, 3))
    got = parallel_hull(ball, client=client, chunk_rows=1_000, fan_in=3, check=True)
    assert got.workers == 2 and len(got.chunks) == 10 and len(got.merges) == 2  # 10 sets, then 4, then the final run
    assert_same(got, convex_hull(ball))
    mix = degenerate_mix(6)
    assert_same(parallel_hull(mix, client=client, chunk_rows=33, fan_in=2, check=True), convex_hull(mix))


def test_on_two_workers_from_files_and_dask(client: Client, tmp_path: Path) -> None:
    pts = degenerate_mix(7)
    want = convex_hull(pts)
    np.save(tmp_path / "pts.npy", pts)
    assert_same(parallel_hull(tmp_path / "pts.npy", client=client, chunk_rows=45), want)
    z = zarr.create_array(store=str(tmp_path / "pts.zarr"), shape=pts.shape, chunks=(45, 3), dtype="f8")
    z[:] = pts
    assert_same(parallel_hull(str(tmp_path / "pts.zarr"), client=client), want)
    assert_same(parallel_hull(da.from_array(pts, chunks=(60, 3)), client=client), want)


def test_through_a_scheduler_address(client: Client) -> None:
    address = str(client.scheduler_info()["address"])
    pts = degenerate_mix(8)
    with connect(scheduler=address) as other:
        assert other is not None and other is not client
        assert_same(parallel_hull(pts, client=other, chunk_rows=70), convex_hull(pts))


def test_errors_from_workers_are_the_same_errors(client: Client, tmp_path: Path) -> None:
    pts = np.random.default_rng(9).normal(size=(400, 3))
    pts[250, 0] = np.nan
    with pytest.raises(ValueError, match=r"^points: row 250 is not finite"):
        parallel_hull(pts, client=client, chunk_rows=100)
    np.save(tmp_path / "pts.npy", pts)
    with pytest.raises(ValueError, match=r"pts\.npy: row 250 is not finite"):
        parallel_hull(tmp_path / "pts.npy", client=client, chunk_rows=100)
    with pytest.raises(DegenerateInputError) as got:
        parallel_hull(np.c_[pts[:, :2], np.ones(400)][:249], client=client, chunk_rows=50)
    assert "affine dimension 2" in str(got.value)


def _block_or_die(flag: str, block: NDArray[np.float64], always: bool) -> NDArray[np.float64]:
    """The block — after killing the worker process running it, the first time (or every time)."""
    if always or not os.path.exists(flag):
        Path(flag).touch()
        os.kill(os.getpid(), signal.SIGKILL)
    return block


def _dying_array(pts: NDArray[np.float64], flag: Path, *, at: int, always: bool = False) -> Any:
    """``pts`` as a Dask array of blocks of 100 rows, the block starting at row ``at`` deadly."""
    parts = []
    for a in range(0, len(pts), 100):
        block = pts[a : a + 100]
        if a == at:
            lazy = delayed(_block_or_die, pure=False)(str(flag), block, always)
            parts.append(da.from_delayed(lazy, shape=block.shape, dtype=block.dtype))
        else:
            parts.append(da.from_array(block, chunks=block.shape))
    return da.concatenate(parts)


def test_a_worker_killed_mid_run_gives_the_right_hull(client: Client, tmp_path: Path) -> None:
    pts = degenerate_mix(10)
    flag = tmp_path / "killed-once"
    got = parallel_hull(_dying_array(pts, flag, at=200), client=client)
    assert flag.exists()  # a worker did die
    assert_same(got, convex_hull(pts))
    client.wait_for_workers(2, timeout=60)


def test_a_task_that_always_kills_its_worker_is_a_clear_error(client: Client, tmp_path: Path) -> None:
    pts = degenerate_mix(11)
    with pytest.raises(ClusterError, match=r"was given up on: the 2 workers that ran it died") as info:
        parallel_hull(_dying_array(pts, tmp_path / "flag", at=100, always=True), client=client)
    assert "\n" not in str(info.value)
    client.wait_for_workers(2, timeout=60)
