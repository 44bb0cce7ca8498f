"""Draw the pictures of the docs from real runs of persistri: ``python docs/figures.py [--out DIR]``.

Every picture is computed, not drawn by hand, and the script checks what it
draws against the paper before drawing it, so a picture can never show
something the code does not do:

* ``tent.png`` (the paper's Fig. 4) — one insertion of a real bulldozer run,
  read back from ``hull.history``: the faces of the old version that the new
  point ``p`` sees (the *lit* faces), the horizon, and the tent of new faces
  around ``p`` in the next version.  Checked: the lit faces are exactly the
  faces ``p`` sees (``orient3d < 0``) and exactly the faces removed between the
  two versions; the tent is exactly the faces added, one ``(u, w, p)`` per
  horizon edge ``(u, w)``; every point bulldozed off a lit face either sits in a
  tent face's conflict list or is gone.
* ``walking-graph.png`` (Fig. 5) — the walking graph of that insertion
  (Definition 1): the lit faces projected along ``c → p`` (Theorem 3), an arc
  between two adjacent lit faces as Definition 1 decides it, computed with the
  predicates *literally* ("is the facet ``(u, w, c)`` of the tetrahedron
  ``(u, w, c, b)`` visible from ``p``"), and cross-checked against the single
  sign the bulldozer uses (``orient3d(u, w, c, p) = −1``).  Checked: one arc per
  shared edge, the associated face of ``p`` has in-degree 0, the graph is acyclic
  (Theorem 2) and every node is reachable from the associated face (Lemma 9).
  Faces are numbered in the topological order in which they are visited.
* ``hull-history.png`` — four versions of one hull's history (time travel).
* ``terrain-lod.png`` — three levels of detail of one greedy-insertion run on
  the Jacksboro DEM, read back from the run's history (paper §5).
* ``mesh-refinement.png`` — versions of one Ruppert refinement (paper §1): the
  constrained Delaunay triangulation, an undo (the circumcentre tried, the
  subsegment it encroaches, its cavity) and the split after it, a later
  version, the final mesh, and the whole history; drawn and checked by
  ``mesh_figures.py`` beside this script, from the run's record of its undone
  and blocked points (checked against its counts and exactly before drawing).

``make docs`` runs this script before ``mkdocs build --strict``, so the pictures
are redrawn (and their checks rerun) by every ``make test``; the PNGs are also
committed so that the site builds from a clean clone.  Everything is seeded, and
the PNGs carry no timestamp, so an unchanged program redraws identical files.
Takes a few seconds.
"""

from __future__ import annotations

import argparse
import sys
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import FancyArrowPatch, Polygon  # noqa: E402
from numpy.typing import NDArray  # noqa: E402

from persistri.impl.geometry.predicates import Predicates3  # noqa: E402
from persistri.impl.hull.api import HullHistory, convex_hull  # noqa: E402
from persistri.impl.hull.bulldozer import initial_tetrahedron  # noqa: E402
from persistri.impl.hull.packed import conflict_list  # noqa: E402
from persistri.impl.hull.distributions import generate  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the sibling mesh_figures.py, also when loaded by path
import mesh_figures  # noqa: E402

__all__ = ["Insertion", "WalkingGraph", "insertion", "walking_graph", "main"]

Tri = tuple[int, int, int]
Edge = tuple[int, int]

# The run every hull picture is drawn from: small enough to read, large enough for a real walk.
HULL_DIST = "InBall"
HULL_N = 60
HULL_SEED = 1
PNG_METADATA: dict[str, Any] = {"Software": None}
"""No software version in the PNG: an unchanged program redraws byte-identical files."""


class FigureCheckError(AssertionError):
    """What a picture was about to show disagrees with the paper or with the run."""


def _require(cond: bool, message: str) -> None:
    if not cond:
        raise FigureCheckError(message)


def _edges(t: Tri) -> tuple[Edge, Edge, Edge]:
    a, b, c = t
    return ((a, b), (b, c), (c, a))


@dataclass(frozen=True)
class Insertion:
    """One step of a bulldozer run, read back from the history: version ``k − 1`` → version ``k``.

    Labels are point indices of the run's predicates (= input rows: the input
    has no duplicates).  ``lit`` are the faces of the old version that ``p``
    sees, ``horizon`` their boundary edges (oriented as in the lit face),
    ``tent`` the new faces, ``moved`` the points that were in the lit faces'
    conflict lists (``p`` excepted), ``kept`` those of them that are pending in
    the new version and ``gone`` those found interior.
    """

    k: int
    p: int
    pred: Predicates3
    before: dict[Tri, tuple[int, ...]]
    after: dict[Tri, tuple[int, ...]]
    lit: list[Tri]
    horizon: list[Edge]
    tent: list[Tri]
    associated: Tri
    moved: list[int]
    kept: list[int]
    gone: list[int]


def _faces(history: HullHistory, k: int) -> dict[Tri, tuple[int, ...]]:
    """The faces of version ``k`` with their conflict lists (as point labels)."""
    out: dict[Tri, tuple[int, ...]] = {}
    for t, datum in history.structure.items(history[k]):
        a, b, c = (int(v) for v in t)
        out[(a, b, c)] = tuple(int(q) for q in conflict_list(datum))  # packed in one int in a history run
    return out


def insertion(history: HullHistory, pred: Predicates3, k: int) -> Insertion:
    """Insertion ``k`` of ``history`` (1 ≤ k < len), with every claim the pictures make checked."""
    p = history.inserted[k]
    before, after = _faces(history, k - 1), _faces(history, k)
    lit = sorted(t for t in before if pred.orient3d(*t, p) < 0)
    removed = sorted(set(before) - set(after))
    added = sorted(set(after) - set(before))
    _require(lit == removed, f"insertion {k}: the faces p sees are not the faces removed")
    lit_edges = {e for t in lit for e in _edges(t)}
    horizon = sorted(e for e in lit_edges if (e[1], e[0]) not in lit_edges)
    _require(
        sorted((u, w, p) for u, w in horizon) == sorted(_rotate_to(t, p) for t in added),
        f"insertion {k}: the tent is not one face (u, w, p) per horizon edge (u, w)",
    )
    owners = [t for t in lit if p in before[t]]
    _require(len(owners) == 1, f"insertion {k}: p is in {len(owners)} conflict lists, not 1")
    moved = sorted(q for t in lit for q in before[t] if q != p)
    pending_after = {q for t in added for q in after[t]}
    kept = [q for q in moved if q in pending_after]
    gone = [q for q in moved if q not in pending_after]
    _require(pending_after <= set(moved), f"insertion {k}: a tent face holds a point no lit face held")
    for q in gone:
        _require(all(pred.orient3d(*t, q) > 0 for t in after), f"insertion {k}: point {q} was dropped but is outside")
    return Insertion(k, p, pred, before, after, lit, horizon, added, owners[0], moved, kept, gone)


def _rotate_to(t: Tri, p: int) -> Tri:
    """The rotation of ``t`` that ends with ``p`` (same orientation)."""
    a, b, c = t
    if c == p:
        return t
    if a == p:
        return (b, c, a)
    return (c, a, b)


@dataclass(frozen=True)
class WalkingGraph:
    """The walking graph of an insertion (Definition 1): arcs between lit faces and to horizon edges.

    ``order`` is a topological order (Kahn's algorithm from the associated face),
    the order in which the bulldozer may process the faces.
    """

    arcs: list[tuple[Tri, Tri]]
    to_horizon: list[tuple[Tri, Edge]]
    order: list[Tri]


def walking_graph(ins: Insertion) -> WalkingGraph:
    """The walking graph of ``ins``, checked against Definition 1, Theorem 2 and Lemma 9."""
    pred, p = ins.pred, ins.p
    c = pred.centre
    assert c is not None
    lit = set(ins.lit)
    by_edge = {e: t for t in ins.before for e in _edges(t)}
    arcs: list[tuple[Tri, Tri]] = []
    to_horizon: list[tuple[Tri, Edge]] = []
    for a_face in ins.lit:
        for u, w in _edges(a_face):
            b_face = by_edge[(w, u)]
            if b_face not in lit:
                to_horizon.append((a_face, (u, w)))
                continue
            # Definition 1, literally: the facet (u, w, c) of the tetrahedron (u, w, c, b), b the third
            # vertex of B, is visible to p iff p and b lie on opposite sides of the plane through u, w, c.
            b = next(x for x in b_face if x not in (u, w))
            definition = pred.orient3d(u, w, c, p) == -pred.orient3d(u, w, c, b)
            _require(
                definition == (pred.orient3d(u, w, c, p) == -1),
                f"arc {a_face} -> {b_face}: Definition 1 and the bulldozer's one-sign test disagree",
            )
            if definition:
                arcs.append((a_face, b_face))
    # "For any two adjacent visible faces A and B, there exists exactly one arc between them" (after Theorem 2):
    # each shared edge was tested from both sides, independently.
    pairs: dict[frozenset[Tri], int] = {}
    for a_face in ins.lit:
        for u, w in _edges(a_face):
            b_face = by_edge[(w, u)]
            if b_face in lit:
                pairs.setdefault(frozenset((a_face, b_face)), 0)
    for arc in arcs:
        pairs[frozenset(arc)] += 1
    _require(all(n == 1 for n in pairs.values()), "not exactly one arc across each edge shared by two lit faces")
    indeg = {t: 0 for t in ins.lit}
    succ: dict[Tri, list[Tri]] = {t: [] for t in ins.lit}
    for src, dst in arcs:
        indeg[dst] += 1
        succ[src].append(dst)
    _require(indeg[ins.associated] == 0, "the associated face of p has an arc into it")
    _require([t for t in ins.lit if indeg[t] == 0] == [ins.associated], "a lit face other than the associated one has in-degree 0")
    order: list[Tri] = []
    queue = deque([ins.associated])
    left = dict(indeg)
    while queue:
        t = queue.popleft()
        order.append(t)
        for s in sorted(succ[t]):
            left[s] -= 1
            if left[s] == 0:
                queue.append(s)
    # Kahn's algorithm from the one source reaches every node exactly when the graph is acyclic
    # (Theorem 2) and every node is reachable from the associated face (Lemma 9).
    _require(len(order) == len(ins.lit), "the walking graph has a cycle or an unreachable face")
    return WalkingGraph(arcs, to_horizon, order)


# -- drawing -------------------------------------------------------------------------------


def _projector(pts: NDArray[np.float64], c: NDArray[np.float64], p: NDArray[np.float64]) -> Any:
    """Orthogonal projection onto the plane through ``c`` perpendicular to ``c → p`` (Theorem 3), as 2D coordinates."""
    d = (p - c) / np.linalg.norm(p - c)
    helper = np.array([1.0, 0.0, 0.0]) if abs(d[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(d, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(d, e1)

    def project(i: int | Sequence[int]) -> NDArray[np.float64]:
        x = pts[np.asarray(i)] - c
        return np.stack([x @ e1, x @ e2], axis=-1)

    front = d
    return project, front


def _front(pts: NDArray[np.float64], faces: Sequence[Tri], d: NDArray[np.float64]) -> list[Tri]:
    """The faces whose outward normal points towards the viewer at infinity along ``d``."""
    out = []
    for t in faces:
        a, b, c = pts[list(t)]
        if float(np.cross(b - a, c - a) @ d) > 0:
            out.append(t)
    return out


def _draw_faces(ax: Any, project: Any, faces: Sequence[Tri], **style: Any) -> None:
    for t in faces:
        ax.add_patch(Polygon(project(list(t)), closed=True, **style))


def _frame(ax: Any, project: Any, labels: Sequence[int], title: str) -> None:
    xy = project(list(labels))
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    pad = 0.12 * float(np.max(hi - lo))
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(title, fontsize=10)


def draw_tent(ins: Insertion, out: Path) -> Path:
    """``tent.png``: the lit faces and the horizon (before), the tent around p (after)."""
    pts = ins.pred.points
    c = ins.pred.centre
    assert c is not None
    project, d = _projector(pts, pts[c], pts[ins.p])
    fig, axes = plt.subplots(1, 2, figsize=(10, 5.2))
    near = sorted({v for t in ins.lit for v in t} | {ins.p})
    framed = near + ins.moved
    ring = [t for t in _front(pts, list(ins.before), d) if any(v in near for v in t)]
    ax = axes[0]
    _draw_faces(ax, project, ring, facecolor="#eeeeee", edgecolor="#999999", linewidth=0.6)
    _draw_faces(ax, project, ins.lit, facecolor="#ffe9a8", edgecolor="#7a5c00", linewidth=1.0, linestyle="--")
    for u, w in ins.horizon:
        xy = project([u, w])
        ax.plot(xy[:, 0], xy[:, 1], color="black", linewidth=2.6, solid_capstyle="round")
    _moved_points(ax, project, ins, after=False)
    _light(ax, project(ins.p))
    _frame(ax, project, framed, f"version {ins.k - 1}: {len(ins.lit)} lit faces (dashed), horizon (bold)")
    ax = axes[1]
    ring_after = [t for t in _front(pts, list(ins.after), d) if any(v in near for v in t)]
    _draw_faces(ax, project, ring_after, facecolor="#eeeeee", edgecolor="#999999", linewidth=0.6)
    _draw_faces(ax, project, ins.tent, facecolor="#b9d7f0", edgecolor="#1f4e79", linewidth=1.0)
    for u, w in ins.horizon:
        xy = project([u, w])
        ax.plot(xy[:, 0], xy[:, 1], color="black", linewidth=2.6, solid_capstyle="round")
    _moved_points(ax, project, ins, after=True)
    _light(ax, project(ins.p))
    _frame(ax, project, framed, f"version {ins.k}: the tent, {len(ins.tent)} new faces around p")
    fig.suptitle(
        f"Inserting point p = {ins.p} ({HULL_DIST}, n = {HULL_N}, seed {HULL_SEED}), seen along c → p",
        fontsize=11,
    )
    fig.tight_layout()
    return _save(fig, out / "tent.png")


def _moved_points(ax: Any, project: Any, ins: Insertion, *, after: bool) -> None:
    """The points bulldozed off the lit faces: before, all of them; after, kept (dot) or found interior (x)."""
    if not ins.moved:
        return
    if not after:
        xy = project(ins.moved)
        ax.scatter(xy[:, 0], xy[:, 1], s=14, color="#7a5c00", zorder=3, label="points to bulldoze")
        ax.legend(loc="lower left", fontsize=8, frameon=False)
        return
    if ins.kept:
        xy = project(ins.kept)
        ax.scatter(xy[:, 0], xy[:, 1], s=14, color="#1f4e79", zorder=3, label="still outside (tent lists)")
    if ins.gone:
        xy = project(ins.gone)
        ax.scatter(xy[:, 0], xy[:, 1], s=22, marker="x", color="#a00000", zorder=3, label="now interior (dropped)")
    ax.legend(loc="lower left", fontsize=8, frameon=False)


def _light(ax: Any, xy: NDArray[np.float64]) -> None:
    ax.scatter([xy[0]], [xy[1]], s=70, color="black", zorder=5)
    ax.annotate("p", xy, xytext=(6, 6), textcoords="offset points", fontsize=11, weight="bold")


def draw_walking_graph(ins: Insertion, g: WalkingGraph, out: Path) -> Path:
    """``walking-graph.png``: the lit faces projected along c → p, numbered in topological order, with their arcs."""
    pts = ins.pred.points
    c = ins.pred.centre
    assert c is not None
    project, _ = _projector(pts, pts[c], pts[ins.p])
    fig, ax = plt.subplots(figsize=(6.4, 6.4))
    _draw_faces(ax, project, ins.lit, facecolor="#fff4d1", edgecolor="#b39b5a", linewidth=0.8)
    for u, w in ins.horizon:
        xy = project([u, w])
        ax.plot(xy[:, 0], xy[:, 1], color="black", linewidth=2.6, solid_capstyle="round")
    centre = {t: project(list(t)).mean(axis=0) for t in ins.lit}
    rank = {t: i for i, t in enumerate(g.order)}

    def arrow(a: NDArray[np.float64], b: NDArray[np.float64], color: str) -> None:
        ax.add_patch(
            FancyArrowPatch(tuple(a), tuple(b), arrowstyle="-|>", mutation_scale=13, color=color,
                            linewidth=1.3, shrinkA=9, shrinkB=9, zorder=4)
        )

    for a, b in g.arcs:
        arrow(centre[a], centre[b], "#1f4e79")
    for a, (u, w) in g.to_horizon:
        mid = project([u, w]).mean(axis=0)
        arrow(centre[a], mid, "#a05a00")
    for t, xy in centre.items():
        assoc = t == ins.associated
        ax.scatter([xy[0]], [xy[1]], s=260, facecolor="#1f4e79" if assoc else "white",
                   edgecolor="#1f4e79", linewidth=1.4, zorder=5)
        ax.annotate(str(rank[t]), xy, ha="center", va="center", fontsize=9, zorder=6,
                    color="white" if assoc else "#1f4e79", weight="bold")
    _light(ax, project(ins.p))
    near = sorted({v for t in ins.lit for v in t})
    _frame(ax, project, near, f"walking graph of p = {ins.p}: {len(ins.lit)} faces, {len(g.arcs)} arcs, "
                              f"{len(ins.horizon)} horizon edges")
    ax.text(0.01, 0.01, "filled node: the associated face of p (in-degree 0)\n"
            "blue arcs: face → face (Definition 1); brown arcs: face → horizon edge",
            transform=ax.transAxes, fontsize=8, va="bottom")
    fig.tight_layout()
    return _save(fig, out / "walking-graph.png")


def draw_hull_history(history: HullHistory, pts: NDArray[np.float64], out: Path) -> Path:
    """``hull-history.png``: four versions of one run, each drawn from the kept complex."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    ks = [0, len(history) // 6, len(history) // 2, len(history) - 1]
    fig = plt.figure(figsize=(12, 3.4))
    light = np.array([0.4, -0.5, 0.75]) / np.linalg.norm([0.4, -0.5, 0.75])
    for j, k in enumerate(ks):
        ax = fig.add_subplot(1, 4, j + 1, projection="3d")
        tri = history.simplices(k)
        faces = pts[tri]
        normal = np.cross(faces[:, 1] - faces[:, 0], faces[:, 2] - faces[:, 0])
        normal /= np.linalg.norm(normal, axis=1)[:, None]
        shade = 0.35 + 0.6 * np.clip(normal @ light, 0, 1)
        colours = np.column_stack([0.35 * shade, 0.55 * shade, 0.85 * shade, np.ones_like(shade)])
        ax.add_collection3d(Poly3DCollection(faces, facecolors=colours, edgecolors="#203040", linewidths=0.3))
        pend = history.pending(k)
        if pend.size:
            ax.scatter(pts[pend, 0], pts[pend, 1], pts[pend, 2], s=5, color="#a00000")
        for setter in (ax.set_xlim, ax.set_ylim, ax.set_zlim):
            setter(-1, 1)
        ax.set_box_aspect((1, 1, 1), zoom=1.45)
        ax.set_axis_off()
        ax.set_title(f"history[{k}]: {len(tri)} faces,\n{pend.size} points pending", fontsize=9)
    fig.subplots_adjust(left=0, right=1, bottom=0, top=0.88, wspace=0)
    return _save(fig, out / "hull-history.png")


def draw_terrain_lod(out: Path) -> Path:
    """``terrain-lod.png``: three levels of detail of one greedy-insertion run, read from its history."""
    from matplotlib.colors import LightSource

    from persistri.impl.terrain.greedy import greedy_insertion
    from persistri.impl.terrain.grids import jacksboro

    heights = jacksboro().heights[::4, ::4]
    tin = greedy_insertion(heights, max_points=400)
    assert tin.history is not None
    levels = [tin.history.at(points=k) for k in (25, 100, 400)]
    _require(levels[-1].triangles.tolist() == tin.triangles.tolist(), "the last level of detail is not the final mesh")
    rows, cols = heights.shape
    ls = LightSource(azdeg=315, altdeg=45)
    span = float(heights.max() - heights.min()) or 1.0
    relief = ls.shade(heights, cmap=plt.get_cmap("gist_earth"), vert_exag=0.1 * max(rows, cols) / span, blend_mode="soft")
    fig, axes = plt.subplots(1, 3, figsize=(12, 4.0))
    for ax, lvl in zip(axes, levels):
        ax.imshow(relief, origin="upper", extent=(-0.5, cols - 0.5, rows - 0.5, -0.5), interpolation="bilinear")
        ax.triplot(lvl.vertices[:, 0], lvl.vertices[:, 1], lvl.triangles, color="black", linewidth=0.4)
        ax.set_xlim(-0.5, cols - 0.5)
        ax.set_ylim(rows - 0.5, -0.5)
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_title(f"history.at(points={lvl.n_points}): max error {lvl.max_error:.0f} m", fontsize=9)
    fig.suptitle(f"Jacksboro DEM ({rows} × {cols} samples, every 4th): one run, three levels of detail", fontsize=11)
    fig.tight_layout()
    return _save(fig, out / "terrain-lod.png")


def draw_mesh_refinement(out: Path) -> Path:
    """``mesh-refinement.png``: one Ruppert refinement's versions, its undos checked (:mod:`mesh_figures`)."""
    mesh = mesh_figures.refinement_run()
    return mesh_figures.draw_refinement(mesh, mesh_figures.checked_record(mesh), out)


def _save(fig: Any, path: Path) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, metadata=PNG_METADATA)
    plt.close(fig)
    return path


def hull_run() -> tuple[NDArray[np.float64], HullHistory, Predicates3]:
    """The run the hull pictures are drawn from, and its predicates with the bulldozer's centre."""
    pts = generate(HULL_DIST, HULL_N, seed=HULL_SEED)
    hull = convex_hull(pts, history=True, seed=HULL_SEED, check=True, labels="input")  # labels = input rows
    history = hull.history
    assert history is not None
    _require(history.rows.tolist() == list(range(HULL_N)), "the run merged duplicates: labels are not input rows")
    pred = Predicates3(pts)
    tetra = initial_tetrahedron(pred, HULL_N)
    pred = pred.with_centroid(*tetra)
    _require(history.vertices(0).tolist() == sorted(tetra), "the first version is not the first tetrahedron")
    return pts, history, pred


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Draw every picture into ``--out`` (default: the ``images`` folder beside this script)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path(__file__).resolve().parent / "images")
    args = parser.parse_args(argv)
    pts, history, pred = hull_run()
    steps = [insertion(history, pred, k) for k in range(1, len(history))]
    # The picture: among the insertions with 6 to 10 lit faces (a walking graph that reads at a glance),
    # the one that bulldozes the most points; the earliest on a tie.
    ins = max((s for s in steps if 6 <= len(s.lit) <= 10), key=lambda s: (len(s.moved), -s.k))
    graphs = [walking_graph(s) for s in steps]  # every insertion of the run is checked, not only the one drawn
    g = graphs[steps.index(ins)]
    written = [
        draw_tent(ins, args.out),
        draw_walking_graph(ins, g, args.out),
        draw_hull_history(history, pts, args.out),
        draw_terrain_lod(args.out),
        draw_mesh_refinement(args.out),
    ]
    for path in written:
        print(f"wrote {path}")
    return written


if __name__ == "__main__":
    main()
