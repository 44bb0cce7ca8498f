"""The picture series of one Ruppert refinement, read back from its history: ``mesh-refinement.png`` (docs/meshing.md).

Drawn by ``docs/figures.py`` (``make docs``).  One refinement of a gallery
domain (:data:`MESH_DOMAIN` at :data:`MESH_MIN_ANGLE` degrees with the area
bound :data:`MESH_MAX_AREA`) is run once; every panel is a version read from
``mesh.history`` — the constrained Delaunay triangulation it starts from, the
version an **undo** returned to with the circumcentre that was tried and
dropped, the version in which the subsegment it encroached was split instead,
a later version and the final mesh — and a chart of the whole history.

The points the run dropped come from its own record, ``mesh.history.undone``
and ``mesh.history.blocked`` (:mod:`persistri.impl.mesh.record`); before anything
is drawn the record is checked against the run (:func:`checked_record`;
:class:`FigureCheckError` on any disagreement): one record per undo and per
blocked point the run counted; no dropped point in any kept version; each undone
point strictly inside the diametral lens of every subsegment it is recorded to
encroach (exact, on predicates built from the recorded coordinates alone), that
subsegment present in the version it was tried on and split — replaced by two
halves through the point that version adds — in the version recorded; the
cavity's triangles in the version tried on.  Every version drawn passes
:func:`~persistri.impl.mesh.verify.verify_mesh`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.api import QualityMesh, triangulate
from persistri.impl.mesh.gallery import gallery_domain
from persistri.impl.mesh.plot import draw_mesh, mesh_origin
from persistri.impl.mesh.quality import inside_lens
from persistri.impl.mesh.record import Blocked, Undone
from persistri.impl.mesh.verify import verify_mesh

__all__ = [
    "MESH_DOMAIN",
    "MESH_MIN_ANGLE",
    "MESH_MAX_AREA",
    "FigureCheckError",
    "Record",
    "refinement_run",
    "checked_record",
    "draw_refinement",
]

MESH_DOMAIN = "l-shape"
MESH_MIN_ANGLE = 30.0
MESH_MAX_AREA = 0.05
"""The run the picture series is drawn from: small enough to read, with undos and blocked points."""

Tri = tuple[int, int, int]
Edge = tuple[int, int]


class FigureCheckError(AssertionError):
    """What a picture was about to show disagrees with the run."""


def _require(cond: bool, message: str) -> None:
    if not cond:
        raise FigureCheckError(message)


@dataclass(frozen=True)
class Record:
    """The run's dropped points, checked against the run: ``undone`` and ``blocked`` as the history records them."""

    undone: tuple[Undone, ...]
    blocked: tuple[Blocked, ...]


def refinement_run(name: str = MESH_DOMAIN, min_angle: float = MESH_MIN_ANGLE, max_area: float | None = MESH_MAX_AREA) -> QualityMesh:
    """The refinement the series is drawn from (deterministic: no seed is involved)."""
    return triangulate(gallery_domain(name).pslg, min_angle=min_angle, max_area=max_area)


def _subsegments(mesh: QualityMesh, k: int) -> set[frozenset[int]]:
    """Version ``k``'s subsegments, as pairs of point indices."""
    arr = mesh.history.mesh(k)
    return {frozenset(int(v) for v in row) for row in arr.points[arr.segments].tolist()}


def _triangles(mesh: QualityMesh, k: int) -> set[Tri]:
    """Version ``k``'s finite triangles (domain and exterior), as point indices in their stored rotation."""
    out: set[Tri] = set()
    for t, _ in mesh.history.structure.items(mesh.history[k]):
        a, b, c = (int(v) for v in t)
        if min(a, b, c) >= 0:
            out.update({(a, b, c), (b, c, a), (c, a, b)})
    return out


def _encroaches(mesh: QualityMesh, lo: int, hi: int, p: int) -> bool:
    """Whether ``p`` lies strictly inside the diametral lens of ``{lo, hi}`` at the run's bound: exact, on
    predicates over the three recorded points alone."""
    P = GrowingPredicates2(np.array([mesh.history.point(v) for v in (lo, hi, p)]))
    return P.dot_sign(0, 1, 2) < 0 and inside_lens(P, 0, 1, 2, mesh.min_angle)


def checked_record(mesh: QualityMesh) -> Record:
    """The run's record of its dropped points, checked against the run (module docstring)."""
    history = mesh.history
    undone, blocked = history.undone, history.blocked
    _require(len(undone) == mesh.undos, f"{len(undone)} undone insertions recorded; the run undid {mesh.undos}")
    _require(len(blocked) == mesh.blocked, f"{len(blocked)} blocked points recorded; the run blocked {mesh.blocked}")
    kept = {int(p) for p in history.inserted}
    last = len(history) - 1
    for d in (*undone, *blocked):
        _require(0 <= d.version <= last, f"point {d.point} was tried on version {d.version}, not in the history")
        _require(d.point not in kept, f"point {d.point}, recorded as dropped, is in a kept version")
        _require(history.point(d.point) == d.xy, f"point {d.point} is recorded at {d.xy}, not where it is")
    for d in undone:
        _require(bool(d.encroached), f"undone point {d.point} encroaches nothing")
        segs = _subsegments(mesh, d.version)
        tris = _triangles(mesh, d.version)
        _require(all(t in tris for t in d.cavity), f"undone point {d.point}: its cavity is not in version {d.version}")
        for (lo, hi, _), at in zip(d.encroached, d.split_at):
            _require(frozenset((lo, hi)) in segs, f"undone point {d.point}: ({lo}, {hi}) is no subsegment of version {d.version}")
            _require(_encroaches(mesh, lo, hi, d.point), f"undone point {d.point} does not encroach ({lo}, {hi})")
            _require(at is not None and d.version < at <= last, f"undone point {d.point}: ({lo}, {hi}) was never split")
            assert at is not None
            q = int(history.inserted[at - 1])
            before, after = _subsegments(mesh, at - 1), _subsegments(mesh, at)
            _require(
                frozenset((lo, hi)) in before and frozenset((lo, hi)) not in after
                and {frozenset((lo, q)), frozenset((q, hi))} <= after,
                f"after undoing point {d.point}, version {at} adds point {q}, not splitting ({lo}, {hi})",
            )
    return Record(undone, blocked)


def _edges(t: Tri) -> tuple[Edge, Edge, Edge]:
    a, b, c = t
    return ((a, b), (b, c), (c, a))


def _check_version(mesh: QualityMesh, k: int) -> None:
    arr = mesh.history.mesh(k)
    report = verify_mesh(mesh.domain, arr.vertices, arr.triangles)
    _require(report.ok, f"history[{k}] is not a valid constrained Delaunay mesh of the domain: {report}")


def _marks(ax: Any, mesh: QualityMesh, origin: Any, points: Sequence[int], style: dict[str, Any]) -> None:
    if points:
        xy = np.array([mesh.history.point(p) for p in points]) - origin
        ax.plot(xy[:, 0], xy[:, 1], linestyle="none", zorder=6, **style)


_UNDONE: dict[str, Any] = {"marker": "x", "color": "#d01010", "markersize": 7, "markeredgewidth": 2}
_BLOCKED: dict[str, Any] = {"marker": "+", "color": "#606060", "markersize": 7, "markeredgewidth": 1.5}
_DELETED: dict[str, Any] = {"marker": "o", "color": "none", "markeredgecolor": "#d01010", "markersize": 7}
_SPLIT: dict[str, Any] = {"marker": "s", "color": "#e08000", "markersize": 7, "markeredgecolor": "black"}


def _panel(ax: Any, mesh: QualityMesh, k: int, origin: Any, title: str, *, colour: bool = False) -> Any:
    arr = mesh.history.mesh(k)
    polys = draw_mesh(ax, arr.vertices, arr.triangles, segments=arr.segments, n_input=mesh.domain.vertices.shape[0],
                      origin=origin, colour=colour)
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(title, fontsize=9)
    return polys


def draw_refinement(mesh: QualityMesh, record: Record, out: Path, name: str = MESH_DOMAIN) -> Path:
    """``mesh-refinement.png``: the CDT, an undo and the split after it, a later version, the final mesh, the history."""
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import Circle, Polygon

    at = mesh.history.point
    last = len(mesh.history) - 1
    _require(bool(record.undone), "the run drawn has no undo to show")

    # The undo drawn: the one whose encroached subsegment is longest (its circle reads best), the earliest on a tie.
    def length(d: Undone) -> float:
        lo, hi, _ = d.encroached[0]
        return float(np.hypot(*np.subtract(at(lo), at(hi))))

    show = max(record.undone, key=lambda d: (length(d), -d.version))
    split = show.split_at[0]
    _require(split is not None, f"the subsegment undone point {show.point} encroached was never split")
    assert split is not None
    later = (split + last) // 2
    for k in sorted({0, show.version, split - 1, split, later, last}):
        _check_version(mesh, k)
    origin = mesh_origin(mesh.vertices)
    fig, axes = plt.subplots(2, 3, figsize=(13.5, 9.2))
    a0, a1, a2, a3, a4, a5 = axes.ravel()

    _panel(a0, mesh, 0, origin, f"history[0]: the constrained Delaunay\ntriangulation ({len(mesh.history.mesh(0).triangles)} triangles)")

    what = "the off-centre c of the bad triangle (outlined)" if show.offcenter else "the circumcentre c of the bad triangle (outlined)"
    _panel(a1, mesh, show.version, origin, f"history[{show.version}]: {what}\nencroaches subsegment s: the new version is dropped")
    a1.add_patch(Polygon(np.array([at(v) for v in show.triangle]) - origin, closed=True, fill=False, edgecolor="#d01010",
                         linewidth=2.2, zorder=6))
    for t in show.cavity:
        a1.add_patch(Polygon(np.array([at(v) for v in t]) - origin, closed=True, facecolor="#f4b0b0", edgecolor="none", zorder=2))
    cx, cy = np.subtract(show.xy, origin)
    for t in show.cavity:
        for u, _ in _edges(t):
            x = np.subtract(at(u), origin)
            a1.plot([cx, x[0]], [cy, x[1]], color="#d01010", linewidth=0.8, linestyle="--", zorder=3)
    lo, hi, _ = show.encroached[0]
    pu, pw = np.subtract(at(lo), origin), np.subtract(at(hi), origin)
    a1.plot([pu[0], pw[0]], [pu[1], pw[1]], color="#e08000", linewidth=4, zorder=5)
    a1.add_patch(Circle(tuple((pu + pw) / 2), float(np.hypot(*(pu - pw))) / 2, fill=False, linestyle="--",
                        edgecolor="#e08000", linewidth=1.3, zorder=5))
    a1.plot([cx], [cy], linestyle="none", zorder=7, **_UNDONE)
    a1.annotate("c", (cx, cy), textcoords="offset points", xytext=(6, 4), color="#d01010", fontsize=10, weight="bold")
    a1.annotate("s", tuple((pu + pw) / 2), textcoords="offset points", xytext=(6, -12), color="#b06000", fontsize=10, weight="bold")

    q = int(mesh.history.inserted[split - 1])
    deleted = list(mesh.history.deleted[split - 1])  # free vertices in s's diametral circle (Chew's rule), if any
    also = f", {len(deleted)} free vert{'ex' if len(deleted) == 1 else 'ices'} in its circle deleted" if deleted else ""
    _panel(a2, mesh, split, origin,
           f"history[{split}]: s split instead{also}\n(history[{show.version}] itself was never changed)")
    _marks(a2, mesh, origin, [q], _SPLIT)
    _marks(a2, mesh, origin, deleted, _DELETED)

    _panel(a3, mesh, later, origin, f"history[{later}]: {len(mesh.history.mesh(later).triangles)} triangles")

    polys = _panel(a4, mesh, last, origin,
                   f"history[{last}], the final mesh: {len(mesh.triangles)} triangles,\n"
                   f"min angle ≥ {mesh.min_angle:g}°, {mesh.undos} undos, {mesh.blocked} blocked", colour=True)
    _marks(a4, mesh, origin, [d.point for d in record.undone], _UNDONE)
    _marks(a4, mesh, origin, [d.point for d in record.blocked], _BLOCKED)
    bar = fig.colorbar(polys, ax=a4, shrink=0.75, pad=0.02)
    bar.set_label("smallest angle (°)")

    sizes = [len(mesh.history.mesh(k).triangles) for k in range(last + 1)]
    a5.plot(range(last + 1), sizes, color="#20303a", linewidth=1.2)
    for version, colour in [(d.version, "#d01010") for d in record.undone] + [(d.version, "#909090") for d in record.blocked]:
        a5.axvline(version, color=colour, linewidth=0.8, alpha=0.7)
    a5.set_xlabel("version k (insertions so far)")
    a5.set_ylabel("triangles in history[k]")
    a5.set_title("every version kept: red, an undo from version k;\ngrey, a blocked point"
                 + ("; dips: vertices deleted" if any(b < a for a, b in zip(sizes, sizes[1:])) else ""), fontsize=9)
    a5.set_xlim(0, last)

    handles = [
        Line2D([], [], linestyle="none", **_UNDONE, label="Steiner point tried and undone"),
        Line2D([], [], linestyle="none", **_BLOCKED, label="point blocked by a segment"),
        Line2D([], [], linestyle="none", **_SPLIT, label="segment split after an undo"),
        Line2D([], [], linestyle="none", marker="s", color="#b02020", markersize=4, label="split points on segments"),
    ]
    if deleted:
        handles.append(Line2D([], [], linestyle="none", **_DELETED, label="vertex deleted by the split"))
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=9, frameon=False)
    fig.suptitle(
        f"Ruppert's refinement of the {name} (min angle {mesh.min_angle:g}°, max area {mesh.max_area:g}): "
        "versions read from mesh.history",
        fontsize=11,
    )
    fig.tight_layout(rect=(0, 0.04, 1, 0.97))
    return _save(fig, out / "mesh-refinement.png")


def _save(fig: Any, path: Path) -> Path:
    import matplotlib.pyplot as plt

    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100, metadata={"Software": None})
    plt.close(fig)
    return path
