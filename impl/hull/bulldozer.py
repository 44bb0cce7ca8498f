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
"""

from __future__ import annotations

import itertools
from array import array
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.complex.vertex import Vertex, VertexState
from persistri.impl.geometry.kernel import KERNEL_BATCH, Indices
from persistri.impl.geometry.predicates import Predicates3
from persistri.impl.hull.errors import BulldozerCheckError, DegenerateInputError

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

IntArray = NDArray[np.intp]
ListArray = NDArray[np.int32]
"""A long conflict list: 4 bytes a point, half of ``intp``'s (every version keeps its lists)."""
Triangle = tuple[Vertex, Vertex, Vertex]
Conflict = tuple[int, ...] | ListArray
"""A conflict list: point indices, a tuple below ``KERNEL_BATCH`` entries, else a read-only int32 array."""
FaceDatum = tuple[int, Conflict]
"""The datum of a hull face: ``(face id, conflict list)``."""

PENDING: Final = 0
"""Status of a point outside the current hull (in the conflict list of its associated face)."""
INTERIOR: Final = 1
"""Status of a point found inside the hull (discarded for good)."""
ON_HULL: Final = 2
"""Status of a point that was inserted (a vertex of the hull when inserted)."""

_RUN_BLOCK: Final = 1024
"""How many points of the insertion order :meth:`Bulldozer.run` filters at once by status."""

_HORIZON: Final = -1
"""The face id of an out-edge that leads off the visible region (a horizon edge)."""


def _freeze(pts: Indices) -> Conflict:
    """``pts`` as a conflict list: a tuple when short, else a read-only int32 array (a copy only when
    ``pts`` is not int32 already: partitions of int32 lists are int32)."""
    if isinstance(pts, np.ndarray):
        if len(pts) < KERNEL_BATCH:
            return tuple(pts.tolist())
        arr: ListArray = pts.astype(np.int32, copy=False)
        arr.setflags(write=False)
        return arr
    return tuple(pts)


def _join(parts: list[Indices]) -> Indices:
    """The concatenation of point lists (one array if any part is an array, else a list)."""
    if len(parts) == 1:
        return parts[0]
    for x in parts:
        if type(x) is np.ndarray:
            return np.concatenate([x if type(x) is np.ndarray else np.array(x, dtype=np.int32) for x in parts])
    out: list[int] = []
    for x in parts:
        out.extend(x)
    return out


def _as_list(pts: Indices) -> list[int]:
    return pts.tolist() if isinstance(pts, np.ndarray) else list(pts)


def _assign(table: bytearray | array[int], view: NDArray[Any], pts: Indices, value: int) -> None:
    """``table[q] = value`` for every ``q`` in ``pts``: through the numpy ``view`` of ``table`` for an array."""
    if isinstance(pts, np.ndarray):
        # numpy scatters through intp indices three times faster than through int32 ones, converting included.
        view[pts if pts.dtype == np.intp else pts.astype(np.intp)] = value
    else:
        for q in pts:
            table[q] = value


def _smallest_first(a: int, b: int, d: int) -> tuple[int, int, int]:
    """The rotation of triangle ``(a, b, d)`` that starts at its smallest vertex (same orientation)."""
    if a < b and a < d:
        return (int(a), int(b), int(d))
    if b < d:
        return (int(b), int(d), int(a))
    return (int(d), int(a), int(b))


def all_but(n: int, tetra: tuple[int, int, int, int]) -> IntArray:
    """``0 … n-1`` without the four points of ``tetra``, increasing. O(n)."""
    keep = np.ones(n, dtype=bool)
    keep[list(tetra)] = False
    return np.flatnonzero(keep).astype(np.intp, copy=False)


def triangle_array(triangles: Iterable[Triangle]) -> IntArray:
    """Triangles of vertices as an (m, 3) int array of their labels (point indices). O(m)."""
    tris = list(triangles)
    flat = np.fromiter(itertools.chain.from_iterable(tris), dtype=np.intp, count=3 * len(tris))
    return flat.reshape(-1, 3)


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
            # Scaled so that squares cannot overflow; a float heuristic, verified exactly below.  Dot
            # products by einsum, not BLAS: a threaded BLAS call leaves its worker threads spinning,
            # which costs CPU time long after the call (measured: 0.1 s at 256K points).
            scale = max(float(pts.max()), -float(pts.min())) or 1.0
            i0 = int(np.argmin(pts[:, 0]))
            dq = pts / scale  # scaled before subtracting: 1e308 - (-1e308) would overflow
            dq -= dq[i0].copy()
            d0 = np.einsum("ij,ij->i", dq, dq)  # squared distances to point i0
            i1 = int(np.argmax(d0))
            u = dq[i1]
            along = np.einsum("ij,j->i", dq, u)
            # Squared distances to the line (i0, i1), by Pythagoras: |dq|² - (dq·u)²/|u|².
            i2 = int(np.argmax(d0 - along * along / float(np.einsum("i,i->", u, u))))
            nrm = np.cross(u, dq[i2])
            i3 = int(np.argmax(np.abs(np.einsum("ij,j->i", dq, nrm))))
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


Out = tuple[Vertex, Vertex, int, Triangle | None, Conflict]
"""An out-edge ``(u, w, face id, triangle, conflict list)`` of a visible face; the id is
:data:`_HORIZON` (and the triangle None) for a horizon edge.  The neighbour's triangle and list
ride along so that the neighbour can be expanded when the walk first reaches it."""

Entry = tuple[Triangle, FaceDatum]
"""A face as the bulldozer's table holds it and :meth:`TwoComplex.replace` adds it: ``(triangle, (id, list))``."""


class _Visible:
    """Bookkeeping of one visible face during one insertion (local to the insertion, never persistent)."""

    __slots__ = ("tri", "own", "incoming", "indeg", "outs")

    def __init__(self, tri: Triangle, own: Indices, indeg: int, outs: list[Out]) -> None:
        self.tri = tri
        self.own = own  # its conflict list (all see it)
        self.incoming: list[Indices] = []  # points bulldozed into it along arcs (not yet tested)
        self.indeg = indeg  # arcs into it from faces not processed yet
        self.outs = outs  # in the edge order (a, b), (b, d), (d, a)


class _FaceTable:
    """Every face ever made, as rows of point indices by face id, and which are in the hull (``check=True`` only).

    Face ids are consecutive, so the table grows by appending; it lets the check
    test every face of the hull against a point in one vectorised batch.
    """

    def __init__(self) -> None:
        self.corners: IntArray = np.zeros((1024, 3), dtype=np.intp)
        self.live: NDArray[np.bool_] = np.zeros(1024, dtype=bool)

    def add(self, fid: int, tri: Triangle) -> None:
        if fid >= len(self.live):
            self._grow(fid)
        self.corners[fid] = tri
        self.live[fid] = True

    def add_many(self, fids: IntArray, corners: IntArray) -> None:
        """Faces ``corners[j]`` with ids ``fids[j]``, at once (a resumed run's faces)."""
        if fids.size:
            self._grow(int(fids.max()))
            self.corners[fids] = corners
            self.live[fids] = True

    def _grow(self, fid: int) -> None:
        size = len(self.live)
        while fid >= size:
            size *= 2
        if size > len(self.live):
            extra = size - len(self.live)
            self.corners = np.concatenate([self.corners, np.zeros((extra, 3), dtype=np.intp)])
            self.live = np.concatenate([self.live, np.zeros(extra, dtype=bool)])


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
    ) -> None:
        centre = pred.centre
        if centre is None:
            raise ValueError("the predicates need the centre point: use pred.with_centroid(*tetra)")
        self.pred = pred
        kernel = pred.kernel()
        self._o3 = kernel.orient3d
        self._partition = kernel.partition
        self._signs = kernel.signs
        self.S = structure
        self.C: int = centre
        self.n: int = centre  # the input points are 0 … centre-1
        self.check = check
        self.stepwise = stepwise
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
        self.complex: Complex[FaceDatum] = self._start(tetra) if resume is None else self._resume(*resume)

    def _vertex(self, i: int) -> Vertex:
        """The vertex of input point ``i`` (label ``i``), made on first use."""
        v = self.verts.get(i)
        if v is None:
            # What int_vertex.new(VertexState(lineage, i), i) returns, without the state it would also make:
            # each point is inserted once, so its index is a label no other vertex of the lineage has.
            v = self.verts[i] = Vertex(i, i, self._lineage)
        return v

    # -- the first hull --------------------------------------------------------------

    def _new_face(self, tri: Triangle, kept: Indices) -> Entry:
        """A new face ``tri`` with the conflict list ``kept``: its id, its table entry, its points' association."""
        fid = self._next_fid
        self._next_fid += 1
        conflict = _freeze(kept)
        _assign(self._assoc, self.assoc, conflict, fid)
        entry = (tri, (fid, conflict))
        self.faces[fid] = entry
        if self._table is not None:
            self._table.add(fid, tri)
        return entry

    def _start(self, tetra: tuple[int, int, int, int]) -> Complex[FaceDatum]:
        P = self.pred
        V = {i: self._vertex(i) for i in tetra}
        a, b, c, d = tetra
        faces: list[Triangle] = []
        for (i, j, k), opp in (((a, b, c), d), ((a, d, b), c), ((b, d, c), a), ((c, d, a), b)):
            # Outward: the opposite vertex (inside) is below the face (+1).
            tri = (V[i], V[j], V[k]) if P.orient3d(i, j, k, opp) > 0 else (V[i], V[k], V[j])
            faces.append(tri)
        others = all_but(self.n, tetra)
        self.status[list(tetra)] = ON_HULL
        # Each other point goes to the face its ray from the centre leaves through: the face's cone.
        if self.check or P.stats is not None:
            cones = self._cones_by_planes(faces, others)  # by definition: checked, and the counts of the paper
        else:
            cones = self._cones_by_tree(tetra, others)
        cx = self.S.new(2)
        for tri in faces:
            x, y, z = tri
            out, _ = self._partition(x, y, z, cones[frozenset(tri)])
            _assign(self._status, self.status, out, PENDING)
            cx = self.S.add(cx, *self._new_face(tri, out))
        return cx

    def _cones_by_planes(self, faces: list[Triangle], others: IntArray) -> dict[frozenset[int], IntArray]:
        """The points of ``others`` in the cone from the centre through each face, by the cone's definition.

        ``q`` is in the cone of face ``(x, y, z)`` iff it is on the inner side of the
        three planes ``(c, x, y)``, ``(c, y, z)``, ``(c, z, x)``: six planes in all,
        each tested on every point (counted runs, and ``check=True``, which also
        verifies that the cones partition the points).  O(n) tests.
        """
        P, C = self.pred, self.C
        side: dict[tuple[int, int], NDArray[np.int8]] = {}

        def plane_side(x: int, y: int) -> NDArray[np.int8]:
            if (x, y) in side:
                return side[(x, y)]
            if (y, x) in side:
                return -side[(y, x)]
            s = self._signs(C, x, y, others)
            side[(x, y)] = s
            return s

        cones: dict[frozenset[int], IntArray] = {}
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
            cones[frozenset(tri)] = others[inside]
        if self.check and others.size and not bool(claimed.all()):
            raise BulldozerCheckError("some point lies in no cone of the first tetrahedron's faces")
        return cones

    def _cones_by_tree(self, tetra: tuple[int, int, int, int], others: IntArray) -> dict[frozenset[int], IntArray]:
        """:meth:`_cones_by_planes` in three tests per point: a decision tree over the same planes.

        The plane ``(c, a, b)`` has ``c`` and ``d`` on opposite sides (the centre is
        inside), and the cone of ``abc`` lies on ``c``'s side, that of ``abd`` on
        ``d``'s.  On ``c``'s side the cones met are those of the three faces at
        ``c``; there, a point is in the cone of the face ``c x y`` iff it lies in
        the wedge between the half-planes that the axis from the centre through
        the apex ``c`` spans with ``x`` and with ``y`` — the routing question of
        the associated face (two tests of planes through the axis).  Likewise on
        ``d``'s side around the apex ``d``.  The same cones as the definition (a perturbed point set is
        in general position, where both are exact), each list in increasing
        order as there; ``tests/test_hull.py`` compares the two.  O(n) tests.
        """
        C, partition, o3 = self.C, self._partition, self._o3

        def split(x: int, y: int, ref: int, pts: Indices) -> tuple[Indices, Indices]:
            """``pts`` on ``ref``'s side of the plane ``(c, x, y)``, and on the other side."""
            minus, plus = partition(C, x, y, pts)
            return (plus, minus) if o3(C, x, y, ref) > 0 else (minus, plus)

        a, b, c, d = tetra
        found: dict[frozenset[int], list[Indices]] = {}
        for apex, half, (x, y, z) in zip((c, d), split(a, b, c, others), ((a, b, d), (a, b, c))):
            # Around the axis from the centre through apex, the wedges between x, y and z.
            y_side, z_side = split(apex, x, y, half)
            in_xy, in_yz = split(apex, y, x, y_side)
            in_zx, in_zy = split(apex, z, x, z_side)
            for corners, pts in (((apex, x, y), in_xy), ((apex, y, z), in_yz), ((apex, y, z), in_zy), ((apex, z, x), in_zx)):
                found.setdefault(frozenset(corners), []).append(pts)
        return {key: np.sort(np.asarray(_join(parts), dtype=np.intp)) for key, parts in found.items()}

    # -- continuing a run ------------------------------------------------------------

    def _resume(self, cx: Complex[FaceDatum], table: IntArray) -> Complex[FaceDatum]:
        """Take over ``cx``, the last version of an earlier run, whose faces are the rows ``(id, a, b, d)`` of ``table``.

        Nothing is done per old face in Python: the face table by id (kept in
        every resumed run: :meth:`triangles` reads it) is filled from ``table``
        at numpy speed, and :attr:`faces` holds only the faces this run makes or
        changes — a lit old face is read from the complex, like every
        neighbour.  New vertices join the version's lineage; face ids continue
        after ``table``'s.  ``check=True`` takes over every face from ``cx``
        instead and verifies that ``table`` lists them and that their conflict
        lists are empty (O(faces)).  O(faces) vectorised otherwise.
        """
        ft = self._table = _FaceTable()
        ft.add_many(table[:, 0], table[:, 1:])
        self._next_fid = int(table[:, 0].max()) + 1 if table.size else 0
        if cx.lineage is not None:
            self._lineage = cx.lineage
        if self.check:
            faces = self.faces
            for tri, datum in self.S.items(cx):
                fid, lst = datum
                if len(lst):
                    raise BulldozerCheckError(f"face {tri} of the version to continue has pending points")
                faces[fid] = (tri, datum)
            listed = {(fid, *_smallest_first(a, b, d)) for fid, a, b, d in table.tolist()}
            if listed != {(fid, *_smallest_first(*tri)) for fid, (tri, _) in faces.items()} or len(listed) != len(table):
                raise BulldozerCheckError("the face table to resume from does not list the version's faces")
        return cx

    def attach(self, points: IntArray, fids: IntArray) -> Complex[FaceDatum]:
        """Associate interior-marked points with faces: ``points[j]`` lies in the cone from the centre through face ``fids[j]``.

        The points beyond their face (those that see it) join its conflict
        list and become pending; the others are inside the hull and stay
        interior — the association of Appendix A.1, for points that arrive after
        the hull was built.  Returns the new version (one ``replace`` of the
        faces that gained points by themselves with their longer lists); every
        other face, its datum and its map nodes are shared with the current
        version, which is returned itself when no point is outside.
        ``check=True`` verifies each point's cone (the three signs
        ``orient3d(u, w, c, q) = -1``).  O(len(points)) plane-side tests.
        """
        status, assoc = self._status, self._assoc
        faces = self.faces
        if self.check:
            self._check_cones(points, fids)
        by_face = np.argsort(fids, kind="stable")
        sorted_fids = fids[by_face]
        cuts = np.flatnonzero(sorted_fids[1:] != sorted_fids[:-1]) + 1
        removed: list[Triangle] = []
        added: list[Entry] = []
        for start, stop in zip([0, *cuts.tolist()], [*cuts.tolist(), int(fids.size)]):
            if start == stop:
                continue
            fid = int(sorted_fids[start])
            known = faces.get(fid)
            lst: Conflict = ()
            if known is None:  # an old face of a resumed run, with an empty list: its triangle from the table
                assert self._table is not None
                a, b, d = self._table.corners[fid].tolist()
                tri: Triangle = (self._vertex(a), self._vertex(b), self._vertex(d))
            else:
                tri, (_, lst) = known
            out, _ = self._partition(tri[0], tri[1], tri[2], points[by_face[start:stop]])
            if not len(out):
                continue
            conflict = _freeze(_join([lst, out]) if len(lst) else out)
            _assign(status, self.status, conflict, PENDING)
            _assign(assoc, self.assoc, conflict, fid)
            entry = faces[fid] = (tri, (fid, conflict))
            removed.append(tri)
            added.append(entry)
        cx = self.complex
        if added:
            if self.stepwise:
                for tri in removed:
                    cx = self.S.rem(cx, tri)
                for tri, datum in added:
                    cx = self.S.add(cx, tri, datum)
            else:
                cx = self.S.replace(cx, removed, added)
            self.complex = cx
        return cx

    def _check_cones(self, points: IntArray, fids: IntArray) -> None:
        """Each point of ``points`` in the cone from the centre through its face of ``fids`` (all three signs)."""
        if not points.size:
            return
        assert self._table is not None
        corners = self._table.corners[fids]
        for i, j in ((0, 1), (1, 2), (2, 0)):
            bad = np.flatnonzero(self.pred.orient3d_many(corners[:, i], corners[:, j], self.C, points) != -1)
            if bad.size:
                k = int(bad[0])
                raise BulldozerCheckError(
                    f"point {int(points[k])} is not in the cone of face {tuple(corners[k].tolist())} it was located in"
                )

    # -- one insertion ---------------------------------------------------------------

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

    def insert(self, p: int) -> Complex[FaceDatum]:
        """Insert the outside point ``p``; return the new hull version (Appendix A.1.2).

        Raises :class:`ValueError` if ``p`` is not outside the current hull.
        """
        status, assoc = self._status, self._assoc
        if status[p] != PENDING:
            raise ValueError(f"point {p} is not outside the current hull")
        S, C, check = self.S, self.C, self.check
        o3, partition = self._o3, self._partition
        faces = self.faces
        cx = self.complex
        vp = self._vertex(p)
        fid0 = assoc[p]
        tri0, (_, lst) = faces[fid0]
        if self.stepwise:
            # The paper's code reads the list from the complex (a counted dictionary operation).
            found = S.data(cx, tri0)
            assert found is not None, "the associated face of a pending point is in the hull"
            lst = found[0][1]
        own0: Indices = lst[lst != p] if type(lst) is np.ndarray else [q for q in lst if q != p]
        # The face across an edge: neighbour (one lookup, a scan that stops at the face; each vertex's list
        # read once in this version), or findi in stepwise mode, whose counts (the whole list scanned) are
        # the paper's.
        across = self._across_counted(cx) if self.stepwise else S.neighbours(cx)

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
                gtri, (gid, gpts) = found
                vis = visible.get(gid)
                if vis is None:
                    vis = visible[gid] = o3(gtri[0], gtri[1], gtri[2], p) < 0
                if not vis:
                    outs.append((u, w, _HORIZON, None, ()))
                    continue
                s = -1 if known_out else o3(u, w, C, p)
                if check and o3(u, w, C, f) != -1:
                    raise BulldozerCheckError(f"the centre is not strictly behind face {tri} (orient3d(u, w, c, f) = +1)")
                if s < 0:
                    outs.append((u, w, gid, gtri, gpts))
                else:
                    indeg += 1
                pending_edges[(u, w)] = (s, fid, tri)
            rec = work[fid] = _Visible(tri, own, indeg, outs)
            return rec

        first = expand(fid0, tri0, own0, in_cone=True)
        if check and (first.indeg != 0 or len(first.outs) != 3):
            raise BulldozerCheckError(
                f"the associated face of point {p} has in-degree {first.indeg} and out-degree "
                f"{len(first.outs)} in the walking graph (expected 0 and 3)"
            )
        queue = [fid0]
        processed: list[int] = []
        tents: list[tuple[Triangle, Indices]] = []
        discarded: list[Indices] = []
        routed: list[Indices] = []  # every bulldozed point, for the checks
        while queue:
            fid = queue.pop()
            rec = work[fid]
            processed.append(fid)
            a, b, d = rec.tri
            pts: Indices = rec.own
            incoming = rec.incoming
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
            outs = rec.outs
            groups: Sequence[Indices]
            if len(outs) == 1:
                groups = (pts,)
            elif not len(pts):
                groups = ((), (), ())
            elif len(outs) == 2:
                (u1, w1, _, _, _), (u2, w2, _, _, _) = outs
                # Consecutive edges of (a, b, d) share a vertex v: w1 == u2, or (d, a) and (a, b): u1 == w2.
                # The out-edge (x, v) has orient3d(c, p, v, x) = -orient3d(x, v, c, p) = +1, the
                # out-edge (v, x) has orient3d(c, p, v, x) = orient3d(v, x, c, p) = -1.
                v, x, first_sign = (w1, u1, 1) if w1 == u2 else (u1, w1, -1)
                if check and o3(C, p, v, x) != first_sign:
                    raise BulldozerCheckError(f"the routing sign of face {rec.tri} is not the out-arc's")
                minus, plus = partition(C, p, v, pts)
                groups = (plus, minus) if first_sign > 0 else (minus, plus)
            elif len(outs) == 3:
                # The associated face: all three edges are out-arcs, so orient3d(c, p, x, y) = -1 for each
                # edge (x, y) and q's projection lies in sector (x, y) iff
                # orient3d(c, p, x, q) = -1 and orient3d(c, p, y, q) = +1; two tests decide it.
                b_minus, b_plus = partition(C, p, b, pts)
                in_ab, da1 = partition(C, p, a, b_plus)
                da2, in_bd = partition(C, p, d, b_minus)
                in_da = _join([da1, da2])
                if check:
                    self._check_sectors(p, rec.tri, pts, (in_ab, in_bd, in_da))
                groups = (in_ab, in_bd, in_da)
            else:
                raise BulldozerCheckError(f"visible face {rec.tri} has no out-edge in the walking graph")
            for (u, w, gid, gtri, gpts), grp in zip(outs, groups):
                if gid == _HORIZON:
                    # The tent face (u, w, p) keeps the points that see it; the others are interior.
                    if len(grp):
                        grp, gone = partition(u, w, p, grp)
                        if len(gone):
                            discarded.append(gone)
                    tents.append(((u, w, vp), grp))
                    continue
                target = work.get(gid)
                if target is None:
                    assert gtri is not None
                    target = expand(gid, gtri, gpts)
                if len(grp):
                    target.incoming.append(grp)
                target.indeg -= 1
                if target.indeg == 0:
                    queue.append(gid)

        if check:
            self._check_walk(p, fid0, work, processed)

        # The new version: the lit faces removed, the tent added.
        lit = [work[fid].tri for fid in processed]  # as the walk met them (the rotation findi gave)
        for fid in processed:
            faces.pop(fid, None)  # a resumed run's old faces are not in the dict
        if self._table is not None:
            self._table.live[processed] = False
        added: list[Entry] = []
        fid = self._next_fid
        table = self._table
        for tent, kept in tents:
            # A new face and its list, each of its points associated with it (_new_face, written out).
            if type(kept) is np.ndarray:
                conflict = _freeze(kept)
                _assign(assoc, self.assoc, conflict, fid)
            else:
                conflict = tuple(kept)
                for q in conflict:
                    assoc[q] = fid
            entry = faces[fid] = (tent, (fid, conflict))
            added.append(entry)
            if table is not None:
                table.add(fid, tent)
            fid += 1
        self._next_fid = fid
        if self.stepwise:
            for tri in lit:
                cx = S.rem(cx, tri)
            for tent, datum in added:
                cx = S.add(cx, tent, datum)
        else:
            cx = S.replace(cx, lit, added)
        for gone in discarded:
            # Only the status: a point's associated face id means something while it is pending.
            _assign(status, self.status, gone, INTERIOR)
        status[p] = ON_HULL
        self.complex = cx
        if check:
            self._check_bulldozed(p, routed, added)
        return cx

    def _across_counted(self, cx: Complex[FaceDatum]) -> Callable[[tuple[Vertex, Vertex]], tuple[Triangle, FaceDatum] | None]:
        """The face holding a directed edge of ``cx``, by ``findi`` as the paper's code finds it (stepwise mode)."""
        findi = self.S.findi

        def across(edge: tuple[Vertex, Vertex]) -> tuple[Triangle, FaceDatum] | None:
            ((tri, datum),) = findi(cx, edge)
            return tri, datum

        return across

    # -- check=True ------------------------------------------------------------------

    def _check_sectors(self, p: int, tri: Triangle, pts: Indices, groups: tuple[Indices, Indices, Indices]) -> None:
        """The associated face's points split into the three projected sectors, each by all three signs."""
        o3, C = self._o3, self.C
        a, b, d = tri
        if sorted(_as_list(pts)) != sorted(q for g in groups for q in _as_list(g)):
            raise BulldozerCheckError(f"the projected sectors of face {tri} lose or repeat points")
        for (x, y), grp in zip(((a, b), (b, d), (d, a)), groups):
            if o3(C, p, x, y) != -1:
                raise BulldozerCheckError(f"edge {(x, y)} of the associated face of point {p} is not an out-arc")
            for q in _as_list(grp):
                if not (o3(C, p, x, q) == -1 and o3(C, p, y, q) == 1):
                    raise BulldozerCheckError(f"point {q} is routed across edge {(x, y)} of face {tri} but its ray is not there")

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
        stack = [self.faces[fid0][0]]
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
        if len(self.faces) <= 4096 and self._table is not None:
            # Every face of the hull, tested at once (vectorised): the visible ones are exactly the walk's.
            fids = np.flatnonzero(self._table.live[: self._next_fid])
            corners = self._table.corners[fids]
            lit = P.orient3d_many(corners[:, 0], corners[:, 1], corners[:, 2], p) < 0
            everywhere = set(fids[lit].tolist())
            if everywhere != set(work):
                raise BulldozerCheckError(
                    f"inserting point {p}: {len(everywhere)} faces are visible but the walk found {len(work)} (Lemma 9)"
                )

    def _check_bulldozed(self, p: int, routed: list[Indices], tents: list[Entry]) -> None:
        """Theorems 6 and 7: every bulldozed point is in the list of its associated face or rightly interior.

        Independently of the walk, with the checked predicates: the ray from the
        centre to each bulldozed point ``q`` must leave the new hull through
        exactly one tent face ``(u, w, p)`` — the cone bounded by the planes
        ``(c, u, w)``, ``(c, w, p)`` and ``(c, p, u)`` — and ``q`` must be pending in
        that face's list if it is beyond the face, interior otherwise.  Vectorised
        over every (tent face, point) pair at once (the planes ``(c, x, p)`` are
        shared by the two tent faces at the horizon vertex ``x``).
        """
        P, C = self.pred, self.C
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
        fids = np.array([t[1][0] for t in tents], dtype=np.intp)[owner]
        beyond = P.orient3d_many(us[owner], ws[owner], p, pts) < 0
        bad = np.flatnonzero(beyond & ((self.status[pts] != PENDING) | (self.assoc[pts] != fids)))
        if bad.size:
            j = int(bad[0])
            raise BulldozerCheckError(
                f"inserting point {p}: point {int(pts[j])} is outside tent face {tents[int(owner[j])][0]} (its "
                f"associated face, Theorem 6) but is not in that face's list"
            )
        bad = np.flatnonzero(~beyond & (self.status[pts] != INTERIOR))
        if bad.size:
            raise BulldozerCheckError(
                f"inserting point {p}: point {int(pts[bad[0]])} is inside the new hull but was not discarded (Theorem 7)"
            )

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
