"""Segment sets made clean, exactly: repeats merged, segments split at the vertices on them, crossings refused.

The steps of :func:`~persistri.impl.mesh.domain.as_pslg` that work on the
segments alone, in order: :func:`dedupe` (repeated segments, either orientation,
merge), :func:`split_at_vertices` (a segment with vertices on its interior
becomes its pieces, so overlapping collinear segments become shared pieces),
:func:`refuse_crossings` (after splitting, two segments meet only at a shared
vertex or cross properly; a crossing is a :class:`~persistri.impl.mesh.errors.DomainError`),
and :func:`convex_hull` for ``convex=True``.  Every decision is an exact
orientation sign (:class:`~persistri.impl.geometry.growing.GrowingPredicates2`'s
true signs: the proved filter vectorised over every candidate at once,
:func:`orient_signs`, exact integers for what it leaves); candidates come from
sorting by x, so the work is near O(m log m) for boundaries of ordinary shape
and O(m²) only for many long segments over one slab of x.  Messages name input rows (``origin`` for segments, ``name`` for
vertices).
"""

from __future__ import annotations

from bisect import bisect_left, bisect_right
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from persistri.impl.geometry.filter import ERRBOUND_ORIENT2D, orient2d_terms
from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.errors import DomainError

__all__ = ["FEW_SEGMENTS", "Labels", "OrientSigns", "convex_hull", "dedupe", "orient_signs", "split_at_vertices", "refuse_crossings", "point_text"]

_PAIR_BUDGET = 1 << 22
"""Candidate segment pairs examined per block of the crossing sweep (bounds its memory)."""


def point_text(p: NDArray[np.float64]) -> str:
    """A point as ``(x, y)`` with each coordinate's shortest round-tripping repr."""
    return f"({float(p[0])!r}, {float(p[1])!r})"


class OrientSigns(Protocol):
    """Exact true orientation signs by point index (``Predicates2`` and ``GrowingPredicates2`` both give them)."""

    def orient2d_sign(self, a: int, b: int, c: int) -> int:
        """The true sign (-1, 0, +1) of orient2d(a, b, c): +1 when they turn counterclockwise."""
        ...


def orient_signs(
    pred: GrowingPredicates2,
    columns: tuple[NDArray[np.float64], NDArray[np.float64]],
    a: NDArray[np.intp],
    b: NDArray[np.intp],
    c: NDArray[np.intp],
) -> NDArray[np.int8]:
    """The true signs of ``orient2d(a[k], b[k], c[k])`` for index arrays of one length; exact.

    ``columns`` is ``pred.filter_columns()``.  One vectorised pass of the proved
    filter (:func:`~persistri.impl.geometry.filter.orient2d_terms` and its bound, the
    operations of ``pred.orient2d_sign``'s own filter; a point the filter cannot take
    is NaN there, which no comparison accepts) decides most entries; each other one
    (an exact zero among them) is ``pred.orient2d_sign``.  O(len(a)) vectorised, plus
    O(1) Python per undecided entry.
    """
    fx, fy = columns
    det, perm = orient2d_terms(fx[a], fy[a], fx[b], fy[b], fx[c], fy[c])
    thr = ERRBOUND_ORIENT2D * perm
    pos = det > thr
    neg = det < -thr
    out: NDArray[np.int8] = pos.view(np.int8) - neg.view(np.int8)
    unsure = np.flatnonzero(~(pos | neg))
    if unsure.size:
        sign = pred.orient2d_sign
        for k, p, q, r in zip(unsure.tolist(), a[unsure].tolist(), b[unsure].tolist(), c[unsure].tolist()):
            out[k] = sign(p, q, r)
    return out


def convex_hull(verts: NDArray[np.float64], pred: OrientSigns) -> list[int]:
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
    m = seg.shape[0]
    if m < 2:
        return seg, origin, marks
    if m <= FEW_SEGMENTS:
        # Distinct pairs (the usual case), told by one set of sorted pairs.
        if len({(a, b) if a < b else (b, a) for a, b in seg.tolist()}) == m:
            return seg, origin, marks
    else:
        key = np.sort(seg, axis=1)
        # Distinct pairs are told by one set of Python ints: a pair (a, b), a < b <= max, as one code.
        codes = key[:, 0] * (int(key[:, 1].max()) + 1) + key[:, 1]
        if len(set(codes.tolist())) == m:
            return seg, origin, marks
    key = np.sort(seg, axis=1)
    label = Labels(seg, origin, name)
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
    pred: GrowingPredicates2,
    notes: list[str],
    name: NDArray[np.intp],
    repair: bool,
    columns: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.intp] | None]:
    """Split every segment at the vertices on its interior (exact collinearity), or refuse.

    Candidates come from the vertices sorted by x: those in the segment's
    closed bounding box other than its ends, every (segment, candidate) pair at
    once (in blocks of :data:`_PAIR_BUDGET` pairs); an exact ``orient2d_sign == 0``
    decides (collinear and in the box means on the closed segment), by
    :func:`orient_signs`.  ``columns``: ``pred.filter_columns()`` if made already.
    O(m log n + k) vectorised for k candidate pairs, plus O(m) Python when a
    segment is split.
    """
    m = seg.shape[0]
    if m == 0:
        return seg, origin, marks
    if m <= FEW_SEGMENTS:
        on_of = _vertices_on_few(verts, seg, pred)
    else:
        on_of = _vertices_on_many(verts, seg, pred, columns)
    if not on_of:
        return seg, origin, marks
    label = Labels(seg, origin, name)
    new_seg: list[list[int]] = []
    new_origin: list[int] = []
    new_marks: list[int] = []
    for k_, (a, b) in enumerate(seg.tolist()):
        on = on_of.get(k_, [])
        ax_, ay_ = float(verts[a, 0]), float(verts[a, 1])
        if on and origin[k_] >= 0:
            first = on[0] if len(on) == 1 else min(on, key=lambda v: (abs(verts[v, 0] - ax_), abs(verts[v, 1] - ay_)))
            msg = f"vertex {int(name[first])} at {point_text(verts[first])} lies on the interior of {label(k_)}"
            if not repair:
                raise DomainError(msg)
            rest = f" (and {len(on) - 1} more)" if len(on) > 1 else ""
            notes.append(msg + rest + ": split there")
        bx_, by_ = float(verts[b, 0]), float(verts[b, 1])
        chain = [a] + sorted(on, key=lambda v: (float(verts[v, 0]), float(verts[v, 1])), reverse=(ax_, ay_) > (bx_, by_)) + [b]
        for u, v in zip(chain[:-1], chain[1:]):
            new_seg.append([u, v])
            new_origin.append(int(origin[k_]))
            if marks is not None:
                new_marks.append(int(marks[k_]))
    return (
        np.array(new_seg, dtype=np.intp).reshape(-1, 2),
        np.array(new_origin, dtype=np.intp),
        None if marks is None else np.array(new_marks, dtype=np.intp),
    )


FEW_SEGMENTS = 32
"""Up to this many segments, :func:`split_at_vertices` and :func:`refuse_crossings` find their candidates with
Python loops over lists (O(m·n) and O(m²) comparisons of doubles) instead of numpy's vectorised sweep, whose
fixed cost of some fifty array calls is most of a small domain's validation; both ways give the same candidates
in the same order, and the same exact signs decide (tests/test_mesh_segments_paths.py compares them)."""


def _vertices_on_few(verts: NDArray[np.float64], seg: NDArray[np.intp], pred: GrowingPredicates2) -> dict[int, list[int]]:
    """:func:`_vertices_on_many`'s answer with Python loops (a few segments). O(m·n)."""
    pts: list[list[float]] = verts.tolist()
    by_x = sorted(range(len(pts)), key=lambda v: pts[v][0])  # stable, as numpy's stable argsort
    xs_sorted = [pts[v][0] for v in by_x]
    sign = pred.orient2d_sign
    on_of: dict[int, list[int]] = {}
    for s, (a, b) in enumerate(seg.tolist()):
        (ax, ay), (bx, by) = pts[a], pts[b]
        lo_y, hi_y = (ay, by) if ay <= by else (by, ay)
        lo_x, hi_x = (ax, bx) if ax <= bx else (bx, ax)
        for k in range(bisect_left(xs_sorted, lo_x), bisect_right(xs_sorted, hi_x)):
            v = by_x[k]
            if v != a and v != b and lo_y <= pts[v][1] <= hi_y and sign(a, b, v) == 0:
                on_of.setdefault(s, []).append(v)
    return on_of


def _vertices_on_many(
    verts: NDArray[np.float64],
    seg: NDArray[np.intp],
    pred: GrowingPredicates2,
    columns: tuple[NDArray[np.float64], NDArray[np.float64]] | None,
) -> dict[int, list[int]]:
    """The vertices on each segment's closed bounding box and line, ends excluded: ``segment -> vertices`` in the
    order of the vertices sorted by x (stable), for the segments that have any (:func:`split_at_vertices`).
    Vectorised over every (segment, candidate) pair at once, in blocks of :data:`_PAIR_BUDGET`. O(m log n + k)."""
    by_x = np.argsort(verts[:, 0], kind="stable")
    xs_sorted = verts[by_x, 0]
    ys = verts[:, 1]
    a_all, b_all = seg[:, 0], seg[:, 1]
    ax, bx = verts[a_all, 0], verts[b_all, 0]
    ay, by = verts[a_all, 1], verts[b_all, 1]
    lo_y, hi_y = np.minimum(ay, by), np.maximum(ay, by)
    lo = np.searchsorted(xs_sorted, np.minimum(ax, bx), side="left")
    count = np.searchsorted(xs_sorted, np.maximum(ax, bx), side="right") - lo
    if columns is None:
        columns = pred.filter_columns()
    on_of: dict[int, list[int]] = {}
    for start, stop in _blocks(count):
        reps = count[start:stop]
        k = np.repeat(np.arange(start, stop), reps)  # each pair's segment, candidates in the order of by_x
        cand = by_x[lo[k] + (np.arange(k.size) - np.repeat(np.cumsum(reps) - reps, reps))]
        inside = (ys[cand] >= lo_y[k]) & (ys[cand] <= hi_y[k]) & (cand != a_all[k]) & (cand != b_all[k])
        k, cand = k[inside], cand[inside]
        if k.size:
            zero = orient_signs(pred, columns, a_all[k], b_all[k], cand) == 0
            for s, v in zip(k[zero].tolist(), cand[zero].tolist()):
                on_of.setdefault(s, []).append(v)
    return on_of


def refuse_crossings(
    verts: NDArray[np.float64],
    seg: NDArray[np.intp],
    origin: NDArray[np.intp],
    name: NDArray[np.intp],
    pred: GrowingPredicates2,
    columns: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
) -> None:
    """Raise for the first pair of segments (in sweep order) that cross; exact.

    After splitting, two segments meet only at a shared endpoint or by crossing
    properly: each straddles the other's line (both orientation products < 0).
    Candidate pairs come from a sweep in x over the segments' bounding boxes; the
    proved filter, vectorised over them (:func:`orient_signs`' first pass), sets
    aside every pair with a segment's two ends certainly on one side of the other's
    line, and the exact signs decide the rest in sweep order.  ``columns``:
    ``pred.filter_columns()`` if made already.
    """
    m = seg.shape[0]
    if m < 2:
        return
    if m <= FEW_SEGMENTS:
        pairs: Iterable[tuple[int, int]] = _crossing_candidates_few(verts, seg)
    else:
        pairs = _crossing_candidates_many(verts, seg, pred, columns)
    a, b = seg[:, 0].tolist(), seg[:, 1].tolist()
    for s, t in pairs:
        p, q, r, u = a[s], b[s], a[t], b[t]
        if pred.orient2d_sign(p, q, r) * pred.orient2d_sign(p, q, u) < 0 and (
            pred.orient2d_sign(r, u, p) * pred.orient2d_sign(r, u, q) < 0
        ):
            s, t = min(s, t), max(s, t)
            x, y = _crossing_point(verts, seg[s], seg[t])
            label = Labels(seg, origin, name)
            raise DomainError(f"{label(s)} and {label(t)} cross at about ({x:.17g}, {y:.17g}) without a shared vertex")


def _crossing_candidates_few(verts: NDArray[np.float64], seg: NDArray[np.intp]) -> Iterator[tuple[int, int]]:
    """:func:`_crossing_candidates_many`'s pairs with Python loops (a few segments; no filter pass: the exact test
    decides every pair, and a pair the filter sets aside cannot cross). O(m²)."""
    pts: list[list[float]] = verts.tolist()
    ends: list[list[int]] = seg.tolist()
    boxes = []
    for a, b in ends:
        (ax, ay), (bx, by) = pts[a], pts[b]
        boxes.append((min(ax, bx), max(ax, bx), min(ay, by), max(ay, by)))
    order = sorted(range(len(ends)), key=lambda k: boxes[k][0])  # stable, as numpy's stable argsort
    for r, i in enumerate(order):
        _, hi_x, lo_y, hi_y = boxes[i]
        a, b = ends[i]
        for j in order[r + 1 :]:
            lo_xj, _, lo_yj, hi_yj = boxes[j]
            if lo_xj > hi_x:
                break
            if lo_y <= hi_yj and lo_yj <= hi_y:
                c, d = ends[j]
                if a != c and a != d and b != c and b != d:
                    yield i, j


def _crossing_candidates_many(
    verts: NDArray[np.float64],
    seg: NDArray[np.intp],
    pred: GrowingPredicates2,
    columns: tuple[NDArray[np.float64], NDArray[np.float64]] | None,
) -> Iterator[tuple[int, int]]:
    """The pairs of segments that may cross, in sweep order: boxes overlapping (a sweep in x over the segments
    sorted by their least x, stable), no shared end, and not set aside by the proved filter (both ends of one
    certainly on one side of the other's line).  Vectorised, in blocks of :data:`_PAIR_BUDGET` pairs."""
    m = seg.shape[0]
    a, b = seg[:, 0], seg[:, 1]
    lo_x = np.minimum(verts[a, 0], verts[b, 0])
    hi_x = np.maximum(verts[a, 0], verts[b, 0])
    lo_y = np.minimum(verts[a, 1], verts[b, 1])
    hi_y = np.maximum(verts[a, 1], verts[b, 1])
    order = np.argsort(lo_x, kind="stable")
    sorted_lo = lo_x[order]
    end = np.searchsorted(sorted_lo, hi_x[order], side="right")
    count = np.maximum(end - np.arange(m) - 1, 0)
    for start, stop in _blocks(count):
        rows = np.arange(start, stop)
        reps = count[rows]
        first_pos = np.repeat(rows, reps)
        offsets = np.arange(int(reps.sum())) - np.repeat(np.cumsum(reps) - reps, reps)
        i, j = order[first_pos], order[first_pos + 1 + offsets]
        keep = (lo_y[i] <= hi_y[j]) & (lo_y[j] <= hi_y[i])
        keep &= (a[i] != a[j]) & (a[i] != b[j]) & (b[i] != a[j]) & (b[i] != b[j])
        i, j = i[keep], j[keep]
        if i.size:
            if columns is None:
                columns = pred.filter_columns()
            apart = _one_side(columns, a[i], b[i], a[j], b[j]) | _one_side(columns, a[j], b[j], a[i], b[i])
            i, j = i[~apart], j[~apart]
        yield from zip(i.tolist(), j.tolist())


def _blocks(count: NDArray[np.intp]) -> list[tuple[int, int]]:
    """Consecutive ranges ``[start, stop)`` of rows whose counts of pairs sum to at most :data:`_PAIR_BUDGET`
    (a row over it alone); the pairs of the blocks in order are the pairs of all rows in order. O(m)."""
    counts: list[int] = count.tolist()
    m = len(counts)
    if sum(counts) <= _PAIR_BUDGET:
        return [(0, m)] if m else []
    blocks: list[tuple[int, int]] = []
    start = 0
    while start < m:
        stop = start + 1
        budget = counts[start]
        while stop < m and budget + counts[stop] <= _PAIR_BUDGET:
            budget += counts[stop]
            stop += 1
        blocks.append((start, stop))
        start = stop
    return blocks


def _one_side(
    columns: tuple[NDArray[np.float64], NDArray[np.float64]],
    p: NDArray[np.intp],
    q: NDArray[np.intp],
    r: NDArray[np.intp],
    u: NDArray[np.intp],
) -> NDArray[np.bool_]:
    """Per entry, whether the proved filter puts ``r`` and ``u`` strictly on one side of line ``p q``.

    True only when both orientation signs are certain and equal (then the segments
    ``p q`` and ``r u`` cannot cross); False leaves the entry to the exact test.
    """
    fx, fy = columns
    px, py, qx, qy = fx[p], fy[p], fx[q], fy[q]
    d1, m1 = orient2d_terms(px, py, qx, qy, fx[r], fy[r])
    d2, m2 = orient2d_terms(px, py, qx, qy, fx[u], fy[u])
    t1, t2 = ERRBOUND_ORIENT2D * m1, ERRBOUND_ORIENT2D * m2
    same: NDArray[np.bool_] = ((d1 > t1) & (d2 > t2)) | ((d1 < -t1) & (d2 < -t2))
    return same


def _crossing_point(verts: NDArray[np.float64], s: NDArray[np.intp], t: NDArray[np.intp]) -> tuple[float, float]:
    p, r = verts[s[0]], verts[t[0]]
    d, e = verts[s[1]] - p, verts[t[1]] - r
    with np.errstate(all="ignore"):
        denom = d[0] * e[1] - d[1] * e[0]
        lam = ((r[0] - p[0]) * e[1] - (r[1] - p[1]) * e[0]) / denom
        return float(p[0] + lam * d[0]), float(p[1] + lam * d[1])
