"""What a trace is: the recorded operations, their codes, the :class:`Trace` arrays and their validation.

The format is described in :mod:`persistri.impl.complex.trace` (which
re-exports everything public here); this module holds the operation codes
(:data:`OPERATIONS`, :data:`MAKES_VERSION`, :data:`FIRST`), the trace errors,
and :class:`Trace`, whose constructor checks every event (O(len), vectorised).
The recorder (:mod:`~persistri.impl.complex.trace_record`), the replay
(:mod:`~persistri.impl.complex.trace_replay`) and the files
(:mod:`~persistri.impl.complex.trace_files`) build on it.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "OPERATIONS",
    "MAKES_VERSION",
    "FIRST",
    "Trace",
    "TraceError",
    "UntrackedVersionError",
    "TraceFormatError",
    "ReplayMismatch",
]

IntArray = NDArray[np.int64]

OPERATIONS: Final[tuple[str, ...]] = (
    "new",
    "dim",
    "isEmpty",
    "vertices",
    "simplices",
    "data",
    "grep",
    "find",
    "findi",
    "items",
    "add",
    "rem",
    "update",
    "replace.rem",
    "replace.add",
    "replace",
)
"""The recorded operations; an event's ``op`` is an index into this tuple.

``replace`` (persistri's batched change) is recorded as one ``replace.rem``
event per removed triangle, one ``replace.add`` per added one, then the
``replace`` event itself, whose ``arg`` is the number of triangles before it.
"""

_CODE: Final = {name: i for i, name in enumerate(OPERATIONS)}
(NEW, DIM, IS_EMPTY, VERTICES, SIMPLICES, DATA, GREP, FIND, FINDI, ITEMS, ADD, REM, UPDATE, REPLACE_REM, REPLACE_ADD, REPLACE) = range(
    len(OPERATIONS)
)

MAKES_VERSION: Final[frozenset[str]] = frozenset({"new", "add", "rem", "update", "replace"})
"""The operations that make a new version (their ``result`` is its index)."""

FIRST: Final = 1
"""The ``arg`` of a ``findi`` event recorded from ``neighbour``: replayed with ``neighbour``, result 1 or 0.

A format-2 extension: older traces have only ``arg`` 0 on ``findi`` events, and
a ``neighbour`` event replayed as ``findi`` gives the same result on every
surface where no directed edge is in two triangles (what the algorithms make).
"""

_FORMAT: Final = "persistri-trace"
_FORMAT_VERSION: Final = 2
_READS: Final = (1, 2)  # version 1 had no replace events; it reads the same


class TraceError(ValueError):
    """A trace cannot be recorded or replayed as asked."""


class UntrackedVersionError(TraceError):
    """The recorder was given a complex it did not make, or one older than its ``window`` of versions."""


class TraceFormatError(TraceError):
    """A saved or constructed trace is malformed (the message names the first problem)."""


class ReplayMismatch(AssertionError):
    """A replay returned something else than the recorded run at some event: one of the two complexes is wrong."""


@dataclass(frozen=True, eq=False)
class Trace:
    """The recorded operations of one run on n-complexes (:mod:`persistri.impl.complex.trace`); arrays of one length each.

    Build one with :class:`TracingTwoComplex` or :func:`load_trace`; the
    constructor validates (:class:`TraceFormatError`).
    """

    n: int
    op: NDArray[np.uint8]
    src: IntArray
    simplex: IntArray
    arg: IntArray
    result: IntArray

    def __post_init__(self) -> None:
        _validate(self)

    def __len__(self) -> int:
        return int(self.op.shape[0])

    @property
    def versions(self) -> int:
        """How many versions the run made."""
        makes = np.isin(self.op, [_CODE[o] for o in MAKES_VERSION])
        return int(np.count_nonzero(makes))

    def counts(self) -> dict[str, int]:
        """How many times each operation occurs, for the operations that occur (in :data:`OPERATIONS` order)."""
        tally = np.bincount(self.op, minlength=len(OPERATIONS))
        return {name: int(tally[i]) for i, name in enumerate(OPERATIONS) if tally[i]}

    def labels(self) -> IntArray:
        """The distinct vertex labels the trace mentions, sorted."""
        flat = self.simplex.ravel()
        out: IntArray = np.unique(flat[flat >= 0])
        return out

    def event(self, k: int) -> tuple[str, int, tuple[int, ...], int, int]:
        """Event ``k`` as ``(op, src, simplex labels, arg, result)``."""
        row = self.simplex[k]
        return (
            OPERATIONS[int(self.op[k])],
            int(self.src[k]),
            tuple(int(x) for x in row[row >= 0]),
            int(self.arg[k]),
            int(self.result[k]),
        )

    def events(self) -> Iterator[tuple[str, int, tuple[int, ...], int, int]]:
        """Every :meth:`event` in order, for reading a trace (slow: Python objects)."""
        for k in range(len(self)):
            yield self.event(k)


def _validate(t: Trace) -> None:
    """Raise :class:`TraceFormatError` unless ``t`` is a well-formed trace.  O(len)."""
    if isinstance(t.n, bool) or not isinstance(t.n, int) or t.n < 1:
        raise TraceFormatError(f"trace: dimension must be a positive int, got {t.n!r}")
    arrays: dict[str, NDArray[Any]] = {"op": t.op, "src": t.src, "simplex": t.simplex, "arg": t.arg, "result": t.result}
    for name, a in arrays.items():
        if not isinstance(a, np.ndarray):
            raise TraceFormatError(f"trace: {name} must be a numpy array, got {type(a).__name__}")
        if not np.issubdtype(a.dtype, np.integer):
            raise TraceFormatError(f"trace: {name} must hold integers, got dtype {a.dtype}")
    m = t.op.shape[0]
    for name, a in arrays.items():
        want = (m, t.n + 1) if name == "simplex" else (m,)
        if a.shape != want:
            raise TraceFormatError(f"trace: {name} has shape {a.shape}, expected {want}")
    if m and (int(t.op.min()) < 0 or int(t.op.max()) >= len(OPERATIONS)):
        raise TraceFormatError(f"trace: op codes must be in 0..{len(OPERATIONS) - 1}")
    if m and int(t.simplex.min()) < -1:
        raise TraceFormatError("trace: vertex labels are non-negative (-1 pads)")
    makes = np.isin(t.op, [_CODE[o] for o in MAKES_VERSION])
    made_before: IntArray = np.cumsum(makes) - makes  # versions made before each event
    news = t.op == NEW
    if np.any(t.src[news] != -1):
        raise TraceFormatError("trace: a new event reads no version (src must be -1)")
    reads = ~news
    bad = reads & ((t.src < 0) | (t.src >= made_before))
    if np.any(bad):
        k = int(np.flatnonzero(bad)[0])
        raise TraceFormatError(f"trace: event {k} reads version {int(t.src[k])}, not made before it")
    findis = t.op == FINDI
    bad_arg = findis & (t.arg != 0) & (t.arg != FIRST)
    if np.any(bad_arg):
        k = int(np.flatnonzero(bad_arg)[0])
        raise TraceFormatError(f"trace: findi event {k} has arg {int(t.arg[k])} (0: findi, {FIRST}: neighbour)")
    bad_first = findis & (t.arg == FIRST) & (t.result != 0) & (t.result != 1)
    if np.any(bad_first):
        k = int(np.flatnonzero(bad_first)[0])
        raise TraceFormatError(f"trace: neighbour event {k} (findi, arg {FIRST}) says {int(t.result[k])} triangles, not 0 or 1")
    if np.any(t.result[makes] != made_before[makes]):
        k = int(np.flatnonzero(makes & (t.result != made_before))[0])
        raise TraceFormatError(f"trace: event {k} should make version {int(made_before[k])}, says {int(t.result[k])}")
    _validate_replaces(t)


def _validate_replaces(t: Trace) -> None:
    """Each run of ``replace.rem`` then ``replace.add`` events is closed by a ``replace`` of the same version,
    whose ``arg`` counts them.  O(len), vectorised."""
    m = t.op.shape[0]
    parts = (t.op == REPLACE_REM) | (t.op == REPLACE_ADD)
    closes = t.op == REPLACE
    if not (parts.any() or closes.any()):
        return
    idx = np.arange(m)
    # The first event at or after each event that is not a part (m if none), and the last before it.
    after = np.minimum.accumulate(np.where(parts, m, idx)[::-1])[::-1]
    before = np.maximum.accumulate(np.where(parts, -1, idx))
    bad = parts & (after == m)
    if not bad.any():
        nxt = np.where(parts, after, 0)
        bad = parts & ((t.op[nxt] != REPLACE) | (t.src[nxt] != t.src))
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise TraceFormatError(f"trace: event {k} is part of a replace that no replace event of version {int(t.src[k])} closes")
    if m > 1 and np.any((t.op[:-1] == REPLACE_ADD) & (t.op[1:] == REPLACE_REM)):
        k = int(np.flatnonzero((t.op[:-1] == REPLACE_ADD) & (t.op[1:] == REPLACE_REM))[0]) + 1
        raise TraceFormatError(f"trace: event {k}: a replace lists its removed triangles before its added ones")
    start = np.concatenate(([0], before[:-1] + 1)) if m else before
    counts = idx - np.where(idx > 0, start, 0)
    wrong = closes & (t.arg != counts)
    if wrong.any():
        k = int(np.flatnonzero(wrong)[0])
        raise TraceFormatError(f"trace: replace event {k} says {int(t.arg[k])} triangles, {int(counts[k])} precede it")
