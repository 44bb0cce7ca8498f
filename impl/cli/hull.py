"""``persistri hull``: the exact 3D convex hull of a point file or of a generated distribution.

One process by default for an input of one chunk (2,097,152 points, or ``--chunk-size``); on a Dask cluster otherwise
(:mod:`persistri.impl.scale`): ``--workers N`` starts a local cluster of N worker
processes, ``--scheduler ADDR`` (or ``PERSISTRI_SCHEDULER``) uses an existing one,
``--workers 1`` is the one-process path.  Both paths give exactly the same hull
and write the same files; the parallel one reads a ``.npy`` memory-mapped, chunk
by chunk, and also reads directories of ``.npy`` files and Zarr stores.
"""

from __future__ import annotations

import math
import zipfile
from pathlib import Path
from typing import Any

import click
import numpy as np
from numpy.typing import NDArray
from rich.table import Table

from persistri.impl.cli.checks import FILE_PATH, PLOT_FORMATS, Outputs, check_backend, check_column_count, check_input, parse_columns
from persistri.impl.cli.console import stderr_console, stdout_console
from persistri.impl.cli.errors import about, error_line, fail, one_line
from persistri.impl.files import MESH_FORMATS, POINT_FORMATS, read_points, write_mesh
from persistri.impl.hull.api import Hull, convex_hull
from persistri.impl.hull.distributions import DISTRIBUTIONS, generate
from persistri.impl.maps import BACKENDS
from persistri.impl.scale import dask_missing
from persistri.impl.scale.cluster import ENV_SCHEDULER, plan
from persistri.impl.scale.hull import MAX_CHUNK_ROWS
from persistri.impl.scale.sources import DEFAULT_CHUNK_ROWS, PointSource, points_source, read_block
from persistri.impl.stats import Stats

__all__ = ["hull", "write_npz_streamed"]


def stats_table(stats: Stats, title: str) -> Table:
    """The counters of ``stats`` as a rich table."""
    table = Table(title=title)
    table.add_column("count")
    table.add_column("value", justify="right")
    for name, value in stats.as_dict().items():
        table.add_row(name.replace("_", " "), f"{value:,}")
    return table


def write_npz_streamed(path: Path, source: PointSource, arrays: dict[str, NDArray[Any]]) -> None:
    """An ``.npz`` whose ``points`` are ``source``'s rows as float64, written block by block (memory: one
    block), followed by ``arrays``: what ``np.savez(path, points=all rows, **arrays)`` writes, without
    ever holding all rows."""
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_STORED, allowZip64=True) as zf:
        with zf.open("points.npy", "w", force_zip64=True) as fh:
            header = {"descr": np.lib.format.dtype_to_descr(np.dtype(np.float64)), "fortran_order": False, "shape": (source.n, 3)}
            np.lib.format.write_array_header_1_0(fh, header)
            for b in source.blocks:
                data = b.data.compute() if type(b.data).__module__.startswith("dask") else b.data
                fh.write(np.ascontiguousarray(read_block(data, b.start, source.what)).tobytes())
        for name, arr in arrays.items():
            with zf.open(f"{name}.npy", "w", force_zip64=True) as fh:
                np.lib.format.write_array(fh, np.asanyarray(arr), allow_pickle=False)


def _chunked_source(input_path: Path, chunk_rows: int | None) -> PointSource:
    """INPUT read as chunks (headers only): a ``.npy``, a directory of ``.npy`` files or a Zarr store."""
    try:
        return points_source(input_path, chunk_rows)
    except (ValueError, TypeError, OSError) as exc:
        message = error_line(exc)
        fail(message if str(input_path) in message else f"{input_path}: {message}")


@click.command("hull", short_help="The exact convex hull of a point file or a §4 distribution.")
@click.argument("input_path", metavar="INPUT", required=False, type=FILE_PATH)
@click.option("-o", "--output", type=FILE_PATH, help=f"Output mesh ({', '.join(MESH_FORMATS)}).")
@click.option("--dist", type=click.Choice(sorted(DISTRIBUTIONS), case_sensitive=False), help="Generate the input from a §4 distribution instead of reading INPUT.")
@click.option("-n", "--points", "n", type=click.IntRange(min=4), default=10_000, show_default=True, help="How many points --dist generates (a hull needs 4).")
@click.option("--backend", default="red_black", show_default=True, help=f"ORD_MAP backend of the complex ({', '.join(BACKENDS)}).")
@click.option("--columns", metavar="A,B,C", callback=parse_columns, help="The columns to read as x,y,z: numbers from 0 or header names (text files; x, y, z for .ply; numbers for .npy, then read whole).  [default: the header's x,y,z, else every column]")
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True, help="Seed of the insertion order (and of --dist).")
@click.option("--check", is_flag=True, help="Assert the theorems of Appendix A at every insertion and verify the hull exactly.")
@click.option("--stats", "show_stats", is_flag=True, help="Print the operation counts (paper §4) as a table (one process: implies --workers 1).")
@click.option("--plot", type=FILE_PATH, help=f"Draw the hull to this image ({', '.join(PLOT_FORMATS)}).")
@click.option("--workers", type=click.IntRange(min=1), help=f"Worker processes: 1 = this process; N = a local Dask cluster of N.  [default: one per core for more than one chunk ({MAX_CHUNK_ROWS:,} points, or --chunk-size)]")
@click.option("--scheduler", metavar="ADDR", help=f"Run on the existing Dask cluster of this scheduler (tcp://host:8786; also ${ENV_SCHEDULER}).")
@click.option("--chunk-size", "chunk_rows", type=click.IntRange(min=1), help=f"Points per chunk on a cluster.  [default: one chunk per worker, {DEFAULT_CHUNK_ROWS:,} to {MAX_CHUNK_ROWS:,}]")
@click.option("--quiet", is_flag=True, help="No progress bar and no summary.")
def hull(
    input_path: Path | None,
    output: Path | None,
    dist: str | None,
    n: int,
    backend: str,
    columns: list[str | int] | None,
    seed: int,
    check: bool,
    show_stats: bool,
    plot: Path | None,
    workers: int | None,
    scheduler: str | None,
    chunk_rows: int | None,
    quiet: bool,
) -> None:
    """The exact convex hull of INPUT (.npy, .csv/.xyz/.txt, .ply, a directory of .npy files, a Zarr store)
    or of --dist NAME -n N.

    OUTPUT by extension: .ply, .obj, .off, .stl (triangles, outward) or .npz with
    the arrays points (the input as read), simplices and vertices (input row indices).
    Text input: one point x y z per line, separated by commas, semicolons, tabs
    or spaces; header lines, # comments and blank lines are skipped; a header
    naming x, y, z among other columns picks those, --columns any three; UTF-8
    or UTF-16 with its byte-order mark, or gzip-compressed (points.xyz.gz).

    On a Dask cluster (--workers N, --scheduler ADDR) the points are hulled chunk by
    chunk on the workers and the chunk hulls merged: exactly the same hull.  A .npy is
    then read memory-mapped, so it may be larger than memory.
    """
    if (input_path is None) == (dist is None):
        raise click.UsageError("give either INPUT or --dist NAME")
    if workers is not None and scheduler is not None:
        raise click.UsageError("give either --workers or --scheduler, not both (a cluster has its own workers)")
    if scheduler is not None and not scheduler.strip():
        raise click.BadParameter("an address such as tcp://host:8786, not an empty string", param_hint="--scheduler")
    explicit = (workers is not None and workers > 1) or scheduler is not None
    if show_stats and explicit:
        raise click.UsageError("--stats counts the operations of one process: use it with --workers 1")
    directory = input_path is not None and input_path.is_dir()
    if columns is not None and (input_path is None or directory):
        raise click.UsageError("--columns chooses the columns of an input file: not for --dist or a directory")
    check_column_count(columns, (3,), "x,y,z")
    if input_path is not None and not directory:
        check_input(input_path, POINT_FORMATS, kind="point")
    outputs = Outputs([input_path])
    outputs.file(output, MESH_FORMATS, what="mesh")
    outputs.file(plot, PLOT_FORMATS, what="plot")
    check_backend(backend)

    # How many rows, to know whether there is more than one chunk to share: from the headers alone for a
    # directory or a .npy (a .npy whose header is wrong goes to the one-process reader, which names it).
    source: PointSource | None = None
    points: NDArray[np.float64] | None = None
    # With --columns a .npy is read whole (its chosen columns are a new array), like a text file.
    npy = input_path is not None and input_path.suffix.lower() == ".npy" and not directory and columns is None
    if directory:
        assert input_path is not None
        source = _chunked_source(input_path, chunk_rows)
        rows: int | None = source.n
    elif npy:
        assert input_path is not None
        rows = _npy_rows(input_path)
    else:
        points = read_points(input_path, (3,), fields=columns) if input_path is not None else generate(dist or "", n, seed)
        rows = points.shape[0]
    # By default a cluster only for more than one largest chunk: below that one process is as fast (bench scale,
    # docs/performance.md) and needs no cluster start-up; --chunk-size says what a chunk is.
    tasks = 1 if show_stats or rows is None else max(1, math.ceil(rows / (chunk_rows or MAX_CHUNK_ROWS)))
    kind = plan(workers, scheduler, tasks=tasks)[0] if rows is not None else "sequential"
    if kind != "sequential" and (why := dask_missing()) is not None:
        if explicit:
            fail(why)
        kind = "sequential"  # the default only: without the extra, one process as before
    if kind == "sequential" and not directory:
        if points is None:  # a .npy on the one-process path: read whole, as before
            assert input_path is not None
            points = read_points(input_path, (3,))
        _one_process(points, input_path, dist, n, seed, backend, check, show_stats, quiet, outputs, output, plot)
        return
    if npy:
        assert input_path is not None
        source = _chunked_source(input_path, chunk_rows)  # headers checked: one line for a bad one
    _on_cluster(
        input_path if source is not None else points, input_path, dist, n, seed, backend, check, quiet, outputs, output, plot,
        workers, scheduler, chunk_rows, kind,
    )


def _npy_rows(path: Path) -> int | None:
    """The rows of the ``.npy`` file ``path`` from its header, or None if it is not an ``(n, 3)`` numeric array."""
    from persistri.impl.files import read_npy

    try:
        shape = read_npy(path, mmap=True).shape
    except (ValueError, OSError):
        return None
    return int(shape[0]) if len(shape) == 2 and shape[1] == 3 else None


def _one_process(
    points: NDArray[np.float64],
    input_path: Path | None,
    dist: str | None,
    n: int,
    seed: int,
    backend: str,
    check: bool,
    show_stats: bool,
    quiet: bool,
    outputs: Outputs,
    output: Path | None,
    plot: Path | None,
) -> None:
    """The one-process path: :func:`~persistri.impl.hull.api.convex_hull` of the points in memory."""
    stats = Stats() if show_stats else None
    with about(input_path):
        result: Hull = convex_hull(points, backend=backend, seed=seed, check=check, stats=stats, progress=not quiet)
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
    _summary(quiet, input_path, dist, n, seed, check, len(result.simplices), len(result.vertices), len(result.duplicates), "")
    if show_stats and result.stats is not None:
        stdout_console().print(stats_table(result.stats, f"operation counts ({backend})"))
    if output is None and plot is None and quiet:
        click.echo(f"{len(result.simplices)} faces, {len(result.vertices)} vertices")


def _on_cluster(
    source: Any,
    input_path: Path | None,
    dist: str | None,
    n: int,
    seed: int,
    backend: str,
    check: bool,
    quiet: bool,
    outputs: Outputs,
    output: Path | None,
    plot: Path | None,
    workers: int | None,
    scheduler: str | None,
    chunk_rows: int | None,
    kind: str,
) -> None:
    """The chunked path: :func:`~persistri.impl.scale.hull.parallel_hull` on a cluster (or, for a directory
    or Zarr store with ``--workers 1``, chunk by chunk in this process)."""
    from persistri.impl.scale.cluster import connect
    from persistri.impl.scale.hull import parallel_hull

    err = stderr_console()
    with about(input_path):
        with connect(workers, scheduler, tasks=None if kind != "sequential" else 1, dashboard=not quiet) as client:
            if client is not None and not quiet:
                n = len(client.scheduler_info(n_workers=-1)["workers"])
                where = f"{n} worker{'' if n == 1 else 's'}"
                err.print(f"dask: {where}, dashboard {client.dashboard_link}", soft_wrap=True, highlight=False)
            result = parallel_hull(
                source, client=client, chunk_rows=chunk_rows, seed=seed, backend=backend, check=check, progress=not quiet
            )
    local = np.searchsorted(result.vertices, result.simplices).astype(np.intp)
    with outputs.staged() as stage:
        if output is not None:
            if output.suffix.lower() == ".npz":
                arrays = {"simplices": result.simplices, "vertices": result.vertices}
                write_npz_streamed(stage(output), result.source, arrays)
            else:
                write_mesh(stage(output), result.vertex_points, local)
        if plot is not None:
            from persistri.impl.hull.plot import plot_hull

            plot_hull(result.vertex_points, local, stage(plot), interior=False)
    k = len(result.chunks)
    on = f"; {k:,} chunk{'s' if k != 1 else ''}, {result.candidates:,} points reached the final run"
    w = result.workers
    on += f", on {w} worker{'s' if w != 1 else ''}" if w else ", in this process"
    _summary(quiet, input_path, dist, n, seed, check, len(result.simplices), len(result.vertices), len(result.duplicates), on)
    if output is None and plot is None and quiet:
        click.echo(f"{len(result.simplices)} faces, {len(result.vertices)} vertices")


def _summary(
    quiet: bool, input_path: Path | None, dist: str | None, n: int, seed: int, check: bool, faces: int, vertices: int, duplicates: int, more: str
) -> None:
    if quiet:
        return
    source = str(input_path) if input_path is not None else f"{dist} n={n} seed={seed}"
    verified = " (verified exactly)" if check else ""
    stderr_console().print(
        one_line(
            f"hull of {source}: {faces} faces, {vertices} vertices, {duplicates} duplicate row{'' if duplicates == 1 else 's'} merged"
            f"{verified}{more}"
        )
    )
