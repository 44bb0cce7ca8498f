"""The quality-mesh benchmark (``persistri bench mesh``): Ruppert's refinement against Triangle, in the same run.

On every domain of the bench gallery (:mod:`persistri.impl.mesh.gallery`: a
square with a hole, an L-shape, a star with 20° tips, a circle, a cracked
square, a UTM-offset tile, a comb) and each minimum-angle bound (20°, 30° and
33° by default), optionally with a maximum area (one bound for every domain,
or ``size=N``: each domain's exact area over ``N``, about ``N`` to ``2N``
triangles, to compare at 10⁴–10⁵ triangles):

* **Triangle** — Shewchuk's, through the ``triangle`` package:
  ``triangle.triangulate(domain.to_dict(), "pq<angle>[a<area>]")``;
* **persistri** — :func:`persistri.impl.mesh.api.triangulate` with its
  defaults (lenses, off-centres) and the same bounds;
* for each: triangles, vertices, the smallest angle outside Ruppert's exemption
  and the exempt triangles, as the exact checker measures them
  (:func:`~persistri.impl.mesh.verify.verify_mesh`, run with the bounds: a mesh
  *passes* when it is a valid constrained Delaunay mesh of the domain that meets
  them; Triangle's with ``exact_segments=False``, since its split points are
  rounded), and persistri's undos, deletions (Chew's: free vertices in a
  subsegment's diametral circle, deleted before it is split), insertions and
  segment splits;
* the ratios persistri ÷ Triangle of the triangle counts and of the times.

Times are CPU seconds (``time.process_time``) of one call from the same input —
the domain as Triangle's dictionary of arrays, which ``triangulate`` validates
as a :class:`~persistri.impl.mesh.domain.PSLG` inside the timed call, as a user's
call does — warm (each timed call right after an untimed one of the same
mesher, so that neither starts with the caches the collector's full pass just
emptied: Triangle's small domains run 5× slower cold), the cyclic collector off
during both, best of ``repeat`` rounds; each round runs Triangle, then persistri,
on the same domain, so that a machine whose speed drifts affects both alike.
A persistri run that stops with :class:`~persistri.impl.mesh.steiner.PrecisionLimitError`
(a split where no double lies on the segment) is recorded as ``limit`` with its
message.  A benchmark, not a test: its tests check the counts, never the times.
"""

from __future__ import annotations

import gc
import platform
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from typing import TYPE_CHECKING, Any, Final

import numpy as np

from persistri.impl.bench.hull import persistri_build

if TYPE_CHECKING:
    from persistri.impl.mesh.domain import PSLG

__all__ = [
    "DEFAULT_ANGLES",
    "DEFAULT_REPEAT",
    "TriangleMissingError",
    "MesherRun",
    "MeshRecord",
    "MeshBench",
    "triangle_switches",
    "triangle_version",
    "run_mesh_bench",
    "mesh_table",
]

DEFAULT_ANGLES: Final = (20.0, 30.0, 33.0)
"""The minimum-angle bounds of the issue's comparison: Triangle users' common 20°–33°."""

DEFAULT_REPEAT: Final = 5
"""Timed rounds per domain and bound; the best of each mesher is kept."""

ProgressCallback = Callable[[int, int, str], None]
"""``(steps done, steps in all, what runs next)``."""


class TriangleMissingError(ImportError):
    """The ``triangle`` package (Shewchuk's Triangle) is not installed: the benchmark has no peer."""


def triangle_version() -> str:
    """The installed ``triangle`` package's version; :class:`TriangleMissingError` when it is missing."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        import triangle  # noqa: F401
    except ImportError:
        raise TriangleMissingError(
            "bench mesh compares with Shewchuk's Triangle, which is not installed: pip install triangle "
            "(or pip install 'persistri[dev]')"
        ) from None
    try:
        return version("triangle")
    except PackageNotFoundError:
        return "unknown"


@dataclass(frozen=True, slots=True)
class MesherRun:
    """One mesher on one domain at one bound.

    ``status`` is ``"ok"``, ``"limit"`` (persistri stopped at the limit of double
    precision: ``note`` says where) or ``"error"`` (anything else: ``note``).
    ``min_angle`` is the smallest angle outside the exempt triangles and
    ``min_angle_all`` over all, in degrees, as :func:`verify_mesh` measures them;
    ``passes`` whether the mesh passes it with the bounds (``problem``: the first
    problem otherwise).  ``undos``, ``deletions``, ``insertions``, ``segment_splits``
    and ``rounded_splits`` are persistri's (None for Triangle).
    """

    mesher: str
    status: str
    seconds: float
    triangles: int = 0
    vertices: int = 0
    min_angle: float | None = None
    min_angle_all: float | None = None
    exempt: int = 0
    passes: bool = False
    problem: str = ""
    undos: int | None = None
    deletions: int | None = None
    insertions: int | None = None
    segment_splits: int | None = None
    rounded_splits: int | None = None
    note: str = ""

    @property
    def reached(self) -> bool:
        """Whether the mesh is valid and meets the bounds (outside the exemption)."""
        return self.status == "ok" and self.passes


@dataclass(frozen=True, slots=True)
class MeshRecord:
    """One domain at one angle bound (and area bound): Triangle and persistri."""

    domain: str
    angle: float
    max_area: float | None
    triangle: MesherRun
    persistri: MesherRun

    @property
    def count_ratio(self) -> float | None:
        """persistri's triangles ÷ Triangle's (None when either did not finish)."""
        if self.triangle.status != "ok" or self.persistri.status != "ok" or self.triangle.triangles == 0:
            return None
        return self.persistri.triangles / self.triangle.triangles

    @property
    def time_ratio(self) -> float | None:
        """persistri's best time ÷ Triangle's (None when either did not finish)."""
        if self.triangle.status != "ok" or self.persistri.status != "ok" or self.triangle.seconds <= 0:
            return None
        return self.persistri.seconds / self.triangle.seconds

    @property
    def reached_where_triangle_does(self) -> bool:
        """The issue's target: persistri meets the bounds wherever Triangle does."""
        return self.persistri.reached or not self.triangle.reached


@dataclass
class MeshBench:
    """The whole benchmark: what was measured and how."""

    domains: tuple[str, ...]
    angles: tuple[float, ...]
    max_area: float | None
    size: int | None
    repeat: int
    triangle: str
    python: str = field(default_factory=lambda: f"Python {sys.version.split()[0]}")
    machine: str = field(default_factory=lambda: f"{platform.machine()} {platform.system()}")
    build: str = field(default_factory=persistri_build)
    records: list[MeshRecord] = field(default_factory=list)

    def errors(self) -> list[MeshRecord]:
        """Records where persistri's mesh failed the checker or the run raised (a bug, not a limit)."""
        return [
            r for r in self.records
            if r.persistri.status == "error" or (r.persistri.status == "ok" and not r.persistri.passes)
        ]

    def as_dict(self) -> dict[str, Any]:
        """A JSON-ready dictionary (ratios included)."""
        return {
            "domains": list(self.domains),
            "angles": list(self.angles),
            "max_area": self.max_area,
            "size": self.size,
            "repeat": self.repeat,
            "triangle": self.triangle,
            "python": self.python,
            "machine": self.machine,
            "build": self.build,
            "timer": "CPU seconds (time.process_time) of a warm call (after an untimed one) from Triangle's "
            "dictionary, cyclic GC off, best of the rounds; each round runs Triangle then persistri on the same domain",
            "records": [
                {
                    "domain": r.domain,
                    "angle": r.angle,
                    "max_area": r.max_area,
                    "triangle": asdict(r.triangle),
                    "persistri": asdict(r.persistri),
                    "count_ratio": r.count_ratio,
                    "time_ratio": r.time_ratio,
                    "reached_where_triangle_does": r.reached_where_triangle_does,
                }
                for r in self.records
            ],
        }


def _number(x: float) -> str:
    """A number as Triangle's switch parser reads it: digits and a point, never an exponent."""
    return str(np.format_float_positional(float(x), trim="-"))


def triangle_switches(angle: float, max_area: float | None) -> str:
    """Triangle's switches for a PSLG at these bounds: ``p``, ``q<angle>`` (none for 0), ``a<area>``."""
    switches = "p"
    if angle > 0:
        switches += f"q{_number(angle)}"
    if max_area is not None:
        switches += f"a{_number(max_area)}"
    return switches


def _measure(
    domain: PSLG, vertices: Any, triangles: Any, angle: float, max_area: float | None, exact_segments: bool
) -> dict[str, Any]:
    """What the exact checker says of one mesh, as :class:`MesherRun` fields."""
    from persistri.impl.mesh.verify import verify_mesh

    report = verify_mesh(
        domain, vertices, triangles, min_angle=angle or None, max_area=max_area, exact_segments=exact_segments
    )
    return {
        "triangles": int(len(triangles)),
        "vertices": int(len(vertices)),
        "min_angle": report.min_angle_unexempt,
        "min_angle_all": report.min_angle,
        "exempt": report.exempt,
        "passes": report.ok,
        "problem": "" if report.ok else str(report.problems[0]),
    }


def warm_cpu_seconds(run: Callable[[], Any]) -> tuple[float, Any]:
    """(CPU seconds of one call of ``run``, its result), timed right after an untimed call, the collector off.

    A full collection (``gc.collect``) walks every object and leaves the caches cold; a
    millisecond mesher timed after it measures the refill (H3's measure, docs/performance.md).
    """
    enabled = gc.isenabled()
    gc.collect()
    gc.disable()
    try:
        run()
        t0 = time.process_time()
        result = run()
        return time.process_time() - t0, result
    finally:
        if enabled:
            gc.enable()


def _bench_one(name: str, domain: PSLG, angle: float, max_area: float | None, repeat: int) -> MeshRecord:
    import triangle

    from persistri.impl.mesh.api import triangulate
    from persistri.impl.mesh.steiner import PrecisionLimitError

    data = domain.to_dict()
    switches = triangle_switches(angle, max_area)
    t_best = p_best = float("inf")
    t_out: Any = None
    p_mesh: Any = None
    p_failure: tuple[str, str] | None = None
    for _ in range(repeat):
        seconds, t_out = warm_cpu_seconds(lambda: triangle.triangulate(data, switches))
        t_best = min(t_best, seconds)
        if p_failure is not None:
            continue
        try:
            seconds, p_mesh = warm_cpu_seconds(lambda: triangulate(data, min_angle=angle, max_area=max_area))
        except PrecisionLimitError as exc:
            p_failure = ("limit", str(exc).splitlines()[0])
        except Exception as exc:  # a bug in persistri: recorded, and the bench exits 1
            p_failure = ("error", f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}")
        else:
            p_best = min(p_best, seconds)
    t_run = MesherRun(
        "triangle", "ok", t_best,
        **_measure(domain, t_out["vertices"], t_out["triangles"], angle, max_area, exact_segments=False),
    )
    if p_failure is not None:
        p_run = MesherRun("persistri", p_failure[0], float("nan"), note=p_failure[1])
    else:
        p_run = MesherRun(
            "persistri", "ok", p_best,
            undos=p_mesh.undos, deletions=p_mesh.deletions, insertions=p_mesh.insertions, segment_splits=p_mesh.segment_splits,
            rounded_splits=p_mesh.rounded_splits,
            **_measure(domain, p_mesh.vertices, p_mesh.triangles, angle, max_area, p_mesh.exact_segments),
        )
    return MeshRecord(name, angle, max_area, t_run, p_run)


def run_mesh_bench(
    domains: Sequence[str] | None = None,
    angles: Sequence[float] = DEFAULT_ANGLES,
    *,
    max_area: float | None = None,
    size: int | None = None,
    repeat: int = DEFAULT_REPEAT,
    on_progress: ProgressCallback | None = None,
) -> MeshBench:
    """Run the benchmark (module docstring) on the gallery ``domains`` (default: all) at each of ``angles``.

    ``max_area`` bounds every triangle's area on every domain; ``size`` instead
    bounds it by each domain's exact area over ``size`` (not both).  Raises
    :class:`TriangleMissingError` without the ``triangle`` package, and
    :class:`ValueError` for an unknown domain or a bad bound.
    """
    from persistri.impl.mesh.domain import domain_of
    from persistri.impl.mesh.gallery import GALLERY, gallery_domain

    version = triangle_version()
    names = tuple(GALLERY if domains is None else domains)
    unknown = [n for n in names if n not in GALLERY]
    if unknown:
        raise ValueError(f"unknown gallery domain {', '.join(unknown)}; the domains are {', '.join(GALLERY)}")
    if not names:
        raise ValueError("no domain to measure")
    bounds = tuple(float(a) for a in angles)
    if not bounds or any(not 0.0 <= a < 60.0 for a in bounds):
        raise ValueError(f"angle bounds must be degrees in [0, 60), got {', '.join(map(str, angles)) or 'none'}")
    if max_area is not None and size is not None:
        raise ValueError("give max_area or size, not both")
    if max_area is not None and not (np.isfinite(max_area) and max_area > 0):
        raise ValueError(f"max_area must be a positive number, got {max_area}")
    if size is not None and size < 1:
        raise ValueError(f"size must be a positive triangle count, got {size}")
    if repeat < 1:
        raise ValueError(f"repeat must be at least 1, got {repeat}")
    bench = MeshBench(names, bounds, max_area, size, repeat, version)
    # The map backend is imported on its first use; load it before any clock starts, so that a first round does not
    # time an import (Triangle's import is not timed either).
    from persistri.impl.maps import backend as map_backend

    map_backend("int_trie")
    steps = len(names) * len(bounds)
    done = 0
    for name in names:
        domain = gallery_domain(name).pslg
        area = max_area if size is None else float(domain_of(domain).area) / size
        for angle in bounds:
            if on_progress is not None:
                on_progress(done, steps, f"{name} at {angle:g}°")
            bench.records.append(_bench_one(name, domain, angle, area, repeat))
            done += 1
    if on_progress is not None:
        on_progress(done, steps, "done")
    return bench


def _angle(run: MesherRun) -> str:
    if run.status != "ok" or run.min_angle is None:
        return ""
    exempt = f" ({run.exempt} ex)" if run.exempt else ""
    return f"{run.min_angle:.1f}{exempt}"


def _ms(run: MesherRun) -> str:
    return f"{run.seconds * 1e3:,.1f}" if run.status == "ok" else ""


def _ratio(x: float | None, digits: int) -> str:
    return "" if x is None else f"{x:,.{digits}f}"


def mesh_table(bench: MeshBench) -> Any:
    """The benchmark as a rich renderable: one row per domain and bound, then the notes of runs that stopped."""
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    area = (
        f", max area {bench.max_area:g}" if bench.max_area is not None
        else f", max area = domain area / {bench.size:,}" if bench.size is not None else ""
    )
    table = Table(
        title=f"Quality meshes: persistri (Ruppert, undo by persistence) against Triangle {bench.triangle}{area}",
        caption=(
            f"T = Triangle, p = persistri; min angle: the smallest outside Ruppert's exemption (ex: exempt triangles), "
            f"exact checker's measure; ok: passes verify_mesh with the bounds (Triangle's with rounded split points "
            f"allowed); ms: CPU of a warm call (after an untimed one) from the same arrays, best of {bench.repeat} round(s), cyclic GC off; {bench.python} on {bench.machine}; "
            f"persistri {bench.build}"
        ),
        header_style="bold",
    )
    for name, justify in (
        ("domain", "left"), ("angle", "right"), ("T tris", "right"), ("p tris", "right"), ("p/T", "right"),
        ("T verts", "right"), ("p verts", "right"), ("T min°", "right"), ("p min°", "right"), ("T ok", "left"),
        ("p ok", "left"), ("undos", "right"), ("T ms", "right"), ("p ms", "right"), ("time ×", "right"),
    ):
        table.add_column(name, justify=justify, no_wrap=True)  # type: ignore[arg-type]  # rich's JustifyMethod literal
    previous = None
    notes: list[str] = []
    for r in bench.records:
        if previous is not None and previous != r.domain:
            table.add_section()
        t, p = r.triangle, r.persistri
        p_ok = "yes" if p.reached else ("NO" if p.status == "ok" else p.status)
        if p.status != "ok":
            notes.append(f"{r.domain} at {r.angle:g}°: persistri {p.status}: {p.note}")
        elif not p.passes:
            notes.append(f"{r.domain} at {r.angle:g}°: persistri's mesh: {p.problem}")
        if p.rounded_splits:
            notes.append(
                f"{r.domain} at {r.angle:g}°: persistri rounded {p.rounded_splits} split point(s) to the nearest "
                "doubles, off the segment by an ulp (as Triangle does); checked with rounding allowed"
            )
        if not t.passes:
            notes.append(f"{r.domain} at {r.angle:g}°: Triangle's mesh: {t.problem}")
        table.add_row(
            r.domain if r.domain != previous else "",
            f"{r.angle:g}",
            f"{t.triangles:,}",
            f"{p.triangles:,}" if p.status == "ok" else "",
            _ratio(r.count_ratio, 2),
            f"{t.vertices:,}",
            f"{p.vertices:,}" if p.status == "ok" else "",
            _angle(t),
            _angle(p),
            "yes" if t.passes else "NO",
            p_ok,
            f"{p.undos:,}" if p.undos is not None else "",
            _ms(t),
            _ms(p),
            _ratio(r.time_ratio, 0),
        )
        previous = r.domain
    parts: list[Any] = [table]
    parts += [Text(n) for n in notes]
    return Group(*parts)
