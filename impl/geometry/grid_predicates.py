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

**Labels.**  By default point ``i`` is grid sample ``i`` (row-major).  With
``labels="zorder"`` point ``i`` is the sample whose z-order label
(:class:`~persistri.impl.geometry.grid_labels.GridZOrder`) is ``i``: a triangulator
that labels its vertices so gets the locality of the complex's keys
(:mod:`~persistri.impl.geometry.grid_labels` says what it gained and cost when greedy
insertion was tried with it; greedy insertion keeps the default).  The points are then
indexed by label (``len`` is the label space's size, with holes: the labels of no
sample are not valid points), the samples' own coordinates are still read by grid
index (:meth:`GridPredicates2.grid_coordinates`), and Simulation of Simplicity ranks
the points by *grid index*, as the default labels do: every sign, ties included, is
the one the row-major predicates give for the same samples (``_sos2`` and
``_sos_incircle`` map the labels to grid indices, and the 2D kernel defers its
exact-zero shortcut to them: ``_sos_rank`` is set).
"""

from __future__ import annotations

import operator
from typing import Any

import numpy as np
from numpy.typing import NDArray

from persistri.impl.geometry.exact import IntegerScale
from persistri.impl.geometry.grid_labels import GridZOrder
from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.geometry.sos import sort_with_parity, sos_orient2d, sos_orient3d
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

    __slots__ = ("cols", "n", "floats", "zorder")

    def __init__(self, cols: int, n: int, zorder: GridZOrder | None = None) -> None:
        super().__init__()
        self.cols = cols
        self.n = n
        self.floats: dict[int, float] = {}
        # With z-order labels, the point of label i is decoded from it (and i must be a sample's label).
        self.zorder = zorder

    def put(self, i: int, x: int, y: int) -> tuple[float, ...]:
        """Make and keep point ``i``'s row ``(x, y)`` (the caller knows its coordinates); the row. O(1)."""
        floats = self.floats
        fx = floats.get(x)
        if fx is None:
            fx = floats[x] = float(x)
        fy = floats.get(y)
        if fy is None:
            fy = floats[y] = float(y)
        row = (fx, fy)
        self[i] = row
        return row

    def __missing__(self, i: int) -> tuple[float, ...]:
        # As a list of rows would: any integer (bool included), IndexError out of range, TypeError otherwise.
        try:
            k = operator.index(i)
        except TypeError:
            raise TypeError(f"point indices must be integers, got {i!r}") from None
        if not 0 <= k < self.n:
            raise IndexError(f"point index {k} out of range for {self.n} points")
        z = self.zorder
        if z is None:
            y, x = divmod(k, self.cols)
        else:
            x, y = z.decode(k)
            if x >= z.shape[1] or y >= z.shape[0]:
                raise IndexError(f"point index {k} is the z-order label of no sample of a {z.shape} grid")
        # Kept under i itself when it is an int (a Vertex: the one object the mesh holds anyway); equal keys
        # hash alike, so a later look-up by k, by i or by another equal int finds the row.
        return self.put(i if isinstance(i, int) else k, x, y)


class GridPredicates2(Predicates2):
    """Exact ``orient2d`` and ``incircle`` over the points ``(col, row)`` of a ``rows × cols`` grid, by point index.

    ``GridPredicates2((rows, cols), stats=None, labels="rows")``: O(1) to build (O(rows + cols) with
    ``labels="zorder"``), O(1) memory per point tested.  The same methods, signs, counting and errors as
    :class:`~persistri.impl.geometry.predicates.Predicates2` built over
    ``grid_points((rows, cols))`` (point ``i`` is ``(i mod cols, i div cols)``); with
    ``labels="zorder"`` point ``i`` is the sample of z-order label ``i`` and every sign is the one of
    its grid index (module docstring).  :class:`ValueError` for a shape that is not two integers in
    ``[1, GRID_LIMIT]`` or for other labels.
    """

    __slots__ = ("_shape", "_columns", "zorder", "row_table")

    _shape: tuple[int, int]
    _columns: tuple[NDArray[Any], NDArray[Any]] | None
    zorder: GridZOrder | None
    """The z-order labels of the points (``labels="zorder"``), or None (point ``i`` is grid sample ``i``)."""
    row_table: dict[int, tuple[float, ...]]
    """The table of rows: ``row_table[i]`` is point ``i``'s ``(x, y)`` as floats, made on first use and kept (a
    dict, an attribute: compiled callers read a vertex's coordinates from it without a Python call each)."""

    def __init__(self, shape: tuple[int, int], *, stats: Stats | None = None, labels: str = "rows") -> None:
        rows, cols = shape
        for v in (rows, cols):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 1 <= v <= GRID_LIMIT:
                raise ValueError(f"a grid's shape is two integers from 1 to {GRID_LIMIT}, got {shape!r}")
        if labels not in ("rows", "zorder"):
            raise ValueError(f"labels must be 'rows' or 'zorder', got {labels!r}")
        rows, cols = int(rows), int(cols)
        zorder = GridZOrder((rows, cols)) if labels == "zorder" else None
        n = rows * cols if zorder is None else zorder.size
        self._shape = (rows, cols)
        self._columns = None
        self.zorder = zorder
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
        self._rows = self.row_table = _GridRows(cols, n, zorder)
        top = max(rows, cols) - 1
        # Integer coordinates: grain 0 (the least over the nonzero ones is that of an odd number), magnitude < 2^25.
        self._span = (0, top.bit_length()) if top > 0 else None
        self._shift = 0  # every grain is >= 0 >= GRAIN_MIN and every magnitude <= 25 <= TOP_MAX: no scaling needed
        self._uniform = True
        self._grain = None
        self._scale = IntegerScale(0, 0)
        self._ints = {}
        # Simulation of Simplicity in index order; with z-order labels in grid-index order, by this class's own
        # _sos2 and _sos_incircle (the kernel defers its exact-zero shortcut to them when _sos_rank is set:
        # the empty list says "ranked otherwise than by index"; nothing reads it here).
        self._sos_rank = None if zorder is None else []

    def __repr__(self) -> str:
        extra = "" if self.zorder is None else ", labels='zorder'"
        return f"GridPredicates2(shape={self._shape}{extra})"

    @property
    def shape(self) -> tuple[int, int]:
        """The grid's ``(rows, cols)``."""
        return self._shape

    @property
    def points(self) -> NDArray[np.float64]:
        """The ``(n, 2)`` array of the points, ``(col, row)`` in index order: made on each call. O(n).

        With z-order labels, row ``i`` is the point of label ``i`` (a hole's, outside the grid, included)."""
        rows, cols = self._shape
        xy = np.empty((self._n, 2), dtype=np.float64)
        if self.zorder is not None:
            x, y = self.zorder.decode_many(np.arange(self._n, dtype=np.int64))
            xy[:, 0], xy[:, 1] = x, y
        else:
            xy[:, 0] = np.tile(np.arange(cols, dtype=np.float64), rows)
            xy[:, 1] = np.repeat(np.arange(rows, dtype=np.float64), cols)
        xy.setflags(write=False)
        return xy

    def coordinate_columns(self) -> tuple[NDArray[Any], NDArray[Any]]:
        """The ``x`` and ``y`` of every grid sample, by grid index, as two read-only columns of small integers
        (``uint16`` up to 65,536 rows and columns, ``int32`` beyond): 4 bytes per sample, made on the first call
        (gathering from them is three times faster than dividing the indices).  O(n) once."""
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

    def grid_coordinates(self, q: NDArray[np.signedinteger[Any]]) -> tuple[NDArray[Any], NDArray[Any]]:
        """``(x, y)`` of grid samples ``q`` (row-major indices, whatever the labels): ``(q mod cols, q div cols)``,
        as integers of ``q``'s dtype. O(len(q)).

        Divided, not gathered from :meth:`coordinate_columns`: the columns would take 4 bytes a sample
        (16 MB on a 2,048² grid) for the terrain's sector tests and errors, and for ``int32`` sample
        lists one ``divmod`` costs less than two gathers, which convert the indices to ``intp`` first."""
        y, x = np.divmod(q, self._shape[1])
        return x, y

    def coordinates(self, q: NDArray[np.signedinteger[Any]]) -> tuple[NDArray[Any], NDArray[Any]]:
        """``(x, y)`` of points ``q`` (indices: grid indices, or labels with ``labels="zorder"``), as integers.
        O(len(q))."""
        z = self.zorder
        if z is None:
            y, x = np.divmod(q, self._shape[1])  # grid_coordinates, written out (the terrain's hot path)
            return x, y
        return z.decode_many(q)

    def label(self, q: int) -> int:
        """The point index of grid sample ``q``: ``q`` itself, or its z-order label (whose row of floats is made
        now: the caller is about to test it). O(1)."""
        z = self.zorder
        if z is None:
            return q
        y, x = divmod(q, self._shape[1])
        i = z.spread_x[x] | z.spread_y[y]
        rows = self._rows
        assert isinstance(rows, _GridRows)
        if i not in rows:
            rows.put(i, x, y)
        out: int = i
        return out

    def labels(self, q: NDArray[np.integer[Any]]) -> NDArray[np.intp]:
        """The point indices of grid samples ``q`` (an array). O(len(q))."""
        z = self.zorder
        out: NDArray[np.intp] = np.asarray(q, dtype=np.intp) if z is None else z.labels(q).astype(np.intp)
        return out

    def grid_index(self, i: int) -> int:
        """The row-major grid index of point ``i`` (``i`` itself with the default labels). O(1)."""
        if self.zorder is None:
            return int(i)
        x, y = self._rows[i]
        return int(y) * self._shape[1] + int(x)

    def grid_indices(self, i: NDArray[np.integer[Any]]) -> NDArray[np.intp]:
        """The row-major grid indices of points ``i`` (an array). O(len(i))."""
        z = self.zorder
        out: NDArray[np.intp] = np.asarray(i, dtype=np.intp) if z is None else z.grid_indices(i).astype(np.intp)
        return out

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
        if self.zorder is None:
            y, x = divmod(int(i), self._shape[1])
            return (x, y)
        fx, fy = self._rows[i]
        return (int(fx), int(fy))

    def _int_columns(self, q: IntArray) -> list[NDArray[np.object_]]:
        x, y = self.coordinates(np.asarray(q, dtype=np.intp))
        return [x.astype(object), y.astype(object)]

    # -- Simulation of Simplicity by grid index (z-order labels) ---------------------------

    def _sos2(self, a: int, b: int, c: int) -> int:
        if self.zorder is None:
            return super()._sos2(a, b, c)
        # The row-major predicates' SoS of the same samples: their grid indices sorted, the points in that order.
        g = self.grid_index
        order, parity = sort_with_parity((g(a), g(b), g(c)))
        cols = self._shape[1]
        return parity * sos_orient2d(*((q % cols, q // cols) for q in order))

    def _sos_incircle(self, a: int, b: int, c: int, d: int) -> int:
        if self.zorder is None:
            return super()._sos_incircle(a, b, c, d)
        rows = self._rows
        cols = self._shape[1]
        ga, gb, gc, gd = ((int(y) * cols + int(x)) for x, y in (rows[a], rows[b], rows[c], rows[d]))
        order, parity = sort_with_parity((ga, gb, gc, gd))
        # The first term of the Λ4 sequence — orient2d of the three points of largest index — decides most
        # cocircular grid quadruples (the 2D kernel's shortcut for the default labels, the same sign).
        _, i1, i2, i3 = order
        py, px = divmod(i1, cols)
        qy, qx = divmod(i2, cols)
        ry, rx = divmod(i3, cols)
        first = (px - rx) * (qy - ry) - (py - ry) * (qx - rx)
        if first:
            return parity * (1 if first > 0 else -1)
        lifted = []
        for q in order:
            y, x = divmod(q, cols)
            lifted.append((x, y, x * x + y * y))
        return parity * sos_orient3d(*lifted)
