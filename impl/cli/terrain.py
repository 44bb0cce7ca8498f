"""``persistri terrain``: mesh a height grid by greedy insertion on the persistent Delaunay triangulation (paper §5)."""

from __future__ import annotations

import math
from pathlib import Path

import click
import numpy as np

from persistri.impl.cli.checks import FILE_OR_NAME, FILE_PATH, PLOT_FORMATS, Outputs, check_backend, check_input, check_output_dir
from persistri.impl.cli.console import count_noun, stderr_console, stdout_console
from persistri.impl.cli.errors import about, error_line, fail, one_line
from persistri.impl.cli.hull import stats_table
from persistri.impl.maps import BACKENDS
from persistri.impl.stats import Stats
from persistri.impl.terrain.export import TIN_FORMATS, sidecar_wkt, write_tin
from persistri.impl.terrain.grids import GRID_FORMATS, NODATA_RULES, read_grid

__all__ = ["terrain", "TERRAIN_MESH_FORMATS", "parse_nodata"]

TERRAIN_MESH_FORMATS = TIN_FORMATS
"""Output formats of ``persistri terrain`` (by extension)."""


def parse_nodata(text: str) -> str | float:
    """``--nodata`` as :func:`persistri.impl.terrain.grids.as_heights` takes it: a rule name or a height.

    Raises :class:`click.BadParameter` (a usage error) for anything else.
    """
    if text in NODATA_RULES:
        return text
    try:
        value = float(text)
    except ValueError:
        raise click.BadParameter(f"{text} is neither {', '.join(NODATA_RULES)} nor a height") from None
    if not np.isfinite(value):
        raise click.BadParameter(f"{text} is not a finite height")
    return value


def _nodata_option(ctx: click.Context, param: click.Parameter, value: str) -> str | float:
    return parse_nodata(value)


@click.command("terrain", short_help="A TIN of a height grid, to a max error or a vertex count.")
@click.argument("source", metavar="INPUT", type=FILE_OR_NAME)
@click.option("--max-error", type=click.FloatRange(min=0), help="Stop once every sample is within this vertical distance.")
@click.option("--max-points", type=click.IntRange(min=4), help="Stop once the mesh has this many vertices.")
@click.option("-o", "--output", type=FILE_PATH, help=f"Output mesh ({', '.join(TERRAIN_MESH_FORMATS)}).")
@click.option(
    "--plot",
    type=FILE_PATH,
    help=f"Draw the mesh over the shaded relief to this image ({', '.join(PLOT_FORMATS)}).",
)
@click.option(
    "--nodata",
    default="error",
    show_default=True,
    callback=_nodata_option,
    help="No-data (NaN) cells: error, fill (nearest valid cell), min (lowest valid height) or a height.",
)
@click.option(
    "--world",
    is_flag=True,
    help="Write the mesh in the input's world coordinates (.asc, GeoTIFF, jacksboro), counterclockwise seen from "
    "above, with the input's CRS (a .prj beside a .ply/.obj/.stl/.off).",
)
@click.option("--backend", default="red_black", show_default=True, help=f"ORD_MAP backend of the complex ({', '.join(BACKENDS)}).")
@click.option("--check", is_flag=True, help="Assert the insertion invariants and verify the mesh exactly.")
@click.option("--stats", "show_stats", is_flag=True, help="Print the operation counts (paper §4–5) as a table.")
@click.option("--quiet", is_flag=True, help="No progress bar and no summary.")
@click.option(
    "--workers",
    type=click.IntRange(min=1),
    help="Mesh by tiles on a local Dask cluster of N worker processes (1: tiles in this process). "
    "Without --tile, --workers or --scheduler: one process, no tiles.",
)
@click.option(
    "--tile",
    type=click.IntRange(min=3),
    help="Mesh by tiles of SIZE × SIZE samples (neighbours share a row or column), seams decided first, so "
    "the mesh is watertight and --max-error holds at every sample; .npy, .tif and .zarr are read in windows.",
)
@click.option(
    "--scheduler",
    metavar="ADDR",
    help="Mesh by tiles on an existing Dask cluster (tcp://host:8786; also PERSISTRI_SCHEDULER with --tile).",
)
@click.option(
    "--tile-output",
    type=FILE_PATH,
    help="With tiles: also write each tile's mesh to this directory (tile_I_J.npz, whole-grid coordinates).",
)
def terrain(
    source: str,
    max_error: float | None,
    max_points: int | None,
    output: Path | None,
    plot: Path | None,
    nodata: str | float,
    world: bool,
    backend: str,
    check: bool,
    show_stats: bool,
    quiet: bool,
    workers: int | None,
    tile: int | None,
    scheduler: str | None,
    tile_output: Path | None,
) -> None:
    """Approximate the height grid INPUT by a Delaunay TIN, greedily (Garland–Heckbert).

    INPUT is a grid file (.npy, .npz, .asc, .csv/.txt rows of heights, also .gz, .tif/.tiff, a grayscale
    .png heightmap) or the word jacksboro (the DEM shipped with matplotlib).  Give --max-error,
    --max-points or both.

    Vertices are x = column, y = row, z = height (row 0 is the grid's first row),
    triangles counterclockwise in (x, y).  With --world they are in the input's
    world coordinates (GeoTIFF tie point and pixel scale, .asc corner and cell
    size) and the triangles are counterclockwise seen from above there too, so
    normals point up (+z) for north-up and south-up rasters alike.

    OUTPUT by extension: .ply, .obj, .stl, .off (only the vertices the triangles
    use), or .npz with the arrays vertices, triangles, samples (the flat grid
    index row * cols + col of each vertex), grid_shape, max_error, rms_error,
    world, and for a georeferenced input transform (x0, y0, dx, dy) and crs
    (EPSG:nnnn or WKT).  The CRS comes from the GeoTIFF's GeoKeys or from a .prj
    beside an .asc; with --world a .ply/.obj/.stl/.off gets it as WKT in a .prj
    file of the same name (mesh.ply -> mesh.prj).  GeoTIFFs, compressed or
    not (LZW, deflate, zstd, PackBits; tiled or in strips), need pip install
    'persistri[geotiff]'.

    With --tile (or --workers N ≥ 2, or --scheduler) the grid is meshed by
    tiles on Dask (pip install 'persistri[dask]'): each seam between tiles is
    decided once, each tile meshed from its seams, and the tiles stitched into
    one watertight mesh with --max-error at every sample.  .npy, .tif/.tiff and
    .zarr inputs are read in windows, so a worker holds one tile, not the grid.
    """
    from persistri.impl.terrain.greedy import greedy_insertion

    err = stderr_console()
    if max_error is None and max_points is None:
        raise click.UsageError("give --max-error, --max-points or both")
    if max_error is not None and not math.isfinite(max_error):
        raise click.BadParameter(f"{max_error} is not a finite height", param_hint="--max-error")
    if tile is not None or scheduler is not None or (workers is not None and workers > 1) or tile_output is not None:
        _tiled(source, max_error, max_points, output, plot, nodata, world, backend, check, show_stats, quiet,
               workers, tile, scheduler, tile_output)
        return
    check_input(Path(source), GRID_FORMATS, kind="grid", words=("jacksboro",))
    outputs = Outputs([source])
    outputs.file(output, TERRAIN_MESH_FORMATS, what="mesh")
    outputs.file(plot, PLOT_FORMATS, what="plot")
    check_backend(backend)
    grid = read_grid(source)
    if world and grid.transform is None:
        fail(f"{source}: --world needs georeferencing, and this input has none")
    if output is not None:
        with about(output):
            wkt = sidecar_wkt(output, grid.crs, world=world)  # a CRS that cannot be written fails before the run
        if wkt is not None:  # its .prj beside the mesh: checked as an output too, before the run
            outputs.file(output.with_suffix(".prj"), (".prj",), what="projection")
    missing = np.isnan(grid.heights)
    if nodata == "error" and bool(missing.any()):
        row, col = (int(v) for v in np.argwhere(missing)[0])
        fail(_no_data(source, int(missing.sum()), row, col))
    stats = Stats() if show_stats else None
    with about(source):
        tin = greedy_insertion(
            grid.heights,
            max_error=max_error,
            max_points=max_points,
            backend=backend,
            check=check,
            stats=stats,
            progress=not quiet,
            transform=grid.transform,
            nodata=nodata,
        )
    written: list[Path] = []
    with outputs.staged() as stage:
        if output is not None:
            files = write_tin(stage(output), tin, world=world, sidecar_at=output.with_suffix(".prj"))
            written = [stage.target(w) for w in files]
        if plot is not None:
            from persistri.impl.terrain.plot import plot_tin

            heights = np.nan_to_num(grid.heights, nan=float(np.nanmin(grid.heights)))
            name = "jacksboro" if source.lower() == "jacksboro" else Path(source).name
            plot_tin(heights, tin.vertices, tin.triangles, stage(plot),
                     title=f"{name}: {tin.n_points:,} points, max error {tin.max_error:.4g}")
    if not quiet:
        verified = " (verified exactly)" if check else ""
        rows, cols = tin.shape
        err.print(
            one_line(
                f"terrain {source} ({rows} × {cols}): {tin.n_points:,} points, {len(tin.triangles):,} triangles, "
                f"max error {tin.max_error:.6g}, rms {tin.rms_error:.6g}{verified}"
            )
        )
        if written:
            where = "grid coordinates" if not world else "world coordinates" + (
                f", CRS {tin.crs.label}" if tin.crs is not None else ", no CRS read from the input"
            )
            err.print(one_line(f"wrote {', '.join(str(w) for w in written)} ({where})"))
    if show_stats and tin.stats is not None:
        stdout_console().print(stats_table(tin.stats, f"operation counts ({backend})"))
    if output is None and plot is None and quiet:
        click.echo(f"{tin.n_points} points, {len(tin.triangles)} triangles, max error {tin.max_error:.6g}")


def _no_data(source: str, count: int, row: int, col: int) -> str:
    """The one line for a grid with no-data cells and ``--nodata error`` (the default)."""
    return (
        f"{source}: {count} no-data cell{'s' if count != 1 else ''} (NaN), the first at (row {row}, col {col}); "
        "say how to treat them: --nodata fill, min or a height"
    )


def _tiled(
    source: str,
    max_error: float | None,
    max_points: int | None,
    output: Path | None,
    plot: Path | None,
    nodata: str | float,
    world: bool,
    backend: str,
    check: bool,
    show_stats: bool,
    quiet: bool,
    workers: int | None,
    tile: int | None,
    scheduler: str | None,
    tile_output: Path | None,
) -> None:
    """``persistri terrain`` by tiles on Dask (:func:`persistri.impl.scale.terrain.tiled_terrain`): everything that
    can be checked is checked before a cluster is started."""
    err = stderr_console()
    if max_error is None or max_points is not None:
        fail("meshing by tiles needs --max-error and no --max-points: each tile stops at the error bound, "
             "and a point budget has no meaning across tiles")
    for given, name in ((plot is not None, "--plot"), (check, "--check"), (show_stats, "--stats")):
        if given:
            fail(f"{name} is not available when meshing by tiles (--tile, --workers N ≥ 2 or --scheduler)")
    if workers is not None and scheduler is not None:
        fail("give either --workers or --scheduler, not both (a cluster has its own workers)")
    from persistri.impl.scale import dask_missing

    if (why := dask_missing()) is not None:  # the modules below import Dask only when they run: ask first
        fail(f"meshing by tiles needs Dask: {why}")
    try:
        from persistri.impl.scale.cluster import ClusterError, connect
        from persistri.impl.scale.terrain import DEFAULT_TILE, MissingHeights, tiled_terrain, write_tile_meshes
        from persistri.impl.scale.terrain_source import LAZY_FORMATS, open_dem
    except ImportError as exc:
        fail(f"meshing by tiles needs Dask: pip install 'persistri[dask]' ({exc})")
    path = Path(source)
    if not (path.suffix.lower() == ".zarr" and path.is_dir()):
        check_input(path, (*GRID_FORMATS, *LAZY_FORMATS), kind="grid", words=("jacksboro",))
    outputs = Outputs([source])
    outputs.file(output, TERRAIN_MESH_FORMATS, what="mesh")
    if tile_output is not None:
        check_output_dir(tile_output)
    check_backend(backend)
    with about(source):
        dem = open_dem(source)
    if world and dem.transform is None:
        fail(f"{source}: --world needs georeferencing, and this input has none")
    if output is not None:
        with about(output):
            wkt = sidecar_wkt(output, dem.transform.crs if dem.transform is not None else None, world=world)
        if wkt is not None:  # its .prj beside the mesh: checked before the cluster starts
            outputs.file(output.with_suffix(".prj"), (".prj",), what="projection")
    size = DEFAULT_TILE if tile is None else tile
    try:
        with connect(workers, scheduler, dashboard=not quiet) as client:
            if client is not None and not quiet:
                link = getattr(client, "dashboard_link", None)
                n = len(client.scheduler_info().get("workers", {}))
                err.print(f"dask: {count_noun(n, 'worker')}" + (f", dashboard {link}" if link else ""))
            with about(source):
                try:
                    tin = tiled_terrain(dem, max_error=max_error, tile=size, client=client, nodata=nodata,
                                        backend=backend, progress=not quiet, keep_tiles=tile_output is not None)
                except MissingHeights as exc:  # in the command's words
                    fail(_no_data(source, exc.count, *exc.first))
    except ClusterError as exc:
        fail(error_line(exc))
    except ValueError as exc:  # connect's own checks of --workers and --scheduler
        fail(error_line(exc))
    written: list[Path] = []
    with outputs.staged() as stage:
        if output is not None:
            files = write_tin(stage(output), tin, world=world, sidecar_at=output.with_suffix(".prj"))
            written = [stage.target(w) for w in files]
    if tile_output is not None:
        with about(tile_output):
            write_tile_meshes(tile_output, tin, world=world)
        written.append(tile_output)
    if not quiet:
        rows, cols = tin.shape
        ti, tj = tin.tiling.shape
        err.print(
            one_line(
                f"terrain {source} ({rows} × {cols}) in {ti} × {tj} tiles of {size}: {tin.n_points:,} points, "
                f"{len(tin.triangles):,} triangles, max error {tin.max_error:.6g}, rms {tin.rms_error:.6g}"
            )
        )
        if written:
            where = "grid coordinates" if not world else "world coordinates" + (
                f", CRS {tin.crs.label}" if tin.crs is not None else ", no CRS read from the input"
            )
            err.print(one_line(f"wrote {', '.join(str(w) for w in written)} ({where})"))
    if output is None and quiet:
        click.echo(f"{tin.n_points} points, {len(tin.triangles)} triangles, max error {tin.max_error:.6g}")
