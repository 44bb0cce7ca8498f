"""Replaying a trace: re-execute its events on any complex structure, with nothing else running.

:class:`Replay` does the untimed work once (fresh vertices, each event's
arguments, when each version may be freed); :meth:`Replay.run` then performs
only the complex operations, checking each result against the recorded
summary.  Data are placeholders (the index of the event that stored them),
as :mod:`persistri.impl.complex.trace` explains.  O(events) plus the cost of
the operations on the structure.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from persistri.impl.complex.simplex import Simplex
from persistri.impl.complex.structure import Complex, ComplexStructure
from persistri.impl.complex.trace_events import (
    ADD,
    DATA,
    FIND,
    FINDI,
    GREP,
    IS_EMPTY,
    ITEMS,
    MAKES_VERSION,
    NEW,
    REM,
    REPLACE,
    REPLACE_ADD,
    REPLACE_REM,
    SIMPLICES,
    UPDATE,
    VERTICES,
    ReplayMismatch,
    Trace,
    TraceError,
)
from persistri.impl.complex.vertex import Vertex, VertexState, int_vertex

__all__ = ["Replay", "replay"]


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
