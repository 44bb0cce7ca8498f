"""A rendered view of a hull: shaded triangles, matplotlib's Agg backend (no display needed)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

__all__ = ["plot_hull"]


def plot_hull(
    points: NDArray[np.float64],
    simplices: NDArray[np.intp],
    path: str | Path,
    *,
    title: str | None = None,
    interior: bool = True,
) -> Path:
    """Draw the hull ``(points, simplices)`` to ``path`` (PNG by extension): faces lit from over the viewer's shoulder.

    Points that are not hull vertices are drawn as small dots when ``interior``.
    Only the faces turned towards the viewer are drawn (matplotlib sorts polygons
    by their mean depth, which paints some back faces over front ones; a convex
    hull's front faces never overlap), in the data's own proportions, and the
    picture is cropped to the hull and its title.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.transforms import Bbox
    from mpl_toolkits.mplot3d import proj3d
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    pts = np.asarray(points, dtype=np.float64)
    tri = np.asarray(simplices, dtype=np.intp)
    # Scale by a power of two to |coordinates| < 1 first (exact): the extent of points near ±1e308
    # would overflow, and that of subnormal ones would lose its digits.
    if pts.size:
        pts = np.ldexp(pts, -int(np.frexp(np.max(np.abs(pts)))[1]))
    centre = (pts.max(axis=0) + pts.min(axis=0)) / 2
    spans = pts.max(axis=0) - pts.min(axis=0)
    span = float(np.max(spans)) or 1.0
    p = (pts - centre) / span  # drawn in a unit box: huge offsets and tiny scales render alike
    half = np.maximum(spans / span / 2, 0.05)  # the box's half-extents, in proportion (a flat hull stays visible)
    faces = p[tri]
    normal = np.cross(faces[:, 1] - faces[:, 0], faces[:, 2] - faces[:, 0])
    with np.errstate(all="ignore"):
        normal /= np.linalg.norm(normal, axis=1)[:, None]
    elev, azim = np.radians(22.0), np.radians(35.0)
    eye = np.array([np.cos(elev) * np.cos(azim), np.cos(elev) * np.sin(azim), np.sin(elev)])
    front = ~(normal @ eye <= 0)  # outward normals (faces with no normal are kept)
    # A light over the viewer's left shoulder: every face seen is lit, at a different angle.
    side = np.cross([0.0, 0.0, 1.0], eye)
    light = eye + np.array([0.0, 0.0, 0.6]) - 0.5 * side / np.linalg.norm(side)
    light /= np.linalg.norm(light)
    shade = np.nan_to_num(np.clip(normal @ light, 0.0, 1.0))
    colours = plt.get_cmap("viridis")(0.25 + 0.7 * shade)
    fig = plt.figure(figsize=(6, 6), dpi=170)
    ax = fig.add_subplot(projection="3d")
    ax.add_collection3d(
        Poly3DCollection(faces[front], facecolors=colours[front], edgecolors=(0, 0, 0, 0.25), linewidths=0.3)
    )
    if interior:
        inside = np.setdiff1d(np.arange(p.shape[0]), np.unique(tri))
        if inside.size:
            ax.scatter(*p[inside].T, s=1, c="0.3", alpha=0.3, depthshade=False)
    ax.set_xlim(-half[0], half[0])
    ax.set_ylim(-half[1], half[1])
    ax.set_zlim(-half[2], half[2])
    ax.set_box_aspect(tuple(half))
    ax.set_axis_off()
    ax.view_init(elev=22, azim=35)
    # Crop to the drawn hull (3D axes keep a square of blank around it), the title just above it.
    fig.canvas.draw()
    used = p[np.unique(tri)] if tri.size else p
    x, y, _ = proj3d.proj_transform(used[:, 0], used[:, 1], used[:, 2], ax.get_proj())
    xy = ax.transData.transform(np.column_stack([x, y]))
    (x0, y0), (x1, y1) = xy.min(axis=0), xy.max(axis=0)
    width, height = fig.bbox.width, fig.bbox.height
    label = fig.text(
        (x0 + x1) / 2 / width, (y1 + 8) / height,
        title or f"convex hull: {tri.shape[0]} faces, {np.unique(tri).size} vertices",
        ha="center", va="bottom", fontsize=12,
    )
    box = Bbox.union([Bbox.from_extents(x0, y0, x1, y1), label.get_window_extent()]).padded(10)
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, bbox_inches=box.transformed(fig.dpi_scale_trans.inverted()))
    plt.close(fig)
    return out
