"""Point location in a version of the mesh: the visibility walk and the straight walk that stops at segments.

Two walks over one version of :class:`~persistri.impl.mesh.triangulation.MeshTriangulation`
(they read it; they make no version):

* :func:`locate` — a triangle in conflict with a point, for the constrained Delaunay
  triangulation's vertex insertions: Devillers' stochastic visibility walk, which
  ignores constraints (as :meth:`persistri.impl.terrain.delaunay.Triangulator.locate`);
* :func:`walk_to` — from a bad triangle towards its Steiner point along a straight
  line, never crossing a segment: the triangle that holds the point, or the
  subsegment that blocks it (Ruppert's refinement then splits that instead;
  :mod:`~persistri.impl.mesh.ruppert`).

They are the triangulation's :meth:`~persistri.impl.mesh.triangulation.MeshTriangulation.locate`
and :meth:`~persistri.impl.mesh.triangulation.MeshTriangulation.walk_to`.  Exact
orientations (float filter first, SoS for ties).  Costs: O(length of the walk) reads
of the version, O(lg n) each.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Literal

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.vertex import Vertex
from persistri.impl.geometry.filter import ERRBOUND_ORIENT2D
from persistri.impl.mesh.datum import Constraint, MeshDatum, MeshError, Tri, constraint_of, edge_key
from persistri.impl.mesh.edges import EdgeIndex

if TYPE_CHECKING:
    from persistri.impl.mesh.triangulation import MeshTriangulation

__all__ = ["locate", "walk_to"]


def locate(T: MeshTriangulation, c: Complex[MeshDatum], p: int, hint: tuple[Tri, MeshDatum]) -> tuple[Tri, MeshDatum]:
    """A triangle of ``c`` in conflict with ``p``: a visibility walk from ``hint`` that ignores constraints.

    As :meth:`persistri.impl.terrain.delaunay.Triangulator.locate` (Devillers'
    stochastic walk; a ghost reached is in conflict unless ``p`` is on the line of
    its hull edge and outside it, and then every triangle is tested).  O(walk).
    """
    S, P = T.S, T.pred
    inf = T.infinite
    tri, dat = hint
    came: tuple[Vertex, Vertex] | None = None
    turn = 0
    for _ in range(1 << 22):
        if inf in tri:
            if T.conflicts(tri, p):
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
                tri, dat = T.across(c, u, w)
                came = (w, u)
                break
        else:
            return tri, dat
    for t, d in S.items(c):
        if T.conflicts(t, p):
            return t, d
    raise MeshError(f"internal: no triangle is in conflict with point {p}")


def walk_to(
    T: MeshTriangulation, c: Complex[MeshDatum], start: tuple[Tri, MeshDatum], p: int, index: EdgeIndex | None = None
) -> tuple[Literal["found"], tuple[Tri, MeshDatum]] | tuple[Literal["blocked"], Constraint]:
    """Walk from the finite triangle ``start`` towards point ``p`` along a straight line, never crossing a segment.

    ``("found", (triangle, datum))``: the triangle containing ``p`` (SoS
    orientation; ``p`` may lie exactly on its boundary); ``("blocked", (u, w,
    segment))``: the line from ``start`` to ``p`` crosses the constrained edge
    ``{u, w}`` (``segment`` -1 for a hull edge that is no segment).  The line
    starts at the vertex of ``start`` opposite the edge ``p`` lies beyond (a
    circumcentre or off-centre of ``start`` lies beyond at most one of its
    edges: two would need two obtuse angles).  ``index``: an
    :data:`~persistri.impl.mesh.edges.EdgeIndex` of ``c``, read instead of the complex.  O(length).
    """
    pred = T.pred
    rows = pred.filter_rows
    # orient2d's filter inlined at each test below (the predicates' own, the same operations: ``det`` and ``thr`` of
    # orient2d(a, b, c) from ``a − c`` and ``b − c``), exact or SoS through ``pred.orient2d`` when it cannot tell;
    # counted runs go through the predicates.  Three of the four tests have ``c = p``.
    exact = pred.stats is not None
    px, py = rows[p]
    tri, dat = start
    a, b, cc = tri
    # The first edge of start that p lies beyond (the tests are pure: the later ones are not needed).
    for r, l, v in ((a, b, cc), (b, cc, a), (cc, a, b)):
        rx, ry = rows[r]
        lx, ly = rows[l]
        acx = rx - px
        bcx = lx - px
        acy = ry - py
        bcy = ly - py
        detleft = acx * bcy
        detright = acy * bcx
        det = detleft - detright
        thr = ERRBOUND_ORIENT2D * (abs(detleft) + abs(detright))
        if exact or not (det > thr or det < -thr):
            if pred.orient2d(r, l, p) < 0:  # P(r, l, p) < 0
                break
        elif det < 0.0:
            break
    else:
        return "found", start
    # The exit edge (r, l), directed as in the current triangle: r right of the line v → p, l left of it.
    inf = T.infinite
    while True:
        seg = constraint_of(dat, r, l) if dat[2] else -1
        if seg >= 0:
            return "blocked", (*edge_key(r, l), seg)
        if index is None:
            tri, dat = T.across(c, r, l)  # (l, r, z)
            z = tri[2]
        else:
            z, dat = index[(l, r)]
            tri = (l, r, z)
        if z == inf:
            return "blocked", (*edge_key(r, l), -1)
        zx, zy = rows[z]
        bcx = zx - px
        bcy = zy - py
        # P(r, z, p) > 0
        rx, ry = rows[r]
        acx = rx - px
        acy = ry - py
        detleft = acx * bcy
        detright = acy * bcx
        det = detleft - detright
        thr = ERRBOUND_ORIENT2D * (abs(detleft) + abs(detright))
        if exact or not (det > thr or det < -thr):
            right = pred.orient2d(r, z, p) > 0
        else:
            right = det > 0.0
        if right:
            # and P(z, l, p) > 0
            lx, ly = rows[l]
            acx = zx - px
            acy = zy - py
            bcx = lx - px
            bcy = ly - py
            detleft = acx * bcy
            detright = acy * bcx
            det = detleft - detright
            thr = ERRBOUND_ORIENT2D * (abs(detleft) + abs(detright))
            if exact or not (det > thr or det < -thr):
                if pred.orient2d(z, l, p) > 0:
                    return "found", (tri, dat)
            elif det > 0.0:
                return "found", (tri, dat)
        # P(v, p, z) > 0: the line leaves through (r, z), else through (z, l)
        vx, vy = rows[v]
        acx = vx - zx
        bcx = px - zx
        acy = vy - zy
        bcy = py - zy
        detleft = acx * bcy
        detright = acy * bcx
        det = detleft - detright
        thr = ERRBOUND_ORIENT2D * (abs(detleft) + abs(detright))
        if exact or not (det > thr or det < -thr):
            left = pred.orient2d(v, p, z) > 0
        else:
            left = det > 0.0
        if left:
            l = z
        else:
            r = z
