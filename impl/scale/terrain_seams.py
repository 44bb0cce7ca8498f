"""Seams of a tiled terrain: how a grid is cut into tiles, and the border vertices each seam gets, decided once.

Issue 18, on the terrain of paper §5.  A grid of ``rows × cols`` samples is cut
by *border lines* — rows ``0, s, 2s, …, rows − 1`` and columns ``0, s, 2s, …,
cols − 1`` with ``s = tile − 1`` (:class:`Tiling`) — into tiles of at most
``tile × tile`` samples that overlap by one row or column: the samples on a
border line belong to the tiles on both sides of it.  Where a row line meets a
column line is a *tile corner*, shared by up to four tiles.  A *seam* is the
piece of a border line between two consecutive tile corners: the top, bottom,
left or right side of a tile, shared with the neighbour across it (sides on the
grid's rim have none).

Each seam's vertices are chosen by :func:`seam_vertices`, once, from its own
samples only: Douglas–Peucker with the vertical error, which in one dimension is
greedy insertion to a threshold (the worst sample of a segment is inserted
while the segment's worst error exceeds the bound; a split changes only its own
segment, so the order of the splits does not change the result).  It keeps the
seam's two ends (tile corners) and every sample it inserts; every other sample
of the seam is then within ``max_error`` of the polyline, **exactly**: the
decision "within the bound" is a float evaluation outside a proven band around
the bound and exact rational arithmetic inside it (:func:`seam_vertices`), so
the guarantee does not depend on a rounding.  Where the two meshes of
neighbouring tiles meet they meet along this polyline
(:mod:`persistri.impl.scale.terrain` proves it), so the polyline's error is the
mesh's error at every seam sample.

Cost: O(n · d) float work for a seam of ``n`` samples whose Douglas–Peucker
recursion is ``d`` deep (O(n log n) on ordinary profiles), plus one exact
evaluation per sample that falls in the band (almost never).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Final

import numpy as np
from numpy.typing import NDArray

__all__ = ["Tiling", "Seam", "seam_vertices", "SEAM_BAND"]

IntArray = NDArray[np.intp]
FloatArray = NDArray[np.float64]

SEAM_BAND: Final = 2.0**-45
"""Relative width of the band around the bound inside which :func:`seam_vertices` decides exactly.

The float error of one sample, ``|z − (z_i + (z_j − z_i)·((t − i)/(j − i)))|``,
takes five roundings (a difference, a quotient of integers, a product, a sum, a
difference), each of relative size at most ``u = 2^-53``, on quantities of size
at most ``4M`` with ``M`` the largest ``|z|`` of the segment: the computed error
is within ``16·u·M < 2^-48·M`` of the true one.  A computed error farther than
``2^-45·(M + e)`` from the bound ``e`` (that product itself computed with a
relative error of a few ``u``) is therefore on the same side of ``e`` as the
true error; the samples nearer than that are decided with :class:`~fractions.Fraction`.
"""


@dataclass(frozen=True, slots=True)
class Tiling:
    """The tiles of a ``rows × cols`` grid with tiles of at most ``tile × tile`` samples (module docstring).

    ``row_lines`` and ``col_lines`` are the border lines, first ``0`` and last
    ``rows − 1`` (``cols − 1``); tile ``(i, j)`` spans rows
    ``row_lines[i] … row_lines[i + 1]`` and columns ``col_lines[j] … col_lines[j + 1]``,
    both ends included.

    >>> t = Tiling.of((10, 7), 4)
    >>> t.row_lines, t.col_lines, t.shape
    ((0, 3, 6, 9), (0, 3, 6), (3, 2))
    >>> t.window(2, 1)
    (6, 9, 3, 6)
    """

    rows: int
    cols: int
    tile: int
    row_lines: tuple[int, ...]
    col_lines: tuple[int, ...]

    @classmethod
    def of(cls, shape: tuple[int, int], tile: int) -> Tiling:
        """The tiling of a grid of ``shape`` by tiles of ``tile`` samples a side; :class:`ValueError` if ``tile < 3``
        or the grid is smaller than 2 × 2.  O(rows / tile + cols / tile)."""
        if isinstance(tile, bool) or not isinstance(tile, (int, np.integer)):
            raise TypeError(f"tile must be an integer, not {type(tile).__name__}")
        if tile < 3:
            raise ValueError(f"tile must be at least 3 samples a side (a tile needs an interior), got {tile}")
        rows, cols = (int(v) for v in shape)
        if rows < 2 or cols < 2:
            raise ValueError(f"a terrain needs at least 2 rows and 2 columns, got shape {(rows, cols)}")
        step = int(tile) - 1
        return cls(rows, cols, int(tile), _lines(rows, step), _lines(cols, step))

    @property
    def shape(self) -> tuple[int, int]:
        """How many tiles down and across."""
        return (len(self.row_lines) - 1, len(self.col_lines) - 1)

    def __len__(self) -> int:
        return (len(self.row_lines) - 1) * (len(self.col_lines) - 1)

    def tiles(self) -> list[tuple[int, int]]:
        """Every tile ``(i, j)``, row-major."""
        ti, tj = self.shape
        return [(i, j) for i in range(ti) for j in range(tj)]

    def window(self, i: int, j: int) -> tuple[int, int, int, int]:
        """``(r0, r1, c0, c1)``: tile ``(i, j)`` spans rows ``r0 … r1`` and columns ``c0 … c1``, ends included."""
        return (self.row_lines[i], self.row_lines[i + 1], self.col_lines[j], self.col_lines[j + 1])


def _lines(n: int, step: int) -> tuple[int, ...]:
    return tuple(range(0, n - 1, step)) + (n - 1,)


@dataclass(frozen=True, slots=True)
class Seam:
    """The vertices chosen on one seam, and the errors of its samples.

    * ``vertices`` — positions along the seam (``0 … n − 1``), increasing, both ends included;
    * ``max_error`` — the largest error of a seam sample against the polyline
      (each error the float nearest the true one, so it is ≤ the bound whenever
      the true error is);
    * ``scale``, ``scaled_squares`` — the sum of squared errors as
      ``scale² · scaled_squares`` (``scale`` the largest error): sums of squares
      of heights up to 1e250 would overflow.
    """

    vertices: IntArray
    max_error: float
    scale: float
    scaled_squares: float


def seam_vertices(z: FloatArray, max_error: float) -> Seam:
    """Douglas–Peucker on the profile ``z`` (heights at positions ``0 … n − 1``) to the bound ``max_error`` (module docstring).

    Returns the :class:`Seam`: every sample is within ``max_error`` of the
    polyline through the chosen vertices, exactly.  A segment is split at the
    first sample of largest float error (the splits never need to be exact:
    any interior sample makes progress).  ``n ≥ 2``.  O(n · depth).

    >>> s = seam_vertices(np.array([0.0, 1.0, 0.0, 0.0, 3.0, 0.0]), 0.5)
    >>> s.vertices.tolist(), s.max_error        # sample 2 is 0.5 below the chord from 1 to 3: within
    ([0, 1, 3, 4, 5], 0.5)
    >>> s = seam_vertices(np.array([0.0, 1.0, 2.0, 3.5, 4.0]), 0.5)
    >>> s.vertices.tolist(), s.max_error        # 3.5 is exactly 0.5 above the chord: kept out
    ([0, 4], 0.5)
    """
    z = np.asarray(z, dtype=np.float64)
    n = int(z.size)
    if n < 2:
        raise ValueError(f"a seam has at least 2 samples, got {n}")
    e = float(max_error)
    keep = np.zeros(n, dtype=bool)
    keep[0] = keep[-1] = True
    errors = np.zeros(n, dtype=np.float64)
    stack = [(0, n - 1)]
    while stack:
        i, j = stack.pop()
        if j - i < 2:
            continue
        err, exact = _segment_errors(z, i, j, e)
        if exact is None:
            k = i + 1 + int(np.argmax(err))
            keep[k] = True
            stack.append((k, j))
            stack.append((i, k))
        else:
            errors[i + 1 : j] = exact
    vertices = np.flatnonzero(keep).astype(np.intp)
    scale = float(errors.max())
    squares = float(np.sum((errors / scale) ** 2)) if scale > 0 else 0.0
    return Seam(vertices, scale, scale, squares)


def _segment_errors(z: FloatArray, i: int, j: int, e: float) -> tuple[FloatArray, FloatArray | None]:
    """The float errors of the samples strictly between ``i`` and ``j``, and, when they are all within ``e``
    (exactly), the errors to report (the float ones, made correctly rounded inside the band); else None."""
    zi, zj = float(z[i]), float(z[j])
    inner = z[i + 1 : j]
    t = np.arange(1, j - i, dtype=np.float64)
    err: FloatArray = np.abs(inner - (zi + (zj - zi) * (t / float(j - i))))
    top = float(err.max())
    m = max(abs(zi), abs(zj), float(np.abs(inner).max()))
    band = SEAM_BAND * (m + e)
    if top > e + band:
        return err, None
    if top < e - band:
        return err, err
    out = err.copy()
    for k in np.flatnonzero(err >= e - band).tolist():
        exact = _exact_error(zi, zj, float(inner[k]), k + 1, j - i)
        if exact > e:
            return err, None
        out[k] = float(exact)  # Fraction → float rounds to nearest: ≤ e since e is a float
    return err, out


def _exact_error(zi: float, zj: float, zt: float, t: int, length: int) -> Fraction:
    """``|z_t − (z_i + (z_j − z_i)·t/length)|`` in exact rational arithmetic."""
    fi, fj, ft = Fraction(zi), Fraction(zj), Fraction(zt)
    return abs(ft - fi - (fj - fi) * Fraction(t, length))
