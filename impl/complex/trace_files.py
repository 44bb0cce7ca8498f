"""Trace files: :func:`save_trace` and :func:`load_trace`, ``.npz`` (compressed arrays) or ``.json``.

:func:`load_trace` validates what it reads (the header, then every event
through :class:`~persistri.impl.complex.trace_events.Trace`) and raises
:class:`~persistri.impl.complex.trace_events.TraceFormatError` naming the
first problem.  Both are O(events).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from persistri.impl.complex.trace_events import (
    OPERATIONS,
    _CODE,
    _FORMAT,
    _FORMAT_VERSION,
    _READS,
    Trace,
    TraceFormatError,
)

__all__ = ["save_trace", "load_trace"]


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
