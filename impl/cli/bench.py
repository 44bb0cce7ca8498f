"""``persistri bench``: benchmarks that measure persistri against its peers in the same run.

A click group; each benchmark is a sub-command: here the structures' own
(``maps``, ``complex``) and the Dask scale-out (``scale``); the geometric
algorithms against their peers (``hull``, ``delaunay``, ``terrain``, ``mesh``)
are in :mod:`persistri.impl.cli.bench_geometry`.  The measuring code lives in
:mod:`persistri.impl.bench`; the commands parse options, show progress on
stderr and print results on stdout.
"""

from __future__ import annotations

import json
import zipfile
from pathlib import Path
from typing import Any

import click

from persistri.impl.bench import complex as bench_complex
from persistri.impl.bench.complex_report import print_complex
from persistri.impl.bench.maps import DEFAULT_REPEAT, DEFAULT_SEED, DEFAULT_SIZES, SUBJECTS, run_map_bench
from persistri.impl.bench.maps_report import print_maps
from persistri.impl.cli.bench_geometry import delaunay_, hull, mesh, terrain
from persistri.impl.cli.bench_options import parse_sizes, progress_bar, sizes_option
from persistri.impl.cli.checks import FILE_PATH, check_backend, check_input
from persistri.impl.cli.console import stderr_console, stdout_console
from persistri.impl.cli.errors import about, error_line, fail

__all__ = ["bench", "parse_sizes", "progress_bar", "stdout_console", "TRACE_FORMATS"]

TRACE_FORMATS = (".npz", ".json")
"""The formats of a saved trace (``bench complex --trace``)."""


@click.group(short_help="persistri against its peers, measured in the same run.")
def bench() -> None:
    """Measure persistri against its peers, in the same run (see each sub-command)."""


@bench.command("maps", short_help="insert, find, remove per map backend, against dict and peers.")
@click.option(
    "--sizes",
    default=",".join(str(n) for n in DEFAULT_SIZES),
    show_default=True,
    callback=sizes_option,
    help="Key counts, separated by commas.",
)
@click.option("--repeat", type=click.IntRange(min=1), default=DEFAULT_REPEAT, show_default=True, help="Timed runs per figure; the best is kept.")
@click.option("--seed", type=int, default=DEFAULT_SEED, show_default=True, help="Seed of the random key orders.")
@click.option(
    "--only",
    default=None,
    metavar="NAMES",
    help=f"Measure only these maps (comma-separated; dict always runs, as the baseline). Maps: {', '.join(s.name for s in SUBJECTS)}.",
)
@click.option("--json", "as_json", is_flag=True, help="Print the records as JSON instead of a table.")
def maps(sizes: tuple[int, ...], repeat: int, seed: int, only: str | None, as_json: bool) -> None:
    """Per-operation cost of insert, find and remove, for every map backend and its peers.

    Builds an n-key map from empty (a random permutation of range(n)), finds
    every key and removes every key (each in another random order), for
    persistri's backends, its adapters, Python's dict and the third-party
    persistent maps (immutables' C and pure-Python HAMTs, pyrsistent).  Prints
    µs per operation and the ratio to dict.  Exit status 1 if a map failed.
    The default sizes take tens of minutes (10^6 keys dominates); --sizes
    1000,10000 takes a few minutes (the association list at 10^4 dominates).
    """
    only_names = None if only is None else [name.strip() for name in only.split(",") if name.strip()]
    err = stderr_console()
    try:
        with progress_bar(err, "bench maps") as update:
            result = run_map_bench(sizes, repeat=repeat, seed=seed, only=only_names, on_progress=update)
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="--only") from None
    if as_json:
        click.echo(json.dumps(result.as_dict(), indent=2, ensure_ascii=False))
    else:
        print_maps(result, stdout_console())
    if result.errors():
        raise SystemExit(1)


@bench.command("complex", short_help="What persistence costs the 2-complex, per map backend.")
@click.option(
    "--sizes",
    default=",".join(str(n) for n in bench_complex.DEFAULT_SIZES),
    show_default=True,
    callback=sizes_option,
    help="Triangle counts of the spheres, separated by commas (rounded up to even).",
)
@click.option(
    "--workload",
    type=click.Choice(bench_complex.WORKLOADS),
    default="sphere",
    show_default=True,
    help="sphere: grown like a hull, without geometry (fast); hull: the bulldozer on OnSphere points (minutes at 10^5).",
)
@click.option(
    "--stepwise",
    is_flag=True,
    help="Generate the workload with a rem per removed and an add per added triangle (the paper's code) "
    "instead of one replace per step (the bulldozer's default).",
)
@click.option(
    "--trace",
    "trace_path",
    type=FILE_PATH,
    default=None,
    help="Replay this saved trace (.npz or .json, a closed 2-complex at its end) instead of a generated workload.",
)
@click.option("--repeat", type=click.IntRange(min=1), default=bench_complex.DEFAULT_REPEAT, show_default=True, help="Timed runs per figure; the best is kept.")
@click.option("--seed", type=int, default=bench_complex.DEFAULT_SEED, show_default=True, help="Seed of the workload.")
@click.option(
    "--only",
    default=None,
    metavar="NAMES",
    help=f"Measure only these complexes (comma-separated; ephemeral always runs, as the baseline). "
    f"Complexes: {', '.join(s.name for s in bench_complex.SUBJECTS)}.",
)
@click.option("--json", "as_json", is_flag=True, help="Print the records as JSON instead of a table.")
def complex_(
    sizes: tuple[int, ...],
    workload: str,
    stepwise: bool,
    trace_path: Path | None,
    repeat: int,
    seed: int,
    only: str | None,
    as_json: bool,
) -> None:
    """What persistence costs the 2-complex: a closed sphere built and walked on every backend and on the ephemeral baseline.

    Records (or loads) a trace of the SIMPCOMP operations that build a
    triangulated sphere, replays it on the 2-complex over each map backend and
    on the NOT persistent baseline over a dict, in the same run, then walks
    the final sphere across every edge.  Prints CPU seconds, µs per operation
    and the ratio to the baseline.  Exit status 1 if a complex failed.
    """
    from persistri.impl.complex.trace import TraceError, load_trace

    only_names = None if only is None else [name.strip() for name in only.split(",") if name.strip()]
    known = [s.name for s in bench_complex.SUBJECTS]
    unknown = [name for name in only_names or () if name not in known]
    if unknown:
        raise click.BadParameter(f"unknown complex {', '.join(unknown)}; known: {', '.join(known)}", param_hint="--only")
    trace = None
    if trace_path is not None:
        check_input(trace_path, TRACE_FORMATS, kind="trace")
        if trace_path.suffix.lower() == ".npz" and not zipfile.is_zipfile(trace_path):
            # numpy would try to unpickle it and say so: say what it is not.
            fail(f"{trace_path}: not a .npz archive (not a zip file, or a truncated one)")
        try:
            trace = load_trace(trace_path)
        except TraceError as exc:
            message = error_line(exc).removeprefix("load_trace: ")
            fail(message if str(trace_path) in message else f"{trace_path}: {message}")
    err = stderr_console()
    with about(trace_path), progress_bar(err, "bench complex") as update:
        result = bench_complex.run_complex_bench(
            sizes,
            workload="hull" if workload == "hull" else "sphere",
            stepwise=stepwise,
            trace=trace,
            repeat=repeat,
            seed=seed,
            only=only_names,
            on_progress=update,
        )
    if as_json:
        click.echo(json.dumps(result.as_dict(), indent=2, ensure_ascii=False))
    else:
        print_complex(result, stdout_console())
    if result.errors():
        raise SystemExit(1)


@bench.command("scale", short_help="The chunked hull and tiled terrain on 1 and 2 Dask workers.")
@click.option("-n", "--points", "n", type=click.IntRange(min=4), default=4_000_000, show_default=True, help="Points of the hull.")
@click.option("--dist", default="InBall", show_default=True, help="Their §4 distribution.")
@click.option("--chunk-size", "chunk_rows", type=click.IntRange(min=1), default=None, help="Points per chunk.  [default: one chunk per worker, 262,144 to 2,097,152 (chunk_rows_for)]")
@click.option("--workers", "worker_counts", default="1,2", show_default=True, callback=sizes_option, help="Worker counts to measure, separated by commas.")
@click.option("--terrain-size", type=click.IntRange(min=0), default=8000, show_default=True, help="Side of the synthetic DEM of the tiled-terrain rows (0: none).")
@click.option("--dir", "directory", type=FILE_PATH, default=None, help="Where the points and DEM files are written (and reused).  [default: a temporary directory]")
@click.option("--json", "as_json", is_flag=True, help="Print the records as JSON instead of tables.")
def scale(n: int, dist: str, chunk_rows: int | None, worker_counts: tuple[int, ...], terrain_size: int, directory: Path | None, as_json: bool) -> None:
    """The parallel side on local Dask clusters of 1 and 2 worker processes (docs/scale-out.md).

    The exact hull of --points points of --dist: one process (convex_hull) against
    parallel_hull on 1 and 2 workers: wall time, speed-up, peak resident memory per
    worker, and whether each result equals the one-process hull exactly.  Then the
    tiled terrain of a synthetic --terrain-size² DEM, by the same measures.  Needs
    persistri[dask].  Minutes at the defaults.
    """
    import dataclasses
    import tempfile

    from persistri.impl.bench.scale import hull_rows, hull_table, terrain_available, terrain_table
    from persistri.impl.hull.distributions import DISTRIBUTIONS
    from persistri.impl.scale import dask_missing

    if (why := dask_missing()) is not None:
        fail(why)
    if dist.lower() not in {d.lower() for d in DISTRIBUTIONS}:
        raise click.BadParameter(f"unknown distribution {dist!r}; known: {', '.join(DISTRIBUTIONS)}", param_hint="--dist")
    if directory is not None:
        from persistri.impl.cli.checks import check_output_dir

        check_output_dir(directory)
    err = stderr_console()
    with tempfile.TemporaryDirectory(prefix="persistri-bench-scale-") as scratch:
        folder = directory or Path(scratch)
        rows = hull_rows(folder, n=n, dist=dist, chunk_rows=chunk_rows, workers=worker_counts,
                         progress=lambda line: err.print(f"bench scale: {line}", highlight=False))
        terrain: tuple[list[Any], bool] | None = None
        if terrain_size and terrain_available():
            from persistri.impl.scale.terrain_bench import bench_rows

            err.print(f"bench scale: tiled terrain of a {terrain_size:,} × {terrain_size:,} DEM", highlight=False)
            terrain = bench_rows(folder, size=terrain_size, workers=worker_counts)
    if as_json:
        out: dict[str, Any] = {"hull": [dataclasses.asdict(r) for r in rows]}
        if terrain is not None:
            out["terrain"] = {"rows": [dataclasses.asdict(r) for r in terrain[0]], "same": terrain[1]}
        click.echo(json.dumps(out, indent=2, ensure_ascii=False))
    else:
        console = stdout_console()
        console.print(hull_table(rows, f"exact hull of {n:,} {dist} points"))
        if terrain is not None:
            console.print(terrain_table(terrain[0], terrain[1], f"tiled terrain of a {terrain_size:,} × {terrain_size:,} DEM"))
        elif terrain_size:
            console.print("tiled terrain: not measured (persistri.impl.scale.terrain_bench is not installed)")
    if not all(r.same for r in rows) or (terrain is not None and not terrain[1]):
        raise SystemExit(1)


for _command in (hull, delaunay_, terrain, mesh):
    bench.add_command(_command)
