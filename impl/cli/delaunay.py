"""``persistri delaunay``: the exact Delaunay triangulation of a file of 2D points (paper §5, issue item 7)."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

from persistri.impl.cli.console import stderr_console, stdout_console
from persistri.impl.cli.hull import one_line, stats_table
from persistri.impl.files import MESH_FORMATS, POINT_FORMATS, read_points, write_mesh
from persistri.impl.maps import BACKENDS, UnknownBackendError
from persistri.impl.stats import Stats
from persistri.impl.terrain.check import TerrainCheckError

__all__ = ["delaunay_command"]


@click.command("delaunay")
@click.argument("input_path", metavar="INPUT", type=click.Path(dir_okay=False, path_type=Path))
@click.option("-o", "--output", type=click.Path(dir_okay=False, path_type=Path), help=f"Output ({', '.join(MESH_FORMATS)}).")
@click.option("--plot", type=click.Path(dir_okay=False, path_type=Path), help="Draw the triangulation to this PNG.")
@click.option("--backend", default="red_black", show_default=True, help=f"ORD_MAP backend of the complex ({', '.join(BACKENDS)}).")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the insertion order.")
@click.option("--check", is_flag=True, help="Assert the insertion invariants and verify the triangulation exactly.")
@click.option("--stats", "show_stats", is_flag=True, help="Print the operation counts as a table.")
@click.option("--quiet", is_flag=True, help="No summary.")
def delaunay_command(
    input_path: Path,
    output: Path | None,
    plot: Path | None,
    backend: str,
    seed: int,
    check: bool,
    show_stats: bool,
    quiet: bool,
) -> None:
    """The exact Delaunay triangulation of the points in INPUT (.npy, .csv/.xyz/.txt: rows of x,y or x,y,z).

    Every distinct point is a vertex (exactly equal rows are merged and
    reported); triangles are counterclockwise.  A third column (z) is carried
    into mesh outputs.  OUTPUT by extension: .npz with the arrays points (the
    input as read), triangles (input row indices) and hull, or .ply, .obj,
    .off, .stl (z = 0 without a third column).
    """
    from persistri.impl.terrain.scattered import delaunay

    err = stderr_console()
    try:
        if input_path.suffix.lower() not in POINT_FORMATS:
            raise ValueError(f"{input_path}: unknown point format; use one of {', '.join(POINT_FORMATS)}")
        if output is not None and output.suffix.lower() not in MESH_FORMATS:
            raise ValueError(f"{output}: unknown output format; use one of {', '.join(MESH_FORMATS)}")
        raw = np.asarray(read_points(input_path))
        if raw.ndim != 2 or raw.shape[1] not in (2, 3):
            raise ValueError(f"{input_path}: expected rows of x,y or x,y,z, got an array of shape {raw.shape}")
        stats = Stats() if show_stats else None
        result = delaunay(raw[:, :2], backend=backend, check=check, stats=stats, seed=seed)
    except (ValueError, TypeError, OSError, UnknownBackendError, TerrainCheckError) as exc:
        raise click.ClickException(one_line(exc)) from None
    if output is not None:
        xyz = np.zeros((raw.shape[0], 3))
        xyz[:, : raw.shape[1]] = raw
        write_mesh(
            output,
            xyz,
            result.triangles,
            npz_arrays={"points": raw, "triangles": result.triangles, "hull": result.hull},
        )
    if plot is not None:
        from persistri.impl.terrain.plot import plot_triangulation

        plot_triangulation(result.points, result.triangles, plot, title=f"{input_path.name}: {len(result.triangles):,} triangles")
    if not quiet:
        verified = " (verified exactly)" if check else ""
        dup = result.duplicates
        shown = ", ".join(f"row {a} = row {b}" for a, b in dup[:5]) + (" …" if len(dup) > 5 else "")
        err.print(
            f"delaunay of {input_path}: {len(result.triangles):,} triangles, {raw.shape[0] - len(dup):,} vertices, "
            f"{len(result.hull):,} on the hull{verified}"
            + (f"; {len(dup)} duplicate rows merged ({shown})" if dup else "")
        )
    if show_stats and result.stats is not None:
        stdout_console().print(stats_table(result.stats, f"operation counts ({backend})"))
    if output is None and plot is None and quiet:
        click.echo(f"{len(result.triangles)} triangles")
