"""A terrain mesh drawn over its shaded relief, like the paper's Figs. 9–10 (matplotlib's Agg backend, no display).

The relief is the height grid lit from the north-west (``matplotlib.colors.LightSource``);
the triangulation is drawn on top in grid coordinates.  Row 0 is at the top of the
picture, as in the array (and as in a north-up raster); nothing is flipped.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["plot_tin", "plot_triangulation"]


def plot_tin(
    heights: ArrayLike,
    vertices: ArrayLike,
    triangles: ArrayLike,
    path: str | Path,
    *,
    title: str | None = None,
) -> Path:
    """Draw the mesh ``(vertices, triangles)`` (``x`` = column, ``y`` = row) over the relief of ``heights``; PNG by extension."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LightSource

    h = np.asarray(heights, dtype=np.float64)
    v = np.asarray(vertices, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.intp).reshape(-1, 3)
    rows, cols = h.shape
    low = float(np.nanmin(h))
    span = float(np.nanmax(h) - low) or 1.0
    ls = LightSource(azdeg=315, altdeg=45)
    # Shaded as heights in [0, 1] with a vertical exaggeration of about a tenth of the grid's width,
    # so the relief reads at any height range (subnormal ranges included: dividing by one would overflow).
    relief = ls.shade((np.nan_to_num(h, nan=low) - low) / span, cmap=plt.get_cmap("gist_earth"),
                      vert_exag=0.1 * max(rows, cols), blend_mode="soft")
    width = 8.0
    fig, ax = plt.subplots(figsize=(width, width * rows / cols + 0.6), dpi=120)
    ax.imshow(relief, origin="upper", extent=(-0.5, cols - 0.5, rows - 0.5, -0.5), interpolation="bilinear")
    if t.size:
        ax.triplot(v[:, 0], v[:, 1], t, color="black", linewidth=0.25, alpha=0.7)
    ax.set_xlim(-0.5, cols - 0.5)
    ax.set_ylim(rows - 0.5, -0.5)
    ax.set_aspect("equal")
    ax.set_xlabel("column (x)")
    ax.set_ylabel("row (y)")
    ax.set_title(title or f"{v.shape[0]:,} points, {t.shape[0]:,} triangles")
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, bbox_inches="tight")
    plt.close(fig)
    return out


def plot_triangulation(points: ArrayLike, triangles: ArrayLike, path: str | Path, *, title: str | None = None) -> Path:
    """Draw a 2D triangulation of scattered points (axes in the points' own units, offset removed for legibility)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    p = np.asarray(points, dtype=np.float64)[:, :2]
    t = np.asarray(triangles, dtype=np.intp).reshape(-1, 3)
    origin = p.min(axis=0) if p.size else np.zeros(2)
    unit = ""
    with np.errstate(over="ignore"):
        q = p - origin  # UTM-sized offsets would swamp the tick labels
    if q.size and not float(np.max(q)) < 2.0**1000:
        # Extents near float64's limit overflow here or in matplotlib's ticks: draw in units of 2^e (exact scaling).
        e = int(np.frexp(np.max(np.abs(p)))[1])
        q = np.ldexp(p, -e) - np.ldexp(origin, -e)
        unit = f" (units of 2^{e})"
    fig, ax = plt.subplots(figsize=(7, 7), dpi=120)
    if t.size:
        ax.triplot(q[:, 0], q[:, 1], t, color="tab:blue", linewidth=0.4)
    ax.plot(q[:, 0], q[:, 1], ".", color="black", markersize=2)
    ax.set_aspect("equal")
    ax.set_xlabel(f"x − {origin[0]:.10g}{unit}")
    ax.set_ylabel(f"y − {origin[1]:.10g}{unit}")
    ax.set_title(title or f"Delaunay: {p.shape[0]:,} points, {t.shape[0]:,} triangles")
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, bbox_inches="tight")
    plt.close(fig)
    return out
