"""Exact 2D predicates over the points of a height grid, computed from their indices: :class:`GridPredicates2`.

Greedy insertion (paper §5) triangulates the samples of a ``rows × cols`` grid:
point ``i`` is ``(x, y) = (i mod cols, i div cols)``.  A
:class:`~persistri.impl.geometry.predicates.Predicates2` over those points would
keep an ``(n, 2)`` array of them, its scaled copy and a row table — some 170
bytes per sample, 700 MB for a 2,048 × 2,048 grid, where only the few vertices
are ever tested one by one.  :class:`GridPredicates2` answers the same tests with
the same signs (the same filter, exact arithmetic and Simulation of Simplicity,
by point index) and keeps nothing per sample: a point's row of floats is
computed from its index, and kept, the first time it is tested (the vertices),
and the samples' coordinates, which the terrain's sector tests and errors read
in bulk, are divided out of their indices (:meth:`GridPredicates2.coordinates`).

The coordinates are small integers, so the filter needs no scaling (``shift``
0: every grain is 1, every magnitude below ``2^25``) and the exact integers are
the coordinates themselves.  :meth:`GridPredicates2.points` still returns the
``(n, 2)`` array, made on each call.
"""

from __future__ import annotations

import operator
from typing import Any

import numpy as np
from numpy.typing import NDArray

from persistri.impl.geometry.exact import IntegerScale
from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.stats import Stats

__all__ = ["GridPredicates2", "GRID_LIMIT"]

GRID_LIMIT = 2**25
"""Largest number of rows or columns: coordinates stay below ``2^25`` (the filters' and the sectors' bounds)."""

IntArray = NDArray[np.intp]


class _GridRows(dict[int, tuple[float, ...]]):
    """Point ``i``'s row of floats ``(i mod cols, i div cols)``, made on first use and kept (a dict with ``__missing__``).

    The rows share their float objects: one per distinct coordinate (``floats``, at most ``rows + cols``
    of them), not two per point; and a row is kept under the integer it was asked for (a vertex is an
    ``int``), not under a copy of it.  On a 2,048² grid meshed to 75K vertices the rows took 9.9 MB with
    two floats each and take 4.0 MB (``tracemalloc``), the table itself 2.5 MB.
    """

    __slots__ = ("cols", "n", "floats")

    def __init__(self, cols: int, n: int) -> None:
        super().__init__()
        self.cols = cols
        self.n = n
        self.floats: dict[int, float] = {}

    def __missing__(self, i: int) -> tuple[float, ...]:
        # As a list of rows would: any integer (bool included), IndexError out of range, TypeError otherwise.
        try:
            k = operator.index(i)
        except TypeError:
            raise TypeError(f"point indices must be integers, got {i!r}") from None
        if not 0 <= k < self.n:
            raise IndexError(f"point index {k} out of range for {self.n} points")
        y, x = divmod(k, self.cols)
        floats = self.floats
        fx = floats.get(x)
        if fx is None:
            fx = floats[x] = float(x)
        fy = floats.get(y)
        if fy is None:
            fy = floats[y] = float(y)
        row = (fx, fy)
        # Kept under i itself when it is an int (a Vertex: the one object the mesh holds anyway); equal keys
        # hash alike, so a later look-up by k, by i or by another equal int finds the row.
        self[i if isinstance(i, int) else k] = row
        return row


class GridPredicates2(Predicates2):
    """Exact ``orient2d`` and ``incircle`` over the points ``(col, row)`` of a ``rows × cols`` grid, by point index.

    ``GridPredicates2((rows, cols), stats=None)``: O(1) to build, O(1) memory per
    point tested.  The same methods, signs, counting and errors as
    :class:`~persistri.impl.geometry.predicates.Predicates2` built over
    ``grid_points((rows, cols))`` (point ``i`` is ``(i mod cols, i div cols)``).
    :class:`ValueError` for a shape that is not two integers in ``[1, GRID_LIMIT]``.
    """

    __slots__ = ("_shape", "_columns")

    _shape: tuple[int, int]
    _columns: tuple[NDArray[Any], NDArray[Any]] | None

    def __init__(self, shape: tuple[int, int], *, stats: Stats | None = None) -> None:
        rows, cols = shape
        for v in (rows, cols):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 1 <= v <= GRID_LIMIT:
                raise ValueError(f"a grid's shape is two integers from 1 to {GRID_LIMIT}, got {shape!r}")
        rows, cols = int(rows), int(cols)
        n = rows * cols
        self._shape = (rows, cols)
        self._columns = None
        self._n = n
        self._dim = 2
        self.stats = stats
        empty = np.zeros((0, 2))
        empty.setflags(write=False)
        self._points = empty  # never read: every reader of the points is overridden below
        self._cols = (np.zeros(0), np.zeros(0))
        # The row table: a dict that makes a point's row on first use, where the base class keeps a list of
        # n lazy rows (8 bytes per sample).  Every reader of _rows indexes it by one point (the checked
        # tests, the kernel: the base class declares it a RowTable) or is overridden here (_row).
        self._rows = _GridRows(cols, n)
        top = max(rows, cols) - 1
        # Integer coordinates: grain 0 (the least over the nonzero ones is that of an odd number), magnitude < 2^25.
        self._span = (0, top.bit_length()) if top > 0 else None
        self._shift = 0  # every grain is >= 0 >= GRAIN_MIN and every magnitude <= 25 <= TOP_MAX: no scaling needed
        self._uniform = True
        self._grain = None
        self._scale = IntegerScale(0, 0)
        self._ints = {}
        self._sos_rank = None  # Simulation of Simplicity in index order

    def __repr__(self) -> str:
        return f"GridPredicates2(shape={self._shape})"

    @property
    def shape(self) -> tuple[int, int]:
        """The grid's ``(rows, cols)``."""
        return self._shape

    @property
    def points(self) -> NDArray[np.float64]:
        """The ``(n, 2)`` array of the grid's points, ``(col, row)`` in index order: made on each call. O(n)."""
        rows, cols = self._shape
        xy = np.empty((self._n, 2), dtype=np.float64)
        xy[:, 0] = np.tile(np.arange(cols, dtype=np.float64), rows)
        xy[:, 1] = np.repeat(np.arange(rows, dtype=np.float64), cols)
        xy.setflags(write=False)
        return xy

    def coordinate_columns(self) -> tuple[NDArray[Any], NDArray[Any]]:
        """The ``x`` and ``y`` of every point, as two read-only columns of small integers (``uint16`` up to
        65,536 rows and columns, ``int32`` beyond): 4 bytes per sample, made on the first call (gathering from
        them is three times faster than dividing the indices).  O(n) once."""
        cols = self._columns
        if cols is None:
            rows, width = self._shape
            kind = np.uint16 if max(rows, width) <= 1 << 16 else np.int32
            cols = self._columns = (
                np.tile(np.arange(width, dtype=kind), rows),
                np.repeat(np.arange(rows, dtype=kind), width),
            )
            for c in cols:
                c.setflags(write=False)
        return cols

    def coordinates(self, q: NDArray[np.signedinteger[Any]]) -> tuple[NDArray[Any], NDArray[Any]]:
        """``(x, y)`` of points ``q``: ``(q mod cols, q div cols)``, as integers of ``q``'s dtype. O(len(q)).

        Divided, not gathered from :meth:`coordinate_columns`: the columns would take 4 bytes a sample
        (16 MB on a 2,048² grid) for the terrain's sector tests and errors, and for ``int32`` sample
        lists one ``divmod`` costs less than two gathers, which convert the indices to ``intp`` first."""
        y, x = np.divmod(q, self._shape[1])
        return x, y

    def xy(self, i: int) -> tuple[float, float]:
        """``(x, y)`` of point ``i`` as floats (its row, kept once made). O(1)."""
        x, y = self._rows[i]
        return x, y

    # -- the hooks of the base class ---------------------------------------------------

    def _row(self, i: int) -> tuple[float, ...]:
        return self._rows[i]

    def _filter_columns(self, i: int | IntArray) -> list[NDArray[np.float64]]:
        if isinstance(i, int):
            fx, fy = self._rows[i]
            return [np.asarray(fx), np.asarray(fy)]
        x, y = self.coordinates(i)
        return [x.astype(np.float64), y.astype(np.float64)]

    def _extents(self) -> list[tuple[float, float]]:
        rows, cols = self._shape
        return [(0.0, float(cols - 1)), (0.0, float(rows - 1))]

    def _int(self, i: int) -> tuple[int, ...]:
        y, x = divmod(int(i), self._shape[1])
        return (x, y)

    def _int_columns(self, q: IntArray) -> list[NDArray[np.object_]]:
        y, x = np.divmod(np.asarray(q, dtype=np.intp), self._shape[1])
        return [x.astype(object), y.astype(object)]
