"""One insertion of the bulldozer: the walking graph, the bulldozing and the tent (paper Appendix A.1.2).

:func:`insert` adds the outside point ``p`` to the current hull of a
:class:`~persistri.impl.hull.bulldozer.Bulldozer` and returns the new version;
it is the paper's three operations of the incremental update done together
(Appendix A.1):

1. remove the faces ``p`` can see, found by walking the **walking graph**
   (Definition 1) from ``p``'s associated face in topological order
   (Kahn's algorithm: a face is processed once every arc into it has been);
2. add the **tent**: a face ``(u, w, p)`` on every horizon edge ``(u, w)``;
3. **bulldoze** the points of the removed faces: each is pushed along the
   arcs of the walking graph — across the edge its projected ray ``p → q``
   leaves through (Definition 5, Theorem 3) — dropped as interior as soon as
   it cannot see a face on its way (Theorem 7), and at a horizon edge either
   joins the conflict list of the tent face there (Theorem 6) or is interior.

Every test is an exact ``orient3d`` with Simulation of Simplicity
(:class:`~persistri.impl.geometry.predicates.Predicates3`, through its
unvalidated :class:`~persistri.impl.geometry.kernel.Orient3dKernel`), so
the algorithm runs on a point set in general position — the paper's standing
assumption — and its output is a valid hull of the real points.  With the sign
convention ``orient3d(a, b, c, q) = -1`` iff ``q`` is beyond the plane of the
outward face ``(a, b, c)``:

* ``p`` sees face ``F = (a, b, d)``  ⇔  ``orient3d(a, b, d, p) < 0``;
* arc ``F → G`` across the edge ``e = (u, w)`` of ``F`` (third vertex ``f``)  ⇔
  the plane through ``e`` and ``c`` has ``p`` on ``f``'s side:
  ``orient3d(u, w, c, p) == orient3d(u, w, c, f)`` (Definition 1; the proof in
  ``proofs/proof_walking.py`` reduces it to this sign).  The centre is strictly
  behind every face, ``orient3d(u, w, f, c) = +1``, and swapping the last two
  points negates the sign, so ``orient3d(u, w, c, f) = -1`` always: the arc
  test is **one** sign per edge, ``orient3d(u, w, c, p) = -1``.  Seen from
  ``G``, across ``(w, u)``, the sign is the opposite one, so the edge is tested
  once and each edge between two visible faces is an arc in exactly one
  direction;
* which of two out-edges sharing the vertex ``v`` the projected ray ``p → q``
  crosses: the side of ``q`` with respect to the plane through ``c``, ``p``
  and ``v`` (it contains the projection direction ``c → p``), compared with the
  side of the out-edge's other end ``x`` — which is again a sign already known:
  ``orient3d(c, p, v, x) = ±orient3d(v, x, c, p)``, an out-arc's sign.

``check=True`` recomputes every sign the code derives instead of testing
(:mod:`~persistri.impl.hull.bulldozer_checks`).

Per point and face this is at most two plane-side tests (one "can q see F",
one "which out-edge"), as the paper says (§3); the kernel's ``split`` makes a
face's routing and the tests against its tents in one pass.  An empty list is
never partitioned (nothing to test).  The list of the point being inserted is
read from the run's face table, not looked up in the complex (the ``stepwise``
mode reads it from the complex, as the paper's code does, so that its
dictionary-operation counts stay the paper's); the face across an edge is the
complex's ``neighbour`` in the version being changed (``findi`` in the stepwise
mode).  The new version is one ``replace`` of the lit faces by the tent, or
the paper's ``rem`` and ``add`` per face in the stepwise mode.

Cost: O(1) expected complex operations per insertion (each O(lg n) with the
red-black backend) and O(|moved points|) plane-side tests (Theorem 11, §3).
Compiled in the compiled twin (``tools/compiled_twin.py``): it is the hull's
innermost loop.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, Final

import numpy as np

from persistri.impl.complex.replace import replace_trusted
from persistri.impl.complex.structure import Complex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.complex.vertex import Vertex
from persistri.impl.geometry.kernel import SCALAR_BELOW, Indices
from persistri.impl.hull.bulldozer_checks import check_bulldozed, check_sectors, check_walk
from persistri.impl.hull.conflicts import (
    INTERIOR,
    ON_HULL,
    PENDING,
    Conflict,
    FaceDatum,
    FaceTuple,
    Triangle,
    _assign,
    _join,
    tent_faces,
)
from persistri.impl.hull.errors import BulldozerCheckError
from persistri.impl.hull.packed import PackedFace, conflict_list, face_id, points_of

if TYPE_CHECKING:
    from persistri.impl.hull.bulldozer import Bulldozer

__all__ = ["insert", "across_counted"]


_HORIZON: Final = -1
"""The face id of an out-edge that leads off the visible region (a horizon edge)."""


Out = tuple[Vertex, Vertex, int, Triangle | None, Conflict | PackedFace]
"""An out-edge ``(u, w, face id, triangle, conflict list)`` of a visible face; the id is
:data:`_HORIZON` (and the triangle None) for a horizon edge.  The neighbour's triangle and list
ride along so that the neighbour can be expanded when the walk first reaches it (in a packed run,
its packed datum: decoded when the neighbour is expanded, not for every neighbour read)."""


_Visible = list[Any]
"""Bookkeeping of one visible face during one insertion (local to the insertion, never persistent): the list
``[tri, own, incoming, indeg, outs]`` — the triangle, its conflict list (all see it), the lists of points
bulldozed into it along arcs (not yet tested), the number of arcs into it from faces not processed yet,
and its out-edges in the edge order (a, b), (b, d), (d, a).  A list, not an object with attributes:
interpreted, making one costs a third of calling a class's ``__init__``, four times an insertion."""


def insert(bd: Bulldozer, p: int) -> Complex[FaceDatum]:
    """Insert the outside point ``p`` into ``bd``'s current hull; return the new version (Appendix A.1.2).

    ``bd``'s state (the current version, the face table, each point's status and
    associated face) moves to the new version; the old version is not changed.
    Raises :class:`ValueError` if ``p`` is not outside the current hull.
    O(1) expected complex operations and O(|moved points|) plane-side tests.
    """
    status, assoc = bd._status, bd._assoc
    if status[p] != PENDING:
        raise ValueError(f"point {p} is not outside the current hull")
    S, check = bd.S, bd.check
    o3, partition, split = bd._o3, bd._partition, bd._split
    sift = bd._sift if bd.pred.stats is None else None  # counted runs count each partition as it is called
    # The centre and p as the objects every kernel call takes (compiled, an int variable is boxed anew
    # at each call of a kernel closure: a new int object for an index above 256).
    C: Any = bd.C
    p_obj: Any = p
    faces = bd.faces
    cx = bd.complex
    # Each point is inserted once, so its vertex is new: made here, not looked up in (and added to) verts.
    vp = Vertex(p, p, bd._lineage)
    fid0: Any = assoc[p]  # face ids stay int objects from here on: compiled, an int variable is re-boxed at
    # every use as a key or tuple item (a new object above 256), e.g. once per point in assoc[q] = fid below
    packed = bd.packed
    entry0: tuple[Triangle, Any] = faces[fid0]
    tri0, datum0 = entry0
    lst: Indices = points_of(datum0) if packed else datum0[1]
    if bd.stepwise:
        # The paper's code reads the list from the complex (a counted dictionary operation).
        found = S.data(cx, tri0)
        assert found is not None, "the associated face of a pending point is in the hull"
        lst = conflict_list(found[0])
    own0: Indices
    if type(lst) is np.ndarray:
        own0 = lst[lst != p]
    else:
        rest = list(lst)
        rest.remove(p)  # p is in its own face's list, once
        own0 = rest
    # The face across an edge: neighbour (one lookup, a scan that stops at the face; each vertex's list
    # read once in this version; unchecked: the walk asks only about edges of faces it read from cx), or
    # findi in stepwise mode, whose counts (the whole list scanned) are the paper's.
    # Its datum typed Any here: a tuple unpacked as one (FaceTuple below) when not packed, no cast call.
    across: Callable[[tuple[Vertex, Vertex]], tuple[Triangle, Any] | None] = (
        across_counted(S, cx) if bd.stepwise else S.neighbours_unchecked(cx)
    )

    visible: dict[int, bool] = {fid0: True}  # face id -> can p see it (each face tested once)
    work: dict[int, _Visible] = {}
    # Directed edge (u, w) of an expanded face F whose neighbour across it is visible and not
    # yet expanded -> (orient3d(u, w, c, p), F's id, F): the neighbour reads the sign from here.
    pending_edges: dict[tuple[Vertex, Vertex], tuple[int, int, Triangle]] = {}

    def expand(fid: int, tri: Triangle, own: Indices, in_cone: bool = False) -> _Visible:
        """Classify the three edges of the visible face ``tri``: horizon, out-arc or in-arc.

        ``in_cone``: ``p`` lies in the face's cone from the centre (its associated face, Theorem 6),
        so every edge ``(u, w)`` has ``orient3d(u, w, c, p) = -1`` — the cone's definition — and
        leads out; the sign is then not tested (``check=True`` tests it, and that the face has
        in-degree 0).
        """
        outs: list[Out] = []
        known_out = in_cone and not check
        indeg = 0
        a, b, d = tri
        for u, w, f in ((a, b, d), (b, d, a), (d, a, b)):
            back = (w, u)
            known = pending_edges.pop(back, None)
            if known is not None:
                # The neighbour G was expanded first; its sign for (w, u) is minus ours.
                s, gid, gtri = known
                if s > 0:
                    outs.append((u, w, gid, gtri, ()))
                else:
                    indeg += 1
                continue
            found = across(back)
            if found is None:
                raise BulldozerCheckError(f"the hull is not a closed surface: no face across edge {(u, w)} of {tri}")
            gtri, gdatum = found
            gpts: Conflict | PackedFace
            if packed:
                gid = face_id(gdatum)
                gpts = gdatum
            else:
                tup: FaceTuple = gdatum
                gid, gpts = tup
            vis = visible.get(gid)
            if vis is None:
                vis = visible[gid] = o3(gtri[0], gtri[1], gtri[2], p_obj) < 0
            if not vis:
                outs.append((u, w, _HORIZON, None, ()))
                continue
            s = -1 if known_out else o3(u, w, C, p_obj)
            if check and o3(u, w, C, f) != -1:
                raise BulldozerCheckError(f"the centre is not strictly behind face {tri} (orient3d(u, w, c, f) = +1)")
            if s < 0:
                outs.append((u, w, gid, gtri, gpts))
            else:
                indeg += 1
            pending_edges[(u, w)] = (s, fid, tri)
        rec: _Visible = [tri, own, [], indeg, outs]
        work[fid] = rec
        return rec

    first = expand(fid0, tri0, own0, in_cone=True)
    if check and (first[3] != 0 or len(first[4]) != 3):
        raise BulldozerCheckError(
            f"the associated face of point {p} has in-degree {first[3]} and out-degree "
            f"{len(first[4])} in the walking graph (expected 0 and 3)"
        )
    queue: list[Any] = [fid0]
    processed: list[Any] = []
    lit: list[Triangle] = []  # the lit faces as the walk met them (the rotation findi gave)
    tents: list[tuple[Triangle, Indices]] = []
    discarded: list[Indices] = []
    routed: list[Indices] = []  # every bulldozed point, for the checks
    # Typed once here, so that the compiled twin treats the record's items as what they are, not as objects.
    tri: Triangle
    own: Indices
    incoming: list[Indices]
    outs: list[Out]
    while queue:
        fid = queue.pop()
        tri, own, incoming, _, outs = work[fid]
        processed.append(fid)
        lit.append(tri)
        a, b, d = tri
        pts: Indices = own
        if check:
            routed.append(pts)
            routed.extend(incoming)
        # The points bulldozed in are tested against the face with the routing (sift: one pass, each point's
        # row read once) when the face has two out-edges, or one on the horizon (then with its tent's test), and
        # every list is short, where partition and split would loop over the points (the same tests and lists);
        # else by partition here.
        fused = False
        if incoming:
            # Two out-edges, or one on the horizon (the face's points then go to its tent: the sift's
            # plane is the tent's, with no second level).
            if sift is not None and (len(outs) == 2 or (len(outs) == 1 and outs[0][2] == _HORIZON)):
                total = len(pts)
                for part in incoming:
                    total += len(part)
                fused = total < SCALAR_BELOW
            if not fused:
                # The points bulldozed in across all in-arcs, tested together: those that cannot see
                # the face are inside the new hull (Theorem 7).
                sees, gone = partition(a, b, d, incoming[0] if len(incoming) == 1 else _join(incoming))
                if len(gone):
                    discarded.append(gone)
                if len(sees):
                    pts = _join([pts, sees]) if len(pts) else sees
        groups: Sequence[Indices]
        tented = False  # whether the groups of horizon out-edges were tested against their tents already
        if len(outs) == 1:
            if fused:
                # The one out-edge (u, w) is on the horizon: the points that see the face and its tent
                # (u, w, p) are the tent's list, the others interior (partition by the face, then by the tent).
                assert sift is not None
                u1, w1, _, _, _ = outs[0]
                gone, tent_kept, _, tent_gone, _ = sift(tri, pts, incoming, u1, w1, p_obj, None, None)
                if gone:
                    discarded.append(gone)
                if tent_gone:
                    discarded.append(tent_gone)
                groups = (tent_kept,)
                tented = True
            else:
                groups = (pts,)
        elif not fused and not len(pts):
            groups = ((), (), ())
        elif len(outs) == 2:
            (u1, w1, g1, _, _), (u2, w2, g2, _, _) = outs
            # Consecutive edges of (a, b, d) share a vertex v: w1 == u2, or (d, a) and (a, b): u1 == w2.
            # The out-edge (x, v) has orient3d(c, p, v, x) = -orient3d(x, v, c, p) = +1, the
            # out-edge (v, x) has orient3d(c, p, v, x) = orient3d(v, x, c, p) = -1.
            v, x, first_sign = (w1, u1, 1) if w1 == u2 else (u1, w1, -1)
            if check and o3(C, p_obj, v, x) != first_sign:
                raise BulldozerCheckError(f"the routing sign of face {tri} is not the out-arc's")
            # The routing and, for an out-edge on the horizon, its tent (u, w, p) in one pass: the points
            # routed there that see the tent stay (its list), the others are interior.
            tent1 = (u1, w1, p_obj) if g1 == _HORIZON else None
            tent2 = (u2, w2, p_obj) if g2 == _HORIZON else None
            kept1: Indices
            kept2: Indices
            gone1: Indices
            gone2: Indices
            if fused:
                assert sift is not None
                if first_sign > 0:
                    gone, kept2, gone2, kept1, gone1 = sift(tri, pts, incoming, C, p_obj, v, tent2, tent1)
                else:
                    gone, kept1, gone1, kept2, gone2 = sift(tri, pts, incoming, C, p_obj, v, tent1, tent2)
                if gone:
                    discarded.append(gone)
            elif first_sign > 0:
                kept2, gone2, kept1, gone1 = split(C, p_obj, v, pts, tent2, tent1)
            else:
                kept1, gone1, kept2, gone2 = split(C, p_obj, v, pts, tent1, tent2)
            if len(gone1):
                discarded.append(gone1)
            if len(gone2):
                discarded.append(gone2)
            groups = (kept1, kept2)
            tented = True
        elif len(outs) == 3:
            # The associated face: all three edges are out-arcs, so orient3d(c, p, x, y) = -1 for each
            # edge (x, y) and q's projection lies in sector (x, y) iff
            # orient3d(c, p, x, q) = -1 and orient3d(c, p, y, q) = +1; two tests decide it, in one pass.
            da2, in_bd, in_ab, da1 = split(C, p_obj, b, pts, (C, p_obj, d), (C, p_obj, a))
            in_da = _join([da1, da2])
            if check:
                check_sectors(bd, p, tri, pts, (in_ab, in_bd, in_da))
            groups = (in_ab, in_bd, in_da)
        else:
            raise BulldozerCheckError(f"visible face {tri} has no out-edge in the walking graph")
        for (u, w, gid, gtri, gpts), grp in zip(outs, groups):
            if gid == _HORIZON:
                # The tent face (u, w, p) keeps the points that see it; the others are interior.
                if len(grp) and not tented:
                    grp, gone = partition(u, w, p_obj, grp)
                    if len(gone):
                        discarded.append(gone)
                tents.append(((u, w, vp), grp))
                continue
            target = work.get(gid)
            if target is None:
                assert gtri is not None
                own_g: Any = points_of(gpts) if packed and type(gpts) is int else gpts
                target = expand(gid, gtri, own_g)
            if len(grp):
                into: list[Indices] = target[2]
                into.append(grp)
            indeg: int = target[3]
            indeg -= 1
            target[3] = indeg
            if indeg == 0:
                queue.append(gid)

    if check:
        check_walk(bd, p, fid0, work, processed)

    # The new version: the lit faces removed, the tent added.
    for fid in processed:
        faces.pop(fid, None)  # a resumed run's old faces are not in the dict
    if bd._table is not None:
        bd._table.live[processed] = False
    added = tent_faces(tents, bd._next_fid, faces, assoc, bd.assoc, bd._table, packed)
    bd._next_fid += len(added)
    if bd.stepwise:
        for tri in lit:
            cx = S.rem(cx, tri)
        for tent, datum in added:
            cx = S.add(cx, tent, datum)
    else:
        cx = replace_trusted(S, cx, lit, added)  # S.replace's result, compiled on the twin
    for gone in discarded:
        # Only the status: a point's associated face id means something while it is pending.
        _assign(status, bd.status, gone, INTERIOR)
    status[p] = ON_HULL
    bd.complex = cx
    if check:
        check_bulldozed(bd, p, routed, added)
    return cx


def across_counted(S: TwoComplex[FaceDatum], cx: Complex[FaceDatum]) -> Callable[[tuple[Vertex, Vertex]], tuple[Triangle, FaceDatum] | None]:
    """The face holding a directed edge of ``cx``, by ``findi`` as the paper's code finds it (stepwise mode). O(1) to make."""
    findi = S.findi

    def across(edge: tuple[Vertex, Vertex]) -> tuple[Triangle, FaceDatum] | None:
        ((tri, datum),) = findi(cx, edge)
        return tri, datum

    return across
