"""``persistri.Delaunay``: the exact 2D Delaunay triangulation in scipy.spatial's shape.

A thin, immutable view of :func:`persistri.impl.terrain.scattered.delaunay`
(the incremental Delaunay triangulation of paper §5 on the persistent complex)
with the attributes of :class:`scipy.spatial.Delaunay` and an exact
``find_simplex`` (:mod:`persistri.impl.terrain.locate`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Generic, Literal, cast, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri._arrays import read_only, refuse_other_dimension
from persistri._scipy_options import (
    check_qhull_options, closed_error, delaunay_lifting, keeps_coplanar, lifted, lifted_planes, lifting_constants,
)
from persistri.impl.complex.adjacency import triangle_neighbors, vertex_neighbor_vertices, vertex_to_simplex
from persistri.impl.geometry.barycentric import barycentric_transforms
from persistri.impl.geometry.points import as_points
from persistri.impl.stats import Stats
from persistri.impl.terrain.delaunay_history import DelaunayHistory
from persistri.impl.terrain.locate import locate_points
from persistri.impl.terrain.scattered import DelaunayTriangulation, delaunay

if TYPE_CHECKING:
    from typing_extensions import TypeVar

    H = TypeVar("H", bound=DelaunayHistory | None, default=DelaunayHistory | None)
else:
    from typing import TypeVar

    H = TypeVar("H")  # its bound and default (PEP 696) matter to type checkers only

__all__ = ["Delaunay"]

IntcArray = NDArray[np.intc]
FloatArray = NDArray[np.float64]



class Delaunay(Generic[H]):
    """The exact Delaunay triangulation of 2D points (paper §5), in the shape of :class:`scipy.spatial.Delaunay`.

    ``Delaunay(points, furthest_site=False, incremental=False, qhull_options=None, *,
    backend="int_trie", seed=0, check=False, stats=None, history=False)``
    triangulates ``points`` (``(n, 2)`` reals), every decision exact, ties among
    cocircular points broken by Simulation of Simplicity
    (:func:`persistri.impl.terrain.scattered.delaunay` documents the arguments).
    Every distinct input point is a vertex — at coordinates where Qhull drops
    points (UTM eastings, centimetre spacing) too.

    Compared with scipy on the same points (code ported from it): in general
    position the triangles, ``neighbors``, ``vertex_neighbor_vertices`` and
    ``convex_hull`` are scipy's as sets (the order of triangles, and of the
    vertices within one, may differ), and ``find_simplex`` names the same
    triangle for a point inside one. Where four or more points are cocircular (a
    grid) more than one triangulation is Delaunay: persistri's ties and Qhull's
    are broken differently, so the diagonals, and the triangle ``find_simplex``
    names, may differ. Of exactly equal rows persistri keeps the
    first; Qhull keeps any one. A NaN or infinite query is a :class:`ValueError`
    (scipy answers -1).

    Attributes (arrays are read-only; index arrays are ``np.intc`` like scipy's):

    * ``points`` — ``(n, 2)`` float64, the input as validated;
    * ``simplices`` — ``(m, 3)`` triangles as input rows, counterclockwise;
    * ``neighbors`` — ``(m, 3)``: ``neighbors[i, j]`` is the triangle across the
      edge opposite ``simplices[i, j]``, -1 on the hull;
    * ``convex_hull`` — ``(h, 2)``: the hull's edges as input rows, in
      counterclockwise order around it (collinear hull points are vertices);
    * ``vertex_neighbor_vertices`` — ``(indptr, indices)``: the vertices joined to
      vertex ``k`` are ``indices[indptr[k]:indptr[k+1]]`` (sorted);
    * ``vertex_to_simplex`` — ``(n,)``: a triangle of each vertex, -1 for a merged row;
    * ``duplicates`` — ``(k, 2)``: ``[row, earlier equal row]`` for every input row
      merged into an earlier, exactly equal one;
    * ``coplanar`` — ``(k, 3)``: scipy's report of input points that are not
      vertices, ``[row, a triangle at its twin, the twin]``: here only the
      merged duplicates, and none when ``qhull_options`` are given without ``Qc``
      (as scipy's);
    * ``transform`` — ``(m, 3, 2)`` float64: each triangle's barycentric transform
      (within 2⁻⁴⁰ relative of the exact one, never NaN), and the lifting to the
      paraboloid: ``paraboloid_scale``, ``paraboloid_shift``, ``lift_points(x)``,
      ``equations`` (``(m, 4)``), ``plane_distance(xi)`` — float64 measurements,
      scipy's numbers up to rounding under the same ``qhull_options``, whose ``Qbb``
      and ``Qz`` set the lifting as they set scipy's (given options replace scipy's
      defaults: :mod:`persistri._scipy_options`); the exact decisions are
      ``find_simplex``'s.  Far out (coordinates near 1e154 and beyond, where
      ``|x|²`` exceeds the doubles and Qhull refuses the input) they are computed
      on the points scaled by a power of two, never with a numpy warning: finite
      under ``Qbb`` (scipy's default); without it the lifting ``|x|²`` itself is
      beyond the doubles, and ``lift_points`` gives ``inf``, ``equations`` finite
      but vertical planes (a normal's ``z`` is 0: the lifting is steeper than a
      double resolves), ``plane_distance`` ``±inf`` or NaN;
    * ``min_bound``, ``max_bound``, ``furthest_site`` (False), ``good`` (all ones, as
      scipy's without ``QG``), ``close()`` (ends incremental mode, else nothing to
      release), ``npoints``, ``ndim`` (2), ``nsimplex``, ``seed``, and ``result``,
      the full :class:`~persistri.impl.terrain.scattered.DelaunayTriangulation`.

    What persistence adds: ``add_points(points)`` returns a NEW triangulation of
    these points and the new ones, continuing this one's run and sharing its
    structure (this one stays exactly as it was), and ``history`` (with
    ``history=True``) holds every intermediate triangulation.  scipy's arguments
    are taken in scipy's positions (:mod:`persistri._scipy_options`):
    ``incremental=True`` makes ``add_points`` change this object, as scipy's
    does, until ``close()``; ``qhull_options`` that only tune Qhull's round-off
    are accepted, since nothing here rounds, ``Qbb`` and ``Qz`` set the lifting as
    in scipy, and others are a :class:`ValueError`; ``furthest_site=True`` is a
    :class:`NotImplementedError`.

    Errors, one line each: :class:`TypeError` / :class:`ValueError` for input that
    is not ``(n, 2)`` finite reals;
    :class:`~persistri.impl.terrain.errors.DegenerateInputError` (a ``ValueError``)
    for fewer than 3 distinct points or all on one line.  Expected O(n log n).

    >>> import numpy as np, persistri
    >>> tri = persistri.Delaunay([[0, 0], [2, 0], [0, 2], [2, 2], [3, 1]])
    >>> tri.simplices.tolist()
    [[0, 1, 2], [1, 3, 2], [1, 4, 3]]
    >>> tri.find_simplex([[0.5, 0.5], [1, 1], [2, 0], [-1, 0]]).tolist()    # interior, edge, vertex, outside
    [0, 0, 2, -1]
    """

    __slots__ = ("_tri", "_check", "_incremental", "_closed", "_points", "_simplices", "_neighbors", "_hull_edges", "_vnv", "_v2s", "_transform", "_equations", "_scaling", "_lift", "_qc")

    _tri: DelaunayTriangulation
    _check: bool
    _incremental: bool
    _closed: bool
    _points: FloatArray
    _simplices: IntcArray
    _neighbors: IntcArray
    _hull_edges: IntcArray
    _vnv: tuple[IntcArray, IntcArray] | None
    _v2s: IntcArray | None
    _transform: FloatArray | None
    _equations: FloatArray | None
    _scaling: tuple[float, float] | None
    _lift: tuple[bool, bool]  # (Qbb, Qz) of the qhull_options: scipy's lifting constants follow them
    _qc: bool  # Qc among the qhull_options (scipy's defaults): scipy's coplanar lists the merged rows only then

    @overload
    def __init__(
        self: Delaunay[DelaunayHistory], points: ArrayLike, furthest_site: bool = ..., incremental: bool = ...,
        qhull_options: str | None = ..., *, backend: str = ..., seed: int = ..., check: bool = ...,
        stats: Stats | None = ..., history: Literal[True],
    ) -> None: ...

    @overload
    def __init__(
        self: Delaunay[None], points: ArrayLike, furthest_site: bool = ..., incremental: bool = ...,
        qhull_options: str | None = ..., *, backend: str = ..., seed: int = ..., check: bool = ...,
        stats: Stats | None = ..., history: Literal[False] = ...,
    ) -> None: ...

    @overload
    def __init__(
        self: Delaunay[DelaunayHistory | None], points: ArrayLike, furthest_site: bool = ..., incremental: bool = ...,
        qhull_options: str | None = ..., *, backend: str = ..., seed: int = ..., check: bool = ...,
        stats: Stats | None = ..., history: bool,
    ) -> None: ...

    def __init__(
        self,
        points: ArrayLike,
        furthest_site: bool = False,
        incremental: bool = False,
        qhull_options: str | None = None,
        *,
        backend: str = "int_trie",
        seed: int = 0,
        check: bool = False,
        stats: Stats | None = None,
        history: bool = False,
    ) -> None:
        if furthest_site:
            raise NotImplementedError(
                "Delaunay: furthest_site=True is not implemented (persistri computes the nearest-site Delaunay "
                "triangulation, the lower hull of the lifted points)"
            )
        check_qhull_options(qhull_options, "Delaunay")
        self._lift = delaunay_lifting(qhull_options)
        self._qc = keeps_coplanar(qhull_options, "Delaunay")
        self._incremental = bool(incremental)
        self._closed = False
        refuse_other_dimension(points, "Delaunay")
        pts = as_points(points, 2, what="points")  # errors name the argument as the user passed it
        self._adopt(delaunay(pts, backend=backend, seed=seed, check=check, stats=stats, history=history), check)

    def _adopt(self, tri: DelaunayTriangulation, check: bool) -> None:
        self._tri = tri
        self._check = bool(check)
        self._points = read_only(tri.points)
        self._simplices = read_only(tri.triangles, np.intc)
        # The walks of find_simplex need the adjacency, so it is built up front.
        self._neighbors = read_only(triangle_neighbors(tri.triangles), np.intc)
        cycle = tri.hull
        self._hull_edges = read_only(np.stack([cycle, np.roll(cycle, -1)], axis=1), np.intc)
        self._vnv = None
        self._v2s = None
        self._transform = None
        self._equations = None
        self._scaling = None

    @classmethod
    def from_triangulation(cls, tri: DelaunayTriangulation) -> Delaunay[DelaunayHistory | None]:
        """The public view of a :class:`~persistri.impl.terrain.scattered.DelaunayTriangulation` already computed."""
        if not isinstance(tri, DelaunayTriangulation):
            raise TypeError(f"Delaunay.from_triangulation needs a persistri DelaunayTriangulation, not {type(tri).__name__}")
        return cls._from(tri, False, (True, True), True)

    def add_points(self, points: ArrayLike, restart: bool = False, *, check: bool | None = None) -> Delaunay[H]:
        """The triangulation of these points and ``points`` (``(k, 2)``): a NEW one, or, in incremental mode, this one.

        Made without ``incremental=True``, this triangulation is left exactly as it
        was and a new one is returned: it continues this one's run from its final
        version and shares its structure
        (:func:`~persistri.impl.terrain.extend_delaunay.extend_delaunay`).  Made with
        ``incremental=True`` (scipy's mode), this object moves to that new version
        and returns itself — as scipy's ``add_points`` changes its triangulation —
        until :meth:`close`; the old version is still there underneath (in
        ``history``, if kept).  Either way ``points`` are this one's rows followed
        by the new ones (row numbers keep their meaning), ``simplices`` exactly
        those of a triangulation of all the rows at once, and ``history``
        continues this one's when this one kept it.  ``restart=True`` (scipy's
        option) triangulates all the rows again from scratch instead of
        continuing: the same triangulation, a history of its own.  ``check``
        defaults to this one's.  Errors as for the constructor, about ``points``;
        :class:`RuntimeError` after :meth:`close` in incremental mode.  Expected
        O(n + k log(n + k)) (restart: O((n + k) log(n + k))).

        >>> import persistri
        >>> tri = persistri.Delaunay([[0, 0], [2, 0], [0, 2], [2, 2]])
        >>> more = tri.add_points([[1, 1]])
        >>> tri.nsimplex, more.nsimplex, more.npoints
        (2, 4, 5)
        >>> live = persistri.Delaunay([[0, 0], [2, 0], [0, 2], [2, 2]], incremental=True)   # scipy's mode
        >>> live.add_points([[1, 1]]) is live, live.nsimplex
        (True, 4)
        """
        if self._closed:
            raise closed_error("Delaunay")
        chk = self._check if check is None else check
        old = self._tri
        if restart:
            rows = np.concatenate([old.points, as_points(points, 2, what="new points")])
            new = delaunay(rows, backend=old.backend, seed=old.seed, check=chk, history=old.history is not None)
        else:
            from persistri.impl.terrain.extend_delaunay import extend_delaunay

            new = extend_delaunay(old, points, check=chk)
        if self._incremental:
            self._adopt(new, chk)
            return self
        return cast("Delaunay[H]", Delaunay._from(new, chk, self._lift, self._qc))  # the history is kept iff this one's is

    @classmethod
    def _from(
        cls, tri: DelaunayTriangulation, check: bool, lift: tuple[bool, bool], qc: bool,
    ) -> Delaunay[DelaunayHistory | None]:
        self = cast("Delaunay[DelaunayHistory | None]", cls.__new__(cls))
        self._lift = lift
        self._qc = qc
        self._incremental = False
        self._closed = False
        self._adopt(tri, check)
        return self

    @property
    def history(self) -> H:
        """Every intermediate triangulation, oldest first, sharing structure (``history=True``), else None (time travel).

        ``history.simplices(k)`` is the triangulation after ``k`` insertions past the
        first triangle, as input rows; ``history.inserted`` names the rows in the
        order they were inserted (:class:`~persistri.impl.terrain.delaunay_history.DelaunayHistory`).
        Typed ``DelaunayHistory`` for a triangulation made with ``history=True`` (and those
        :meth:`add_points` makes from it), None for one made without.
        """
        return cast(H, self._tri.history)  # the constructor's overloads tie H to its `history` argument

    def find_simplex(self, xi: ArrayLike, bruteforce: bool = False, tol: float | None = None) -> IntcArray:
        """For each point of ``xi`` (shape ``(..., 2)``), a triangle containing it, or -1 outside the hull.

        Exact: a point on an edge or a vertex is inside (one of the triangles
        there), a point outside the hull by the least representable amount is
        outside; no tolerance, unlike scipy's (:mod:`persistri.impl.terrain.locate`).
        The result has shape ``xi.shape[:-1]``, dtype ``np.intc``.  A NaN or
        infinite coordinate raises :class:`ValueError`.  Expected O(log n) per
        point (a k-d tree for the start, then a short exact walk).  scipy's
        ``bruteforce`` changes nothing here (every answer is exact already); its
        ``tol`` must be None or 0, the exact test (a :class:`ValueError` otherwise).
        """
        if tol is not None and tol != 0:
            raise ValueError(f"find_simplex: tol={tol!r}: persistri's test is exact (no tolerance); give tol=None or 0")
        flat, lead = self._query(xi, "xi")
        found = locate_points(self._tri.points, self._tri.triangles, self._neighbors, flat)
        out: IntcArray = found.astype(np.intc).reshape(lead)
        return out

    # -- scipy.spatial.Delaunay's attributes -----------------------------------------

    @property
    def points(self) -> FloatArray:
        """``(n, 2)`` float64: the input points as validated (read-only)."""
        return self._points

    @property
    def simplices(self) -> IntcArray:
        """``(m, 3)``: the triangles as input rows, counterclockwise (read-only)."""
        return self._simplices

    @property
    def neighbors(self) -> IntcArray:
        """``(m, 3)``: the triangle across the edge opposite ``simplices[i, j]``, -1 on the hull (read-only)."""
        return self._neighbors

    @property
    def convex_hull(self) -> IntcArray:
        """``(h, 2)``: the hull's edges as input rows, counterclockwise around it (read-only)."""
        return self._hull_edges

    @property
    def vertex_neighbor_vertices(self) -> tuple[IntcArray, IntcArray]:
        """``(indptr, indices)``: vertex ``k``'s neighbours are ``indices[indptr[k]:indptr[k+1]]``. O(m log m), once."""
        if self._vnv is None:
            indptr, indices = vertex_neighbor_vertices(self._tri.triangles, self.npoints)
            self._vnv = (read_only(indptr, np.intc), read_only(indices, np.intc))
        return self._vnv

    @property
    def vertex_to_simplex(self) -> IntcArray:
        """``(n,)``: a triangle having each input row as a vertex, -1 for a merged duplicate. O(m), once."""
        if self._v2s is None:
            self._v2s = read_only(vertex_to_simplex(self._tri.triangles, self.npoints), np.intc)
        return self._v2s

    @property
    def duplicates(self) -> IntcArray:
        """``(k, 2)``: ``[row, earlier equal row]`` for each input row merged into an exactly equal earlier one."""
        return read_only(np.array(self._tri.duplicates, dtype=np.intc).reshape(-1, 2))

    @property
    def coplanar(self) -> IntcArray:
        """``(k, 3)``: ``[row, triangle, vertex]`` for each input row that is not a vertex (merged duplicates only).

        As scipy's, empty when ``qhull_options`` are given without ``Qc`` (scipy's defaults hold it: Qhull
        keeps the points it leaves out only then).  O(k) once per call (after ``vertex_to_simplex``).
        """
        if not self._qc:
            return read_only(np.zeros((0, 3), dtype=np.intc))
        dup = np.array(self._tri.duplicates, dtype=np.intc).reshape(-1, 2)
        out = np.stack([dup[:, 0], self.vertex_to_simplex[dup[:, 1]], dup[:, 1]], axis=1).astype(np.intc)
        return read_only(out)

    @property
    def transform(self) -> FloatArray:
        """``(m, 3, 2)`` float64: ``[T⁻¹; r]`` per triangle, the barycentric coordinates of ``x`` being ``T⁻¹(x − r)``.

        As :attr:`scipy.spatial.Delaunay.transform`: ``T``'s columns are the first
        two vertices minus the third, ``r`` is the third.  Every entry within a
        relative 2⁻⁴⁰ of its exact value, thin triangles included (where scipy
        documents NaN for nearly degenerate ones). O(m) once, then cached (read-only).
        """
        if self._transform is None:
            self._transform = read_only(barycentric_transforms(self._points, self._simplices))
        return self._transform

    @property
    def paraboloid_scale(self) -> float:
        """The scale of the lifting ``scale·|x|² + shift``, scipy's under the same ``qhull_options``
        (:func:`~persistri._scipy_options.lifting_constants`: 1.0 without ``Qbb``)."""
        return self._lifting()[0]

    @property
    def paraboloid_shift(self) -> float:
        """The shift of the lifting ``scale·|x|² + shift``."""
        return self._lifting()[1]

    def lift_points(self, x: ArrayLike) -> FloatArray:
        """``x`` (shape ``(..., 2)``) lifted to the paraboloid, shape ``(..., 3)``, float64."""
        flat, lead = self._query(x, "x")
        return lifted(flat, *self._lifting()).reshape(lead + (3,))

    @property
    def equations(self) -> FloatArray:
        """``(m, 4)`` float64: each triangle's lifted plane, ``[unit normal (pointing down), offset]``. O(m) once."""
        if self._equations is None:
            scale, shift = self._lifting()
            self._equations = read_only(lifted_planes(self._points, self._simplices, scale, shift))
        return self._equations

    def plane_distance(self, xi: ArrayLike) -> FloatArray:
        """``(..., m)`` float64: the signed distance of each lifted point of ``xi`` from every triangle's plane.

        Positive below the plane (inside the triangle's circumcircle, up to
        float64 rounding), as scipy's. O(m) per point.
        """
        z = self.lift_points(xi)
        eq = self.equations
        with np.errstate(all="ignore"):  # |unit normal · z + offset| ≤ 3·max |z| + max |offset|: mostly no check
            bound = 3.0 * float(np.abs(z).max(initial=0.0)) + float(np.abs(eq[:, 3]).max(initial=0.0))
            out: FloatArray = z @ eq[:, :3].T + eq[:, 3]
            if not bound < 1e308 and not bool(np.isfinite(out).all()):  # sums beyond the doubles far out: again scaled by 2^-j, scaled back
                finite = np.abs(np.concatenate([z.ravel(), eq[:, 3]]))
                j = int(np.frexp(finite[np.isfinite(finite)].max(initial=1.0))[1])
                again = np.ldexp(np.ldexp(z, -j) @ eq[:, :3].T + np.ldexp(eq[:, 3], -j), j)
                out = np.where(np.isfinite(out), out, again)  # inf or NaN where the lifting is (class docstring)
        return out

    @property
    def good(self) -> IntcArray:
        """``(m,)`` ones: scipy's marks every simplex good (1) when no ``QG`` option is given (persistri refuses
        ``QGn``: it computes no visibility from a point)."""
        return read_only(np.ones(self.nsimplex, dtype=np.intc))

    @property
    def min_bound(self) -> FloatArray:
        """``(2,)`` float64: the least coordinates of the input points."""
        return read_only(self._points.min(axis=0))

    @property
    def max_bound(self) -> FloatArray:
        """``(2,)`` float64: the greatest coordinates of the input points."""
        return read_only(self._points.max(axis=0))

    @property
    def furthest_site(self) -> bool:
        """False: this is the Delaunay triangulation, not the furthest-site one."""
        return False

    def close(self) -> None:
        """End incremental mode (``incremental=True``: :meth:`add_points` then raises, as scipy's); otherwise nothing
        to do (the triangulation holds no resources, and :meth:`add_points` goes on returning new ones). O(1)."""
        if self._incremental:
            self._closed = True

    def _lifting(self) -> tuple[float, float]:
        """``(paraboloid_scale, paraboloid_shift)``, over the input points, as scipy's under these options. O(n) once."""
        if self._scaling is None:
            self._scaling = lifting_constants(self._points, *self._lift)
        return self._scaling

    def _query(self, x: ArrayLike, name: str) -> tuple[FloatArray, tuple[int, ...]]:
        """``x`` (shape ``(..., 2)``) as validated ``(k, 2)`` float64 rows (:func:`~persistri.impl.geometry.points.as_points`:
        real, finite, exact) and its leading shape ``...``, or one clear error naming ``name``."""
        if isinstance(x, (str, bytes)):
            raise TypeError(f"{name} must be an array of 2D points, not {type(x).__name__}")
        try:
            raw = np.asarray(x)
        except (ValueError, TypeError) as exc:
            raise ValueError(f"{name} must be a rectangular array of 2D points: {exc}") from None
        if raw.ndim == 0 or raw.shape[-1] != 2:
            raise ValueError(f"{name} must be an array of 2D points, shape (..., 2), got shape {raw.shape}")
        return as_points(raw.reshape(-1, 2), 2, what=name), raw.shape[:-1]

    @property
    def npoints(self) -> int:
        """The number of input rows (duplicates included)."""
        return int(self._points.shape[0])

    @property
    def ndim(self) -> int:
        """2."""
        return 2

    @property
    def nsimplex(self) -> int:
        """The number of triangles."""
        return int(self._simplices.shape[0])

    @property
    def seed(self) -> int:
        """The seed of the insertion order (the triangulation does not depend on it where it is unique)."""
        return self._tri.seed

    @property
    def result(self) -> DelaunayTriangulation:
        """The full result of :func:`persistri.delaunay`: the persistent complex, its structure, counts."""
        return self._tri

    def __repr__(self) -> str:
        kept = "" if self._tri.history is None else f", history of {len(self._tri.history)} versions"
        n, e = self.nsimplex, self._hull_edges.shape[0]
        return f"persistri.Delaunay({self.npoints} points, {n} triangle{'' if n == 1 else 's'}, {e} hull edges{kept})"
