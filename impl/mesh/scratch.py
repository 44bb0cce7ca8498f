"""A mutable scratch triangulation for building the constrained Delaunay triangulation in one version (paper §1).

The refinement's history starts at the constrained Delaunay triangulation of the
domain (``history[0]``); the steps that build it — each vertex inserted, each
segment recovered — are not versions anyone reads.  Making each of them a version
of the persistent 2-complex cost one ``replace`` per vertex, most of the time of
a small domain's whole mesh.  :class:`ScratchComplex` is the part of the
:class:`~persistri.impl.complex.two_complex.TwoComplex` interface that
:class:`~persistri.impl.mesh.triangulation.MeshTriangulation` and the CDT
builder use (``new``, ``add``, ``data``, ``neighbour``, ``neighbours``,
``replace``, ``items``, ``grep``), on one mutable dictionary: each "version" it
returns is the same object, changed in place, so it must only ever be used
forwards — as the builder does — and it is never a version of the history.  The
builder then writes the finished triangulation into the persistent complex with
one ``replace`` (:func:`~persistri.impl.mesh.cdt.constrained_delaunay`).

Representation: every triangle ``(a, b, c)`` (any rotation, counterclockwise) is
three directed edges ``(a, b) → (c, datum)``, ``(b, c) → (a, datum)``,
``(c, a) → (b, datum)``; on a closed surface (ghosts close the hull) each directed
edge is in at most one triangle.  ``out[v]`` is one directed edge leaving ``v``,
from which ``v``'s star is walked.  Costs: O(1) expected per lookup and per
triangle added or removed; ``grep`` O(degree); ``items`` O(N).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import Any

from persistri.impl.complex.vertex import Vertex
from persistri.impl.geometry.filter import ERRBOUND_INCIRCLE, ERRBOUND_ORIENT2D
from persistri.impl.mesh.triangulation import EXTERIOR, MeshDatum, MeshError, MeshTriangulation, Tri

__all__ = ["ScratchComplex", "insert_vertex"]

Edges = dict[tuple[Vertex, Vertex], tuple[Vertex, MeshDatum]]


class _Scratch:
    """The mutable state: the directed edges and one edge out of each vertex."""

    __slots__ = ("edges", "out")

    def __init__(self) -> None:
        self.edges: Edges = {}
        self.out: dict[Vertex, tuple[Vertex, Vertex]] = {}


class ScratchComplex:
    """The 2-complex interface of the CDT builder on one mutable :class:`_Scratch` (module docstring)."""

    def new(self, dim: int) -> Any:
        """An empty scratch triangulation (``dim`` must be 2)."""
        if dim != 2:
            raise ValueError(f"a scratch triangulation holds triangles, not {dim}-simplices")
        return _Scratch()

    def add(self, c: Any, s: Tri, x: MeshDatum) -> Any:
        """``c`` with the triangle ``s`` (datum ``x``) added; ``c`` itself, changed. O(1)."""
        self._put(c, s, x)
        return c

    def data(self, c: Any, s: Tri) -> tuple[MeshDatum] | None:
        """``(datum,)`` if the triangle ``s`` is held in this orientation, else None. O(1)."""
        a, b, cc = s
        found = c.edges.get((a, b))
        if found is None or found[0] != cc:
            return None
        return (found[1],)

    def neighbour(self, c: Any, s: tuple[Vertex, Vertex]) -> tuple[Tri, MeshDatum] | None:
        """The triangle holding the directed edge ``s = (u, w)``, as ``((u, w, x), datum)``, or None. O(1)."""
        found = c.edges.get(s)
        if found is None:
            return None
        return (s[0], s[1], found[0]), found[1]

    def neighbours(self, c: Any) -> Callable[[tuple[Vertex, Vertex]], tuple[Tri, MeshDatum] | None]:
        """``s ↦ neighbour(c, s)``."""
        edges = c.edges

        def neighbour(s: tuple[Vertex, Vertex]) -> tuple[Tri, MeshDatum] | None:
            found = edges.get(s)
            if found is None:
                return None
            return (s[0], s[1], found[0]), found[1]

        return neighbour

    def neighbours_unchecked(self, c: Any) -> Callable[[tuple[Vertex, Vertex]], tuple[Tri, MeshDatum] | None]:
        """:meth:`neighbours`: the scratch triangulation checks no edge either (the 2-complex's name for walks). O(1)."""
        return self.neighbours(c)

    def replace(self, c: Any, removed: Sequence[Tri], added: Iterable[tuple[Tri, MeshDatum]]) -> Any:
        """``c`` without the triangles ``removed`` (any rotation) and with ``added``; ``c`` itself, changed. O(k)."""
        edges = c.edges
        for a, b, cc in removed:
            for u, w, y in ((a, b, cc), (b, cc, a), (cc, a, b)):
                found = edges.pop((u, w), None)
                if found is None or found[0] != y:
                    raise MeshError(f"internal: the scratch triangulation holds no triangle {(u, w, y)}")
        for s, x in added:
            self._put(c, s, x)
        return c

    def items(self, c: Any) -> list[tuple[Tri, MeshDatum]]:
        """Each triangle once, as the rotation starting at its smallest vertex, with its datum. O(N)."""
        return [((u, w, x), d) for (u, w), (x, d) in c.edges.items() if u < w and u < x]

    def grep(self, c: Any, dim: int, s: tuple[Vertex, ...]) -> list[Tri]:
        """The triangles having the vertex ``s[0]`` (``dim`` 2, one vertex), each starting at it. O(degree)."""
        if dim != 2 or len(s) != 1:
            raise ValueError("a scratch triangulation answers grep for the triangles of one vertex only")
        (v,) = s
        first = c.out.get(v)
        if first is None:
            return []
        edges = c.edges
        out: list[Tri] = []
        u, w = first
        found = edges.get((u, w))
        if found is None:
            raise MeshError(f"internal: the scratch edge out of vertex {int(v)} is gone")
        while True:
            x = found[0]
            out.append((u, w, x))
            w = x
            if (u, w) == first:
                return out
            found = edges.get((u, w))
            if found is None:  # an open star (not on a closed surface): walk no further
                return out

    def _put(self, c: Any, s: Tri, x: MeshDatum) -> None:
        a, b, cc = s
        edges, out = c.edges, c.out
        for u, w, y in ((a, b, cc), (b, cc, a), (cc, a, b)):
            if (u, w) in edges:
                raise MeshError(f"internal: the scratch edge {(int(u), int(w))} is already in a triangle")
            edges[(u, w)] = (y, x)
            out[u] = (u, w)


def insert_vertex(T: MeshTriangulation, c: Any, p: int, hint: tuple[Tri, MeshDatum]) -> tuple[Tri, MeshDatum]:
    """Insert point ``p`` into the scratch triangulation ``c`` of ``T`` (``T.S`` a :class:`ScratchComplex`) before any
    segment is (no constraint anywhere): ``T.locate`` from ``hint``, then ``T.insert``, step for step — the same walk,
    the same conflict search, the same fan and data ids, the same entries stored in the same order — on the
    dictionary itself, with the predicates' orient2d and incircle filters inlined (the same operations as
    :func:`~persistri.impl.geometry.filter.orient2d_terms` and ``incircle_terms``, so their proved bounds hold; the
    predicates decide exactly whenever a filter cannot), and the fan's ids handed out without a call each.  The
    cavity's edges are deleted without comparing the third vertex they were read with in the same call, and the
    fan's stored without a look-up each: one size check afterwards sees a fan edge that was already there.
    Returns a finite triangle of the fan (the next walk's hint).  O(walk + cavity).
    """
    pred = T.pred
    rows = pred.filter_rows
    edges: Edges = c.edges
    out = c.out
    inf = T.infinite
    px, py = rows[p]
    # -- T.locate: the visibility walk (a ghost reached is in conflict unless p is beyond its hull edge's line).
    tri, dat = hint
    came: tuple[Vertex, Vertex] | None = None
    turn = 0
    located = False
    for _ in range(1 << 22):
        if inf in tri:
            if T.conflicts(tri, p):
                located = True
            break
        a, b, cc = tri
        turn += 1
        for j in range(3):
            k = (turn + j) % 3
            u, w = (a, b) if k == 0 else (b, cc) if k == 1 else (cc, a)
            if came is not None and came[0] == u and came[1] == w:
                continue
            ux, uy = rows[u]
            wx, wy = rows[w]
            # orient2d_terms(ux, uy, wx, wy, px, py), operation for operation.
            acx = ux - px
            bcx = wx - px
            acy = uy - py
            bcy = wy - py
            detleft = acx * bcy
            detright = acy * bcx
            det = detleft - detright
            thr = ERRBOUND_ORIENT2D * (abs(detleft) + abs(detright))
            if det < -thr:
                below = True
            elif det > thr:
                below = False
            else:
                below = pred.orient2d(u, w, p) < 0
            if below:
                found = edges.get((w, u))
                if found is None:
                    raise MeshError(f"internal: no triangle holds the edge {(int(w), int(u))}: the complex is not closed")
                tri, dat = (w, u, found[0]), found[1]
                came = (w, u)
                break
        else:
            located = True
            break
    if not located:
        for t, d in ScratchComplex().items(c):
            if T.conflicts(t, p):
                tri, dat = t, d
                break
        else:
            raise MeshError(f"internal: no triangle is in conflict with point {p}")
    # -- T.cavity: the triangles in conflict with p, reached from the located one (no edge is constrained yet).
    cavity: dict[int, tuple[Tri, MeshDatum]] = {dat[0]: (tri, dat)}
    rejected: set[int] = set()
    boundary: list[tuple[Vertex, Vertex, int]] = []
    a, b, cc = tri
    stack = [(a, b, dat), (b, cc, dat), (cc, a, dat)]
    while stack:
        u, w, sdat = stack.pop()
        found = edges.get((w, u))
        if found is None:
            raise MeshError("internal: a closed surface has a triangle beyond every edge")
        x, ndat = found
        nid = ndat[0]
        if nid in cavity:
            continue
        if nid not in rejected:
            if w < 0 or u < 0 or x < 0:
                inside = T.conflicts((w, u, x), p)
            else:
                ax, ay = rows[w]
                bx, by = rows[u]
                cx, cy = rows[x]
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
                    inside = pred.incircle(w, u, x, p) > 0
            if inside:
                cavity[nid] = ((w, u, x), ndat)
                stack.append((u, x, ndat))
                stack.append((x, w, ndat))
                continue
        rejected.add(nid)
        boundary.append((u, w, sdat[1]))
    # -- T.build and ScratchComplex.replace: the fan from p, the cavity's edges popped, the fan's edges put.
    vp = T.vertex(p)
    succ = {u: (w, region) for u, w, region in boundary}
    if len(succ) != len(boundary):
        raise MeshError(f"internal: the cavity of point {p} is not a disc")
    first = succ[inf][0] if inf in succ else boundary[0][0]
    created: list[tuple[Tri, MeshDatum]] = []
    u = first
    tid = T._next_id  # T.new_datum's ids, handed out here in the same order
    while True:
        w, region = succ[u]
        if w == inf:
            break
        created.append(((u, w, vp), (tid, region, ())))
        tid += 1
        u = w
        if u == first:
            break
    if inf in succ:
        # An open fan: p is on the hull; two ghosts close it, on the new hull edges (p, u) and (first, p).
        created.append(((u, inf, vp), (tid, EXTERIOR, ())))
        created.append(((inf, first, vp), (tid + 1, EXTERIOR, ())))
        tid += 2
    T._next_id = tid
    # The cavity's triangles were read from this dictionary in this call, so each edge is there with its third
    # vertex (a missing one would raise KeyError); the fan's edges are its boundary edges, just freed, and spokes
    # to the new vertex: none is present, and the size check below would see one that was (a store that replaces).
    expected = len(edges) + 3 * (len(created) - len(cavity))
    for (ta, tb, tc), _ in cavity.values():
        del edges[(ta, tb)]
        del edges[(tb, tc)]
        del edges[(tc, ta)]
    for (ta, tb, tc), d in created:
        edges[(ta, tb)] = (tc, d)
        edges[(tb, tc)] = (ta, d)
        edges[(tc, ta)] = (tb, d)
        out[ta] = (ta, tb)
        out[tb] = (tb, tc)
        out[tc] = (tc, ta)
    if len(edges) != expected:
        raise MeshError(f"internal: the fan of point {p} overlaps the scratch triangulation")
    hint = created[0]
    if inf in hint[0]:
        return next((t, d) for t, d in created if inf not in t)
    return hint
