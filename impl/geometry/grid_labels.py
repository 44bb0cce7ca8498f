"""Z-order labels of a height grid's samples: :class:`GridZOrder` (locality of the complex's keys, paper §5).

A greedy-insertion run (:mod:`persistri.impl.terrain.greedy`) makes one persistent
version of its 2-complex per inserted sample, and that version copies the search
paths, in the complex's ordered map, of the six or seven vertices the insertion
changed.  Labelled by grid index (row-major) those vertices — neighbours on the
mesh — lie a row apart in key order, spread over the whole tree, and their paths
share only its top levels; labelled along a space-filling curve they are near one
another in key order and their paths share most of their nodes (the scattered
Delaunay's Hilbert labels, the hull's z-order labels: docs/performance.md).

The label of the sample at column ``x``, row ``y`` of a ``rows × cols`` grid is
its *Morton code*: the bits of ``x`` and ``y`` interleaved (``x`` in the even
positions), the extra high bits of the longer axis on top.  It is a function of
the sample alone, cheap both ways — :meth:`GridZOrder.label` is two table reads
and an ``or`` (each axis's bits spread once, per column and per row), and
:meth:`GridZOrder.decode` reads one table entry per byte of the label — and
vectorised over arrays (:meth:`GridZOrder.labels`, :meth:`GridZOrder.decode_many`).
The labels are below ``size = 2^(bx + by)`` (``bx``, ``by`` the bit lengths of
``cols − 1`` and ``rows − 1``): fewer than four times the grid's samples, with
holes (the codes of the box's points outside the grid), so ``size`` is the first
label no sample has — the symbolic infinite vertex's.

The labels are only an *order*: every test that decides a triangulation ranks the
samples by grid index (row-major) as before
(:class:`~persistri.impl.geometry.grid_predicates.GridPredicates2` with
``labels="zorder"``), so every mesh is the one the row-major labels give.

Measured (2026-11-28, docs/performance.md, "The terrain's vertices in z-order, tried"):
greedy insertion wired to these labels made every mesh, error and level bit for bit the
same and cut the tree nodes a version adds by a third (Jacksboro at 20,000 points: 37.7 →
24.5), but the whole run cost 1.7–3.2 % *more* instructions interpreted and 2 % more on the
compiled twin: the conversions between labels and grid indices at the terrain's Python
level (the sector test's ray coordinates, the vertices' heights, the final read in the
row-major order its RMS error is summed in) cost more than the map's shared paths saved.
Greedy insertion keeps row-major labels; these stay for a triangulator that converts in
compiled code.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["GridZOrder"]

IntArray = NDArray[np.intp]


def _positions(bits_x: int, bits_y: int) -> tuple[list[int], list[int]]:
    """The label bit of each bit of ``x`` and of ``y``: interleaved up to the shorter axis's bits, then the
    longer axis's bits on top, one after another."""
    common = min(bits_x, bits_y)
    px = [2 * j if j < common else common + j for j in range(bits_x)]
    py = [2 * j + 1 if j < common else common + j for j in range(bits_y)]
    return px, py


def _spread(values: NDArray[np.int64], positions: list[int]) -> NDArray[np.int64]:
    out = np.zeros(values.shape, dtype=np.int64)
    for j, pos in enumerate(positions):
        out |= ((values >> j) & 1) << pos
    return out


class GridZOrder:
    """The z-order (Morton) labels of the samples of a ``rows × cols`` grid (module docstring).

    ``GridZOrder((rows, cols))``: O(rows + cols) to build (each axis's spread bits, and a table of
    256 entries per byte of the labels for decoding).  Sample ``q = y · cols + x`` (row-major grid
    index) has label :meth:`label` ``(q)``; a label's ``(x, y)`` is :meth:`decode` ``(label)``.  Labels
    are distinct, below :attr:`size`; the samples' z-order is their labels' order.
    """

    __slots__ = ("shape", "size", "_sx", "_sy", "spread_x", "spread_y", "_dx", "_dy", "_dx_lists", "_dy_lists")

    shape: tuple[int, int]
    size: int
    spread_x: list[int]
    """``spread_x[x]``: the label bits of column ``x`` (a label is ``spread_x[x] | spread_y[y]``)."""
    spread_y: list[int]
    """``spread_y[y]``: the label bits of row ``y``."""

    def __init__(self, shape: tuple[int, int]) -> None:
        rows, cols = int(shape[0]), int(shape[1])
        if rows < 1 or cols < 1:
            raise ValueError(f"a grid has at least one row and one column, got {shape!r}")
        self.shape = (rows, cols)
        bx, by = (cols - 1).bit_length(), (rows - 1).bit_length()
        self.size = 1 << (bx + by)
        px, py = _positions(bx, by)
        self._sx = _spread(np.arange(cols, dtype=np.int64), px)
        self._sy = _spread(np.arange(rows, dtype=np.int64), py)
        self.spread_x = self._sx.tolist()
        self.spread_y = self._sy.tolist()
        # Decoding: each byte of a label gives some bits of x and some of y; one table of 256 entries per byte.
        nbytes = max(1, -(-(bx + by) // 8))
        byte = np.arange(256, dtype=np.int64)
        self._dx: list[NDArray[np.int64]] = []
        self._dy: list[NDArray[np.int64]] = []
        for k in range(nbytes):
            dx = np.zeros(256, dtype=np.int64)
            dy = np.zeros(256, dtype=np.int64)
            for j, pos in enumerate(px):
                if 8 * k <= pos < 8 * k + 8:
                    dx |= ((byte >> (pos - 8 * k)) & 1) << j
            for j, pos in enumerate(py):
                if 8 * k <= pos < 8 * k + 8:
                    dy |= ((byte >> (pos - 8 * k)) & 1) << j
            self._dx.append(dx)
            self._dy.append(dy)
        self._dx_lists: list[list[int]] = [t.tolist() for t in self._dx]
        self._dy_lists: list[list[int]] = [t.tolist() for t in self._dy]

    def __repr__(self) -> str:
        return f"GridZOrder(shape={self.shape})"

    def label(self, q: int) -> int:
        """The label of grid sample ``q`` (row-major index, ``0 ≤ q < rows · cols``). O(1)."""
        y, x = divmod(q, self.shape[1])
        return self.spread_x[x] | self.spread_y[y]

    def label_xy(self, x: int, y: int) -> int:
        """The label of the sample at column ``x``, row ``y``. O(1)."""
        return self.spread_x[x] | self.spread_y[y]

    def labels(self, q: NDArray[np.integer[Any]]) -> NDArray[np.int64]:
        """The labels of grid samples ``q`` (an array of row-major indices), as ``int64``. O(len(q))."""
        y, x = np.divmod(np.asarray(q, dtype=np.int64), self.shape[1])
        out: NDArray[np.int64] = self._sx[x] | self._sy[y]
        return out

    def decode(self, label: int) -> tuple[int, int]:
        """``(x, y)`` of the sample labelled ``label`` (any label below :attr:`size`: a hole gives a point of the
        bounding power-of-two box outside the grid). O(bytes of the label)."""
        x = y = 0
        k = 0
        c = int(label)
        dx, dy = self._dx_lists, self._dy_lists
        while c:
            b = c & 255
            x |= dx[k][b]
            y |= dy[k][b]
            c >>= 8
            k += 1
        return x, y

    def grid_index(self, label: int) -> int:
        """The row-major grid index of the sample labelled ``label``. O(bytes of the label)."""
        x, y = self.decode(label)
        return y * self.shape[1] + x

    def decode_many(self, labels: NDArray[np.integer[Any]]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
        """``(x, y)`` of an array of labels (below :attr:`size`), as two ``int64`` arrays. O(len · bytes)."""
        c = np.asarray(labels, dtype=np.int64)
        x = np.zeros(c.shape, dtype=np.int64)
        y = np.zeros(c.shape, dtype=np.int64)
        for k, (dx, dy) in enumerate(zip(self._dx, self._dy)):
            b = (c >> (8 * k)) & 255
            x |= dx[b]
            y |= dy[b]
        return x, y

    def grid_indices(self, labels: NDArray[np.integer[Any]]) -> NDArray[np.int64]:
        """The row-major grid indices of an array of labels. O(len · bytes)."""
        x, y = self.decode_many(labels)
        out: NDArray[np.int64] = y * self.shape[1] + x
        return out
