"""Recording a trace: :class:`TracingTwoComplex`, a 2-complex structure that forwards and records.

Every SIMPCOMP operation (and persistri's ``findi``, ``items``, ``neighbour``
and ``replace``) is forwarded to the inner structure and appended to the
event lists as described in :mod:`persistri.impl.complex.trace`, at O(1)
cost per operation beyond the inner structure's.  Versions are named by the
order they were made; the recorder remembers the last ``window`` of them.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterator, Sequence
from typing import Any, TypeVar

import numpy as np

from persistri.impl.complex.simplex import Simplex
from persistri.impl.complex.structure import Complex
from persistri.impl.complex.trace_events import (
    ADD,
    DATA,
    DIM,
    FIND,
    FINDI,
    FIRST,
    GREP,
    IS_EMPTY,
    ITEMS,
    NEW,
    REM,
    REPLACE,
    REPLACE_ADD,
    REPLACE_REM,
    SIMPLICES,
    UPDATE,
    VERTICES,
    Trace,
    UntrackedVersionError,
)
from persistri.impl.complex.two_complex import Triangle, TwoComplex
from persistri.impl.complex.vertex import Vertex
from persistri.spec.option import Option

__all__ = ["TracingTwoComplex"]

D = TypeVar("D")


class TracingTwoComplex(TwoComplex[D]):
    """A 2-complex structure that forwards every operation to ``inner`` and records it (:mod:`persistri.impl.complex.trace`).

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

    def iter_items(self, c: Complex[D], /) -> Iterator[tuple[Triangle, D]]:
        """``items``, recorded as one ``items`` event (so a replay sees the same operations)."""
        return iter(self.items(c))

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
        """``add (c, s, x)``, recorded (``x`` is not: see :mod:`persistri.impl.complex.trace`)."""
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
        """``update (c, s, f)``, recorded (``f`` is not: see :mod:`persistri.impl.complex.trace`)."""
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
