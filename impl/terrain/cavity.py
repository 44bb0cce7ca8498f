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
look-ups (two list reads each from the triangulator's neighbour records, or a
search of the complex's maps, O(lg n) with the red-black backend), ``O(k)``
exact ``incircle`` tests and one ``replace`` of ``O(k)`` map updates; the
redistribution ``O(m · k)`` ``orient2d`` tests for ``m`` pooled samples, in one
vectorised batch.  A module of its own because the insertion is a concept of
its own, with one caller (as the walk, :mod:`persistri.impl.terrain.walk`);
compiled by the twin with the triangulator.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from persistri.impl.complex.replace import replace_cone, same_replace
from persistri.impl.terrain.errors import TriangulationCheckError
from persistri.impl.terrain.insertion import EMPTY, NO_SECTOR, Insertion, IntArray, Samples, fan_samples, third

if TYPE_CHECKING:
    from persistri.impl.terrain.delaunay import Triangulator

__all__ = ["insert", "insert_linked"]


def insert(T: Triangulator, p: int, start: int) -> Insertion:
    """``T.insert(p, start)``: insert point ``p`` from the live triangle ``start``, which must be in conflict with it
    (module docstring).  Returns the :class:`~persistri.impl.terrain.insertion.Insertion`; the new version is
    also ``T.complex``.  O(k) look-ups and tests for a cavity of ``k`` triangles, plus the samples' sort."""
    cx = T.complex
    # The look-ups read the triangulator's neighbour records when it keeps them (edge_index=True), else the
    # complex: one version only, whose neighbour function reads each vertex's list from the map once (shared
    # with the locate before it).
    adj = T.adj
    if adj is not None:
        return insert_linked(T, adj, p, start)
    neighbour = T.neighbours()
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
    # The triangle holding the directed edge (a, b): tri0 itself.  Records (x, datum) and datum as tuples of
    # any length: compiled, their items are read directly (Any indexes generically; a fixed-length tuple
    # type would unbox them).
    rec: tuple[Any, ...]
    found: Any = neighbour((a, b))
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
    while edges:
        u, w = edges.pop()
        # The triangle (w, u, x) across (u, w): x and its datum.
        ntri: tuple[Any, ...]
        nb: Any = neighbour((w, u))
        assert nb is not None, "a closed surface: every oriented edge has its reverse"
        rec = nb
        ntri = rec[0]
        x = ntri[2]
        datum = rec[1]
        nid = datum[0]
        if nid in inside:
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

    ring, closed = _ring(p, bound, ends, j, check)
    nfan = len(ring) - 1
    own, samples, counts, sector = _fan_lists(T, p, lists, ring, closed, nfan, check)

    # The new version: the cavity removed, the fan added (one replace, or the paper's rem and add each).
    tri_of = T.tri_of
    for rid in removed:
        del tri_of[rid]
    created: list[tuple[Any, ...]] = []  # (id, triangle) pairs, kept boxed
    fan: list[tuple[Any, ...]] = []  # (triangle, datum) pairs, kept boxed (see above)
    tid = T._next_id
    u = ring[0]
    for i in range(nfan):
        w = ring[i + 1]
        tri: Any = (u, w, vp)
        if check and T.pred.orient2d_sign(u, w, p) <= 0:
            raise TriangulationCheckError(f"insert: point {p} makes the flat or inverted triangle {tri}")
        tid_obj: Any = tid  # boxed once (compiled), stored three times
        tri_of[tid_obj] = tri  # as _new_id, inlined: once per fan triangle
        fan.append((tri, (tid_obj, own[i])))
        created.append((tid_obj, tri))
        tid += 1
        u = w
    T._next_id = tid
    if not closed:
        # The two ghosts on the new hull edges (ring[-1], p) and (p, ring[0]).
        for tri in ((ring[-1], inf, vp), (inf, ring[0], vp)):
            fan.append((tri, (T._new_id(tri), EMPTY)))
    T.live += len(fan) - len(removed)
    cx = _new_version(T, p, cx, removed_tris, fan)
    return Insertion(p, cx, removed, created, samples, counts, not closed, ring, sector, own)


def insert_linked(T: Triangulator, adj: list[Any], p: int, start: int) -> Insertion:
    """:func:`insert` through the triangulator's neighbour records (``T.adj``, ``edge_index=True``): the same
    cavity, searched in the same order, the same fan and the same new version, with the neighbour across each
    edge read from the records (two list reads) instead of the complex, and the records updated for the fan.

    A record is ``[triangle, datum, n0, n1, n2, mark]`` (:class:`~persistri.impl.terrain.delaunay.Triangulator`):
    ``nk`` the id of the triangle across the record's edge ``k``; ``mark`` tells, during one search, a triangle
    found in the cavity or found outside it (two objects made for the search: an identity test each, where
    the search kept two sets of ids).  O(k) for a cavity of ``k`` triangles.
    """
    cplx = T.complex
    pp: Any = p  # p as an object, for the vertex table and the kernel's tests (compiled: boxed once)
    vp = T._verts.get(pp)
    if vp is None:
        vp = T.new_vertex(pp)
    # Triangles, records and ids are typed Any here: compiled by mypyc (the twin), a local of a fixed-length
    # tuple type is unboxed and every store of it boxes a new tuple, and an int is boxed at every use as an item.
    sid: Any = start
    check = T.check
    R: list[Any] | None = adj[start] if 0 <= start < len(adj) else None
    if R is None:
        raise TriangulationCheckError(f"insert: start triangle {start} is not in the current version")
    tri0: Any = R[0]
    if check and not T.conflicts(tri0, p):
        raise TriangulationCheckError(f"insert: point {p} is not in conflict with the start triangle {tri0}")
    a, b, c = tri0
    datum: tuple[Any, ...] = R[1]
    # This search's two marks (the records' last item): in the cavity, and outside it.
    mark_in: list[Any] = []
    mark_out: list[Any] = []
    R[5] = mark_in
    removed: list[Any] = [sid]
    removed_tris = [tri0]
    part: Any = datum[1]
    lists: list[Samples] = [] if part is EMPTY else [part]  # the removed triangles' sample lists (the scattered points have none)
    # The cavity's boundary edges (u, w) in the order found, by their first vertices u: clockwise around the
    # cavity (as in insert), with the record beyond each and the position of the edge (w, u) in it.
    bound: list[Any] = []
    ends: list[Any] = []
    outer: list[Any] = []
    inf = T.infinite
    kern = T.kernel
    uncounted = not T.counted
    # incircle's filter, written out below (kernel2d's statements, in its order: the same determinant): its
    # rows and its static threshold, +inf when the run is counted (every test then goes to the kernel's
    # method, which counts it).  A determinant within the threshold, or a row not made yet, goes to the method.
    rows = kern._rows
    ic_static: float = kern._ic_static if uncounted else math.inf
    # Each entry: an edge (u, w) of a cavity triangle and the id of the triangle across it, whose side is still
    # to be decided; a triangle entered across (w, u) is (w, u, x) in some rotation: only its other two edges
    # are queued, (u, x) then (x, w) (the same order as insert's).
    edges = [(a, b, R[2]), (b, c, R[3]), (c, a, R[4])]
    j = -1
    nid: Any
    ni: int  # the id unboxed, to index adj as a list (compiled: no generic item read)
    k: int
    while edges:
        u, w, nid = edges.pop()
        ni = nid
        Rn: list[Any] = adj[ni]
        ntri: tuple[Any, ...] = Rn[0]
        mark = Rn[5]
        if mark is mark_in:
            continue
        # The rotation of (w, u, x) in the record: k the position of w, the edge (w, u) its edge k.
        if ntri[0] is w:
            k = 0
            x = ntri[2]
        elif ntri[1] is w:
            k = 1
            x = ntri[0]
        else:
            k = 2
            x = ntri[1]
        if check:
            T._check_indexed(w, u, (ntri, Rn[1]))
        if mark is not mark_out:
            if x is inf:
                hit = T.ghost_conflict(w, u, p)
            elif w is inf:
                hit = T.ghost_conflict(u, x, p)
            elif u is inf:
                hit = T.ghost_conflict(x, w, p)
            else:
                # kern.incircle(w, u, x, p) > 0, its filter inlined (a call a test fewer):
                try:
                    ax, ay = rows[w]
                    bx, by = rows[u]
                    cx, cy = rows[x]
                    dx, dy = rows[pp]
                    adx = ax - dx
                    bdx = bx - dx
                    cdx = cx - dx
                    ady = ay - dy
                    bdy = by - dy
                    cdy = cy - dy
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
                except ValueError:  # a row not made yet (the kernel's method makes it)
                    det = 0.0
                if det > ic_static:
                    hit = True
                elif det < -ic_static:
                    hit = False
                else:
                    hit = (kern.incircle_uncounted(w, u, x, pp) if uncounted else kern.incircle(w, u, x, pp)) > 0
            if hit:
                Rn[5] = mark_in
                removed.append(nid)
                removed_tris.append(ntri)
                datum = Rn[1]
                part = datum[1]
                if part is not EMPTY:
                    lists.append(part)
                # (u, x) is the record's edge k + 1, (x, w) its edge k + 2.
                if k == 0:
                    edges.append((u, x, Rn[3]))
                    edges.append((x, w, Rn[4]))
                elif k == 1:
                    edges.append((u, x, Rn[4]))
                    edges.append((x, w, Rn[2]))
                else:
                    edges.append((u, x, Rn[2]))
                    edges.append((x, w, Rn[3]))
                continue
            Rn[5] = mark_out
        if u is inf:
            j = len(bound)  # the boundary passes through ∞ (p is on or beyond the hull): an open fan
        bound.append(u)
        outer.append(Rn)
        outer.append(nid)
        if check:
            ends.append(w)

    ring: list[Any]
    if j < 0 and not check:  # (_ring's closed ring, inlined: b0, b(k-1), …, b1, b0)
        ring = bound[::-1]
        ring.insert(0, bound[0])
        closed = True
    else:
        ring, closed = _ring(p, bound, ends, j, check)
    nfan = len(ring) - 1
    own: list[Samples]
    samples: Samples | None
    counts: list[int]
    sector: IntArray | None
    if lists:
        own, samples, counts, sector = _fan_lists(T, p, lists, ring, closed, nfan, check)
    else:  # (_fan_lists, inlined: the scattered points have no samples)
        own = [EMPTY] * nfan
        samples = EMPTY
        counts = [0] * nfan
        sector = NO_SECTOR

    # The records of the cavity's triangles die; the fan's are made, linked to one another around p and to
    # the records beyond the boundary (whose edge (w, u) now faces a fan triangle).
    rid: Any
    ri: int
    for rid in removed:
        ri = rid
        adj[ri] = None
    # The cycle under the cone, with the record beyond each of its edges: the ring, and ∞ when open (the two
    # ghosts last, as insert makes them).  The boundary edge under cycle edge t is the found edge (s − t) mod m.
    m = len(bound)
    s = 0 if closed else j - 1
    created: list[tuple[Any, ...]] = []  # (id, triangle) pairs, kept boxed
    fan: list[tuple[Any, ...]] = []  # (triangle, datum) pairs, kept boxed
    tid = T._next_id
    ids: list[Any] = list(range(tid, tid + m))  # the fan's ids, each boxed once (in C)
    prev: Any = ids[m - 1]
    ids.append(ids[0])  # the next triangle of the last is the first
    # The cycle's vertices: the ring, then ∞ and the ring's first vertex when the fan is open.
    cycle = ring if closed else ring + [inf, ring[0]]
    u = ring[0]
    for t in range(m):
        w = cycle[t + 1]
        tri: Any = (u, w, vp)
        if check and t < nfan and T.pred.orient2d_sign(u, w, p) <= 0:
            raise TriangulationCheckError(f"insert: point {p} makes the flat or inverted triangle {tri}")
        tid_obj: Any = ids[t]
        e = 2 * ((s - t) % m)
        # The record beyond the boundary edge (u, w): its edge (w, u), at w's position, now faces this triangle.
        Ro: list[Any] = outer[e]
        to: tuple[Any, ...] = Ro[0]
        Ro[2 if to[0] is w else (3 if to[1] is w else 4)] = tid_obj
        if t < nfan:
            d: Any = (tid_obj, own[t])
            created.append((tid_obj, tri))
        else:
            d = (tid_obj, EMPTY)
        fan.append((tri, d))
        # Edge 0 (u, w) faces the record beyond; edge 1 (w, p) the next fan triangle; edge 2 (p, u) the one before.
        adj.append([tri, d, outer[e + 1], ids[t + 1], prev, None])
        prev = tid_obj
        u = w
    T._next_id = tid + m
    T.live += m - len(removed)
    if T.stepwise or check:
        cplx = _new_version(T, p, cplx, removed_tris, fan)
    else:  # (_new_version's replace_cone, inlined)
        cplx = replace_cone(T.S, cplx, removed_tris, fan)
        T.complex = cplx
    return Insertion(p, cplx, removed, created, samples, counts, not closed, ring, sector, own)


def _ring(p: int, bound: list[Any], ends: list[Any], j: int, check: bool) -> tuple[list[Any], bool]:
    """The cavity's boundary as the fan's ring, counterclockwise, and whether it is closed, from the boundary edges'
    first vertices ``bound`` in the order found (clockwise; ``j`` the position of ∞ among them, −1 when it is not
    on the boundary).  A closed ring repeats its first vertex at the end; an open one (∞ on the boundary: the
    point is on or beyond the hull) runs from the vertex after ∞ to the vertex before it.  ``check=True``: the
    boundary a simple cycle (``ends``: the edges' second vertices).  O(k)."""
    k = len(bound)
    if check:
        if len(set(bound)) != k:
            raise TriangulationCheckError(f"insert: the cavity of point {p} is not a disc (its boundary is not one cycle)")
        if any([ends[i] is not bound[i - 1] for i in range(k)]):
            raise TriangulationCheckError(f"insert: the cavity boundary of point {p} is not a simple cycle")
    if j < 0:
        # bound = [b0, b1, …, b(k-1)] clockwise: the fan's boundary b0, b(k-1), …, b1, b0 (closed: b0 repeated).
        ring = bound[::-1]
        ring.insert(0, bound[0])
        return ring, True
    # ∞ = b(j): the open fan b(j-1), b(j-2), …, b(j+1) (indices modulo k).
    return (bound[j - 1 :: -1] + bound[k - 1 : j : -1] if j else bound[k - 1 : 0 : -1]), False


def _fan_lists(
    T: Triangulator, p: int, lists: list[Samples], ring: list[Any], closed: bool, nfan: int, check: bool
) -> tuple[list[Samples], Samples | None, list[int], IntArray | None]:
    """The samples of the removed finite triangles (``lists``), sorted into the fan's sectors and cut into the fan
    triangles' lists (:func:`~persistri.impl.terrain.insertion.fan_samples`); the scattered Delaunay's triangles
    have none: then no array is made.  O(m · nfan) for ``m`` samples."""
    if lists:
        return fan_samples(T.pred, p, lists, ring, closed, nfan, exact_floats=T.small_integers, check=check)
    return [EMPTY] * nfan, EMPTY, [0] * nfan, NO_SECTOR


def _new_version(T: Triangulator, p: int, cx: Any, removed_tris: list[Any], fan: list[tuple[Any, ...]]) -> Any:
    """The version after the insertion of ``p``: ``cx`` with the cavity ``removed_tris`` removed and the ``fan``
    added — one ``replace`` (:func:`~persistri.impl.complex.replace.replace_cone`: the fan, ghosts last, is the
    cone from the new vertex over the cavity's boundary cycle in order), or the paper's ``rem`` and ``add`` each
    (``stepwise=True``); ``check=True`` compares ``replace_cone`` with the public ``replace``.  Also
    ``T.complex``.  O(V_t·lg V + Σ δ) as ``replace``."""
    S = T.S
    if T.stepwise:
        for tri in removed_tris:
            cx = S.rem(cx, tri)
        for tri, datum in fan:
            cx = S.add(cx, tri, datum)
    elif T.check:  # the compiled entry, compared with the public replace where it changed the complex
        done = replace_cone(S, cx, removed_tris, fan)
        if not same_replace(S, done, S.replace(cx, removed_tris, fan), removed_tris, fan):
            raise TriangulationCheckError(f"insert: point {p}: replace_cone differs from replace")
        cx = done
    else:
        cx = replace_cone(S, cx, removed_tris, fan)
    T.complex = cx
    return cx
