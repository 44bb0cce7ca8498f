"""``extend_parallel``: new points added to a hull computed chunk by chunk, as a new hull sharing its structure.

A :class:`~persistri.impl.scale.hull.ParallelHull` keeps the final merge's full
persistent run (:class:`~persistri.impl.hull.api.Hull`) over the candidates
that reached it — every vertex of the hull among them.  Points added to a set
can only take vertices away from it, so the hull of the input and new points
is the hull of the candidates and new points, and the bulldozer can resume the
final merge's run (:func:`~persistri.impl.hull.extend.extend_hull`, paper §3,
Appendix A.1) as the one-process ``add_points`` resumes its own.  The old hull
is unchanged; every face the new points leave alone is shared.

**Exactly the one-process extension.**  Three things make it so:

* *Duplicates.*  A new point equal to an old row is merged into the old row
  and reported as ``(new row, first equal old row)`` — also when that old row
  never reached the final merge (a point inside the hull), so the input is
  scanned once for the new points, block by block, in this process; a new
  point equal to an earlier new one is merged into it.
* *Labels.*  The one-process extension labels the distinct new points after
  the old ones, in Morton order over their own box
  (:func:`~persistri.impl.geometry.zorder.morton_order`); the final merge was
  labelled ``"input"``, so the new points are handed to it in that same order.
  Every pair of points then compares as in the one-process run (Simulation of
  Simplicity depends only on the order of the labels), and points that are
  not candidates are not vertices either way.
* *The end.*  The hull of the perturbed points does not depend on the
  bulldozer's path (its first tetrahedron, centre and insertion order).

Cost: one read of the input (O(n), the duplicate scan: ``k`` new points against
each block, O((b + k) lg(b + k)) per block of ``b`` rows), then
``extend_hull``'s on the candidates.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.geometry.points import as_points, unique_rows
from persistri.impl.geometry.zorder import morton_order
from persistri.impl.hull.extend import extend_hull
from persistri.impl.scale.hull import ParallelHull, _canonical
from persistri.impl.scale.sources import Block, PointSource, read_block

__all__ = ["extend_parallel"]


def _first_old_rows(source: PointSource, new: NDArray[np.float64]) -> NDArray[np.int64]:
    """For each row of ``new``, the first row of ``source`` exactly equal to it, or -1. One read of ``source``."""
    k = new.shape[0]
    found = np.full(k, -1, dtype=np.int64)
    if not k:
        return found
    for b in source.blocks:
        data = b.data.compute(scheduler="synchronous") if type(b.data).__module__.startswith("dask") else b.data
        block = read_block(data, b.start, source.what)
        if not block.shape[0]:
            continue
        # New rows first: an old row's representative is a new row exactly when it equals one.
        u = unique_rows(np.concatenate([new, block]))
        rep = u.first[u.inverse]
        hits = np.flatnonzero(rep[k:] < k)
        for local, j in zip(hits.tolist(), rep[k:][hits].tolist(), strict=True):
            if found[j] < 0:  # blocks in row order, rows in order within one: the first hit is the first row
                found[j] = b.start + local
        # A new row equal to another new row shares its representative: give it the same old row.
        found = np.where(found < 0, found[rep[:k]], found)
        if np.all(found >= 0):
            break
    return found


def extend_parallel(
    result: ParallelHull, new_points: ArrayLike, *, check: bool = False, progress: bool | Any = False
) -> ParallelHull:
    """The hull of ``result``'s input and ``new_points`` (``(k, 3)``), continuing its final merge; ``result``
    is unchanged.

    The result's input is ``result``'s rows followed by the new ones (rows ``n … n + k - 1``;
    its ``source`` reads both), and its ``simplices``, ``vertices`` and ``duplicates`` are
    exactly those of ``convex_hull(old points)`` extended by
    :func:`~persistri.impl.hull.extend.extend_hull` with ``new_points`` (the module docstring
    says why).  ``check``, ``progress`` and the errors are ``extend_hull``'s.  In this process.
    """
    new = as_points(new_points, 3, what="new points")
    n, k = result.n, new.shape[0]
    old = _first_old_rows(result.source, new)
    u = unique_rows(new)
    first_new = u.first[u.inverse]
    rows_new = np.arange(n, n + k, dtype=np.int64)
    merged: list[tuple[int, int]] = []
    for j in range(k):
        if old[j] >= 0:
            merged.append((n + j, int(old[j])))
        elif first_new[j] != j:
            merged.append((n + j, n + int(first_new[j])))
    fresh = np.flatnonzero((old < 0) & (first_new == np.arange(k)))
    ordered = fresh[morton_order(np.take(new, fresh, axis=0))] if fresh.size else fresh
    hull = extend_hull(result.hull, np.take(new, ordered, axis=0).reshape(-1, 3), check=check, progress=progress)
    assert len(hull.duplicates) == len(result.hull.duplicates)  # every duplicate was merged above
    rows = np.concatenate([result.rows, rows_new[ordered]])
    simplices = _canonical(rows[hull.simplices])
    source = PointSource(
        n + k,
        (*result.source.blocks, Block(n, n + k, new)),
        f"{result.source.name} and {k:,} added points",
        result.source.what,
    )
    return ParallelHull(
        simplices=simplices,
        vertices=np.unique(simplices),
        duplicates=result.duplicates + tuple(merged),
        n=n + k,
        hull=hull,
        rows=rows,
        chunks=result.chunks,
        merges=result.merges,
        workers=result.workers,
        source=source,
    )
