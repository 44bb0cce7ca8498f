"""Segment sets made clean, exactly: repeats merged, segments split at the vertices on them, crossings refused.

The steps of :func:`~persistri.impl.mesh.domain.as_pslg` that work on the
segments alone, in order: :func:`dedupe` (repeated segments, either orientation,
merge), :func:`split_at_vertices` (a segment with vertices on its interior
becomes its pieces, so overlapping collinear segments become shared pieces),
:func:`refuse_crossings` (after splitting, two segments meet only at a shared
vertex or cross properly; a crossing is a :class:`~persistri.impl.mesh.errors.DomainError`),
and :func:`convex_hull` for ``convex=True``.  Every decision is an exact
orientation sign (:class:`~persistri.impl.geometry.predicates.Predicates2`'s
true signs); candidates come from sorting by x, so the work is near O(m log m)
for boundaries of ordinary shape and O(m²) only for many long segments over one
slab of x.  Messages name input rows (``origin`` for segments, ``name`` for
vertices).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.mesh.errors import DomainError

__all__ = ["Labels", "convex_hull", "dedupe", "split_at_vertices", "refuse_crossings", "point_text"]

_PAIR_BUDGET = 1 << 22
"""Candidate segment pairs examined per block of the crossing sweep (bounds its memory)."""


def point_text(p: NDArray[np.float64]) -> str:
    """A point as ``(x, y)`` with each coordinate's shortest round-tripping repr."""
    return f"({float(p[0])!r}, {float(p[1])!r})"


def convex_hull(verts: NDArray[np.float64], pred: Predicates2) -> list[int]:
    """The convex hull's extreme vertices, counterclockwise (Andrew's monotone chain, exact turns). O(n log n)."""
    order = np.lexsort((verts[:, 1], verts[:, 0])).tolist()

    def chain(seq: list[int]) -> list[int]:
        out: list[int] = []
        for p in seq:
            while len(out) >= 2 and pred.orient2d_sign(out[-2], out[-1], p) <= 0:
                out.pop()
            out.append(p)
        return out

    lower, upper = chain(order), chain(order[::-1])
    return lower[:-1] + upper[:-1]


@dataclass(frozen=True)
class Labels:
    """Names segments in messages by their input row and input vertex rows."""

    seg: NDArray[np.intp]
    origin: NDArray[np.intp]
    name: NDArray[np.intp]

    def __call__(self, k: int) -> str:
        a, b = (int(self.name[v]) for v in self.seg[k])
        o = int(self.origin[k])
        return f"segment {o} ({a}–{b})" if o >= 0 else f"convex hull edge ({a}–{b})"


def dedupe(
    seg: NDArray[np.intp],
    origin: NDArray[np.intp],
    marks: NDArray[np.intp] | None,
    notes: list[str],
    name: NDArray[np.intp],
) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.intp] | None]:
    """Merge repeated segments (either orientation) into the first; a note for each input one dropped."""
    label = Labels(seg, origin, name)
    if seg.shape[0] < 2:
        return seg, origin, marks
    key = np.sort(seg, axis=1)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    if first.size == seg.shape[0]:
        return seg, origin, marks
    keep = np.sort(first)
    for k in np.flatnonzero(first[inverse] != np.arange(seg.shape[0])).tolist():
        j = int(first[inverse[k]])
        if origin[k] >= 0 and origin[k] != origin[j]:
            notes.append(f"{label(k)} repeats {label(j)}: merged")
    return seg[keep], origin[keep], None if marks is None else marks[keep]


def split_at_vertices(
    verts: NDArray[np.float64],
    seg: NDArray[np.intp],
    origin: NDArray[np.intp],
    marks: NDArray[np.intp] | None,
    pred: Predicates2,
    notes: list[str],
    name: NDArray[np.intp],
    repair: bool,
) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.intp] | None]:
    """Split every segment at the vertices on its interior (exact collinearity), or refuse.

    Candidates come from the vertices sorted by x: those in the segment's
    closed bounding box; exact ``orient2d_sign == 0`` decides (collinear and in
    the box means on the closed segment).
    """
    m = seg.shape[0]
    if m == 0:
        return seg, origin, marks
    label = Labels(seg, origin, name)
    by_x = np.argsort(verts[:, 0], kind="stable")
    xs_sorted = verts[by_x, 0]
    ys = verts[:, 1]
    new_seg: list[list[int]] = []
    new_origin: list[int] = []
    new_marks: list[int] = []
    split_any = False
    for k in range(m):
        a, b = int(seg[k, 0]), int(seg[k, 1])
        ax, ay = float(verts[a, 0]), float(verts[a, 1])
        bx, by = float(verts[b, 0]), float(verts[b, 1])
        lo = int(np.searchsorted(xs_sorted, min(ax, bx), side="left"))
        hi = int(np.searchsorted(xs_sorted, max(ax, bx), side="right"))
        cand = by_x[lo:hi]
        cand = cand[(ys[cand] >= min(ay, by)) & (ys[cand] <= max(ay, by)) & (cand != a) & (cand != b)]
        on: list[int] = []
        if cand.size:
            signs = pred.orient2d_sign_batch(a, b, cand)
            on = cand[signs == 0].tolist()
        if on and origin[k] >= 0:
            first = on[0] if len(on) == 1 else min(on, key=lambda v: (abs(verts[v, 0] - ax), abs(verts[v, 1] - ay)))
            msg = f"vertex {int(name[first])} at {point_text(verts[first])} lies on the interior of {label(k)}"
            if not repair:
                raise DomainError(msg)
            rest = f" (and {len(on) - 1} more)" if len(on) > 1 else ""
            notes.append(msg + rest + ": split there")
        chain = [a] + sorted(on, key=lambda v: (float(verts[v, 0]), float(verts[v, 1])), reverse=(ax, ay) > (bx, by)) + [b]
        split_any = split_any or bool(on)
        for u, v in zip(chain[:-1], chain[1:]):
            new_seg.append([u, v])
            new_origin.append(int(origin[k]))
            if marks is not None:
                new_marks.append(int(marks[k]))
    if not split_any:
        return seg, origin, marks
    return (
        np.array(new_seg, dtype=np.intp).reshape(-1, 2),
        np.array(new_origin, dtype=np.intp),
        None if marks is None else np.array(new_marks, dtype=np.intp),
    )


def refuse_crossings(
    verts: NDArray[np.float64], seg: NDArray[np.intp], origin: NDArray[np.intp], name: NDArray[np.intp], pred: Predicates2
) -> None:
    """Raise for the first pair of segments (in sweep order) that cross; exact.

    After splitting, two segments meet only at a shared endpoint or by crossing
    properly: each straddles the other's line (both orientation products < 0).
    Candidate pairs come from a sweep in x over the segments' bounding boxes.
    """
    m = seg.shape[0]
    if m < 2:
        return
    label = Labels(seg, origin, name)
    a, b = seg[:, 0], seg[:, 1]
    lo_x = np.minimum(verts[a, 0], verts[b, 0])
    hi_x = np.maximum(verts[a, 0], verts[b, 0])
    lo_y = np.minimum(verts[a, 1], verts[b, 1])
    hi_y = np.maximum(verts[a, 1], verts[b, 1])
    order = np.argsort(lo_x, kind="stable")
    sorted_lo = lo_x[order]
    end = np.searchsorted(sorted_lo, hi_x[order], side="right")
    count = np.maximum(end - np.arange(m) - 1, 0)
    start = 0
    while start < m:
        stop = start + 1
        budget = int(count[start])
        while stop < m and budget + int(count[stop]) <= _PAIR_BUDGET:
            budget += int(count[stop])
            stop += 1
        rows = np.arange(start, stop)
        reps = count[rows]
        first_pos = np.repeat(rows, reps)
        offsets = np.arange(int(reps.sum())) - np.repeat(np.cumsum(reps) - reps, reps)
        i, j = order[first_pos], order[first_pos + 1 + offsets]
        keep = (lo_y[i] <= hi_y[j]) & (lo_y[j] <= hi_y[i])
        keep &= (a[i] != a[j]) & (a[i] != b[j]) & (b[i] != a[j]) & (b[i] != b[j])
        for s, t in zip(i[keep].tolist(), j[keep].tolist()):
            p, q, r, u = int(a[s]), int(b[s]), int(a[t]), int(b[t])
            if pred.orient2d_sign(p, q, r) * pred.orient2d_sign(p, q, u) < 0 and (
                pred.orient2d_sign(r, u, p) * pred.orient2d_sign(r, u, q) < 0
            ):
                s, t = min(s, t), max(s, t)
                x, y = _crossing_point(verts, seg[s], seg[t])
                raise DomainError(f"{label(s)} and {label(t)} cross at about ({x:.17g}, {y:.17g}) without a shared vertex")
        start = stop


def _crossing_point(verts: NDArray[np.float64], s: NDArray[np.intp], t: NDArray[np.intp]) -> tuple[float, float]:
    p, r = verts[s[0]], verts[t[0]]
    d, e = verts[s[1]] - p, verts[t[1]] - r
    with np.errstate(all="ignore"):
        denom = d[0] * e[1] - d[1] * e[0]
        lam = ((r[0] - p[0]) * e[1] - (r[1] - p[1]) * e[0]) / denom
        return float(p[0] + lam * d[0]), float(p[1] + lam * d[1])
