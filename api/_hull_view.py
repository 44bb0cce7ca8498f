"""The attributes of ``persistri.ConvexHull``: scipy.spatial's, and what persistence adds.

:class:`HullView` reads a computed :class:`~persistri.impl.hull.api.Hull` (or a
chunked run's :class:`~persistri.impl.scale.hull.ParallelHull`) in the shape of
:class:`scipy.spatial.ConvexHull` — read-only ``np.intc`` index arrays, the
measures computed on first access (:mod:`persistri.impl.hull.measures`) — and
adds ``history``, ``result``, ``chunked``.  :class:`persistri.ConvexHull`
(:mod:`persistri._hull`) is this view plus its construction and ``add_points``;
the attributes are documented there, each one's cost here.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Generic, cast

import numpy as np
from numpy.typing import NDArray

from persistri._arrays import coplanar_report, read_only
from persistri._hull_chunked import read_all, whole_input_history
from persistri.impl.complex.adjacency import triangle_neighbors
from persistri.impl.hull.api import Hull, HullHistory
from persistri.impl.hull.measures import enclosed_volume, equations_of, facet_normals, half_sum

if TYPE_CHECKING:
    from typing_extensions import TypeVar

    from persistri.impl.scale.hull import ParallelHull

    H = TypeVar("H", bound=HullHistory | None, default=HullHistory | None)
else:
    from typing import TypeVar

    H = TypeVar("H")  # its bound and default (PEP 696) matter to type checkers only

__all__ = ["HullView", "H"]

IntcArray = NDArray[np.intc]
FloatArray = NDArray[np.float64]


class HullView(Generic[H]):
    """The attributes of a computed hull in :class:`scipy.spatial.ConvexHull`'s shape (:class:`persistri.ConvexHull`'s).

    Immutable but for :meth:`_adopt`, which :class:`persistri.ConvexHull` calls as it is made
    (and, in incremental mode, as it moves to a new hull).  ``H`` is the history's type:
    :class:`~persistri.impl.hull.api.HullHistory` or None.
    """

    __slots__ = (
        "_hull", "_check", "_n", "_points", "_simplices", "_vertices", "_neighbors", "_facets", "_equations", "_area",
        "_volume", "_chunked", "_mpoints", "_msimplices", "_history", "_incremental", "_closed", "_qc",
    )

    _hull: Hull
    _check: bool
    _n: int
    _points: FloatArray | None
    _simplices: IntcArray
    _vertices: IntcArray
    _neighbors: IntcArray | None
    _facets: tuple[FloatArray, FloatArray] | None
    _equations: FloatArray | None
    _area: float | None
    _volume: float | None
    _chunked: ParallelHull | None
    _mpoints: FloatArray  # the coordinates the measures read: all points, or only the vertices (chunked)
    _msimplices: NDArray[np.intp]  # the triangles as rows of _mpoints, in the order of `simplices`
    _history: HullHistory | None
    _incremental: bool
    _closed: bool
    _qc: bool  # Qc among the qhull_options (scipy's coplanar lists the merged duplicates only then)
    def _reset(self, hull: Hull, check: bool) -> None:
        self._hull = hull
        self._check = check
        self._neighbors = None
        self._facets = None
        self._equations = None
        self._area = None
        self._volume = None

    def _adopt(self, hull: Hull, check: bool) -> None:
        self._reset(hull, check)
        self._chunked = None
        self._points = read_only(hull.points)
        self._n = int(hull.points.shape[0])
        self._simplices = read_only(hull.simplices, np.intc)
        self._vertices = read_only(hull.vertices, np.intc)
        self._mpoints = hull.points
        self._msimplices = hull.simplices
        self._history = hull.history

    def _adopt_chunked(self, result: ParallelHull, check: bool) -> None:
        self._reset(result.hull, check)
        self._chunked = result
        self._points = None  # read on first access: the input may not fit in memory
        self._n = result.n
        self._simplices = read_only(result.simplices, np.intc)
        self._vertices = read_only(result.vertices, np.intc)
        self._mpoints = read_only(result.vertex_points)
        self._msimplices = np.searchsorted(result.vertices, result.simplices).astype(np.intp)
        self._history = whole_input_history(result)
    # -- scipy.spatial.ConvexHull's attributes ---------------------------------------

    @property
    def points(self) -> FloatArray:
        """``(n, 3)`` float64: the input points as validated (read-only).

        For chunked input, read on first access: a float64 ``.npy`` file memory-mapped (nothing
        loaded), any other input loaded whole (O(n) memory: :attr:`vertex_points` may be all you need).
        """
        if self._points is None:
            assert self._chunked is not None
            self._points = read_all(self._chunked.source)
        return self._points

    @property
    def vertex_points(self) -> FloatArray:
        """``(len(vertices), 3)`` float64: the coordinates of :attr:`vertices`, in their order (read-only).

        ``points[vertices]``, without reading the other points (for chunked input: only these are in memory).
        """
        if self._chunked is not None:
            return self._mpoints
        return read_only(self._hull.points[self._hull.vertices])

    @property
    def simplices(self) -> IntcArray:
        """``(m, 3)``: each triangle as input rows, outward by the right-hand rule (read-only)."""
        return self._simplices

    @property
    def vertices(self) -> IntcArray:
        """The input rows that are hull vertices, sorted (read-only)."""
        return self._vertices

    @property
    def neighbors(self) -> IntcArray:
        """``(m, 3)``: ``neighbors[i, j]`` is the triangle across the edge opposite ``simplices[i, j]``. O(m log m), once."""
        if self._neighbors is None:
            self._neighbors = read_only(triangle_neighbors(self._msimplices), np.intc)
        return self._neighbors

    @property
    def equations(self) -> FloatArray:
        """``(m, 4)``: outward unit normal and offset per triangle; ``normal·x + offset <= 0`` inside. O(m), once."""
        if self._equations is None:
            normals, _ = self._normals()
            self._equations = read_only(equations_of(self._mpoints, self._msimplices, normals))
        return self._equations

    def _normals(self) -> tuple[FloatArray, FloatArray]:
        """The facets' unit normals and cross-product lengths (:func:`~persistri.impl.hull.measures.facet_normals`), once."""
        if self._facets is None:
            self._facets = facet_normals(self._mpoints, self._msimplices)
        return self._facets

    @property
    def area(self) -> float:
        """The surface area of the hull. O(m), once."""
        if self._area is None:
            _, lengths = self._normals()
            self._area = half_sum(lengths)
        return self._area

    @property
    def volume(self) -> float:
        """The volume of the hull, computed exactly and rounded once to a double. O(m) big-integer work, once."""
        if self._volume is None:
            self._volume = enclosed_volume(self._mpoints, self._msimplices)
        return self._volume

    @property
    def duplicates(self) -> IntcArray:
        """``(k, 2)``: ``[row, earlier equal row]`` for each input row merged into an exactly equal earlier one."""
        pairs = self._hull.duplicates if self._chunked is None else self._chunked.duplicates
        return read_only(np.array(pairs, dtype=np.intc).reshape(-1, 2))

    @property
    def coplanar(self) -> IntcArray:
        """``(k, 3)``: scipy's report of input points that are not vertices, ``[row, a triangle at its twin, the twin]``.

        As scipy's, empty unless ``qhull_options`` holds ``Qc`` (Qhull keeps the points it leaves out
        only then; scipy's ``ConvexHull`` defaults lack it).  With ``Qc``, the merged duplicates of
        vertices (:attr:`duplicates`), where scipy lists those too; Qhull also lists the points lying
        on a flat facet that it did not take as vertices, which persistri does not (such points are
        decided by the perturbation: those moved out are vertices, docs/exactness.md).  O(n + m) once per call.
        """
        if not self._qc:
            return read_only(np.zeros((0, 3), dtype=np.intc))
        return coplanar_report(self._hull.duplicates if self._chunked is None else self._chunked.duplicates, self._simplices, self._n)

    @property
    def good(self) -> None:
        """None, as scipy's without a ``QG`` option (persistri computes no good facets: ``QGn`` is refused)."""
        return None

    @property
    def min_bound(self) -> FloatArray:
        """``(3,)`` float64: the least coordinates of the input, attained at hull vertices. O(h)."""
        return read_only(self.vertex_points.min(axis=0))

    @property
    def max_bound(self) -> FloatArray:
        """``(3,)`` float64: the greatest coordinates of the input, attained at hull vertices. O(h)."""
        return read_only(self.vertex_points.max(axis=0))
    @property
    def npoints(self) -> int:
        """The number of input rows (duplicates included)."""
        return self._n

    @property
    def ndim(self) -> int:
        """3."""
        return 3

    @property
    def nsimplex(self) -> int:
        """The number of triangles."""
        return int(self._simplices.shape[0])

    # -- what persistri adds ---------------------------------------------------------

    @property
    def history(self) -> H:
        """Every intermediate hull, oldest first, sharing structure (``history=True``), else None (time travel).

        For chunked input, the versions of the final merge (the hulls of growing sets of candidates,
        the last one this hull), with ``history.simplices(k)`` and ``inserted`` as rows of the whole input.
        Typed :class:`~persistri.impl.hull.api.HullHistory` for a hull made with ``history=True``
        (and the hulls :meth:`add_points` makes from it), None for one made without.
        """
        return cast(H, self._history)  # the constructor's overloads tie H to its `history` argument

    @property
    def backend(self) -> str:
        """The ``ORD_MAP`` backend of the hull's persistent complex."""
        return self._hull.backend

    @property
    def seed(self) -> int:
        """The seed of the random insertion order."""
        return self._hull.seed

    @property
    def result(self) -> Hull:
        """The full result of :func:`persistri.convex_hull`: the persistent complex, its structure, counts.

        For chunked input, the final merge's (its ``points`` are the candidates, input rows ``chunked.rows``).
        """
        return self._hull

    @property
    def chunked(self) -> ParallelHull | None:
        """How a chunked input was hulled (:class:`~persistri.impl.scale.hull.ParallelHull`: chunks, merges,
        workers, candidates), else None."""
        return self._chunked

    def __repr__(self) -> str:
        kept = "" if self._history is None else f", history of {len(self._history)} versions"
        if self._chunked is not None:
            k = len(self._chunked.chunks)
            kept += f", {k} chunk{'' if k == 1 else 's'} of {self._chunked.source.name}"
        return (
            f"persistri.ConvexHull({self.npoints} points, {self.nsimplex} triangles, "
            f"{self._vertices.size} vertices, backend={self.backend!r}{kept})"
        )
