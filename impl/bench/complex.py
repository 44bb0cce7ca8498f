"""The complex benchmark: what persistence costs the 2-complex, measured against the ephemeral baseline.

The workload is a **trace** (:mod:`persistri.impl.complex.trace`): the SIMPCOMP
operations that build a closed triangulated sphere of ``T`` triangles, recorded
once and then replayed — with nothing else running — on the 2-complex over
every map backend and on the ephemeral baseline, in the same run.  This is
how the paper separates the cost of the complex from the rest of the hull
(§4, Fig. 8).  Two workloads:

* ``sphere`` (default) — a sphere *grown the way the bulldozer grows a hull*,
  without geometry (:func:`sphere_trace`): for each new vertex p, look up one
  random triangle (``data``, as the bulldozer looks up the face a point is
  associated with), grow from it a random disk of on average 4 triangles
  across their edges (``findi``, the walk), query the three neighbours of each
  (``findi``, the walking-graph test), then replace the disk by the cone of
  its boundary from p (one ``replace``, as the bulldozer replaces the lit
  faces by the tent; with ``stepwise``, a ``rem`` per disk triangle and an
  ``add`` per cone triangle, as the paper's code does).  Each step adds 2
  triangles; the mix per vertex — 1 ``data``, about 15 ``findi``, 4 triangles
  removed, 6 added — is the bulldozer's (1, 12, 4, 6);
* ``hull`` — the bulldozer itself (:func:`hull_trace`): the convex hull of
  ``T/2 + 2`` points uniform on the sphere (the paper's OnSphere), recorded.
  Its geometry takes minutes at 10^5 triangles, so it is not the default.

Each subject then does, on the same trace:

* ``build`` — replay every event of the trace (:meth:`Replay.run` without
  verification; the vertex objects and argument tuples are built beforehand,
  untimed).  Reported per event;
* ``walk`` — visit every triangle of the final sphere once, from one triangle,
  across every edge (``findi`` of the reversed edge: the neighbour query of
  §2), depth first.  Reported per ``findi``.

Each phase is the best of ``repeat`` runs of **process CPU time**
(:func:`time.process_time`: the workload is single-threaded and does no I/O,
so CPU time is its cost, much less disturbed than wall time by other processes
on a shared machine — though not immune: they share its caches) with the cyclic
garbage collector off while timing (persistent structures make no reference
cycles).  The runs are interleaved — round r times every subject once — so a
change of machine load during the benchmark affects all subjects alike.  Every figure is also given as a ratio to the ephemeral
baseline's, and the total (build + walk) ratio is the one the project's
targets speak of.  Every run is checked untimed: the final sphere must have
exactly the triangles of the recorded one, and the walk must visit all of
them; a subject that fails is reported as ``error``.

The association-list complex is O(V) per operation (O(T²) per build), so it
runs only up to :data:`ASSOC_LIST_MAX_TRIANGLES` triangles; the report states
how its cost per operation grows between the sizes it ran at.
"""

from __future__ import annotations

import dataclasses
import gc
import math
import platform
import time
from collections.abc import Callable, Collection, Sequence
from dataclasses import dataclass
from typing import Any, Final, Literal

from persistri.impl.bench.complex_workloads import DEFAULT_SEED, ComplexBenchError, even_size, hull_trace, sphere_trace, walk
from persistri.impl.complex.ephemeral import EphemeralTwoComplex
from persistri.impl.complex.simpcomp import two_complex
from persistri.impl.complex.structure import Complex
from persistri.impl.complex.trace import Replay, Trace
from persistri.impl.complex.two_complex import TwoComplex

__all__ = [
    "ASSOC_LIST_MAX_TRIANGLES",
    "DEFAULT_REPEAT",
    "DEFAULT_SEED",
    "DEFAULT_SIZES",
    "WORKLOADS",
    "ComplexBench",
    "ComplexBenchError",
    "ComplexBenchRecord",
    "ComplexSubject",
    "SUBJECTS",
    "ProgressCallback",
    "Workload",
    "hull_trace",
    "sphere_trace",
    "run_complex_bench",
    "walk",
]

Workload = Literal["sphere", "hull"]
WORKLOADS: Final[tuple[Workload, ...]] = ("sphere", "hull")
"""The generated workloads (see the module docstring)."""

Kind = Literal["baseline", "persistri", "adapter"]
Status = Literal["ok", "skipped", "unavailable", "error"]

DEFAULT_SIZES: Final = (500, 2_000, 100_000)
"""Triangle counts measured by default: two small ones (where the association list runs too) and 10^5."""

DEFAULT_REPEAT: Final = 3
"""Timed runs per figure by default (the best is kept)."""

ASSOC_LIST_MAX_TRIANGLES: Final = 2_000
"""Largest sphere the association-list complex is measured on: O(V) per operation, O(T²) per build."""

ProgressCallback = Callable[[int, int, str], None]
"""``(steps done, steps in all, what runs next)``."""

_BASELINE: Final = "ephemeral"


# -- subjects ------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class ComplexSubject:
    """One 2-complex the benchmark measures: its name, kind, description, and its structure's factory."""

    name: str
    kind: Kind
    description: str
    make: Callable[[], TwoComplex[Any]]
    """Import what the subject needs and return a fresh structure; raises if it is not available."""
    max_triangles: int | None = None
    """Largest sphere it is measured on (``None``: no limit)."""
    skip_note: str = ""


SUBJECTS: Final[tuple[ComplexSubject, ...]] = (
    ComplexSubject(
        "ephemeral", "baseline", "2-complex over a mutable dict, NOT persistent (the baseline)", lambda: two_complex("ephemeral")
    ),
    ComplexSubject("red_black", "persistri", "persistent 2-complex over the red-black tree", lambda: two_complex("red_black")),
    ComplexSubject("hamt", "persistri", "persistent 2-complex over the HAMT", lambda: two_complex("hamt")),
    ComplexSubject(
        "assoc_list",
        "persistri",
        "persistent 2-complex over the sorted association list",
        lambda: two_complex("assoc_list"),
        max_triangles=ASSOC_LIST_MAX_TRIANGLES,
        skip_note="measured up to {limit} triangles only: O(V) per map operation, so O(T²) per build",
    ),
    ComplexSubject("immutables", "adapter", "persistent 2-complex over immutables.Map (C HAMT)", lambda: two_complex("immutables")),
    ComplexSubject("pyrsistent", "adapter", "persistent 2-complex over pyrsistent.pmap", lambda: two_complex("pyrsistent")),
)
"""Every subject, in table order; the ephemeral baseline first."""


# -- records -------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class ComplexBenchRecord:
    """The figures of one subject on one sphere (``None`` when not measured)."""

    complex: str
    kind: Kind
    description: str
    triangles: int
    """Triangles of the final sphere."""
    events: int
    """Operations replayed by ``build``."""
    status: Status
    build_s: float | None
    """CPU seconds of the build (best of repeat)."""
    walk_s: float | None
    build_us: float | None
    """µs per replayed operation."""
    walk_us: float | None
    """µs per ``findi`` of the walk."""
    build_vs_ephemeral: float | None
    walk_vs_ephemeral: float | None
    total_vs_ephemeral: float | None
    """(build + walk) ÷ the baseline's (build + walk): the figure the performance targets speak of."""
    note: str

    def as_dict(self) -> dict[str, Any]:
        """The record as a JSON-ready dictionary."""
        return dataclasses.asdict(self)


RECORD_FIELDS: Final = tuple(f.name for f in dataclasses.fields(ComplexBenchRecord))


@dataclass(frozen=True, slots=True)
class ComplexBench:
    """A finished benchmark: parameters, machine, the workload of each size, one record per (size, subject)."""

    workload: str
    sizes: tuple[int, ...]
    repeat: int
    seed: int
    python: str
    machine: str
    operations: tuple[tuple[int, dict[str, int]], ...]
    """Per size: the count of each operation in its trace."""
    records: tuple[ComplexBenchRecord, ...]

    def errors(self) -> list[ComplexBenchRecord]:
        """The records of subjects that failed while measured."""
        return [r for r in self.records if r.status == "error"]

    def record(self, name: str, triangles: int) -> ComplexBenchRecord | None:
        """The record of subject ``name`` on the sphere of ``triangles`` triangles."""
        return next((r for r in self.records if r.complex == name and r.triangles == triangles), None)

    def growth(self, name: str) -> tuple[int, int, float] | None:
        """``(T1, T2, α)``: the build's cost per operation grows as T^α from T1 to T2 triangles
        (the two extreme sizes ``name`` was measured at), or None if it ran at fewer than two."""
        ok = sorted((r.triangles, r.build_us) for r in self.records if r.complex == name and r.build_us)
        if len(ok) < 2 or ok[0][0] == ok[-1][0]:
            return None
        (t1, u1), (t2, u2) = ok[0], ok[-1]
        assert u1 is not None and u2 is not None
        return t1, t2, math.log(u2 / u1) / math.log(t2 / t1)

    def growth_notes(self) -> dict[str, tuple[int, int, float]]:
        """:meth:`growth` of each complex measured only up to a size limit (the association list): the
        complexes whose growth rate the report states."""
        out: dict[str, tuple[int, int, float]] = {}
        for s in SUBJECTS:
            g = self.growth(s.name)
            if s.max_triangles is not None and g is not None:
                out[s.name] = g
        return out

    def as_dict(self) -> dict[str, Any]:
        """The whole benchmark as a JSON-ready dictionary."""
        return {
            "benchmark": "complex",
            "workload": self.workload,
            "unit": "CPU seconds (best of repeat runs); µs per operation; ratios to the ephemeral baseline",
            "sizes": list(self.sizes),
            "repeat": self.repeat,
            "seed": self.seed,
            "python": self.python,
            "machine": self.machine,
            "operations": {str(t): counts for t, counts in self.operations},
            "growth": {name: {"from": g[0], "to": g[1], "exponent": g[2]} for name, g in self.growth_notes().items()},
            "records": [r.as_dict() for r in self.records],
        }


# -- measuring -----------------------------------------------------------------------------


def _timed(run: Callable[[], Any]) -> tuple[Any, float]:
    """``run()``'s result and its CPU time, the cyclic GC off while timing."""
    gc_was_enabled = gc.isenabled()
    gc.disable()
    try:
        start = time.process_time()
        result = run()
        elapsed = time.process_time() - start
    finally:
        if gc_was_enabled:
            gc.enable()
    return result, elapsed


def _labels(S: TwoComplex[Any], c: Complex[Any]) -> list[tuple[int, int, int]]:
    """The triangles of ``c`` as label triples (``items`` starts each at its least vertex), sorted."""
    out = []
    for (a, b, d), _ in S.items(c):
        out.append((int(a), int(b), int(d)))
    return sorted(out)


@dataclass
class _Timing:
    """One subject's structure and its best times so far (the rounds are interleaved across subjects)."""

    subject: ComplexSubject
    S: TwoComplex[Any]
    build: float = math.inf
    walk: float = math.inf

    def round(self, replay: Replay, expected: list[tuple[int, int, int]]) -> None:
        """Time one build and one walk, checking both untimed (ComplexBenchError if wrong)."""
        S, name = self.S, self.subject.name
        final, t_build = _timed(lambda: replay.run(S, verify=False))
        got = _labels(S, final)
        if got != expected:
            raise ComplexBenchError(
                f"{name}: the replayed sphere has {len(got)} triangles, not the recorded {len(expected)} (or other ones)"
            )
        start = next(iter(S.items(final)))[0]
        visited, t_walk = _timed(lambda: walk(S, final, start))
        if visited != len(expected):
            raise ComplexBenchError(f"{name}: the walk visited {visited} of {len(expected)} triangles")
        # The complex is dropped when this returns: untimed, like every check here.
        self.build = min(self.build, t_build)
        self.walk = min(self.walk, t_walk)


def _subjects(only: Collection[str] | None) -> list[ComplexSubject]:
    if only is None:
        return list(SUBJECTS)
    known = {s.name for s in SUBJECTS}
    unknown = sorted(set(only) - known)
    if unknown:
        raise ValueError(f"unknown complex(es) {', '.join(map(repr, unknown))}; known: {', '.join(s.name for s in SUBJECTS)}")
    return [s for s in SUBJECTS if s.name in only or s.name == _BASELINE]


def run_complex_bench(
    sizes: Sequence[int] = DEFAULT_SIZES,
    *,
    workload: Workload = "sphere",
    stepwise: bool = False,
    trace: Trace | None = None,
    repeat: int = DEFAULT_REPEAT,
    seed: int = DEFAULT_SEED,
    only: Collection[str] | None = None,
    assoc_list_max: int | None = None,
    on_progress: ProgressCallback | None = None,
) -> ComplexBench:
    """Measure every subject (or those in ``only``, plus the baseline) on a sphere of each size; module docstring.

    ``trace`` replays that trace (a closed 2-complex at its end) instead of
    generating ``workload`` at ``sizes``; ``stepwise`` generates it with a ``rem``
    and an ``add`` per triangle instead of one ``replace`` per step.  ``assoc_list_max`` overrides
    :data:`ASSOC_LIST_MAX_TRIANGLES`.  A subject that cannot be loaded is
    ``unavailable``; one that fails while measured is ``error`` with the reason.
    """
    if workload not in WORKLOADS:
        raise ValueError(f"workload: one of {', '.join(WORKLOADS)}, got {workload!r}")
    if isinstance(repeat, bool) or not isinstance(repeat, int) or repeat < 1:
        raise ValueError(f"repeat: a positive integer, got {repeat!r}")
    if trace is None:
        if not sizes:
            raise ValueError("sizes: give at least one triangle count")
        plan = sorted({even_size(t) for t in sizes})
    else:
        if trace.n != 2:
            raise ValueError(f"trace: the benchmark replays traces of 2-complexes, this one is of {trace.n}-complexes")
        plan = [-1]
    subjects = _subjects(only)
    total = len(plan) * (1 + repeat * len(subjects))
    done = 0
    records: list[ComplexBenchRecord] = []
    operations: list[tuple[int, dict[str, int]]] = []
    for size in plan:
        if on_progress is not None:
            on_progress(done, total, f"{workload} workload, {size:,} triangles" if trace is None else "loading the trace")
        if trace is not None:
            tr = trace
        elif workload == "sphere":
            tr = sphere_trace(size, seed, stepwise=stepwise)
        else:
            tr = hull_trace(size, seed, stepwise=stepwise)
        done += 1
        rp = Replay(tr)
        base = EphemeralTwoComplex[Any]()
        expected = _labels(base, rp.run(base, verify=True))  # the recorded run, re-checked event by event
        triangles = len(expected)
        operations.append((triangles, tr.counts()))
        seconds: dict[str, tuple[float, float]] = {}
        outcome: dict[str, tuple[Status, str]] = {}
        timings: list[_Timing] = []
        for subject in subjects:
            limit = assoc_list_max if subject.name == "assoc_list" and assoc_list_max is not None else subject.max_triangles
            if limit is not None and triangles > limit:
                outcome[subject.name] = ("skipped", subject.skip_note.format(limit=f"{limit:,}"))
                continue
            try:
                timings.append(_Timing(subject, subject.make()))
            except Exception as exc:  # noqa: BLE001 - a backend that cannot load is reported, the others run
                outcome[subject.name] = ("unavailable", f"{type(exc).__name__}: {exc}")
        # Rounds interleaved across subjects, so that a change of machine load affects them alike.
        for r in range(repeat):
            for timing in timings:
                name = timing.subject.name
                if name in outcome:  # failed in an earlier round
                    continue
                if on_progress is not None:
                    on_progress(done, total, f"{name}, {triangles:,} triangles, run {r + 1} of {repeat}")
                try:
                    timing.round(rp, expected)
                except Exception as exc:  # noqa: BLE001 - a failing subject is reported; the others still run
                    outcome[name] = ("error", f"{type(exc).__name__}: {exc}")
                done += 1
        for timing in timings:
            if timing.subject.name not in outcome:
                outcome[timing.subject.name] = ("ok", "")
                seconds[timing.subject.name] = (timing.build, timing.walk)
        done = (plan.index(size) + 1) * (1 + repeat * len(subjects))
        baseline = seconds.get(_BASELINE)
        for subject in subjects:
            status, note = outcome[subject.name]
            records.append(_record(subject, triangles, len(tr), status, note, seconds.get(subject.name), baseline))
    if on_progress is not None:
        on_progress(total, total, "done")
    return ComplexBench(
        workload="trace" if trace is not None else workload + (" (stepwise)" if stepwise else ""),
        sizes=tuple(t for t, _ in operations),
        repeat=repeat,
        seed=seed,
        python=f"{platform.python_implementation()} {platform.python_version()}",
        machine=f"{platform.machine()} {platform.system()}".strip(),
        operations=tuple(operations),
        records=tuple(records),
    )


def _record(
    subject: ComplexSubject,
    triangles: int,
    events: int,
    status: Status,
    note: str,
    secs: tuple[float, float] | None,
    baseline: tuple[float, float] | None,
) -> ComplexBenchRecord:
    build_s = walk_s = build_us = walk_us = None
    rb = rw = rt = None
    if secs is not None:
        build_s, walk_s = secs
        build_us = build_s / max(events, 1) * 1e6
        walk_us = walk_s / max(3 * triangles, 1) * 1e6
        if baseline is not None:
            rb = build_s / baseline[0] if baseline[0] > 0 else None
            rw = walk_s / baseline[1] if baseline[1] > 0 else None
            rt = (build_s + walk_s) / sum(baseline) if sum(baseline) > 0 else None
    return ComplexBenchRecord(
        complex=subject.name,
        kind=subject.kind,
        description=subject.description,
        triangles=triangles,
        events=events,
        status=status,
        build_s=build_s,
        walk_s=walk_s,
        build_us=build_us,
        walk_us=walk_us,
        build_vs_ephemeral=rb,
        walk_vs_ephemeral=rw,
        total_vs_ephemeral=rt,
        note=note,
    )
