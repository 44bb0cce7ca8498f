"""``persistri bench hull | delaunay | terrain | mesh``: the geometric algorithms against their C/C++ peers.

Each command runs persistri and its peer in the same process and prints the
ratio: the bulldozer hull against Qhull (scipy's ``ConvexHull``), the
scattered Delaunay triangulation against scipy's ``Delaunay``, the greedy
terrain mesher against pydelatin, and Ruppert's refinement against
Shewchuk's Triangle.  The measuring code lives in :mod:`persistri.impl.bench`;
:mod:`persistri.impl.cli.bench` adds these commands to its group.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import click

from persistri.impl.cli.bench_options import parse_sizes, progress_bar, sizes_option
from persistri.impl.cli.checks import check_backend, check_input
from persistri.impl.cli.console import stderr_console, stdout_console
from persistri.impl.cli.errors import about, fail

__all__ = ["delaunay_", "hull", "mesh", "terrain"]


@click.command("terrain", short_help="Greedy insertion against pydelatin (paper §5, Fig. 11).")
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
@click.option("--sweep", type=click.IntRange(min=0), default=24, show_default=True, help="Vertex counts, log-spaced from the smallest size to the largest, at which both maximum errors are compared (0: none).")
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
    sweep: int,
    grid_source: str,
    as_json: bool,
) -> None:
    """Greedy insertion on the Jacksboro DEM (or --grid) against pydelatin, in the same run (paper §5, Fig. 11).

    For each size: pydelatin's time and vertex count, persistri's time to the
    same vertex count, both maximum errors (recomputed over every sample), and
    persistri's key comparisons, dictionary operations, plane-side tests and
    flops; then both maximum errors at --sweep vertex counts between the
    smallest size and the largest (their ratio's median and quartiles, and
    how often persistri's mesh is better, equal or worse).  --memory adds the memory kept with every level of detail against
    the final mesh alone.  --max-error (or --relief) refines both meshers to
    that error and compares their times instead; --peak-memory adds their peak
    memory.  --grid synthetic:2048 is a 2,048 × 2,048 fractal terrain
    (persistri.impl.terrain.synthetic).  Needs the pydelatin package (pip
    install pydelatin).
    """
    from persistri.impl.bench.terrain import run_terrain_bench, terrain_table
    from persistri.impl.bench.terrain_target import relief, run_to_error, target_table
    from persistri.impl.terrain.grids import GRID_FORMATS, as_heights, read_grid
    from persistri.impl.terrain.synthetic import parse_synthetic, synthetic_dem

    try:
        import pydelatin  # noqa: F401  (the peer: checked before anything is read or measured)
    except ImportError:
        fail("bench terrain compares with pydelatin, which is not installed: pip install pydelatin (or pip install 'persistri[dev]')")
    err = stderr_console()
    target = max_error is not None or relief_fraction is not None
    if max_error is not None and relief_fraction is not None:
        fail("give --max-error or --relief, not both")
    if peak_memory and not target:
        fail("--peak-memory measures a run to --max-error or --relief: give one of them")
    try:
        size_list = parse_sizes(sizes, "vertex count") if sizes is not None else (() if target else parse_sizes("1600,3200,6400,12800"))
    except click.BadParameter as exc:  # parsed here, not by a callback: name the option as click would
        exc.param_hint = "'--sizes'"
        raise
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
                sweep=sweep, on_progress=update,
            )
            out.update(result.as_dict())
            renderables.append(terrain_table(result))
    if as_json:
        click.echo(json.dumps(out, indent=2, ensure_ascii=False))
    else:
        console = stdout_console()
        for r in renderables:
            console.print(r)


@click.command("delaunay", short_help="Exact 2D Delaunay against scipy's Delaunay (Qhull).")
@click.option(
    "--sizes",
    default="10000,100000",
    show_default=True,
    callback=sizes_option,
    help="Point counts, separated by commas.",
)
@click.option("--repeat", type=click.IntRange(min=1), default=1, show_default=True, help="Timed runs per figure; the best is kept.")
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True, help="Seed of the points and of the insertion order.")
@click.option("--backend", default="int_trie", show_default=True, help="ORD_MAP backend of the complex.")
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


@click.command("hull", short_help="The exact bulldozer hull against scipy's Qhull.")
@click.option(
    "--sizes",
    default="16384,65536,262144",
    show_default=True,
    callback=sizes_option,
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
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True, help="Seed of the points and of the insertion order.")
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

    if min(sizes) < 4:
        raise click.BadParameter(f"{min(sizes)}: a 3D hull needs at least 4 points", param_hint="'--sizes'")
    dist_names = tuple(_distribution(d.strip(), "--dists") for d in dists.split(",") if d.strip())
    if not dist_names:
        raise click.BadParameter("give at least one distribution", param_hint="'--dists'")
    if memory:
        memory_dist = _distribution(memory_dist, "--memory-dist")
    backend_names = tuple(b.strip() for b in backends.split(",") if b.strip())
    if not backend_names:
        raise click.BadParameter("give at least one backend", param_hint="'--backends'")
    for name in backend_names:
        check_backend(name, "--backends")
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


def _distribution(name: str, option: str) -> str:
    """The §4 distribution ``name`` in its own spelling (any case, as ``persistri hull --dist`` takes it);
    a usage error naming ``option`` for another name."""
    from persistri.impl.hull.distributions import DISTRIBUTIONS

    for known in DISTRIBUTIONS:
        if known.lower() == name.lower():
            return known
    raise click.BadParameter(f"unknown distribution {name!r}; known: {', '.join(DISTRIBUTIONS)}", param_hint=f"'{option}'")


TRIANGLE_MAX_ANGLE = 34.0
"""The largest ``--angles`` bound of ``bench mesh``: Triangle's documentation says it often succeeds up to
34° and may never finish above (on the square with a hole it runs for ever at 40°), and a benchmark whose
peer never returns measures nothing.  ``persistri mesh --min-angle`` takes bounds up to 60°."""


def _angles_option(ctx: click.Context, param: click.Parameter, value: str) -> tuple[float, ...]:
    angles: list[float] = []
    for item in value.split(","):
        try:
            angle = float(item.strip())
        except ValueError:
            raise click.BadParameter(f"{item.strip()!r} is not a number of degrees (give numbers separated by commas)") from None
        if not 0.0 <= angle < 60.0:
            raise click.BadParameter(f"{item.strip()} is not an angle bound in [0, 60) degrees")
        if angle > TRIANGLE_MAX_ANGLE:
            raise click.BadParameter(
                f"{item.strip()}° is above {TRIANGLE_MAX_ANGLE:g}°, where Shewchuk's Triangle (the peer) may never finish "
                f"(its documentation: it often succeeds up to {TRIANGLE_MAX_ANGLE:g}°); persistri mesh --min-angle takes bounds up to 60°"
            )
        angles.append(angle)
    return tuple(angles)


@click.command("mesh", short_help="Ruppert's refinement against Shewchuk's Triangle.")
@click.option(
    "--domains",
    default=None,
    metavar="NAMES",
    help="Gallery domains, separated by commas (default: all: square-hole, l-shape, star, circle, crack, utm-tile, comb, needle, fan).",
)
@click.option(
    "--angles", default="20,30,33", show_default=True, callback=_angles_option,
    help="Minimum-angle bounds in degrees, separated by commas (at most 34: Triangle may never finish above).",
)
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
