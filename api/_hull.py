"""``persistri.ConvexHull``: the exact 3D convex hull in scipy.spatial's shape, every version kept.

A thin, immutable view of :func:`persistri.impl.hull.api.convex_hull` (the
bulldozer, paper §3 and Appendix A) with the attributes of
:class:`scipy.spatial.ConvexHull`, plus what persistence adds: ``history`` (every
intermediate hull, sharing structure) and :meth:`ConvexHull.add_points`, which
returns a *new* hull and leaves this one as it was.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri._arrays import read_only
from persistri.impl.complex.adjacency import triangle_neighbors
from persistri.impl.hull.api import Hull, HullHistory, convex_hull
from persistri.impl.hull.measures import enclosed_volume, equations_of, facet_normals
from persistri.impl.stats import Stats

__all__ = ["ConvexHull"]

IntcArray = NDArray[np.intc]
FloatArray = NDArray[np.float64]



class ConvexHull:
    """The exact convex hull of 3D points (paper §3), in the shape of :class:`scipy.spatial.ConvexHull`.

    ``ConvexHull(points, *, backend="red_black", history=False, seed=0, check=False,
    stats=None, progress=False)`` computes the hull of ``points`` (``(n, 3)``
    reals) by the bulldozer, every decision exact
    (:func:`persistri.impl.hull.api.convex_hull` documents the arguments).

    Attributes (arrays are read-only; index arrays are ``np.intc`` like scipy's):

    * ``points`` — ``(n, 3)`` float64, the input as validated;
    * ``simplices`` — ``(m, 3)`` the triangles as input rows, each **outward** by
      the right-hand rule (scipy's are unoriented), rotated to start at its
      smallest row, rows sorted;
    * ``vertices`` — the input rows that are hull vertices, sorted (scipy's order
      in 3D); every extreme point is one, and of exactly equal rows only the first;
    * ``neighbors`` — ``(m, 3)``: ``neighbors[i, j]`` is the triangle across the
      edge opposite ``simplices[i, j]`` (never -1: the hull is closed);
    * ``equations`` — ``(m, 4)``: ``[normal, offset]``, the outward unit normal and
      ``offset = −normal·a``, so ``normal·x + offset <= 0`` inside (scipy's
      convention), from the exact hull (:mod:`persistri.impl.hull.measures`);
    * ``area``, ``volume`` — the surface area, and the enclosed volume computed
      exactly and rounded once;
    * ``duplicates`` — ``(k, 2)``: ``[row, earlier equal row]`` for every input row
      merged into an earlier, exactly equal one;
    * ``history`` — every intermediate hull (:class:`~persistri.impl.hull.api.HullHistory`)
      with ``history=True``, else None;
    * ``npoints``, ``ndim`` (3), ``nsimplex``, ``backend``, ``seed``, and ``result``,
      the full :class:`~persistri.impl.hull.api.Hull` (its persistent complex,
      the structure that reads it, counts).

    Errors are the deep API's, one line each: :class:`TypeError` /
    :class:`ValueError` for input that is not ``(n, 3)`` finite reals,
    :class:`~persistri.impl.hull.errors.DegenerateInputError` (a ``ValueError``)
    when the distinct points do not span space.  Expected O(n lg n) time.

    >>> import numpy as np, persistri
    >>> cube = np.array([[x, y, z] for x in (0, 2) for y in (0, 2) for z in (0, 2)], dtype=float)
    >>> hull = persistri.ConvexHull(cube)
    >>> hull.vertices.tolist(), hull.nsimplex, hull.volume, hull.area
    ([0, 1, 2, 3, 4, 5, 6, 7], 12, 8.0, 24.0)
    >>> bigger = hull.add_points([[1.0, 1.0, 5.0]])    # a new hull; the old one is unchanged
    >>> bigger.volume, hull.volume
    (12.0, 8.0)
    """

    __slots__ = (
        "_hull", "_check", "_points", "_simplices", "_vertices", "_neighbors", "_facets", "_equations", "_area", "_volume"
    )

    _hull: Hull
    _check: bool
    _points: FloatArray
    _simplices: IntcArray
    _vertices: IntcArray
    _neighbors: IntcArray | None
    _facets: tuple[FloatArray, FloatArray] | None
    _equations: FloatArray | None
    _area: float | None
    _volume: float | None

    def __init__(
        self,
        points: ArrayLike,
        *,
        backend: str = "red_black",
        history: bool = False,
        seed: int = 0,
        check: bool = False,
        stats: Stats | None = None,
        progress: bool | Callable[[int], Any] = False,
    ) -> None:
        hull = convex_hull(points, backend=backend, history=history, seed=seed, check=check, stats=stats, progress=progress)
        self._adopt(hull, check)

    def _adopt(self, hull: Hull, check: bool) -> None:
        self._hull = hull
        self._check = check
        self._points = read_only(hull.points)
        self._simplices = read_only(hull.simplices, np.intc)
        self._vertices = read_only(hull.vertices, np.intc)
        self._neighbors = None
        self._facets = None
        self._equations = None
        self._area = None
        self._volume = None

    @classmethod
    def from_hull(cls, hull: Hull, *, check: bool = False) -> ConvexHull:
        """The public view of a :class:`~persistri.impl.hull.api.Hull` already computed (no work is redone).

        ``check`` is what :meth:`add_points` does by default.  O(m) (the index arrays' conversion).
        """
        if not isinstance(hull, Hull):
            raise TypeError(f"ConvexHull.from_hull needs a persistri Hull, not {type(hull).__name__}")
        self = cls.__new__(cls)
        self._adopt(hull, check)
        return self

    # -- persistence ------------------------------------------------------------------

    def add_points(
        self, points: ArrayLike, *, check: bool | None = None, progress: bool | Callable[[int], Any] = False
    ) -> ConvexHull:
        """A NEW hull of these points and ``points`` (``(k, 3)``); this hull is left exactly as it was.

        Unlike scipy's ``add_points`` (which changes the hull in place), the new
        hull shares its structure with this one: the bulldozer resumes from this
        hull's final version (:func:`persistri.impl.hull.extend.extend_hull`), so
        its ``points`` are this hull's rows followed by the new ones (row numbers
        keep their meaning), and its ``history`` continues this one's when this
        one kept it.  ``check`` defaults to this hull's.  Errors as for the
        constructor, about ``points``.
        """
        from persistri.impl.hull.extend import extend_hull

        chk = self._check if check is None else check
        return ConvexHull.from_hull(extend_hull(self._hull, points, check=chk, progress=progress), check=chk)

    # -- scipy.spatial.ConvexHull's attributes ---------------------------------------

    @property
    def points(self) -> FloatArray:
        """``(n, 3)`` float64: the input points as validated (read-only)."""
        return self._points

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
            self._neighbors = read_only(triangle_neighbors(self._hull.simplices), np.intc)
        return self._neighbors

    @property
    def equations(self) -> FloatArray:
        """``(m, 4)``: outward unit normal and offset per triangle; ``normal·x + offset <= 0`` inside. O(m), once."""
        if self._equations is None:
            normals, _ = self._normals()
            self._equations = read_only(equations_of(self._hull.points, self._hull.simplices, normals))
        return self._equations

    def _normals(self) -> tuple[FloatArray, FloatArray]:
        """The facets' unit normals and cross-product lengths (:func:`~persistri.impl.hull.measures.facet_normals`), once."""
        if self._facets is None:
            self._facets = facet_normals(self._hull.points, self._hull.simplices)
        return self._facets

    @property
    def area(self) -> float:
        """The surface area of the hull. O(m), once."""
        if self._area is None:
            _, lengths = self._normals()
            self._area = math.fsum(lengths.tolist()) / 2
        return self._area

    @property
    def volume(self) -> float:
        """The volume of the hull, computed exactly and rounded once to a double. O(m) big-integer work, once."""
        if self._volume is None:
            self._volume = enclosed_volume(self._hull.points, self._hull.simplices)
        return self._volume

    @property
    def duplicates(self) -> IntcArray:
        """``(k, 2)``: ``[row, earlier equal row]`` for each input row merged into an exactly equal earlier one."""
        return read_only(np.array(self._hull.duplicates, dtype=np.intc).reshape(-1, 2))

    @property
    def npoints(self) -> int:
        """The number of input rows (duplicates included)."""
        return int(self._points.shape[0])

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
    def history(self) -> HullHistory | None:
        """Every intermediate hull, oldest first, sharing structure (``history=True``), else None (time travel)."""
        return self._hull.history

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
        """The full result of :func:`persistri.convex_hull`: the persistent complex, its structure, counts."""
        return self._hull

    def __repr__(self) -> str:
        kept = "" if self._hull.history is None else f", history of {len(self._hull.history)} versions"
        return (
            f"persistri.ConvexHull({self.npoints} points, {self.nsimplex} triangles, "
            f"{self._vertices.size} vertices, backend={self.backend!r}{kept})"
        )
