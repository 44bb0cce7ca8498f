"""One insertion of the incremental Delaunay triangulation (paper §5): the cavity of a point and its fan.

:meth:`~persistri.impl.terrain.delaunay.Triangulator.insert` is :func:`insert`:
from a live triangle in conflict with the new point ``p`` (the triangulator's
conflict rule: ``incircle`` with Simulation of Simplicity, or the ghost rule),

1. the **cavity** — the triangles in conflict with ``p`` — is found by a search
   across edges, testing each neighbour once (it is connected and star-shaped
   from ``p``: the classical Bowyer–Watson lemma, which the lifting map turns
   into the bulldozer's "the visible region is connected");
2. the cavity is removed and the **fan** (the 2D tent) from ``p`` to every edge of
   its boundary is added: one new persistent version
   (:meth:`~persistri.impl.complex.two_complex.TwoComplex.replace`'s result, made by
   :func:`~persistri.impl.complex.replace.replace_cone` from the fan in the
   boundary's order, or the paper's ``rem`` and ``add`` each with ``stepwise=True``);
3. the **conflict lists** of the removed finite triangles — here *samples*, points
   not yet inserted that lie in the triangle, as if the bulldozer's centre sat at
   vertical infinity — are pooled and each sample goes to the fan triangle whose
   angular sector around ``p`` contains it: ``orient2d(p, v, q)`` against every
   boundary vertex ``v`` (the 2D version of the bulldozer's projected rays;
   :func:`~persistri.impl.terrain.insertion.fan_samples`,
   :mod:`persistri.impl.terrain.sectors`).

The fan triangles all have positive area: a fan triangle ``(u, w, p)`` over a
cavity boundary edge ``(u, w)`` could only be flat if ``p`` were on the line
``uw``; outside the segment, ``p`` is strictly outside every circle through
``u`` and ``w``, so the cavity triangle on ``(u, w)`` would not be in conflict
(unless it is the start triangle, which contains ``p``, so ``p`` is on the
segment); on the open segment, ``p`` is strictly inside every such circle and in
conflict with the ghost there, so both sides of ``(u, w)`` are in the cavity
and ``(u, w)`` is not on its boundary.  ``check=True`` asserts it exactly.

Costs per insertion: the cavity's ``k`` triangles cost ``O(k)`` neighbour
look-ups (two dictionary reads each from the triangulator's edge index, or a
search of the complex's maps, O(lg n) with the red-black backend), ``O(k)``
exact ``incircle`` tests and one ``replace`` of ``O(k)`` map updates; the
redistribution ``O(m · k)`` ``orient2d`` tests for ``m`` pooled samples, in one
vectorised batch.  A module of its own because the insertion is a concept of
its own, with one caller (as the walk, :mod:`persistri.impl.terrain.walk`);
compiled by the twin with the triangulator.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from persistri.impl.complex.replace import replace_cone, same_replace
from persistri.impl.terrain.errors import TriangulationCheckError
from persistri.impl.terrain.insertion import EMPTY, NO_SECTOR, Insertion, IntArray, Samples, fan_samples, third

if TYPE_CHECKING:
    from persistri.impl.terrain.delaunay import Triangulator

__all__ = ["insert"]


def insert(T: Triangulator, p: int, start: int) -> Insertion:
    """``T.insert(p, start)``: insert point ``p`` from the live triangle ``start``, which must be in conflict with it
    (module docstring).  Returns the :class:`~persistri.impl.terrain.insertion.Insertion`; the new version is
    also ``T.complex``.  O(k) look-ups and tests for a cavity of ``k`` triangles, plus the samples' sort."""
    S = T.S
    cx = T.complex
    # The look-ups read the index of the current version's edges when there is one (edge_index=True), else
    # the complex: one version only, whose neighbour function reads each vertex's list from the map once
    # (shared with the locate before it).
    index = T.edges
    neighbour = T.neighbours() if index is None else None
    vp = T._verts.get(p)
    if vp is None:
        vp = T.vertex(p)
    # Triangles and neighbour records are typed Any in this loop: compiled by mypyc (the twin), a local of
    # a fixed-length tuple type is unboxed and every store of it (tri_of, the fan, the removed list) boxes a
    # new tuple; Any keeps the one object (1–2.6 % fewer instructions for a 20K-point Delaunay, cachegrind).
    sid: Any = start  # ids as objects: compiled, an int is boxed at every use as a key or an item
    tri0: Any = T.tri_of[sid]
    check = T.check
    if check and not T.conflicts(tri0, p):
        raise TriangulationCheckError(f"insert: point {p} is not in conflict with the start triangle {tri0}")
    a, b, c = tri0
    # The triangle holding the directed edge (a, b): tri0 itT.  Records (x, datum) and datum as tuples of
    # any length: compiled, their items are read directly (Any indexes generically; a fixed-length tuple
    # type would unbox them).
    rec: tuple[Any, ...]
    if index is not None:
        found: Any = index[a].get(b)
        if check:
            T._check_indexed(a, b, found)
        if found is None or third(found[0], a) is not c:
            raise TriangulationCheckError(f"insert: start triangle {tri0} is not in the current version")
    else:
        assert neighbour is not None
        found = neighbour((a, b))
        if found is None or found[0][2] != c:
            raise TriangulationCheckError(f"insert: start triangle {tri0} is not in the current version")
    rec = found
    datum: tuple[Any, ...] = rec[1]
    removed: list[Any] = [sid]
    removed_tris = [tri0]
    part: Any = datum[1]
    lists: list[Samples] = [] if part is EMPTY else [part]  # the removed triangles' sample lists (the scattered points have none)
    inside = {sid}
    rejected: set[int] = set()
    # The cavity's boundary edges (u, w) in the order found, by their first vertices u: clockwise around the
    # cavity (the stack expands an edge into the far triangle's other two edges, last one first: the reverse
    # of the counterclockwise order), so that edge i's w is edge i-1's u.  check=True keeps the ws and asserts it.
    bound: list[Any] = []
    ends: list[Any] = []
    inf = T.infinite
    kern = T.kernel  # its tests called as methods: compiled, a direct call each
    uncounted = not T.counted  # the kernel's tests need not read the predicates' stats (Triangulator.counted)
    # p as an object, for the kernel's tests (compiled, an int local is boxed at every call).
    pp: Any = p
    # Each entry: an edge (u, w) of a cavity triangle whose far side is still to be decided.
    # A triangle entered across (w, u) is found as (w, u, x): only its other two edges are queued.
    # (edges.pop and edges.append written out, not bound to locals: compiled, they are then list operations.)
    edges = [(a, b), (b, c), (c, a)]
    j = -1
    row_w: dict[Any, tuple[Any, ...]]  # the index's row of w (a dict: compiled, its operations are direct)
    while edges:
        u, w = edges.pop()
        # The triangle (w, u, x) across (u, w) (from the index, in the rotation it was made in): x and its datum.
        ntri: tuple[Any, ...]
        if index is not None:
            row_w = index[w]
            nb: Any = row_w.get(u)
            if check:
                T._check_indexed(w, u, nb)
            rec = nb
            ntri = rec[0]
            x = ntri[2] if ntri[0] is w else (ntri[0] if ntri[1] is w else ntri[1])  # third(ntri, w), inlined
        else:
            assert neighbour is not None
            nb = neighbour((w, u))
            assert nb is not None, "a closed surface: every oriented edge has its reverse"
            rec = nb
            ntri = rec[0]
            x = ntri[2]
        datum = rec[1]
        nid = datum[0]
        if nid in inside:
            # Both sides of (u, w) are in the cavity: (w, u) leaves the index now, (u, w) when it is looked up
            # from the other side (each directed edge is looked up once: only from the triangle across it).
            if index is not None:
                del row_w[u]
            continue
        if nid not in rejected:
            if x is inf:
                hit = T.ghost_conflict(w, u, p)
            elif w is inf:
                hit = T.ghost_conflict(u, x, p)
            elif u is inf:
                hit = T.ghost_conflict(x, w, p)
            else:
                hit = (kern.incircle_uncounted(w, u, x, pp) if uncounted else kern.incircle(w, u, x, pp)) > 0
            if hit:
                if index is not None:
                    # (u, w) and (w, u) are inside the cavity and looked up no more ((w, u) is the entry of
                    # the triangle entered, whose other two edges only are queued): both leave the index.
                    del row_w[u]
                    del index[u][w]
                inside.add(nid)
                removed.append(nid)
                removed_tris.append(ntri)
                part = datum[1]
                if part is not EMPTY:
                    lists.append(part)
                edges.append((u, x))
                edges.append((x, w))
                continue
            rejected.add(nid)
        if u is inf:
            j = len(bound)  # the boundary passes through ∞ (p is on or beyond the hull): an open fan
        bound.append(u)
        if check:
            ends.append(w)

    # The cavity boundary as one cycle, counterclockwise; a ghost edge puts ∞ on it (the point is on or beyond
    # the hull): the fan is then open, from the vertex after ∞ to the vertex before it.
    k = len(bound)
    if check:
        if len(set(bound)) != k:
            raise TriangulationCheckError(f"insert: the cavity of point {p} is not a disc (its boundary is not one cycle)")
        if any([ends[i] is not bound[i - 1] for i in range(k)]):
            raise TriangulationCheckError(f"insert: the cavity boundary of point {p} is not a simple cycle")
    closed = j < 0
    if closed:
        # bound = [b0, b1, …, b(k-1)] clockwise: the fan's boundary b0, b(k-1), …, b1, b0 (closed: b0 repeated).
        ring = bound[::-1]
        ring.insert(0, bound[0])
    else:
        # ∞ = b(j): the open fan b(j-1), b(j-2), …, b(j+1) (indices modulo k).
        ring = bound[j - 1 :: -1] + bound[k - 1 : j : -1] if j else bound[k - 1 : 0 : -1]
    nfan = len(ring) - 1

    # The samples of the removed finite triangles, sorted into the fan's sectors and cut into the fan
    # triangles' lists (insertion.fan_samples); the scattered Delaunay's triangles have none.
    own: list[Samples]
    samples: Samples | None
    counts: list[int]
    sector: IntArray | None
    if lists:
        own, samples, counts, sector = fan_samples(
            T.pred, p, lists, ring, closed, nfan, exact_floats=T.small_integers, check=check
        )
    else:
        own, samples, counts, sector = [EMPTY] * nfan, EMPTY, [0] * nfan, NO_SECTOR

    # The new version: the cavity removed, the fan added (one replace, or the paper's rem and add each).
    tri_of = T.tri_of
    for rid in removed:
        del tri_of[rid]
    created: list[tuple[Any, ...]] = []  # (id, triangle) pairs, kept boxed
    fan: list[tuple[Any, ...]] = []  # (triangle, datum) pairs, kept boxed (see above)
    tid = T._next_id
    u = ring[0]
    # The edge index (edge_index=True), whose cavity's interior edges left it in the search, takes the fan's
    # edges: each boundary edge (u, w) again, the spokes (w, p) and (p, u) new; one record (triangle, datum)
    # for the three edges of a triangle, the fan's own.  Each ring vertex's row is read once.
    row_p: dict[Any, tuple[Any, ...]] = {}
    row_u = row_p
    if index is not None:
        index[vp] = row_p
        row_u = index[u]
    for i in range(nfan):
        w = ring[i + 1]
        tri: Any = (u, w, vp)
        if check and T.pred.orient2d_sign(u, w, p) <= 0:
            raise TriangulationCheckError(f"insert: point {p} makes the flat or inverted triangle {tri}")
        tid_obj: Any = tid  # boxed once (compiled), stored three times
        tri_of[tid_obj] = tri  # as _new_id, inlined: once per fan triangle
        # Any: compiled, a local narrowed to the literal's fixed-length tuple type would be unboxed and boxed
        # anew at each store (a copy for the fan, another for the index: one record and one datum object each).
        frec: Any = (tri, (tid_obj, own[i]))
        fan.append(frec)
        created.append((tid_obj, tri))
        if index is not None:
            row_w = index[w]
            row_u[w] = row_w[vp] = row_p[u] = frec
            row_u = row_w
        tid += 1
        u = w
    T._next_id = tid
    if not closed:
        # The two ghosts on the new hull edges (ring[-1], p) and (p, ring[0]).
        for tri in ((ring[-1], inf, vp), (inf, ring[0], vp)):
            frec = (tri, (T._new_id(tri), EMPTY))
            fan.append(frec)
            if index is not None:
                ta, tb, tc = tri
                index[ta][tb] = index[tb][tc] = index[tc][ta] = frec
    if T.stepwise:
        for tri in removed_tris:
            cx = S.rem(cx, tri)
        for tri, datum in fan:
            cx = S.add(cx, tri, datum)
    elif check:  # the compiled entry, compared with the public replace where it changed the complex
        done = replace_cone(S, cx, removed_tris, fan)
        if not same_replace(S, done, S.replace(cx, removed_tris, fan), removed_tris, fan):
            raise TriangulationCheckError(f"insert: point {p}: replace_cone differs from replace")
        cx = done
    else:
        # The fan (ghosts last) is the cone from vp over the cavity's boundary cycle in order (∞ on it when
        # open): replace_cone reads each ring vertex's two new entries off it.
        cx = replace_cone(S, cx, removed_tris, fan)
    T.complex = cx
    return Insertion(p, cx, removed, created, samples, counts, not closed, ring, sector, own)

