"""The visibility walk that locates a new point in the triangulator's current version (paper §5).

:meth:`~persistri.impl.terrain.delaunay.Triangulator.locate` and
:meth:`~persistri.impl.terrain.delaunay.Triangulator.locate_after` are these two
functions: :func:`walk` crosses, from a triangle, an edge that has the point
strictly beyond it until no such edge is left (the method docstrings state the
rule and why it ends); :func:`walk_from_fan` first finds the point's angle in
the fan of the insertion that made the current version, with ``orient2d``
tests instead of look-ups in the complex.  A module of its own because the
walk is a concept of its own, with one caller; compiled by the twin with the
triangulator.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from persistri.impl.terrain.errors import TriangulationCheckError
from persistri.impl.terrain.insertion import third

if TYPE_CHECKING:
    from persistri.impl.terrain.delaunay import Triangulator
    from persistri.impl.terrain.insertion import Insertion

__all__ = ["walk", "walk_from_fan"]


def walk_from_fan(T: Triangulator, p: int, last: Insertion) -> int:
    """``T.locate_after(p, last)``: the id of a live triangle in conflict with ``p``, the walk started in the fan of
    ``last`` (the method's docstring).  O(len(last.created)) ``orient2d`` tests, then the walk."""
    created = last.created
    if last.hull_vertex or last.version is not T.complex:
        return T.locate(p, created[0][0])
    kern = T.kernel  # its tests called as methods: compiled, a direct call each
    uncounted = not T.counted  # the kernel's tests need not read the predicates' stats (Triangulator.counted)
    rays: list[Any] = last.rays
    # The points as objects for the kernel's tests (compiled, an int local is boxed again at every call).
    q: Any = last.point
    pp: Any = p
    # The signs orient2d(q, r_j, p) around the fan are one run of +1 and one of -1: from r_0, scan
    # forward to the first -1 if r_0 has +1, else backward to the first +1 (about a quarter of the fan).
    nfan = len(created)
    i = -1
    # The scan's tests orient2d(q, r_j, p) with orient2d's filter written out (kernel2d's statements, a = q,
    # b = r_j, c = p: the same determinant), q's and p's parts read once; a determinant within the static
    # threshold (+inf when counted: the method counts each test), or a row not made yet, goes to the method.
    rows = kern._rows
    st: float = kern._o2_static if uncounted else math.inf
    try:
        ax, ay = rows[q]
        cx, cy = rows[pp]
    except ValueError:  # not made yet: made now with their blocks (the predicates' _row, as the kernel does)
        row = kern._pred._row
        (ax, ay), (cx, cy) = row(q), row(pp)
    acx = ax - cx
    acy = ay - cy
    r: Any = rays[0]
    det: float
    try:
        bx, by = rows[r]
        bcx = bx - cx
        bcy = by - cy
        detleft = acx * bcy
        detright = acy * bcx
        det = detleft - detright
    except ValueError:
        det = 0.0
    first = det > st or (
        not det < -st and (kern.orient2d_uncounted(q, r, pp) if uncounted else kern.orient2d(q, r, pp)) > 0
    )
    if first:
        for j in range(1, nfan):
            r = rays[j]
            try:
                bx, by = rows[r]
                bcx = bx - cx
                bcy = by - cy
                detleft = acx * bcy
                detright = acy * bcx
                det = detleft - detright
            except ValueError:
                det = 0.0
            if det > st:
                continue
            if det < -st or (kern.orient2d_uncounted(q, r, pp) if uncounted else kern.orient2d(q, r, pp)) < 0:
                i = j - 1
                break
    else:
        for j in range(nfan - 1, 0, -1):
            r = rays[j]
            try:
                bx, by = rows[r]
                bcx = bx - cx
                bcy = by - cy
                detleft = acx * bcy
                detright = acy * bcx
                det = detleft - detright
            except ValueError:
                det = 0.0
            if det < -st:
                continue
            if det > st or (kern.orient2d_uncounted(q, r, pp) if uncounted else kern.orient2d(q, r, pp)) > 0:
                i = j
                break
    if i >= 0:
        u = rays[i]
        w = rays[i + 1]
        if (kern.orient2d_uncounted(u, w, pp) if uncounted else kern.orient2d(u, w, pp)) > 0:
            tid: int = created[i][0]
            return tid
        adj = T.adj
        if adj is not None:
            # The triangle across (u, w) of fan triangle i = (u, w, q): its record's edge 0 faces it.
            nid: Any = adj[created[i][0]][2]
            Rn: list[Any] = adj[nid]
            nb: Any = (Rn[0], Rn[1])
            if T.check:
                T._check_indexed(w, u, nb)
            return walk(T, p, nid, (w, u, third(Rn[0], w)), True, 0)
        nb = T.neighbours()((w, u))
        assert nb is not None, "a closed surface: every oriented edge has its reverse"
        rec: tuple[Any, ...] = nb  # a tuple of any length: compiled, its items are read directly
        return walk(T, p, rec[1][0], rec[0], True, 0)
    # Not reached (the fan's angles cover the plane around q); kept safe all the same.
    return T.locate(p, created[0][0])


def walk(T: Triangulator, p: int, tid: int, tri: tuple[Any, ...], entered: bool, turn: int) -> int:
    """The walk of ``T.locate`` from triangle ``tri`` (id ``tid``); ``entered``: the walk came into ``tri`` across its
    first edge (a triangle found by ``neighbour((w, u))`` is ``(w, u, x)``), which it does not test again.  Each
    step one ``neighbour`` look-up and at most three ``orient2d`` tests; O(n) as a last resort (never needed)."""
    kern = T.kernel  # its tests called as methods: compiled, a direct call each
    uncounted = not T.counted  # as in walk_from_fan
    adj = T.adj  # the neighbour records of the current version, when the triangulator keeps them
    neighbour = T.neighbours() if adj is None else None
    check = T.check
    inf = T.infinite
    pp: Any = p  # an object for the kernel (as in walk_from_fan)
    limit = 4 * (len(adj) if adj is not None else len(T.tri_of)) + 16  # a bound on the live triangles, times 4
    # Each step's tests orient2d(u, w, p) with orient2d's filter written out (kernel2d's statements, c = p: the
    # same determinant), as in walk_from_fan; p's row read once.
    rows = kern._rows
    st: float = kern._o2_static if uncounted else math.inf
    try:
        cx, cy = rows[pp]
    except ValueError:  # not made yet (or a counted run, or a checked kernel): every test goes to the method
        cx = cy = 0.0
        st = math.inf
    det: float
    for _ in range(limit):
        a, b, c = tri
        if a is inf or b is inf or c is inf:  # vertices are made once each (Triangulator.vertex): identity is equality
            if T.conflicts(tri, p):
                return tid
            break
        turn += 1
        k = turn % 3
        u, w = a, b
        moved = False
        for _j in range(3):
            if k == 0:
                u, w = a, b
            elif k == 1:
                u, w = b, c
            else:
                u, w = c, a
            if k or not entered:
                try:
                    ax, ay = rows[u]
                    bx, by = rows[w]
                    acx = ax - cx
                    bcx = bx - cx
                    acy = ay - cy
                    bcy = by - cy
                    detleft = acx * bcy
                    detright = acy * bcx
                    det = detleft - detright
                except ValueError:
                    det = 0.0
                if det < -st or (
                    not det > st and (kern.orient2d_uncounted(u, w, pp) if uncounted else kern.orient2d(u, w, pp)) < 0
                ):
                    moved = True
                    break
            k = k + 1 if k < 2 else 0
        if not moved:
            return tid
        if adj is not None:
            # The record of tid names the triangle across each of its edges; (u, w) is its edge at u's position.
            R: list[Any] = adj[tid]
            t: tuple[Any, ...] = R[0]
            nid: Any = R[2] if t[0] is u else (R[3] if t[1] is u else R[4])
            Rn: list[Any] = adj[nid]
            t = Rn[0]
            if check:
                T._check_indexed(w, u, (t, Rn[1]))
            tri = (w, u, t[2] if t[0] is w else (t[0] if t[1] is w else t[1]))  # third(t, w), inlined
            tid = nid
            entered = True
            continue
        assert neighbour is not None
        nb = neighbour((w, u))
        assert nb is not None, "a closed surface: every oriented edge has its reverse"
        rec: tuple[Any, ...] = nb  # tuples of any length: compiled, their items are read directly
        tri = rec[0]
        tid = rec[1][0]
        entered = True
    for tid, tri in T.tri_of.items():
        if T.conflicts(tri, p):
            return tid
    raise TriangulationCheckError(f"locate: no triangle is in conflict with point {p}")
