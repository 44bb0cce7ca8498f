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

Where it lives: the format, the operation codes and the errors in
:mod:`~persistri.impl.complex.trace_events`; recording in
:mod:`~persistri.impl.complex.trace_record`; replay in
:mod:`~persistri.impl.complex.trace_replay`; files in
:mod:`~persistri.impl.complex.trace_files`.  Everything public is re-exported
here: import it from this module.

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

from persistri.impl.complex.trace_events import (
    FIRST,
    MAKES_VERSION,
    OPERATIONS,
    ReplayMismatch,
    Trace,
    TraceError,
    TraceFormatError,
    UntrackedVersionError,
)
from persistri.impl.complex.trace_files import load_trace, save_trace
from persistri.impl.complex.trace_record import TracingTwoComplex
from persistri.impl.complex.trace_replay import Replay, replay

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
