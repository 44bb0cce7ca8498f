"""Point arrays at the API boundary: validation and exact duplicate detection.

:func:`as_points` turns array-like input into a C-contiguous ``(n, dim)``
float64 array whose every entry is the exact value given, or raises a one-line
error naming what is wrong (the first offending row for NaN/inf).
:func:`unique_rows` finds exactly equal rows: two doubles are equal exactly when
the rationals they denote are, so this never merges distinct points.
"""

from __future__ import annotations

import decimal
import numbers
import os
import reprlib
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["as_points", "UniqueRows", "unique_rows", "appended_rows"]


def as_points(points: ArrayLike, dim: int, *, what: str = "points") -> NDArray[np.float64]:
    """``points`` as a C-contiguous ``(n, dim)`` float64 array, converted exactly.

    Raises :class:`TypeError` for non-numeric input (strings, complex numbers,
    objects that are not real numbers; the first is named) and
    :class:`ValueError` for a ragged or wrongly shaped array (the first short
    row, or the shape found, is named), for a NaN or infinite coordinate (the
    first such row is named), or for a number that float64 cannot hold exactly
    (integers beyond 2^53 that are not doubles, long doubles with more
    precision, Fractions like 1/3, integers of a list that numpy would read as
    float64 because floats or negative numbers beyond 2^63 are mixed in):
    persistri never rounds its input.  Python
    numbers a float64 holds exactly (big ints such as 2^70, Fractions,
    Decimals) are taken as those doubles.  Booleans and integers are accepted as reals.  ``-0.0`` becomes
    ``0.0`` (the same number).  O(n).
    """
    if isinstance(points, (str, bytes, os.PathLike)):
        is_path = isinstance(points, os.PathLike)
        hint = " (a file name: read the file first, e.g. with numpy.load or numpy.loadtxt)" if is_path else ""
        raise TypeError(f"{what} must be an array of real numbers, not {type(points).__name__}{hint}")
    try:
        raw = np.asarray(points)
    except (ValueError, TypeError) as exc:  # ragged nested sequences
        raise ValueError(f"{what} must be a rectangular (n, {dim}) array of reals: {_ragged(points, dim) or exc}") from None
    if raw.dtype == object:
        raw = _from_objects(raw, dim, what)
    elif raw.dtype.kind == "f" and raw.ndim == 2 and not isinstance(points, np.ndarray):
        _refuse_rounded_numbers(points, raw, what)
    if raw.dtype.kind not in "biuf":
        raise TypeError(f"{what} must be real numbers, not {raw.dtype}")
    if raw.ndim != 2 or raw.shape[1] != dim:
        raise ValueError(f"{what} must be an (n, {dim}) array, got shape {raw.shape}")
    arr = np.ascontiguousarray(raw, dtype=np.float64)
    if raw.dtype != np.float64 and raw.size:
        with np.errstate(all="ignore"):  # out-of-range casts are caught by the comparison
            inexact = (arr.astype(raw.dtype) != raw) & (raw == raw)  # NaN is reported below
        if inexact.any():
            row = int(np.argmax(inexact.any(axis=1)))
            raise ValueError(f"{what}: row {row} is not exactly representable as float64: {raw[row].tolist()}")
    finite = np.isfinite(arr)
    if not finite.all():
        row = int(np.argmax(~finite.all(axis=1)))
        raise ValueError(f"{what}: row {row} is not finite: {arr[row].tolist()}")
    out: NDArray[np.float64] = arr + 0.0  # -0.0 + 0.0 == +0.0
    return out


def rounded_by_numpy(values: object, raw: NDArray[Any]) -> tuple[NDArray[Any], NDArray[np.bool_]] | None:
    """Where numpy rounded the nested sequence ``values`` reading it as the floats ``raw``: the entries as Python
    objects and the mask of those that differ from the number they came from, or None if none does.

    numpy reads a list mixing integers with floats, or integers of both signs beyond 2^63, as float64, and
    rounds the integers a double cannot hold (2^53 + 1 becomes 2^53).  Only entries of magnitude 2^53 or more
    can be rounded, so only those are compared, each with its Python number (Python compares an int with a
    float exactly; numpy's integer scalars are compared as Python ints).  O(n), vectorised but for such entries.
    """
    with np.errstate(invalid="ignore"):
        big = np.abs(raw) >= 2.0**53  # an integer below 2^53 converts exactly: only these cells can be rounded
    if not big.any():
        return None
    objs = np.asarray(values, dtype=object)
    if objs.shape != raw.shape:
        return None
    inexact = np.zeros(raw.shape, dtype=bool)
    exact = np.array([int(x) if isinstance(x, np.integer) else x for x in objs[big].tolist()], dtype=object)
    inexact[big] = np.not_equal(exact, raw[big]).astype(bool)
    return (objs, inexact) if inexact.any() else None


def _refuse_rounded_numbers(points: object, raw: NDArray[Any], what: str) -> None:
    """Raise :class:`ValueError` naming the first row of the nested sequence ``points`` whose numbers numpy rounded
    reading them as ``raw`` (:func:`rounded_by_numpy`: four points off a plane may land on it).  O(n)."""
    found = rounded_by_numpy(points, raw)
    if found is not None:
        objs, inexact = found
        row = int(np.argmax(inexact.any(axis=1)))
        raise ValueError(
            f"{what}: row {row} is not exactly representable as float64: {reprlib.repr(objs[row].tolist())} "
            f"(numpy reads this list as float64, which rounds such integers; persistri never "
            f"rounds its input: give integers beyond 2^53 as exact doubles or as an integer array)"
        )


def _ragged(points: object, dim: int) -> str | None:
    """The first row of a nested sequence whose length is not ``dim``, described; None if none is found."""
    try:
        rows = list(points)  # type: ignore[call-overload]
    except TypeError:
        return None
    for i, row in enumerate(rows):
        try:
            n = len(row)
        except TypeError:
            return f"row {i} is {type(row).__name__}, not a row of {dim} numbers"
        if n != dim:
            return f"row {i} has {n} entries, not {dim}"
    return None


def _from_objects(raw: NDArray[Any], dim: int, what: str) -> NDArray[Any]:
    """An object array of Python numbers (big ints, Fractions, Decimals) as float64, if every entry is exact.

    Raises :class:`TypeError` naming the first entry that is not a real number, and
    :class:`ValueError` naming the first row a float64 cannot hold exactly.  O(n).
    """
    if raw.ndim != 2 or raw.shape[1] != dim:
        raise ValueError(f"{what} must be an (n, {dim}) array, got shape {raw.shape}")
    out = np.empty(raw.shape, dtype=np.float64)
    for i, row in enumerate(raw.tolist()):
        for j, x in enumerate(row):
            if not isinstance(x, (numbers.Real, decimal.Decimal)):  # Decimal is not registered as a Real
                raise TypeError(f"{what}: row {i} holds {type(x).__name__} {x!r:.40}, not a real number")
            try:
                f = float(x)
            except (OverflowError, ValueError):  # beyond the doubles; a signalling NaN Decimal
                f = np.inf
            if f == f and f != x:
                raise ValueError(f"{what}: row {i} is not exactly representable as float64: {reprlib.repr(row)}")
            out[i, j] = f
    return out


class UniqueRows(NamedTuple):
    """The distinct rows of a point array.

    ``first[j]`` is the row index of the first occurrence of distinct point
    ``j`` (increasing); ``inverse[i]`` is the distinct point of row ``i``, so
    ``points[first][inverse] == points`` row for row.
    """

    first: NDArray[np.intp]
    inverse: NDArray[np.intp]


def unique_rows(points: NDArray[np.float64]) -> UniqueRows:
    """The exactly distinct rows of a validated ``(n, d)`` array (:func:`as_points`). O(n log n).

    >>> u = unique_rows(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 0.0]]))
    >>> u.first.tolist(), u.inverse.tolist()
    ([0, 1], [0, 1, 0])
    """
    n = points.shape[0]
    if n == 0:
        empty = np.zeros(0, dtype=np.intp)
        return UniqueRows(empty, empty.copy())
    if points.shape[1]:
        first_column = np.sort(points[:, 0])
        if not bool(np.any(first_column[1:] == first_column[:-1])):
            # Distinct first coordinates (typical of real-valued data): every row is distinct.
            every = np.arange(n, dtype=np.intp)
            return UniqueRows(every, every.copy())
    # Sort the rows lexicographically (stable: equal rows keep their input order, so each
    # run of equal rows starts at its first occurrence); a run starts where a row differs
    # from the previous one.  Float comparison: -0.0 and 0.0 are one number.
    order = np.lexsort(points.T[::-1])
    ranked = np.take(points, order, axis=0)  # whole rows at once (fancy indexing goes element by element)
    starts = np.ones(n, dtype=bool)
    starts[1:] = np.any(ranked[1:] != ranked[:-1], axis=1)
    run = np.cumsum(starts) - 1  # the run of each sorted row
    heads = order[starts]  # the first occurrence of each distinct row, in sorted-row order
    by_row = np.argsort(heads, kind="stable")
    rank = np.empty_like(by_row)
    rank[by_row] = np.arange(by_row.size)
    inverse = np.empty(n, dtype=np.intp)
    inverse[order] = rank[run]
    return UniqueRows(heads[by_row].astype(np.intp), inverse)


def appended_rows(points: NDArray[np.float64], n_old: int) -> tuple[tuple[tuple[int, int], ...], NDArray[np.intp]]:
    """The rows ``n_old …`` appended to ``points``: which repeat an earlier row, and which are new. O(n log n).

    Returns ``(merged, fresh)``: ``merged`` the pairs ``(row, first equal row)`` for
    each appended row equal to an earlier one (old or appended), ``fresh`` the
    appended rows that are the first of their value, in input order — what
    continuing a run on ``points[:n_old]`` needs, with the same representatives a
    run on all of ``points`` would take (the first of equal rows).

    >>> merged, fresh = appended_rows(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.0, 0.0]]), 2)
    >>> merged, fresh.tolist()
    (((2, 1), (4, 3)), [3])
    """
    uniq = unique_rows(points)
    rep = uniq.first[uniq.inverse[n_old:]]
    mine = np.arange(n_old, points.shape[0], dtype=np.intp)
    repeat = rep != mine
    merged = tuple(zip(mine[repeat].tolist(), rep[repeat].tolist()))
    fresh: NDArray[np.intp] = mine[~repeat]
    return merged, fresh
