"""``persistri delaunay``: the exact Delaunay triangulation of a file of 2D points (paper §5, issue item 7)."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

from persistri.impl.cli.checks import FILE_PATH, PLOT_FORMATS, Outputs, check_backend, check_column_count, check_input, parse_columns
from persistri.impl.cli.console import count_noun, stderr_console, stdout_console
from persistri.impl.cli.errors import about, one_line
from persistri.impl.cli.hull import stats_table
from persistri.impl.files import MESH_FORMATS, POINT_FORMATS, read_points, write_mesh
from persistri.impl.maps import BACKENDS
from persistri.impl.stats import Stats

__all__ = ["delaunay_command"]


@click.command("delaunay", short_help="The exact Delaunay triangulation of scattered x,y points.")
@click.argument("input_path", metavar="INPUT", type=FILE_PATH)
@click.option("-o", "--output", type=FILE_PATH, help=f"Output ({', '.join(MESH_FORMATS)}).")
@click.option("--plot", type=FILE_PATH, help=f"Draw the triangulation to this image ({', '.join(PLOT_FORMATS)}).")
@click.option("--backend", default="int_trie", show_default=True, help=f"ORD_MAP backend of the complex ({', '.join(BACKENDS)}).")
@click.option("--columns", metavar="A,B[,C]", callback=parse_columns, help="The columns to read as x,y[,z]: numbers from 0 or header names (text files; x, y, z for .ply; numbers for .npy).  [default: the header's x,y,z, else every column]")
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True, help="Seed of the insertion order.")
@click.option("--check", is_flag=True, help="Assert the insertion invariants and verify the triangulation exactly.")
@click.option("--stats", "show_stats", is_flag=True, help="Print the operation counts as a table.")
@click.option("--quiet", is_flag=True, help="No summary.")
def delaunay_command(
    input_path: Path,
    output: Path | None,
    plot: Path | None,
    backend: str,
    columns: list[str | int] | None,
    seed: int,
    check: bool,
    show_stats: bool,
    quiet: bool,
) -> None:
    """The exact Delaunay triangulation of the points in INPUT (.npy, .csv/.xyz/.txt, also .gz: rows of x,y or x,y,z;
    a header naming x, y (z) among other columns picks those, --columns any two or three; .ply: the
    vertices' x, y, z).

    Every distinct point is a vertex (rows of equal x, y are merged and
    reported, with a warning where their z differ: the earlier row's is
    kept); triangles are counterclockwise.  A third column (z) is carried
    into mesh outputs.  OUTPUT by extension: .npz with the arrays points (the
    input as read), triangles (input row indices) and hull, or .ply, .obj,
    .off, .stl (z = 0 without a third column).
    """
    from persistri.impl.terrain.scattered import delaunay

    err = stderr_console()
    check_column_count(columns, (2, 3), "x,y or x,y,z")
    check_input(input_path, POINT_FORMATS, kind="point")
    outputs = Outputs([input_path])
    outputs.file(output, MESH_FORMATS, what="mesh")
    outputs.file(plot, PLOT_FORMATS, what="plot")
    check_backend(backend)
    raw = read_points(input_path, (2, 3), fields=columns)
    stats = Stats() if show_stats else None
    with about(input_path):
        result = delaunay(raw[:, :2], backend=backend, check=check, stats=stats, seed=seed)
    with outputs.staged() as stage:
        if output is not None:
            xyz = np.zeros((raw.shape[0], 3))
            xyz[:, : raw.shape[1]] = raw
            write_mesh(
                stage(output),
                xyz,
                result.triangles,
                npz_arrays={"points": raw, "triangles": result.triangles, "hull": result.hull},
            )
        if plot is not None:
            from persistri.impl.terrain.plot import plot_triangulation

            title = f"{input_path.name}: {len(result.triangles):,} triangles"
            plot_triangulation(result.points, result.triangles, stage(plot), title=title)
    dup = result.duplicates
    # Rows merged for their equal x, y whose z differ: the TIN keeps the earlier row's height, said even with --quiet.
    clashes = [(a, b) for a, b in dup if raw.shape[1] == 3 and raw[a, 2] != raw[b, 2]]
    if clashes:
        a, b = clashes[0]
        more = f" ({len(clashes):,} such rows)" if len(clashes) > 1 else ""
        err.print(
            one_line(
                f"persistri: warning: {input_path}: row {a} has the x, y of row {b} but another z "
                f"({float(raw[a, 2])!r}, not {float(raw[b, 2])!r}): the mesh keeps row {b}'s z{more}"
            ),
            soft_wrap=True, highlight=False, markup=False,
        )
    if not quiet:
        verified = " (verified exactly)" if check else ""
        shown = ", ".join(f"row {a} = row {b}" for a, b in dup[:5]) + (" …" if len(dup) > 5 else "")
        what = "row" if len(dup) == 1 else "rows"
        err.print(
            one_line(
                f"delaunay of {input_path}: {count_noun(len(result.triangles), 'triangle')}, {count_noun(raw.shape[0] - len(dup), 'vertex')}, "
                f"{len(result.hull):,} on the hull{verified}"
                + (f"; {len(dup):,} duplicate {what} merged ({shown})" if dup else "")
            )
        )
    if show_stats and result.stats is not None:
        stdout_console().print(stats_table(result.stats, f"operation counts ({backend})"))
    if output is None and plot is None and quiet:
        click.echo(f"{len(result.triangles)} triangles")
