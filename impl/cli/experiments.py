"""``persistri experiments``: regenerate the paper's Figs. 6, 7, 8 and 11 as CSV, PNG and a paper-vs-ours table.

The measuring code is :mod:`persistri.impl.experiments`; this command parses
options, draws one progress bar per figure on stderr (on a terminal), prints a
note for anything left out on stderr, and where the files went on stdout.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

import click
from rich.console import Console, JustifyMethod
from rich.progress import BarColumn, Progress, TaskProgressColumn, TextColumn, TimeElapsedColumn, TimeRemainingColumn
from rich.table import Table
from rich.text import Text

from persistri.impl.cli.checks import FILE_PATH, check_output_dir
from persistri.impl.cli.console import stderr_console, stdout_console
from persistri.impl.cli.errors import about, fail
from persistri.impl.experiments.dems import DEMS
from persistri.impl.experiments.fig8 import BACKENDS as FIG8_BACKENDS
from persistri.impl.experiments.fig11 import DEFAULT_DEMS, OPTIONAL_DEMS
from persistri.impl.experiments.output import Progress as ProgressCallback
from persistri.impl.experiments.output import parse_sizes
from persistri.impl.experiments.suite import FIGURES, replot, run_experiments, sizes_for
from persistri.impl.experiments.sweep import SWEPT
from persistri.impl.scale import dask_missing
from persistri.impl.scale.cluster import ENV_SCHEDULER, connect

__all__ = ["experiments", "parse_size_options"]

_UNITS = {"fig6": "points", "fig7": "points", "fig8": "steps", "fig11": "points"}


def parse_size_options(names: Sequence[str], values: tuple[str, ...]) -> dict[str, tuple[int, ...]]:
    """``--sizes`` values → sizes per figure, for a command that runs the figures ``names``.

    For one figure a value is a comma-separated list (``128K,256K``); for
    several each value names its figure (``fig6=128K,256K``).  Raises
    :class:`click.BadParameter` naming the problem.
    """
    out: dict[str, tuple[int, ...]] = {}
    for value in values:
        name, sep, text = value.partition("=")
        if sep:
            name = name.strip()
            if name not in FIGURES:
                raise click.BadParameter(f"{name!r} is not a figure ({', '.join(FIGURES)})", param_hint="--sizes")
            if name not in names:
                raise click.BadParameter(f"sizes for {name} given, but the command runs {', '.join(names)}", param_hint="--sizes")
        else:
            if len(names) != 1:
                raise click.BadParameter(
                    "with several figures, name the figure of each list: --sizes fig6=128K,256K --sizes fig8=16K",
                    param_hint="--sizes",
                )
            name, text = names[0], value
        if name in out:
            raise click.BadParameter(f"sizes for {name} given twice", param_hint="--sizes")
        try:
            out[name] = parse_sizes(text)
        except ValueError as exc:
            raise click.BadParameter(str(exc), param_hint="--sizes") from None
    return out


def _ints(text: str, what: str) -> tuple[int, ...]:
    try:
        items = tuple(int(s) for s in text.split(",") if s.strip())
    except ValueError:
        raise click.BadParameter(f"{text!r}: give integers separated by commas", param_hint=what) from None
    if not items:
        raise click.BadParameter("give at least one", param_hint=what)
    if any(i < 0 for i in items):
        raise click.BadParameter(f"{text!r}: seeds are non-negative integers", param_hint=what)
    return items


@contextmanager
def _bars(console: Console) -> Iterator[Progress]:
    columns = (
        TextColumn("{task.description}"),
        BarColumn(),
        TaskProgressColumn(),
        TimeElapsedColumn(),
        TimeRemainingColumn(),
    )
    # Off a terminal rich would print every bar's last state at the end: nothing to follow there.
    with Progress(*columns, console=console, transient=False, disable=not console.is_terminal) as progress:
        yield progress


@click.command("experiments", short_help="Regenerate the paper's Figs. 6, 7, 8 and 11 (CSV, PNG, tables).")
@click.argument("which", nargs=-1, required=True, type=click.Choice([*FIGURES, "all"]))
@click.option(
    "--out",
    "out",
    required=True,
    type=FILE_PATH,
    help="Directory for figN.csv, figN.png, figN.md and summary.md (created if missing; its parent must exist).",
)
@click.option("--quick", is_flag=True, help="Small sizes: every figure in seconds (what the test suite runs).")
@click.option(
    "--sizes",
    "size_values",
    multiple=True,
    metavar="SIZES",
    help="Sizes instead of the preset's: '16K,32K' for one figure, 'fig6=128K,256K' (repeatable) with all. K = 1024.",
)
@click.option("--seeds", default="0", show_default=True, help="Seeds (points and insertion order) of Figs. 6-8, comma-separated.")
@click.option("--repeat", type=click.IntRange(min=1), default=1, show_default=True, help="Fig. 8: timed runs per figure, the best kept.")
@click.option(
    "--backends",
    default=",".join(FIG8_BACKENDS),
    show_default=True,
    help="Fig. 8: complexes to replay the trace on (the ephemeral baseline always runs).",
)
@click.option(
    "--dems",
    default=None,
    metavar="NAMES",
    help=f"Fig. 11: the DEMs, comma-separated, of {', '.join(DEMS)}.  Default: {','.join(DEFAULT_DEMS)}, leaving out "
    f"{', '.join(sorted(OPTIONAL_DEMS))} with a note where its package is not installed.",
)
@click.option(
    "--workers",
    type=click.IntRange(min=1),
    help="Make the counted hull runs of Figs. 6-7 on a local Dask cluster of N worker processes first (1: this process).  [default: this process]",
)
@click.option("--scheduler", metavar="ADDR", help=f"Make them on the existing Dask cluster of this scheduler (tcp://host:8786; ${ENV_SCHEDULER} is not read here).")
@click.option("--replot", "replot_only", is_flag=True, help="Measure nothing: redraw the PNGs and rewrite the pages from an earlier run's CSV and JSON in --out.")
def experiments(
    which: tuple[str, ...],
    out: Path,
    quick: bool,
    size_values: tuple[str, ...],
    seeds: str,
    repeat: int,
    backends: str,
    dems: str | None,
    workers: int | None,
    scheduler: str | None,
    replot_only: bool,
) -> None:
    """Regenerate the paper's Fig. 6, 7, 8, 11 (several, or all) into --out: CSV, PNG and a paper-vs-persistri table each.

    \b
    fig6   key comparisons and flops of the hull against n, OnSphere and BordHeavy (128K-512K)
    fig7   the same counts for the five distributions at one size (512K)
    fig8   the complex operations alone (a replayed trace) against Qhull's total time (16K-64K)
    fig11  terrain counts on two real DEMs (1,600-12,800 points)

    The paper's sizes are long: Figs. 6-7 need about 35 minutes of CPU (the
    three sphere distributions at 512K, each about 8 minutes, extrapolated from
    64K as n lg n); Figs. 8 and 11 a few minutes.  --quick takes seconds.

    With --workers N or --scheduler ADDR the counted hull runs of Figs. 6 and 7
    (the sweep over distributions, sizes and seeds) are made first as Dask tasks,
    in parallel: the same counts and files.  Figs. 8 and 11 run in this process
    (Fig. 8 times its runs).
    """
    names = list(FIGURES) if "all" in which else [f for f in FIGURES if f in which]
    if workers is not None and scheduler is not None:
        raise click.UsageError("give either --workers or --scheduler, not both (a cluster has its own workers)")
    if scheduler is not None and not scheduler.strip():
        raise click.BadParameter("an address such as tcp://host:8786, not an empty string", param_hint="--scheduler")
    distributed = (workers is not None and workers > 1) or scheduler is not None
    if replot_only and distributed:
        raise click.UsageError("--replot measures nothing: --workers and --scheduler do not apply")
    if replot_only:
        if not out.is_dir():
            fail(f"{out}: no such directory (--replot redraws the files of an earlier run there)")
        check_output_dir(out)
        with about(out):
            pages = replot(names, out)
        for page in pages:
            click.echo(f"rewrote {page} and {page.with_suffix('.png').name}")
        return
    sizes = parse_size_options(names, size_values)
    seed_list = _ints(seeds, "--seeds")
    backend_list = tuple(b.strip() for b in backends.split(",") if b.strip())
    dem_list = None if dems is None else tuple(d.strip() for d in dems.split(",") if d.strip())
    if dem_list is not None:
        unknown = [d for d in dem_list if d not in DEMS]
        if unknown or not dem_list:
            raise click.BadParameter(f"known DEMs: {', '.join(DEMS)}", param_hint="--dems")
    try:
        for n in names:
            sizes_for(n, quick=quick, override=sizes)
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="--sizes") from None
    check_output_dir(out)
    err = stderr_console()
    swept = [n for n in names if n in SWEPT]
    if distributed and not swept:
        err.print(f"note: --workers and --scheduler apply to {' and '.join(SWEPT)}; {', '.join(names)} run in this process", markup=False, highlight=False)
    if distributed and swept and (why := dask_missing()) is not None:
        fail(why)
    with connect(workers if distributed and swept else 1, scheduler if swept else None) as client, _bars(err) as bars:
        if client is not None:
            count = len(client.scheduler_info(n_workers=-1)["workers"])
            err.print(f"dask: {count} worker{'' if count == 1 else 's'}, dashboard {client.dashboard_link}", soft_wrap=True, highlight=False, markup=False)

        def progress_for(name: str) -> ProgressCallback:
            task = bars.add_task(name, total=None)

            def update(done: int, total: int, what: str) -> None:
                bars.update(task, completed=done, total=total, description=f"{name}: {what} ({_UNITS[name]})")

            return update

        summary = run_experiments(
            names,
            out,
            quick=quick,
            sizes=sizes,
            seeds=seed_list,
            backends=backend_list,
            repeat=repeat,
            dems=dem_list,
            progress=progress_for,
            client=client,
        )
    table = Table(title=Text(f"persistri experiments → {out}"))
    columns: tuple[tuple[str, JustifyMethod], ...] = (
        ("figure", "left"),
        ("sizes", "left"),
        ("wall-clock s", "right"),
        ("CPU s", "right"),
        ("files", "left"),
    )
    for col, justify in columns:
        table.add_column(col, justify=justify)
    for r in summary.runs:
        table.add_row(
            r.name,
            ", ".join(f"{n:,}" for n in r.sizes),
            f"{r.wall_seconds:.1f}",
            f"{r.cpu_seconds:.1f}",
            " ".join(p.name for p in r.files),
        )
    for note in summary.notes:
        err.print(f"note: {note}", markup=False, highlight=False)
    stdout_console().print(table)
    if summary.path is not None:
        click.echo(f"summary: {summary.path}")
