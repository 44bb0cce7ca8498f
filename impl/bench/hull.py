"""The hull benchmark (``persistri bench hull``): the bulldozer against Qhull, in the same run.

For each distribution of the paper's §4 (OnSphere, EqHeavy, PolHeavy, InBall,
BordHeavy; :mod:`persistri.impl.hull.distributions`) and each point count
``n`` (default 16K, 64K and 256K = 2^14, 2^16, 2^18 points, the same seeded
points for every subject):

* **Qhull** — :class:`scipy.spatial.ConvexHull` (floating point), best of
  3 runs, timed again right before *each* run of persistri;
* **persistri** — :func:`~persistri.impl.hull.api.convex_hull` (exact) on each
  requested ``ORD_MAP`` backend (``red_black`` by default), best of ``repeat``
  (the subjects take turns, run by run); its ratio to the Qhull time measured
  just before that best run, and its time per insertion.  Pairing each run with
  a Qhull time taken next to it keeps the ratio honest on a shared machine whose
  speed drifts over minutes (measured here: Qhull's best of 3 on the same 256K
  points ranged from 2.5 s to 5.7 s within an hour);
* the **ephemeral baseline** — the same bulldozer on the NOT persistent
  2-complex over a ``dict`` (:mod:`persistri.impl.complex.ephemeral`), and every
  backend's time over it: what persistence costs in this run;
* whether persistri's hull has Qhull's vertex set (it should on these inputs:
  random points in general position).

With ``memory=True`` it also measures, with ``tracemalloc``, the memory of a
run that keeps every intermediate hull (``history=True``: one complex version
per insertion, sharing structure): what the versions alone hold, per inserted
point, and what the whole run keeps against a run that keeps only the final
hull (:class:`HullMemory`; InBall, 16K points by default), on the first backend
of ``backends`` (``red_black`` if that is the ephemeral baseline, which keeps no
versions): ``backends=("red_black_arena", "red_black")`` measures the arena
backend, the one meant for keeping histories.

Times are CPU seconds of this process (``time.process_time``) with the cyclic
garbage collector off during each timed call (``convex_hull`` pauses it itself;
Qhull's call is timed the same way), so that other processes on a shared
machine inflate them less; it is a benchmark, not a test.
"""

from __future__ import annotations

import gc
import platform
import sys
import time
import tracemalloc
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "DEFAULT_HULL_SIZES",
    "DEFAULT_DISTS",
    "DEFAULT_MEMORY_N",
    "DEFAULT_MEMORY_DIST",
    "HullRecord",
    "HullTiming",
    "HullMemory",
    "HullBench",
    "run_hull_bench",
    "hull_table",
    "cpu_seconds",
    "persistri_build",
    "TWIN_MODULES",
]

DEFAULT_HULL_SIZES: Final = (16_384, 65_536, 262_144)
"""The point counts of the issue's table: 16K, 64K, 256K."""

DEFAULT_DISTS: Final = ("OnSphere", "EqHeavy", "PolHeavy", "InBall", "BordHeavy")
"""The five distributions of the paper's §4, in its order."""

DEFAULT_MEMORY_N: Final = 16_384
"""Point count of the history-memory measurement."""

DEFAULT_MEMORY_DIST: Final = "InBall"
"""Distribution of the history-memory measurement (the issue's: InBall, at 16K and 256K points)."""

EPHEMERAL: Final = "ephemeral"
"""The backend name of the NOT persistent baseline."""

ProgressCallback = Callable[[int, int, str], None]
"""``(steps done, steps in all, what runs next)``."""


@dataclass(frozen=True, slots=True)
class HullTiming:
    """persistri's time on one complex (a backend, or the ephemeral baseline) for one input."""

    backend: str
    seconds: float
    vs_qhull: float
    """``seconds`` over ``qhull_s``: each of persistri's runs is divided by the Qhull time measured just before it."""
    qhull_s: float
    """Qhull's time (best of 3) measured just before the run that gave ``seconds``."""
    us_per_insertion: float
    vs_ephemeral: float | None
    """``seconds`` over the ephemeral baseline's in the same run (None if it was not run)."""
    agrees: bool
    """Whether the hull's vertex set is Qhull's."""


@dataclass(frozen=True, slots=True)
class HullRecord:
    """One distribution at one point count."""

    dist: str
    n: int
    vertices: int
    """Vertices of the hull (persistri's; Qhull's when they differ is in ``agrees``)."""
    insertions: int
    qhull_s: float
    """Qhull's best time over every measurement of this input (each timing has the one taken next to it)."""
    timings: tuple[HullTiming, ...]

    def timing(self, backend: str) -> HullTiming | None:
        """The timing of ``backend`` (or of the ephemeral baseline), if measured."""
        for t in self.timings:
            if t.backend == backend:
                return t
        return None


@dataclass(frozen=True, slots=True)
class HullMemory:
    """Memory of one run of ``n`` points of ``dist``, in bytes (tracemalloc): every version kept, or only the final.

    ``versions_kept`` is what the full history alone holds: the memory still
    reachable from the tuple of versions once the rest of the result (the
    input points, the arrays of the final hull) is dropped — every complex
    version with its map nodes, vertex lists, entries, face data and conflict
    lists, each shared piece counted once.  ``history_kept`` and
    ``final_only_kept`` are what a whole run keeps (the result object with its
    arrays included) with and without ``history=True``.
    """

    n: int
    backend: str
    versions: int
    history_kept: int
    history_peak: int
    final_only_kept: int
    final_only_peak: int
    dist: str = "InBall"
    insertions: int = 0
    versions_kept: int = 0

    @property
    def per_version(self) -> float:
        """Bytes kept per additional version: what time travel adds to a run, per insertion."""
        return (self.history_kept - self.final_only_kept) / max(self.versions - 1, 1)

    @property
    def per_insertion(self) -> float:
        """Bytes the full history holds per inserted point: ``versions_kept`` over the insertions."""
        return self.versions_kept / max(self.insertions, 1)


TWIN_MODULES: Final = (
    "persistri.impl.geometry.kernel",
    "persistri.impl.geometry.kernel_split",
    "persistri.impl.hull.bulldozer",
    "persistri.impl.hull.insertion",
    "persistri.impl.hull.conflicts",
    "persistri.impl.maps.red_black_tree",
    "persistri.impl.maps.red_black_adjust",
    "persistri.impl.maps.red_black_adjust_insert",
    "persistri.impl.complex.vertex_lists",
    "persistri.impl.complex.vertex_changes",
    "persistri.impl.complex.replace",
    "persistri.impl.complex.neighbours",
)
"""The modules ``tools/compiled_twin.py`` compiles that the hull runs through (its ``MODULES``, by import name)."""


def persistri_build() -> str:
    """Which persistri is running: ``"interpreted"``, or ``"compiled twin (kernel, bulldozer, … by mypyc)"``
    naming those of :data:`TWIN_MODULES` that were imported as extension modules."""
    import importlib

    modules = [importlib.import_module(name) for name in TWIN_MODULES]
    compiled = [m.__name__.rsplit(".", 1)[1] for m in modules if not str(m.__file__).endswith(".py")]
    return f"compiled twin ({', '.join(compiled)} by mypyc)" if compiled else "interpreted"


@dataclass
class HullBench:
    """The whole benchmark: what was measured and how."""

    sizes: tuple[int, ...]
    dists: tuple[str, ...]
    backends: tuple[str, ...]
    repeat: int
    seed: int
    python: str = field(default_factory=lambda: f"Python {sys.version.split()[0]}")
    machine: str = field(default_factory=lambda: f"{platform.machine()} {platform.system()}")
    build: str = field(default_factory=persistri_build)
    records: list[HullRecord] = field(default_factory=list)
    memory: HullMemory | None = None

    def as_dict(self) -> dict[str, Any]:
        """A JSON-ready dictionary."""
        out: dict[str, Any] = {
            "sizes": list(self.sizes),
            "dists": list(self.dists),
            "backends": list(self.backends),
            "repeat": self.repeat,
            "seed": self.seed,
            "python": self.python,
            "machine": self.machine,
            "build": self.build,
            "timer": "CPU seconds (time.process_time), best of the repeats, cyclic GC off; Qhull (best of 3) timed "
            "right before each run, vs_qhull divides a subject's best run by the Qhull time taken before it",
            "records": [
                {
                    "dist": r.dist,
                    "n": r.n,
                    "vertices": r.vertices,
                    "insertions": r.insertions,
                    "qhull_s": r.qhull_s,
                    "timings": [asdict(t) for t in r.timings],
                }
                for r in self.records
            ],
        }
        if self.memory is not None:
            out["memory"] = dict(
                asdict(self.memory), per_version=self.memory.per_version, per_insertion=self.memory.per_insertion
            )
        return out


def cpu_seconds(run: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    """(best CPU seconds of ``repeat`` calls, the last result), the cyclic collector off while timing."""
    best = float("inf")
    result: Any = None
    enabled = gc.isenabled()
    for _ in range(repeat):
        result = None
        gc.collect()
        gc.disable()
        try:
            t0 = time.process_time()
            result = run()
            best = min(best, time.process_time() - t0)
        finally:
            if enabled:
                gc.enable()
    return best, result


def _qhull(points: NDArray[np.float64], repeat: int) -> tuple[float, NDArray[np.intp]]:
    from scipy.spatial import ConvexHull

    seconds, hull = cpu_seconds(lambda: ConvexHull(points), max(3, repeat))
    return seconds, np.sort(np.asarray(hull.vertices, dtype=np.intp))


def _memory(n: int, seed: int, backend: str, dist: str = "InBall") -> HullMemory:
    from persistri.impl.hull.api import convex_hull
    from persistri.impl.hull.distributions import generate

    # A small run first, so that the modules a run imports on first use are not counted as its memory.
    convex_hull(generate(dist, 64, seed + 1), backend=backend, seed=seed, history=True)
    points = generate(dist, n, seed)

    def measure(keep: bool) -> tuple[int, int, int, int, int]:
        """(kept by the run, its peak, versions, insertions, kept by the versions alone), from a base."""
        gc.collect()
        tracemalloc.start()
        try:
            base = tracemalloc.get_traced_memory()[0]
            hull = convex_hull(points, backend=backend, seed=seed, history=keep)
            gc.collect()
            kept, peak = tracemalloc.get_traced_memory()
            versions = hull.history.versions if hull.history is not None else (hull.complex,)
            insertions = hull.insertions
            del hull
            gc.collect()
            alone = tracemalloc.get_traced_memory()[0]
            count = len(versions)
            del versions
        finally:
            tracemalloc.stop()
        return kept - base, peak - base, count, insertions, alone - base

    kept_all, peak_all, versions, insertions, alone = measure(True)
    kept_one, peak_one, _, _, _ = measure(False)
    return HullMemory(n, backend, versions, kept_all, peak_all, kept_one, peak_one, dist, insertions, alone)


def run_hull_bench(
    sizes: Sequence[int] = DEFAULT_HULL_SIZES,
    *,
    dists: Sequence[str] = DEFAULT_DISTS,
    backends: Sequence[str] = ("red_black",),
    ephemeral: bool = True,
    repeat: int = 1,
    seed: int = 0,
    memory: bool = False,
    memory_n: int = DEFAULT_MEMORY_N,
    memory_dist: str = DEFAULT_MEMORY_DIST,
    on_progress: ProgressCallback | None = None,
) -> HullBench:
    """Run the benchmark described in the module docstring; ``ephemeral`` adds the baseline.

    Raises ``ValueError`` for an unknown distribution, a size below 4 or an
    empty backend list, and ``UnknownBackendError`` for an unknown backend
    (before anything is timed).
    """
    from persistri.impl.complex.simpcomp import two_complex
    from persistri.impl.hull.api import convex_hull
    from persistri.impl.hull.distributions import DISTRIBUTIONS, generate

    sizes = tuple(sorted({int(s) for s in sizes}))
    if not sizes or sizes[0] < 4:
        raise ValueError("sizes must be point counts of at least 4")
    unknown = [d for d in (*dists, *((memory_dist,) if memory else ())) if d not in DISTRIBUTIONS]
    if unknown:
        raise ValueError(f"unknown distribution {unknown[0]!r}; known: {', '.join(DISTRIBUTIONS)}")
    if not backends:
        raise ValueError("give at least one backend")
    for b in backends:
        two_complex(b)  # UnknownBackendError now, not after minutes of timing
    subjects = [b for b in backends if b != EPHEMERAL] + ([EPHEMERAL] if ephemeral or EPHEMERAL in backends else [])
    bench = HullBench(sizes, tuple(dists), tuple(backends), repeat, seed)
    steps = len(sizes) * len(dists) * repeat * len(subjects) + (2 if memory else 0)
    done = 0

    def report(what: str) -> None:
        if on_progress is not None:
            on_progress(done, steps, what)

    for dist in dists:
        for n in sizes:
            points = generate(dist, n, seed)
            # subject -> (best seconds, Qhull's seconds just before that run, insertions, agrees, vertices)
            best: dict[str, tuple[float, float, int, bool, int]] = {}
            q_best = float("inf")
            for _ in range(repeat):
                for b in subjects:
                    report(f"{dist} {n:,}: Qhull, then persistri on {b}")
                    q_s, q_vertices = _qhull(points, 1)
                    q_best = min(q_best, q_s)
                    seconds, hull = cpu_seconds(lambda: convex_hull(points, backend=b, seed=seed), 1)
                    agrees = bool(np.array_equal(hull.vertices, q_vertices))
                    if b not in best or seconds < best[b][0]:
                        best[b] = (seconds, q_s, hull.insertions, agrees, int(hull.vertices.size))
                    del hull
                    done += 1
            eph = best[EPHEMERAL][0] if EPHEMERAL in best else None
            timings = tuple(
                HullTiming(
                    backend=b,
                    seconds=s,
                    vs_qhull=s / q_s if q_s > 0 else float("inf"),
                    qhull_s=q_s,
                    us_per_insertion=s / max(ins, 1) * 1e6,
                    vs_ephemeral=(s / eph if eph else None),
                    agrees=agrees,
                )
                for b, (s, q_s, ins, agrees, _) in ((b, best[b]) for b in subjects)
            )
            first = best[subjects[0]]
            bench.records.append(HullRecord(dist, n, first[4], first[2], q_best, timings))
    if memory:
        report(f"memory: {memory_dist} {memory_n:,} with every version, then the final only")
        done += 1
        bench.memory = _memory(memory_n, seed, backends[0] if backends[0] != EPHEMERAL else "red_black", memory_dist)
        done += 1
    report("done")
    return bench


def _mb(n: float) -> str:
    return f"{n / 2**20:,.1f} MB"


def _ratio(r: float | None) -> str:
    if r is None:
        return "—"
    return f"{r:,.0f}×" if r >= 100 else f"{r:.1f}×" if r >= 10 else f"{r:.2f}×"


def hull_table(bench: HullBench) -> Any:
    """The benchmark as a rich renderable: one row per (distribution, size, complex), then the memory line."""
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    table = Table(
        title="Exact 3D convex hull: persistri's bulldozer against Qhull (lower is better)",
        caption=(
            f"CPU seconds, best of {bench.repeat} run(s), each after Qhull's best of 3 (the Qhull s beside it; ×Qhull is "
            f"their ratio), cyclic GC off, seed {bench.seed}; "
            f"×eph = time ÷ the ephemeral (dict, not persistent) baseline's; {bench.python} on {bench.machine}; "
            f"persistri {bench.build}"
        ),
        header_style="bold",
    )
    for name, justify in (
        ("dist", "left"),
        ("n", "right"),
        ("vertices", "right"),
        ("inserted", "right"),
        ("Qhull s", "right"),
        ("complex", "left"),
        ("ours s", "right"),
        ("×Qhull", "right"),
        ("µs/ins", "right"),
        ("×eph", "right"),
        ("agree", "left"),
    ):
        table.add_column(name, justify=justify, no_wrap=True)  # type: ignore[arg-type]  # rich's JustifyMethod literal
    previous = None
    for r in bench.records:
        if previous is not None and previous != r.dist:
            table.add_section()
        for j, t in enumerate(r.timings):
            table.add_row(
                r.dist if j == 0 else "",
                f"{r.n:,}" if j == 0 else "",
                f"{r.vertices:,}" if j == 0 else "",
                f"{r.insertions:,}" if j == 0 else "",
                f"{t.qhull_s:.3f}",
                t.backend,
                f"{t.seconds:.2f}",
                _ratio(t.vs_qhull),
                f"{t.us_per_insertion:,.0f}",
                _ratio(t.vs_ephemeral) if t.backend != EPHEMERAL else "1",
                "yes" if t.agrees else "NO",
                style="dim" if t.backend == EPHEMERAL else None,
            )
        previous = r.dist
    parts: list[Any] = [table]
    m = bench.memory
    if m is not None:
        parts.append(
            Text(
                f"memory, {m.dist} {m.n:,} points on {m.backend}: the full history ({m.versions:,} versions) holds "
                f"{_mb(m.versions_kept)}, {m.per_insertion / 1024:,.2f} KB per inserted point; the run keeps "
                f"{_mb(m.history_kept)} with it (peak {_mb(m.history_peak)}), {_mb(m.final_only_kept)} with the final "
                f"hull only (peak {_mb(m.final_only_peak)}): {m.per_version / 1024:,.2f} KB per extra version"
            )
        )
    return Group(*parts)
