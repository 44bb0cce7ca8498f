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
    """Draw the hull ``(points, simplices)`` to ``path`` (PNG by extension): faces lit from one side.

    Points that are not hull vertices are drawn as small dots when ``interior``.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    pts = np.asarray(points, dtype=np.float64)
    tri = np.asarray(simplices, dtype=np.intp)
    # Scale by a power of two to |coordinates| < 1 first (exact): the extent of points near ±1e308
    # would overflow, and that of subnormal ones would lose its digits.
    if pts.size:
        pts = np.ldexp(pts, -int(np.frexp(np.max(np.abs(pts)))[1]))
    centre = (pts.max(axis=0) + pts.min(axis=0)) / 2
    span = float(np.max(pts.max(axis=0) - pts.min(axis=0))) or 1.0
    p = (pts - centre) / span  # drawn in a unit box: huge offsets and tiny scales render alike
    faces = p[tri]
    normal = np.cross(faces[:, 1] - faces[:, 0], faces[:, 2] - faces[:, 0])
    with np.errstate(all="ignore"):
        normal /= np.linalg.norm(normal, axis=1)[:, None]
    light = np.array([0.4, -0.5, 0.75])
    light /= np.linalg.norm(light)
    shade = np.nan_to_num(np.clip(normal @ light, 0.0, 1.0))
    colours = plt.get_cmap("viridis")(0.25 + 0.7 * shade)
    fig = plt.figure(figsize=(6, 6), dpi=120)
    ax = fig.add_subplot(projection="3d")
    ax.add_collection3d(Poly3DCollection(faces, facecolors=colours, edgecolors=(0, 0, 0, 0.25), linewidths=0.3))
    if interior:
        inside = np.setdiff1d(np.arange(p.shape[0]), np.unique(tri))
        if inside.size:
            ax.scatter(*p[inside].T, s=1, c="0.3", alpha=0.3, depthshade=False)
    lim = 0.55
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_zlim(-lim, lim)
    ax.set_box_aspect((1, 1, 1))
    ax.set_axis_off()
    ax.view_init(elev=22, azim=35)
    ax.set_title(title or f"convex hull: {tri.shape[0]} faces, {np.unique(tri).size} vertices")
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, bbox_inches="tight")
    plt.close(fig)
    return out
