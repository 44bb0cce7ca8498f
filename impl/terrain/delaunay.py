"""Incremental Delaunay triangulation on the persistent 2-complex (paper §5, Bowyer–Watson through the lifting map).

A :class:`Triangulator` keeps a Delaunay triangulation of some of the points of
a :class:`~persistri.impl.geometry.predicates.Predicates2` as a *closed* surface
in a :class:`~persistri.impl.complex.two_complex.TwoComplex`: the finite
triangles, counterclockwise, plus one **ghost triangle** ``(u, w, ∞)`` on every
convex-hull edge, where ``∞`` is a symbolic vertex (label ``len(pred)``, no
coordinates).  With the ghosts every oriented edge has exactly one triangle on
each side, so the neighbour of a triangle across its edge ``(u, w)`` is always
``findi(c, (w, u))`` — the same walk as the bulldozer's (paper Appendix A) — and
the convex hull needs no special case: it is where the ghosts are.

Why a symbolic vertex rather than a big enclosing triangle of constructed
points: through the lifting map the Delaunay triangulation is the lower convex
hull of the points lifted to the paraboloid ``z = x² + y²``, and the ghosts are
the vertical faces that close it off *at infinity*.  A finite enclosing triangle
would be a different point set whose Delaunay triangulation differs from the
input's near the hull unless its vertices are far enough — a distance that
depends on the input and must itself be computed exactly.  The symbolic vertex
is at the right place by construction, costs nothing, and its tests reduce to
``orient2d``: the "circumcircle" of ghost ``(u, w, ∞)`` is the open half-plane
left of ``u → w`` (outside the hull) together with the open segment ``(u, w)``.

The conflict rule (Shewchuk's, exact):

* a finite triangle ``(a, b, c)`` is in conflict with ``p`` iff
  ``incircle(a, b, c, p) = +1`` — the exact sign, ties among cocircular points
  broken by the predicates' Simulation of Simplicity (one consistent perturbed
  point set for ``orient2d`` and ``incircle``); or, for a *strict* triangulator
  (``Triangulator(strict=True)``, greedy insertion's), iff ``p`` is strictly
  inside the circle: a point exactly on it is not in conflict, so an insertion
  keeps every edge that Delaunay allows it to keep (Bowyer–Watson's and Lawson's
  own rule; below);
* a ghost ``(u, w, ∞)`` iff ``orient2d_sign(u, w, p) > 0`` (``p`` strictly
  outside the hull edge), or the exact sign is 0 and ``p`` lies strictly between
  ``u`` and ``w``.  The true sign, not SoS: a point exactly on a hull edge
  *splits* it.  Were SoS to put such a point infinitesimally inside, the fan
  would contain the zero-area triangle ``(u, w, p)``; infinitesimally outside, a
  zero-area triangle would appear on the next collinear insertion.  With this
  rule no finite triangle ever has zero area (:mod:`persistri.impl.terrain.cavity` says why).

The strict rule gives *a* Delaunay triangulation (every interior edge has exact
``incircle ≤ 0``), the one that depends on the insertion order where four or
more points are cocircular; SoS gives the one Delaunay triangulation of the
perturbed points, whatever the order.  The strict rule is a symbolic perturbation
too, a consistent one: lift each point above the paraboloid by an infinitesimal
that dominates every earlier point's (and the planar SoS of ``orient2d``, which
the lift does not touch).  An insertion only ever asks ``incircle(a, b, c, p)``
with ``p`` the newest of the four, so on an exact zero the lift of ``p`` decides,
and it puts ``p`` outside the circle; each version is then the one Delaunay
triangulation of its points so perturbed.  The scattered Delaunay wants the latter
(an extended run equals one run of all its points); greedy insertion wants the
former, because the point it inserts is the sample of largest error: SoS
connects it across a cocircular quadrilateral about half of the time, which
spreads its height over a triangle that did not hold it, and costs error (on
grid DEMs, where cocircular samples are everywhere: docs/performance.md,
"Max error at equal vertex count").  The cavity stays star-shaped with ``p``
strictly inside it: a boundary edge ``(u, w)`` separates a triangle whose open
disc holds ``p`` from one whose open disc does not, and both discs contain the
open segment ``uw``, so ``p`` is strictly on the cavity's side of it.

One insertion of ``p`` (:meth:`Triangulator.insert`) finds the **cavity** (the
triangles in conflict with ``p``), removes it and adds the **fan** from ``p`` to
its boundary: one new persistent version (:mod:`persistri.impl.terrain.cavity`);
the walk that finds a first triangle in conflict is :mod:`persistri.impl.terrain.walk`.

Points are indices into the predicates' point array; each is a
:class:`~persistri.impl.complex.vertex.Vertex` whose label is its index.
"""

from __future__ import annotations

from collections.abc import Callable
from itertools import chain
from typing import Any, Final

import numpy as np

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.complex.vertex import Lineage, Vertex, VertexState
from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.terrain.cavity import insert
from persistri.impl.terrain.errors import TriangulationCheckError
from persistri.impl.terrain.insertion import (
    EMPTY,
    Insertion,
    Samples,
    Triangle,
    TriDatum,
    canonical_triangles,
    _frozen,
    link,
    sample_dtype,
    third,
)
from persistri.impl.terrain.walk import walk, walk_from_fan

__all__ = [
    "TriDatum",
    "Triangle",
    "Insertion",
    "Triangulator",
    "TriangulationCheckError",
    "EMPTY",
    "Samples",
    "sample_dtype",
    "canonical_triangles",
]

_NEW_INT: Final[Any] = int.__new__
"""``int.__new__``, read once (compiled, ``int.__new__(cls, i)`` looks the method up on ``int`` at every call)."""


class Triangulator:
    """The state of an incremental Delaunay triangulation: the current complex version and its bookkeeping.

    ``Triangulator(pred, structure)`` makes an empty state whose vertices (one
    per point of ``pred``, label = index, made on first use by :meth:`vertex`,
    plus the symbolic :attr:`infinite` vertex) share one lineage;
    :meth:`begin` lays the first triangles, :meth:`insert` adds one point and
    returns the new version (every old version stays valid: the complex is
    persistent).  :meth:`locate` finds a triangle in conflict with a
    point by walking, for inputs without conflict lists.

    ``tri_of`` maps the id of every live triangle (ghosts included) to its
    vertices (read from :attr:`adj` when the run keeps neighbour records); it is
    the run's scratch index of the current version, not part of any version (an older version is read through the complex alone; the
    scattered ``delaunay`` reads its final triangles from it when nothing is
    counted, and compares it with the complex under ``check=True``).  Sample lists are read-only arrays of
    :attr:`sample_dtype` (:func:`sample_dtype`: ``int32`` up to 2^31 points).

    Each insertion changes the complex once, replacing the cavity by the fan
    (:meth:`~persistri.impl.complex.two_complex.TwoComplex.replace`: one map
    update per vertex touched); ``stepwise=True`` makes the same change as the
    paper's code, a ``rem`` per cavity triangle and an ``add`` per fan triangle
    (the experiments count that).

    ``edge_index=True`` (the scattered Delaunay) keeps, beside ``tri_of``, a
    *neighbour record* for every live triangle of the current version
    (:attr:`adj`, a list by triangle id, None at the ids of dead triangles):
    ``[triangle, datum, n0, n1, n2, mark]``, the triangle and datum objects the
    complex holds, ``nk`` the id of the triangle across the record's edge ``k``
    (edge 0 is ``(triangle[0], triangle[1])``, 1 and 2 follow it), and ``mark``
    the scratch of one cavity search (:mod:`persistri.impl.terrain.cavity`).
    Every insertion updates it with the complex; the walk's and the cavity's
    neighbour look-ups read it instead of the complex's maps: the same answers
    (``check=True`` compares each with the complex's), two list reads each
    instead of a tree search and a scan of a vertex list (or, as the index of
    directed edges it replaced did, two dictionary reads, and a dictionary
    store or deletion for every edge an insertion makes or removes).  Like
    ``tri_of`` it is the run's scratch index of the current version, not part of
    any version (about 0.3 KB a point while the run lasts, from the objects' sizes; 0.2–0.26 KB a point
    more at a greedy run's peak than the ``tri_of`` dictionary it replaces, measured).  On in the
    scattered ``delaunay`` and in greedy insertion
    (:class:`~persistri.impl.terrain.greedy_run.GreedyRun`, whose queue tells a live triangle by its
    record); off by default and in counted runs, which count the paper's look-ups.

    ``live`` — the number of live triangles of the current version (ghosts included), kept by every
    insertion: ``len(tri_of)`` without the dictionary that ``tri_of`` makes from the records.

    ``strict=True`` — a point exactly on a triangle's circumcircle is not in conflict with it
    (module docstring); greedy insertion's rule.  Default: SoS decides.

    ``counted`` — whether the predicates count (their ``stats`` is set), decided at construction: a run's
    predicates keep their ``stats``.  Uncounted, the cavity and the walks call the kernel's
    ``incircle_uncounted`` and ``orient2d_uncounted``, the same signs without reading ``stats`` at every test.
    """

    def __init__(
        self,
        pred: Predicates2,
        structure: TwoComplex[TriDatum],
        *,
        check: bool = False,
        stepwise: bool = False,
        edge_index: bool = False,
        strict: bool = False,
    ) -> None:
        self.pred = pred
        self.S = structure
        self.check = check
        self.stepwise = stepwise
        self.n = len(pred)
        # The dtype of every sample list (begin converts the first ones; the rest are cut from them).
        self.sample_dtype = sample_dtype(self.n)
        # Vertices are made when first used: a height grid has 10^5 samples and only a
        # few thousand become vertices.  Vertex i has label i (its point index) and is
        # made once (memoised), so labels are unique in the lineage — the vertices the
        # VERTEX state would hand out in index order (``int_vertex.new_many``).
        self.lineage: Lineage = VertexState.initial().lineage
        self._verts: dict[int, Vertex] = {}
        # The class of the lineage's vertices whose point is their label (vertex): made by Vertex once, then
        # instantiated directly (Vertex's interpreted __new__ was 3 % of a compiled insertion).  Reset with
        # the lineage (resume).
        self._label_class: type[Vertex] | None = None
        self.infinite: Vertex = self.vertex(self.n)
        # The live triangles by id (tri_of), kept here when the run keeps no neighbour records (else adj has them).
        self._tri_of: dict[int, Triangle] = {}
        self._next_id = 0
        # The number of live triangles of the current version (ghosts included): len(tri_of), without the
        # dictionary that tri_of makes from the records.
        self.live = 0
        self.complex: Complex[TriDatum] = structure.new(2)
        # The neighbour function of one version (TwoComplex.neighbours), kept while that version is current:
        # the walk that locates a point and the insertion that follows read one version, so they share the
        # vertex lists it has read from the map (a lookup of a list already read is a scan, not a tree search).
        self._read_version: Complex[TriDatum] | None = None
        self._read: Callable[[Any], Any] | None = None
        # The neighbour records of the current version's triangles, by id (class docstring), or None when the
        # look-ups read the complex.  Off in counted runs: they count the paper's look-ups, one per edge crossed.
        # Items typed Any: compiled by mypyc, the triangle and datum stay the objects the complex holds.
        self.adj: list[Any] | None = [] if edge_index and pred.stats is None and structure.stats is None else None
        self.kernel = pred.kernel()
        # The conflict rule for cocircular points (module docstring): SoS, or strictly inside only.
        self.kernel.strict = strict
        self.strict = strict
        # Whether the run is counted, decided once (the predicates' stats is fixed for a run, as the neighbour
        # records assume): uncounted, the cavity and the walks call the kernel's tests that do not read stats.
        self.counted = pred.stats is not None
        # The sector test's float path is exact when orient2d's is (docs of kernel2d and sectors).
        self.small_integers = self.kernel.exact_orient2d

    # -- construction ------------------------------------------------------------------

    def _check_indexed(self, w: Any, u: Any, nb: Any) -> None:
        """``check=True``: what :attr:`adj` answered across ``(w, u)`` — ``nb``, the neighbour's ``(triangle,
        datum)`` — is what the complex answers (the same triangle and the same datum object)."""
        ref: Any = self.neighbours()((w, u))
        if nb is None or ref is None or ref[0] != (w, u, third(nb[0], w)) or ref[1] is not nb[1]:
            raise TriangulationCheckError(f"insert: the indexed neighbour across {(w, u)} is {nb}, the complex has {ref}")

    def neighbours(self) -> Callable[[Any], Any]:
        """``s ↦ neighbour(c, s)`` for the current version ``c``, made once per version: :meth:`locate` and
        the :meth:`insert` after it share it, and with it the vertex lists already read from the map.  Every
        caller asks about edges of triangles it read from ``c``, so the edges go unchecked
        (:meth:`TwoComplex.neighbours_unchecked`; counted runs still count each call).  O(1)."""
        cx = self.complex
        read = self._read
        if read is None or self._read_version is not cx:
            read = self._read = self.S.neighbours_unchecked(cx)
            self._read_version = cx
        return read

    def vertex(self, i: int) -> Vertex:
        """The vertex of point ``i`` (label ``i``; ``i = n`` is the symbolic infinite vertex, point None). O(1).

        A vertex whose point is its ``int`` label is an instance of one class per lineage
        (:class:`~persistri.impl.complex.vertex.Vertex`): after the first, made by ``Vertex``, the others
        are made as that class's ``int`` directly — the same object ``Vertex`` would make, without its
        interpreted ``__new__``.
        """
        io: Any = i  # boxed once (compiled: an int parameter is boxed again at every use as an object)
        v = self._verts.get(io)
        if v is None:
            v = self.new_vertex(io)
        return v

    def new_vertex(self, i: Any) -> Vertex:
        """:meth:`vertex` of a point ``i`` that has no vertex yet (the caller has asked ``_verts``): made now. O(1)."""
        cls = self._label_class
        v: Vertex
        if cls is not None and type(i) is int and i < self.n:
            v = _NEW_INT(cls, i)
        else:
            v = Vertex(i, i if i < self.n else None, self.lineage)
            if type(i) is int and i < self.n:
                self._label_class = type(v)
        self._verts[i] = v
        return v

    @property
    def tri_of(self) -> dict[int, Triangle]:
        """The id of every live triangle of the current version (ghosts included) to its vertices (class docstring).

        Kept up to date by every insertion when the run keeps no neighbour records; with them (:attr:`adj`) the
        records are the index, and this is a new dictionary read from them: O(1) without records, O(ids made)
        with them (the scattered ``delaunay`` reads it once, for its result)."""
        adj = self.adj
        if adj is None:
            return self._tri_of
        R: Any
        return {i: R[0] for i, R in enumerate(adj) if R is not None}

    @tri_of.setter
    def tri_of(self, live: dict[int, Triangle]) -> None:
        self._tri_of = live

    def _new_id(self, tri: Triangle) -> int:
        tid = self._next_id
        self._next_id += 1
        self._tri_of[tid] = tri
        return tid

    def begin(self, triangles: list[tuple[tuple[int, int, int], Samples]]) -> Complex[TriDatum]:
        """Lay the first triangulation: finite counterclockwise triangles with their samples, plus the ghosts.

        ``triangles`` must triangulate a convex polygon and be Delaunay (the
        caller's duty: the callers lay one triangle, or a rectangle split along its
        Delaunay diagonal); :class:`ValueError` for a triangle that is not strictly
        counterclockwise (exact).  A ghost ``(w, u, ∞)`` is added on every boundary edge
        ``(u, w)``.  The samples are copied into arrays of :attr:`sample_dtype`.  Returns the first
        version.  O(size).
        """
        if self.tri_of:
            raise ValueError("begin: the triangulation has already begun")
        P, V, S = self.pred, self.vertex, self.S
        cx = self.complex
        edges: set[tuple[int, int]] = set()
        laid: list[Any] = []  # (triangle, datum), for the neighbour records
        for (a, b, c), samples in triangles:
            if P.orient2d_sign(a, b, c) <= 0:
                raise ValueError(f"begin: triangle {(a, b, c)} is not strictly counterclockwise")
            tri = (V(a), V(b), V(c))
            # Any: compiled, a fixed-length tuple would be unboxed and boxed anew for the complex and for the index.
            datum: Any = (self._new_id(tri), _frozen(np.array(samples, dtype=self.sample_dtype)))
            cx = S.add(cx, tri, datum)
            laid.append((tri, datum))
            edges.update(((a, b), (b, c), (c, a)))
        for u, w in sorted(edges):
            if (w, u) not in edges:
                ghost = (V(w), V(u), self.infinite)
                datum = (self._new_id(ghost), EMPTY)
                cx = S.add(cx, ghost, datum)
                laid.append((ghost, datum))
        if self.adj is not None:
            link(self.adj, laid)
            self._tri_of = {}  # the records are the index of the live triangles
        self.live = len(laid)
        self.complex = cx
        return cx

    @classmethod
    def resume(
        cls, pred: Predicates2, structure: TwoComplex[TriDatum], c: Complex[TriDatum], infinite: int, *, check: bool = False
    ) -> Triangulator:
        """A triangulator whose current version is ``c``, ready to insert more points (continuing a run).

        ``c`` must be a finished Delaunay triangulation with ghosts (a scattered
        run's version, its infinite vertex labelled ``infinite``) over the first
        points of ``pred`` (labels index ``pred``; the row at ``infinite`` is never
        read).  The live-triangle index, the neighbour records (when the run keeps
        them: uncounted), the next triangle id and the vertices are read back from ``c``:
        its triangles and data are the same objects, its vertices the complex's own
        (so new triangles join their lineage).  :class:`ValueError` if ``c`` has no
        vertex labelled ``infinite``.  O(size of ``c``).
        """
        T = cls(pred, structure, check=check, edge_index=True)
        # Any: compiled, an item typed (Triangle, TriDatum) would be unboxed, and its triangle and datum boxed anew
        # for the indexes (equal, but not the objects the complex holds: check=True compares the data by identity).
        items: list[Any] = structure.items(c)
        item: Any
        tri_of: dict[Any, Any] = {item[1][0]: item[0] for item in items}
        # The complex's own vertex objects, keyed by themselves (a vertex hashes and compares as its label).
        every = list(chain.from_iterable(tri_of.values()))
        verts: dict[int, Vertex] = dict(zip(every, every))
        if infinite not in verts:
            raise ValueError(f"Triangulator.resume: the complex has no vertex labelled {infinite} (the infinite vertex)")
        if T.adj is not None:
            link(T.adj, items)
        inf = verts[infinite]
        T.lineage = inf.lineage
        T._label_class = None  # the lineage changed: its class is made by its first new vertex
        T._verts = verts
        T.infinite = inf
        if T.adj is None:
            T.tri_of = tri_of
        T._next_id = max(tri_of) + 1
        T.live = len(tri_of)
        T.complex = c
        return T

    # -- the conflict tests --------------------------------------------------------------

    def _between(self, u: int, w: int, p: int) -> bool:
        """Whether ``p``, known to be on the line ``uw``, lies strictly between ``u`` and ``w`` (exact comparisons)."""
        xs, ys = self.pred.coordinates(np.array([u, w, p], dtype=np.intp))
        (ux, wx, px), (uy, wy, py) = xs.tolist(), ys.tolist()
        if ux != wx:
            return bool(min(ux, wx) < px < max(ux, wx))
        return bool(min(uy, wy) < py < max(uy, wy))

    def ghost_conflict(self, u: int, w: int, p: int) -> bool:
        """Whether ``p`` is in conflict with the ghost ``(u, w, ∞)``: strictly outside the hull edge, or on its open segment."""
        s = self.kernel.orient2d_sign(u, w, p)
        if s:
            return s > 0
        return self._between(u, w, p)

    def conflicts(self, tri: Triangle, p: int) -> bool:
        """Whether ``p`` is in conflict with ``tri`` (module docstring: incircle with SoS or strict, or the ghost rule). O(1)."""
        a, b, c = tri
        inf = self.infinite
        if c == inf:
            return self.ghost_conflict(a, b, p)
        if a == inf:
            return self.ghost_conflict(b, c, p)
        if b == inf:
            return self.ghost_conflict(c, a, p)
        return self.kernel.incircle(a, b, c, p) > 0

    # -- one insertion -------------------------------------------------------------------

    def insert(self, p: int, start: int) -> Insertion:
        """Insert point ``p`` from the live triangle ``start``, which must be in conflict with it: the cavity
        removed, the fan added (:func:`persistri.impl.terrain.cavity.insert`, whose docstring says why no fan
        triangle is flat).  Returns the :class:`Insertion`; the new version is also :attr:`complex`.  O(k)
        look-ups and tests for a cavity of ``k`` triangles, plus the sort of its samples."""
        return insert(self, p, start)

    # -- point location --------------------------------------------------------------------

    def locate(self, p: int, hint: int, *, seed: int = 0) -> int:
        """The id of a live triangle in conflict with ``p``, by a visibility walk from triangle ``hint``.

        From a finite triangle the walk crosses an edge that has ``p`` strictly on
        its far side (SoS ``orient2d``), choosing among such edges in a rotating
        order (Devillers' stochastic walk, which cannot cycle forever); a finite
        triangle with no such edge contains ``p`` (closed) and so is in conflict.
        A ghost it reaches is in conflict unless ``p`` lies exactly on the line of
        that hull edge and outside it; then, and if the walk were ever to exceed
        a linear number of steps, every live triangle is tested (O(n), never
        needed on inputs in general position).  Each step is one ``neighbour``
        look-up in the current version and at most three ``orient2d`` tests.
        """
        adj = self.adj
        return walk(self, p, hint, self._tri_of[hint] if adj is None else adj[hint][0], False, seed)

    def locate_after(self, p: int, last: Insertion) -> int:
        """:meth:`locate`, starting around the point of ``last``, the insertion that made the current version.

        For a point ``p`` near ``q = last.point`` (successive points of a
        space-filling-curve order): the fan around ``q`` is known from ``last``
        without reading the complex, so the walk starts in the fan triangle
        ``(r_i, r_{i+1}, q)`` whose angle at ``q`` holds ``p`` — ``orient2d(q,
        r_i, p) = +1`` and ``orient2d(q, r_{i+1}, p) = −1`` (SoS: exactly one
        such ``i`` around a closed fan) — and continues as :meth:`locate` only
        if ``p`` is beyond that triangle's outer edge.  The same walk as
        ``locate`` from there, with the steps across the fan done by at most
        ``len(last.created)`` ``orient2d`` tests (about a quarter of them on
        average, scanning from ``r_0`` towards the change of sign) and one more
        for the outer edge, instead of look-ups in the complex.  When ``q`` is on the hull (an open fan) or ``last`` did not
        make the current version, it is :meth:`locate` from ``last``'s first
        new triangle.  Any triangle in conflict with ``p`` gives the same
        insertion (the cavity is every triangle in conflict): only the walk's
        length depends on where it starts.
        """
        return walk_from_fan(self, p, last)

    # -- reading a version -------------------------------------------------------------------

    def finite_triangles(self, c: Complex[TriDatum] | None = None) -> list[tuple[Triangle, TriDatum]]:
        """The finite triangles of version ``c`` (default: the current one) with their data. O(V + N)."""
        inf = self.infinite
        return [(t, d) for t, d in self.S.items(self.complex if c is None else c) if inf not in t]
