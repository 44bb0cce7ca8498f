"""``persistri hull``: the exact 3D convex hull of a point file or of a generated distribution."""

from __future__ import annotations

from pathlib import Path

import click
from rich.table import Table

from persistri.impl.cli.checks import PLOT_FORMATS, Outputs, check_backend, check_input
from persistri.impl.cli.console import stderr_console, stdout_console
from persistri.impl.cli.errors import about
from persistri.impl.files import MESH_FORMATS, POINT_FORMATS, read_points, write_mesh
from persistri.impl.hull.api import convex_hull
from persistri.impl.hull.distributions import DISTRIBUTIONS, generate
from persistri.impl.maps import BACKENDS
from persistri.impl.stats import Stats

__all__ = ["hull"]


def stats_table(stats: Stats, title: str) -> Table:
    """The counters of ``stats`` as a rich table."""
    table = Table(title=title)
    table.add_column("count")
    table.add_column("value", justify="right")
    for name, value in stats.as_dict().items():
        table.add_row(name.replace("_", " "), f"{value:,}")
    return table


@click.command("hull")
@click.argument("input_path", metavar="INPUT", required=False, type=click.Path(path_type=Path))
@click.option("-o", "--output", type=click.Path(path_type=Path), help=f"Output mesh ({', '.join(MESH_FORMATS)}).")
@click.option("--dist", type=click.Choice(sorted(DISTRIBUTIONS), case_sensitive=False), help="Generate the input from a §4 distribution instead of reading INPUT.")
@click.option("-n", "--points", "n", type=click.IntRange(min=0), default=10_000, show_default=True, help="How many points --dist generates.")
@click.option("--backend", default="red_black", show_default=True, help=f"ORD_MAP backend of the complex ({', '.join(BACKENDS)}).")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the insertion order (and of --dist).")
@click.option("--check", is_flag=True, help="Assert the theorems of Appendix A at every insertion and verify the hull exactly.")
@click.option("--stats", "show_stats", is_flag=True, help="Print the operation counts (paper §4) as a table.")
@click.option("--plot", type=click.Path(path_type=Path), help=f"Draw the hull to this image ({', '.join(PLOT_FORMATS)}).")
@click.option("--quiet", is_flag=True, help="No progress bar and no summary.")
def hull(
    input_path: Path | None,
    output: Path | None,
    dist: str | None,
    n: int,
    backend: str,
    seed: int,
    check: bool,
    show_stats: bool,
    plot: Path | None,
    quiet: bool,
) -> None:
    """The exact convex hull of INPUT (.npy, .csv/.xyz/.txt, .ply) or of --dist NAME -n N.

    OUTPUT by extension: .ply, .obj, .off (triangles, outward) or .npz with the
    arrays points (the input as read), simplices and vertices (input row indices).
    Text input: one point x y z per line, separated by commas, semicolons, tabs
    or spaces; header lines, # comments and blank lines are skipped.
    """
    err = stderr_console()
    if (input_path is None) == (dist is None):
        raise click.UsageError("give either INPUT or --dist NAME")
    if input_path is not None:
        check_input(input_path, POINT_FORMATS, kind="point")
    outputs = Outputs()
    outputs.file(output, MESH_FORMATS, what="mesh")
    outputs.file(plot, PLOT_FORMATS, what="plot")
    check_backend(backend)
    points = read_points(input_path, (3,)) if input_path is not None else generate(dist or "", n, seed)
    stats = Stats() if show_stats else None
    with about(input_path):
        result = convex_hull(points, backend=backend, seed=seed, check=check, stats=stats, progress=not quiet)
    with outputs.staged() as stage:
        if output is not None:
            write_mesh(
                stage(output),
                result.points,
                result.simplices,
                npz_arrays={"points": result.points, "simplices": result.simplices, "vertices": result.vertices},
            )
        if plot is not None:
            from persistri.impl.hull.plot import plot_hull

            plot_hull(result.points, result.simplices, stage(plot))
    if not quiet:
        source = str(input_path) if input_path is not None else f"{dist} n={n} seed={seed}"
        verified = " (verified exactly)" if check else ""
        err.print(
            f"hull of {source}: {len(result.simplices)} faces, {len(result.vertices)} vertices, "
            f"{len(result.duplicates)} duplicate rows merged{verified}"
        )
    if show_stats and result.stats is not None:
        stdout_console().print(stats_table(result.stats, f"operation counts ({backend})"))
    if output is None and plot is None and quiet:
        click.echo(f"{len(result.simplices)} faces, {len(result.vertices)} vertices")
