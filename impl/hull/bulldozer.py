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

``check=True`` recomputes every sign the code derives instead of testing.

Per point and face this is at most two plane-side tests (one "can q see F",
one "which out-edge"), as the paper says (§3).  Conflict lists are tuples of
point indices, or read-only int32 numpy arrays (4 bytes a point: every
version keeps its lists) from
:data:`~persistri.impl.geometry.kernel.KERNEL_BATCH` entries on; the
kernel's ``partition`` tests a short list point by point and a long one in a
vectorised batch.  An empty list is never partitioned (nothing to test).
A run that keeps its history (``pack=True``) stores each face's datum packed
in one ``int`` (:mod:`~persistri.impl.hull.packed`), read back to these forms
when the walk expands the face.

Bookkeeping beside the complex: each point's status and associated face id
(flat arrays), and a table from face id to the face's entry ``(triangle, (id,
conflict list))`` — the very tuple the complex holds — so that the list of the
point being inserted is read from the table, not looked up in the complex (the
``stepwise`` mode reads it from the complex, as the paper's code does, so its
dictionary-operation counts stay the paper's).  The complex is what the walk
asks for adjacency (``neighbour`` across each edge, the one face holding the
reversed edge, through ``neighbours`` of the version being changed, which reads
each vertex's list once; ``findi`` in the stepwise mode); the table only mirrors
its faces.

Insertion order: a random permutation of the points from the seed; a point
that is interior when its turn comes is skipped.  This is equivalent to the
paper's choice (a face with probability proportional to its list, then a point
of it): both pick the next point uniformly among the points still outside.

Vertices: the vertex of input point ``i`` has label ``i`` and is made when
``i`` joins the hull, not for every input point — the vertex
``int_vertex.new(VertexState(lineage, i), i)`` would return (labels stay
unique: each point is inserted at most once).

Everything is iterative (no recursion), so any input size works.

Where it lives: the conflict lists, point statuses and the face table in
:mod:`~persistri.impl.hull.conflicts`; the initial tetrahedron, the first
cones and the first version in :mod:`~persistri.impl.hull.first_hull`; resuming
a run and attaching late points in :mod:`~persistri.impl.hull.resume`; ``check=True``'s verifications
in :mod:`~persistri.impl.hull.bulldozer_checks`; the state of a run and the
insertion loop here (re-exporting what this module always exported).
"""

from __future__ import annotations

from array import array
from collections.abc import Callable, Iterator, Sequence
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from persistri.impl.complex.replace import replace_trusted
from persistri.impl.complex.structure import Complex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.complex.vertex import Vertex, VertexState
from persistri.impl.geometry.kernel import Indices
from persistri.impl.geometry.predicates import Predicates3
from persistri.impl.hull.bulldozer_checks import check_bulldozed, check_sectors, check_walk
from persistri.impl.hull.conflicts import (
    INTERIOR,
    ON_HULL,
    PENDING,
    Conflict,
    Entry,
    FaceDatum,
    FaceTuple,
    IntArray,
    Triangle,
    _assign,
    _FaceTable,
    _join,
    all_but,
    tent_faces,
    triangle_array,
)
from persistri.impl.hull.errors import BulldozerCheckError
from persistri.impl.hull.first_hull import first_hull, initial_tetrahedron
from persistri.impl.hull.packed import PackedFace, conflict_list, face_id, points_of
from persistri.impl.hull.resume import attach, resume

__all__ = [
    "Bulldozer",
    "Conflict",
    "FaceDatum",
    "BulldozerCheckError",
    "initial_tetrahedron",
    "all_but",
    "triangle_array",
    "PENDING",
    "INTERIOR",
    "ON_HULL",
]


_RUN_BLOCK: Final = 1024
"""How many points of the insertion order :meth:`Bulldozer.run` filters at once by status."""

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


class Bulldozer:
    """The state of a bulldozer run: the current hull version and the association of points to faces.

    ``Bulldozer(pred, structure, tetra)`` builds the first hull (the tetrahedron
    ``tetra``, outward) and the conflict lists; :meth:`insert` adds one point
    and returns the new complex version (the old one stays valid).  ``pred``
    must have its centre (``pred.with_centroid(*tetra)``); the points are
    indices ``0 … n-1`` of ``pred``.

    ``resume=(version, faces)`` continues an earlier run instead (adding points
    to a finished hull, :mod:`persistri.impl.hull.extend`): ``version`` is its
    last version (every conflict list empty), ``faces`` its
    :meth:`face_table`; ``pred`` must index that run's points as it did, with
    the same centre (``tetra`` is that run's).  Every point is interior until
    :meth:`attach` associates it with a face.

    Cost per insertion: O(1) expected complex operations (each O(lg n) with the
    red-black backend) and O(|moved points|) plane-side tests (Theorem 11,
    §3: O(n lg n) expected in all).

    The complex changes once per insertion: one
    :meth:`~persistri.impl.complex.two_complex.TwoComplex.replace` of the lit
    faces by the tent (one map update per vertex touched).  ``stepwise=True``
    makes the same change as the paper's code does, one ``rem`` per lit face and
    one ``add`` per tent face (three map updates per face); the experiments use
    it so that their counts are the paper's.  Both give the same versions.

    ``pack=True`` stores each face's datum packed in one ``int``
    (:mod:`~persistri.impl.hull.packed`: the id and the list, run-coded when long),
    for runs that keep every version (a history holds every version's lists); the same faces, ids,
    lists and counts.  A run resumed from a packed version packs.
    """

    def __init__(
        self,
        pred: Predicates3,
        structure: TwoComplex[FaceDatum],
        tetra: tuple[int, int, int, int],
        *,
        check: bool = False,
        stepwise: bool = False,
        resume: tuple[Complex[FaceDatum], IntArray] | None = None,
        pack: bool = False,
    ) -> None:
        centre = pred.centre
        if centre is None:
            raise ValueError("the predicates need the centre point: use pred.with_centroid(*tetra)")
        self.pred = pred
        kernel = pred.kernel()
        self._o3 = kernel.orient3d
        self._partition = kernel.partition
        self._split = kernel.split
        self._signs = kernel.signs
        self.S = structure
        self.C: int = centre
        self.n: int = centre  # the input points are 0 … centre-1
        self.check = check
        self.stepwise = stepwise
        self.packed = pack
        self._lineage = VertexState.initial().lineage
        self.verts: dict[int, Vertex] = {}
        # Per point, its status and the id of its associated face (-1 before it has one; the last face's
        # id once it is interior or on the hull: read only while the point is pending): Python containers,
        # read one point at a time at Python speed, and numpy views of the same memory, for writing many.
        self._status = bytearray([INTERIOR]) * self.n
        self._assoc = array("q", [-1]) * self.n
        self.status: NDArray[np.int8] = np.frombuffer(self._status, dtype=np.int8)
        self.assoc: NDArray[np.int64] = np.frombuffer(self._assoc, dtype=np.int64)
        # Face id -> (triangle, (id, conflict list)) for every face of the current version: the same
        # entries as the complex holds, kept beside it so that a point's list is read without a lookup.
        self.faces: dict[int, Entry] = {}
        self._next_fid = 0
        self._table = _FaceTable() if check else None
        self._resumed = resume is not None
        self.complex: Complex[FaceDatum] = first_hull(self, tetra) if resume is None else self._resume(*resume)

    def _vertex(self, i: int) -> Vertex:
        """The vertex of input point ``i`` (label ``i``), made on first use."""
        v = self.verts.get(i)
        if v is None:
            # What int_vertex.new(VertexState(lineage, i), i) returns, without the state it would also make:
            # each point is inserted once, so its index is a label no other vertex of the lineage has.
            v = self.verts[i] = Vertex(i, i, self._lineage)
        return v

    # -- continuing a run ------------------------------------------------------------

    def _resume(self, cx: Complex[FaceDatum], table: IntArray) -> Complex[FaceDatum]:
        """Take over ``cx``, the last version of an earlier run, whose faces are the rows ``(id, a, b, d)`` of ``table``
        (:func:`.resume.resume`: no Python step per old face).  O(faces) vectorised."""
        return resume(self, cx, table)

    def attach(self, points: IntArray, fids: IntArray) -> Complex[FaceDatum]:
        """Associate interior-marked points with faces: ``points[j]`` lies in the cone from the centre through face ``fids[j]``.

        Those beyond their face join its list and become pending, the others stay
        interior (Appendix A.1, for points that arrive after the hull was built;
        :func:`.resume.attach`).  Returns the new version, or the current one when
        no point is outside.  O(len(points)) plane-side tests and one ``replace``.
        """
        return attach(self, points, fids)

    # -- the current version's faces --------------------------------------------------

    def triangles(self) -> IntArray:
        """The faces of the current version, outward, as an (m, 3) array of point indices.

        Read from the face table the bulldozer keeps beside the complex (face id ->
        entry, changed with every insertion; in a resumed run, the face table by id),
        so no traversal of the complex is needed.  O(m).
        """
        if self._resumed:
            table = self._table
            assert table is not None
            return table.corners[np.flatnonzero(table.live[: self._next_fid])]
        return triangle_array(tri for tri, _ in self.faces.values())

    def face_table(self) -> IntArray:
        """The faces of the current version as rows ``(id, a, b, d)``, outward: what ``resume`` takes. O(m)."""
        if self._resumed:
            table = self._table
            assert table is not None
            fids = np.flatnonzero(table.live[: self._next_fid])
            return np.column_stack([fids, table.corners[fids]]).astype(np.intp, copy=False)
        fids = np.fromiter(self.faces.keys(), dtype=np.intp, count=len(self.faces))
        return np.column_stack([fids, self.triangles()]).astype(np.intp, copy=False)

    def pending(self) -> int:
        """How many points are still outside the hull. O(n)."""
        return int(np.count_nonzero(self.status == PENDING))

    # -- one insertion ---------------------------------------------------------------

    def insert(self, p: int) -> Complex[FaceDatum]:
        """Insert the outside point ``p``; return the new hull version (Appendix A.1.2).

        Raises :class:`ValueError` if ``p`` is not outside the current hull.
        """
        status, assoc = self._status, self._assoc
        if status[p] != PENDING:
            raise ValueError(f"point {p} is not outside the current hull")
        S, check = self.S, self.check
        o3, partition, split = self._o3, self._partition, self._split
        # The centre and p as the objects every kernel call takes (compiled, an int variable is boxed anew
        # at each call of a kernel closure: a new int object for an index above 256).
        C: Any = self.C
        p_obj: Any = p
        faces = self.faces
        cx = self.complex
        # Each point is inserted once, so its vertex is new: made here, not looked up in (and added to) verts.
        vp = Vertex(p, p, self._lineage)
        fid0: Any = assoc[p]  # face ids stay int objects from here on: compiled, an int variable is re-boxed at
        # every use as a key or tuple item (a new object above 256), e.g. once per point in assoc[q] = fid below
        packed = self.packed
        entry0: tuple[Triangle, Any] = faces[fid0]
        tri0, datum0 = entry0
        lst: Indices = points_of(datum0) if packed else datum0[1]
        if self.stepwise:
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
            self._across_counted(cx) if self.stepwise else S.neighbours_unchecked(cx)
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
            if incoming:
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
                groups = (pts,)
            elif not len(pts):
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
                if first_sign > 0:
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
                    check_sectors(self, p, tri, pts, (in_ab, in_bd, in_da))
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
            check_walk(self, p, fid0, work, processed)

        # The new version: the lit faces removed, the tent added.
        for fid in processed:
            faces.pop(fid, None)  # a resumed run's old faces are not in the dict
        if self._table is not None:
            self._table.live[processed] = False
        added = tent_faces(tents, self._next_fid, faces, assoc, self.assoc, self._table, packed)
        self._next_fid += len(added)
        if self.stepwise:
            for tri in lit:
                cx = S.rem(cx, tri)
            for tent, datum in added:
                cx = S.add(cx, tent, datum)
        else:
            cx = replace_trusted(S, cx, lit, added)  # S.replace's result, compiled on the twin
        for gone in discarded:
            # Only the status: a point's associated face id means something while it is pending.
            _assign(status, self.status, gone, INTERIOR)
        status[p] = ON_HULL
        self.complex = cx
        if check:
            check_bulldozed(self, p, routed, added)
        return cx

    def _across_counted(self, cx: Complex[FaceDatum]) -> Callable[[tuple[Vertex, Vertex]], tuple[Triangle, FaceDatum] | None]:
        """The face holding a directed edge of ``cx``, by ``findi`` as the paper's code finds it (stepwise mode)."""
        findi = self.S.findi

        def across(edge: tuple[Vertex, Vertex]) -> tuple[Triangle, FaceDatum] | None:
            ((tri, datum),) = findi(cx, edge)
            return tri, datum

        return across

    # -- the whole run ---------------------------------------------------------------

    def run(self, order: IntArray, progress: Callable[[int], None] | None = None) -> Iterator[tuple[int, Complex[FaceDatum]]]:
        """Insert the points of ``order`` that are outside when their turn comes; yield ``(p, version)``.

        ``order`` is read in blocks of :data:`_RUN_BLOCK`: a point's status only
        ever leaves ``PENDING``, so the points that are interior (or on the hull)
        when a block begins are dropped from it in one vectorised step, and only
        the others are visited one by one (each rechecked at its turn).  Late in
        a run most points are interior, and this skips them at numpy speed.
        ``progress`` is called with the size of each block.
        """
        status, view = self._status, self.status
        for start in range(0, order.size, _RUN_BLOCK):
            block = order[start : start + _RUN_BLOCK]
            for p in block[view[block] == PENDING].tolist():
                if status[p] == PENDING:
                    yield p, self.insert(p)
            if progress is not None:
                progress(block.size)
