"""Validating and de-duplicating the input of a 3D hull: clear errors, never a wrong answer.

:func:`as_points` turns anything array-like into an ``(n, 3)`` float64 array or
raises a one-line error; :func:`merge_duplicates` merges exactly equal rows and
reports them.  Both run at the API boundary, before any geometry.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["as_points", "merge_duplicates", "Duplicates"]


def as_points(points: ArrayLike, *, dim: int = 3, what: str = "points") -> NDArray[np.float64]:
    """``points`` as a C-contiguous ``(n, dim)`` float64 array.

    Raises :class:`TypeError` for non-numeric input (strings, objects, complex
    numbers) and :class:`ValueError` for a wrong shape (naming the shape found)
    or a NaN/inf coordinate (naming the first offending row).  Booleans and
    integers are accepted as reals; integers beyond 2^53 that a double cannot
    hold exactly are rejected rather than silently rounded.
    """
    if isinstance(points, (str, bytes)):
        raise TypeError(f"{what} must be an array of real numbers, not {type(points).__name__}")
    try:
        raw = np.asarray(points)
    except (ValueError, TypeError) as exc:  # ragged nested sequences
        raise ValueError(f"{what} must be a rectangular (n, {dim}) array of reals: {exc}") from None
    if raw.dtype == object:
        raise ValueError(
            f"{what} must be a rectangular (n, {dim}) array of reals (ragged rows or non-numeric entries)"
        )
    if raw.dtype.kind not in "biuf":
        raise TypeError(f"{what} must be real numbers, not {raw.dtype} ({raw.dtype.kind!r} kind)")
    if raw.ndim != 2 or raw.shape[1] != dim:
        raise ValueError(f"{what} must be an (n, {dim}) array, got shape {raw.shape}")
    if raw.dtype.kind in "iu" and raw.size:
        big = np.abs(raw.astype(np.float64)) > 2.0**53
        if big.any():
            row = int(np.argmax(big.any(axis=1)))
            raise ValueError(f"{what}: row {row} has an integer too large to be exact as a double: {raw[row].tolist()}")
    arr = np.ascontiguousarray(raw, dtype=np.float64)
    finite = np.isfinite(arr)
    if not finite.all():
        row = int(np.argmax(~finite.all(axis=1)))
        raise ValueError(f"{what}: row {row} is not finite: {arr[row].tolist()}")
    # -0.0 and 0.0 are the same point: normalise so that byte-wise de-duplication agrees.
    out: NDArray[np.float64] = arr + 0.0
    return out


@dataclass(frozen=True)
class Duplicates:
    """The result of merging exactly equal input rows.

    ``representatives[j]`` is the input row index standing for distinct point j
    (the first occurrence); ``inverse[i]`` is the distinct point of input row i;
    ``merged`` lists ``(row, representative row)`` for every dropped row.
    """

    representatives: NDArray[np.intp]
    inverse: NDArray[np.intp]
    merged: tuple[tuple[int, int], ...]

    @property
    def count(self) -> int:
        """How many input rows were merged into an earlier equal row."""
        return len(self.merged)


def merge_duplicates(points: NDArray[np.float64]) -> Duplicates:
    """Merge exactly equal rows of a validated ``(n, d)`` array (O(n log n)).

    Exact equality of doubles is exact equality of the points they denote, so this
    never merges distinct points.

    >>> d = merge_duplicates(np.array([[0., 0, 0], [1, 0, 0], [0, 0, 0]]))
    >>> d.representatives.tolist(), d.merged
    ([0, 1], ((2, 0),))
    """
    n = points.shape[0]
    if n == 0:
        empty = np.zeros(0, dtype=np.intp)
        return Duplicates(empty, empty, ())
    _, first, inverse = np.unique(points, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    # Keep the input order of first occurrences.
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    reps = first[order].astype(np.intp)
    inv = rank[inverse].astype(np.intp)
    dup_rows = np.nonzero(reps[inv] != np.arange(n))[0]
    merged = tuple((int(i), int(reps[inv[i]])) for i in dup_rows)
    return Duplicates(reps, inv, merged)
