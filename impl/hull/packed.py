"""A hull face's datum packed in one ``int``: the form a run keeping its history stores (issue 17).

Every version of a history keeps the data of its faces, so a face's datum
``(face id, conflict list)`` is stored many times over: as a 2-tuple, an
``int`` id, a tuple of ``int`` points or a numpy array.  A run with
``history=True`` stores each datum as **one** plain ``int`` instead, whose bits are::

    bits 0-31    the face id
    then, a short list (below KERNEL_BATCH entries, at most SHORT_MAX):
    bits 32-39   2 × (its number of points), even
    bits 40-     the points as int32, little-endian
    or a long list (run-coded):
    bits 32-63   2 × (bytes of the run code) + 1, odd
    bits 64-     the run code, little-endian

A face whose list is empty is its id alone (28 bytes, against 84 for ``(id, ())``
and its ``int``).  A short list's count takes one byte, not four: 3 bytes a
short face, about 10 bytes an inserted point at InBall 256K (docs/performance.md,
"Memory of a full history").  A long list — a read-only int32 array in a run without
history — is coded by :func:`pack_points` as its **runs** of consecutive
indices: the bulldozer's lists are concatenations of a few increasing parts of
spatially numbered points (Morton labels: a face's points lie near one another),
and 79 % of the steps between consecutive points of a long list are +1 on
InBall 256K.  Each run is its length and its gap (its first point minus the
end of the run before it, negative at a join), both as int8, any value outside
``-127 … 127`` marked ``-128`` and stored apart, in order, as int16 (int32 when
one of the list's does not fit): 0.6 bytes a point there, against 4.  Exact: decoding gives the same points in
the same order (:func:`unpack_points`: a cumulative sum, a repeat and a range).

Read a datum of either form with :func:`face_id` and :func:`conflict_list` (the
list in its usual form: a tuple when short, else a read-only int32 array,
decoded on each read; :meth:`HullHistory.pending
<persistri.impl.hull.api.HullHistory.pending>` does).  A plain ``int`` and not a
subclass that would index like the tuple: an ``int`` subclass is tracked by the
garbage collector, 16 more bytes a face (96 bytes an inserted point at 256K).

Cost: packing is done once per new face and unpacking once per face the
bulldozer expands (O(list length), a few numpy calls for a long list), so it is
used only where lists are kept — a run without history drops each version's
lists with the version and keeps the 2-tuples, which cost nothing to read.
"""

from __future__ import annotations

import struct
from array import array
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "PackedFace",
    "pack_face",
    "face_id",
    "conflict_list",
    "points_of",
    "pack_points",
    "unpack_points",
    "ID_MASK",
    "SHORT_MAX",
]

ID_MASK: Final = 0xFFFFFFFF
"""The face id's bits in a :class:`PackedFace` (``datum & ID_MASK``); ids are below 2**32."""

SHORT_MAX: Final = 127
"""The most points a short list's one-byte count holds (``2 × count`` is even and below 256); a tuple or list of
more is packed as a long list (the bulldozer's short lists are below KERNEL_BATCH = 64)."""

_COUNTS: Final = struct.Struct("<3i")
"""A coded int32 sequence starts with its length, its number of escapes and their width (int32 each)."""

_ESCAPE: Final = -128
"""The int8 that marks an escaped value (its value is in the escapes, in order)."""

ListArray = NDArray[np.int32]


PackedFace = int
"""A packed face datum (the module's layout): a plain ``int``; a face datum of the other form is a 2-tuple."""


def _code(values: ListArray) -> bytes:
    """int32 ``values`` as int8, each outside ``-127 … 127`` an escape: ``_COUNTS`` (values, escapes ``e``, their
    width ``w``: 2 if every escaped value fits int16, else 4), the ``e`` escaped values in order (``w`` bytes
    each), then one int8 a value, ``-128`` at an escape. O(len(values))."""
    small = values.astype(np.int8)
    bad = (small != values) | (small == _ESCAPE)
    if bad.any():
        small[bad] = _ESCAPE
        escaped = values[bad]
        narrow = escaped.astype(np.int16)
        if np.array_equal(narrow, escaped):
            return b"".join((_COUNTS.pack(values.size, escaped.size, 2), narrow.tobytes(), small.tobytes()))
        return b"".join((_COUNTS.pack(values.size, escaped.size, 4), escaped.tobytes(), small.tobytes()))
    return _COUNTS.pack(values.size, 0, 0) + small.tobytes()


def _decode(code: bytes, off: int) -> tuple[ListArray, int]:
    """The int32 values :func:`_code` wrote at ``code[off:]``, and the offset after them. O(their number)."""
    n, e, w = _COUNTS.unpack_from(code, off)
    off += _COUNTS.size
    small = np.frombuffer(code, dtype=np.int8, count=n, offset=off + w * e)
    values = small.astype(np.int32)
    if e:
        values[small == _ESCAPE] = np.frombuffer(code, dtype=np.int16 if w == 2 else np.int32, count=e, offset=off)
    return values, off + w * e + n


def pack_points(pts: ListArray) -> bytes:
    """The run code of a conflict list ``pts`` (int32, not empty): the module's layout.

    The runs of consecutive indices, each its gap and its length (:func:`_code` each: gaps, then
    lengths).  O(len(pts)), vectorised."""
    n = pts.size
    breaks = np.flatnonzero(pts[1:] - pts[:-1] != 1)
    bounds = np.empty(breaks.size + 2, dtype=np.intp)
    bounds[0] = 0
    bounds[1:-1] = breaks + 1
    bounds[-1] = n
    lengths = (bounds[1:] - bounds[:-1]).astype(np.int32)
    starts = pts[bounds[:-1]]
    gaps = np.empty_like(starts)
    gaps[0] = starts[0]
    gaps[1:] = starts[1:] - starts[:-1] - lengths[:-1]
    return _code(gaps) + _code(lengths)


def unpack_points(code: bytes) -> ListArray:
    """The list :func:`pack_points` coded, as a read-only int32 array (the same points, in order). O(length).

    The first point of run ``i`` is the sum of the gaps and lengths before it and its own gap, so run ``i``
    is ``cumsum(gaps)[i] + (its positions in the list)``: every partial sum is a point minus a position,
    exact in int32."""
    gaps, off = _decode(code, 0)
    lengths, _ = _decode(code, off)
    out: ListArray = np.repeat(gaps.cumsum(dtype=np.int32), lengths)
    out += np.arange(out.size, dtype=np.int32)
    out.setflags(write=False)
    return out


def pack_face(fid: int, conflict: Any) -> PackedFace:
    """The datum of face ``fid`` with the conflict list ``conflict`` (a tuple or list of point ints when short,
    an int32 array when long: the form :func:`~persistri.impl.hull.conflicts._freeze` gives). O(len(conflict))."""
    if not 0 <= fid <= ID_MASK:
        raise OverflowError(f"face id {fid} does not fit a packed face datum (32 bits)")
    kind = type(conflict)
    n = len(conflict)
    if kind is np.ndarray or n > SHORT_MAX:
        code = pack_points(np.asarray(conflict, dtype=np.int32))
        return fid | (2 * len(code) + 1) << 32 | int.from_bytes(code, "little") << 64
    if not n:
        return fid
    # The points as one uint32 array, read as one int, above the id and the one-byte count.
    if kind is array:
        words = conflict  # an int32 array of points (points_of): non-negative, the same bytes as uint32
    elif kind is list:
        words = array("I")
        words.fromlist(conflict)
    else:
        words = array("I", conflict)
    return fid | n << 33 | int.from_bytes(words, "little") << 40


def _unpack(datum: int) -> Any:
    """The conflict list of a packed datum, in its usual form: a tuple when short, else a read-only int32 array."""
    meta = (datum >> 32) & 0xFF
    if meta & 1:
        return unpack_points((datum >> 64).to_bytes(((datum >> 32) & ID_MASK) >> 1, "little"))
    if not meta:
        return ()
    return tuple(array("i", (datum >> 40).to_bytes(2 * meta, "little")))


def points_of(datum: int) -> Any:
    """The conflict list of a packed datum as the bulldozer reads it: an int32 ``array`` when short (no tuple
    made), else the read-only int32 array of :func:`unpack_points`. O(length)."""
    meta = (datum >> 32) & 0xFF
    if meta & 1:
        return unpack_points((datum >> 64).to_bytes(((datum >> 32) & ID_MASK) >> 1, "little"))
    if not meta:
        return ()
    return array("i", (datum >> 40).to_bytes(2 * meta, "little"))


def face_id(datum: Any) -> int:
    """The face id of a datum, packed or ``(id, list)``. O(1)."""
    if type(datum) is int:
        return datum & ID_MASK
    fid: int = datum[0]
    return fid


def conflict_list(datum: Any) -> Any:
    """The conflict list of a datum, packed or ``(id, list)``: a tuple when short, else a read-only int32 array."""
    if type(datum) is int:
        return _unpack(datum)
    return datum[1]
