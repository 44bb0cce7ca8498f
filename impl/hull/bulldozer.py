"""The bulldozer: a randomized incremental 3D convex hull on a persistent complex (paper §3, Appendix A).

The hull is a closed, outward-oriented 2-complex (:class:`~persistri.impl.complex.two_complex.TwoComplex`)
whose every triangle carries its **conflict list**: the not-yet-inserted points
*associated* with it.  A fixed centre point ``c`` strictly inside the first
tetrahedron defines the association: a point ``q`` outside the hull belongs to
the face through which the ray ``c → q`` leaves the hull (Appendix A.1).

One insertion of a point ``p`` (:meth:`Bulldozer.insert`) is the paper's three
operations done together:

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
(:class:`~persistri.impl.geometry.predicates.Predicates3`), so the algorithm
runs on a point set in general position — the paper's standing assumption —
and its output is a valid hull of the real points.  With the sign convention
``orient3d(a, b, c, q) = -1`` iff ``q`` is beyond the plane of the
outward face ``(a, b, c)``:

* ``p`` sees face ``F = (a, b, d)``  ⇔  ``orient3d(a, b, d, p) < 0``;
* arc ``F → G`` across the edge ``e = (u, w)`` of ``F`` (third vertex ``f``)  ⇔
  the plane through ``e`` and ``c`` has ``p`` on ``f``'s side:
  ``orient3d(u, w, c, p) == orient3d(u, w, c, f)`` (Definition 1; the proof in
  ``proofs/proof_walking.py`` reduces it to this sign);
* which of two out-edges sharing the vertex ``v`` the projected ray ``p → q``
  crosses: the side of ``q`` with respect to the plane through ``c``, ``p``
  and ``v`` (it contains the projection direction ``c → p``).

Per point and face this is at most two plane-side tests (one "can q see F",
one "which out-edge"), as the paper says (§3).  Conflict lists are numpy
arrays of point indices, tested in batches.

Insertion order: a random permutation of the points from the seed; a point
that is interior when its turn comes is skipped.  This is equivalent to the
paper's choice (a face with probability proportional to its list, then a point
of it): both pick the next point uniformly among the points still outside.

Everything is iterative (no recursion), so any input size works.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Final

import numpy as np
from numpy.typing import NDArray

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.complex.vertex import Vertex, VertexState, int_vertex
from persistri.impl.geometry.predicates import Predicates3
from persistri.impl.hull.errors import DegenerateInputError

__all__ = ["Bulldozer", "FaceDatum", "BulldozerCheckError", "initial_tetrahedron", "PENDING", "INTERIOR", "ON_HULL"]

IntArray = NDArray[np.intp]
Triangle = tuple[Vertex, Vertex, Vertex]
FaceDatum = tuple[int, IntArray]
"""The datum of a hull face: ``(face id, conflict list)``; the list is a read-only array of point indices."""

PENDING: Final = 0
"""Status of a point outside the current hull (in the conflict list of its associated face)."""
INTERIOR: Final = 1
"""Status of a point found inside the hull (discarded for good)."""
ON_HULL: Final = 2
"""Status of a point that was inserted (a vertex of the hull when inserted)."""

_EMPTY: Final[IntArray] = np.zeros(0, dtype=np.intp)
_EMPTY.setflags(write=False)


class BulldozerCheckError(AssertionError):
    """A ``check=True`` assertion of the bulldozer failed: a theorem of Appendix A did not hold."""


def _frozen(a: IntArray) -> IntArray:
    a.setflags(write=False)
    return a


def initial_tetrahedron(pred: Predicates3, n: int) -> tuple[int, int, int, int]:
    """Four points among the first ``n`` of ``pred`` spanning a tetrahedron of nonzero volume (exact).

    A fat tetrahedron is chosen from extremes (least x, farthest from it,
    farthest from their line, farthest from their plane, in floating point) and
    verified exactly; if that fails, the exact greedy
    :meth:`~persistri.impl.geometry.predicates.Predicates3.affine_basis` decides.
    Raises :class:`DegenerateInputError` naming the affine dimension when the
    points are identical, collinear or coplanar.  O(n).
    """
    pts = pred.points[:n]
    if n >= 4:
        with np.errstate(all="ignore"):
            scale = float(np.max(np.abs(pts))) or 1.0
            q = pts / scale
            i0 = int(np.argmin(q[:, 0]))
            d0 = ((q - q[i0]) ** 2).sum(axis=1)
            i1 = int(np.argmax(d0))
            u = q[i1] - q[i0]
            cr = np.cross(q - q[i0], u)
            i2 = int(np.argmax((cr**2).sum(axis=1)))
            nrm = np.cross(q[i1] - q[i0], q[i2] - q[i0])
            i3 = int(np.argmax(np.abs((q - q[i0]) @ nrm)))
        cand = (i0, i1, i2, i3)
        if len(set(cand)) == 4 and pred.orient3d_sign(*cand) != 0:
            return cand
    basis = pred.affine_basis(np.arange(n, dtype=np.intp))
    if len(basis) < 4:
        dim = len(basis) - 1
        what = {-1: "there are no points", 0: "all points are identical", 1: "all points are collinear",
                2: "all points are coplanar"}[dim]
        raise DegenerateInputError(
            f"no 3D convex hull: {what} (affine dimension {max(dim, 0)}, {n} distinct points)",
            affine_dimension=max(dim, 0),
            distinct=n,
        )
    a, b, c, d = basis
    return (a, b, c, d)


@dataclass
class _Visible:
    """Bookkeeping of one visible face during one insertion (local to the insertion, never persistent)."""

    tri: Triangle
    own: IntArray
    incoming: list[IntArray] = field(default_factory=list)
    indeg: int = 0
    outs: list[tuple[Vertex, Vertex, Vertex, int, Triangle | None, IntArray]] = field(default_factory=list)


class Bulldozer:
    """The state of a bulldozer run: the current hull version and the association of points to faces.

    ``Bulldozer(pred, structure, tetra)`` builds the first hull (the tetrahedron
    ``tetra``, outward) and the conflict lists; :meth:`insert` adds one point
    and returns the new complex version (the old one stays valid).  ``pred``
    must have its centre (``pred.with_centroid(*tetra)``); the points are
    indices ``0 … n-1`` of ``pred``.

    Cost per insertion: O(1) expected complex operations (each O(lg n) with the
    red-black backend) and O(|moved points|) plane-side tests (Theorem 11,
    §3: O(n lg n) expected in all).
    """

    def __init__(
        self,
        pred: Predicates3,
        structure: TwoComplex[FaceDatum],
        tetra: tuple[int, int, int, int],
        *,
        check: bool = False,
    ) -> None:
        centre = pred.centre
        if centre is None:
            raise ValueError("the predicates need the centre point: use pred.with_centroid(*tetra)")
        self.pred = pred
        self.S = structure
        self.C: int = centre
        self.n: int = centre  # the input points are 0 … centre-1
        self.check = check
        _, self.verts = int_vertex.new_many(VertexState.initial(), range(self.n))
        self.status: NDArray[np.int8] = np.full(self.n, INTERIOR, dtype=np.int8)
        self.assoc: IntArray = np.full(self.n, -1, dtype=np.intp)
        self.face_tri: dict[int, Triangle] = {}
        self._next_fid = 0
        self.complex: Complex[FaceDatum] = self._start(tetra)

    # -- the first hull --------------------------------------------------------------

    def _new_fid(self, tri: Triangle) -> int:
        fid = self._next_fid
        self._next_fid += 1
        self.face_tri[fid] = tri
        return fid

    def _start(self, tetra: tuple[int, int, int, int]) -> Complex[FaceDatum]:
        P, C, V = self.pred, self.C, self.verts
        a, b, c, d = tetra
        faces: list[Triangle] = []
        for (i, j, k), opp in (((a, b, c), d), ((a, d, b), c), ((b, d, c), a), ((c, d, a), b)):
            # Outward: the opposite vertex (inside) is below the face (+1).
            tri = (V[i], V[j], V[k]) if P.orient3d(i, j, k, opp) > 0 else (V[i], V[k], V[j])
            faces.append(tri)
        others = np.setdiff1d(np.arange(self.n, dtype=np.intp), np.array(tetra, dtype=np.intp))
        self.status[list(tetra)] = ON_HULL
        # The cone of face (x, y, z) from c: q on the inner side of the planes (c, x, y), (c, y, z), (c, z, x).
        side: dict[tuple[int, int], NDArray[np.int8]] = {}

        def plane_side(x: int, y: int) -> NDArray[np.int8]:
            if (x, y) in side:
                return side[(x, y)]
            if (y, x) in side:
                return -side[(y, x)]
            s = P.orient3d_batch(C, x, y, others) if others.size else np.zeros(0, dtype=np.int8)
            side[(x, y)] = s
            return s

        cx = self.S.new(2)
        claimed = np.zeros(others.size, dtype=bool)
        for tri in faces:
            x, y, z = tri
            inside = (
                (plane_side(x, y) == P.orient3d(C, x, y, z))
                & (plane_side(y, z) == P.orient3d(C, y, z, x))
                & (plane_side(z, x) == P.orient3d(C, z, x, y))
            )
            if self.check and bool(np.any(inside & claimed)):
                raise BulldozerCheckError("the cones of the first tetrahedron's faces overlap")
            claimed |= inside
            cand = others[inside]
            out = cand[P.orient3d_batch(x, y, z, cand) < 0] if cand.size else _EMPTY
            fid = self._new_fid(tri)
            self.assoc[out] = fid
            self.status[out] = PENDING
            cx = self.S.add(cx, tri, (fid, _frozen(np.array(out, dtype=np.intp))))
        if self.check and others.size and not bool(claimed.all()):
            raise BulldozerCheckError("some point lies in no cone of the first tetrahedron's faces")
        return cx

    # -- one insertion ---------------------------------------------------------------

    def pending(self) -> int:
        """How many points are still outside the hull. O(n)."""
        return int(np.count_nonzero(self.status == PENDING))

    def insert(self, p: int) -> Complex[FaceDatum]:
        """Insert the outside point ``p``; return the new hull version (Appendix A.1.2).

        Raises :class:`ValueError` if ``p`` is not outside the current hull.
        """
        if self.status[p] != PENDING:
            raise ValueError(f"point {p} is not outside the current hull")
        P, S, C, V = self.pred, self.S, self.C, self.verts
        o3, ob = P.orient3d, P.orient3d_batch
        cx = self.complex
        vp = V[p]
        fid0 = int(self.assoc[p])
        tri0 = self.face_tri[fid0]
        found = S.data(cx, tri0)
        assert found is not None, "the associated face of a pending point is in the hull"
        own0 = found[0][1]
        own0 = own0[own0 != p]

        visible: dict[int, bool] = {fid0: True}
        work: dict[int, _Visible] = {}

        def expand(fid: int, tri: Triangle, own: IntArray) -> _Visible:
            """Classify the three edges of the visible face ``tri``: horizon, out-arc or in-arc."""
            rec = _Visible(tri, own)
            a, b, d = tri
            for u, w, f in ((a, b, d), (b, d, a), (d, a, b)):
                ((gtri, (gid, gpts)),) = S.findi(cx, (w, u))
                vis = visible.get(gid)
                if vis is None:
                    vis = o3(gtri[0], gtri[1], gtri[2], p) < 0
                    visible[gid] = vis
                if not vis:
                    rec.outs.append((u, w, f, -1, None, _EMPTY))
                elif o3(u, w, C, p) == o3(u, w, C, f):
                    rec.outs.append((u, w, f, gid, gtri, gpts))
                else:
                    rec.indeg += 1
            work[fid] = rec
            return rec

        first = expand(fid0, tri0, own0)
        if self.check and (first.indeg != 0 or len(first.outs) != 3):
            raise BulldozerCheckError(
                f"the associated face of point {p} has in-degree {first.indeg} and out-degree "
                f"{len(first.outs)} in the walking graph (expected 0 and 3)"
            )
        queue = [fid0]
        processed: list[int] = []
        tents: list[tuple[Triangle, IntArray]] = []
        discarded: list[IntArray] = []
        routed: list[IntArray] = []  # every bulldozed point, for the checks
        while queue:
            fid = queue.pop()
            rec = work[fid]
            processed.append(fid)
            a, b, d = rec.tri
            if self.check:
                routed.append(rec.own)
                routed.extend(rec.incoming)
            parts = [rec.own] if rec.own.size else []
            for arr in rec.incoming:
                sees = ob(a, b, d, arr) < 0
                parts.append(arr[sees])
                discarded.append(arr[~sees])
            pts = parts[0] if len(parts) == 1 else (np.concatenate(parts) if parts else _EMPTY)
            outs = rec.outs
            groups: list[IntArray]
            if not pts.size:
                groups = [_EMPTY] * len(outs)
            elif len(outs) == 1:
                groups = [pts]
            elif len(outs) == 2:
                (u1, w1, _, _, _, _), (u2, w2, _, _, _, _) = outs
                # Consecutive edges of (a, b, d) share w1 == u2; (d, a) and (a, b) share u1 == w2.
                v, x = (w1, u1) if w1 == u2 else (u1, w1)
                side = ob(C, p, v, pts) == o3(C, p, v, x)
                groups = [pts[side], pts[~side]]
            elif len(outs) == 3:
                s_a, s_b, s_d = ob(C, p, a, pts), ob(C, p, b, pts), ob(C, p, d, pts)
                in_ab = (s_a == o3(C, p, a, b)) & (s_b == o3(C, p, b, a))
                in_bd = (s_b == o3(C, p, b, d)) & (s_d == o3(C, p, d, b))
                in_da = ~(in_ab | in_bd)
                if self.check:
                    exact_da = (s_d == o3(C, p, d, a)) & (s_a == o3(C, p, a, d))
                    if bool(np.any(in_ab & in_bd)) or not bool(np.array_equal(in_da, exact_da)):
                        raise BulldozerCheckError(f"the projected sectors of face {rec.tri} do not partition its points")
                # outs are in edge order (a,b), (b,d), (d,a) for the associated face
                groups = [pts[in_ab], pts[in_bd], pts[in_da]]
            else:
                raise BulldozerCheckError(f"visible face {rec.tri} has no out-edge in the walking graph")
            for (u, w, _f, gid, gtri, gpts), grp in zip(outs, groups):
                if gid < 0:
                    tent = (u, w, vp)
                    if grp.size:
                        sees = ob(u, w, p, grp) < 0
                        tents.append((tent, grp[sees]))
                        discarded.append(grp[~sees])
                    else:
                        tents.append((tent, _EMPTY))
                    continue
                target = work.get(gid)
                if target is None:
                    assert gtri is not None
                    target = expand(gid, gtri, gpts)
                if grp.size:
                    target.incoming.append(grp)
                target.indeg -= 1
                if target.indeg == 0:
                    queue.append(gid)

        if self.check:
            self._check_walk(p, fid0, work, processed)

        # The new version: the lit faces removed, the tent added.
        for fid in processed:
            cx = S.rem(cx, work[fid].tri)
            del self.face_tri[fid]
        new_tents: list[tuple[int, Triangle, IntArray]] = []
        for tent, kept in tents:
            fid = self._new_fid(tent)
            kept = _frozen(np.array(kept, dtype=np.intp))
            cx = S.add(cx, tent, (fid, kept))
            if kept.size:
                self.assoc[kept] = fid
            new_tents.append((fid, tent, kept))
        if discarded:
            gone = np.concatenate(discarded)
            if gone.size:
                self.status[gone] = INTERIOR
                self.assoc[gone] = -1
        self.status[p] = ON_HULL
        self.assoc[p] = -1
        self.complex = cx
        if self.check:
            self._check_bulldozed(p, routed, new_tents)
        return cx

    # -- check=True ------------------------------------------------------------------

    def _check_walk(self, p: int, fid0: int, work: dict[int, _Visible], processed: list[int]) -> None:
        """Theorem 2 and Lemma 9: the walk was a topological order of the whole visible region."""
        if len(processed) != len(work) or len(set(processed)) != len(processed):
            stuck = sorted(set(work) - set(processed))
            raise BulldozerCheckError(
                f"inserting point {p}: the walking graph has a cycle or an unreachable face "
                f"({len(stuck)} visible faces never reached in-degree 0: {stuck[:5]})"
            )
        # Independently: the faces visible to p, by a search over adjacency from the associated face.
        S, P, cx = self.S, self.pred, self.complex
        seen = {fid0}
        stack = [self.face_tri[fid0]]
        while stack:
            a, b, d = stack.pop()
            for u, w in ((a, b), (b, d), (d, a)):
                ((gtri, (gid, _)),) = S.findi(cx, (w, u))
                if gid not in seen and P.orient3d(gtri[0], gtri[1], gtri[2], p) < 0:
                    seen.add(gid)
                    stack.append(gtri)
        if seen != set(work):
            raise BulldozerCheckError(
                f"inserting point {p}: the walk visited {len(work)} faces but {len(seen)} visible faces "
                f"are connected to the associated face (Lemma 9)"
            )
        if len(self.face_tri) <= 4096:
            everywhere = {
                fid for fid, t in self.face_tri.items() if P.orient3d(t[0], t[1], t[2], p) < 0
            }
            if everywhere != set(work):
                raise BulldozerCheckError(
                    f"inserting point {p}: {len(everywhere)} faces are visible but the walk found {len(work)} (Lemma 9)"
                )

    def _in_cone(self, tri: Triangle, q: int) -> bool:
        """Whether the ray from the centre through ``q`` leaves through face ``tri`` (exact, SoS)."""
        P, C = self.pred, self.C
        x, y, z = tri
        return (
            P.orient3d(C, x, y, q) == P.orient3d(C, x, y, z)
            and P.orient3d(C, y, z, q) == P.orient3d(C, y, z, x)
            and P.orient3d(C, z, x, q) == P.orient3d(C, z, x, y)
        )

    def _check_bulldozed(self, p: int, routed: list[IntArray], tents: list[tuple[int, Triangle, IntArray]]) -> None:
        """Theorems 6 and 7: every bulldozed point is in the list of its associated face or rightly interior."""
        P = self.pred
        for arr in routed:
            for q in arr.tolist():
                cones = [(fid, tri) for fid, tri, _ in tents if self._in_cone(tri, q)]
                if len(cones) != 1:
                    raise BulldozerCheckError(
                        f"inserting point {p}: the ray to point {q} leaves the tent through {len(cones)} faces"
                    )
                fid, tri = cones[0]
                outside = P.orient3d(tri[0], tri[1], tri[2], q) < 0
                if outside and (self.status[q] != PENDING or int(self.assoc[q]) != fid):
                    raise BulldozerCheckError(
                        f"inserting point {p}: point {q} is outside tent face {tri} (its associated face, "
                        f"Theorem 6) but is not in that face's list"
                    )
                if not outside and self.status[q] != INTERIOR:
                    raise BulldozerCheckError(
                        f"inserting point {p}: point {q} is inside the new hull but was not discarded (Theorem 7)"
                    )

    # -- the whole run ---------------------------------------------------------------

    def run(self, order: IntArray, progress: Callable[[int], None] | None = None) -> Iterator[tuple[int, Complex[FaceDatum]]]:
        """Insert the points of ``order`` that are outside when their turn comes; yield ``(p, version)``."""
        status = self.status
        for p in order.tolist():
            if status[p] == PENDING:
                yield p, self.insert(p)
            if progress is not None:
                progress(1)

