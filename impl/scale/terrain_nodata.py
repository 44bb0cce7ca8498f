"""No-data in DEMs read in windows (:mod:`persistri.impl.scale.terrain_source`), and the pass that checks every cell.

No-data (:class:`NodataRule`) as :func:`~persistri.impl.terrain.grids.as_heights`
has it — ``error``, ``min`` (the lowest valid height of the whole grid, found by
:func:`survey`), a height — and ``fill`` decided per window so that every window
holding a cell gives it the same value: the nearest valid cell (Euclidean, in
cells), found within ``reach`` cells around the window, ties broken by the
smallest ``(row, col)``; a no-data cell with no valid cell within ``reach`` is an
error naming it.  (The one-process path breaks ties as
``scipy.ndimage.distance_transform_edt`` does; without ties the two agree.)
:func:`survey` checks every cell of a grid, chunk by chunk, before any meshing.
Not in the paper: the input side of §5's meshes at scale.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from persistri.impl.scale.terrain_source import Dem, DemSource, FloatArray
from persistri.impl.terrain.grids import HEIGHT_LIMIT, NODATA_RULES

if TYPE_CHECKING:
    from distributed import Client

__all__ = ["NodataRule", "Survey", "survey", "filled_window"]


@dataclass(frozen=True, slots=True)
class NodataRule:
    """What becomes of no-data cells: ``kind`` one of ``error``, ``fill``, ``min``, ``value``; ``value`` the height
    for ``min`` (the grid's lowest, from :func:`survey`) and ``value``; ``reach`` the search radius of ``fill``."""

    kind: str
    value: float = 0.0
    reach: int = 0

    @classmethod
    def of(cls, nodata: str | float, *, reach: int) -> NodataRule:
        """The rule of ``as_heights``'s ``nodata`` argument (``min``'s height is set later by :func:`survey`)."""
        if isinstance(nodata, str):
            if nodata not in NODATA_RULES:
                raise ValueError(f"nodata must be one of {', '.join(NODATA_RULES)} or a number, got {nodata!r}")
            return cls(nodata, 0.0, int(reach))
        if isinstance(nodata, bool) or not isinstance(nodata, (int, float, np.integer, np.floating)):
            raise TypeError(f"nodata must be one of {', '.join(NODATA_RULES)} or a number, got {nodata!r}")
        fill = float(nodata)
        if not math.isfinite(fill) or abs(fill) > HEIGHT_LIMIT:
            raise ValueError(f"nodata fill height must be finite and within ±{HEIGHT_LIMIT:g}, got {fill}")
        return cls("value", fill, int(reach))


@dataclass(frozen=True, slots=True)
class Survey:
    """One pass over the whole grid, chunk by chunk: the no-data count, the first no-data cell, the lowest valid height."""

    missing: int
    first_missing: tuple[int, int] | None
    lowest: float


def survey(dem: Dem, *, client: Client | None = None, chunks: int = 1024) -> Survey:
    """Check every cell as :func:`~persistri.impl.terrain.grids.as_heights` does, without loading the grid:
    a reduction over :meth:`Dem.heights` on the cluster (or in this process).

    Raises :class:`ValueError` (one line naming the grid and the first bad cell)
    for an infinite height, one beyond :data:`HEIGHT_LIMIT`, or a grid of nothing
    but no-data.  O(rows · cols) work, one chunk's memory per task.
    """
    import dask.array as da
    from dask.base import compute

    x = dem.heights(chunks)
    nan = da.isnan(x)
    inf = da.isinf(x)
    big = da.fabs(da.where(nan | inf, 0.0, x)) > HEIGHT_LIMIT
    parts = (nan.sum(), nan.any(axis=1), inf.any(axis=1), big.any(axis=1), da.nanmin(da.where(inf, np.nan, x)))
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # "All-NaN slice": a grid of no-data, refused below
        if client is not None:
            futures = client.compute(list(parts))
            results = client.gather(futures)
        else:
            run: Any = compute  # not annotated
            results = list(run(*parts, scheduler="sync"))
    count, nan_rows, inf_rows, big_rows, lowest = results
    rows, cols = dem.shape
    for flags, what in ((inf_rows, "is infinite"), (big_rows, f"is beyond ±{HEIGHT_LIMIT:g}: the float64 error measure would overflow")):
        if bool(np.any(flags)):
            r = int(np.argmax(flags))
            line = dem.source.read(r, r + 1, 0, cols)[0]
            bad = np.isinf(line) if what == "is infinite" else (np.abs(np.nan_to_num(line, posinf=0.0, neginf=0.0)) > HEIGHT_LIMIT)
            c = int(np.argmax(bad))
            raise ValueError(f"{dem.name}: cell (row {r}, col {c}) {what}")
    count = int(count)
    if count == rows * cols:
        raise ValueError(f"{dem.name}: every cell is no-data (NaN); nothing to triangulate")
    first = None
    if count:
        r = int(np.argmax(nan_rows))
        c = int(np.argmax(np.isnan(dem.source.read(r, r + 1, 0, cols)[0])))
        first = (r, c)
    return Survey(count, first, float(lowest))


def filled_window(source: DemSource, r0: int, r1: int, c0: int, c1: int, rule: NodataRule) -> FloatArray:
    """Rows ``r0 … r1`` and columns ``c0 … c1`` (ends included) with no-data cells replaced by ``rule``.

    The result for a cell does not depend on the window it is read in (module
    docstring): what lets two tiles and a seam agree on a filled border cell.
    ``rule.kind == "error"`` with a no-data cell raises :class:`ValueError`.
    O(window) — for ``fill``, O((window + 2·reach)²) read and searched.
    """
    out = source.read(r0, r1 + 1, c0, c1 + 1)
    missing = np.isnan(out)
    if not bool(missing.any()):
        return out
    if rule.kind in ("value", "min"):
        out[missing] = rule.value
        return out
    if rule.kind == "error":
        r, c = (int(v) for v in np.argwhere(missing)[0])
        raise ValueError(f"{source.name}: no-data cell at (row {r0 + r}, col {c0 + c}); say how to treat no-data cells")
    return _nearest_fill(source, r0, r1, c0, c1, out, missing, rule.reach)


def _nearest_fill(source: DemSource, r0: int, r1: int, c0: int, c1: int, out: FloatArray, missing: NDArray[np.bool_],
                  reach: int) -> FloatArray:
    """``fill``: each no-data cell of the window takes the nearest valid cell's height, ties to the smallest ``(row, col)``.

    The window grown by ``reach`` on every side holds every cell within ``reach``
    of a window cell, so a nearest distance ``d ≤ reach`` found in it is the
    grid's, and the cells at that distance are all in it: the choice depends on
    the cell alone.  ``d > reach`` is refused rather than guessed.
    """
    from scipy.ndimage import distance_transform_edt

    rows, cols = source.shape
    R0, R1 = max(0, r0 - reach), min(rows - 1, r1 + reach)
    C0, C1 = max(0, c0 - reach), min(cols - 1, c1 + reach)
    ext = source.read(R0, R1 + 1, C0, C1 + 1)
    void = np.isnan(ext)
    cells = np.argwhere(missing) + np.array([r0 - R0, c0 - C0])
    if bool(void.all()):
        d2 = np.full(len(cells), reach * reach + 1, dtype=np.int64)
    else:
        _, (ri, ci) = distance_transform_edt(void, return_indices=True)
        near_r = ri[cells[:, 0], cells[:, 1]].astype(np.int64)
        near_c = ci[cells[:, 0], cells[:, 1]].astype(np.int64)
        d2 = (near_r - cells[:, 0]) ** 2 + (near_c - cells[:, 1]) ** 2
    far = d2 > reach * reach
    if bool(far.any()):
        r, c = (int(v) for v in cells[int(np.argmax(far))])
        raise ValueError(
            f"{source.name}: no-data cell (row {R0 + r}, col {C0 + c}) has no valid cell within {reach} cells; "
            "--nodata fill on tiles looks that far only: use a larger --tile, --nodata min or a height"
        )
    values = np.empty(len(cells), dtype=np.float64)
    todo = np.ones(len(cells), dtype=bool)
    h, w = ext.shape
    for dist2 in np.unique(d2).tolist():
        group = np.flatnonzero(d2 == dist2)
        for dr, dc in _offsets(int(dist2)):
            pending = group[todo[group]]
            if not pending.size:
                break
            rr, cc = cells[pending, 0] + dr, cells[pending, 1] + dc
            ok = (rr >= 0) & (rr < h) & (cc >= 0) & (cc < w)
            hit = pending[ok]
            ok_rr, ok_cc = rr[ok], cc[ok]
            valid = ~void[ok_rr, ok_cc]
            values[hit[valid]] = ext[ok_rr[valid], ok_cc[valid]]
            todo[hit[valid]] = False
    assert not bool(todo.any()), "every no-data cell has a valid cell at its nearest distance"
    out[missing] = values
    return out


def _offsets(d2: int) -> list[tuple[int, int]]:
    """Every integer ``(dr, dc)`` with ``dr² + dc² = d2``, in increasing ``(dr, dc)`` order."""
    found: list[tuple[int, int]] = []
    top = math.isqrt(d2)
    for dr in range(-top, top + 1):
        rest = d2 - dr * dr
        dc = math.isqrt(rest)
        if dc * dc == rest:
            found.extend([(dr, -dc), (dr, dc)] if dc else [(dr, 0)])
    return found
