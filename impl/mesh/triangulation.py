"""The constrained Delaunay triangulation as a persistent 2-complex: insertion, location and walks (paper §1, §4, §5).

A :class:`MeshTriangulation` reads and changes versions of a
:class:`~persistri.impl.complex.two_complex.TwoComplex` whose triangles carry a
:data:`MeshDatum`; it never changes a version: every insertion returns a new
one, and every old version stays a valid mesh (Ruppert's undo is to keep using
the old one; :mod:`persistri.impl.mesh.ruppert`).

**What a version holds.**  The whole convex hull of the vertices is
triangulated, as in :mod:`persistri.impl.terrain.delaunay`: counterclockwise
finite triangles plus one *ghost* ``(u, w, ∞)`` on every hull edge, ``∞`` a
symbolic vertex (label -1), so that the complex is a closed surface, the
neighbour across any edge is one ``find``, and walks need no special case.  The
domain is the part of it that is not *exterior*: each triangle's datum says
which region it belongs to (:data:`EXTERIOR` for the concavities and holes that
were eaten away, and for ghosts).  Exterior triangles are kept rather than
deleted because deleting them would open the surface; they are never refined.

**Constraints are data of the version.**  A datum records which of the
triangle's edges lie on input segments, and on which (``(lo, hi, segment)``
per constrained edge, ``lo < hi`` the vertex labels).  Both triangles beside a
constrained edge record it (a ghost too, for a segment on the hull), so a
version knows its own constraints: an old version read after later splits
still has its own subsegments.

**Insertion** (:meth:`MeshTriangulation.insert`) is Bowyer–Watson restricted
by the constraints: the cavity is the set of triangles in conflict with the new
point (exact ``incircle``, SoS for ties; the ghost rule of
:mod:`~persistri.impl.terrain.delaunay` for ghosts) reachable from the start
triangle *without crossing a constrained edge* — except the one subsegment
being split, when the point lies exactly on it.  The cavity is replaced by the
fan from the point to its boundary (one ``replace``: one version).  This keeps
the triangulation constrained Delaunay (Delaunay refinement's standard step:
Shewchuk 1997, §2.1): a triangle outside the cavity is not in conflict or is
separated from the point by a segment, which is what constrained Delaunay
allows.  No fan triangle is flat: a point on the line of a boundary edge but
outside the edge is strictly outside every circle through its endpoints (the
chord lemma of :mod:`proofs.proof_terrain`), so that edge's inner triangle would
not be in conflict; a point *on* a boundary edge is a split, and the split
edge is not on the boundary.

**Deletion** (:meth:`MeshTriangulation.remove`, for Chew's rule in the
refinement) replaces a free vertex's star by the Delaunay triangulation of its
link — again one ``replace``, one new version.  The refinement deletes before a
split and makes one version for the deletions and the split together
(:meth:`MeshTriangulation.build`'s ``before``).

The data a version holds are in :mod:`~persistri.impl.mesh.datum` (importable from here
too), the deletion in :mod:`~persistri.impl.mesh.deletion` and the walks
(:meth:`MeshTriangulation.locate`, :meth:`MeshTriangulation.walk_to`) in
:mod:`~persistri.impl.mesh.walk`; this module is the insertion.

Costs: an insertion whose cavity has ``k`` triangles costs ``O(k)`` complex
operations (O(lg n) each) and ``O(k)`` exact predicates (float-filtered); a
deletion of a vertex of degree ``k`` ``O(k²)`` predicates; a walk ``O(length)``.
"""

from __future__ import annotations

from operator import itemgetter
from typing import Any, Literal

from persistri.impl.complex.replace import replace_cone, replace_trusted, same_replace
from persistri.impl.complex.structure import Complex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.complex.vertex import Lineage, Vertex, VertexState
from persistri.impl.geometry.filter import ERRBOUND_INCIRCLE
from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.datum import (
    EXTERIOR,
    INFINITE,
    Cavity,
    Constraint,
    Insertion,
    MeshDatum,
    MeshError,
    Pending,
    Tri,
    constraint_of,
    edge_key,
)
from persistri.impl.mesh.deletion import remove_vertex
from persistri.impl.mesh.edges import EdgeIndex, edge_reader
from persistri.impl.mesh.walk import locate, walk_to

__all__ = [
    "EXTERIOR",
    "INFINITE",
    "Constraint",
    "MeshDatum",
    "Tri",
    "Insertion",
    "Cavity",
    "MeshTriangulation",
    "MeshError",
    "edge_key",
    "constraint_of",
]


_new_tuple = tuple.__new__
"""``tuple.__new__``: a named tuple of :mod:`~persistri.impl.mesh.datum` made from its fields in one C call (its own
``__new__`` is a Python function: a frame per step)."""


class MeshTriangulation:
    """The operations on versions of a constrained triangulation over the points of a :class:`GrowingPredicates2`.

    ``MeshTriangulation(pred, structure)``; vertices are made on first use
    (:meth:`vertex`, label = point index) in one lineage, ``∞`` has label -1.
    The object holds no version: every method takes the version it reads.
    """

    def __init__(self, pred: GrowingPredicates2, structure: TwoComplex[MeshDatum], *, check: bool = False) -> None:
        self.pred = pred
        self.S = structure
        self.check = check
        self.lineage: Lineage = VertexState.initial().lineage
        self._verts: dict[int, Vertex] = {}
        self.infinite: Vertex = Vertex(INFINITE, None, self.lineage)
        self._verts[INFINITE] = self.infinite
        self._next_id = 0
        # The structure has the compiled entry for two lists (a TwoComplex's own, uncounted replace).
        self._trusted = getattr(structure, "_batched", None) is not None

    def vertex(self, i: int) -> Vertex:
        """The vertex of point ``i`` (``-1``: the symbolic infinite vertex). O(1)."""
        v = self._verts.get(i)
        if v is None:
            # The object Vertex(i, None, self.lineage) makes, without its frame: every vertex of the lineage without
            # a point has the class of ∞ (Vertex.__new__'s "none" kind; read here, not kept: classes do not pickle).
            v = self._verts[i] = int.__new__(type(self.infinite), i)
        return v

    def with_structure(self, structure: Any) -> MeshTriangulation:
        """A triangulation over the same points, the same vertices and the same datum ids, on another structure
        (the CDT's :class:`~persistri.impl.mesh.scratch.ScratchComplex`).  Ids it hands out are taken back with
        :meth:`take_ids_from`. O(1)."""
        other = MeshTriangulation.__new__(MeshTriangulation)
        other.pred = self.pred
        other.S = structure
        other.check = self.check
        other.lineage = self.lineage
        other._verts = self._verts
        other.infinite = self.infinite
        other._next_id = self._next_id
        other._trusted = getattr(structure, "_batched", None) is not None
        return other

    def take_ids_from(self, other: MeshTriangulation) -> None:
        """Continue numbering data after the ids ``other`` (made by :meth:`with_structure`) handed out. O(1)."""
        self._next_id = max(self._next_id, other._next_id)

    def new_datum(self, region: int, constraints: tuple[Constraint, ...] = ()) -> MeshDatum:
        """A datum with a fresh id."""
        tid = self._next_id
        self._next_id += 1
        return (tid, region, constraints)

    def empty(self) -> Complex[MeshDatum]:
        """The empty 2-complex of this triangulation's structure."""
        return self.S.new(2)

    # -- reading a version ---------------------------------------------------------------

    def across(self, c: Complex[MeshDatum], u: Vertex, w: Vertex) -> tuple[Tri, MeshDatum]:
        """The triangle ``(w, u, x)`` on the far side of the edge ``(u, w)`` of a triangle holding ``(u, w)``. O(lg n)."""
        found = self.S.neighbour(c, (w, u))
        if found is None:
            raise MeshError(f"internal: no triangle holds the edge {(int(w), int(u))}: the complex is not closed")
        return found

    def conflicts(self, tri: Tri, p: int) -> bool:
        """Whether point ``p`` is in conflict with ``tri``: strictly inside its circle (SoS), or the ghost rule. O(1)."""
        a, b, c = tri
        if a < 0 or b < 0 or c < 0:
            k = tri.index(self.infinite)
            u, w = tri[(k + 1) % 3], tri[(k + 2) % 3]
            s = self.pred.orient2d_sign(u, w, p)
            if s:
                return s > 0
            return self.pred.between(u, w, p)
        return self.pred.incircle(a, b, c, p) > 0

    # -- insertion -----------------------------------------------------------------------

    def insert(
        self,
        c: Complex[MeshDatum],
        p: int,
        start: tuple[Tri, MeshDatum],
        split: tuple[int, int, int] | None = None,
        index: EdgeIndex | None = None,
        on_line: bool = False,
        before: Pending | None = None,
    ) -> Insertion:
        """Insert point ``p`` into version ``c`` from ``start``, a triangle in conflict with it (module docstring).

        ``split = (u, w, segment)``: ``p`` splits the constrained edge ``{u, w}`` of
        segment ``segment`` (``start`` beside it), which the cavity crosses; the two
        halves ``{u, p}``, ``{p, w}`` become constrained.  ``p`` lies on the edge exactly
        (then it conflicts with both triangles beside it), or — a split point rounded
        where no double lies on the segment — within an ulp of it, off its line.
        Then the cavity starts from the triangle beside the edge on ``p``'s side; the one
        beyond goes too when it is a domain triangle (whatever its circle says: the
        edge must go, and a sliver left in the domain would not be Delaunay), and when
        it is exterior (a ghost, a hole) it stays, rewritten without the constraint,
        and the sliver between the new chain ``u–p–w`` and the old edge joins the
        exterior (so a hull stays convex).  ``index`` and ``on_line``: as :meth:`cavity`'s; ``before``: as
        :meth:`build`'s (``c`` is then ``before.base``, and ``index`` describes it with those steps done).  Returns the
        :class:`Insertion`; ``c`` is unchanged.
        """
        return self.build(self.cavity(c, p, start, split, index, on_line), before)

    def cavity(
        self,
        c: Complex[MeshDatum],
        p: int,
        start: tuple[Tri, MeshDatum],
        split: tuple[int, int, int] | None = None,
        index: EdgeIndex | None = None,
        on_line: bool = False,
    ) -> Cavity:
        """The conflict search of :meth:`insert`, without building anything: which triangles go, and the boundary.

        Reads ``c`` only (no complex operation that makes a version): the refinement decides on the
        boundary whether the point would encroach a subsegment before paying for the new version.  ``index``: an
        :data:`~persistri.impl.mesh.datum.EdgeIndex` of ``c`` (the refinement's, kept in step with the version it
        stands at), read instead of the complex.  ``on_line``: the caller knows that the split point ``p`` lies
        exactly on the line of the split edge (a split point exactly on its segment, between ends exactly on it),
        so its orientation is not tested (it would be decided exactly: it is 0), and a triangle beyond the edge is
        in conflict without a test (``p`` strictly inside the edge is strictly inside every circle through its ends;
        a ghost's rule says the same); with :attr:`check` both are tested anyway. O(k).
        """
        conflicts = self.conflicts
        pred = self.pred
        crossing = edge_key(split[0], split[1]) if split is not None else None
        get = index.get if index is not None else edge_reader(self.S, c)
        off_line = 0
        if split is not None:
            if not on_line or self.check:
                off_line = pred.orient2d_sign(split[0], split[1], p)
                if on_line and off_line:
                    raise MeshError(f"internal: split point {p} is off the line of the edge {crossing}")
            if off_line:
                lo, hi = self.vertex(split[0]), self.vertex(split[1])
                e0 = (lo, hi) if off_line > 0 else (hi, lo)
                rec0 = get(e0)
                if rec0 is None:
                    raise MeshError(f"internal: no triangle beside the subsegment {crossing} on the side of point {p}")
                start = ((e0[0], e0[1], rec0[0]), rec0[1])
        stri, sdat = start
        if self.check and not off_line and not conflicts(stri, p):
            raise MeshError(f"internal: point {p} is not in conflict with the start triangle {stri}")
        cavity: dict[int, tuple[Tri, MeshDatum]] = {sdat[0]: start}
        rejected: set[int] = set()
        # Each boundary edge (u, w) with the region inside it and its segment (-1 if none).
        boundary: list[tuple[Vertex, Vertex, int, int]] = []
        beyond: tuple[Tri, MeshDatum] | None = None
        a, b, cc = stri
        stack = [(a, b, sdat), (b, cc, sdat), (cc, a, sdat)]
        # The incircle filter inlined (the predicates' own filter, the same operations), exact when it cannot tell;
        # counted runs go through the predicates.
        rows_all = pred.filter_rows
        rows = rows_all if pred.stats is None else None
        px, py = rows_all[p]
        while stack:
            u, w, dat = stack.pop()
            cons = dat[2]
            if cons:
                lo, hi = (u, w) if u < w else (w, u)
                seg = -1
                for ca, cb, cs in cons:  # constraint_of(dat, u, w), inlined
                    if ca == lo and cb == hi:
                        seg = cs
                        break
                if seg >= 0:
                    if (lo, hi) != crossing:
                        boundary.append((u, w, dat[1], seg))
                        continue
                    # The subsegment split: both triangles beside it go (a domain triangle beyond a rounded point's
                    # edge whatever its circle says); an exterior one beyond a rounded point stays, and the sliver
                    # between the new chain u–p–w and the old edge is exterior.
                    rec = get((w, u))
                    assert rec is not None, "a closed surface has a triangle beyond every edge"
                    ndat = rec[1]
                    ntri = (w, u, rec[0])
                    found = (ntri, ndat)
                    nid = ndat[0]
                    if nid in cavity:
                        continue
                    if nid not in rejected:
                        if ndat[1] != EXTERIOR if off_line else (on_line and not self.check) or conflicts(ntri, p):
                            cavity[nid] = found
                            x = ntri[2]
                            stack.append((u, x, ndat))
                            stack.append((x, w, ndat))
                            continue
                        rejected.add(nid)
                    boundary.append((u, w, EXTERIOR, -1))
                    beyond = found
                    continue
            rec = get((w, u))
            assert rec is not None, "a closed surface has a triangle beyond every edge"
            ndat = rec[1]
            nid = ndat[0]
            if nid in cavity:
                continue
            if nid not in rejected:
                x2 = rec[0]
                # The triangle across is (w, u, x2); its tuple is made only for the cavity or the exact test.
                if rows is None or w < 0 or u < 0 or x2 < 0:
                    inside = conflicts((w, u, x2), p)
                else:
                    ax, ay = rows[w]
                    bx, by = rows[u]
                    cx, cy = rows[x2]
                    # incircle_terms(ax, ay, bx, by, cx, cy, px, py), operation for operation (its proved bound holds).
                    adx = ax - px
                    bdx = bx - px
                    cdx = cx - px
                    ady = ay - py
                    bdy = by - py
                    cdy = cy - py
                    bdxcdy = bdx * cdy
                    cdxbdy = cdx * bdy
                    alift = adx * adx + ady * ady
                    cdxady = cdx * ady
                    adxcdy = adx * cdy
                    blift = bdx * bdx + bdy * bdy
                    adxbdy = adx * bdy
                    bdxady = bdx * ady
                    clift = cdx * cdx + cdy * cdy
                    det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady)
                    perm = (
                        (abs(bdxcdy) + abs(cdxbdy)) * alift
                        + (abs(cdxady) + abs(adxcdy)) * blift
                        + (abs(adxbdy) + abs(bdxady)) * clift
                    )
                    thr = ERRBOUND_INCIRCLE * perm
                    if det > thr:
                        inside = True
                    elif det < -thr:
                        inside = False
                    else:
                        inside = pred.incircle(w, u, x2, p) > 0
                if inside:
                    cavity[nid] = ((w, u, x2), ndat)
                    stack.append((u, x2, ndat))
                    stack.append((x2, w, ndat))
                    continue
                rejected.add(nid)
            boundary.append((u, w, dat[1], -1))
        return _new_tuple(Cavity, (c, p, cavity, boundary, beyond, split))  # Cavity(...) without its frame

    def build(self, cav: Cavity, before: Pending | None = None) -> Insertion:
        """The new version for a :class:`Cavity`: its triangles replaced by the fan from its point (one ``replace``).

        ``before``: steps taken since ``before.base`` that made no version (Chew's deletions before a split; the
        cavity was found in the triangulation after them): the new version is made from ``before.base`` by one
        ``replace`` that does them and this insertion together — the same triangles and data as a version for them
        and then one for the insertion.  The :class:`Insertion` names the insertion's own triangles either way.
        O(k) complex operations; ``cav.version`` and ``before.base`` are unchanged."""
        c, p, cavity, boundary, beyond, split = cav
        verts = self._verts
        vp = verts.get(p)  # self.vertex(p), inlined: a new point's vertex
        if vp is None:
            vp = verts[p] = int.__new__(type(self.infinite), p)
        inf = self.infinite
        pred = self.pred
        succ: dict[Vertex, tuple[Vertex, int, int]] = {}
        for u, w, region, seg in boundary:  # a loop, not a comprehension: no function frame per call
            succ[u] = (w, region, seg)
        if len(succ) != len(boundary):
            raise MeshError(f"internal: the cavity of point {p} is not a disc")
        first = succ[inf][0] if inf in succ else boundary[0][0]
        # A split makes the edges from p to the subsegment's ends {s0, s1} constrained (segment sseg): the fan edge
        # from p to a boundary vertex x is one of them exactly when x is s0 or s1.
        s0, s1, sseg = split if split is not None else (-2, -2, -1)
        created: list[tuple[Tri, MeshDatum]] = []
        u = first
        check = self.check
        tid = self._next_id
        while True:
            w, region, seg = succ[u]
            if w == inf:
                break
            tri = (u, w, vp)
            if check and pred.orient2d_sign(u, w, p) <= 0:
                raise MeshError(f"internal: point {p} makes the flat or inverted triangle {tri}")
            if seg >= 0 or sseg >= 0:
                cons: list[Constraint] = []
                if seg >= 0:
                    cons.append((u, w, seg) if u < w else (w, u, seg))
                if sseg >= 0:
                    # The edges (w, p) and (p, u), in this order.
                    if w == s0 or w == s1:
                        cons.append((w, vp, sseg) if w < vp else (vp, w, sseg))
                    if u == s0 or u == s1:
                        cons.append((u, vp, sseg) if u < vp else (vp, u, sseg))
                created.append((tri, (tid, region, tuple(cons))))
            else:
                created.append((tri, (tid, region, ())))
            tid += 1
            u = w
            if u == first:
                break
        self._next_id = tid
        if inf in succ:
            # An open fan: p is on the hull; two ghosts close it, on the new hull edges (p, u) and (first, p).
            for g, x in (((u, inf, vp), u), ((inf, first, vp), first)):
                cons2: tuple[Constraint, ...] = ()
                if sseg >= 0 and (x == s0 or x == s1):
                    cons2 = ((x, vp, sseg) if x < vp else (vp, x, sseg),)
                created.append((g, self.new_datum(EXTERIOR, cons2)))
        removed = tuple(cavity.values())
        if beyond is not None:
            # Its edge is no longer a subsegment: the triangle beyond is replaced by itself without the constraint.
            assert split is not None, "only a rounded split point leaves a triangle beyond"
            gt, gd = beyond
            removed += (beyond,)
            crossing = edge_key(split[0], split[1])
            created.append((gt, self.new_datum(EXTERIOR, tuple(k for k in gd[2] if (k[0], k[1]) != crossing))))
        if before is None:
            # With no triangle beyond, created is the cone from vp over the cavity's boundary cycle in order (its
            # ghosts last when open), as the scattered Delaunay's fan: replace_cone groups it from the cycle.
            gone = list(map(itemgetter(0), removed))  # no comprehension frame
            version = self._replace(c, gone, created, beyond is None)
        else:
            gone, made = before.then(removed, tuple(created))
            version = self._replace(before.base, gone, made)
        return _new_tuple(Insertion, (version, removed, tuple(created)))  # Insertion(...) without its frame

    def _replace(
        self, c: Complex[MeshDatum], removed: list[Tri], added: list[tuple[Tri, MeshDatum]], cone: bool = False
    ) -> Complex[MeshDatum]:
        """``self.S.replace(c, removed, added)``: through the 2-complex's entry for algorithms that pass two lists
        (:func:`~persistri.impl.complex.replace.replace_trusted`, compiled on the twin; the same version), compared
        with the public ``replace`` when :attr:`check` is on.  ``cone``: ``added`` is the cone from a new vertex over
        the cycle of ``removed``'s boundary in order, through
        :func:`~persistri.impl.complex.replace.replace_cone` (grouped from the cycle; anything else it hands on to
        ``replace_trusted``).  A structure without that entry (the CDT's scratch triangulation, a counted
        structure) gets its own ``replace``.  O(V_t·lg V + Σ δ) as ``replace``."""
        S = self.S
        if not self._trusted:
            return S.replace(c, removed, added)
        done: Complex[MeshDatum] = (replace_cone if cone else replace_trusted)(S, c, removed, added)
        if self.check and not same_replace(S, done, S.replace(c, removed, added), removed, added):
            raise MeshError(f"internal: {'replace_cone' if cone else 'replace_trusted'} differs from replace")
        return done

    # -- deletion and location: persistri.impl.mesh.deletion, persistri.impl.mesh.walk ---------------

    def remove(self, c: Complex[MeshDatum], v: int, start: tuple[Tri, MeshDatum]) -> Insertion:
        """Version ``c`` without the free vertex ``v`` (``start`` a triangle of ``c`` at ``v``): its star replaced by
        the Delaunay triangulation of its link, one ``replace``
        (:func:`~persistri.impl.mesh.deletion.remove_vertex`). O(k²) predicates for a star of ``k`` triangles."""
        return remove_vertex(self, c, v, start)


    def locate(self, c: Complex[MeshDatum], p: int, hint: tuple[Tri, MeshDatum]) -> tuple[Tri, MeshDatum]:
        """A triangle of ``c`` in conflict with ``p``: a visibility walk from ``hint`` that ignores constraints
        (:func:`~persistri.impl.mesh.walk.locate`). O(walk)."""
        return locate(self, c, p, hint)

    def walk_to(
        self, c: Complex[MeshDatum], start: tuple[Tri, MeshDatum], p: int
    ) -> tuple[Literal["found"], tuple[Tri, MeshDatum]] | tuple[Literal["blocked"], Constraint]:
        """From the finite triangle ``start`` towards ``p`` along a straight line, never crossing a segment:
        ``("found", triangle)`` or ``("blocked", (u, w, segment))`` (:func:`~persistri.impl.mesh.walk.walk_to`).
        O(length)."""
        return walk_to(self, c, start, p)
