"""Continuing a bulldozer run: taking over an earlier run's last version, and points that arrive later.

:meth:`~persistri.impl.hull.bulldozer.Bulldozer._resume` and
:meth:`~persistri.impl.hull.bulldozer.Bulldozer.attach` are these functions
(their docstrings state what they do and cost): :func:`resume` takes over a
version and its face table without a Python step per old face, :func:`attach`
associates new points with the faces whose cones hold them (Appendix A.1, for
points that come after the hull was built), in one ``replace``.  Used by
``add_points`` and the parallel hull (:mod:`persistri.impl.hull.extend`); once
per run or per call, so interpreted, beside the compiled insertion loop.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from persistri.impl.complex.structure import Complex
from persistri.impl.hull.bulldozer_checks import check_cones
from persistri.impl.hull.conflicts import (
    PENDING,
    Conflict,
    Entry,
    FaceDatum,
    IntArray,
    Triangle,
    _assign,
    _FaceTable,
    _freeze,
    _join,
    _smallest_first,
)
from persistri.impl.hull.errors import BulldozerCheckError
from persistri.impl.hull.packed import conflict_list, face_id, pack_face

if TYPE_CHECKING:
    from persistri.impl.hull.bulldozer import Bulldozer

__all__ = ["resume", "attach"]


def resume(B: Bulldozer, cx: Complex[FaceDatum], table: IntArray) -> Complex[FaceDatum]:
    """``B._resume(cx, table)``: ``B`` takes over ``cx``, the last version of an earlier run, whose faces are the rows ``(id, a, b, d)`` of ``table``.

    Nothing is done per old face in Python: the face table by id (kept in
    every resumed run: :meth:`~persistri.impl.hull.bulldozer.Bulldozer.triangles`
    reads it) is filled from ``table`` at numpy speed, and ``B.faces`` holds only
    the faces this run makes or changes — a lit old face is read from the
    complex, like every neighbour.  New vertices join the version's lineage;
    face ids continue after ``table``'s.  ``check=True`` takes over every face
    from ``cx`` instead and verifies that ``table`` lists them and that their
    conflict lists are empty (O(faces) in Python).  O(faces) vectorised otherwise.
    """
    ft = B._table = _FaceTable()
    ft.add_many(table[:, 0], table[:, 1:])
    B._next_fid = int(table[:, 0].max()) + 1 if table.size else 0
    if cx.lineage is not None:
        B._lineage = cx.lineage
    if B.check:
        faces = B.faces
        for tri, datum in B.S.items(cx):
            fid, lst = face_id(datum), conflict_list(datum)
            if len(lst):
                raise BulldozerCheckError(f"face {tri} of the version to continue has pending points")
            faces[fid] = (tri, datum)
        listed = {(fid, *_smallest_first(a, b, d)) for fid, a, b, d in table.tolist()}
        if listed != {(fid, *_smallest_first(*tri)) for fid, (tri, _) in faces.items()} or len(listed) != len(table):
            raise BulldozerCheckError("the face table to resume from does not list the version's faces")
    return cx


def attach(B: Bulldozer, points: IntArray, fids: IntArray) -> Complex[FaceDatum]:
    """``B.attach(points, fids)``: ``points[j]``, interior-marked and in the cone from the centre through face ``fids[j]``, joins its list if it sees it.

    The points beyond their face (those that see it) join its conflict list and
    become pending; the others are inside the hull and stay interior — the
    association of Appendix A.1, for points that arrive after the hull was
    built.  Returns the new version (one ``replace`` of the faces that gained
    points by themselves with their longer lists); every other face, its datum
    and its map nodes are shared with the current version, which is returned
    itself when no point is outside.  ``check=True`` verifies each point's cone
    (the three signs ``orient3d(u, w, c, q) = -1``).  O(len(points)) plane-side
    tests and one ``replace``.
    """
    status, assoc = B._status, B._assoc
    faces = B.faces
    if B.check:
        check_cones(B, points, fids)
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
            assert B._table is not None
            a, b, d = B._table.corners[fid].tolist()
            tri: Triangle = (B._vertex(a), B._vertex(b), B._vertex(d))
        else:
            tri, datum = known
            lst = conflict_list(datum)
        out, _ = B._partition(tri[0], tri[1], tri[2], points[by_face[start:stop]])
        if not len(out):
            continue
        conflict = _freeze(_join([lst, out]) if len(lst) else out)
        _assign(status, B.status, conflict, PENDING)
        _assign(assoc, B.assoc, conflict, fid)
        entry = faces[fid] = (tri, pack_face(fid, conflict) if B.packed else (fid, conflict))
        removed.append(tri)
        added.append(entry)
    cx = B.complex
    if added:
        if B.stepwise:
            for tri in removed:
                cx = B.S.rem(cx, tri)
            for tri, datum in added:
                cx = B.S.add(cx, tri, datum)
        else:
            cx = B.S.replace(cx, removed, added)
        B.complex = cx
    return cx
