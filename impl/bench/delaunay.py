"""The scattered Delaunay benchmark (``persistri bench delaunay``): persistri against scipy.spatial.Delaunay, in the same run.

For each size ``n``, ``n`` points uniform in the unit square (numpy's PCG64 from
``seed``) are triangulated by

* **scipy** — :class:`scipy.spatial.Delaunay` (Qhull, C, floating point; the
  triangulation of the lifted points' lower hull), best of ``max(3, repeat)``;
* **persistri** — :func:`persistri.impl.terrain.scattered.delaunay` (exact
  predicates, BRIO order, walking location, every insertion a persistent
  version), best of ``repeat``;

and the ratio of their CPU times (``process_time``: both are single-threaded)
is printed with the triangle counts (equal for points in general position).
The points are generated before either is timed.  A benchmark, not a test.
"""

from __future__ import annotations

import gc
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any, Final

import numpy as np

__all__ = [
    "DEFAULT_DELAUNAY_SIZES", "DelaunayRecord", "DelaunayBench", "run_delaunay_bench", "delaunay_table", "terrain_build",
]

DEFAULT_DELAUNAY_SIZES: Final[tuple[int, ...]] = (10_000, 100_000)
"""The sizes of issue 17's rows."""

ProgressCallback = Callable[[int, int, str], None]


@dataclass(frozen=True, slots=True)
class DelaunayRecord:
    """One size: both times and both triangle counts."""

    n: int
    scipy_s: float
    persistri_s: float
    scipy_triangles: int
    persistri_triangles: int

    @property
    def time_ratio(self) -> float:
        """persistri's time over scipy's."""
        return self.persistri_s / self.scipy_s if self.scipy_s > 0 else float("inf")


@dataclass
class DelaunayBench:
    """The whole benchmark: what was measured and how."""

    seed: int
    backend: str
    repeat: int
    records: list[DelaunayRecord] = field(default_factory=list)
    build: str = field(default_factory=lambda: terrain_build())

    def as_dict(self) -> dict[str, Any]:
        """A JSON-ready dictionary (ratios included)."""
        return {
            "build": self.build,
            "seed": self.seed,
            "backend": self.backend,
            "repeat": self.repeat,
            "records": [dict(asdict(r), time_ratio=r.time_ratio) for r in self.records],
        }


def terrain_build() -> str:
    """Which build of the modules a 2D run goes through is running: ``"interpreted"``, or ``"compiled twin (…
    by mypyc)"`` naming those of them imported as extension modules (``tools/compiled_twin.py``): the 2D kernel
    and the triangulator's modules, and the persistent structures' inner modules, which the twin compiles for
    the hull and a terrain run spends a third of its time in."""
    from persistri.impl.complex import replace, vertex_changes, vertex_lists
    from persistri.impl.geometry import kernel2d
    from persistri.impl.maps import red_black_adjust, red_black_tree
    from persistri.impl.terrain import cavity, greedy_run, plane_errors, sectors
    from persistri.impl.terrain import delaunay as triangulator

    mods = (
        kernel2d, triangulator, cavity, sectors, greedy_run, plane_errors,
        red_black_tree, red_black_adjust, replace, vertex_lists, vertex_changes,
    )
    compiled = [m.__name__.rsplit(".", 1)[1] for m in mods if not str(m.__file__).endswith(".py")]
    return f"compiled twin ({', '.join(compiled)} by mypyc)" if compiled else "interpreted"


def _best(run: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    best = float("inf")
    out: Any = None
    for _ in range(repeat):
        out = None
        gc.collect()
        t0 = time.process_time()
        out = run()
        best = min(best, time.process_time() - t0)
    return best, out


def run_delaunay_bench(
    sizes: Sequence[int] = DEFAULT_DELAUNAY_SIZES,
    *,
    seed: int = 0,
    backend: str = "int_trie",
    repeat: int = 1,
    on_progress: ProgressCallback | None = None,
) -> DelaunayBench:
    """Run the benchmark (module docstring) at ``sizes`` points."""
    from scipy.spatial import Delaunay

    from persistri.impl.terrain.scattered import delaunay

    sizes = sorted({int(s) for s in sizes})
    if not sizes or sizes[0] < 3:
        raise ValueError("sizes must be point counts of at least 3")
    bench = DelaunayBench(seed, backend, repeat)
    steps = 2 * len(sizes)
    for i, n in enumerate(sizes):
        pts = np.random.default_rng(seed).random((n, 2))
        if on_progress is not None:
            on_progress(2 * i, steps, f"scipy, {n:,} points")
        s_time, tri = _best(lambda: Delaunay(pts), max(3, repeat))
        s_count = int(tri.simplices.shape[0])
        del tri
        if on_progress is not None:
            on_progress(2 * i + 1, steps, f"persistri, {n:,} points")
        o_time, ours = _best(lambda: delaunay(pts, backend=backend, seed=seed), repeat)
        o_count = int(ours.triangles.shape[0])
        del ours
        bench.records.append(DelaunayRecord(n, s_time, o_time, s_count, o_count))
    if on_progress is not None:
        on_progress(steps, steps, "done")
    return bench


def delaunay_table(bench: DelaunayBench) -> Any:
    """The benchmark as a rich renderable; its title names the build that ran (:func:`terrain_build`)."""
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    table = Table(title=f"Scattered Delaunay, uniform points in the unit square (seed {bench.seed}; persistri {bench.build})")
    for name in ("points", "scipy s", "persistri s", "time ×", "scipy triangles", "persistri triangles"):
        table.add_column(name, justify="right")
    for r in bench.records:
        table.add_row(
            f"{r.n:,}",
            f"{r.scipy_s:.3f}",
            f"{r.persistri_s:.2f}",
            f"{r.time_ratio:,.1f}×",
            f"{r.scipy_triangles:,}",
            f"{r.persistri_triangles:,}",
        )
    note = Text(
        "times: CPU seconds, best of the repeats (scipy at least 3); scipy.spatial.Delaunay is Qhull in floating point; "
        f"persistri exact, every insertion a persistent version ({bench.backend} backend)."
    )
    return Group(table, note)
