"""The picture series of one Ruppert refinement, read back from its history: ``mesh-refinement.png`` (docs/meshing.md).

Drawn by ``docs/figures.py`` (``make docs``).  One refinement of a gallery
domain (:data:`MESH_DOMAIN` at :data:`MESH_MIN_ANGLE` degrees with the area
bound :data:`MESH_MAX_AREA`) is run once; every panel is a version read from
``mesh.history`` — the constrained Delaunay triangulation it starts from, the
version before an **undo** with the circumcentre that was tried and dropped,
the version after it with the subsegment split instead, a later version and
the final mesh — and a chart of the whole history.

Nothing the refiner does is recorded beyond its versions, the points it kept
and its counts, so the pictures' claims about the points it *dropped* are
recomputed and checked (:func:`dropped_points`; :class:`FigureCheckError` on any
disagreement): the run's point set is append-only, so a Steiner point that is
in no version was tried from the version the refinement stood at when it was
made, and dropped.  It was **undone** (inserted, then dropped because it
encroached a subsegment) exactly when it lies in a domain triangle of that
version, on no segment, and its cavity — the triangles whose circumcircle holds
it (exact incircle with the same perturbation), reached without crossing a
segment — has a subsegment on its boundary whose diametral lens holds it; else
it was **blocked** (a segment lay between it and its triangle).  The
classification must give the refinement's own ``undos`` and ``blocked``
counts, each version may drop at most one point, and the version after an
undo must add a split point on one of the subsegments the undone point
encroached (Ruppert's rule: split them instead).  Every version drawn passes
:func:`~persistri.impl.mesh.verify.verify_mesh`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from persistri.impl.mesh.api import QualityMesh, triangulate
from persistri.impl.mesh.gallery import gallery_domain
from persistri.impl.mesh.plot import draw_mesh, mesh_origin
from persistri.impl.mesh.quality import inside_lens
from persistri.impl.mesh.verify import verify_mesh

__all__ = [
    "MESH_DOMAIN",
    "MESH_MIN_ANGLE",
    "MESH_MAX_AREA",
    "FigureCheckError",
    "Dropped",
    "refinement_run",
    "dropped_points",
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
class Dropped:
    """A Steiner point the refinement tried from version ``k`` and kept in no version.

    ``point`` is its index in the run's point set, ``xy`` its coordinates.
    ``undone``: it was inserted and the new version dropped (it encroached the
    subsegments ``encroached``, pairs of point indices; ``cavity`` the triangles
    of version ``k`` its insertion replaced); otherwise it was blocked before
    insertion and both are empty.
    """

    k: int
    point: int
    xy: tuple[float, float]
    undone: bool
    encroached: tuple[Edge, ...]
    cavity: tuple[Tri, ...]


def refinement_run(name: str = MESH_DOMAIN, min_angle: float = MESH_MIN_ANGLE, max_area: float | None = MESH_MAX_AREA) -> QualityMesh:
    """The refinement the series is drawn from (deterministic: no seed is involved)."""
    return triangulate(gallery_domain(name).pslg, min_angle=min_angle, max_area=max_area)


def _pred(mesh: QualityMesh) -> Any:
    """The run's append-only point set and its exact predicates (the kept and the dropped points)."""
    return mesh._run.T.pred


def _version(mesh: QualityMesh, k: int) -> tuple[list[Tri], set[frozenset[int]]]:
    """Version ``k``'s domain triangles and subsegments, as point indices."""
    arr = mesh.history.mesh(k)
    tris = [tuple(int(v) for v in row) for row in arr.points[arr.triangles].tolist()]
    segs = {frozenset(int(v) for v in row) for row in arr.points[arr.segments].tolist()}
    return [(a, b, c) for a, b, c in tris], segs


def _edges(t: Tri) -> tuple[Edge, Edge, Edge]:
    a, b, c = t
    return ((a, b), (b, c), (c, a))


def _classify(mesh: QualityMesh, k: int, p: int) -> tuple[bool, tuple[Edge, ...], tuple[Tri, ...]]:
    """Whether point ``p``, tried from version ``k``, was undone; the subsegments it encroaches and its cavity."""
    P = _pred(mesh)
    tris, segs = _version(mesh, k)
    holding = [t for t in tris if all(P.orient2d_sign(u, w, p) >= 0 for u, w in _edges(t))]
    on_segment = any(
        P.orient2d_sign(u, w, p) == 0 and P.between(u, w, p) for t in holding for u, w in _edges(t) if frozenset((u, w)) in segs
    )
    if not holding or on_segment:
        return False, (), ()
    by_edge = {e: t for t in tris for e in _edges(t)}
    cavity: list[Tri] = []
    seen: set[Tri] = set()
    boundary: list[Edge] = []
    stack = list(holding)
    seen.update(holding)
    while stack:
        t = stack.pop()
        cavity.append(t)
        for u, w in _edges(t):
            beyond = by_edge.get((w, u))
            if frozenset((u, w)) in segs or beyond is None:
                boundary.append((u, w))
            elif beyond not in seen and P.incircle(*beyond, p) > 0:
                seen.add(beyond)
                stack.append(beyond)
            elif beyond not in seen:
                boundary.append((u, w))
    bound = mesh.min_angle
    encroached = tuple(
        (u, w) for u, w in boundary if frozenset((u, w)) in segs and inside_lens(P, u, w, p, bound)
    )
    return bool(encroached), encroached, tuple(cavity)


def dropped_points(mesh: QualityMesh) -> list[Dropped]:
    """Every Steiner point the run tried and kept in no version, classified and checked (module docstring)."""
    P = _pred(mesh)
    n = mesh.domain.vertices.shape[0]
    inserted = [int(p) for p in mesh.history.inserted]
    _require(inserted == sorted(inserted) and len(set(inserted)) == len(inserted),
             "the kept points were not made in the order of the versions")
    kept = set(inserted)
    # The triangulation locates the hole and region points by adding them to the point set (in this order) before
    # the refinement starts: they are not Steiner points.
    located = [tuple(map(float, xy)) for xy in (*mesh.domain.holes.tolist(), *mesh.domain.regions[:, :2].tolist())]
    first = n + len(located) if [P.xy(n + i) for i in range(min(len(located), len(P) - n))] == located else n
    out: list[Dropped] = []
    for p in range(first, len(P)):
        if p in kept:
            continue
        k = int(np.searchsorted(inserted, p))  # the versions made before p was
        undone, encroached, cavity = _classify(mesh, k, p)
        out.append(Dropped(k, p, P.xy(p), undone, encroached, cavity))
    undos = sum(d.undone for d in out)
    _require(undos == mesh.undos, f"{undos} dropped points encroach a subsegment of their cavity; the run undid {mesh.undos}")
    _require(len(out) - undos == mesh.blocked, f"{len(out) - undos} dropped points look blocked; the run blocked {mesh.blocked}")
    _require(len({d.k for d in out}) == len(out), "a version dropped two points: a split must follow each drop")
    for d in out:
        if not d.undone:
            continue
        _require(d.k < len(inserted), f"the run ended right after undoing point {d.point}: no subsegment was split")
        q = inserted[d.k]
        _, segs = _version(mesh, d.k + 1)  # by the mesh's own subsegments: a rounded split point is off by an ulp
        _require(
            any({frozenset((u, q)), frozenset((q, w))} <= segs and frozenset((u, w)) not in segs for u, w in d.encroached),
            f"after undoing point {d.point}, version {d.k + 1} adds point {q}, splitting none of the subsegments it encroached",
        )
    return out


def _circumscribed(mesh: QualityMesh, d: Dropped) -> Tri | None:
    """The triangle of version ``d.k`` whose circumcentre, rounded to doubles, is ``d.xy`` (None: an off-centre).

    Steiner points are exact circumcentres rounded once, so the float circumcentre of the right triangle is within
    a few units in the last place; an off-centre lies on the bisector of the shortest edge, nearer to it.
    """
    P = _pred(mesh)
    tris, _ = _version(mesh, d.k)
    x, y = d.xy
    best: tuple[float, Tri] | None = None
    for t in tris:
        (ax, ay), (bx, by), (cx, cy) = (P.xy(v) for v in t)
        den = 2 * ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax))
        b2, c2 = (bx - ax) ** 2 + (by - ay) ** 2, (cx - ax) ** 2 + (cy - ay) ** 2
        ux = ax + ((cy - ay) * b2 - (by - ay) * c2) / den
        uy = ay + ((bx - ax) * c2 - (cx - ax) * b2) / den
        gap = float(np.hypot(ux - x, uy - y)) / max(np.sqrt(b2), np.sqrt(c2))
        if best is None or gap < best[0]:
            best = (gap, t)
    return best[1] if best is not None and best[0] < 1e-9 else None


def _check_version(mesh: QualityMesh, k: int) -> None:
    arr = mesh.history.mesh(k)
    report = verify_mesh(mesh.domain, arr.vertices, arr.triangles)
    _require(report.ok, f"history[{k}] is not a valid constrained Delaunay mesh of the domain: {report}")


def _marks(ax: Any, P: Any, origin: Any, points: Sequence[int], style: dict[str, Any]) -> None:
    if points:
        xy = np.array([P.xy(p) for p in points]) - origin
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


def draw_refinement(mesh: QualityMesh, dropped: Sequence[Dropped], out: Path, name: str = MESH_DOMAIN) -> Path:
    """``mesh-refinement.png``: the CDT, an undo and the split after it, a later version, the final mesh, the history."""
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import Circle, Polygon

    P = _pred(mesh)
    last = len(mesh.history) - 1
    undone = [d for d in dropped if d.undone]
    _require(bool(undone), "the run drawn has no undo to show")
    # The undo drawn: the one whose encroached subsegment is longest (its circle reads best), the earliest on a tie.
    def length(d: Dropped) -> float:
        (u, w) = d.encroached[0]
        return float(np.hypot(*np.subtract(P.xy(u), P.xy(w))))

    show = max(undone, key=lambda d: (length(d), -d.k))
    later = (show.k + 1 + last) // 2
    for k in sorted({0, show.k, show.k + 1, later, last}):
        _check_version(mesh, k)
    origin = mesh_origin(mesh.vertices)
    fig, axes = plt.subplots(2, 3, figsize=(13.5, 9.2))
    a0, a1, a2, a3, a4, a5 = axes.ravel()

    _panel(a0, mesh, 0, origin, f"history[0]: the constrained Delaunay\ntriangulation ({len(mesh.history.mesh(0).triangles)} triangles)")

    bad = _circumscribed(mesh, show)
    what = "the circumcentre c of the bad triangle (outlined)" if bad is not None else "the off-centre c of a bad triangle"
    _panel(a1, mesh, show.k, origin, f"history[{show.k}]: {what}\nencroaches subsegment s: the new version is dropped")
    if bad is not None:
        a1.add_patch(Polygon(np.array([P.xy(v) for v in bad]) - origin, closed=True, fill=False, edgecolor="#d01010",
                             linewidth=2.2, zorder=6))
    for t in show.cavity:
        a1.add_patch(Polygon(np.array([P.xy(v) for v in t]) - origin, closed=True, facecolor="#f4b0b0", edgecolor="none", zorder=2))
    cx, cy = np.subtract(show.xy, origin)
    for t in show.cavity:
        for u, w in _edges(t):
            x = np.subtract(P.xy(u), origin)
            a1.plot([cx, x[0]], [cy, x[1]], color="#d01010", linewidth=0.8, linestyle="--", zorder=3)
    u, w = show.encroached[0]
    pu, pw = np.subtract(P.xy(u), origin), np.subtract(P.xy(w), origin)
    a1.plot([pu[0], pw[0]], [pu[1], pw[1]], color="#e08000", linewidth=4, zorder=5)
    a1.add_patch(Circle(tuple((pu + pw) / 2), float(np.hypot(*(pu - pw))) / 2, fill=False, linestyle="--",
                        edgecolor="#e08000", linewidth=1.3, zorder=5))
    a1.plot([cx], [cy], linestyle="none", zorder=7, **_UNDONE)
    a1.annotate("c", (cx, cy), textcoords="offset points", xytext=(6, 4), color="#d01010", fontsize=10, weight="bold")
    a1.annotate("s", tuple((pu + pw) / 2), textcoords="offset points", xytext=(6, -12), color="#b06000", fontsize=10, weight="bold")

    q = int(mesh.history.inserted[show.k])
    before, after = (set(mesh.history.mesh(k).points.tolist()) for k in (show.k, show.k + 1))
    _require(after - before == {q}, f"history[{show.k + 1}] adds points {sorted(after - before)}, not just the split point {q}")
    deleted = sorted(before - after)  # free vertices in s's diametral circle, if the refiner deletes them (Chew)
    also = f", {len(deleted)} free vert{'ex' if len(deleted) == 1 else 'ices'} in its circle deleted" if deleted else ""
    _panel(a2, mesh, show.k + 1, origin,
           f"history[{show.k + 1}]: s split instead{also}\n(history[{show.k}] itself was never changed)")
    _marks(a2, P, origin, [q], _SPLIT)
    _marks(a2, P, origin, deleted, _DELETED)

    _panel(a3, mesh, later, origin, f"history[{later}]: {len(mesh.history.mesh(later).triangles)} triangles")

    polys = _panel(a4, mesh, last, origin,
                   f"history[{last}], the final mesh: {len(mesh.triangles)} triangles,\n"
                   f"min angle ≥ {mesh.min_angle:g}°, {mesh.undos} undos, {mesh.blocked} blocked", colour=True)
    _marks(a4, P, origin, [d.point for d in undone], _UNDONE)
    _marks(a4, P, origin, [d.point for d in dropped if not d.undone], _BLOCKED)
    bar = fig.colorbar(polys, ax=a4, shrink=0.75, pad=0.02)
    bar.set_label("smallest angle (°)")

    sizes = [len(mesh.history.mesh(k).triangles) for k in range(last + 1)]
    a5.plot(range(last + 1), sizes, color="#20303a", linewidth=1.2)
    for d in dropped:
        a5.axvline(d.k, color="#d01010" if d.undone else "#909090", linewidth=0.8, alpha=0.7)
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
