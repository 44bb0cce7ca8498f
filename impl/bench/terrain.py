"""The terrain benchmark (``persistri bench terrain``): greedy insertion against pydelatin, in the same run.

On the Jacksboro DEM (344 × 403 samples) at 1,600 / 3,200 / 6,400 / 12,800
points (paper §5, Fig. 11; issue item 8):

* **pydelatin** (``Delatin(heights, max_points=k, max_error=0)``, the C++ ``hmm``
  triangulator: greedy insertion with Delaunay flips in floating point) — its time
  (best of ``repeat``, at least 3) and its vertex count;
* **persistri** run *to pydelatin's vertex count* — its time (a fresh run per
  size, best of ``repeat``) and the time ratio;
* the **maximum error** of both meshes, each recomputed independently over
  every grid sample, both the same way (:func:`persistri.impl.bench.terrain_sweep.max_error`:
  pydelatin's rows flipped back — its ``y`` is ``rows − 1 − row`` — and each vertex
  at the grid's own height);
* persistri's **best level within the budget**: the smallest maximum error among
  the kept levels of detail with at most that many points — free to read from the
  history.  The maximum error of greedy insertion is not monotone in the number
  of points (an insertion can make a long triangle across a ridge, which the next
  insertions repair): on Jacksboro about a quarter of the levels are more than
  10 % above the best level before them, for pydelatin as for persistri, so the
  error *at* one vertex count is partly luck;
* the **sweep** (``sweep`` counts, log-spaced from the smallest size to the
  largest; :mod:`persistri.impl.bench.terrain_sweep`): the distribution of the
  error ratio over many vertex counts — its median and quartiles, and the shares
  of counts where persistri's mesh is better, equal or worse — for the level at
  the count and for the best level within it.  This, not the ratio at one count,
  is what says whether one rule is better than the other;
* the **operation counts** of the paper's Fig. 11 — key comparisons, dictionary
  operations, plane-side (orient2d / incircle) tests and their flops — from one
  counted run to the largest size, read at each size (the run is deterministic,
  so the counts at ``k`` points are those of a run stopped there);
* with ``memory=True``, the memory **kept** by a run that keeps every level of
  detail against one that keeps only the final mesh (``tracemalloc``: memory
  still allocated while the result is alive, and the peak), and the size of the
  final mesh's arrays alone.

Timings are CPU seconds of the call (``process_time``: both are single-threaded,
and CPU time is steadier than wall-clock time on a shared machine), with the
grid already in memory: a benchmark, not a test.
"""

from __future__ import annotations

import gc
import time
import tracemalloc
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from persistri.impl.bench.terrain_sweep import ErrorSweep, error_sweep, max_error, pydelatin_mesh, sweep_counts
from persistri.impl.stats import Stats

__all__ = [
    "DEFAULT_TERRAIN_SIZES",
    "DEFAULT_SWEEP",
    "TerrainRecord",
    "TerrainMemory",
    "TerrainBench",
    "run_terrain_bench",
    "terrain_table",
]

DEFAULT_TERRAIN_SIZES: tuple[int, ...] = (1_600, 3_200, 6_400, 12_800)
"""The vertex counts of the issue's table."""

DEFAULT_SWEEP = 24
"""Vertex counts of the error sweep, log-spaced from the smallest size to the largest (0: no sweep)."""

ProgressCallback = Callable[[int, int, str], None]


@dataclass(frozen=True, slots=True)
class TerrainRecord:
    """One size: pydelatin's and persistri's time and maximum error at the same vertex count, and the counts."""

    target: int
    points: int
    pydelatin_s: float
    persistri_s: float
    pydelatin_error: float
    persistri_error: float
    persistri_best_error: float
    key_comparisons: int
    dict_ops: int
    plane_side_tests: int
    flops: int

    @property
    def time_ratio(self) -> float:
        """persistri's time over pydelatin's."""
        return self.persistri_s / self.pydelatin_s if self.pydelatin_s > 0 else float("inf")

    @property
    def error_ratio(self) -> float:
        """persistri's maximum error over pydelatin's at this one count (issue 17's target is ≤ 1.00; one count is
        partly luck: read the sweep, :mod:`persistri.impl.bench.terrain_sweep`)."""
        return self.persistri_error / self.pydelatin_error if self.pydelatin_error > 0 else float("nan")


@dataclass(frozen=True, slots=True)
class TerrainMemory:
    """Memory of one run to ``points`` vertices, in bytes (tracemalloc)."""

    points: int
    history_kept: int
    history_peak: int
    final_only_kept: int
    final_only_peak: int
    final_arrays: int
    versions: int


@dataclass
class TerrainBench:
    """The whole benchmark: what was measured and how."""

    grid: str
    shape: tuple[int, int]
    backend: str
    repeat: int
    records: list[TerrainRecord] = field(default_factory=list)
    memory: TerrainMemory | None = None
    sweep: ErrorSweep | None = None

    def as_dict(self) -> dict[str, Any]:
        """A JSON-ready dictionary (ratios included)."""
        out: dict[str, Any] = {
            "grid": self.grid,
            "shape": list(self.shape),
            "backend": self.backend,
            "repeat": self.repeat,
            "records": [dict(asdict(r), time_ratio=r.time_ratio, error_ratio=r.error_ratio) for r in self.records],
        }
        if self.memory is not None:
            out["memory"] = asdict(self.memory)
        if self.sweep is not None:
            out["sweep"] = self.sweep.as_dict()
        return out


def _pydelatin(heights: NDArray[np.float64], k: int, repeat: int) -> tuple[float, int, float]:
    """(best time, vertex count, maximum error recomputed) of pydelatin refined to ``k`` points."""
    from pydelatin import Delatin

    h32 = heights.astype(np.float32)
    best = float("inf")
    for _ in range(max(3, repeat)):
        t0 = time.process_time()
        Delatin(h32, max_points=k, max_error=0.0)
        best = min(best, time.process_time() - t0)
    xy, tri = pydelatin_mesh(heights, k)  # the same (deterministic) mesh, read in grid coordinates
    return best, int(xy.shape[0]), max_error(heights, xy, tri)


def _ours(heights: NDArray[np.float64], k: int, backend: str, repeat: int) -> tuple[float, float, int]:
    """(best time, maximum error recomputed, vertex count) of persistri's greedy insertion to ``k`` points."""
    from persistri.impl.terrain.greedy import greedy_insertion

    best = float("inf")
    tin: Any = None
    for _ in range(repeat):
        tin = None
        gc.collect()
        t0 = time.process_time()
        tin = greedy_insertion(heights, max_points=k, backend=backend)
        best = min(best, time.process_time() - t0)
    return best, max_error(heights, tin.vertices, tin.triangles), int(tin.n_points)


def _counts(heights: NDArray[np.float64], sizes: Sequence[int], backend: str) -> tuple[dict[int, Stats], Any]:
    """The Stats of one counted run, read when the mesh reaches each of ``sizes`` vertices, and its history."""
    from persistri.impl.terrain.greedy import greedy_insertion

    stats = Stats()
    wanted = set(sizes)
    seen: dict[int, Stats] = {}
    count = [4]

    def tick(k: int) -> None:
        count[0] += k
        if count[0] in wanted:
            snap = Stats()
            snap += stats
            seen[count[0]] = snap

    tin = greedy_insertion(heights, max_points=max(sizes), backend=backend, stats=stats, progress=tick)
    assert tin.history is not None
    return seen, tin.history


def _memory(heights: NDArray[np.float64], k: int, backend: str) -> TerrainMemory:
    from persistri.impl.terrain.greedy import greedy_insertion

    def measure(keep: bool) -> tuple[int, int, Any]:
        gc.collect()
        tracemalloc.start()
        try:
            base = tracemalloc.get_traced_memory()[0]
            tin = greedy_insertion(heights, max_points=k, backend=backend, history=keep)
            gc.collect()
            kept, peak = tracemalloc.get_traced_memory()
        finally:
            tracemalloc.stop()
        return kept - base, peak - base, tin

    kept_all, peak_all, tin = measure(True)
    versions = len(tin.history) if tin.history is not None else 1
    del tin
    kept_one, peak_one, tin = measure(False)
    arrays = int(tin.vertices.nbytes + tin.triangles.nbytes + tin.samples.nbytes)
    return TerrainMemory(k, kept_all, peak_all, kept_one, peak_one, arrays, versions)


def run_terrain_bench(
    sizes: Sequence[int] = DEFAULT_TERRAIN_SIZES,
    *,
    heights: NDArray[np.float64] | None = None,
    grid_name: str = "jacksboro",
    backend: str = "red_black",
    repeat: int = 1,
    memory: bool = False,
    sweep: int = DEFAULT_SWEEP,
    on_progress: ProgressCallback | None = None,
) -> TerrainBench:
    """Run the benchmark (module docstring) on ``heights`` (default: the Jacksboro DEM) at ``sizes`` points;
    ``sweep`` vertex counts from the smallest size to the largest for the error sweep (0: none)."""
    from persistri.impl.terrain.grids import as_heights, jacksboro

    if heights is None:
        heights = jacksboro().heights
        grid_name = "jacksboro"
    h = as_heights(heights, what=grid_name)
    sizes = sorted({int(s) for s in sizes})
    if not sizes or sizes[0] < 4:
        raise ValueError("sizes must be vertex counts of at least 4")
    if sweep < 0:
        raise ValueError(f"sweep must be a number of vertex counts >= 0, got {sweep}")
    bench = TerrainBench(grid_name, (int(h.shape[0]), int(h.shape[1])), backend, repeat)
    steps = 2 * len(sizes) + 1 + (1 if memory else 0) + (1 if sweep else 0)
    done = 0

    def report(what: str) -> None:
        if on_progress is not None:
            on_progress(done, steps, what)

    measured: list[tuple[int, int, float, float, float, float]] = []
    for k in sizes:
        report(f"pydelatin to {k:,} points")
        p_time, p_points, p_err = _pydelatin(h, k, repeat)
        done += 1
        report(f"persistri to {p_points:,} points")
        o_time, o_err, o_points = _ours(h, p_points, backend, repeat)
        done += 1
        measured.append((k, o_points, p_time, o_time, p_err, o_err))
    report("operation counts")
    counts, history = _counts(h, [m[1] for m in measured], backend)
    levels = np.asarray(history.max_errors)
    done += 1
    for k, points, p_time, o_time, p_err, o_err in measured:
        st = counts.get(points, Stats())
        best = float(levels[: points - 3].min())  # levels 0 … points-4 have 4 … points vertices
        bench.records.append(
            TerrainRecord(
                k, points, p_time, o_time, p_err, o_err, best, st.key_comparisons, st.dict_ops, st.plane_side_tests, st.flops
            )
        )
    if sweep:
        ks = sweep_counts(sizes[0], sizes[-1], sweep)
        report(f"max error at {len(ks)} vertex counts")
        # persistri's run went to pydelatin's largest count: the sweep's counts beyond it are read at its end.
        bench.sweep = error_sweep(h, ks, history)
        done += 1
    del history
    if memory:
        report(f"memory at {measured[-1][1]:,} points")
        bench.memory = _memory(h, measured[-1][1], backend)
        done += 1
    report("done")
    return bench


def _millions(n: int) -> str:
    return f"{n / 1e6:.2f}M" if n >= 10_000 else f"{n:,}"


def _mb(n: int) -> str:
    return f"{n / 2**20:,.1f} MB"


def terrain_table(bench: TerrainBench) -> Any:
    """The benchmark as a rich renderable: the table and, when measured, the memory lines."""
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    from persistri.impl.bench.delaunay import terrain_build

    table = Table(
        title=f"Greedy insertion on {bench.grid} {bench.shape[0]}×{bench.shape[1]} ({bench.backend} backend; persistri {terrain_build()})"
    )
    for name in (
        "points",
        "pydelatin s",
        "persistri s",
        "time ×",
        "pydelatin err",
        "persistri err",
        "err ratio",
        "best ≤ k",
        "key comps",
        "tests",
        "flops",
    ):
        table.add_column(name, justify="right")
    for r in bench.records:
        table.add_row(
            f"{r.points:,}",
            f"{r.pydelatin_s:.3f}",
            f"{r.persistri_s:.2f}",
            f"{r.time_ratio:,.0f}×",
            f"{r.pydelatin_error:.4g}",
            f"{r.persistri_error:.4g}",
            f"{r.error_ratio:.3f}",
            f"{r.persistri_best_error:.4g}",
            _millions(r.key_comparisons),
            _millions(r.plane_side_tests),
            _millions(r.flops),
        )
    parts: list[Any] = [table]
    if bench.sweep is not None:
        parts.append(Text(bench.sweep.summary()))
    m = bench.memory
    if m is not None:
        parts.append(
            Text(
                f"memory at {m.points:,} points: every level of detail kept ({m.versions:,} versions) "
                f"{_mb(m.history_kept)} (peak {_mb(m.history_peak)}); final mesh only {_mb(m.final_only_kept)} "
                f"(peak {_mb(m.final_only_peak)}); the final mesh's arrays {_mb(m.final_arrays)}"
            )
        )
    parts.append(
        Text(
            "err: maximum vertical error, recomputed over every sample for both meshes; persistri run to "
            "pydelatin's vertex count; times in CPU seconds; best ≤ k: persistri's smallest maximum error among its kept levels of detail "
            "with at most k points; times best of the repeats (pydelatin at least 3); key comps, tests "
            "(plane-side: orient2d and incircle) and flops: persistri's operation counts (dictionary operations too in "
            "--json), with one replace per insertion (Fig. 11 counts the paper's rem and add per triangle: "
            "persistri experiments fig11)."
        )
    )
    return Group(*parts)
