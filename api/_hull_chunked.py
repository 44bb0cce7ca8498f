"""Inputs too big to load, for ``persistri.ConvexHull``: which inputs are read chunk by chunk, where they run,
and how their points are read back when asked for.

A Dask array, a Zarr array, or the path of a ``.npy`` file, of a directory of
``.npy`` files or of a Zarr store is hulled chunk by chunk by
:func:`persistri.impl.scale.hull.parallel_hull`, in this process or on a Dask
cluster, as ``persistri hull`` decides (:func:`~persistri.impl.scale.cluster.plan`).
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from persistri._arrays import read_only
from persistri.impl.hull.api import HullHistory

if TYPE_CHECKING:
    from distributed import Client

    from persistri.impl.scale.hull import ParallelHull
    from persistri.impl.scale.sources import PointSource

__all__ = ["too_big_to_load", "chunked_hull", "read_all", "whole_input_history"]

FloatArray = NDArray[np.float64]


def too_big_to_load(points: object) -> bool:
    """Whether ``points`` is read chunk by chunk: a path, a Dask or Zarr array, or a chunked source."""
    if isinstance(points, (str, os.PathLike)):
        return True
    module = type(points).__module__
    return module.split(".")[0] in ("dask", "zarr") or module == "persistri.impl.scale.sources"


def chunked_hull(
    points: Any,
    *,
    client: Client | None,
    workers: int | None,
    scheduler: str | None,
    chunk_rows: int | None,
    seed: int,
    backend: str,
    history: bool,
    check: bool,
    progress: bool,
) -> ParallelHull:
    """:func:`~persistri.impl.scale.hull.parallel_hull` of ``points`` where ``persistri hull`` would run it.

    O(chunks) here before the run (the headers are read to count the rows); Dask is imported only
    when a cluster is used.
    """
    from persistri.impl.scale import dask_missing
    from persistri.impl.scale.cluster import connect, plan
    from persistri.impl.scale.hull import MAX_CHUNK_ROWS, parallel_hull
    from persistri.impl.scale.sources import points_source

    options: dict[str, Any] = {"chunk_rows": chunk_rows, "seed": seed, "backend": backend, "history": history, "check": check, "progress": progress}
    if client is not None:
        if workers is not None or scheduler is not None:
            raise ValueError("give a client, a worker count or a scheduler address, not several")
        if not type(client).__module__.startswith("distributed"):
            raise TypeError(f"client must be a distributed.Client, not {type(client).__name__}")
        return parallel_hull(points, client=client, **options)
    # As `persistri hull`: a cluster by default only for more than one chunk (one process is as fast below).
    n = points_source(points, chunk_rows).n  # headers only; a bad file or shape is its one-line error here
    tasks = max(1, -(-n // (chunk_rows or MAX_CHUNK_ROWS)))
    if plan(workers, scheduler, tasks=tasks)[0] != "sequential" and (why := dask_missing()) is not None:
        if workers is not None or scheduler is not None:
            raise ModuleNotFoundError(why)
        workers = 1  # the default only: without the extra, in this process
    with connect(workers, scheduler, tasks=tasks) as here:
        return parallel_hull(points, client=here, **options)


def read_all(source: PointSource) -> FloatArray:
    """Every row of ``source`` as one read-only float64 array: a float64 ``.npy`` file memory-mapped, else read. O(n)."""
    from persistri.impl.scale.sources import NpyRows, read_block

    files = {b.data.path for b in source.blocks if isinstance(b.data, NpyRows)}
    if len(files) == 1 and all(isinstance(b.data, NpyRows) for b in source.blocks):
        mapped = np.load(files.pop(), mmap_mode="r", allow_pickle=False)
        if mapped.dtype == np.float64 and mapped.shape == (source.n, 3):
            out: FloatArray = mapped  # validated block by block when the hull was computed
            return out
    parts = []
    for b in source.blocks:
        data = b.data.compute(scheduler="synchronous") if type(b.data).__module__.startswith("dask") else b.data
        parts.append(read_block(data, b.start, source.what))
    return read_only(np.concatenate(parts) if parts else np.zeros((0, 3)))


def whole_input_history(result: ParallelHull) -> HullHistory | None:
    """The final merge's versions (if kept), its labels renamed to rows of the whole input; the versions are
    shared, not copied.  O(candidates + insertions)."""
    h = result.hull.history
    if h is None:
        return None
    return HullHistory(h.structure, result.rows[h.rows].astype(np.intp), h.versions, tuple(int(result.rows[i]) for i in h.inserted))
