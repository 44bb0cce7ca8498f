"""Traces: record the SIMPCOMP operations an algorithm performs, and replay them on any complex.

The paper separates the cost of the complex from the rest of the convex hull
(§4, Fig. 8) by timing the complex operations alone.  persistri does it with a
**trace**: run the algorithm once on a :class:`TracingTwoComplex` — a
2-complex structure that forwards every operation to a real one and records
it — then :func:`replay` the recorded operations on any 2-complex structure
(any ``ORD_MAP`` backend, the paper's unspecialised functor, or the ephemeral
baseline) with nothing else running::

    rec = TracingTwoComplex(two_complex("red_black"))
    convex_hull(points, structure=rec)
    trace = rec.stop()
    final = replay(trace, two_complex("hamt"))      # the same final hull, on another backend

What a trace holds, per event (:class:`Trace`, numpy arrays of equal length):

* ``op`` — which SIMPCOMP operation (:data:`OPERATIONS`; ``findi`` and ``items``
  are persistri's additions, recorded too);
* ``src`` — the version it was applied to, as an index: versions are numbered
  0, 1, 2, … in the order ``new``, ``add``, ``rem``, ``update`` and ``replace`` made them,
  so branching histories (operations on old versions) are recorded faithfully;
* ``simplex`` — its simplex argument as vertex **labels** (``int(v)``), padded
  with −1 (the vertices themselves and their points are not recorded: the
  complex never looks at points);
* ``arg`` — the dimension argument (``new``, ``simplices``, ``grep``); for
  ``findi``, :data:`FIRST` (1) when the call was ``neighbour`` — a ``findi``
  that stops at the first triangle — and 0 for ``findi`` itself; else 0;
* ``result`` — a summary of what it returned: the index of the version made
  (``new``, ``add``, ``rem``, ``update``), the number of simplices returned
  (``find``, ``findi``, ``grep``, ``simplices``, ``items``, ``vertices``; for
  a ``neighbour``'s ``findi`` event 1 or 0),
  1/0 for ``data`` (SOME/NONE) and ``isEmpty``, n for ``dim``.  :func:`replay`
  with ``verify=True`` checks every summary, so a replay that diverges from the
  recorded run is caught at the first differing event.

**Data are not recorded.**  Each datum is replaced by a placeholder: on replay,
the datum stored by ``add`` (or computed by ``update``'s function) is the index
of that event (for ``replace``, the index of the triangle's ``replace.add`` event).  The complex never looks inside its data, so every operation
does the same work with placeholders as with the algorithm's data (the cost of
the algorithm's own ``update`` function, which is not the complex's, is left
out).  A call that raised (bad input) is not recorded: it changed nothing.

Traces are saved as ``.npz`` (compressed numpy arrays) or ``.json``
(:func:`save_trace`, :func:`load_trace`); :func:`load_trace` validates what it
reads and raises :class:`TraceFormatError` naming the first problem.

Memory: the recorder keeps the last ``window`` versions it made (default
1024) to recognise them when they come back; an operation on an older version
raises :class:`UntrackedVersionError` (``window=None`` keeps every version, and
so all their nodes).  :func:`replay` keeps a version only until its last use.

>>> from persistri.impl.complex import VertexState, int_vertex, two_complex
>>> _, (a, b, c, d) = int_vertex.new_many(VertexState.initial(), "abcd")
>>> rec = TracingTwoComplex(two_complex("red_black"))
>>> k = rec.add(rec.add(rec.new(2), (a, b, c), "x"), (a, c, d), "y")
>>> rec.findi(k, (c, a))
[((v2, v0, v1), 'x')]
>>> trace = rec.stop()
>>> trace.counts()
{'new': 1, 'findi': 1, 'add': 2}
>>> S = two_complex("hamt")
>>> S.items(replay(trace, S))      # data are placeholders: the index of the event that stored each
[((v0, v1, v2), 1), ((v0, v2, v3), 2)]
"""

from __future__ import annotations

import json
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final, TypeVar

import numpy as np
from numpy.typing import NDArray

from persistri.impl.complex.simplex import Simplex
from persistri.impl.complex.structure import Complex, ComplexStructure
from persistri.impl.complex.two_complex import Triangle, TwoComplex
from persistri.impl.complex.vertex import Vertex, VertexState, int_vertex
from persistri.spec.option import Option

__all__ = [
    "OPERATIONS",
    "MAKES_VERSION",
    "FIRST",
    "Trace",
    "TraceError",
    "UntrackedVersionError",
    "TraceFormatError",
    "ReplayMismatch",
    "TracingTwoComplex",
    "Replay",
    "replay",
    "save_trace",
    "load_trace",
]

D = TypeVar("D")
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
    """The recorded operations of one run on n-complexes (module docstring); arrays of one length each.

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


# -- recording -------------------------------------------------------------------------


class TracingTwoComplex(TwoComplex[D]):
    """A 2-complex structure that forwards every operation to ``inner`` and records it (module docstring).

    Its complex values are ``inner``'s own (same family), so they can be
    checked and read with ``inner`` too.  Recording costs O(1) per operation
    beyond ``inner``'s.  :meth:`stop` ends the recording and returns the
    :class:`Trace`; afterwards operations are forwarded unrecorded.
    """

    def __init__(self, inner: TwoComplex[D], *, window: int | None = 1024) -> None:
        if not isinstance(inner, TwoComplex):
            raise TypeError(f"TracingTwoComplex: inner must be a TwoComplex structure, got {type(inner).__name__}")
        if window is not None and (isinstance(window, bool) or not isinstance(window, int) or window < 1):
            raise ValueError(f"TracingTwoComplex: window must be a positive int or None, got {window!r}")
        self.n = 2
        self.inner = inner
        self.family = inner.family
        self._raw = inner._raw
        self._m = inner._m
        self._stats = inner.stats
        self._window = window
        self._recording = True
        self._ops: list[int] = []
        self._srcs: list[int] = []
        self._simplices: list[tuple[int, ...]] = []
        self._args: list[int] = []
        self._results: list[int] = []
        self._made = 0
        self._known: dict[int, tuple[int, Complex[D]]] = {}
        self._order: deque[int] = deque()
        self._last: Complex[D] | None = None
        self._last_index = -1

    @property
    def recording(self) -> bool:
        """Whether operations are still being recorded (until :meth:`stop`)."""
        return self._recording

    def trace(self) -> Trace:
        """The trace recorded so far (recording goes on).  O(events)."""
        m = len(self._ops)
        simplex = np.full((m, 3), -1, dtype=np.int64)
        for k, labels in enumerate(self._simplices):
            if labels:
                simplex[k, : len(labels)] = labels
        return Trace(
            2,
            np.array(self._ops, dtype=np.uint8),
            np.array(self._srcs, dtype=np.int64),
            simplex,
            np.array(self._args, dtype=np.int64),
            np.array(self._results, dtype=np.int64),
        )

    def stop(self) -> Trace:
        """End the recording and return the :class:`Trace`; later operations are forwarded unrecorded."""
        t = self.trace()
        self._recording = False
        self._known.clear()
        self._order.clear()
        self._last = None
        return t

    # -- bookkeeping ---------------------------------------------------------------------

    def _src(self, c: Any, what: str) -> int:
        """The index of version ``c``; UntrackedVersionError for a complex this recorder does not know."""
        if c is self._last:
            return self._last_index
        entry = self._known.get(id(c))
        if entry is None or entry[1] is not c:
            limit = "" if self._window is None else f" or one older than the last {self._window} versions (window=)"
            raise UntrackedVersionError(
                f"{what}: this complex was not made through this TracingTwoComplex{limit}, so the trace cannot name it"
            )
        return entry[0]

    def _record(self, op: int, src: int, s: Any, arg: int, result: int) -> None:
        self._ops.append(op)
        self._srcs.append(src)
        self._simplices.append(() if s is None else tuple(int(v) for v in s))
        self._args.append(arg)
        self._results.append(result)

    def _version(self, c: Complex[D]) -> int:
        """Register ``c`` as the next version; returns its index."""
        k = self._made
        self._made += 1
        self._last, self._last_index = c, k
        self._known[id(c)] = (k, c)
        self._order.append(id(c))
        if self._window is not None and len(self._order) > self._window:
            del self._known[self._order.popleft()]
        return k

    # -- the SIMPCOMP operations, recorded -------------------------------------------------

    def new(self, n: int, /) -> Complex[D]:
        """``new n``, recorded."""
        c = self.inner.new(n)
        if self._recording:
            self._record(NEW, -1, None, n, self._version(c))
        return c

    def dim(self, c: Complex[D], /) -> int:
        """``dim c``, recorded."""
        if not self._recording:
            return self.inner.dim(c)
        src = self._src(c, "dim")
        d = self.inner.dim(c)
        self._record(DIM, src, None, 0, d)
        return d

    def isEmpty(self, c: Complex[D], /) -> bool:
        """``isEmpty c``, recorded."""
        if not self._recording:
            return self.inner.isEmpty(c)
        src = self._src(c, "isEmpty")
        e = self.inner.isEmpty(c)
        self._record(IS_EMPTY, src, None, 0, int(e))
        return e

    def vertices(self, c: Complex[D], /) -> Sequence[Vertex]:
        """``vertices c``, recorded."""
        if not self._recording:
            return self.inner.vertices(c)
        src = self._src(c, "vertices")
        vs = self.inner.vertices(c)
        self._record(VERTICES, src, None, 0, len(vs))
        return vs

    def simplices(self, c: Complex[D], d: int, /) -> Sequence[Simplex]:
        """``simplices c d``, recorded."""
        if not self._recording:
            return self.inner.simplices(c, d)
        src = self._src(c, "simplices")
        out = self.inner.simplices(c, d)
        self._record(SIMPLICES, src, None, d, len(out))
        return out

    def items(self, c: Complex[D], /) -> list[tuple[Triangle, D]]:
        """Each triangle with its datum, recorded."""
        if not self._recording:
            return self.inner.items(c)
        src = self._src(c, "items")
        out = self.inner.items(c)
        self._record(ITEMS, src, None, 0, len(out))
        return out

    def data(self, c: Complex[D], s: Simplex, /) -> Option[D]:
        """``data (c, s)``, recorded."""
        if not self._recording:
            return self.inner.data(c, s)
        src = self._src(c, "data")
        x = self.inner.data(c, s)
        self._record(DATA, src, s, 0, 0 if x is None else 1)
        return x

    def grep(self, c: Complex[D], d: int, s: Simplex, /) -> Sequence[Simplex]:
        """``grep c (d, s)``, recorded."""
        if not self._recording:
            return self.inner.grep(c, d, s)
        src = self._src(c, "grep")
        out = self.inner.grep(c, d, s)
        self._record(GREP, src, s, d, len(out))
        return out

    def find(self, c: Complex[D], s: Simplex, /) -> list[Triangle]:
        """``find (c, s)``, recorded."""
        if not self._recording:
            return self.inner.find(c, s)
        src = self._src(c, "find")
        out = self.inner.find(c, s)
        self._record(FIND, src, s, 0, len(out))
        return out

    def findi(self, c: Complex[D], s: Simplex, /) -> list[tuple[Triangle, D]]:
        """``find`` with data, recorded."""
        if not self._recording:
            return self.inner.findi(c, s)
        src = self._src(c, "findi")
        out = self.inner.findi(c, s)
        self._record(FINDI, src, s, 0, len(out))
        return out

    def neighbour(self, c: Complex[D], s: Simplex, /) -> tuple[Triangle, D] | None:
        """``neighbour (c, s)``, recorded as a ``findi`` event with ``arg`` 1 (a findi that stops at the first
        triangle; its result is 1 or 0), which :func:`replay` re-executes with ``neighbour``."""
        if not self._recording:
            return self.inner.neighbour(c, s)
        src = self._src(c, "neighbour")
        out = self.inner.neighbour(c, s)
        self._record(FINDI, src, s, FIRST, 0 if out is None else 1)
        return out

    def add(self, c: Complex[D], s: Simplex, x: D, /) -> Complex[D]:
        """``add (c, s, x)``, recorded (``x`` is not: see the module docstring)."""
        if not self._recording:
            return self.inner.add(c, s, x)
        src = self._src(c, "add")
        out = self.inner.add(c, s, x)
        self._record(ADD, src, s, 0, self._version(out))
        return out

    def rem(self, c: Complex[D], s: Simplex, /) -> Complex[D]:
        """``rem (c, s)``, recorded."""
        if not self._recording:
            return self.inner.rem(c, s)
        src = self._src(c, "rem")
        out = self.inner.rem(c, s)
        self._record(REM, src, s, 0, self._version(out))
        return out

    def update(self, c: Complex[D], s: Simplex, f: Callable[[D], D], /) -> Complex[D]:
        """``update (c, s, f)``, recorded (``f`` is not: see the module docstring)."""
        if not self._recording:
            return self.inner.update(c, s, f)
        src = self._src(c, "update")
        out = self.inner.update(c, s, f)
        self._record(UPDATE, src, s, 0, self._version(out))
        return out

    def replace(
        self, c: Complex[D], removed: Sequence[Simplex], added: Sequence[tuple[Simplex, D]], /
    ) -> Complex[D]:
        """``replace (c, removed, added)``, recorded as its parts then the ``replace`` event (data are not)."""
        if not self._recording:
            return self.inner.replace(c, removed, added)
        src = self._src(c, "replace")
        removed, added = list(removed), list(added)
        out = self.inner.replace(c, removed, added)
        for s in removed:
            self._record(REPLACE_REM, src, s, 0, -1)
        for s, _ in added:
            self._record(REPLACE_ADD, src, s, 0, -1)
        self._record(REPLACE, src, None, len(removed) + len(added), self._version(out))
        return out

    def check(self, c: Complex[D], /) -> None:
        """``inner``'s representation check (not recorded: not a SIMPCOMP operation)."""
        self.inner.check(c)

    def __repr__(self) -> str:
        state = "recording" if self._recording else "stopped"
        return f"<TracingTwoComplex over {self.inner!r}, {state}, {len(self._ops)} events>"


# -- replay ----------------------------------------------------------------------------


class Replay:
    """A trace made ready to run: its vertices made and each event's arguments built (untimed work).

    :meth:`run` then does only the complex operations, so timing it measures
    the complex (what ``persistri bench complex`` does).  The vertices are
    fresh, of a new lineage, one per recorded label, each located at its label.
    """

    def __init__(self, trace: Trace) -> None:
        if not isinstance(trace, Trace):
            raise TypeError(f"Replay: expected a Trace, got {type(trace).__name__}")
        self.trace = trace
        labels = trace.labels()
        top = int(labels[-1]) + 1 if labels.size else 0
        _, verts = int_vertex.new_many(VertexState.initial(), range(top))
        self.vertices: list[Vertex] = verts
        cache: dict[tuple[int, ...], tuple[Vertex, ...]] = {}
        args: list[tuple[Vertex, ...]] = []
        for row in trace.simplex.tolist():
            key = tuple(x for x in row if x >= 0)
            s = cache.get(key)
            if s is None:
                s = tuple(verts[x] for x in key)
                cache[key] = s
            args.append(s)
        self._simplices = args
        self._ops: list[int] = trace.op.tolist()
        self._srcs: list[int] = trace.src.tolist()
        self._args: list[int] = trace.arg.tolist()
        self._results: list[int] = trace.result.tolist()
        # Each version is kept until its last use; the last version made is kept to the end.
        last_use: dict[int, int] = {}
        for k, src in enumerate(self._srcs):
            if src >= 0:
                last_use[src] = k
        self._final = trace.versions - 1
        frees: list[tuple[int, ...]] = [()] * len(trace)
        by_event: dict[int, list[int]] = {}
        for v, k in last_use.items():
            if v != self._final:
                by_event.setdefault(k, []).append(v)
        for k, vs in by_event.items():
            frees[k] = tuple(vs)
        self._frees = frees

    def run(self, structure: ComplexStructure[Any], *, verify: bool = True) -> Complex[Any]:
        """Re-execute every event on ``structure`` and return the last version made.

        ``structure`` must make n-complexes for the trace's n (a 2-complex
        structure for a recorded 2-complex run).  With ``verify`` every
        result is compared with the recorded summary (:class:`ReplayMismatch`
        names the first event that differs).  The ephemeral baseline can
        replay a trace whose every operation reads the newest version only.
        """
        if not isinstance(structure, ComplexStructure):
            raise TypeError(f"replay: expected a persistri complex structure, got {type(structure).__name__}")
        if structure.n != self.trace.n:
            raise TraceError(f"replay: the trace is of {self.trace.n}-complexes, the structure makes {structure.n}-complexes")
        if self._final < 0:
            raise TraceError("replay: the trace makes no complex (it has no new event)")
        new, add, rem, update = structure.new, structure.add, structure.rem, structure.update
        data, find, findi, replace = structure.data, structure.find, structure.findi, structure.replace
        neighbour = structure.neighbour
        removed: list[Simplex] = []
        added: list[tuple[Simplex, int]] = []
        # A list indexed by version (a slot is cleared at the version's last use): cheaper than a dict.
        versions: list[Complex[Any] | None] = [None] * (self._final + 1)
        made = 0
        events = zip(self._ops, self._srcs, self._simplices, self._args, self._results, self._frees, strict=True)
        for k, (op, src, s, arg, want, free) in enumerate(events):
            got: int
            if op == FINDI:
                if arg:
                    got = 0 if neighbour(versions[src], s) is None else 1
                else:
                    got = len(findi(versions[src], s))
            elif op == ADD:
                versions[made] = add(versions[src], s, k)
                got = made
                made += 1
            elif op == REM:
                versions[made] = rem(versions[src], s)
                got = made
                made += 1
            elif op == DATA:
                got = 0 if data(versions[src], s) is None else 1
            elif op == FIND:
                got = len(find(versions[src], s))
            elif op == REPLACE_REM:
                removed.append(s)
                got = -1
            elif op == REPLACE_ADD:
                added.append((s, k))
                got = -1
            elif op == REPLACE:
                versions[made] = replace(versions[src], removed, added)
                removed, added = [], []
                got = made
                made += 1
            elif op == UPDATE:
                versions[made] = update(versions[src], s, _placeholder(k))
                got = made
                made += 1
            elif op == NEW:
                versions[made] = new(arg)
                got = made
                made += 1
            else:
                got = self._query(structure, op, versions[src], s, arg)
            if verify and got != want:
                _mismatch(self.trace, k, got)
            if free:
                for v in free:
                    versions[v] = None
        final = versions[self._final]
        assert final is not None
        return final

    @staticmethod
    def _query(structure: ComplexStructure[Any], op: int, c: Any, s: Simplex, arg: int) -> int:
        """The summary of a rare query (grep, items, simplices, vertices, isEmpty, dim)."""
        if op == GREP:
            return len(structure.grep(c, arg, s))
        if op == ITEMS:
            return len(structure.items(c))
        if op == SIMPLICES:
            return len(structure.simplices(c, arg))
        if op == VERTICES:
            return len(structure.vertices(c))
        if op == IS_EMPTY:
            return int(structure.isEmpty(c))
        return structure.dim(c)


def _placeholder(k: int) -> Callable[[Any], int]:
    """The function ``update`` is replayed with: its result is the event index (data are not recorded)."""

    def f(_old: Any) -> int:
        return k

    return f


def _mismatch(trace: Trace, k: int, got: int) -> None:
    op, src, labels, arg, want = trace.event(k)
    what = "version" if op in MAKES_VERSION else "result"
    raise ReplayMismatch(
        f"replay diverges at event {k}: {op}(version {src}, {labels!r}{f', {arg}' if arg else ''}) "
        f"gave {what} {got}, the recorded run {want}"
    )


def replay(trace: Trace, structure: ComplexStructure[Any], *, verify: bool = True) -> Complex[Any]:
    """Re-execute ``trace`` on ``structure`` and return the last version made (:meth:`Replay.run`)."""
    return Replay(trace).run(structure, verify=verify)


# -- files -----------------------------------------------------------------------------


def save_trace(trace: Trace, path: str | Path) -> Path:
    """Write ``trace`` to ``path``: ``.npz`` (compressed arrays) or ``.json`` (one list per event); returns the path."""
    p = Path(path)
    if p.suffix == ".npz":
        with p.open("wb") as fh:
            np.savez_compressed(
                fh,
                format=np.array(_FORMAT),
                format_version=np.array(_FORMAT_VERSION),
                n=np.array(trace.n),
                op=trace.op,
                src=trace.src,
                simplex=trace.simplex,
                arg=trace.arg,
                result=trace.result,
            )
    elif p.suffix == ".json":
        doc = {
            "format": _FORMAT,
            "format_version": _FORMAT_VERSION,
            "n": trace.n,
            "operations": list(OPERATIONS),
            "events": [[op, src, list(labels), arg, result] for op, src, labels, arg, result in trace.events()],
        }
        p.write_text(json.dumps(doc, separators=(",", ":")))
    else:
        raise TraceFormatError(f"save_trace: {p.name!r}: the file name must end in .npz or .json")
    return p


def load_trace(path: str | Path) -> Trace:
    """Read a trace written by :func:`save_trace` (``.npz`` or ``.json``); TraceFormatError if malformed."""
    p = Path(path)
    if p.suffix == ".npz":
        try:
            with np.load(p, allow_pickle=False) as z:
                fields = {k: z[k] for k in z.files}
        except (OSError, ValueError) as exc:
            raise TraceFormatError(f"load_trace: {p}: not a readable .npz file ({exc})") from None
        need = ("format", "format_version", "n", "op", "src", "simplex", "arg", "result")
        missing = [k for k in need if k not in fields]
        if missing:
            raise TraceFormatError(f"load_trace: {p}: missing arrays {', '.join(missing)}")
        _check_header(p, str(fields["format"]), int(fields["format_version"]))
        return Trace(
            int(fields["n"]),
            fields["op"].astype(np.uint8, copy=False),
            fields["src"].astype(np.int64, copy=False),
            fields["simplex"].astype(np.int64, copy=False),
            fields["arg"].astype(np.int64, copy=False),
            fields["result"].astype(np.int64, copy=False),
        )
    if p.suffix == ".json":
        try:
            doc = json.loads(p.read_text())
        except (OSError, ValueError) as exc:
            raise TraceFormatError(f"load_trace: {p}: not a readable JSON file ({exc})") from None
        if not isinstance(doc, dict):
            raise TraceFormatError(f"load_trace: {p}: expected a JSON object")
        _check_header(p, doc.get("format"), doc.get("format_version"))
        return _from_json(p, doc)
    raise TraceFormatError(f"load_trace: {p.name!r}: the file name must end in .npz or .json")


def _check_header(p: Path, fmt: object, version: object) -> None:
    if fmt != _FORMAT:
        raise TraceFormatError(f"load_trace: {p}: not a persistri trace (format {fmt!r})")
    if version not in _READS:
        raise TraceFormatError(f"load_trace: {p}: trace format version {version!r}, this persistri reads {_READS}")


def _from_json(p: Path, doc: dict[str, Any]) -> Trace:
    n = doc.get("n")
    events = doc.get("events")
    names = doc.get("operations")
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise TraceFormatError(f"load_trace: {p}: n must be a positive int, got {n!r}")
    if not isinstance(events, list) or not isinstance(names, list):
        raise TraceFormatError(f"load_trace: {p}: expected the lists 'operations' and 'events'")
    m = len(events)
    op = np.zeros(m, dtype=np.uint8)
    src = np.zeros(m, dtype=np.int64)
    simplex = np.full((m, n + 1), -1, dtype=np.int64)
    arg = np.zeros(m, dtype=np.int64)
    result = np.zeros(m, dtype=np.int64)
    for k, e in enumerate(events):
        ok = (
            isinstance(e, list)
            and len(e) == 5
            and e[0] in _CODE
            and all(isinstance(x, int) and not isinstance(x, bool) for x in (e[1], e[3], e[4]))
            and isinstance(e[2], list)
            and len(e[2]) <= n + 1
            and all(isinstance(x, int) and not isinstance(x, bool) and x >= 0 for x in e[2])
        )
        if not ok:
            raise TraceFormatError(f"load_trace: {p}: event {k} is not [op, src, [labels], arg, result]: {e!r}")
        op[k] = _CODE[e[0]]
        src[k], arg[k], result[k] = e[1], e[3], e[4]
        simplex[k, : len(e[2])] = e[2]
    return Trace(n, op, src, simplex, arg, result)
