"""Measuring tiled terrain: a synthetic DEM written in blocks, and the rows ``persistri bench scale`` prints.

:func:`write_bumps_dem` makes a deterministic ``size × size`` DEM larger than
one wants to hold — a sum of seeded Gaussian bumps — straight into a
memory-mapped ``.npy``, one block of rows at a time, so generating it never
holds more than a block either.  Each bump ``k`` has a centre, a width
``σ_k`` log-uniform between ``size/400`` and ``size/8`` and an amplitude
``∝ σ_k^0.8`` with a random sign (wide hills, small knolls: an fBm-like
spectrum); a bump is separable, ``exp(−(r−y_k)²/2σ²)·exp(−(c−x_k)²/2σ²)``, so
a block of rows is one matrix product over the bumps that reach it.  Heights are
rescaled to ``[0, relief]`` from the extremes of a first pass, in float64.

:func:`bench_rows` meshes such a DEM by tiles on local clusters of 1 and 2
worker processes and reports, per run, the wall time, the speed-up, and each
worker's peak resident memory (``VmHWM`` in the worker process, reset after
importing persistri, with the resident memory then beside it), and checks that a one-process run and a
two-worker run of a smaller DEM give identical arrays.  Not in the paper: the
measurements behind ``docs/scale-out.md``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from persistri.impl.bench.scale import RunRow

__all__ = ["BUMPS", "write_bumps_dem", "TerrainRow", "bench_rows", "worker_memory"]

BUMPS: Final = 4096
"""How many bumps :func:`write_bumps_dem` sums by default."""


def _bumps(size: int, seed: int, count: int) -> tuple[NDArray[np.float64], ...]:
    rng = np.random.default_rng(seed)
    y = rng.uniform(0, size - 1, count)
    x = rng.uniform(0, size - 1, count)
    sigma = np.exp(rng.uniform(np.log(size / 400.0), np.log(size / 8.0), count))
    amp = sigma**0.8 * rng.choice([-1.0, 1.0], count) * rng.uniform(0.5, 1.0, count)
    return y, x, sigma, amp


def _block(rows: NDArray[np.float64], cols: NDArray[np.float64], bumps: tuple[NDArray[np.float64], ...]) -> NDArray[np.float64]:
    y, x, sigma, amp = bumps
    lo, hi = rows[0], rows[-1]
    near = (y + 5 * sigma >= lo) & (y - 5 * sigma <= hi)  # the bumps that reach these rows (e^-12.5 beyond)
    ys, xs, ss, aa = y[near], x[near], sigma[near], amp[near]
    u = np.exp(-((rows[:, None] - ys[None, :]) ** 2) / (2 * ss**2)) * aa
    v = np.exp(-((cols[:, None] - xs[None, :]) ** 2) / (2 * ss**2))
    out: NDArray[np.float64] = u @ v.T
    return out


def write_bumps_dem(path: str | Path, size: int, *, seed: int = 0, bumps: int = BUMPS, relief: float = 1000.0,
                    block: int = 256) -> Path:
    """Write the ``size × size`` bumps DEM (module docstring) to the ``.npy`` file ``path``, ``block`` rows at a time.

    Deterministic for ``(size, seed, bumps, relief)``.  Memory: a block of rows and
    the bumps.  O(size² · bumps reaching a block) float work, in BLAS.
    """
    if size < 2:
        raise ValueError(f"a DEM needs a size of at least 2, got {size}")
    p = Path(path)
    params = _bumps(size, seed, bumps)
    cols = np.arange(size, dtype=np.float64)
    lo, hi = np.inf, -np.inf
    out = np.lib.format.open_memmap(p, mode="w+", dtype=np.float64, shape=(size, size))
    try:
        for r0 in range(0, size, block):
            rows = np.arange(r0, min(size, r0 + block), dtype=np.float64)
            z = _block(rows, cols, params)
            out[r0 : r0 + z.shape[0]] = z
            lo, hi = min(lo, float(z.min())), max(hi, float(z.max()))
        scale = relief / (hi - lo) if hi > lo else 0.0
        for r0 in range(0, size, block):
            part = out[r0 : r0 + block]
            part -= lo
            part *= scale
        out.flush()
    finally:
        del out
    return p


def worker_memory() -> int:
    """The peak resident memory of this process since the last reset, in bytes (run in a worker through
    ``Client.run``; :func:`persistri.impl.bench.scale.worker_peak_rss`)."""
    from persistri.impl.bench.scale import worker_peak_rss

    return worker_peak_rss()


@dataclass(frozen=True)
class TerrainRow(RunRow):
    """One measured run (:class:`~persistri.impl.bench.scale.RunRow`, the first row the reference) and the
    mesh: ``points``, ``triangles``, ``max_error``."""

    points: int
    triangles: int
    max_error: float


def bench_rows(
    directory: str | Path,
    *,
    size: int = 8000,
    tile: int = 1025,
    max_error: float = 1.0,
    workers: tuple[int, ...] = (1, 2),
    check_size: int = 1500,
    seed: int = 0,
) -> tuple[list[TerrainRow], bool]:
    """Measure tiled terrain on a ``size × size`` bumps DEM written to ``directory`` (module docstring).

    Returns the rows (one per entry of ``workers``: a fresh local cluster of that
    many worker processes, one thread each) and whether a one-process run and a
    two-worker run of a ``check_size`` DEM gave identical vertices, triangles and
    errors.  The DEM files are kept in ``directory`` (and reused when present).
    """
    from distributed import Client, LocalCluster

    from persistri.impl.bench.scale import reset_peak_rss
    from persistri.impl.scale.terrain import tiled_terrain

    folder = Path(directory)
    folder.mkdir(parents=True, exist_ok=True)
    dem = folder / f"bumps-{size}-{seed}.npy"
    if not dem.exists():
        write_bumps_dem(dem, size, seed=seed)
    rows: list[TerrainRow] = []
    first = 0.0

    def cluster(n: int) -> Any:
        return LocalCluster(n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
                            dashboard_address=":0", scheduler_kwargs={"dashboard": False}, memory_limit=0)

    for n in workers:
        with cluster(n) as lc, Client(lc) as client:
            client.run(_warm)  # import persistri in every worker before the clock
            client.run(reset_peak_rss)  # a worker inherits the high-water mark of the process that forked it
            base = client.run(worker_memory)
            start = time.perf_counter()
            tin = tiled_terrain(str(dem), max_error=max_error, tile=tile, client=client)
            seconds = time.perf_counter() - start
            mem = client.run(worker_memory)
        first = first or seconds
        rows.append(TerrainRow(
            label=f"{n} worker{'s' if n != 1 else ''}", workers=n, seconds=seconds, speedup=first / seconds,
            baseline=tuple(base.values()), peak=tuple(mem.values()),
            points=tin.n_points, triangles=len(tin.triangles), max_error=tin.max_error,
        ))
    small = folder / f"bumps-{check_size}-{seed}.npy"
    if not small.exists():
        write_bumps_dem(small, check_size, seed=seed)
    alone = tiled_terrain(str(small), max_error=max_error, tile=tile)
    with cluster(2) as lc, Client(lc) as client:
        shared = tiled_terrain(str(small), max_error=max_error, tile=tile, client=client)
    same = (np.array_equal(alone.vertices, shared.vertices) and np.array_equal(alone.triangles, shared.triangles)
            and (alone.max_error, alone.rms_error) == (shared.max_error, shared.rms_error))
    return rows, same


def _warm() -> None:
    """Import what a tile task imports (so that a worker's baseline memory and the clock exclude it)."""
    import persistri.impl.scale.terrain  # noqa: F401
