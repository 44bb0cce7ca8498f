"""Quality meshes drawn (matplotlib's Agg backend, no display): ``persistri mesh --plot`` and the docs' figures.

Each triangle is filled by its smallest angle (a colour scale from 0° to 60°,
the bound asked marked on it), so the skinny triangles a refinement left — the
exempt ones at small input angles — show at a glance; the input segments are
drawn thick over the mesh, the input vertices as black dots and the Steiner
points on segments (segment splits) as small squares.  Coordinates are drawn
relative to the lower-left corner of the mesh, so that a domain at UTM offsets
keeps readable tick labels (the axis labels say what was subtracted).

:func:`draw_mesh` draws on a given axes (the docs' picture series uses it for
each version of one refinement); :func:`plot_mesh` makes a whole picture and
saves it; :func:`smallest_angles` is the per-triangle measure behind the
colours (floating point: for pictures; the exact decisions are
:mod:`~persistri.impl.mesh.verify`'s).  O(T) each, plus matplotlib's drawing.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["ANGLE_COLOURS", "smallest_angles", "mesh_origin", "draw_mesh", "plot_mesh"]

ANGLE_COLOURS = "viridis"
"""The colour map of the triangles' smallest angles (0° dark, 60° light)."""

_SEGMENT_COLOUR = "#b02020"


def smallest_angles(vertices: ArrayLike, triangles: ArrayLike) -> NDArray[np.float64]:
    """The smallest interior angle of each triangle, in degrees (floating point, for pictures). O(T)."""
    v = np.asarray(vertices, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.intp).reshape(-1, 3)
    if t.size == 0:
        return np.zeros(0)
    p = v[t]
    best = np.full(t.shape[0], 180.0)
    for k in range(3):
        a, b, c = p[:, k], p[:, (k + 1) % 3], p[:, (k + 2) % 3]
        u, w = b - a, c - a
        shift = np.frexp(np.maximum(np.abs(u).max(axis=1), np.abs(w).max(axis=1)))[1][:, None]  # exact scaling:
        u, w = np.ldexp(u, -shift), np.ldexp(w, -shift)  # no underflow near 1e-300 (see api.smallest_angle)
        cross = np.abs(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0])
        dot = (u * w).sum(axis=1)
        best = np.minimum(best, np.degrees(np.arctan2(cross, dot)))
    return best


def mesh_origin(vertices: ArrayLike) -> NDArray[np.float64]:
    """The corner subtracted before drawing: the lower-left corner of the vertices' box, or 0 when it is near the origin.

    A domain whose box starts within a few of its own widths of the origin is
    drawn in its own coordinates; one far away (UTM eastings) relative to its corner.
    """
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 2)
    if v.size == 0:
        return np.zeros(2)
    low, high = v.min(axis=0), v.max(axis=0)
    span = float(np.max(high - low)) or 1.0
    if float(np.max(np.abs(low))) <= 4 * span:
        return np.zeros(2)
    origin: NDArray[np.float64] = low
    return origin


def _linewidth(n_triangles: int) -> float:
    """Edges thin enough that a dense mesh is not a black blot."""
    if n_triangles <= 400:
        return 0.6
    if n_triangles <= 4_000:
        return 0.3
    if n_triangles <= 40_000:
        return 0.12
    return 0.0


def _marker_size(ax: Any, q: NDArray[np.float64], t: NDArray[np.intp]) -> float:
    """Vertex markers (points) about a fifth of the median edge as drawn: dense meshes get dots, coarse ones discs."""
    if t.size == 0 or q.size == 0:
        return 3.5
    edges = np.linalg.norm(q[t[:, 1]] - q[t[:, 0]], axis=1)
    span = float(np.max(q.max(axis=0) - q.min(axis=0))) or 1.0
    width_pt = ax.get_position().width * ax.figure.get_size_inches()[0] * 72
    least = 2.0 if t.shape[0] < 2_000 else 0.6  # a graded mesh's median edge is small, but its vertices must show
    return float(np.clip(0.2 * float(np.median(edges)) / span * width_pt, least, 3.5))


def draw_mesh(
    ax: Any,
    vertices: ArrayLike,
    triangles: ArrayLike,
    *,
    segments: ArrayLike | None = None,
    n_input: int | None = None,
    origin: ArrayLike | None = None,
    colour: bool = True,
    linewidth: float | None = None,
) -> Any:
    """Draw a mesh on the matplotlib axes ``ax``; returns the triangles' collection (for a colour bar).

    * ``segments`` — ``(S, 2)`` rows of ``vertices``: the mesh edges on input segments, drawn thick;
    * ``n_input`` — the first ``n_input`` vertices are the domain's (black dots); the others
      are Steiner points, drawn as squares when they lie on a segment (by ``segments``);
    * ``origin`` — subtracted from every coordinate (default :func:`mesh_origin`);
    * ``colour`` — fill each triangle by its smallest angle (:data:`ANGLE_COLOURS`, 0°–60°),
      else a flat pale fill.
    """
    from matplotlib.collections import LineCollection, PolyCollection

    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 2)
    t = np.asarray(triangles, dtype=np.intp).reshape(-1, 3)
    o = mesh_origin(v) if origin is None else np.asarray(origin, dtype=np.float64)
    q = v - o
    lw = _linewidth(t.shape[0]) if linewidth is None else linewidth
    polys = PolyCollection(list(q[t]), edgecolors="#20303a" if lw > 0 else "face", linewidths=lw)
    if colour:
        polys.set_array(smallest_angles(v, t))
        polys.set_cmap(ANGLE_COLOURS)
        polys.set_clim(0.0, 60.0)
    else:
        polys.set_facecolor("#dfe8f0")
    ax.add_collection(polys)
    seg = np.asarray(segments if segments is not None else np.zeros((0, 2)), dtype=np.intp).reshape(-1, 2)
    if seg.size:
        ax.add_collection(LineCollection(list(q[seg]), colors=_SEGMENT_COLOUR, linewidths=max(1.4, 3 * lw)))
    n = v.shape[0] if n_input is None else min(int(n_input), v.shape[0])
    size = _marker_size(ax, q, t)
    ax.plot(q[:n, 0], q[:n, 1], "o", color="black", markersize=size, zorder=4)
    on_segment = np.unique(seg)
    on_segment = on_segment[on_segment >= n]
    if on_segment.size:
        ax.plot(q[on_segment, 0], q[on_segment, 1], "s", color=_SEGMENT_COLOUR, markersize=0.9 * size,
                markeredgecolor="black", markeredgewidth=0.1 * size, zorder=4)
    if v.size:
        low, high = q.min(axis=0), q.max(axis=0)
        pad = 0.03 * float(np.max(high - low) or 1.0)
        ax.set_xlim(low[0] - pad, high[0] + pad)
        ax.set_ylim(low[1] - pad, high[1] + pad)
    ax.set_aspect("equal")
    return polys


def plot_mesh(
    vertices: ArrayLike,
    triangles: ArrayLike,
    path: str | Path,
    *,
    segments: ArrayLike | None = None,
    n_input: int | None = None,
    min_angle: float | None = None,
    title: str | None = None,
) -> Path:
    """Draw a quality mesh to ``path`` (PNG, PDF or SVG by extension): :func:`draw_mesh` with a colour bar and axes.

    ``min_angle`` marks the bound on the colour bar.  Returns ``path``.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 2)
    t = np.asarray(triangles, dtype=np.intp).reshape(-1, 3)
    origin = mesh_origin(v)
    span = v.max(axis=0) - v.min(axis=0) if v.size else np.ones(2)
    aspect = float(span[1] / span[0]) if span[0] > 0 else 1.0
    width = 8.0
    height = min(max(width * aspect, 3.0), 11.0) + 0.8
    fig, ax = plt.subplots(figsize=(width + 1.2, height), dpi=120)
    polys = draw_mesh(ax, v, t, segments=segments, n_input=n_input, origin=origin)
    from mpl_toolkits.axes_grid1 import make_axes_locatable

    bar = fig.colorbar(polys, cax=make_axes_locatable(ax).append_axes("right", size="2.5%", pad=0.12))
    bar.set_label("smallest angle of the triangle (°)")
    if min_angle:
        bar.ax.axhline(min_angle, color="white", linewidth=2)
        bar.ax.axhline(min_angle, color="black", linewidth=1, linestyle="--")
    ax.set_xlabel("x" if origin[0] == 0 else f"x − {origin[0]:.10g}")
    ax.set_ylabel("y" if origin[1] == 0 else f"y − {origin[1]:.10g}")
    angles = smallest_angles(v, t)
    ax.set_title(title or f"{t.shape[0]:,} triangles, {v.shape[0]:,} vertices, smallest angle {angles.min(initial=60.0):.1f}°")
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, bbox_inches="tight", metadata={"Software": None} if out.suffix.lower() == ".png" else None)
    plt.close(fig)
    return out
