"""``persistri mesh``: a quality mesh of a planar domain by Ruppert's refinement, undone by persistence (paper §1).

The domain is a Triangle ``.poly`` file, a ``.node`` file (the convex hull of
its points, as Triangle meshes one) or the name of a bench gallery domain
(:mod:`persistri.impl.mesh.gallery`).  The mesh is
:func:`persistri.impl.mesh.api.triangulate`'s; ``--check`` runs the independent
exact checker (:func:`persistri.impl.mesh.verify.verify_mesh`) on it and fails
when the mesh does not pass.  The inputs and outputs are checked before the
refinement starts and written all or nothing (:mod:`persistri.impl.cli.checks`).

Outputs by extension: ``.npz`` (the arrays and the counts), ``.ele`` (Triangle's
``.node`` with attributes and boundary markers + ``.ele`` + ``.poly`` of the mesh
segments with their markers, as Triangle's ``-p`` writes them:
:mod:`persistri.impl.mesh.markers`), ``.ply`` / ``.obj`` / ``.off`` (z = 0).
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click
import numpy as np
from rich.table import Table

from persistri.impl.cli.checks import FILE_OR_NAME, FILE_PATH, PLOT_FORMATS, Outputs, check_backend, check_input
from persistri.impl.cli.console import count_noun, stderr_console, stdout_console
from persistri.impl.cli.errors import about, error_line, fail, one_line
from persistri.impl.maps import BACKENDS
from persistri.impl.mesh.gallery import GALLERY

if TYPE_CHECKING:  # the mesher's modules are imported when a command runs, not when the CLI loads
    from persistri.impl.mesh.api import QualityMesh
    from persistri.impl.mesh.domain import PSLG
    from persistri.impl.mesh.verify import MeshReport

__all__ = ["mesh", "DOMAIN_FORMATS", "MESH_OUTPUT_FORMATS", "read_domain", "npz_arrays"]

DOMAIN_FORMATS = (".poly", ".node")
"""The domain files ``persistri mesh`` reads (besides the gallery's names)."""

MESH_OUTPUT_FORMATS = (".npz", ".ele", ".ply", ".obj", ".off")
"""The mesh files ``persistri mesh`` writes, by extension."""

_TRIANGLE_COMPANIONS = (".node", ".poly")
"""The files written beside an ``.ele`` output (Triangle's ``-p`` output set)."""


def _finite(ctx: click.Context, param: click.Parameter, value: float | None) -> float | None:
    """Refuse NaN and infinities, which click's ranges let through."""
    if value is not None and not math.isfinite(value):
        raise click.BadParameter(f"{value} is not a finite number")
    return value


def _refiner_default(name: str) -> Any:
    """The default of :func:`~persistri.impl.mesh.api.triangulate`'s keyword ``name`` (the option's own default)."""
    import inspect

    from persistri.impl.mesh.api import triangulate

    return inspect.signature(triangulate).parameters[name].default


def read_domain(source: str, *, convex: bool = False) -> PSLG:
    """The :class:`~persistri.impl.mesh.domain.PSLG` named by ``source``: a gallery name, a ``.poly`` or a ``.node`` file.

    A ``.node`` file gives the convex hull of its points (Triangle's behaviour
    for a file without segments); ``convex`` closes a ``.poly`` domain by its
    convex hull (Triangle's ``-c``).  Errors are one line naming the file and
    the line, or the element of the domain that is wrong. O(file).
    """
    from persistri.impl.mesh.domain import as_pslg
    from persistri.impl.mesh.gallery import gallery_domain
    from persistri.impl.mesh.polyfile import read_poly

    if source.lower() in GALLERY:
        pslg = gallery_domain(source.lower()).pslg
        return as_pslg(pslg.vertices, pslg.segments, pslg.holes, pslg.regions, convex=True) if convex else pslg
    return read_poly(Path(source), convex=convex)  # a .node file: the convex hull of its points


def _in_command_words(message: str, source: str) -> str:
    """A refinement error's ``message`` as the command's user reads it: the API's ``convex=True`` is
    ``--convex``, and rows it names (an input vertex, a segment) are said to count from 0 when the
    file numbers from 1."""
    message = message.replace("convex=True", "--convex")
    if re.search(r"\b(input vertex|segment) \d", message) and _first_number(source) == 1:
        message += " (rows counted from 0; the file numbers from 1)"
    return message


_NOTES_SHOWN = 5
"""Repairs of the domain printed one per line; more are counted on one further line."""


def _repairs(source: str, notes: Sequence[str]) -> list[str]:
    """The lines that report what reading the domain repaired (merged duplicate vertices or segments, split
    segments, vertices outside the domain): ``persistri: note: SOURCE: …``, rows said to count from 0 where
    the file numbers from 1.  O(notes)."""
    counted = " (rows counted from 0; the file numbers from 1)" if _first_number(source) == 1 else ""
    lines = []
    for note in notes[:_NOTES_SHOWN]:
        rows = counted if re.search(r"\b(vertex|vertices|segment|segments|hole|region) \d", note) else ""
        lines.append(f"persistri: note: {source}: {note}{rows}")
    if len(notes) > _NOTES_SHOWN:
        more = len(notes) - _NOTES_SHOWN
        lines.append(f"persistri: note: {source}: … and {more:,} more repair{'s' if more != 1 else ''} (read_poly(...).notes lists them)")
    return lines


def _first_number(source: str) -> int:
    """The number of the first vertex in the input's Triangle files (0 or 1), which Triangle's outputs keep; 1 for a gallery domain."""
    path = Path(source)
    if source.lower() in GALLERY or not path.is_file():
        return 1

    def records(p: Path) -> list[list[str]]:
        with p.open(encoding="utf-8", errors="replace") as fh:
            return [r for r in (line.split("#", 1)[0].split() for line in fh) if r][:2]

    first = records(path)
    if len(first) == 2 and first[0][0] != "0":
        token = first[1][0]
    else:
        beside = path.with_suffix(".node")
        rows = records(beside) if beside.is_file() else []
        token = rows[1][0] if len(rows) == 2 else "1"
    return 0 if token.lstrip("+") == "0" else 1


def _dropped_arrays(mesh: QualityMesh) -> dict[str, Any]:
    """The refinement's record of its dropped points as arrays (``history.undone`` / ``history.blocked``).

    ``undone_xy`` (U × 2) and ``undone_version`` (U): each undone point and the version it was tried on (and the
    run went on from); ``undone_encroached`` (E × 3): per subsegment an undone point encroached, the row of that
    point in ``undone_xy`` and the two ``vertices`` rows of the subsegment's ends (split points and input vertices
    are never deleted, so they are rows of the final mesh); ``blocked_xy``, ``blocked_version`` likewise.
    """
    history = mesh.history
    last = history.mesh(len(history) - 1).points
    row = {int(p): k for k, p in enumerate(last.tolist())}
    encroached = [(i, row[lo], row[hi]) for i, d in enumerate(history.undone) for lo, hi, _ in d.encroached]
    return {
        "undone_xy": np.array([d.xy for d in history.undone], dtype=np.float64).reshape(-1, 2),
        "undone_version": np.array([d.version for d in history.undone], dtype=np.int64),
        "undone_encroached": np.array(encroached, dtype=np.int64).reshape(-1, 3),
        "blocked_xy": np.array([d.xy for d in history.blocked], dtype=np.float64).reshape(-1, 2),
        "blocked_version": np.array([d.version for d in history.blocked], dtype=np.int64),
    }


def npz_arrays(mesh: QualityMesh, smallest: float) -> dict[str, Any]:
    """What an ``.npz`` output holds: the mesh's arrays, the bounds, what was reached, the refinement's counts and
    its record of the points it dropped (:func:`_dropped_arrays`), and what Triangle's files carry
    (:mod:`persistri.impl.mesh.markers`): ``vertex_markers`` (N), ``segment_markers`` (one per ``segments`` row) and,
    when the domain has them, ``vertex_attributes`` (N × k)."""
    from persistri.impl.mesh.markers import triangle_markers, vertex_attributes

    marks = triangle_markers(mesh)
    attributes = vertex_attributes(mesh)
    extra: dict[str, Any] = {"vertex_markers": marks.vertex, "segment_markers": marks.segment}
    if attributes is not None:
        extra["vertex_attributes"] = attributes
    return {
        "vertices": mesh.vertices,
        "triangles": mesh.triangles,
        "segments": mesh.segments,
        "segment_of": mesh.segment_of,
        "regions": mesh.regions,
        "min_angle": np.float64(mesh.min_angle),
        "max_area": np.float64(np.nan if mesh.max_area is None else mesh.max_area),
        "min_angle_reached": np.bool_(mesh.min_angle_reached),
        "max_area_reached": np.bool_(mesh.max_area_reached),
        "smallest_angle": np.float64(smallest),
        "n_triangles": np.int64(len(mesh.triangles)),
        "n_vertices": np.int64(len(mesh.vertices)),
        "insertions": np.int64(mesh.insertions),
        "segment_splits": np.int64(mesh.segment_splits),
        "circumcenters": np.int64(mesh.circumcenters),
        "offcenters": np.int64(mesh.offcenters),
        "undos": np.int64(mesh.undos),
        "blocked": np.int64(mesh.blocked),
        "deletions": np.int64(mesh.deletions),
        "exempt": np.int64(mesh.exempt),
        "rounded_splits": np.int64(mesh.rounded_splits),
        "exact_segments": np.bool_(mesh.exact_segments),
        **_dropped_arrays(mesh),
        **extra,
    }


def _write_triangle_files(path: Path, mesh: QualityMesh, first_number: int) -> None:
    """``path`` (.ele) with the ``.node`` and the ``.poly`` of the mesh segments beside it, as Triangle's ``-p`` writes
    them: every vertex with its attributes and boundary marker, every segment with its marker
    (:mod:`persistri.impl.mesh.markers`: Triangle's rules), each triangle with its regional attribute."""
    from persistri.impl.mesh.domain import PSLG
    from persistri.impl.mesh.markers import triangle_markers, vertex_attributes
    from persistri.impl.mesh.polyfile import write_ele, write_poly

    d = mesh.domain
    marks = triangle_markers(mesh)
    segments = PSLG(
        vertices=mesh.vertices,
        segments=mesh.segments[marks.kept],
        holes=d.holes,
        regions=d.regions,
        vertex_markers=marks.vertex,
        segment_markers=marks.segment[marks.kept],
        vertex_attributes=vertex_attributes(mesh),
    )
    write_poly(path.with_suffix(".poly"), segments, first_number=first_number, node_file=True)
    attributes = None
    if d.regions.shape[0]:
        # Triangle's -A: each triangle carries its region's attribute (0 outside every region), not the region's number.
        attributes = np.where(mesh.regions > 0, np.asarray(d.regions[:, 2])[np.maximum(mesh.regions - 1, 0)], 0.0)
    write_ele(path, mesh.triangles, attributes=attributes, first_number=first_number)


def _protect_input(source: str, targets: list[Path]) -> None:
    """Fail when an output would overwrite the input (or the ``.node`` a ``.poly`` read its vertices from)."""
    if source.lower() in GALLERY:
        return
    path = Path(source)
    inputs = [p for p in (path, path.with_suffix(".node")) if p.is_file()]
    for target in targets:
        if target.exists() and any(os.path.samefile(target, p) for p in inputs):
            fail(f"{target}: is an input of this run; name the output otherwise (Triangle writes NAME.1.ele)")


def _summary(source: str, mesh: QualityMesh, smallest: float, report: MeshReport | None, max_steiner: int | None) -> str:
    bound = mesh.min_angle
    what = f"mesh of {source}: {count_noun(len(mesh.triangles), 'triangle')}, {count_noun(len(mesh.vertices), 'vertex')}"
    exempt = f"{mesh.exempt} exempt triangle{'s' if mesh.exempt != 1 else ''} at small input angles"
    if report is not None and report.min_angle_unexempt is not None:
        angle = f"min angle {report.min_angle_unexempt:.2f}°" + (f" outside {exempt}" if mesh.exempt else "")
    elif mesh.exempt:
        # Without the checker's report only the smallest angle of all is known, and it may lie in an exempt
        # triangle: say so rather than call it the smallest outside them.  Where the bound is reached, every
        # other triangle meets it (decided exactly by the refiner).
        angle = f"min angle {smallest:.2f}° counting {exempt}"
        if bound > 0 and mesh.min_angle_reached:
            angle += f", ≥ {bound:g}° outside them"
    else:
        angle = f"min angle {smallest:.2f}°"
    if bound > 0:
        reached = "reached" if mesh.min_angle_reached else "NOT reached"
        if not mesh.min_angle_reached and max_steiner is not None and mesh.insertions >= max_steiner:
            reached += f": stopped at --max-steiner {max_steiner}"
        angle += f" (bound {bound:g}° {reached})"
    if mesh.max_area is not None and not mesh.max_area_reached:
        angle += f"; max area {mesh.max_area:g} NOT reached"
    steps = (
        f"{mesh.insertions:,} insertions ({mesh.segment_splits:,} segment splits, "
        f"{mesh.circumcenters + mesh.offcenters:,} circumcentres/off-centres), "
        f"{mesh.undos:,} undone by returning to the previous version"
    )
    if mesh.deletions:
        steps += f", {mesh.deletions:,} deleted from a split subsegment's circle"
    rounded = f", {mesh.rounded_splits} split points rounded off their segment" if mesh.rounded_splits else ""
    verified = " (verified exactly)" if report is not None and report.ok else ""
    return f"{what}, {angle}; {steps}{rounded}{verified}"


def _versions_text(versions: list[int]) -> str:
    """``3 (history[4], history[9], …)``: how many versions, and the first few."""
    if not versions:
        return "0"
    shown = ", ".join(f"history[{k}]" for k in versions[:3])
    return f"{len(versions):,} ({shown}{', …' if len(versions) > 3 else ''})"


def _stats_table(source: str, mesh: QualityMesh, smallest: float, report: MeshReport | None) -> Table:
    table = Table(title=f"Ruppert's refinement of {source}, undone by persistence")
    table.add_column("count")
    table.add_column("value", justify="right")
    unexempt = report.min_angle_unexempt if report is not None and report.min_angle_unexempt is not None else smallest
    rows = [
        ("triangles", f"{len(mesh.triangles):,}"),
        ("vertices", f"{len(mesh.vertices):,} ({mesh.domain.vertices.shape[0]:,} of the domain)"),
        ("min angle reached (°)", f"{unexempt:.4f}"),
        ("min angle bound (°)", f"{mesh.min_angle:g} ({'reached' if mesh.min_angle_reached else 'not reached'})"),
        ("exempt triangles (small input angles)", f"{mesh.exempt:,}"),
        ("smallest angle of all (°)", f"{smallest:.4f}"),
        ("insertions (versions after the first)", f"{mesh.insertions:,}"),
        ("segment splits", f"{mesh.segment_splits:,}"),
        ("circumcentres", f"{mesh.circumcenters:,}"),
        ("off-centres", f"{mesh.offcenters:,}"),
        ("undos (insertion dropped, previous version kept)", f"{mesh.undos:,}"),
        ("versions an undo returned to (history.undone)", _versions_text(sorted({d.version for d in mesh.history.undone}))),
        ("subsegments split after an undo", f"{sum(len(d.encroached) for d in mesh.history.undone):,}"),
        ("blocked (point beyond a segment, not inserted)", f"{mesh.blocked:,}"),
        ("deletions (free vertices in a split subsegment's circle)", f"{mesh.deletions:,}"),
        ("split points rounded off their segment", f"{mesh.rounded_splits:,}"),
        ("versions kept", f"{len(mesh.history):,}"),
    ]
    if mesh.max_area is not None:
        rows.insert(4, ("max area bound", f"{mesh.max_area:g} ({'reached' if mesh.max_area_reached else 'not reached'})"))
    if report is not None:
        rows.append(("exact check (verify_mesh)", "passed" if report.ok else f"FAILED: {report.problems[0]}"))
    for name, value in rows:
        table.add_row(name, value)
    return table


@click.command("mesh", short_help="A quality mesh of a planar domain by Ruppert's refinement.")
@click.argument("source", metavar="INPUT", type=FILE_OR_NAME)
@click.option(
    "-q", "--min-angle", type=click.FloatRange(0, 60, max_open=True), default=20.0, show_default=True, callback=_finite,
    help="Smallest angle wanted, degrees (0: the plain constrained Delaunay triangulation). Triangle's -q; "
    "20.7 is what Ruppert's theory guarantees, up to about 34 works in practice; beyond, cap with --max-steiner.",
)
@click.option(
    "-a", "--max-area", type=click.FloatRange(min=0, min_open=True), default=None, callback=_finite,
    help="Largest triangle area wanted (Triangle's -a with a number); see also --region-areas.",
)
@click.option(
    "--region-areas", is_flag=True,
    help="Also keep each triangle within its .poly region's own area bound (Triangle's -a without a number); "
    "without it, as in Triangle, regional bounds are read but not applied.",
)
@click.option("-o", "--output", type=FILE_PATH, help=f"Output mesh ({', '.join(MESH_OUTPUT_FORMATS)}).")
@click.option("--plot", type=FILE_PATH, help=f"Draw the mesh to this image ({', '.join(PLOT_FORMATS)}).")
@click.option("--check", is_flag=True, help="Verify the mesh with the independent exact checker; fail if it does not pass.")
@click.option("--stats", "show_stats", is_flag=True, help="Print what the refinement did (insertions, splits, undos) as a table.")
@click.option("--max-steiner", type=click.IntRange(min=0), default=None, help="Stop after this many Steiner points (Triangle's -S).")
@click.option(
    "--encroachment", type=click.Choice(["lens", "circle"]), default="lens", show_default=True,
    help="A subsegment is encroached by a vertex in its diametral lens (Chew's, Triangle's default) or circle "
    "(Ruppert's, Triangle's -D).",
)
@click.option("--no-offcenters", is_flag=True, help="Split bad triangles at their circumcentres only (no off-centres).")
@click.option(
    "--exact-segments/--rounded-segments", default=None,
    help="Split points exactly on their segments, failing where no double lies on one; or round them there to "
    "the nearest doubles, as Triangle does (default: the refiner's).",
)
@click.option("--convex", is_flag=True, help="Mesh the convex hull of the domain, keeping its segments (Triangle's -c).")
@click.option("--backend", default="int_trie", show_default=True, help=f"ORD_MAP backend of the complex ({', '.join(BACKENDS)}).")
@click.option("--quiet", is_flag=True, help="No progress bar and no summary.")
def mesh(
    source: str,
    min_angle: float,
    max_area: float | None,
    region_areas: bool,
    output: Path | None,
    plot: Path | None,
    check: bool,
    show_stats: bool,
    max_steiner: int | None,
    encroachment: str,
    no_offcenters: bool,
    exact_segments: bool | None,
    convex: bool,
    backend: str,
    quiet: bool,
) -> None:
    """A quality mesh of the planar domain INPUT by Ruppert's refinement, every step a persistent version.

    INPUT is a Triangle .poly file (vertices, segments, holes, regions; its
    vertices may be in the .node beside it), a .node file (the convex hull of
    its points) or the name of a gallery domain: square-hole, l-shape, star,
    circle, crack, utm-tile, comb, needle, fan.  Every vertex of the mesh is a pair of
    doubles and every decision is exact; a circumcentre that would encroach a
    segment is undone by returning to the version before it (the paper's §1).

    OUTPUT by extension: .npz with the arrays vertices (N × 2), triangles
    (T × 3, counterclockwise), segments (the mesh edges on input segments),
    segment_of (the input segment of each), regions (each triangle's region,
    numbered from 1 in the .poly's order; 0: none), and the bounds, what was
    reached and the counts, and vertex_markers, segment_markers and
    vertex_attributes as below; .ele writes Triangle's files side by side, as
    triangle -p writes them: .node (every vertex with its attributes and
    boundary marker), .ele (each triangle with its regional attribute, as
    Triangle's -A) and .poly (the mesh segments with their markers, the holes
    and regions). Markers follow Triangle's rules: a nonzero input marker is
    kept; a segment is otherwise 1 on the domain's boundary, 0 inside; a vertex
    on a segment takes its marker, others 0. Attributes: input vertices keep
    theirs; new vertices get them by linear interpolation, as Triangle does
    (along the segment for a split point, in the bad triangle for a
    circumcentre). .ply, .obj, .off with z = 0.
    """
    from persistri.impl.mesh.api import triangulate
    from persistri.impl.mesh.steiner import PrecisionLimitError

    err = stderr_console()
    if not Path(source).suffix and not Path(source).exists() and source.lower() not in GALLERY:
        fail(f"{source}: no such file, nor a gallery domain ({', '.join(GALLERY)})")
    check_input(Path(source), DOMAIN_FORMATS, kind="domain", words=GALLERY)
    outputs = Outputs()
    outputs.file(output, MESH_OUTPUT_FORMATS, what="mesh")
    targets = [output] if output is not None else []
    if output is not None and output.suffix.lower() == ".ele":
        for suffix in _TRIANGLE_COMPANIONS:
            companion = output.with_suffix(suffix)
            outputs.file(companion, (suffix,), what="Triangle")
            targets.append(companion)
    outputs.file(plot, PLOT_FORMATS, what="plot")
    targets += [plot] if plot is not None else []
    _protect_input(source, targets)
    check_backend(backend)
    try:
        with about(source):
            domain = read_domain(source, convex=convex)
    except click.ClickException as exc:
        if "is every boundary closed?" not in exc.message or convex:
            raise
        fail(f"{exc.message}; --convex meshes the convex hull, as Triangle's -c")
    if not quiet:
        for line in _repairs(source, domain.notes):
            err.print(one_line(line), soft_wrap=True, markup=False, highlight=False)
    options: dict[str, Any] = {} if exact_segments is None else {"exact_segments": exact_segments}
    with about(source):
        try:
            result = triangulate(
                domain,
                min_angle=min_angle,
                max_area=max_area,
                region_areas=region_areas,
                backend=backend,
                progress=not quiet,
                offcenters=not no_offcenters,
                max_steiner=max_steiner,
                encroachment=encroachment,
                **options,
            )
        except PrecisionLimitError as exc:
            strict = exact_segments if exact_segments is not None else _refiner_default("exact_segments")
            message = _in_command_words(str(exc), source)
            if not strict:
                raise PrecisionLimitError(message) from None  # rounding was on: the option would not help
            raise ValueError(f"{message} (on the command line: --rounded-segments)") from None
    smallest = float(result.smallest_angle())
    report: MeshReport | None = None
    if check or show_stats:
        from persistri.impl.mesh.verify import verify_mesh

        report = verify_mesh(
            result.domain,
            result.vertices,
            result.triangles,
            min_angle=min_angle or None,
            max_area=max_area,
            exact_segments=result.exact_segments,
            region_areas=region_areas,
        )
        if check and not report.ok:
            total = sum(report.counts.values())
            fail(
                f"{source}: --check: the mesh fails the exact checker ({total} problem{'s' if total != 1 else ''}; "
                f"first: {report.problems[0]})"
            )
    with outputs.staged() as stage:
        if output is not None:
            suffix = output.suffix.lower()
            if suffix == ".ele":
                _write_triangle_files(stage(output), result, _first_number(source))
            else:
                from persistri.impl.files import write_mesh

                xyz = np.zeros((result.vertices.shape[0], 3))
                xyz[:, :2] = result.vertices
                write_mesh(stage(output), xyz, result.triangles, npz_arrays=npz_arrays(result, smallest))
        if plot is not None:
            from persistri.impl.mesh.plot import plot_mesh

            name = source if source.lower() in GALLERY else Path(source).name
            reached = f"≥ {result.min_angle:g}°" if result.min_angle and result.min_angle_reached else f"{smallest:.1f}°"
            plot_mesh(
                result.vertices,
                result.triangles,
                stage(plot),
                segments=result.segments,
                n_input=result.domain.vertices.shape[0],
                min_angle=result.min_angle or None,
                title=f"{name}: {len(result.triangles):,} triangles, min angle {reached}"
                + (f" ({result.exempt} exempt)" if result.exempt else "")
                + f", {result.undos:,} undos",
            )
    if not quiet:
        err.print(one_line(_summary(source, result, smallest, report, max_steiner)), markup=False, highlight=False)
    if show_stats:
        stdout_console().print(_stats_table(source, result, smallest, report))
    if output is None and plot is None and quiet and not show_stats:
        click.echo(f"{len(result.triangles)} triangles, {len(result.vertices)} vertices, {result.undos} undos")
