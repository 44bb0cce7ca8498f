"""Deleting a free vertex from a version: its star replaced by the Delaunay triangulation of its link (Chew 1989).

Chew's rule in the refinement (:mod:`~persistri.impl.mesh.ruppert`) deletes the
circumcentres that lie in a subsegment's diametral circle before splitting it;
:func:`remove_vertex` makes the version without such a vertex — one ``replace``,
one new version, the old one unchanged (paper §1: every step a version).  It is
:meth:`MeshTriangulation.remove <persistri.impl.mesh.triangulation.MeshTriangulation.remove>`.

Costs: O(k²) exact predicates (float-filtered) and one ``replace`` for a star of
``k`` triangles, through the trusted entry the insertions use
(:meth:`~persistri.impl.mesh.triangulation.MeshTriangulation._replace`).  The refinement
itself never makes a version for a deletion: it takes :func:`star_replacement` and
composes it with the split that follows into that split's one ``replace``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.vertex import Vertex
from persistri.impl.geometry.filter import ERRBOUND_INCIRCLE, ERRBOUND_ORIENT2D
from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.datum import Insertion, MeshDatum, MeshError, Tri
from persistri.impl.mesh.edges import EdgeIndex, EdgeReader, edge_reader

if TYPE_CHECKING:
    from persistri.impl.mesh.triangulation import MeshTriangulation

__all__ = ["remove_vertex", "star_replacement", "link_polygon"]


def remove_vertex(
    T: MeshTriangulation, c: Complex[MeshDatum], v: int, start: tuple[Tri, MeshDatum], index: EdgeIndex | None = None
) -> Insertion:
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
    ``index``: an :data:`~persistri.impl.mesh.edges.EdgeIndex` of ``c``, read instead of
    the complex.  O(k²) predicates and one ``replace`` for a star of ``k`` triangles.
    """
    get = index.get if index is not None else edge_reader(T.S, c)  # every lookup is from v (edges of its star)
    star, created = star_replacement(T, v, start, get)
    # The trusted entry the insertions use (compiled on the twin; compared with the public replace when T.check is on).
    version = T._replace(c, [t2 for t2, _ in star], list(created))
    return Insertion(version, star, created)


def star_replacement(
    T: MeshTriangulation, v: int, start: tuple[Tri, MeshDatum], get: EdgeReader
) -> tuple[tuple[tuple[Tri, MeshDatum], ...], tuple[tuple[Tri, MeshDatum], ...]]:
    """:func:`remove_vertex` without making the version: the star of ``v`` (from ``start``, read through ``get``, an
    :data:`~persistri.impl.mesh.edges.EdgeReader` of the version) and the triangles that replace it, with fresh
    data.  The refinement composes these with the split that follows them into one ``replace``
    (:meth:`~persistri.impl.mesh.triangulation.MeshTriangulation.build`'s ``before``). O(k²) predicates."""
    vv = T.vertex(v)
    tri, dat = start
    k = tri.index(vv)
    t: Tri = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3])
    star: list[tuple[Tri, MeshDatum]] = []
    link: list[Vertex] = []
    constraints: dict[tuple[int, int], int] = {}
    region = dat[1]
    first = t[1]
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
        w = t[2]
        rec = get((vv, w))
        assert rec is not None, "a closed surface has a triangle beyond every edge"
        t = (vv, w, rec[0])
        dat = rec[1]
        if w == first:
            break
    new: list[Tri] = []
    link_polygon(T.pred, link[0], link[1], link[:1:-1], new)
    # Each new triangle's constrained edges: its link edges on a segment, as (lo, hi, segment) in its edge order.
    # A loop, not nested generators (a frame each); most stars have no constrained link edge.
    made: list[tuple[Tri, MeshDatum]] = []
    for tri2 in new:
        if constraints:
            cons: list[tuple[int, int, int]] = []
            x0, x1, x2 = tri2
            for x, y in ((x0, x1), (x1, x2), (x2, x0)):
                key = (x, y) if x < y else (y, x)  # edge_key(x, y), inlined
                seg = constraints.get(key)
                if seg is not None:
                    cons.append((key[0], key[1], seg))
            made.append((tri2, T.new_datum(region, tuple(cons))))
        else:
            made.append((tri2, T.new_datum(region, ())))
    created = tuple(made)
    return tuple(star), created


def link_polygon(P: GrowingPredicates2, a: Vertex, b: Vertex, chain: list[Vertex], out: list[Tri]) -> None:
    """Triangulate the part of a deleted vertex's link left of ``a → b``, bounded by ``chain`` (from ``a``'s
    side to ``b``'s): the Delaunay triangles of the link vertices (:func:`remove_vertex`). O(k²) for ``k`` link
    vertices."""
    # The predicates' orient2d and incircle filters inlined (the same operations, so their proved bounds hold; exact
    # whenever a filter cannot tell, NaN rows included); counted runs go through the predicates.
    rows = P.filter_rows if P.stats is None else None
    stack = [(a, b, chain)]
    while stack:
        a, b, chain = stack.pop()
        if not chain:
            continue
        best = -1
        if rows is None:
            for j, x in enumerate(chain):
                if P.orient2d_sign(a, b, x) > 0 and (best < 0 or P.incircle(a, b, chain[best], x) > 0):
                    best = j
        else:
            ax, ay = rows[a]
            bx, by = rows[b]
            ex = ey = 0.0  # the filter copy of chain[best]
            for j, x in enumerate(chain):
                dx, dy = rows[x]
                # orient2d_terms(ax, ay, bx, by, dx, dy): is x left of a → b?
                adx = ax - dx
                bdx = bx - dx
                ady = ay - dy
                bdy = by - dy
                detleft = adx * bdy
                detright = ady * bdx
                det = detleft - detright
                thr = ERRBOUND_ORIENT2D * (abs(detleft) + abs(detright))
                if not det > thr and (det < -thr or P.orient2d_sign(a, b, x) <= 0):
                    continue
                if best >= 0:
                    # incircle_terms(ax, ay, bx, by, ex, ey, dx, dy): is x inside the circle through a, b, chain[best]?
                    edx = ex - dx
                    edy = ey - dy
                    bdxedy = bdx * edy
                    edxbdy = edx * bdy
                    alift = adx * adx + ady * ady
                    edxady = edx * ady
                    adxedy = adx * edy
                    blift = bdx * bdx + bdy * bdy
                    adxbdy = adx * bdy
                    bdxady = bdx * ady
                    elift = edx * edx + edy * edy
                    det = alift * (bdxedy - edxbdy) + blift * (edxady - adxedy) + elift * (adxbdy - bdxady)
                    perm = (
                        (abs(bdxedy) + abs(edxbdy)) * alift
                        + (abs(edxady) + abs(adxedy)) * blift
                        + (abs(adxbdy) + abs(bdxady)) * elift
                    )
                    thr = ERRBOUND_INCIRCLE * perm
                    if not det > thr and (det < -thr or P.incircle(a, b, chain[best], x) < 0):
                        continue
                best = j
                ex, ey = dx, dy
        if best < 0:
            raise MeshError(f"internal: no link vertex lies inside the edge {(int(a), int(b))}")
        x = chain[best]
        out.append((a, b, x))
        stack.append((a, x, chain[:best]))
        stack.append((x, b, chain[best + 1 :]))
