"""``persistri bench``: benchmarks that measure persistri against its peers in the same run.

A click group; each benchmark is a sub-command (``maps``, ``complex``, ``hull``,
``terrain``, ``delaunay`` and ``mesh``).  The measuring code lives in
:mod:`persistri.impl.bench`; the commands parse options, show progress on
stderr and print results on stdout.
"""

from __future__ import annotations

import json
import math
import zipfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import click
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

from persistri.impl.bench import complex as bench_complex
from persistri.impl.bench.complex_report import print_complex
from persistri.impl.bench.maps import DEFAULT_REPEAT, DEFAULT_SEED, DEFAULT_SIZES, SUBJECTS, ProgressCallback, run_map_bench
from persistri.impl.bench.maps_report import print_maps
from persistri.impl.cli.checks import check_backend, check_input
from persistri.impl.cli.console import stderr_console, stdout_console
from persistri.impl.cli.errors import about, error_line, fail

__all__ = ["bench", "parse_sizes", "progress_bar", "stdout_console", "TRACE_FORMATS"]

TRACE_FORMATS = (".npz", ".json")
"""The formats of a saved trace (``bench complex --trace``)."""


def parse_sizes(text: str) -> tuple[int, ...]:
    """``"1000,100_000,1e6"`` → ``(1000, 100000, 1000000)``: positive integers separated by commas.

    Raises :class:`click.BadParameter` naming the bad item.
    """
    sizes: list[int] = []
    for item in text.split(","):
        item = item.strip()
        try:
            value = float(item) if "e" in item.lower() else int(item)
        except ValueError:
            raise click.BadParameter(f"{item!r} is not a key count (give integers separated by commas)") from None
        if value != int(value) or int(value) < 1:
            raise click.BadParameter(f"{item!r} is not a positive integer")
        sizes.append(int(value))
    return tuple(sizes)


def _sizes_option(ctx: click.Context, param: click.Parameter, value: str) -> tuple[int, ...]:
    return parse_sizes(value)


@contextmanager
def progress_bar(console: Console, title: str) -> Iterator[ProgressCallback]:
    """A rich progress bar on ``console`` for the duration of the block, fed by the callback it yields.

    The bar is transient (erased when done) and drawn only when ``console`` is
    a terminal (off one, rich would leave a blank line).
    """
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
    with Progress(*columns, console=console, transient=True, disable=not console.is_terminal) as progress:
        task = progress.add_task(title, total=None)

        def update(done: int, total: int, what: str) -> None:
            progress.update(task, completed=done, total=total, description=f"{title}: {what}")

        yield update


@click.group()
def bench() -> None:
    """Measure persistri against its peers, in the same run (see each sub-command)."""


@bench.command("maps")
@click.option(
    "--sizes",
    default=",".join(str(n) for n in DEFAULT_SIZES),
    show_default=True,
    callback=_sizes_option,
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


@bench.command("terrain")
@click.option(
    "--sizes",
    default=None,
    help="Vertex counts, separated by commas [default: 1600,3200,6400,12800 unless --max-error or --relief is given].",
)
@click.option("--max-error", type=click.FloatRange(min=0.0, min_open=True), default=None, help="Also refine both meshers to this maximum error (height units) and compare their times.")
@click.option("--relief", "relief_fraction", type=click.FloatRange(min=0.0, max=1.0, min_open=True), default=None, help="As --max-error, as a fraction of the grid's relief (0.01: 1 %).")
@click.option("--peak-memory", is_flag=True, help="With --max-error/--relief: the peak memory of each mesher, each run in a fresh process (Linux).")
@click.option("--repeat", type=click.IntRange(min=1), default=1, show_default=True, help="Timed runs per figure; the best is kept.")
@click.option("--backend", default="red_black", show_default=True, help="ORD_MAP backend of the complex.")
@click.option("--memory", is_flag=True, help="Also measure the memory of keeping every level of detail (tracemalloc; slow).")
@click.option("--grid", "grid_source", default="jacksboro", show_default=True, help="The height grid: jacksboro, synthetic[:SIZE[:SEED]] or a grid file.")
@click.option("--json", "as_json", is_flag=True, help="Print the records as JSON instead of a table.")
def terrain(
    sizes: str | None,
    max_error: float | None,
    relief_fraction: float | None,
    peak_memory: bool,
    repeat: int,
    backend: str,
    memory: bool,
    grid_source: str,
    as_json: bool,
) -> None:
    """Greedy insertion on the Jacksboro DEM (or --grid) against pydelatin, in the same run (paper §5, Fig. 11).

    For each size: pydelatin's time and vertex count, persistri's time to the
    same vertex count, both maximum errors (recomputed over every sample), and
    persistri's key comparisons, dictionary operations, plane-side tests and
    flops.  --memory adds the memory kept with every level of detail against
    the final mesh alone.  --max-error (or --relief) refines both meshers to
    that error and compares their times instead; --peak-memory adds their peak
    memory.  --grid synthetic:2048 is a 2,048 × 2,048 fractal terrain
    (persistri.impl.terrain.synthetic).
    """
    from persistri.impl.bench.terrain import run_terrain_bench, terrain_table
    from persistri.impl.bench.terrain_target import relief, run_to_error, target_table
    from persistri.impl.terrain.grids import GRID_FORMATS, as_heights, read_grid
    from persistri.impl.terrain.synthetic import parse_synthetic, synthetic_dem

    err = stderr_console()
    target = max_error is not None or relief_fraction is not None
    if max_error is not None and relief_fraction is not None:
        fail("give --max-error or --relief, not both")
    if peak_memory and not target:
        fail("--peak-memory measures a run to --max-error or --relief: give one of them")
    size_list = parse_sizes(sizes) if sizes is not None else (() if target else parse_sizes("1600,3200,6400,12800"))
    try:
        synthetic = parse_synthetic(grid_source)
    except ValueError as exc:
        fail(str(exc))
    check_backend(backend)
    if synthetic is not None:
        grid = synthetic_dem(synthetic[0], seed=synthetic[1])
    else:
        check_input(Path(grid_source), GRID_FORMATS, kind="grid", words=("jacksboro",))
        grid = read_grid(grid_source)
    name = grid_source.lower() if synthetic is None and grid_source.lower() == "jacksboro" else grid_source
    out: dict[str, object] = {}
    renderables: list[object] = []
    with about(grid_source), progress_bar(err, "bench terrain") as update:
        if target:
            h = as_heights(grid.heights, what=name)
            e = max_error if max_error is not None else float(relief_fraction) * relief(h)  # type: ignore[arg-type]
            update(0, 1, f"both meshers to a maximum error of {e:.4g}")
            record = run_to_error(h, e, grid_name=name, backend=backend, repeat=repeat, peak=peak_memory)
            out["to_error"] = [record.as_dict()]
            renderables.append(target_table([record]))
        if size_list:
            result = run_terrain_bench(
                size_list, heights=grid.heights, grid_name=name, backend=backend, repeat=repeat, memory=memory,
                on_progress=update,
            )
            out.update(result.as_dict())
            renderables.append(terrain_table(result))
    if as_json:
        click.echo(json.dumps(out, indent=2, ensure_ascii=False))
    else:
        console = stdout_console()
        for r in renderables:
            console.print(r)


@bench.command("delaunay")
@click.option(
    "--sizes",
    default="10000,100000",
    show_default=True,
    callback=_sizes_option,
    help="Point counts, separated by commas.",
)
@click.option("--repeat", type=click.IntRange(min=1), default=1, show_default=True, help="Timed runs per figure; the best is kept.")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the points and of the insertion order.")
@click.option("--backend", default="red_black", show_default=True, help="ORD_MAP backend of the complex.")
@click.option("--json", "as_json", is_flag=True, help="Print the records as JSON instead of a table.")
def delaunay_(sizes: tuple[int, ...], repeat: int, seed: int, backend: str, as_json: bool) -> None:
    """Exact 2D Delaunay of uniform random points against scipy.spatial.Delaunay (Qhull), in the same run.

    For each size: scipy's time, persistri's time, their ratio and both
    triangle counts; the caption names the build that ran (interpreted or the
    compiled twin).
    """
    from persistri.impl.bench.delaunay import delaunay_table, run_delaunay_bench

    check_backend(backend)
    if min(sizes) < 3:
        fail("--sizes: a triangulation needs at least 3 points")
    err = stderr_console()
    with progress_bar(err, "bench delaunay") as update:
        result = run_delaunay_bench(sizes, seed=seed, backend=backend, repeat=repeat, on_progress=update)
    if as_json:
        click.echo(json.dumps(result.as_dict(), indent=2, ensure_ascii=False))
    else:
        stdout_console().print(delaunay_table(result))


@bench.command("complex")
@click.option(
    "--sizes",
    default=",".join(str(n) for n in bench_complex.DEFAULT_SIZES),
    show_default=True,
    callback=_sizes_option,
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
    type=click.Path(path_type=Path),
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


@bench.command("hull")
@click.option(
    "--sizes",
    default="16384,65536,262144",
    show_default=True,
    callback=_sizes_option,
    help="Point counts, separated by commas.",
)
@click.option(
    "--dists",
    default="OnSphere,EqHeavy,PolHeavy,InBall,BordHeavy",
    show_default=True,
    help="Distributions of the paper's §4, separated by commas.",
)
@click.option(
    "--backends",
    default="red_black",
    show_default=True,
    help="ORD_MAP backends of the complex, separated by commas (the ephemeral baseline always runs too).",
)
@click.option("--repeat", type=click.IntRange(min=1), default=1, show_default=True, help="Timed runs per figure; the best is kept.")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the points and of the insertion order.")
@click.option("--memory", is_flag=True, help="Also measure the memory of keeping every intermediate hull (tracemalloc; slow).")
@click.option("--memory-n", type=click.IntRange(min=4), default=16384, show_default=True, help="Points for --memory.")
@click.option("--memory-dist", default="InBall", show_default=True, help="Distribution for --memory.")
@click.option("--json", "as_json", is_flag=True, help="Print the records as JSON instead of a table.")
def hull(
    sizes: tuple[int, ...],
    dists: str,
    backends: str,
    repeat: int,
    seed: int,
    memory: bool,
    memory_n: int,
    memory_dist: str,
    as_json: bool,
) -> None:
    """The exact bulldozer hull against scipy's Qhull, per distribution and size, in the same run.

    For each distribution and point count: Qhull's time, persistri's time on
    each backend and on the ephemeral (dict, NOT persistent) baseline, the
    ratios to Qhull and to the baseline, µs per insertion, and whether the
    vertex sets agree.  --memory adds the memory of keeping every intermediate
    hull (bytes the versions hold per inserted point, and the whole run against
    keeping the final hull only).  The default sizes take many minutes (256K
    points dominate).
    """
    from persistri.impl.bench.hull import hull_table, run_hull_bench

    dist_names = tuple(d.strip() for d in dists.split(",") if d.strip())
    backend_names = tuple(b.strip() for b in backends.split(",") if b.strip())
    for name in backend_names:
        check_backend(name)
    err = stderr_console()
    with progress_bar(err, "bench hull") as update:
        result = run_hull_bench(
            sizes,
            dists=dist_names,
            backends=backend_names,
            repeat=repeat,
            seed=seed,
            memory=memory,
            memory_n=memory_n,
            memory_dist=memory_dist,
            on_progress=update,
        )
    if as_json:
        click.echo(json.dumps(result.as_dict(), indent=2, ensure_ascii=False))
    else:
        stdout_console().print(hull_table(result))


def _angles_option(ctx: click.Context, param: click.Parameter, value: str) -> tuple[float, ...]:
    angles: list[float] = []
    for item in value.split(","):
        try:
            angle = float(item.strip())
        except ValueError:
            raise click.BadParameter(f"{item.strip()!r} is not a number of degrees (give numbers separated by commas)") from None
        if not 0.0 <= angle < 60.0:
            raise click.BadParameter(f"{item.strip()} is not an angle bound in [0, 60) degrees")
        angles.append(angle)
    return tuple(angles)


@bench.command("mesh")
@click.option(
    "--domains",
    default=None,
    metavar="NAMES",
    help="Gallery domains, separated by commas (default: all: square-hole, l-shape, star, circle, crack, utm-tile, comb, needle, fan).",
)
@click.option("--angles", default="20,30,33", show_default=True, callback=_angles_option, help="Minimum-angle bounds in degrees, separated by commas.")
@click.option("--max-area", type=click.FloatRange(min=0, min_open=True), default=None, help="Also bound every triangle's area by this, on every domain.")
@click.option(
    "--size",
    type=click.IntRange(min=1),
    default=None,
    help="Instead of --max-area: bound each domain's triangles by its area / SIZE (about SIZE to 2 SIZE triangles).",
)
@click.option("--repeat", type=click.IntRange(min=1), default=5, show_default=True, help="Timed rounds per figure; the best is kept.")
@click.option("--json", "as_json", is_flag=True, help="Print the records as JSON instead of a table.")
def mesh(domains: str | None, angles: tuple[float, ...], max_area: float | None, size: int | None, repeat: int, as_json: bool) -> None:
    """Ruppert's refinement, undone by persistence, against Shewchuk's Triangle on the gallery domains, in the same run.

    For each domain and angle bound: triangles, vertices and the smallest angle
    (outside Ruppert's exemption at small input angles) of Triangle's mesh
    (pq<angle>) and of persistri's, whether each passes the exact checker with
    the bounds, persistri's undos, the ratio of the triangle counts and of the
    CPU times (best of --repeat).  --size 10000 compares at 10^4-10^5
    triangles (minutes).  Needs the triangle package (pip install triangle).
    Exit status 1 if a persistri mesh fails the checker.
    """
    from persistri.impl.bench.mesh import TriangleMissingError, mesh_table, run_mesh_bench
    from persistri.impl.mesh.gallery import GALLERY

    if max_area is not None and size is not None:
        raise click.UsageError("give --max-area or --size, not both")
    if max_area is not None and not math.isfinite(max_area):
        raise click.BadParameter(f"{max_area} is not a finite area", param_hint="--max-area")
    names = None if domains is None else tuple(d.strip().lower() for d in domains.split(",") if d.strip())
    unknown = [d for d in names or () if d not in GALLERY]
    if unknown or names == ():
        raise click.BadParameter(
            f"unknown gallery domain {', '.join(unknown) or '(none given)'}; the domains are {', '.join(GALLERY)}",
            param_hint="--domains",
        )
    err = stderr_console()
    try:
        with progress_bar(err, "bench mesh") as update:
            result = run_mesh_bench(names, angles, max_area=max_area, size=size, repeat=repeat, on_progress=update)
    except TriangleMissingError as exc:
        fail(str(exc))
    if as_json:
        click.echo(json.dumps(result.as_dict(), indent=2, ensure_ascii=False))
    else:
        stdout_console().print(mesh_table(result))
    if result.errors():
        raise SystemExit(1)


@bench.command("scale")
@click.option("-n", "--points", "n", type=click.IntRange(min=4), default=4_000_000, show_default=True, help="Points of the hull.")
@click.option("--dist", default="InBall", show_default=True, help="Their §4 distribution.")
@click.option("--chunk-size", "chunk_rows", type=click.IntRange(min=1), default=None, help="Points per chunk.  [default: one chunk per worker, 262,144 to 2,097,152 (chunk_rows_for)]")
@click.option("--workers", "worker_counts", default="1,2", show_default=True, callback=_sizes_option, help="Worker counts to measure, separated by commas.")
@click.option("--terrain-size", type=click.IntRange(min=0), default=8000, show_default=True, help="Side of the synthetic DEM of the tiled-terrain rows (0: none).")
@click.option("--dir", "directory", type=click.Path(path_type=Path), default=None, help="Where the points and DEM files are written (and reused).  [default: a temporary directory]")
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
