"""``persistri.ConvexHull`` on inputs too big to load: the same hull as the one-process one, attribute by attribute.

Paths (``.npy``, a directory of ``.npy`` files, a Zarr store), Zarr arrays and Dask arrays go through
:func:`persistri.impl.scale.hull.parallel_hull`: in this process (``workers=1``, or by default for one
chunk) and on one real ``distributed.LocalCluster`` of two worker processes shared by the module.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import dask.array as da
import numpy as np
import pytest
import zarr
from distributed import Client
from hypothesis import given
from hypothesis import strategies as st
from numpy.typing import NDArray

import persistri
from persistri.impl.hull.errors import DegenerateInputError
from persistri.impl.scale.cluster import ENV_SCHEDULER, connect

pytestmark = pytest.mark.filterwarnings("ignore::ResourceWarning")


@pytest.fixture(scope="module")
def client() -> Iterator[Client]:
    with connect(workers=2) as c:
        assert c is not None
        yield c


def degenerate(seed: int) -> NDArray[np.float64]:
    """230 rows: a shuffled 5³ integer grid (ties everywhere) with 40 duplicate rows spread over the input,
    20 rows on the plane z = 6 (the hull's top face) and a random cloud inside."""
    rng = np.random.default_rng(seed)
    g = np.array([[x, y, z] for x in range(5) for y in range(5) for z in range(5)], dtype=np.float64)
    g = np.concatenate([g, g[rng.integers(0, len(g), 40)], rng.uniform(0.5, 3.5, size=(45, 3))])
    g = g[rng.permutation(len(g))]
    plane = np.c_[rng.integers(0, 5, size=(20, 2)), np.full(20, 6)].astype(np.float64)
    return np.concatenate([g, plane])


def assert_same_hull(got: persistri.ConvexHull, want: persistri.ConvexHull) -> None:
    """Every attribute that names points or measures the hull, exactly equal."""
    assert got.chunked is not None and want.chunked is None
    for name in ("vertices", "simplices", "neighbors", "equations", "duplicates", "vertex_points", "min_bound", "max_bound"):
        a, b = getattr(got, name), getattr(want, name)
        assert a.dtype == b.dtype and np.array_equal(a, b), name
        assert not a.flags.writeable, name
    assert (got.volume, got.area, got.npoints, got.nsimplex) == (want.volume, want.area, want.npoints, want.nsimplex)
    assert np.array_equal(got.points, want.points) and not got.points.flags.writeable
    assert np.array_equal(got.min_bound, got.points.min(axis=0)) and np.array_equal(got.max_bound, got.points.max(axis=0))


def inputs(pts: NDArray[np.float64], tmp_path: Path) -> dict[str, Any]:
    """``pts`` as every kind of input too big to load: three paths and two lazy arrays."""
    np.save(tmp_path / "pts.npy", pts)
    (tmp_path / "parts").mkdir()
    for i, (a, b) in enumerate([(0, 90), (90, 91), (91, len(pts))]):
        np.save(tmp_path / "parts" / f"{i:03d}.npy", pts[a:b])
    z = zarr.create_array(store=str(tmp_path / "pts.zarr"), shape=pts.shape, chunks=(64, 3), dtype="f8")
    z[:] = pts
    return {
        "npy": str(tmp_path / "pts.npy"),
        "directory": tmp_path / "parts",
        "zarr store": tmp_path / "pts.zarr",
        "zarr array": z,
        "dask array": da.from_array(pts, chunks=(70, 3)),
    }


# --- in this process ----------------------------------------------------------------------------------


def test_every_input_in_this_process_is_the_one_process_hull(tmp_path: Path) -> None:
    pts = degenerate(1)
    want = persistri.ConvexHull(pts)
    assert len(want.duplicates) > 0
    for kind, given in inputs(pts, tmp_path).items():
        got = persistri.ConvexHull(given, workers=1, chunk_rows=50)
        assert got.chunked is not None and got.chunked.workers == 0, kind
        assert len(got.chunked.chunks) >= 5, kind  # really cut: 255 rows in chunks of at most 50
        assert_same_hull(got, want)


def test_by_default_one_chunk_runs_here_without_dask(tmp_path: Path) -> None:
    """A small file takes the chunked path in this process: no cluster, not even Dask imported."""
    pts = degenerate(2)
    np.save(tmp_path / "pts.npy", pts)
    code = (
        "import json, sys, persistri\n"
        f"h = persistri.ConvexHull({str(tmp_path / 'pts.npy')!r})\n"
        "print(json.dumps([h.chunked.workers, h.vertices.tolist(), [m for m in ('dask', 'distributed') if m in sys.modules]]))\n"
    )
    env = {k: v for k, v in os.environ.items() if k != ENV_SCHEDULER}
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True, env=env)
    workers, vertices, imported = json.loads(out.stdout)
    assert (workers, imported) == (0, [])
    assert vertices == persistri.ConvexHull(pts).vertices.tolist()


def test_points_of_a_npy_are_memory_mapped_and_of_others_loaded(tmp_path: Path) -> None:
    pts = degenerate(3)
    given = inputs(pts, tmp_path)
    mapped = persistri.ConvexHull(given["npy"]).points
    assert isinstance(mapped, np.memmap) and np.array_equal(mapped, pts)
    loaded = persistri.ConvexHull(given["directory"]).points
    assert not isinstance(loaded, np.memmap) and np.array_equal(loaded, pts)
    assert np.array_equal(pts[persistri.ConvexHull(given["dask array"]).vertices], persistri.ConvexHull(pts).vertex_points)


def test_history_is_the_final_merges_and_result_its_run(tmp_path: Path) -> None:
    pts = np.random.default_rng(4).normal(size=(2000, 3))
    got = persistri.ConvexHull(da.from_array(pts, chunks=(400, 3)), workers=1, history=True, check=True)
    assert got.chunked is not None and len(got.chunked.chunks) == 5
    final, history = got.result, got.history
    assert history is not None and final.history is not None and len(history) == final.insertions + 1
    assert final.points.shape[0] == got.chunked.candidates < 2000  # the merge saw the candidates only
    assert np.array_equal(np.sort(got.chunked.rows[final.vertices]), got.vertices)
    assert history[-1] is final.complex and history[0] is final.history[0]  # the versions, shared
    assert np.array_equal(history.simplices(len(history) - 1), got.simplices)  # rows of the whole input
    assert not np.array_equal(history.simplices(0), final.history.simplices(0))  # renamed: rows, not candidates
    assert set(history.inserted) <= set(got.chunked.rows.tolist())
    assert "5 chunks of dask array of 2,000 points" in repr(got)


def test_what_cannot_be_done_chunk_by_chunk_is_one_clear_error(tmp_path: Path) -> None:
    pts = degenerate(5)
    np.save(tmp_path / "pts.npy", pts)
    hull = persistri.ConvexHull(tmp_path / "pts.npy")
    with pytest.raises(ValueError, match=r"^new points: row 1 is not finite"):
        hull.add_points([[9.0, 9.0, 9.0], [np.inf, 0.0, 0.0]])
    with pytest.raises(ValueError, match=r"^stats= counts the operations of one process"):
        persistri.ConvexHull(tmp_path / "pts.npy", stats=persistri.Stats())
    with pytest.raises(ValueError, match=r"^a progress callback follows the one-process run"):
        persistri.ConvexHull(pts, workers=1, progress=print)
    with pytest.raises(ValueError, match=r"^give a client, a worker count or a scheduler address, not several"):
        persistri.ConvexHull(pts, client=object(), workers=2)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"^client must be a distributed.Client, not object"):
        persistri.ConvexHull(pts, client=object())  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"^workers must be a whole number of at least 1, got 0"):
        persistri.ConvexHull(pts, workers=0)
    with pytest.raises(FileNotFoundError):
        persistri.ConvexHull(tmp_path / "missing.npy")
    np.save(tmp_path / "flat.npy", np.zeros((4, 2)))
    with pytest.raises(ValueError, match=r"flat\.npy: points must be an \(n, 3\) array, got shape \(4, 2\)"):
        persistri.ConvexHull(str(tmp_path / "flat.npy"))
    bad = pts.copy()
    bad[200, 1] = np.nan
    np.save(tmp_path / "bad.npy", bad)
    with pytest.raises(ValueError, match=r"bad\.npy: row 200 is not finite"):
        persistri.ConvexHull(tmp_path / "bad.npy", chunk_rows=64, workers=1)


# --- add_points: the final merge resumed ---------------------------------------------------------------


def test_add_points_is_the_one_process_extension(tmp_path: Path) -> None:
    """New points on the hull's faces and edges, inside, equal to old rows (vertices or not), to each other."""
    pts = degenerate(8)
    np.save(tmp_path / "pts.npy", pts)
    grid = np.array([[x, y, z] for x in range(5) for y in range(5) for z in range(5)], dtype=np.float64)
    new = np.array(
        [[2, 2, 2], [0, 0, 0], [2, 2, 7], [2, 2, 7], [1, 1, 6], [4, 4, 5], [0, 2, 4], [2, 0, 3.5], [6, 6, 6], [4, 4, 6]],
        dtype=np.float64,
    )
    for seed in (0, 1):
        one = persistri.ConvexHull(pts, seed=seed, history=True)
        got = persistri.ConvexHull(tmp_path / "pts.npy", chunk_rows=60, workers=1, seed=seed, history=True)
        before = got.simplices.copy()
        a, b = one.add_points(new), got.add_points(new)
        assert np.array_equal(got.simplices, before)  # the old hull is unchanged
        assert_same_extension(b, a)
        old_rows = {tuple(p): i for i, p in reversed(list(enumerate(pts.tolist())))}  # each point's first row
        for j, p in enumerate(new.tolist()):  # merged into the first old row, else into the first new one
            first = old_rows.get(tuple(p), len(pts) + new.tolist().index(p))
            assert (first == len(pts) + j) != ([len(pts) + j, first] in b.duplicates.tolist()), p
        assert len(b.duplicates) - len(got.duplicates) >= 4  # [2,2,2], [0,0,0], [4,4,5] old; [2,2,7] twice
        history = b.history
        assert history is not None and got.history is not None
        assert history[: len(got.history)] == tuple(got.history)  # the old versions, the same objects
        # The last version is the bulldozer's, before sliver flips (as in one process): the same vertices.
        assert np.array_equal(history.vertices(len(history) - 1), b.vertices)
        assert_same_extension(b.add_points(grid + 0.5), a.add_points(grid + 0.5))  # a chain of them


def assert_same_extension(got: persistri.ConvexHull, want: persistri.ConvexHull) -> None:
    for name in ("vertices", "simplices", "duplicates", "equations", "vertex_points"):
        assert np.array_equal(getattr(got, name), getattr(want, name)), name
    assert (got.npoints, got.volume, got.area) == (want.npoints, want.volume, want.area)
    assert np.array_equal(got.points, want.points)


@given(
    coords=st.lists(st.tuples(*[st.integers(0, 3)] * 3), min_size=4, max_size=60),
    more=st.lists(st.tuples(*[st.integers(-1, 4)] * 3), min_size=1, max_size=25),
    chunk_rows=st.integers(1, 30),
)
def test_add_points_on_integer_grids(coords: list[tuple[int, int, int]], more: list[tuple[int, int, int]], chunk_rows: int) -> None:
    pts, new = np.array(coords, dtype=np.float64), np.array(more, dtype=np.float64)
    try:
        want = persistri.ConvexHull(pts).add_points(new)
    except DegenerateInputError:
        return  # no hull to extend (the chunked path's same error is tested in test_scale_hull.py)
    assert_same_extension(persistri.ConvexHull(pts, workers=1, chunk_rows=chunk_rows).add_points(new), want)


# --- on two worker processes --------------------------------------------------------------------------


def test_every_input_on_two_workers_is_the_one_process_hull(client: Client, tmp_path: Path) -> None:
    pts = degenerate(6)
    want = persistri.ConvexHull(pts)
    for kind, given in inputs(pts, tmp_path).items():
        got = persistri.ConvexHull(given, client=client, chunk_rows=60)
        assert got.chunked is not None and got.chunked.workers == 2, kind
        assert_same_hull(got, want)


def test_an_array_with_a_client_and_the_scheduler_from_the_environment(
    client: Client, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pts = np.random.default_rng(7).normal(size=(3000, 3))
    want = persistri.ConvexHull(pts)
    assert_same_hull(persistri.ConvexHull(pts, client=client, chunk_rows=1000, check=True), want)
    # No option but more than one chunk: on the cluster PERSISTRI_SCHEDULER names, as `persistri hull` does.
    monkeypatch.setenv(ENV_SCHEDULER, str(client.scheduler_info()["address"]))
    np.save(tmp_path / "pts.npy", pts)
    got = persistri.ConvexHull(tmp_path / "pts.npy", chunk_rows=1000)
    assert got.chunked is not None and got.chunked.workers == 2 and len(got.chunked.chunks) == 3
    assert_same_hull(got, want)
