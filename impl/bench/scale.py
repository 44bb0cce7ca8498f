"""``persistri bench scale``: the parallel hull (and tiled terrain) on local clusters of 1 and 2 workers.

What it measures, on this machine, in one run:

* **the hull** of ``n`` points of a §4 distribution (4M InBall points by
  default), written once to a ``.npy`` that every run reads memory-mapped:
  first :func:`~persistri.impl.hull.api.convex_hull` of all of them as one task
  in a one-worker cluster ("one process": the sequential algorithm, its memory
  measured in a process of its own), then
  :func:`~persistri.impl.scale.hull.parallel_hull` on fresh local clusters of
  1 and 2 worker processes.  Per run: the wall time (cluster start-up
  excluded, the workers' imports done before the clock), the speed-up over the
  one-process run, each worker's peak resident memory (``VmHWM`` in the
  worker, reset after importing persistri: :func:`reset_peak_rss`; the
  resident memory at that moment beside it),
  and the points that reached the final run.  Every parallel result is compared
  with the one-process hull, exactly (vertices, triangles, duplicates).
* **the tiled terrain** rows, from :func:`persistri.impl.scale.terrain_bench.bench_rows`
  (a synthetic 8,000 × 8,000 DEM by default), when that module is present.

Timings are wall-clock, from one run each: they say what this machine did,
not a law (the suite never checks a time).
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from persistri.impl.scale.terrain_bench import TerrainRow

__all__ = [
    "DEFAULT_POINTS", "RunRow", "HullRow", "hull_rows", "worker_cpu", "reset_peak_rss", "worker_peak_rss", "hull_table", "terrain_table",
    "terrain_available",
]

DEFAULT_POINTS: Final = 4_000_000
"""The hull the issue asks about: 4M points."""


@dataclass(frozen=True)
class RunRow:
    """What every measured run of ``persistri bench scale`` reports, hull or tiled terrain.

    ``label`` names the run; ``workers`` is 0 for the one-process run; ``seconds`` wall
    time; ``speedup`` the reference run's time over this one; ``baseline``/``peak`` each
    worker's peak resident memory in bytes after importing persistri / after the run.
    """

    label: str
    workers: int
    seconds: float
    speedup: float
    baseline: tuple[int, ...]
    peak: tuple[int, ...]


@dataclass(frozen=True)
class HullRow(RunRow):
    """One measured hull run (:class:`RunRow`, the one-process run the reference), and:
    ``chunks`` and ``candidates`` (the points that reached the final run; all ``n`` for one process);
    ``faces``, ``vertices``; ``same`` whether the hull equals the one-process hull exactly;
    ``cpu`` the CPU seconds each worker spent in the run and ``client_cpu`` this process's (the
    final run happens here): less sensitive than the wall time to other load on the machine;
    ``filtered`` the points the interior filter dropped before the chunk hulls
    (:mod:`persistri.impl.scale.prefilter`; 0 for one process).
    """

    chunks: int
    candidates: int
    faces: int
    vertices: int
    same: bool
    cpu: tuple[float, ...] = ()
    client_cpu: float = 0.0
    filtered: int = 0


def worker_cpu() -> float:
    """The CPU seconds (user and system) this process has used so far (``Client.run`` calls it in each worker)."""
    import resource

    r = resource.getrusage(resource.RUSAGE_SELF)
    return float(r.ru_utime + r.ru_stime)


def reset_peak_rss() -> None:
    """Reset this process's peak resident memory to its current one, where Linux allows it (``clear_refs``, 4.0+).

    A worker process starts with the high-water mark of the process it was forked from (``ru_maxrss`` survives
    ``fork`` and ``exec``): without the reset, a client that has just written a 512 MB DEM gives every worker a
    "peak" of 512 MB before it has done anything.  Elsewhere nothing happens (the figure is then an upper bound).
    """
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
    except OSError:
        pass


def worker_peak_rss() -> int:
    """The peak resident memory of this process since :func:`reset_peak_rss`, in bytes (``Client.run`` calls it
    in each worker): ``VmHWM`` on Linux, else ``ru_maxrss`` (the peak since the process began)."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024  # kB
    except OSError:
        pass
    import resource

    return int(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss) * 1024  # KiB on Linux


def _warm() -> None:
    """Import what the hull tasks import, before the clock and the baseline."""
    import persistri.impl.hull.api  # noqa: F401
    import persistri.impl.scale.hull  # noqa: F401


def _one_process(path: str, seed: int, backend: str) -> tuple[NDArray[np.intp], NDArray[np.intp], tuple[tuple[int, int], ...], float]:
    """The task of the one-process row: ``convex_hull`` of the whole file, and the seconds it took."""
    from persistri.impl.hull.api import convex_hull

    pts = np.load(path)
    start = time.perf_counter()
    h = convex_hull(pts, seed=seed, backend=backend)
    return h.simplices, h.vertices, h.duplicates, time.perf_counter() - start


def _cluster(n: int) -> Any:
    from distributed import LocalCluster

    # memory_limit=0: no worker is paused or restarted for its memory, so its peak is the algorithm's.
    return LocalCluster(
        n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
        dashboard_address=":0", scheduler_kwargs={"dashboard": False}, memory_limit=0,
    )


def hull_rows(
    directory: str | Path,
    *,
    n: int = DEFAULT_POINTS,
    dist: str = "InBall",
    seed: int = 0,
    chunk_rows: int | None = None,
    workers: Sequence[int] = (1, 2),
    backend: str = "red_black",
    progress: Callable[[str], Any] | None = None,
) -> list[HullRow]:
    """Measure the hull of ``n`` points of ``dist`` (module docstring); the points file is kept in ``directory``.

    ``progress`` is called with a line before each run.  Raises ``ValueError`` for an
    unknown distribution or a worker count below 1.
    """
    from distributed import Client

    from persistri.impl.hull.distributions import generate
    from persistri.impl.scale.hull import parallel_hull

    if any(w < 1 for w in workers):
        raise ValueError(f"worker counts must be at least 1, got {tuple(workers)}")
    folder = Path(directory)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{dist.lower()}-{n}-{seed}.npy"
    if not path.exists():
        np.save(path, generate(dist, n, seed))
    say = progress or (lambda line: None)
    rows: list[HullRow] = []

    say(f"one process: convex_hull of {n:,} {dist} points")
    with _cluster(1) as lc, Client(lc) as client:
        client.run(_warm)
        client.run(reset_peak_rss)
        base = client.run(worker_peak_rss)
        cpu0 = client.run(worker_cpu)
        start, mine = time.perf_counter(), time.process_time()
        simplices, vertices, duplicates, _ = client.submit(_one_process, str(path), seed, backend, pure=False).result()
        seconds, mine = time.perf_counter() - start, time.process_time() - mine
        peak = client.run(worker_peak_rss)
        cpu = tuple(v - cpu0[k] for k, v in client.run(worker_cpu).items())
    one = seconds
    rows.append(HullRow("one process", 0, seconds, 1.0, tuple(base.values()), tuple(peak.values()), 1, n,
                        len(simplices), len(vertices), True, cpu, mine))
    for w in workers:
        say(f"{w} worker{'s' if w != 1 else ''}: parallel_hull of the same file")
        with _cluster(w) as lc, Client(lc) as client:
            client.run(_warm)
            client.run(reset_peak_rss)
            base = client.run(worker_peak_rss)
            cpu0 = client.run(worker_cpu)
            start, mine = time.perf_counter(), time.process_time()
            got = parallel_hull(str(path), client=client, chunk_rows=chunk_rows, seed=seed, backend=backend)
            seconds, mine = time.perf_counter() - start, time.process_time() - mine
            peak = client.run(worker_peak_rss)
            cpu = tuple(v - cpu0[k] for k, v in client.run(worker_cpu).items())
        same = (np.array_equal(got.simplices, simplices) and np.array_equal(got.vertices, vertices)
                and got.duplicates == duplicates)
        rows.append(HullRow(f"{w} worker{'s' if w != 1 else ''}", w, seconds, one / seconds, tuple(base.values()),
                            tuple(peak.values()), len(got.chunks), got.candidates, len(got.simplices),
                            len(got.vertices), same, cpu, mine, sum(c.filtered for c in got.chunks)))
    return rows


def _mib(values: Sequence[int]) -> str:
    return " / ".join(f"{v / 2**20:,.0f}" for v in values)


def hull_table(rows: Sequence[HullRow], title: str) -> Any:
    """The hull rows as a rich table."""
    from rich.table import Table

    table = Table(title=title)
    for name, justify in [("run", "left"), ("seconds", "right"), ("speed-up", "right"), ("CPU s per worker", "right"), ("client CPU s", "right"),
                          ("peak RSS per worker, MiB", "right"),
                          ("after imports, MiB", "right"), ("chunks", "right"), ("filtered", "right"), ("final run points", "right"),
                          ("faces", "right"), ("same hull", "left")]:
        table.add_column(name, justify=justify)  # type: ignore[arg-type]
    for r in rows:
        table.add_row(r.label, f"{r.seconds:.1f}", f"{r.speedup:.2f}×", " / ".join(f"{c:.1f}" for c in r.cpu), f"{r.client_cpu:.1f}", _mib(r.peak), _mib(r.baseline), f"{r.chunks:,}",
                      f"{r.filtered:,}", f"{r.candidates:,}", f"{r.faces:,}", "yes" if r.same else "NO")
    return table


def terrain_table(rows: Sequence[TerrainRow], same: bool, title: str) -> Any:
    """The tiled-terrain rows (:class:`persistri.impl.scale.terrain_bench.TerrainRow`) as a rich table."""
    from rich.table import Table

    table = Table(title=title, caption=f"one process and two workers give identical meshes: {'yes' if same else 'NO'}")
    for name in ("run", "seconds", "speed-up", "peak RSS per worker, MiB", "after imports, MiB", "points", "triangles", "max error"):
        table.add_column(name, justify="left" if name == "run" else "right")
    for r in rows:
        table.add_row(r.label, f"{r.seconds:.1f}", f"{r.speedup:.2f}×", _mib(r.peak), _mib(r.baseline), f"{r.points:,}",
                      f"{r.triangles:,}", f"{r.max_error:.3g}")
    return table


def terrain_available() -> bool:
    """Whether the tiled-terrain side (:mod:`persistri.impl.scale.terrain_bench`) is installed."""
    from importlib.util import find_spec

    return find_spec("persistri.impl.scale.terrain_bench") is not None
