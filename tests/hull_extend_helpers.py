"""Reading hulls in the ``extend_hull`` tests: faces as sets, oriented triangles, grids, snapshots.

Shared by the ``tests/test_hull_extend_*.py`` modules (not collected: no ``test_``
prefix).  :func:`snapshot` recomputes everything observable about a hull from its
complexes (not its cached arrays), so that :func:`assert_unchanged` sees any write
into a node an older version reaches.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from persistri.impl.hull.api import Hull


def facets(simplices: np.ndarray) -> set[frozenset[int]]:
    return {frozenset(t) for t in simplices.tolist()}


def oriented(simplices: np.ndarray) -> set[tuple[int, ...]]:
    """Triangles as their rotation starting at the smallest index (orientation kept)."""
    out = set()
    for t in simplices.tolist():
        k = t.index(min(t))
        out.add(tuple(t[k:] + t[:k]))
    return out


def grid(k: int) -> np.ndarray:
    return np.array([[x, y, z] for x in range(k) for y in range(k) for z in range(k)], dtype=float)


def snapshot(hull: Hull) -> dict[str, Any]:
    """Everything observable about a hull, recomputed from its complexes (not its cached arrays)."""
    from persistri.impl.hull.api import _triangles

    assert hull.rows is not None and hull.bulldozed is not None
    out: dict[str, Any] = {
        "complex": oriented(_triangles(hull.structure, hull.complex, hull.rows)),
        "bulldozed": oriented(_triangles(hull.structure, hull.bulldozed, hull.rows)),
        "simplices": hull.simplices.copy(),
        "points": hull.points.copy(),
        "rows": hull.rows.copy(),
        "bulldozed_faces": None if hull.bulldozed_faces is None else hull.bulldozed_faces.copy(),
    }
    if hull.history is not None:
        # A sample of the versions (every one would cost versions × faces): about 40, the first and last included.
        H = hull.history
        sample = sorted({*range(0, len(H), max(1, len(H) // 40)), len(H) - 1})
        out["history"] = [(k, oriented(H.simplices(k)), H.pending(k).tolist()) for k in sample]
    return out


def assert_unchanged(hull: Hull, before: dict[str, Any]) -> None:
    """``snapshot(hull)`` is still ``before``, key by key."""
    after = snapshot(hull)
    for key, value in before.items():
        if isinstance(value, np.ndarray):
            assert np.array_equal(after[key], value), key
        else:
            assert after[key] == value, key
