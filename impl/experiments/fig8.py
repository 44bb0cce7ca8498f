"""Fig. 8 of the paper: the time of the complex operations alone against Qhull's total time (§4).

The paper's hull was in ML and Qhull (the Minnesota code) in C, so it did not
compare them directly: it dumped the trace of every operation its hull made
on the simplicial complex, replayed the trace in C on balanced trees and
linked lists, and plotted that replay's time beside Qhull's total time for
16K–64K OnSphere points.  Its finding: *the cost of the simplicial-complex
operations is at most half the total cost of the Minnesota code*, on the
distribution where the complex is used most.

:func:`fig8` does the same with persistri's machinery, for each size:

* **Qhull's total** — :class:`scipy.spatial.ConvexHull` (C), best of at least 3 runs;
* **persistri's total** — the whole :func:`~persistri.impl.hull.api.convex_hull`
  (exact predicates included) on the red-black backend, one run;
* a **trace** of the bulldozer's complex operations
  (:func:`persistri.impl.bench.complex.hull_trace`, recorded through a
  :class:`~persistri.impl.complex.trace.TracingTwoComplex`), **replayed alone**
  on each requested backend and on the ephemeral (``dict``, not persistent)
  baseline by :func:`persistri.impl.bench.complex.run_complex_bench`, which checks
  that every replay ends in the recorded hull.

Both persistri runs are ``stepwise`` (a ``rem`` per lit face and an ``add`` per
tent face, as in the paper's code, whose trace the paper replayed); the default
hull makes the same change with one ``replace`` per insertion, which is cheaper.
Times are CPU seconds (``time.process_time``) with the cyclic collector off.
Our replays run in Python, Qhull in C: the table says what that does and does
not let one conclude.  Progress is reported in steps.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Final, Literal

from persistri.impl.experiments.output import (
    Comparison,
    Progress,
    RunInfo,
    figure_paths,
    new_figure,
    save_png,
    size_label,
    write_csv,
    write_markdown,
)

__all__ = ["PAPER_SIZES", "QUICK_SIZES", "BACKENDS", "Fig8Record", "run_fig8", "write_fig8", "fig8"]

PAPER_SIZES: Final = (16_384, 32_768, 65_536)
"""The paper's sizes: 16K, 32K, 64K OnSphere points."""

QUICK_SIZES: Final = (256, 512)
"""``--quick``: seconds, for the test suite."""

BACKENDS: Final = ("red_black", "hamt", "immutables", "pyrsistent")
"""The persistent complexes replayed by default (the ephemeral baseline always runs)."""

QHULL: Final = "Qhull (scipy)"
TOTAL: Final = "persistri hull"

What = Literal["qhull_total", "persistri_total", "complex_replay"]


@dataclass(frozen=True, slots=True)
class Fig8Record:
    """One timed subject at one size."""

    n: int
    seed: int
    subject: str
    """``Qhull (scipy)``, ``persistri hull`` (on ``backend``) or the name of the replayed complex."""
    what: What
    seconds: float | None
    """CPU seconds (best of the repeats); None if not measured (``status``)."""
    events: int
    """Complex operations in the trace (the same for every replay at this size; 0 for the totals)."""
    triangles: int
    """Triangles of the final hull."""
    vs_qhull: float | None
    vs_ephemeral: float | None
    """Replay time over the ephemeral baseline's replay time."""
    status: str
    note: str

    def row(self) -> dict[str, object]:
        """The record as a CSV row."""
        return asdict(self)


def run_fig8(
    sizes: Sequence[int] = PAPER_SIZES,
    *,
    seeds: Sequence[int] = (0,),
    backends: Sequence[str] = BACKENDS,
    total_backend: str = "red_black",
    repeat: int = 1,
    progress: Progress | None = None,
) -> list[Fig8Record]:
    """Time Qhull, persistri's whole hull and the replayed complex operations at each size and seed.

    ``backends`` are names of :data:`persistri.impl.bench.complex.SUBJECTS`
    (ValueError for an unknown one).  ``repeat`` replays (and Qhull runs, at
    least 3) per figure, the best kept.  ``progress(done, total, what)`` counts steps.
    A replay that fails or ends elsewhere than the recorded hull is recorded
    with status ``error`` (its time is meaningless), never silently.
    """
    from scipy.spatial import ConvexHull

    from persistri.impl.bench.complex import SUBJECTS, hull_trace, run_complex_bench
    from persistri.impl.bench.hull import cpu_seconds
    from persistri.impl.hull.api import convex_hull
    from persistri.impl.hull.distributions import on_sphere

    sizes = tuple(sorted(set(sizes)))
    if not sizes or not seeds:
        raise ValueError("fig8: give at least one size and one seed")
    if sizes[0] < 4:
        raise ValueError(f"fig8: a hull needs at least 4 points, got {sizes[0]}")
    if isinstance(repeat, bool) or not isinstance(repeat, int) or repeat < 1:
        raise ValueError(f"fig8: repeat must be a positive integer, got {repeat!r}")
    known = {s.name for s in SUBJECTS}
    unknown = [b for b in backends if b not in known]
    if unknown:
        raise ValueError(f"fig8: unknown complex {unknown[0]!r}; known: {', '.join(sorted(known))}")
    replayed = ["ephemeral"] + [b for b in backends if b != "ephemeral"]
    per_size = 3 + 1 + repeat * len(replayed)
    total = len(sizes) * len(seeds) * per_size
    done = 0

    def report(what: str) -> None:
        if progress is not None:
            progress(done, total, what)

    records: list[Fig8Record] = []
    for n in sizes:
        for seed in seeds:
            label = f"OnSphere {size_label(n)}, seed {seed}"
            points = on_sphere(n, seed)
            report(f"{label}: Qhull")
            q_s, q_hull = cpu_seconds(lambda: ConvexHull(points), max(3, repeat))
            done += 1
            report(f"{label}: persistri's whole hull ({total_backend})")
            t_s, hull = cpu_seconds(lambda: convex_hull(points, backend=total_backend, seed=seed, stepwise=True, labels="input"), 1)
            triangles = int(hull.simplices.shape[0])
            same = bool(set(hull.vertices.tolist()) == set(q_hull.vertices.tolist()))
            del hull
            done += 1
            report(f"{label}: recording the trace")
            trace = hull_trace(2 * n - 4, seed, stepwise=True, labels="input")  # the hull of on_sphere(n, seed), seed's insertion order
            done += 1
            base = done

            def sub(d: int, _t: int, what: str, label: str = label, base: int = base) -> None:
                nonlocal done
                done = base + d
                report(f"{label}: replay — {what}")

            bench = run_complex_bench(trace=trace, repeat=repeat, only=replayed, seed=seed, on_progress=sub)
            done = base + 1 + repeat * len(replayed)
            records.append(Fig8Record(n, seed, QHULL, "qhull_total", q_s, 0, triangles, 1.0, None, "ok", ""))
            records.append(
                Fig8Record(
                    n,
                    seed,
                    TOTAL,
                    "persistri_total",
                    t_s,
                    0,
                    triangles,
                    t_s / q_s if q_s > 0 else None,
                    None,
                    "ok",
                    f"exact predicates, {total_backend} backend"
                    + ("" if same else "; vertex set differs from Qhull's (Qhull is not exact)"),
                )
            )
            for r in bench.records:
                records.append(
                    Fig8Record(
                        n,
                        seed,
                        r.complex,
                        "complex_replay",
                        r.build_s,
                        r.events,
                        r.triangles,
                        (r.build_s / q_s if r.build_s is not None and q_s > 0 else None),
                        r.build_vs_ephemeral,
                        r.status,
                        r.note,
                    )
                )
    report("done")
    return records


def _best(records: Sequence[Fig8Record], n: int, subject: str) -> float | None:
    """The mean over seeds of ``subject``'s seconds at ``n`` (None if never measured)."""
    xs = [r.seconds for r in records if r.n == n and r.subject == subject and r.seconds is not None]
    return sum(xs) / len(xs) if xs else None


def _plot(records: Sequence[Fig8Record], path: Path) -> Path:
    fig, ax = new_figure(7.5, 4.8)
    sizes = sorted({r.n for r in records})
    subjects = [QHULL, TOTAL] + list(dict.fromkeys(r.subject for r in records if r.what == "complex_replay"))
    styles: dict[str, tuple[str, str, str, float]] = {
        QHULL: ("black", "-", "o", 2.5),
        TOTAL: ("tab:gray", "--", "D", 1.5),
        "ephemeral": ("tab:green", ":", "v", 1.5),
    }
    palette = iter(["tab:blue", "tab:red", "tab:purple", "tab:orange", "tab:brown", "tab:pink"])
    for s in subjects:
        xs, ys = [], []
        for n in sizes:
            v = _best(records, n, s)
            if v is not None:
                xs.append(n)
                ys.append(v)
        if not xs:
            continue
        color, ls, marker, lw = styles.get(s, (next(palette, "tab:olive"), "-", "s", 1.5))
        label = (
            "Qhull (scipy, C): whole hull"
            if s == QHULL
            else "persistri: whole hull (exact)"
            if s == TOTAL
            else f"complex operations alone: {s}" + (" (dict, not persistent)" if s == "ephemeral" else "")
        )
        ax.plot(xs, ys, ls, color=color, marker=marker, lw=lw, label=label)
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xticks(sizes, [size_label(n) for n in sizes])
    ax.minorticks_off()
    ax.set_xlabel("Problem size (OnSphere points)")
    ax.set_ylabel("CPU seconds (log scale)")
    ax.set_title("Fig. 8 (persistri): complex operations alone vs Qhull's total")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    return save_png(fig, path)


def _fmt(x: float | None, unit: str = "") -> str:
    if x is None:
        return "—"
    return f"{x:.3g}{unit}"


def _comparisons(records: Sequence[Fig8Record]) -> list[Comparison]:
    sizes = sorted({r.n for r in records})
    replays = [s for s in dict.fromkeys(r.subject for r in records if r.what == "complex_replay") if s != "ephemeral"]
    main = "red_black" if "red_black" in replays else (replays[0] if replays else "ephemeral")
    out: list[Comparison] = []
    vs_q = []
    share = []
    persist = []
    for n in sizes:
        q, t, rb, eph = (_best(records, n, s) for s in (QHULL, TOTAL, main, "ephemeral"))
        if q and rb is not None:
            vs_q.append(rb / q)
        if t and rb is not None:
            share.append(rb / t)
        if eph and rb is not None:
            persist.append(rb / eph)
    span = f"{size_label(sizes[0])}–{size_label(sizes[-1])}" if len(sizes) > 1 else size_label(sizes[0])
    if vs_q:
        out.append(
            Comparison(
                "The complex operations cost at most half of Qhull's total time",
                "replay (C, balanced trees and linked lists) ≤ 0.5 × Qhull's total, OnSphere 16K–64K",
                f"replay on {main} (Python) = {min(vs_q):.0f}–{max(vs_q):.0f} × Qhull's total (C), {span}",
                "not comparable" if max(vs_q) > 0.5 else "agrees",
                ""
                if max(vs_q) <= 0.5
                else "The paper compared C with C; ours compares a CPython replay with Qhull's C. A CPython "
                "operation on tuples and dictionaries costs tens of times its C counterpart, so this ratio measures "
                "the interpreter, not persistence. The two rows below are the same-language comparisons.",
            )
        )
    if share:
        rest = [x / (1 - x) for x in share if x < 1]
        out.append(
            Comparison(
                "Same language: the complex operations against the rest of a whole hull",
                "complex ≤ 0.5 × a whole hull (the paper's replay against Qhull, both in C)",
                f"replay on {main} = {min(share):.0%}–{max(share):.0%} of persistri's whole hull, i.e. "
                + (f"{min(rest):.2f}–{max(rest):.2f} × the rest of it (geometry, conflict lists, bookkeeping)" if rest else "all of it")
                + f", {span}",
                "agrees" if rest and max(rest) <= 0.5 else "partly",
                ""
                if rest and max(rest) <= 0.5
                else "persistri's geometry runs largely in numpy (C loops over conflict lists) while every complex "
                "operation is interpreted Python, which shifts the balance towards the complex compared with an "
                "all-C program; the two halves are still of the same order.",
            )
        )
    if persist:
        out.append(
            Comparison(
                "A persistent dictionary would cost the surface code under 50 % overhead",
                "< 50 % (the paper's conclusion, against Qhull's own non-persistent surface code)",
                f"replay on {main} = {min(persist):.1f}–{max(persist):.1f} × the replay on a mutable dict ({span})",
                "partly" if max(persist) > 1.5 else "agrees",
                ""
                if max(persist) <= 1.5
                else "Against a Python dict (hashing in C, one probe per operation) a persistent tree pays "
                "O(lg n) interpreted node visits and path copies per operation; the paper's baseline was "
                "Qhull's whole run, of which the surface is only a part.",
            )
        )
    return out


def write_fig8(records: Sequence[Fig8Record], out: Path, info: RunInfo) -> Path:
    """Write ``fig8.csv``, ``fig8.png`` and ``fig8.md`` into ``out``; returns the Markdown page's path."""
    paths = figure_paths(out, "fig8")
    write_csv(paths.csv, [r.row() for r in records])
    _plot(records, paths.png)
    rows = [
        (
            size_label(r.n),
            str(r.seed),
            r.subject,
            r.what.replace("_", " "),
            _fmt(r.seconds),
            f"{r.events:,}" if r.events else "—",
            f"{r.seconds / r.events * 1e6:.2f}" if r.seconds is not None and r.events else "—",
            _fmt(r.vs_qhull, "×"),
            _fmt(r.vs_ephemeral, "×"),
            r.status + (f": {r.note}" if r.note else ""),
        )
        for r in records
    ]
    return write_markdown(
        paths.md,
        title="Fig. 8 — the complex operations alone against Qhull's total time",
        intro=(
            "CPU time of Qhull's whole hull, of persistri's whole hull, and of the bulldozer's complex operations "
            "alone (a recorded trace replayed on each complex), OnSphere points (paper §4, Fig. 8)."
        ),
        info=info,
        comparisons=_comparisons(records),
        data_headers=("n", "seed", "subject", "what", "CPU s", "operations", "µs / op", "× Qhull", "× ephemeral", "status"),
        data_rows=rows,
        data_align="lrllrrrrrl",
        notes=(
            "A trace holds every SIMPCOMP operation of the run (data, findi, add, rem, …) with placeholder data; "
            "the replay re-executes them with nothing else running, and is checked to end in the recorded hull.",
            "The association-list complex is O(V) per operation: include it with --backends assoc_list; it is "
            "replayed only up to 2,000 triangles (persistri.impl.bench.complex).",
        ),
        image="fig8.png",
    )


def fig8(
    out: Path,
    sizes: Sequence[int] = PAPER_SIZES,
    *,
    seeds: Sequence[int] = (0,),
    backends: Sequence[str] = BACKENDS,
    repeat: int = 1,
    progress: Progress | None = None,
) -> list[Fig8Record]:
    """Run Fig. 8 (:func:`run_fig8`) and write its files into ``out`` (:func:`write_fig8`); returns the records."""
    w0, c0 = time.perf_counter(), time.process_time()
    records = run_fig8(sizes, seeds=seeds, backends=backends, repeat=repeat, progress=progress)
    info = RunInfo(
        {
            "sizes": ", ".join(size_label(n) for n in sorted(set(sizes))),
            "seeds": ", ".join(map(str, seeds)),
            "complexes": ", ".join(["ephemeral", *[b for b in backends if b != "ephemeral"]]),
            "repeat": str(repeat),
        },
        time.perf_counter() - w0,
        time.process_time() - c0,
    )
    write_fig8(records, out, info)
    return records
