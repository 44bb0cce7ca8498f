"""Arrays handed to users as values: read-only, in scipy.spatial's dtypes."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["read_only", "refuse_other_dimension", "coplanar_report"]


def read_only(a: NDArray[Any], dtype: type[np.generic] | None = None) -> NDArray[Any]:
    """``a`` (copied into ``dtype`` when it differs) as an array nobody can write to through it.

    The results of persistri are values: a hull's arrays are shared by every view
    of it and by the hulls derived from it, so writing to one would change them all. O(1), or O(size) to convert.
    """
    out = np.array(a, dtype=dtype) if dtype is not None and a.dtype != dtype else a.view()
    out.flags.writeable = False
    return out


_OTHER_DIMENSION = {
    ("ConvexHull", 2): "persistri.ConvexHull is the paper's 3D hull; for 2D points, "
    "persistri.Delaunay(points).convex_hull is their hull's edges (exact)",
    ("Delaunay", 3): "persistri.Delaunay triangulates the plane (2D points); for 3D points, "
    "persistri.ConvexHull(points) is their hull (there is no 3D tetrahedralization)",
}


def refuse_other_dimension(points: object, cls: str) -> None:
    """A :class:`ValueError` saying what to use instead when ``points`` is an ``(n, d)`` array of the *other*
    dimension than ``cls`` takes (scipy's ``ConvexHull`` and ``Delaunay`` take any); otherwise nothing (the
    usual validation reports every other shape).  O(1) for arrays; lists are looked at, not converted."""
    shape = getattr(points, "shape", None)
    if shape is None and isinstance(points, (list, tuple)) and points:
        first = points[0]
        shape = (len(points), len(first)) if isinstance(first, (list, tuple)) else None
    if shape is not None and len(shape) == 2:
        hint = _OTHER_DIMENSION.get((cls, int(shape[1])))
        if hint is not None:
            raise ValueError(f"points must be an (n, {5 - int(shape[1])}) array, got shape {tuple(shape)}: {hint}")


def coplanar_report(duplicates: Sequence[tuple[int, int]], simplices: NDArray[Any], n: int) -> NDArray[np.intc]:
    """scipy's ``coplanar`` of a hull, ``(k, 3)`` read-only: ``[row, a triangle at its twin, the twin]`` for each
    merged duplicate ``(row, twin)`` of a vertex (``simplices`` holds rows of ``n`` points).  O(n + m + k)."""
    dup = np.array(duplicates, dtype=np.intp).reshape(-1, 2)
    at = np.full(n, -1, dtype=np.intp)
    at[simplices.ravel()] = np.repeat(np.arange(simplices.shape[0], dtype=np.intp), 3)
    dup = dup[at[dup[:, 1]] >= 0]
    return read_only(np.stack([dup[:, 0], at[dup[:, 1]], dup[:, 1]], axis=1).astype(np.intc))
