"""The bulldozer: a randomized incremental 3D convex hull on a persistent complex (paper §3, Appendix A).

The hull is a closed, outward-oriented 2-complex (:class:`~persistri.impl.complex.two_complex.TwoComplex`)
whose every triangle carries its **conflict list**: the not-yet-inserted points
*associated* with it.  A fixed centre point ``c`` strictly inside the first
tetrahedron defines the association: a point ``q`` outside the hull belongs to
the face through which the ray ``c → q`` leaves the hull (Appendix A.1).
:class:`Bulldozer` is the state of a run — the current version and that
association — and :meth:`Bulldozer.run` the loop over the insertion order; one
insertion (the walking graph, the bulldozing, the tent: Appendix A.1.2) is
:func:`~persistri.impl.hull.insertion.insert`.

Conflict lists are tuples of point indices, or read-only int32 numpy arrays
(4 bytes a point: every version keeps its lists) from
:data:`~persistri.impl.geometry.kernel.KERNEL_BATCH` entries on; the
kernel's ``partition`` tests a short list point by point and a long one in a
vectorised batch.  A run that keeps its history (``pack=True``) stores each
face's datum packed in one ``int`` (:mod:`~persistri.impl.hull.packed`), read
back to these forms when the walk expands the face.

Bookkeeping beside the complex: each point's status and associated face id
(flat arrays), and a table from face id to the face's entry ``(triangle, (id,
conflict list))`` — the very tuple the complex holds — so that the list of the
point being inserted is read from the table, not looked up in the complex.
The complex is what the walk asks for adjacency; the table only mirrors its
faces.

Insertion order: a random permutation of the points from the seed; a point
that is interior when its turn comes is skipped.  This is equivalent to the
paper's choice (a face with probability proportional to its list, then a point
of it): both pick the next point uniformly among the points still outside.

Vertices: the vertex of input point ``i`` has label ``i`` and is made when
``i`` joins the hull, not for every input point — the vertex
``int_vertex.new(VertexState(lineage, i), i)`` would return (labels stay
unique: each point is inserted at most once).

Everything is iterative (no recursion), so any input size works: O(n lg n)
expected time in all (Theorem 11, §3).

Where it lives: one insertion in :mod:`~persistri.impl.hull.insertion`; the
conflict lists, point statuses and the face table in
:mod:`~persistri.impl.hull.conflicts`; the initial tetrahedron, the first
cones and the first version in :mod:`~persistri.impl.hull.first_hull`; resuming
a run and attaching late points in :mod:`~persistri.impl.hull.resume`; ``check=True``'s verifications
in :mod:`~persistri.impl.hull.bulldozer_checks`; the state of a run and its
loop here (re-exporting what this module always exported).
"""

from __future__ import annotations

from array import array
from collections.abc import Callable, Iterator
from typing import Final

import numpy as np
from numpy.typing import NDArray

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.complex.vertex import Vertex, VertexState
from persistri.impl.geometry.predicates import Predicates3
from persistri.impl.hull.conflicts import (
    INTERIOR,
    ON_HULL,
    PENDING,
    Conflict,
    Entry,
    FaceDatum,
    IntArray,
    _FaceTable,
    all_but,
    triangle_array,
)
from persistri.impl.hull.errors import BulldozerCheckError
from persistri.impl.hull.first_hull import first_hull, initial_tetrahedron
from persistri.impl.hull.insertion import insert as insert_point
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
        self._sift = None if check else kernel.sift  # the checks read each partition's lists: not fused there
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
        """Insert the outside point ``p``; return the new hull version (Appendix A.1.2:
        :func:`.insertion.insert`).

        Raises :class:`ValueError` if ``p`` is not outside the current hull.
        """
        return insert_point(self, p)

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
                    yield p, insert_point(self, p)
            if progress is not None:
                progress(block.size)
