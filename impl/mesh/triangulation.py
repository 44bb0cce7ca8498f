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
link — again one ``replace``, one new version.

Costs: an insertion whose cavity has ``k`` triangles costs ``O(k)`` complex
operations (O(lg n) each) and ``O(k)`` exact predicates (float-filtered); a
deletion of a vertex of degree ``k`` ``O(k²)`` predicates; a walk ``O(length)``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Final, Literal, NamedTuple

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.complex.vertex import Lineage, Vertex, VertexState
from persistri.impl.geometry.filter import ERRBOUND_INCIRCLE, ERRBOUND_ORIENT2D
from persistri.impl.geometry.growing import GrowingPredicates2

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
]

EXTERIOR: Final[int] = -1
"""The region of exterior triangles (eaten concavities, holes) and of ghosts."""

INFINITE: Final[int] = -1
"""The label of the symbolic vertex at infinity."""

Constraint = tuple[int, int, int]
"""``(lo, hi, segment)``: the edge between vertex labels ``lo < hi`` lies on input segment ``segment``."""

MeshDatum = tuple[int, int, tuple[Constraint, ...]]
"""The datum of a triangle: ``(id, region, constraints)``; ids are unique over the run (never reused)."""

Tri = tuple[Vertex, Vertex, Vertex]


class MeshError(ValueError):
    """A meshing step met input it cannot handle (crossing segments, a precision limit); the message says which."""


@dataclass(frozen=True, slots=True)
class Insertion:
    """One insertion: the new ``version``, the cavity ``removed`` and the fan ``created`` (each ``(triangle, datum)``)."""

    version: Complex[MeshDatum]
    removed: tuple[tuple[Tri, MeshDatum], ...]
    created: tuple[tuple[Tri, MeshDatum], ...]


class Cavity(NamedTuple):
    """The conflict region of a point, before anything is built: what :meth:`MeshTriangulation.cavity` found.

    ``triangles`` — the triangles to remove, by id; ``boundary`` — its boundary edges ``(u, w, region, segment)``
    in cavity order (``u → w`` as in the cavity triangle beside it, ``region`` of the triangle to make on it,
    ``segment`` -1 if none); ``beyond`` — for a rounded split point, the exterior triangle beyond the split edge
    that stays, rewritten without the constraint (else None); ``split`` as :meth:`MeshTriangulation.insert`'s.
    """

    version: Complex[MeshDatum]
    point: int
    triangles: dict[int, tuple[Tri, MeshDatum]]
    boundary: list[tuple[Vertex, Vertex, int, int]]
    beyond: tuple[Tri, MeshDatum] | None
    split: tuple[int, int, int] | None


def edge_key(u: int, w: int) -> tuple[int, int]:
    """The unordered edge ``{u, w}`` as ``(lo, hi)``."""
    return (u, w) if u < w else (w, u)


def constraint_of(datum: MeshDatum, u: int, w: int) -> int:
    """The input segment the edge ``{u, w}`` of a triangle with ``datum`` lies on, or -1. O(1)."""
    lo, hi = (u, w) if u < w else (w, u)
    for a, b, s in datum[2]:
        if a == lo and b == hi:
            return s
    return -1


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
        self.infinite: Vertex = self.vertex(INFINITE)
        self._next_id = 0

    def vertex(self, i: int) -> Vertex:
        """The vertex of point ``i`` (``-1``: the symbolic infinite vertex). O(1)."""
        v = self._verts.get(i)
        if v is None:
            v = Vertex(i, None, self.lineage)
            self._verts[i] = v
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
        exterior (so a hull stays convex).  Returns the :class:`Insertion`; ``c`` is
        unchanged.
        """
        return self.build(self.cavity(c, p, start, split))

    def cavity(
        self,
        c: Complex[MeshDatum],
        p: int,
        start: tuple[Tri, MeshDatum],
        split: tuple[int, int, int] | None = None,
    ) -> Cavity:
        """The conflict search of :meth:`insert`, without building anything: which triangles go, and the boundary.

        Reads ``c`` only (no complex operation that makes a version): the refinement decides on the
        boundary whether the point would encroach a subsegment before paying for the new version. O(k).
        """
        conflicts = self.conflicts
        pred = self.pred
        crossing = edge_key(split[0], split[1]) if split is not None else None
        off_line = 0
        if split is not None:
            off_line = pred.orient2d_sign(split[0], split[1], p)
            if off_line:
                lo, hi = self.vertex(split[0]), self.vertex(split[1])
                found0 = self.S.neighbour(c, (lo, hi) if off_line > 0 else (hi, lo))
                if found0 is None:
                    raise MeshError(f"internal: no triangle beside the subsegment {crossing} on the side of point {p}")
                start = found0
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
        neighbour = self.S.neighbours(c)  # one version read many times: each vertex's list fetched once
        # The incircle filter inlined (the predicates' own filter, the same operations), exact when it cannot tell;
        # counted runs go through the predicates.
        rows = pred.filter_rows if pred.stats is None else None
        px, py = pred.filter_rows[p]
        while stack:
            u, w, dat = stack.pop()
            forced = False
            seg = -1
            if dat[2]:
                lo, hi = (u, w) if u < w else (w, u)
                for ca, cb, cs in dat[2]:  # constraint_of(dat, u, w), inlined
                    if ca == lo and cb == hi:
                        seg = cs
                        break
                if seg >= 0:
                    if (lo, hi) != crossing:
                        boundary.append((u, w, dat[1], seg))
                        continue
                    forced = True  # the subsegment split: both triangles beside it go
            found = neighbour((w, u))
            assert found is not None, "a closed surface has a triangle beyond every edge"
            ntri, ndat = found
            nid = ndat[0]
            if nid in cavity:
                continue
            if nid not in rejected:
                x0, x1, x2 = ntri
                if forced and off_line:
                    inside = ndat[1] != EXTERIOR
                elif rows is None or x0 < 0 or x1 < 0 or x2 < 0:
                    inside = conflicts(ntri, p)
                else:
                    ax, ay = rows[x0]
                    bx, by = rows[x1]
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
                        inside = pred.incircle(x0, x1, x2, p) > 0
                if inside:
                    cavity[nid] = found
                    x = ntri[2]
                    stack.append((u, x, ndat))
                    stack.append((x, w, ndat))
                    continue
            rejected.add(nid)
            if forced:
                # A rounded split point with the exterior beyond the subsegment: that triangle stays, and the sliver
                # between the new chain u–p–w and the old edge is exterior.
                boundary.append((u, w, EXTERIOR, -1))
                beyond = found
            else:
                boundary.append((u, w, dat[1], seg))
        return Cavity(c, p, cavity, boundary, beyond, split)

    def build(self, cav: Cavity) -> Insertion:
        """The new version for a :class:`Cavity`: its triangles replaced by the fan from its point (one ``replace``).

        O(k) complex operations; ``cav.version`` is unchanged."""
        c, p, split, boundary, beyond = cav.version, cav.point, cav.split, cav.boundary, cav.beyond
        vp = self.vertex(p)
        inf = self.infinite
        pred = self.pred
        succ = {u: (w, region, seg) for u, w, region, seg in boundary}
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
        removed = tuple(cav.triangles.values())
        if beyond is not None:
            # Its edge is no longer a subsegment: the triangle beyond is replaced by itself without the constraint.
            assert split is not None, "only a rounded split point leaves a triangle beyond"
            gt, gd = beyond
            removed += (beyond,)
            crossing = edge_key(split[0], split[1])
            created.append((gt, self.new_datum(EXTERIOR, tuple(k for k in gd[2] if (k[0], k[1]) != crossing))))
        version = self.S.replace(c, [t for t, _ in removed], created)
        return Insertion(version, removed, tuple(created))

    # -- deletion ------------------------------------------------------------------------

    def remove(self, c: Complex[MeshDatum], v: int, start: tuple[Tri, MeshDatum]) -> Insertion:
        """Version ``c`` without the vertex ``v``: its star replaced by the Delaunay triangulation of its link.

        ``start`` is a triangle of ``c`` having ``v`` as a vertex.  ``v`` must be a
        *free* vertex: on no segment and not on the hull (every edge of its star
        unconstrained), as the circumcentres Chew's rule deletes from a subsegment's
        diametral circle are.  The link of ``v`` is a polygon, star-shaped from ``v``,
        each of whose edges has a circle through ``v`` empty of every link vertex (the
        circumcircle of its triangle with ``v``, which sees the whole star): so it is an
        edge of the Delaunay triangulation of the link vertices, which therefore
        triangulates the polygon, and that triangulation, with everything outside
        the star unchanged, is the constrained Delaunay triangulation of the points
        left (every unconstrained edge locally Delaunay).  It is built edge by edge:
        the apex over a base edge is the vertex on its inner side whose circle through
        the edge holds none of the others on that side (exact ``incircle``, SoS).
        O(k²) predicates and one ``replace`` for a star of ``k`` triangles.
        """
        vv = self.vertex(v)
        tri, dat = start
        k = tri.index(vv)
        t: Tri = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3])
        star: list[tuple[Tri, MeshDatum]] = []
        link: list[Vertex] = []
        constraints: dict[tuple[int, int], int] = {}
        region = dat[1]
        first = t[1]
        neighbour = self.S.neighbours(c)  # every lookup is from v: its list is read once
        for _ in range(1 << 16):
            if t[1] < 0 or t[2] < 0:
                raise MeshError(f"internal: vertex {v} is on the hull; only free vertices are removed")
            if dat[1] != region:
                raise MeshError(f"internal: the star of vertex {v} spans two regions")
            for lo, hi, s in dat[2]:
                if lo == v or hi == v:
                    raise MeshError(f"internal: vertex {v} is on segment {s}; only free vertices are removed")
                constraints[(lo, hi)] = s
            star.append((t, dat))
            link.append(t[1])
            found = neighbour((vv, t[2]))
            assert found is not None, "a closed surface has a triangle beyond every edge"
            t, dat = found
            if t[1] == first:
                break
        new: list[Tri] = []
        self._link_polygon(link[0], link[1], link[:1:-1], new)
        created = tuple(
            (
                tri2,
                self.new_datum(
                    region,
                    tuple(
                        (*edge_key(x, y), constraints[edge_key(x, y)])
                        for x, y in ((tri2[0], tri2[1]), (tri2[1], tri2[2]), (tri2[2], tri2[0]))
                        if edge_key(x, y) in constraints
                    ),
                ),
            )
            for tri2 in new
        )
        version = self.S.replace(c, [t2 for t2, _ in star], created)
        return Insertion(version, tuple(star), created)

    def _link_polygon(self, a: Vertex, b: Vertex, chain: list[Vertex], out: list[Tri]) -> None:
        """Triangulate the part of a deleted vertex's link left of ``a → b``, bounded by ``chain`` (from ``a``'s
        side to ``b``'s): the Delaunay triangles of the link vertices (:meth:`remove`)."""
        P = self.pred
        stack = [(a, b, chain)]
        while stack:
            a, b, chain = stack.pop()
            if not chain:
                continue
            best = -1
            for j, x in enumerate(chain):
                if P.orient2d_sign(a, b, x) > 0 and (best < 0 or P.incircle(a, b, chain[best], x) > 0):
                    best = j
            if best < 0:
                raise MeshError(f"internal: no link vertex lies inside the edge {(int(a), int(b))}")
            x = chain[best]
            out.append((a, b, x))
            stack.append((a, x, chain[:best]))
            stack.append((x, b, chain[best + 1 :]))

    # -- location ------------------------------------------------------------------------

    def locate(self, c: Complex[MeshDatum], p: int, hint: tuple[Tri, MeshDatum]) -> tuple[Tri, MeshDatum]:
        """A triangle of ``c`` in conflict with ``p``: a visibility walk from ``hint`` that ignores constraints.

        As :meth:`persistri.impl.terrain.delaunay.Triangulator.locate` (Devillers'
        stochastic walk; a ghost reached is in conflict unless ``p`` is on the line of
        its hull edge and outside it, and then every triangle is tested).  O(walk).
        """
        S, P = self.S, self.pred
        inf = self.infinite
        tri, dat = hint
        came: tuple[Vertex, Vertex] | None = None
        turn = 0
        for _ in range(1 << 22):
            if inf in tri:
                if self.conflicts(tri, p):
                    return tri, dat
                break
            a, b, cc = tri
            edges = ((a, b), (b, cc), (cc, a))
            turn += 1
            for j in range(3):
                u, w = edges[(turn + j) % 3]
                if came == (u, w):
                    continue
                if P.orient2d(u, w, p) < 0:
                    tri, dat = self.across(c, u, w)
                    came = (w, u)
                    break
            else:
                return tri, dat
        for t, d in S.items(c):
            if self.conflicts(t, p):
                return t, d
        raise MeshError(f"internal: no triangle is in conflict with point {p}")

    def walk_to(
        self, c: Complex[MeshDatum], start: tuple[Tri, MeshDatum], p: int
    ) -> tuple[Literal["found"], tuple[Tri, MeshDatum]] | tuple[Literal["blocked"], Constraint]:
        """Walk from the finite triangle ``start`` towards point ``p`` along a straight line, never crossing a segment.

        ``("found", (triangle, datum))``: the triangle containing ``p`` (SoS
        orientation; ``p`` may lie exactly on its boundary); ``("blocked", (u, w,
        segment))``: the line from ``start`` to ``p`` crosses the constrained edge
        ``{u, w}`` (``segment`` -1 for a hull edge that is no segment).  The line
        starts at the vertex of ``start`` opposite the edge ``p`` lies beyond (a
        circumcentre or off-centre of ``start`` lies beyond at most one of its
        edges: two would need two obtuse angles).  O(length).
        """
        pred = self.pred
        rows = pred.filter_rows
        counted = pred.stats is not None

        def P(a: int, b: int, c: int) -> int:
            # orient2d's filter inlined (the predicates' own, the same operations); exact or SoS when it cannot tell.
            ax, ay = rows[a]
            bx, by = rows[b]
            cx, cy = rows[c]
            acx = ax - cx
            bcx = bx - cx
            acy = ay - cy
            bcy = by - cy
            detleft = acx * bcy
            detright = acy * bcx
            det = detleft - detright
            thr = ERRBOUND_ORIENT2D * (abs(detleft) + abs(detright))
            if det > thr and not counted:
                return 1
            if det < -thr and not counted:
                return -1
            return pred.orient2d(a, b, c)

        tri, dat = start
        a, b, cc = tri
        # The first edge of start that p lies beyond (the tests are pure: the later ones are not needed).
        for r, l, v in ((a, b, cc), (b, cc, a), (cc, a, b)):
            if P(r, l, p) < 0:
                break
        else:
            return "found", start
        # The exit edge (r, l), directed as in the current triangle: r right of the line v → p, l left of it.
        inf = self.infinite
        while True:
            seg = constraint_of(dat, r, l) if dat[2] else -1
            if seg >= 0:
                return "blocked", (*edge_key(r, l), seg)
            tri, dat = self.across(c, r, l)  # (l, r, z)
            z = tri[2]
            if z == inf:
                return "blocked", (*edge_key(r, l), -1)
            if P(r, z, p) > 0 and P(z, l, p) > 0:
                return "found", (tri, dat)
            if P(v, p, z) > 0:
                l = z  # the line leaves through (r, z)
            else:
                r = z  # through (z, l)
