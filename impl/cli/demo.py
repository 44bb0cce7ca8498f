"""``persistri demo --out DIR``: the main job of ``make demo``, a sequence of stages that write results to DIR.

Each stage is a :class:`DemoStage`: a name, a title for the progress bar, and a
function that does the work, writes its files into the output directory and
returns them with an optional renderable summary.  :data:`STAGES` lists them in
order; adding a stage (the convex hull, the terrain) is adding an entry.

Stages now:

``hull``
    the exact convex hull (:func:`persistri.impl.hull.api.convex_hull`) of
    generated BordHeavy points (paper §4), checked at every insertion and verified
    exactly, with every intermediate hull kept: ``hull.npz`` (points, simplices,
    vertices), ``hull.ply`` and ``hull.png``;
``terrain``
    greedy insertion on the Jacksboro DEM (paper §5) to 2,000 points, checked at
    every insertion and verified exactly, every level of detail kept:
    ``terrain_jacksboro.npz`` (vertices, triangles, max_error), ``terrain_jacksboro.ply``
    and ``terrain_jacksboro.png`` (the mesh over the shaded relief, like Figs. 9–10);
``mesh``
    a quality mesh of the bench gallery's comb (twelve thin teeth) at a 30°
    minimum angle by Ruppert's refinement, a circumcentre that would encroach a
    segment undone by returning to the previous version (paper §1), verified
    exactly: ``mesh_comb.npz`` (the arrays and counts of ``persistri mesh -o``)
    and ``mesh_comb.png`` (triangles coloured by their smallest angle);
``maps``
    the map benchmark (:mod:`persistri.impl.bench.maps`) at 10³ and 10⁴ keys:
    ``bench_maps.json`` (the records), ``bench_maps.txt`` (the table) and
    ``bench_maps.png`` (µs/op per map and operation, log scale).
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

import click
from rich.console import Console, Group, RenderableType
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TaskID, TextColumn, TimeElapsedColumn
from rich.text import Text

from persistri.impl.bench.maps import DEFAULT_SEED, MapBench, ProgressCallback, run_map_bench
from persistri.impl.bench.maps_report import maps_report, maps_text, save_maps_chart
from persistri.impl.cli.bench import parse_sizes
from persistri.impl.cli.checks import FILE_PATH, check_output_dir
from persistri.impl.cli.console import stdout_console

__all__ = ["DemoSettings", "DemoStage", "StageContext", "StageResult", "STAGES", "demo", "run_demo", "without_unavailable"]

DEMO_HULL_POINTS = 4_000
"""Points of the demo's hull (BordHeavy): checked at every insertion, so kept modest."""

DEMO_TERRAIN_POINTS = 2_000
"""Vertices of the demo's Jacksboro mesh."""

DEMO_MESH_DOMAIN = "comb"
"""The gallery domain the demo meshes (:mod:`persistri.impl.mesh.gallery`)."""

DEMO_MESH_ANGLE = 30.0
"""The demo mesh's minimum-angle bound, degrees."""

DEMO_BENCH_SIZES = (1_000, 10_000)
"""Key counts of the demo's map benchmark."""

DEMO_REPEAT = 3
"""Timed runs per figure of the demo's map benchmark, the best kept: one run on a busy machine
can show an adapter faster than the library it wraps."""

DEMO_ASSOC_LIST_MAX_N = 1_000
"""The association list is measured up to 10³ keys only (its row at 10⁴ says why: O(n) per operation);
at 10⁴ it would take most of the demo's time."""


@dataclass(frozen=True, slots=True)
class DemoSettings:
    """What the whole demo is asked to do."""

    out: Path
    """The directory the stages write into (created if missing)."""
    bench_sizes: tuple[int, ...] = DEMO_BENCH_SIZES
    hull_points: int = DEMO_HULL_POINTS
    terrain_points: int = DEMO_TERRAIN_POINTS
    mesh_domain: str = DEMO_MESH_DOMAIN
    mesh_angle: float = DEMO_MESH_ANGLE
    repeat: int = DEMO_REPEAT
    assoc_list_max_n: int | None = DEMO_ASSOC_LIST_MAX_N
    seed: int = DEFAULT_SEED


@dataclass(frozen=True, slots=True)
class StageContext:
    """What a stage is given: the settings, and a callback that moves its progress bar."""

    settings: DemoSettings
    progress: ProgressCallback
    """``(steps done, steps in all, what runs now)``."""


@dataclass(frozen=True, slots=True)
class StageResult:
    """What a stage made: the files it wrote, a summary to print, and any failures (which fail the demo)."""

    files: list[Path]
    summary: RenderableType | None = None
    failures: list[str] = field(default_factory=list)


@dataclass(frozen=True, slots=True)
class DemoStage:
    """One step of the demo."""

    name: str
    title: str
    run: Callable[[StageContext], StageResult]


def without_unavailable(bench: MapBench) -> tuple[MapBench, str | None]:
    """``bench`` without the rows of maps that could not be loaded, and one line naming them and how to get them.

    The line is ``None`` when every map loaded.  The peers and adapters come with
    the ``adapters`` extra (``make demo`` installs it); a demo run without them
    shows what it measured rather than a block of "unavailable" rows.
    """
    missing = bench.unavailable()
    if not missing:
        return bench, None
    shown = replace(bench, records=tuple(r for r in bench.records if r.status != "unavailable"))
    note = f"not compared, not installed: {', '.join(missing)} (pip install 'persistri[adapters]' to compare them)"
    return shown, note


def mesh_stage(ctx: StageContext) -> StageResult:
    """A quality mesh of a gallery domain, verified exactly; ``mesh_<domain>.npz`` and ``mesh_<domain>.png``."""
    import time

    from rich.table import Table

    from persistri.impl.cli.mesh import npz_arrays
    from persistri.impl.files import write_mesh
    from persistri.impl.mesh.api import triangulate
    from persistri.impl.mesh.gallery import gallery_domain
    from persistri.impl.mesh.plot import plot_mesh
    from persistri.impl.mesh.verify import verify_mesh

    s = ctx.settings
    domain = gallery_domain(s.mesh_domain)
    done = [0]

    def tick(k: int) -> None:
        done[0] += k
        ctx.progress(done[0], done[0], f"{domain.name} at {s.mesh_angle:g}°: {done[0]:,} insertions")

    start = time.perf_counter()
    mesh = triangulate(domain.pslg, min_angle=s.mesh_angle, progress=tick)
    seconds = time.perf_counter() - start
    report = verify_mesh(mesh.domain, mesh.vertices, mesh.triangles, min_angle=s.mesh_angle,
                         exact_segments=mesh.exact_segments)
    smallest = mesh.smallest_angle()
    stem = f"mesh_{domain.name.replace('-', '_')}"
    npz = write_mesh(s.out / f"{stem}.npz", mesh.vertices, mesh.triangles, npz_arrays=npz_arrays(mesh, smallest))
    png = plot_mesh(
        mesh.vertices, mesh.triangles, s.out / f"{stem}.png", segments=mesh.segments,
        n_input=mesh.domain.vertices.shape[0], min_angle=s.mesh_angle,
        title=f"{domain.name} ({domain.description}): {len(mesh.triangles):,} triangles, "
        f"min angle ≥ {s.mesh_angle:g}°, {mesh.undos} undos",
    )
    table = Table(title=f"quality mesh ({domain.name}, Ruppert's refinement, red-black backend)", show_header=False)
    table.add_column()
    table.add_column(justify="right")
    for name, value in (
        ("triangles / vertices", f"{len(mesh.triangles):,} / {len(mesh.vertices):,}"),
        ("min angle reached", f"{report.min_angle_unexempt:.2f}° (bound {s.mesh_angle:g}°)" if report.min_angle_unexempt is not None else "-"),
        ("insertions (versions kept)", f"{mesh.insertions:,} ({len(mesh.history):,})"),
        ("segment splits / circumcentres, off-centres", f"{mesh.segment_splits:,} / {mesh.circumcenters + mesh.offcenters:,}"),
        ("undos (back to the previous version)", f"{mesh.undos:,}"),
        ("deletions (free vertices in a split subsegment's circle)", f"{mesh.deletions:,}"),
        ("exact verification", "ok" if report.ok else str(report)),
        ("seconds", f"{seconds:.2f}"),
    ):
        table.add_row(name, value)
    failures = [] if report.ok else [f"mesh: {report}"]
    return StageResult([npz, png], table, failures)


def maps_stage(ctx: StageContext) -> StageResult:
    """Run the map benchmark and write ``bench_maps.json``, ``bench_maps.txt`` and ``bench_maps.png``.

    The JSON keeps every record; the table, text and chart leave out maps that
    are not installed, with one line saying how to get them (:func:`without_unavailable`).
    """
    s = ctx.settings
    result = run_map_bench(
        s.bench_sizes, repeat=s.repeat, seed=s.seed, assoc_list_max_n=s.assoc_list_max_n, on_progress=ctx.progress
    )
    shown, note = without_unavailable(result)
    json_path, txt_path, png_path = (s.out / f"bench_maps.{ext}" for ext in ("json", "txt", "png"))
    json_path.write_text(json.dumps(result.as_dict(), indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    txt_path.write_text(maps_text(shown) + ("" if note is None else note + "\n"), encoding="utf-8")
    save_maps_chart(shown, png_path)
    failures = [f"bench maps: {r.map} at n={r.n:,}: {r.note}" for r in result.errors()]
    summary: RenderableType = maps_report(shown) if note is None else Group(maps_report(shown), Text(note))
    return StageResult([json_path, txt_path, png_path], summary, failures)


def hull_stage(ctx: StageContext) -> StageResult:
    """The exact hull of BordHeavy points, checked and verified; ``hull.npz``, ``hull.ply``, ``hull.png``."""
    import time

    from rich.table import Table

    from persistri.impl.files import write_mesh
    from persistri.impl.hull.api import convex_hull
    from persistri.impl.hull.distributions import generate
    from persistri.impl.hull.plot import plot_hull
    from persistri.impl.hull.verify import verify_hull
    from persistri.impl.stats import Stats

    s = ctx.settings
    n = s.hull_points
    points = generate("BordHeavy", n, s.seed)
    total = max(n - 4, 1)
    done = [0]

    def tick(k: int) -> None:
        done[0] += k
        if done[0] % 256 == 0 or done[0] == total:
            ctx.progress(done[0], total, f"BordHeavy n={n:,}, checked at every insertion")

    stats = Stats()
    start = time.perf_counter()
    hull = convex_hull(points, seed=s.seed, check=True, history=True, stats=stats, progress=tick)
    seconds = time.perf_counter() - start
    report = verify_hull(points, hull.simplices)
    out = s.out
    npz = write_mesh(
        out / "hull.npz", points, hull.simplices,
        npz_arrays={"points": points, "simplices": hull.simplices, "vertices": hull.vertices},
    )
    ply = write_mesh(out / "hull.ply", points, hull.simplices)
    png = plot_hull(points, hull.simplices, out / "hull.png", title=f"BordHeavy, n = {n:,}: {report}")
    table = Table(title="convex hull (bulldozer, red-black backend)", show_header=False)
    table.add_column()
    table.add_column(justify="right")
    assert hull.history is not None
    for name, value in (
        ("points", f"{n:,}"),
        ("faces", f"{len(hull.simplices):,}"),
        ("vertices", f"{len(hull.vertices):,}"),
        ("hull versions kept", f"{len(hull.history):,}"),
        ("key comparisons", f"{stats.key_comparisons:,}"),
        ("plane-side tests", f"{stats.plane_side_tests:,}"),
        ("exact verification", str(report)),
        ("seconds (with check=True)", f"{seconds:.1f}"),
    ):
        table.add_row(name, value)
    failures = [] if report.ok else [f"hull: {report}"]
    return StageResult([npz, ply, png], table, failures)


def terrain_stage(ctx: StageContext) -> StageResult:
    """Greedy insertion on the Jacksboro DEM, checked and verified; ``terrain_jacksboro.{npz,ply,png}``."""
    import time

    import numpy as np
    from rich.table import Table

    from persistri.impl.files import write_mesh
    from persistri.impl.stats import Stats
    from persistri.impl.terrain.check import verify_tin
    from persistri.impl.terrain.greedy import greedy_insertion
    from persistri.impl.terrain.grids import jacksboro
    from persistri.impl.terrain.plot import plot_tin

    s = ctx.settings
    k = s.terrain_points
    grid = jacksboro()
    total = max(k - 4, 1)
    done = [0]

    def tick(n: int) -> None:
        done[0] += n
        if done[0] % 128 == 0 or done[0] == total:
            ctx.progress(done[0], total, f"Jacksboro DEM to {k:,} points, checked at every insertion")

    stats = Stats()
    start = time.perf_counter()
    tin = greedy_insertion(grid.heights, max_points=k, check=True, stats=stats, progress=tick, transform=grid.transform)
    seconds = time.perf_counter() - start
    report = verify_tin(tin, grid.heights)
    out = s.out
    npz = write_mesh(
        out / "terrain_jacksboro.npz", tin.vertices, tin.triangles,
        npz_arrays={"vertices": tin.vertices, "triangles": tin.triangles, "max_error": np.float64(tin.max_error),
                    "rms_error": np.float64(tin.rms_error), "samples": tin.samples},
    )
    ply = write_mesh(out / "terrain_jacksboro.ply", tin.vertices, tin.triangles)
    png = plot_tin(grid.heights, tin.vertices, tin.triangles, out / "terrain_jacksboro.png",
                   title=f"Jacksboro DEM: {tin.n_points:,} points, max error {tin.max_error:.1f} m")
    assert tin.history is not None
    coarse = tin.history.at(points=min(500, tin.n_points))
    table = Table(title="terrain (greedy insertion, red-black backend)", show_header=False)
    table.add_column()
    table.add_column(justify="right")
    for name, value in (
        ("grid", f"{tin.shape[0]} × {tin.shape[1]} samples"),
        ("points / triangles", f"{tin.n_points:,} / {len(tin.triangles):,}"),
        ("max / rms error (m)", f"{tin.max_error:.1f} / {tin.rms_error:.2f}"),
        ("levels of detail kept", f"{len(tin.history):,}"),
        (f"from history: {coarse.n_points} points", f"max error {coarse.max_error:.1f} m"),
        ("key comparisons", f"{stats.key_comparisons:,}"),
        ("plane-side tests", f"{stats.plane_side_tests:,}"),
        ("exact verification", "ok" if report.ok else "; ".join(report.failures)),
        ("seconds (with check=True)", f"{seconds:.1f}"),
    ):
        table.add_row(name, value)
    failures = [] if report.ok else [f"terrain: {'; '.join(report.failures)}"]
    return StageResult([npz, ply, png], table, failures)


STAGES: tuple[DemoStage, ...] = (
    DemoStage("hull", "exact convex hull", hull_stage),
    DemoStage("terrain", "terrain mesh (Jacksboro DEM)", terrain_stage),
    DemoStage("mesh", "quality mesh (Ruppert, undo by persistence)", mesh_stage),
    DemoStage("maps", "persistent maps vs. their peers", maps_stage),
)
"""The demo's stages, in the order they run."""


def run_demo(settings: DemoSettings, console: Console, stages: Sequence[DemoStage] | None = None) -> list[StageResult]:
    """Run ``stages`` (default :data:`STAGES`) in order under one rich progress display on ``console``.

    Each stage's summary is printed as it finishes.  The bars are drawn only on a terminal
    (elsewhere rich would print them all at the end, after the summaries).
    """
    if stages is None:
        stages = STAGES
    settings.out.mkdir(parents=True, exist_ok=True)
    results: list[StageResult] = []
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
    with Progress(*columns, console=console, disable=not console.is_terminal) as progress:
        for stage in stages:
            task = progress.add_task(stage.title, total=None)

            def update(done: int, total: int, what: str, task: TaskID = task, title: str = stage.title) -> None:
                progress.update(task, completed=done, total=total, description=f"{title}: {what}")

            result = stage.run(StageContext(settings, update))
            progress.update(task, description=f"{stage.title}: done")
            if result.summary is not None:
                progress.console.print(result.summary)
            results.append(result)
    return results


@click.command(short_help="What make demo runs: every stage, its results in --out.")
@click.option(
    "--out",
    type=FILE_PATH,
    default=Path("out"),
    show_default=True,
    help="Directory to write the results into (created if missing; its parent must exist).",
)
@click.option(
    "--bench-sizes",
    default=",".join(map(str, DEMO_BENCH_SIZES)),
    callback=lambda ctx, param, value: parse_sizes(value),
    hidden=True,
    help="Key counts of the map benchmark (for quick runs and tests).",
)
@click.option("--repeat", type=click.IntRange(min=1), default=DEMO_REPEAT, hidden=True, help="Timed runs per benchmark figure.")
@click.option("--hull-points", type=click.IntRange(min=4), default=DEMO_HULL_POINTS, hidden=True, help="Points of the hull stage.")
@click.option("--terrain-points", type=click.IntRange(min=4), default=DEMO_TERRAIN_POINTS, hidden=True, help="Vertices of the terrain stage.")
def demo(out: Path, bench_sizes: tuple[int, ...], repeat: int, hull_points: int, terrain_points: int) -> None:
    """Run the demo: every stage in turn, writing its results into --out.

    Now: the exact convex hull of 4,000 BordHeavy points, checked at every
    insertion (hull.npz, .ply, .png), the Jacksboro DEM meshed by greedy insertion
    to 2,000 points (terrain_jacksboro.npz, .ply, .png), a quality mesh of the
    comb domain at 30° by Ruppert's refinement (mesh_comb.npz, .png), and the
    map benchmark at 10^3 and 10^4 keys
    (bench_maps.json, .txt, .png).  Exit status 1 if a stage reports a failure.
    """
    check_output_dir(out)
    settings = DemoSettings(
        out=out, bench_sizes=bench_sizes, repeat=repeat, hull_points=hull_points, terrain_points=terrain_points
    )
    console = stdout_console()
    results = run_demo(settings, console)
    console.print("wrote:", *(str(p) for r in results for p in r.files), sep="\n  ")
    failures = [f for r in results for f in r.failures]
    for failure in failures:
        click.echo(f"persistri demo: {failure}", err=True)
    if failures:
        raise SystemExit(1)
