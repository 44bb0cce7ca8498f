"""The bulldozer's ``check=True``: every sign the insertion loop derives, recomputed and verified.

Each function raises :class:`~persistri.impl.hull.errors.BulldozerCheckError`
naming the theorem that failed (paper Appendix A): :func:`check_cones` (a
point attached to a finished hull lies in its face's cone), :func:`check_sectors`
(the projected sectors of the associated face), :func:`check_walk` (Theorem 2
and Lemma 9: the walk is a topological order of the whole visible region) and
:func:`check_bulldozed` (Theorems 6 and 7: every bulldozed point is in the
list of its associated tent face or rightly interior).  They read the state
of a :class:`~persistri.impl.hull.bulldozer.Bulldozer` and change nothing;
they run only in checked runs, so they stay interpreted in the compiled twin.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from persistri.impl.geometry.kernel import Indices
from persistri.impl.hull.conflicts import INTERIOR, PENDING, Entry, IntArray, Triangle, _as_list
from persistri.impl.hull.errors import BulldozerCheckError
from persistri.impl.hull.packed import face_id

if TYPE_CHECKING:
    from persistri.impl.hull.bulldozer import Bulldozer
    from persistri.impl.hull.insertion import _Visible

__all__ = ["check_cones", "check_sectors", "check_walk", "check_bulldozed"]


def check_cones(bd: Bulldozer, points: IntArray, fids: IntArray) -> None:
    """Each point of ``points`` in the cone from the centre through its face of ``fids`` (all three signs)."""
    if not points.size:
        return
    assert bd._table is not None
    corners = bd._table.corners[fids]
    for i, j in ((0, 1), (1, 2), (2, 0)):
        bad = np.flatnonzero(bd.pred.orient3d_many(corners[:, i], corners[:, j], bd.C, points) != -1)
        if bad.size:
            k = int(bad[0])
            raise BulldozerCheckError(
                f"point {int(points[k])} is not in the cone of face {tuple(corners[k].tolist())} it was located in"
            )


def check_sectors(bd: Bulldozer, p: int, tri: Triangle, pts: Indices, groups: tuple[Indices, Indices, Indices]) -> None:
    """The associated face's points split into the three projected sectors, each by all three signs."""
    o3, C = bd._o3, bd.C
    a, b, d = tri
    if sorted(_as_list(pts)) != sorted(q for g in groups for q in _as_list(g)):
        raise BulldozerCheckError(f"the projected sectors of face {tri} lose or repeat points")
    for (x, y), grp in zip(((a, b), (b, d), (d, a)), groups):
        if o3(C, p, x, y) != -1:
            raise BulldozerCheckError(f"edge {(x, y)} of the associated face of point {p} is not an out-arc")
        for q in _as_list(grp):
            if not (o3(C, p, x, q) == -1 and o3(C, p, y, q) == 1):
                raise BulldozerCheckError(f"point {q} is routed across edge {(x, y)} of face {tri} but its ray is not there")


def check_walk(bd: Bulldozer, p: int, fid0: int, work: dict[int, _Visible], processed: list[int]) -> None:
    """Theorem 2 and Lemma 9: the walk was a topological order of the whole visible region."""
    if len(processed) != len(work) or len(set(processed)) != len(processed):
        stuck = sorted(set(work) - set(processed))
        raise BulldozerCheckError(
            f"inserting point {p}: the walking graph has a cycle or an unreachable face "
            f"({len(stuck)} visible faces never reached in-degree 0: {stuck[:5]})"
        )
    # Independently: the faces visible to p, by a search over adjacency from the associated face.
    S, P, cx = bd.S, bd.pred, bd.complex
    seen = {fid0}
    stack = [bd.faces[fid0][0]]
    while stack:
        a, b, d = stack.pop()
        for u, w in ((a, b), (b, d), (d, a)):
            ((gtri, gdatum),) = S.findi(cx, (w, u))
            gid = face_id(gdatum)
            if gid not in seen and P.orient3d(gtri[0], gtri[1], gtri[2], p) < 0:
                seen.add(gid)
                stack.append(gtri)
    if seen != set(work):
        raise BulldozerCheckError(
            f"inserting point {p}: the walk visited {len(work)} faces but {len(seen)} visible faces "
            f"are connected to the associated face (Lemma 9)"
        )
    if len(bd.faces) <= 4096 and bd._table is not None:
        # Every face of the hull, tested at once (vectorised): the visible ones are exactly the walk's.
        fids = np.flatnonzero(bd._table.live[: bd._next_fid])
        corners = bd._table.corners[fids]
        lit = P.orient3d_many(corners[:, 0], corners[:, 1], corners[:, 2], p) < 0
        everywhere = set(fids[lit].tolist())
        if everywhere != set(work):
            raise BulldozerCheckError(
                f"inserting point {p}: {len(everywhere)} faces are visible but the walk found {len(work)} (Lemma 9)"
            )


def check_bulldozed(bd: Bulldozer, p: int, routed: list[Indices], tents: list[Entry]) -> None:
    """Theorems 6 and 7: every bulldozed point is in the list of its associated face or rightly interior.

    Independently of the walk, with the checked predicates: the ray from the
    centre to each bulldozed point ``q`` must leave the new hull through
    exactly one tent face ``(u, w, p)`` — the cone bounded by the planes
    ``(c, u, w)``, ``(c, w, p)`` and ``(c, p, u)`` — and ``q`` must be pending in
    that face's list if it is beyond the face, interior otherwise.  Vectorised
    over every (tent face, point) pair at once (the planes ``(c, x, p)`` are
    shared by the two tent faces at the horizon vertex ``x``).
    """
    P, C = bd.pred, bd.C
    parts = [np.asarray(x, dtype=np.intp) for x in routed if len(x)]
    if not parts:
        return
    pts = np.unique(np.concatenate(parts))  # a point is routed once per face it crosses
    m, k = pts.size, len(tents)
    us = np.array([t[0][0] for t in tents], dtype=np.intp)
    ws = np.array([t[0][1] for t in tents], dtype=np.intp)
    fan, at = np.unique(np.concatenate([us, ws]), return_inverse=True)  # the horizon vertices
    iu, iw = at[:k], at[k:]
    everyone = np.tile(pts, k)
    # Each tent face (u, w, p) against each point, and each fan plane (c, x, p) against each point.
    edge = P.orient3d_many(C, np.repeat(us, m), np.repeat(ws, m), everyone).reshape(k, m)
    side = P.orient3d_many(C, np.repeat(fan, m), p, np.tile(pts, fan.size)).reshape(fan.size, m)
    edge_ref = np.array([P.orient3d(C, u, w, p) for u, w in zip(us.tolist(), ws.tolist())])
    w_ref = np.array([P.orient3d(C, w, p, u) for u, w in zip(us.tolist(), ws.tolist())])
    u_ref = np.array([P.orient3d(C, p, u, w) for u, w in zip(us.tolist(), ws.tolist())])
    inside = (edge == edge_ref[:, None]) & (side[iw] == w_ref[:, None]) & (-side[iu] == u_ref[:, None])
    cones = inside.sum(axis=0)
    wrong = np.flatnonzero(cones != 1)
    if wrong.size:
        raise BulldozerCheckError(
            f"inserting point {p}: the ray to point {int(pts[wrong[0]])} leaves the tent through "
            f"{int(cones[wrong[0]])} faces"
        )
    owner = inside.argmax(axis=0)
    fids = np.array([face_id(t[1]) for t in tents], dtype=np.intp)[owner]
    beyond = P.orient3d_many(us[owner], ws[owner], p, pts) < 0
    bad = np.flatnonzero(beyond & ((bd.status[pts] != PENDING) | (bd.assoc[pts] != fids)))
    if bad.size:
        j = int(bad[0])
        raise BulldozerCheckError(
            f"inserting point {p}: point {int(pts[j])} is outside tent face {tents[int(owner[j])][0]} (its "
            f"associated face, Theorem 6) but is not in that face's list"
        )
    bad = np.flatnonzero(~beyond & (bd.status[pts] != INTERIOR))
    if bad.size:
        raise BulldozerCheckError(
            f"inserting point {p}: point {int(pts[bad[0]])} is inside the new hull but was not discarded (Theorem 7)"
        )
