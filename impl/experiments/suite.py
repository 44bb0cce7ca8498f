"""Running several figures at a preset scale: what ``persistri experiments`` does.

Two presets (:data:`PAPER`, :data:`QUICK`) give each figure its sizes; any
figure's sizes can be overridden.  :func:`run_experiments` runs the figures
in the order asked, shares the counted hull runs between Figs. 6 and 7, writes
each figure's files, and writes ``summary.md``: the sizes, the time each figure
took and the claims' verdicts, one line each, and a note for anything left out
(Fig. 11's optional second DEM where its package is not installed).  :func:`replot` redraws the figures and
rewrites the pages of an earlier run from its ``figN.csv`` and ``figN.json``,
without measuring again.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Final

from persistri.impl.experiments import fig6 as f6
from persistri.impl.experiments import fig7 as f7
from persistri.impl.experiments import fig8 as f8
from persistri.impl.experiments import fig11 as f11
from persistri.impl.experiments.counts import HullCount, HullCountCache
from persistri.impl.experiments.dems import load_dem
from persistri.impl.experiments.output import Progress, markdown_table, read_records, read_run_info, size_label
from persistri.impl.experiments.sweep import SWEPT, count_runs, hull_runs

if TYPE_CHECKING:
    from distributed import Client

__all__ = ["FIGURES", "PAPER", "QUICK", "FigureRun", "Summary", "run_experiments", "replot", "sizes_for"]

FIGURES: Final = ("fig6", "fig7", "fig8", "fig11")
"""The figures, in the paper's order."""

PAPER: Final[dict[str, tuple[int, ...]]] = {
    "fig6": f6.PAPER_SIZES,
    "fig7": (f7.PAPER_SIZE,),
    "fig8": f8.PAPER_SIZES,
    "fig11": f11.PAPER_SIZES,
}
"""The paper's sizes: 128K–512K points (Fig. 6), 512K (Fig. 7), 16K–64K (Fig. 8), 1,600–12,800 (Fig. 11)."""

QUICK: Final[dict[str, tuple[int, ...]]] = {
    "fig6": f6.QUICK_SIZES,
    "fig7": (f7.QUICK_SIZE,),
    "fig8": f8.QUICK_SIZES,
    "fig11": f11.QUICK_SIZES,
}
"""``--quick``: every figure in seconds (the test suite runs it)."""


@dataclass(frozen=True, slots=True)
class FigureRun:
    """One figure's run: its sizes, wall and CPU seconds, and the files it wrote."""

    name: str
    sizes: tuple[int, ...]
    wall_seconds: float
    cpu_seconds: float
    files: tuple[Path, ...]


@dataclass
class Summary:
    """Every figure run by :func:`run_experiments`, and where its summary was written."""

    out: Path
    runs: list[FigureRun] = field(default_factory=list)
    path: Path | None = None
    notes: list[str] = field(default_factory=list)
    """What was left out and how to get it, one line each (``fig11: the lidar DEM is left out: …``)."""

    @property
    def wall_seconds(self) -> float:
        """The total wall-clock time of the figures."""
        return sum(r.wall_seconds for r in self.runs)


def sizes_for(name: str, *, quick: bool, override: Mapping[str, Sequence[int]] | None = None) -> tuple[int, ...]:
    """The sizes figure ``name`` runs at: ``override[name]`` if given, else the preset's.

    ValueError for an unknown figure.  Fig. 7 runs at one size: the largest given.
    """
    if name not in FIGURES:
        raise ValueError(f"unknown figure {name!r}; known: {', '.join(FIGURES)}")
    sizes = tuple(sorted(set(override[name]))) if override and name in override else (QUICK if quick else PAPER)[name]
    if not sizes:
        raise ValueError(f"{name}: give at least one size")
    return (max(sizes),) if name == "fig7" else sizes


def run_experiments(
    names: Sequence[str],
    out: Path,
    *,
    quick: bool = False,
    sizes: Mapping[str, Sequence[int]] | None = None,
    seeds: Sequence[int] = (0,),
    backends: Sequence[str] = f8.BACKENDS,
    repeat: int = 1,
    dems: Sequence[str] | None = None,
    progress: Callable[[str], Progress] | None = None,
    client: Client | None = None,
) -> Summary:
    """Run the figures ``names`` (in :data:`FIGURES` order) into ``out``; returns the :class:`Summary`.

    ``progress(name)`` is asked for each figure's progress callback.
    ``backends`` and ``repeat`` are Fig. 8's, ``dems`` Fig. 11's (``None``: the
    installed defaults, :func:`~persistri.impl.experiments.fig11.choose_dems`).
    ``client`` — a ``distributed.Client``: the counted hull runs of Figs. 6 and 7 are made
    first, as tasks on its cluster (:mod:`~persistri.impl.experiments.sweep`; the same
    records and files, a note in the summary says how long it took); None: all in this process.
    Every figure's sizes, and Fig. 11's DEMs, are checked before the first
    figure starts (:class:`~persistri.impl.experiments.dems.DemUnavailableError`
    for a DEM asked for by name that is not installed).
    """
    unknown = [n for n in names if n not in FIGURES]
    if unknown:
        raise ValueError(f"unknown figure {unknown[0]!r}; known: {', '.join(FIGURES)}")
    if sizes:
        extra = [k for k in sizes if k not in FIGURES]
        if extra:
            raise ValueError(f"sizes given for an unknown figure {extra[0]!r}; known: {', '.join(FIGURES)}")
    order = [n for n in FIGURES if n in names]
    plan = {n: sizes_for(n, quick=quick, override=sizes) for n in order}
    for n, ss in plan.items():
        if ss[0] < 4:
            raise ValueError(f"{n}: sizes must be at least 4, got {ss[0]}")
    left_out = f11.choose_dems(dems)[1] if "fig11" in plan else ()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    cache = HullCountCache()
    summary = Summary(out, notes=[f"fig11: {note}" for note in left_out])
    bars: dict[str, Progress | None] = {}

    def progress_of(name: str) -> Progress | None:  # one callback per figure, the sweep's included
        if name not in bars:
            bars[name] = progress(name) if progress is not None else None
        return bars[name]

    swept = [n for n in order if n in SWEPT]
    if client is not None and swept:
        w0 = time.perf_counter()
        made = count_runs(client, hull_runs(plan, seeds), backend="red_black", cache=cache, progress=progress_of(swept[0]))
        summary.notes.insert(
            0,
            f"{', '.join(swept)}: their {made} counted hull runs were made first as Dask tasks "
            f"({_duration(time.perf_counter() - w0)} wall-clock); the times below are what remained",
        )
    for n in order:
        cb = progress_of(n)
        w0, c0 = time.perf_counter(), time.process_time()
        if n == "fig6":
            f6.fig6(out, plan[n], seeds=seeds, progress=cb, cache=cache)
        elif n == "fig7":
            f7.fig7(out, plan[n][0], seeds=seeds, progress=cb, cache=cache)
        elif n == "fig8":
            f8.fig8(out, plan[n], seeds=seeds, backends=backends, repeat=repeat, progress=cb)
        else:
            f11.fig11(out, plan[n], dems=dems, progress=cb)
        files = tuple(out / f"{n}.{ext}" for ext in ("csv", "png", "md"))
        summary.runs.append(FigureRun(n, plan[n], time.perf_counter() - w0, time.process_time() - c0, files))
    summary.path = _write_summary(summary, quick=quick, seeds=seeds)
    return summary


def _duration(s: float) -> str:
    return f"{s:.1f} s" if s < 90 else f"{s / 60:.1f} min"


def _write_summary(summary: Summary, *, quick: bool, seeds: Sequence[int]) -> Path:
    rows = [
        (
            f"[{r.name}]({r.name}.md)",
            ", ".join(f"{n:,}" if r.name == "fig11" else size_label(n) for n in r.sizes),
            _duration(r.wall_seconds),
            _duration(r.cpu_seconds),
        )
        for r in summary.runs
    ]
    text = "\n".join(
        [
            "# persistri experiments",
            "",
            f"Preset: {'quick' if quick else 'paper'} (sizes overridden where they differ from it); "
            f"seeds {', '.join(map(str, seeds))}. Total {_duration(summary.wall_seconds)} wall-clock.",
            "",
            markdown_table(("figure", "sizes", "wall-clock", "CPU"), rows, "llrr"),
            "",
            *(
                ("Fig. 7 reuses the counted runs Fig. 6 made at the same size, so its time is what remained to do.", "")
                if {"fig6", "fig7"} <= {r.name for r in summary.runs}
                else ()
            ),
            *(line for note in summary.notes for line in (f"Note — {note}", "")),
        ]
    )
    path = summary.out / "summary.md"
    path.write_text(text)
    return path


def replot(names: Sequence[str], out: Path) -> list[Path]:
    """Redraw ``figN.png`` and rewrite ``figN.md`` of the figures ``names`` from the ``figN.csv`` and
    ``figN.json`` an earlier run left in ``out``; returns the pages written.

    ValueError (naming the file) when a figure's files are missing or malformed.
    """
    out = Path(out)
    pages: list[Path] = []
    for n in [f for f in FIGURES if f in names]:
        csv_path, json_path = out / f"{n}.csv", out / f"{n}.json"
        if not csv_path.is_file() or not json_path.is_file():
            raise ValueError(f"{n}: {csv_path.name} and {json_path.name} are needed in {out} to redraw it (run it first)")
        info = read_run_info(json_path)
        if n == "fig6":
            pages.append(f6.write_fig6(read_records(csv_path, HullCount), out, info))
        elif n == "fig7":
            pages.append(f7.write_fig7(read_records(csv_path, HullCount), out, info))
        elif n == "fig8":
            pages.append(f8.write_fig8(read_records(csv_path, f8.Fig8Record), out, info))
        else:
            recs = read_records(csv_path, f11.Fig11Record)
            dems = [load_dem(d) for d in dict.fromkeys(r.dem for r in recs)]
            pages.append(f11.write_fig11(recs, dems, out, info))
    return pages
