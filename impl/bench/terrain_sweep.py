"""Maximum error at equal vertex count, over a sweep of vertex counts: persistri against pydelatin (``persistri bench terrain``).

Issue 17's row "terrain max error at equal vertex count ≤ 1.00× pydelatin"
compares two greedy insertions (Garland–Heckbert, paper §5) by the maximum
vertical error of their meshes at the same number of vertices.  At one count
that ratio is partly luck: the maximum error of greedy insertion is not
monotone in the number of points (an insertion can make a long triangle across
a ridge, which the next ones repair), and two runs whose insertion orders
differ by one tie are mid-repair at different counts — on the Jacksboro DEM
the ratio at single counts ranges from 0.7× to 3×, either way.  So the
benchmark reads it over many counts:

* :func:`sweep_counts` — ``n`` vertex counts spaced evenly on a log scale from
  ``lo`` to ``hi`` (both included, rounded, duplicates merged): no count is
  chosen by hand;
* :func:`error_sweep` — at each count, pydelatin refined to it and persistri's
  kept level with as many vertices (one run of persistri gives every level:
  ``TinHistory.at``), both meshes measured the same way by :func:`max_error`;
* :class:`ErrorSweep` — the distribution of the ratio persistri ÷ pydelatin:
  its median and quartiles, and the shares of counts where persistri's mesh
  is better, equal (the same error: in practice the same mesh) or worse; and
  the same for persistri's *best level within the budget* (the least maximum
  error among its levels with at most that many points, which persistence
  gives for free) against pydelatin's mesh at the count.

Both meshes are measured identically: every grid sample's vertical distance to
the mesh, each vertex at the grid's own float64 height (pydelatin stores its
vertices' heights as float32, which alone would move its error by about 10⁻⁷
relative on a non-integer grid), each triangle's vertices put in one canonical
order (counterclockwise, from its smallest sample index), so that two equal
meshes have bit-identical errors and a tie is a tie.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["ErrorSweep", "sweep_counts", "error_sweep", "max_error", "canonical_mesh", "pydelatin_mesh"]

IntArray = NDArray[np.intp]
FloatArray = NDArray[np.float64]


def sweep_counts(lo: int, hi: int, n: int) -> list[int]:
    """``n`` vertex counts from ``lo`` to ``hi`` (both included), evenly spaced on a log scale, rounded and
    without duplicates (fewer than ``n`` when the range is narrow).  :class:`ValueError` for ``lo < 4``,
    ``hi < lo`` or ``n < 1``.  O(n)."""
    if n < 1:
        raise ValueError(f"a sweep needs at least one vertex count, got {n}")
    if lo < 4 or hi < lo:
        raise ValueError(f"a sweep runs from lo >= 4 to hi >= lo vertices, got {lo} to {hi}")
    if n == 1 or lo == hi:
        return sorted({lo, hi})
    return sorted({int(round(k)) for k in np.geomspace(lo, hi, n)})


def canonical_mesh(heights: FloatArray, xy: ArrayLike, triangles: ArrayLike) -> tuple[FloatArray, IntArray]:
    """A mesh of grid samples, ready for :func:`~persistri.impl.terrain.check.mesh_errors`: the vertices
    ``(x, y, z)`` with ``z`` the grid's own height at ``(x = column, y = row)``, and each triangle
    counterclockwise in ``(x, y)`` from its vertex of smallest sample index ``y · cols + x``.

    Two meshes with the same triangles then give the very same floats, whatever order or orientation their
    producers wrote the triangles in (the interpolation sums its three terms in vertex order).  O(k + m)."""
    h = np.asarray(heights, dtype=np.float64)
    cols = h.shape[1]
    v = np.asarray(xy, dtype=np.float64)[:, :2]
    col, row = v[:, 0].astype(np.intp), v[:, 1].astype(np.intp)
    vertices = np.column_stack([v, h[row, col]])
    t = np.asarray(triangles, dtype=np.intp).reshape(-1, 3).copy()
    x, y = v[t, 0], v[t, 1]
    # Exact: integer coordinates below 2^25.
    area = (x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0]) - (y[:, 1] - y[:, 0]) * (x[:, 2] - x[:, 0])
    clockwise = area < 0
    t[clockwise] = t[clockwise][:, ::-1]
    sample = row * cols + col
    first = np.argmin(sample[t], axis=1)
    out: IntArray = np.take_along_axis(t, (first[:, None] + np.arange(3)[None, :]) % 3, axis=1)
    return vertices, out


def max_error(heights: FloatArray, xy: ArrayLike, triangles: ArrayLike) -> float:
    """The maximum vertical error of a mesh of grid samples over every sample (:func:`canonical_mesh`, then
    :func:`~persistri.impl.terrain.check.mesh_errors`; NaN if a sample is uncovered). O(Σ bounding boxes)."""
    from persistri.impl.terrain.check import mesh_errors

    vertices, tri = canonical_mesh(heights, xy, triangles)
    err, _ = mesh_errors(heights, vertices, tri)
    return float(np.max(err))


def pydelatin_mesh(heights: FloatArray, k: int) -> tuple[FloatArray, IntArray]:
    """pydelatin refined to ``k`` points (``Delatin(float32 heights, max_points=k, max_error=0)``): its vertices'
    ``(x, y)`` in grid coordinates (``y`` = row: pydelatin's runs up from the last row) and its triangles."""
    from pydelatin import Delatin

    mesh: Any = Delatin(np.asarray(heights, dtype=np.float32), max_points=int(k), max_error=0.0)
    v = np.asarray(mesh.vertices, dtype=np.float64)[:, :2].copy()
    v[:, 1] = heights.shape[0] - 1 - v[:, 1]
    return v, np.asarray(mesh.triangles, dtype=np.intp)


def _quantiles(r: FloatArray) -> tuple[float, float, float]:
    q1, q2, q3 = np.quantile(r, [0.25, 0.5, 0.75]) if r.size else (np.nan, np.nan, np.nan)
    return float(q1), float(q2), float(q3)


@dataclass(frozen=True, slots=True)
class ErrorSweep:
    """The maximum errors of both meshers at each of ``counts`` vertices (:func:`error_sweep`).

    ``pydelatin`` and ``persistri`` are the errors of the two meshes at each count (pydelatin's vertex
    count, which is the count asked for unless its mesh became exact sooner); ``persistri_best`` is the
    least error among persistri's levels with at most that many points.
    """

    counts: tuple[int, ...]
    pydelatin: tuple[float, ...]
    persistri: tuple[float, ...]
    persistri_best: tuple[float, ...]

    def ratios(self, best: bool = False) -> FloatArray:
        """persistri ÷ pydelatin at each count (``best``: persistri's best level within the budget)."""
        ours = np.array(self.persistri_best if best else self.persistri, dtype=np.float64)
        theirs = np.array(self.pydelatin, dtype=np.float64)
        with np.errstate(divide="ignore", invalid="ignore"):
            out: FloatArray = ours / theirs
        return out

    def quartiles(self, best: bool = False) -> tuple[float, float, float]:
        """The ratio's first quartile, median and third quartile over the counts."""
        return _quantiles(self.ratios(best))

    def shares(self, best: bool = False) -> tuple[float, float, float]:
        """The shares of counts where persistri's error is lower than, equal to and higher than pydelatin's."""
        ours = np.array(self.persistri_best if best else self.persistri, dtype=np.float64)
        theirs = np.array(self.pydelatin, dtype=np.float64)
        n = max(1, ours.size)
        return (
            float(np.count_nonzero(ours < theirs)) / n,
            float(np.count_nonzero(ours == theirs)) / n,
            float(np.count_nonzero(ours > theirs)) / n,
        )

    def as_dict(self) -> dict[str, Any]:
        """A JSON-ready dictionary: the counts and errors, and the summaries."""
        q = self.quartiles()
        b = self.quartiles(best=True)
        return {
            "counts": list(self.counts),
            "pydelatin_errors": list(self.pydelatin),
            "persistri_errors": list(self.persistri),
            "persistri_best_errors": list(self.persistri_best),
            "ratio_quartiles": list(q),
            "ratio_median": q[1],
            "shares_lower_equal_higher": list(self.shares()),
            "best_ratio_quartiles": list(b),
            "best_ratio_median": b[1],
            "best_shares_lower_equal_higher": list(self.shares(best=True)),
        }

    def summary(self) -> str:
        """One paragraph for the benchmark's table: the distribution of the ratio and of the best level's."""
        if not self.counts:
            return "max error at equal vertex count: no counts swept"
        q = self.quartiles()
        b = self.quartiles(best=True)
        lo, eq, hi = self.shares()
        blo, beq, bhi = self.shares(best=True)
        return (
            f"max error at equal vertex count, {len(self.counts)} counts log-spaced from {self.counts[0]:,} to "
            f"{self.counts[-1]:,}: persistri ÷ pydelatin median {q[1]:.3f} (quartiles {q[0]:.3f}–{q[2]:.3f}); "
            f"persistri lower at {lo:.0%}, equal at {eq:.0%}, higher at {hi:.0%} of the counts.  "
            f"persistri's best level with at most k points ÷ pydelatin at k: median {b[1]:.3f} "
            f"(quartiles {b[0]:.3f}–{b[2]:.3f}); lower at {blo:.0%}, equal at {beq:.0%}, higher at {bhi:.0%}."
        )


def error_sweep(heights: FloatArray, counts: Sequence[int], history: Any) -> ErrorSweep:
    """Both meshers' maximum errors at each of ``counts`` vertices (module docstring).

    ``history`` is a :class:`~persistri.impl.terrain.greedy.TinHistory` of a run with at least
    ``max(counts)`` points (or one that stopped sooner at error 0: its last level stands for the counts
    beyond).  Per count: one pydelatin run and two error measurements over the grid.
    """
    h = np.asarray(heights, dtype=np.float64)
    errors = np.asarray(history.max_errors)
    top = 3 + len(history)
    done: list[int] = []
    theirs: list[float] = []
    ours: list[float] = []
    best: list[float] = []
    for k in sorted({int(c) for c in counts}):
        xy, tri = pydelatin_mesh(h, k)
        points = int(xy.shape[0])
        level = min(points, top)
        tin = history.at(points=level)
        done.append(points)
        theirs.append(max_error(h, xy, tri))
        ours.append(max_error(h, tin.vertices, tin.triangles))
        # The best level as the run's levels rank them, measured as the others are.
        j = 4 + int(np.argmin(errors[: level - 3]))
        if j == level:
            best.append(ours[-1])
        else:
            b = history.at(points=j)
            best.append(max_error(h, b.vertices, b.triangles))
    return ErrorSweep(tuple(done), tuple(theirs), tuple(ours), tuple(best))
