"""Heights read exactly: the checks that no height was rounded on its way to float64.

persistri never rounds its input.  A height grid is float64; these functions refuse, naming the first
cell, a height that a double cannot hold exactly: an integer beyond 2^53 that is not a double (int64 or
uint64 bands, ``9007199254740993``, ``2**63 - 1``), a Python integer, Fraction or Decimal that is not a
double (``Fraction(1, 3)``), and a cell of nested lists that numpy rounded reading them as float64 (a
list mixing integers with floats).  Used by :func:`~persistri.impl.terrain.grids.as_heights` (arrays
given to the API) and by the grid readers (:func:`~persistri.impl.terrain.grids.read_grid`,
:mod:`persistri.impl.terrain.geotiff`).  Each check is O(rows · cols), vectorised except for the
cells it has to look at one by one (an object array; cells of 2^53 or more).
"""

from __future__ import annotations

import decimal
import math
import numbers
from typing import Any

import numpy as np
from numpy.typing import NDArray

from persistri.impl.geometry.points import rounded_by_numpy

__all__ = ["exact_objects", "refuse_rounded", "ragged_row", "float_heights", "rounded_integers"]


def exact_objects(raw: NDArray[Any], what: str) -> NDArray[np.float64]:
    """A 2D object array of Python numbers (integers beyond 2^64, Fractions, Decimals) as the float64 heights they
    are exactly; :class:`ValueError` naming the first cell a double cannot hold, or for anything else (ragged rows,
    entries that are not real numbers).  O(rows · cols)."""
    if raw.ndim != 2:
        raise ValueError(f"{what}: not a rectangular 2D array of real numbers (ragged rows or non-numeric entries)")
    out = np.empty(raw.shape, dtype=np.float64)
    for r, row in enumerate(raw.tolist()):
        for c, x in enumerate(row):
            if not isinstance(x, (numbers.Real, decimal.Decimal)):
                hint = " (a no-data cell is NaN)" if x is None else ""
                raise ValueError(f"{what}: cell (row {r}, col {c}) holds {type(x).__name__} {x!r:.40}, not a real number{hint}")
            try:
                f = float(x)
            except (OverflowError, ValueError):  # beyond the doubles; a signalling NaN
                f = math.inf
            if f == f and f != x:
                raise ValueError(f"{what}: cell (row {r}, col {c}) is {x!r:.60}, not exactly representable as float64")
            out[r, c] = f
    return out


def refuse_rounded(heights: object, raw: NDArray[Any], what: str) -> None:
    """:class:`ValueError` naming the first cell of the nested lists ``heights`` that numpy rounded reading them as
    the floats ``raw`` (:func:`~persistri.impl.geometry.points.rounded_by_numpy`: a list mixing integers with
    floats is float64 to numpy, and 2^53 + 1 becomes 2^53).  O(rows · cols), vectorised but for cells of 2^53 or
    more."""
    found = rounded_by_numpy(heights, raw)
    if found is not None:
        objs, inexact = found
        r, c = np.argwhere(inexact)[0]
        raise ValueError(
            f"{what}: cell (row {r}, col {c}) is {objs[r, c]!r:.60}, not exactly representable as float64 (numpy reads "
            f"this list as float64, which rounds it; persistri never rounds its input)"
        )


def ragged_row(heights: object) -> str:
    """``": row 1 has 1 entry, not 2"`` for the first row of a list of rows whose length differs from row 0's; else "".

    Only on the error path of :func:`~persistri.impl.terrain.grids.as_heights`; O(rows).
    """
    try:
        lengths = [len(row) for row in heights]  # type: ignore[attr-defined]
    except TypeError:
        return ""
    for k, n in enumerate(lengths):
        if n != lengths[0]:
            return f": row {k} has {n} {'entry' if n == 1 else 'entries'}, not {lengths[0]}"
    return ""


def rounded_integers(a: NDArray[Any], out: NDArray[np.float64]) -> NDArray[np.bool_]:
    """The cells of the 64-bit integer array ``a`` that its float64 copy ``out`` rounded.  Each is cast back and
    compared in ``a``'s type; a double at or beyond 2^63 (2^64 unsigned) has no integer there to cast to (numpy
    would warn "invalid value") and is inexact: int64 max rounds up to 2^63.  O(size), vectorised."""
    with np.errstate(invalid="ignore"):
        inexact: NDArray[np.bool_] = (out >= 2.0 ** (8 * a.itemsize - (a.dtype.kind == "i"))) | (out.astype(a.dtype) != a)
    return inexact


def float_heights(a: NDArray[Any], source: str, nodata: NDArray[np.bool_] | None = None) -> NDArray[np.float64]:
    """The heights of the band ``a`` as float64, read from ``source``; a :class:`ValueError` naming the first cell
    (not among the ``nodata`` cells, which the caller makes NaN) holding an integer a double would round
    (int64 or uint64 beyond 2^53: ``9007199254740993``, ``2**63 - 1``).  O(size), vectorised.
    """
    if a.dtype.kind not in "biuf":
        raise ValueError(f"{source}: the heights are not numbers (dtype {a.dtype})")
    out: NDArray[np.float64] = np.asarray(a, dtype=np.float64)
    if a.dtype.kind in "iu" and a.itemsize >= 8:
        inexact = rounded_integers(a, out)
        if nodata is not None:
            inexact &= ~nodata
        if inexact.any():
            r, c = (int(v) for v in np.argwhere(inexact)[0]) if a.ndim == 2 else (0, int(np.argmax(inexact)))
            raise ValueError(
                f"{source}: an integer height is not exactly representable as float64: cell (row {r}, col {c}) is "
                f"{int(a[r, c] if a.ndim == 2 else a.flat[c])} (beyond 2^53, a double would round it; persistri "
                "never rounds its input)"
            )
    return out
