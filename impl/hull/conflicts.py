"""The bulldozer's bookkeeping beside the complex: conflict lists, point statuses, the face table.

A face's **conflict list** (Appendix A.1: the points *associated* with it) is
a tuple of point indices when short, a read-only int32 numpy array from
:data:`~persistri.impl.geometry.kernel.KERNEL_BATCH` entries on (4 bytes a
point: every version keeps its lists).  Each point has a status
(:data:`PENDING`, :data:`INTERIOR`, :data:`ON_HULL`) and, while pending, the
id of its associated face; the face table by id mirrors the hull's faces for
``check=True`` and resumed runs.  A face's datum is ``(face id, conflict list)``, or in a run
that keeps its history the same packed in one ``int``
(:mod:`~persistri.impl.hull.packed`: :func:`tent_faces` ``pack=True``).  Compiled with the bulldozer in the compiled
twin (``tools/compiled_twin.py``): the insertion loop of
:mod:`persistri.impl.hull.bulldozer` calls these helpers for every face.
"""

from __future__ import annotations

import itertools
from array import array
from collections.abc import Iterable
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from persistri.impl.complex.vertex import Vertex
from persistri.impl.geometry.kernel import KERNEL_BATCH, Indices
from persistri.impl.hull.packed import PackedFace, pack_face

__all__ = [
    "Conflict",
    "FaceDatum",
    "FaceTuple",
    "Entry",
    "PENDING",
    "INTERIOR",
    "ON_HULL",
    "all_but",
    "tent_faces",
    "triangle_array",
]

IntArray = NDArray[np.intp]
ListArray = NDArray[np.int32]
"""A long conflict list: 4 bytes a point, half of ``intp``'s (every version keeps its lists)."""
Triangle = tuple[Vertex, Vertex, Vertex]
Conflict = tuple[int, ...] | ListArray
"""A conflict list: point indices, a tuple below ``KERNEL_BATCH`` entries, else a read-only int32 array."""
FaceTuple = tuple[int, Conflict]
"""The datum of a hull face in a run without history: ``(face id, conflict list)``."""
FaceDatum = FaceTuple | PackedFace
"""The datum of a hull face: ``(face id, conflict list)``, or the same packed in one ``int`` in a run that keeps
its history (:mod:`~persistri.impl.hull.packed`; ``face_id`` and ``conflict_list`` read either form)."""

PENDING: Final = 0
"""Status of a point outside the current hull (in the conflict list of its associated face)."""
INTERIOR: Final = 1
"""Status of a point found inside the hull (discarded for good)."""
ON_HULL: Final = 2
"""Status of a point that was inserted (a vertex of the hull when inserted)."""

Entry = tuple[Triangle, FaceDatum]
"""A face as the bulldozer's table holds it and :meth:`TwoComplex.replace` adds it: ``(triangle, (id, list))``."""


def _freeze(pts: Indices) -> Conflict:
    """``pts`` as a conflict list: a tuple when short, else a read-only int32 array (a copy only when
    ``pts`` is not int32 already: partitions of int32 lists are int32).  Whether a list is long
    depends on its length alone (:data:`~persistri.impl.geometry.kernel.KERNEL_BATCH`), not on the
    form it arrives in: the compiled kernel's partition returns Python lists up to
    :data:`~persistri.impl.geometry.kernel.COMPILED_BATCH` points, and each build keeps the same lists."""
    if isinstance(pts, np.ndarray):
        if len(pts) < KERNEL_BATCH:
            return tuple(pts.tolist())
        arr: ListArray = pts.astype(np.int32, copy=False)
    elif len(pts) < KERNEL_BATCH:
        return tuple(pts)
    else:
        arr = np.array(pts, dtype=np.int32)
    arr.setflags(write=False)
    return arr


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


def tent_faces(
    tents: list[tuple[Triangle, Indices]],
    fid: int,
    faces: dict[int, Entry],
    assoc: array[int],
    assoc_view: NDArray[np.int64],
    table: _FaceTable | None,
    pack: bool = False,
) -> list[Entry]:
    """The tent's new faces as entries ``(triangle, (id, conflict list))``, ids from ``fid`` on, in the
    order of ``tents`` (each a triangle and the points kept for it): each face entered in ``faces``
    (and ``table``), each of its points associated with it in ``assoc`` (through ``assoc_view``, its
    numpy view, for a long list).  :meth:`Bulldozer.insert <persistri.impl.hull.bulldozer.Bulldozer.insert>`'s
    last step before the new version; ``first_hull.new_face`` for each tent face, written out.
    ``pack``: each datum packed in one ``int`` (:func:`~persistri.impl.hull.packed.pack_face`).
    O(faces + points)."""
    if pack:
        return _tent_faces_packed(tents, fid, faces, assoc, assoc_view, table)
    added: list[Entry] = []
    for tent, kept in tents:
        key: Any = fid  # one int object for the id (compiled, an int would be boxed at each use)
        if type(kept) is np.ndarray or len(kept) >= KERNEL_BATCH:
            conflict = _freeze(kept)
            _assign(assoc, assoc_view, conflict, fid)
        else:
            conflict = tuple(kept)
            points: Any = conflict  # its ints as they are, not unboxed and boxed again
            for q in points:
                assoc[q] = key
        entry = faces[key] = (tent, (key, conflict))
        added.append(entry)
        if table is not None:
            table.add(fid, tent)
        fid += 1
    return added


def _tent_faces_packed(
    tents: list[tuple[Triangle, Indices]],
    fid: int,
    faces: dict[int, Entry],
    assoc: array[int],
    assoc_view: NDArray[np.int64],
    table: _FaceTable | None,
) -> list[Entry]:
    """:func:`tent_faces` with each datum packed (a run keeping its history). O(faces + points)."""
    added: list[Entry] = []
    for tent, kept in tents:
        if type(kept) is np.ndarray or len(kept) >= KERNEL_BATCH:
            conflict = _freeze(kept)
            _assign(assoc, assoc_view, conflict, fid)
            datum = pack_face(fid, conflict)
        else:
            for q in kept:
                assoc[q] = fid
            datum = pack_face(fid, kept)
        entry = faces[fid] = (tent, datum)
        added.append(entry)
        if table is not None:
            table.add(fid, tent)
        fid += 1
    return added


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
