"""The constrained Delaunay triangulation (CDT) of a planar straight-line graph, on the persistent 2-complex.

:func:`constrained_delaunay` builds, from a :class:`~persistri.impl.mesh.domain.PSLG`:

1. the **Delaunay triangulation of its vertices**, by the incremental
   Bowyer–Watson insertion of :mod:`~persistri.impl.mesh.triangulation` in a
   biased randomised order (:func:`~persistri.impl.terrain.scattered.insertion_order`;
   domains of at most 128 vertices in their own order),
   each point located by a walk — as :func:`~persistri.impl.terrain.scattered.delaunay`
   does, exact (SoS ties);
2. every **segment**, by removing the triangles it crosses and retriangulating
   the two cavities on either side (Anglada 1997: a cavity's boundary chain
   seen from the segment ``ab`` is triangulated by choosing the chain vertex
   ``c`` whose circle through ``a, b, c`` holds no other chain vertex — exact
   ``incircle`` with SoS, which makes the choice unique — and recursing on
   the two sub-chains).  The crossed triangles are found by a straight walk
   from ``a`` to ``b`` with exact orientations; a vertex exactly on the
   segment splits it there (both pieces keep the segment's index), and a
   segment that crosses an earlier one is a :class:`~persistri.impl.mesh.triangulation.MeshError`.
   The new edge ``ab`` is recorded as constrained in the data of both
   triangles beside it; the cavity's other edges keep their constraints;
3. the **regions**, as Triangle defines them: triangles reachable from a
   convex-hull edge that is not a segment, or from a hole point, without
   crossing a segment, are *exterior* (concavities and holes eaten away); a
   region point spreads its region over the triangles it reaches the same
   way; the remaining triangles form region 0.  The exterior is kept in the
   complex, marked (:data:`~persistri.impl.mesh.triangulation.EXTERIOR`), so
   the complex stays a closed surface (ghosts on the hull edges).

The result is Delaunay except across segments: for every edge that is not
constrained, neither triangle's circle strictly contains the opposite vertex
of the other (exact ``incircle``; ties among cocircular points decided by SoS,
so the exact sign there is 0).  Inputs at large offsets (UTM metres) are exact
like any others: every test is on the doubles' exact values.

Steps 1 and 2 run on a mutable scratch triangulation
(:class:`~persistri.impl.mesh.scratch.ScratchComplex`, through
:meth:`~persistri.impl.mesh.triangulation.MeshTriangulation.with_structure`): their
intermediate states are no versions anyone reads, and a version of the persistent
complex for each vertex cost most of a small domain's time.  Step 3 writes the
result into the persistent complex with one ``replace``: the CDT is one version,
``history[0]`` of every refinement from it.

Costs: expected O(n log n) scratch operations (O(1) each) for the vertices; a segment
crossing ``k`` triangles O(k²) ``incircle`` tests in the worst case (Anglada)
and O(k) scratch operations; the regions O(N) and one ``replace`` of N triangles.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from operator import itemgetter
from typing import Final

import numpy as np
from numpy.typing import NDArray

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.vertex import Vertex
from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.mesh.domain import PSLG
from persistri.impl.mesh.naming import InputNames
from persistri.impl.mesh.scratch import ScratchComplex, insert_vertex
from persistri.impl.mesh.triangulation import (
    EXTERIOR,
    Constraint,
    MeshDatum,
    MeshError,
    MeshTriangulation,
    Tri,
    constraint_of,
    edge_key,
)
from persistri.impl.terrain.scattered import insertion_order

__all__ = ["SegmentGeometry", "constrained_delaunay", "param_on_segment"]

IntArray = NDArray[np.intp]

_SMALL = 128
"""Domains with at most this many vertices insert them in input order (no sort: the Hilbert keys' numpy passes cost
more than the longer walks there — measured on the 96-gon, 3.5% of its whole mesh at 20°, and on 100–128 random
points; the CDT is the same in any order)."""


@dataclass
class SegmentGeometry:
    """Where the vertices on input segments are: the endpoints of each segment, and each split point's parameter.

    ``ends[s] = (A, B)`` (point indices); ``on_segment[v] = (s, t)``: Steiner
    vertex ``v`` is ``A + t (B − A)`` exactly (``t`` a dyadic rational in (0, 1));
    ``shell[v] = (o, k)``: ``v`` was placed on the concentric shell of radius
    about ``2^k`` around input vertex ``o``; ``off_segment``: the split points that
    are not exactly on their segment (rounded where no double lies on it).  Append-only: a point index, once
    given, keeps its meaning in every version (old and new, every future).
    """

    ends: list[tuple[int, int]]
    on_segment: dict[int, tuple[int, Fraction]]
    shell: dict[int, tuple[int, int]]
    n_input: int
    incident: list[int]
    """The number of segments at each input vertex."""
    off_segment: set[int] = field(default_factory=set)
    made_in: dict[int, tuple[int, int, int]] = field(default_factory=dict)
    """The bad triangle (its three corners) each inserted circumcentre or off-centre was the Steiner point of: what
    :mod:`~persistri.impl.mesh.markers` interpolates the new vertex's attributes in, as Triangle does."""
    names: InputNames = field(default_factory=InputNames)
    """How messages name the segments and input vertices (the rows the user wrote, :mod:`~persistri.impl.mesh.naming`)."""
    _at: dict[int, tuple[int, ...]] | None = field(default=None, repr=False, compare=False)

    def name(self, P: GrowingPredicates2, s: int) -> str:
        """Segment ``s`` in a message, as the user can find it (:meth:`~persistri.impl.mesh.naming.InputNames.segment`:
        its input row and the coordinates of its ends, or "the convex hull edge …"). O(1)."""
        (ax, ay), (bx, by) = P.xy(self.ends[s][0]), P.xy(self.ends[s][1])
        return self.names.segment(s, f"({ax!r}, {ay!r})", f"({bx!r}, {by!r})")

    def segments_at(self, o: int) -> tuple[int, ...]:
        """The segments with an end at input vertex ``o`` (none twice, zero-length ones left out), by index.  The
        table is built on the first call, O(segments); then O(1)."""
        at = self._at
        if at is None:
            table: dict[int, list[int]] = {}
            for t, (c, d) in enumerate(self.ends):
                if c == d:
                    continue
                table.setdefault(c, []).append(t)
                table.setdefault(d, []).append(t)
            at = self._at = {v: tuple(ts) for v, ts in table.items()}
        return at.get(o, ())


_ZERO: Final = Fraction(0)
_ONE: Final = Fraction(1)


def param_on_segment(P: GrowingPredicates2, geo: SegmentGeometry, s: int, v: int) -> Fraction:
    """The parameter ``t`` of vertex ``v`` on segment ``s``: ``v = A + t (B − A)``, exactly. O(1)."""
    a, b = geo.ends[s]
    if v == a:
        return _ZERO
    if v == b:
        return _ONE
    found = geo.on_segment.get(v)
    if found is not None and found[0] == s:
        return found[1]
    # An input vertex on the segment's interior: the exact projection.
    (pa, pb, pv), _ = P.integers(a, b, v)
    dx, dy = pb[0] - pa[0], pb[1] - pa[1]
    return Fraction((pv[0] - pa[0]) * dx + (pv[1] - pa[1]) * dy, dx * dx + dy * dy)


def _first_triangle(P: GrowingPredicates2, order: list[int]) -> tuple[int, int, int]:
    a, b = order[0], order[1]
    for c in order[2:]:
        s = P.orient2d_sign(a, b, c)
        if s:
            return (a, b, c) if s > 0 else (b, a, c)
    raise MeshError(f"all {len(order)} vertices are collinear: the domain has no area")


class _Builder:
    """The CDT construction over one :class:`MeshTriangulation` (module docstring)."""

    def __init__(self, T: MeshTriangulation, *, on_scratch: bool = False) -> None:
        self.T = T
        self.P = T.pred
        # T's structure is a ScratchComplex: vertices are inserted on its dictionary directly (scratch.insert_vertex).
        self.on_scratch = on_scratch
        # Segments already present as edges when they came: constrained in the regions' rebuild of every datum (one
        # version for all of them, not one each), in the order they came: ``edge -> (segment, order)``.
        self.marked: dict[tuple[int, int], tuple[int, int]] = {}

    def vertices(self, n: int) -> Complex[MeshDatum]:
        T, P = self.T, self.P
        pts = P.points[:n]
        # A few vertices go in their own order (the CDT does not depend on it; the sort would cost more than the walks).
        order = list(range(n)) if n <= _SMALL else [int(i) for i in insertion_order(np.asarray(pts), 0)]
        a, b, c = _first_triangle(P, order)
        V = T.vertex
        cx = T.empty()
        tri = (V(a), V(b), V(c))
        cx = T.S.add(cx, tri, T.new_datum(0))
        inf = T.infinite
        for u, w in ((a, b), (b, c), (c, a)):
            cx = T.S.add(cx, (V(w), V(u), inf), T.new_datum(EXTERIOR))
        found = T.S.data(cx, tri)
        assert found is not None, "the first triangle was just added"
        hint: tuple[Tri, MeshDatum] = (tri, found[0])
        done = {a, b, c}
        fast = self.on_scratch and P.stats is None and not T.check
        for q in order:
            if q in done:
                continue
            if fast:
                # T.locate and T.insert on the scratch dictionary, step for step (scratch.insert_vertex).
                hint = insert_vertex(T, cx, q, hint)
                continue
            start = T.locate(cx, q, hint)
            ins = T.insert(cx, q, start)
            cx = ins.version
            # The next point is near this one (Hilbert order): walk from a finite triangle of its fan.
            hint = next((t, d) for t, d in ins.created if inf not in t)
        return cx

    # -- segments --------------------------------------------------------------------------

    def segment(self, cx: Complex[MeshDatum], a: int, b: int, s: int) -> Complex[MeshDatum]:
        """``cx`` with the segment ``ab`` (input segment ``s``) present as constrained edges."""
        T, P, S = self.T, self.P, self.T.S
        va, vb = T.vertex(a), T.vertex(b)
        inf = T.infinite
        fwd = S.neighbour(cx, (va, vb))
        if fwd is not None:
            back = T.across(cx, va, vb)
            self._mark([fwd, back], (*edge_key(a, b), s))
            return cx
        # The triangle at a whose wedge holds the direction to b.
        start: tuple[Tri, MeshDatum] | None = None
        for t in S.grep(cx, 2, (va,)):
            if inf in t:
                continue
            k = t.index(va)
            x, y = t[(k + 1) % 3], t[(k + 2) % 3]
            sx = P.orient2d_sign(a, b, x)
            if sx == 0 and self._ahead(a, b, x):
                return self.segment(self.segment(cx, a, int(x), s), int(x), b, s)
            if sx < 0 and P.orient2d_sign(a, b, y) > 0:
                d = S.data(cx, t)
                assert d is not None
                start = ((va, x, y), d[0])
                break
            if P.orient2d_sign(a, b, y) == 0 and self._ahead(a, b, y):
                return self.segment(self.segment(cx, a, int(y), s), int(y), b, s)
        if start is None:
            raise MeshError(f"internal: segment {s} ({a}, {b}): no triangle at vertex {a} faces vertex {b}")
        (_, r, l), dat = start
        crossed = [start]
        left: list[Vertex] = [l]
        right: list[Vertex] = [r]
        marked = self.marked
        while True:
            seg = constraint_of(dat, r, l) if dat[2] else -1
            if seg < 0 and marked:
                seg = marked.get(edge_key(r, l), (-1, 0))[0]
            if seg >= 0:
                raise MeshError(
                    f"segment {s} (vertices {a}, {b}) crosses segment {seg} (near vertices {int(r)}, {int(l)})"
                )
            tri, dat = T.across(cx, r, l)  # (l, r, z)
            crossed.append((tri, dat))
            z = tri[2]
            if z == vb:
                break
            sz = P.orient2d_sign(a, b, z)
            if sz == 0:
                return self.segment(self.segment(cx, a, int(z), s), int(z), b, s)
            if sz > 0:
                l = z
                left.append(z)
            else:
                r = z
                right.append(z)
        constraints: dict[tuple[int, int], int] = {}
        for ctri, cdat in crossed:
            for lo, hi, sg in cdat[2]:
                constraints[(lo, hi)] = sg
            if marked:
                # A marked edge on the cavity's boundary goes into the new triangle's datum, as a datum would carry it.
                for u, w in ((ctri[0], ctri[1]), (ctri[1], ctri[2]), (ctri[2], ctri[0])):
                    found = marked.get(edge_key(u, w))
                    if found is not None:
                        constraints[edge_key(u, w)] = found[0]
        constraints[edge_key(a, b)] = s
        new: list[Tri] = []
        self._polygon(va, vb, left, new)
        self._polygon(vb, va, right[::-1], new)
        added = []
        for t in new:
            cons = tuple(
                (*edge_key(u, w), constraints[edge_key(u, w)])
                for u, w in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))
                if edge_key(u, w) in constraints
            )
            added.append((t, T.new_datum(0, cons)))
        return S.replace(cx, [t for t, _ in crossed], added)

    def _ahead(self, a: int, b: int, x: int) -> bool:
        """Whether ``x`` (on the line ``ab``) lies strictly between ``a`` and ``b``."""
        return self.P.between(a, b, x)

    def _polygon(self, a: Vertex, b: Vertex, chain: list[Vertex], out: list[Tri]) -> None:
        """Triangulate the pseudo-polygon left of ``a → b`` bounded by ``chain`` (from ``a``'s side to ``b``'s), Anglada's way."""
        incircle = self.P.incircle
        stack = [(a, b, chain)]
        while stack:
            a, b, chain = stack.pop()
            if not chain:
                continue
            i = 0
            for j in range(1, len(chain)):
                if incircle(a, b, chain[i], chain[j]) > 0:
                    i = j
            c = chain[i]
            out.append((a, b, c))
            stack.append((a, c, chain[:i]))
            stack.append((c, b, chain[i + 1 :]))

    def _mark(self, tris: list[tuple[Tri, MeshDatum]], con: Constraint) -> None:
        """Record the edge of ``tris`` (the two triangles beside it) as constrained by ``con``, unless it already is
        (a repeated segment: the first keeps it).  The data change in :meth:`regions`' rebuild. O(1)."""
        key = (con[0], con[1])
        if key in self.marked:
            return
        for _, (_, _, cons) in tris:
            if any(c[0] == con[0] and c[1] == con[1] for c in cons):
                return
        self.marked[key] = (con[2], len(self.marked))

    def _apply_marked(self, by_edge: dict[tuple[int, int], int], datas: list[MeshDatum]) -> None:
        """Give each triangle the marked constraints on its edges that its datum lacks, appended in the order they
        came (``by_edge``: directed edge -> index in ``datas``, changed in place).  O(marked edges)."""
        extra: dict[int, list[tuple[int, Constraint]]] = {}
        for (lo, hi), (seg, order) in self.marked.items():
            for key in ((lo, hi), (hi, lo)):
                k = by_edge.get(key)  # int labels: equal to their Vertex, hashed alike
                if k is None:
                    continue
                cons = datas[k][2]
                if cons and any(c[0] == lo and c[1] == hi for c in cons):
                    continue
                extra.setdefault(k, []).append((order, (lo, hi, seg)))
        for k, found in extra.items():
            found.sort()
            d = datas[k]
            datas[k] = (d[0], d[1], d[2] + tuple([con for _, con in found]))

    # -- regions ---------------------------------------------------------------------------

    def regions(
        self, cx: Complex[MeshDatum], holes: NDArray[np.float64], regions: NDArray[np.float64], target: TwoComplex[MeshDatum]
    ) -> Complex[MeshDatum]:
        """``cx`` with every triangle's region set (module docstring), as one new version of ``target`` made by one
        ``replace`` from the empty complex, its triangles in order (each from its smallest vertex, sorted)."""
        T, S = self.T, self.T.S
        inf = T.infinite
        items = S.items(cx)
        by_edge: dict[tuple[int, int], int] = {}
        tris: list[Tri] = []
        datas: list[MeshDatum] = []
        for k, (t, d) in enumerate(items):
            tris.append(t)
            datas.append(d)
            by_edge[(t[0], t[1])] = k
            by_edge[(t[1], t[2])] = k
            by_edge[(t[2], t[0])] = k
        if self.marked:
            self._apply_marked(by_edge, datas)
        region = [EXTERIOR if inf in t else -2 for t in tris]  # -2: not reached yet

        def flood(seeds: list[int], code: int) -> None:
            stack = [k for k in seeds if region[k] == -2]
            for k in stack:
                region[k] = code
            while stack:
                k = stack.pop()
                t, d = tris[k], datas[k]
                for u, w in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                    if d[2] and constraint_of(d, u, w) >= 0:
                        continue
                    j = by_edge[(w, u)]
                    if region[j] == -2:
                        region[j] = code
                        stack.append(j)

        hull_seeds = []
        for k, t in enumerate(tris):
            if inf in t:
                i = t.index(inf)
                u, w = t[(i + 1) % 3], t[(i + 2) % 3]
                if not datas[k][2] or constraint_of(datas[k], u, w) < 0:
                    hull_seeds.append(by_edge[(w, u)])
        flood(hull_seeds, EXTERIOR)
        hint = next((t, d) for t, d in items if inf not in t)
        for code, pts in ((EXTERIOR, holes), *((r + 1, regions[r : r + 1, :2]) for r in range(regions.shape[0]))):
            for x, y in np.asarray(pts, dtype=np.float64).reshape(-1, 2).tolist():
                p = self.P.append(x, y)
                t, d = T.locate(cx, p, hint)
                if inf in t:
                    continue  # outside the convex hull: nothing to eat or to mark
                k = by_edge[(t[0], t[1])]
                if region[k] == -2:
                    flood([k], code)
        added = [(t, (d[0], region[k] if region[k] != -2 else 0, d[2])) for k, (t, d) in enumerate(zip(tris, datas))]
        added.sort(key=itemgetter(0))  # by the triangle's labels (tuples compare as the labels; no two are equal)
        return target.replace(target.new(2), [], added)


def constrained_delaunay(
    T: MeshTriangulation, domain: PSLG
) -> tuple[Complex[MeshDatum], SegmentGeometry]:
    """The CDT of ``domain`` (module docstring) on ``T`` (whose points start with the domain's vertices, in order).

    Returns the version and the segments' geometry.  Segments of zero length
    (both ends one vertex) are ignored.  :class:`MeshError` for crossing
    segments or collinear vertices.  Expected O(n log n + Σ k²) (``k`` the
    triangles a segment crosses).
    """
    n = domain.vertices.shape[0]
    if n < 3:
        raise MeshError(f"{n} vertices: a domain needs at least 3 not on one line")
    # The vertices and segments go into a mutable scratch triangulation (their steps are no versions anyone reads);
    # the regions' rebuild then makes the CDT one version of T's persistent complex.
    scratch = T.with_structure(ScratchComplex())
    builder = _Builder(scratch, on_scratch=True)
    cx = builder.vertices(n)
    segs = np.asarray(domain.segments, dtype=np.intp).reshape(-1, 2)
    incident = [0] * n
    for s, (a, b) in enumerate(segs.tolist()):
        if a == b:
            continue
        incident[a] += 1
        incident[b] += 1
        cx = builder.segment(cx, a, b, s)
    cx = builder.regions(cx, domain.holes, domain.regions, T.S)
    T.take_ids_from(scratch)
    geo = SegmentGeometry(
        ends=[(int(a), int(b)) for a, b in segs.tolist()],
        on_segment={},
        shell={},
        n_input=n,
        incident=incident,
        names=InputNames.of(domain.segment_origin, domain.vertex_map),
    )
    return cx, geo
