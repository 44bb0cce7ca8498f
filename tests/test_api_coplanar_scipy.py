"""``coplanar`` of ``ConvexHull`` and ``Delaunay`` against scipy's on the same inputs and options.

scipy lists the points Qhull left out only under ``Qc``: among its ``Delaunay`` defaults, not its
``ConvexHull`` ones.  persistri leaves out only exactly equal rows, so where scipy lists them (the
duplicates of vertices) persistri lists the same rows and twins, and where scipy lists none, none.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import spatial

import persistri

CUBE = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
HULL_ROWS = np.vstack([CUBE, [[0.5, 0.5, 0.5]], CUBE[[3, 6]], [[0.5, 0.5, 0.5]]])  # 9, 10 repeat vertices 3, 6; 11 the centre
PLANE_ROWS = np.array([[0, 0], [1, 0], [0, 1], [1, 1], [1, 0], [0.5, 0.5], [0.5, 0.5], [0, 1], [0.25, 0.5]], dtype=float)


def _rows_and_twins(cop: np.ndarray) -> list[tuple[int, int]]:
    return sorted((int(r), int(t)) for r, _, t in cop.tolist())


def _facets_hold_twins(cop: np.ndarray, simplices: np.ndarray) -> bool:
    return all(t in simplices[f].tolist() for _, f, t in cop.tolist())


@pytest.mark.parametrize("options", [None, "Qt", "Qc", "Qc Qx", "Qx", "QJ"])
def test_hull_coplanar_is_scipys(options: str | None) -> None:
    ours = persistri.ConvexHull(HULL_ROWS, qhull_options=options)
    theirs = spatial.ConvexHull(HULL_ROWS, qhull_options=options)
    assert ours.coplanar.dtype == np.intc and ours.coplanar.shape[1] == 3
    assert _rows_and_twins(ours.coplanar) == _rows_and_twins(theirs.coplanar)
    assert _facets_hold_twins(ours.coplanar, ours.simplices)
    assert ours.duplicates.tolist() == [[9, 3], [10, 6], [11, 8]]  # reported whatever the options


def test_hull_coplanar_is_empty_by_default_and_kept_by_add_points() -> None:
    plain = persistri.ConvexHull(HULL_ROWS)
    assert plain.coplanar.shape == (0, 3) and not plain.coplanar.flags.writeable
    qc = persistri.ConvexHull(HULL_ROWS, qhull_options="Qc")
    assert _rows_and_twins(qc.coplanar) == [(9, 3), (10, 6)]
    more = qc.add_points(CUBE[[0]])  # row 12 repeats vertex 0
    assert _rows_and_twins(more.coplanar) == [(9, 3), (10, 6), (12, 0)]
    assert plain.add_points(CUBE[[0]]).coplanar.shape == (0, 3)
    assert persistri.ConvexHull.from_hull(qc.result).coplanar.shape == (0, 3)  # scipy's default options
    chunked = persistri.ConvexHull(HULL_ROWS, qhull_options="Qc", workers=1, chunk_rows=4)
    assert _rows_and_twins(chunked.coplanar) == [(9, 3), (10, 6)]
    assert persistri.ConvexHull(HULL_ROWS, workers=1, chunk_rows=4).coplanar.shape == (0, 3)
    live = persistri.ConvexHull(HULL_ROWS, incremental=True, qhull_options="Qc")
    assert _rows_and_twins(live.add_points(CUBE[[0]]).coplanar) == [(9, 3), (10, 6), (12, 0)]


@pytest.mark.parametrize("options", [None, "Qbb Qc Qz Q12", "Qc", "Qt", "Qbb Qz"])
def test_delaunay_coplanar_is_scipys(options: str | None) -> None:
    ours = persistri.Delaunay(PLANE_ROWS, qhull_options=options)
    theirs = spatial.Delaunay(PLANE_ROWS, qhull_options=options)
    assert _rows_and_twins(ours.coplanar) == _rows_and_twins(theirs.coplanar)
    assert _facets_hold_twins(ours.coplanar, ours.simplices)
    more = ours.add_points([[1.0, 1.0]])  # row 9 repeats vertex 3
    want = _rows_and_twins(theirs.coplanar) + ([(9, 3)] if theirs.coplanar.size else [])
    assert _rows_and_twins(more.coplanar) == sorted(want)
