"""A Python list numpy would round (integers beyond 2^53 mixed with floats) is refused, never rounded.

numpy reads [[2**53 + 1, 5, 2**53], ..., [0.5, 0, 0.5]] as float64, so 2**53 + 1 becomes 2**53: here
that moves a point onto the plane of the others, and a tetrahedron was reported as coplanar input.
"""

from __future__ import annotations

import numpy as np
import pytest

import persistri

B = 2**53


def test_a_tetrahedron_is_not_made_coplanar_by_rounding() -> None:
    pts = [[0, 0, 0], [0, 1, 0], [B, 0, B], [B + 1, 5, B], [0.5, 0, 0.5]]
    with pytest.raises(ValueError, match=r"points: row 3 is not exactly representable as float64: \[9007199254740993, 5, 9007199254740992\]"):
        persistri.ConvexHull(pts)


def test_ints_of_both_signs_beyond_2_63_are_not_rounded() -> None:
    c = 2**62
    pts = [[0, 0, 0], [0, 1, 0], [c, 0, c], [c + 1, 5, c], [2**63, 0, 2**63], [-1, 0, 0]]
    with pytest.raises(ValueError, match="row 3 is not exactly representable as float64"):
        persistri.ConvexHull(pts)


def test_delaunay_and_mesh_vertices_too() -> None:
    with pytest.raises(ValueError, match="row 2 is not exactly representable as float64"):
        persistri.Delaunay([[0, 0], [B, B], [B + 1, B], [0.5, 0.5]])
    with pytest.raises(ValueError, match="vertices: row 1 is not exactly representable as float64"):
        persistri.triangulate({"vertices": [[0, 0], [B + 1, 0], [B + 1, 1.5], [0, 1]], "segments": [[0, 1], [1, 2], [2, 3], [3, 0]]})


def test_a_mixed_list_a_double_holds_is_taken_as_given() -> None:
    pts = [[0, 0, 0], [0, 1, 0], [B, 0, B], [B, 5, B + 2], [0.5, 0, 0.5]]
    assert persistri.ConvexHull(pts).volume == persistri.ConvexHull(np.array(pts, dtype=np.float64)).volume
    with pytest.raises(ValueError, match="row 3 is not finite"):
        persistri.ConvexHull([[0, 0, 0], [0, 1, 0], [1, 0, 0], [0, 0, float("nan")]])


def test_decimals_a_double_holds_are_taken_and_others_refused() -> None:
    from decimal import Decimal

    tetra = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
    halves = [[Decimal("0.5") * c for c in row] for row in tetra]
    assert persistri.ConvexHull(halves).volume == persistri.ConvexHull(np.array(tetra) * 0.5).volume
    with pytest.raises(ValueError, match=r"row 1 is not exactly representable as float64"):
        persistri.ConvexHull([[0, 0, 0], [Decimal("0.1"), 0, 0], [0, 1, 0], [0, 0, 1]])


def test_numpy_integer_scalars_in_a_list_are_compared_exactly() -> None:
    pts = [[0, 0, 0], [0, 1, 0], [B, 0, B], [np.int64(B + 1), 5, B], [0.5, 0, 0.5]]
    with pytest.raises(ValueError, match=r"row 3 is not exactly representable as float64"):
        persistri.ConvexHull(pts)
