"""The fan's sector test: exact float signs on small integers, one + → − change per sample."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.terrain.sectors import EXACT_LIMIT, sector_of, sector_sides, small_integer_points


@given(st.lists(st.tuples(st.integers(-(2**25), 2**25), st.integers(-(2**25), 2**25)), min_size=6, max_size=6, unique=True))
def test_float_path_equals_the_exact_predicate(pts: list[tuple[int, int]]) -> None:
    xy = np.array(pts, dtype=np.float64)
    pred = Predicates2(xy)
    assert small_integer_points(xy)
    ring = np.array([1, 2, 3], dtype=np.intp)
    samples = np.array([4, 5], dtype=np.intp)
    fast = sector_sides(pred, 0, ring, samples, exact_floats=True)
    slow = sector_sides(pred, 0, ring, samples, exact_floats=False)
    assert np.array_equal(fast, slow)
    for j, q in enumerate(samples.tolist()):
        for i, r in enumerate(ring.tolist()):
            assert fast[j, i] == (pred.orient2d_sign(0, r, q) >= 0)


def test_extreme_collinear_values_are_exact() -> None:
    # Products near 2^52: a float evaluation that rounded would miss the exact zero.
    big = EXACT_LIMIT
    xy = np.array([[-big, -big], [big, big], [big - 1, big - 1], [big, big - 1]], dtype=np.float64)
    pred = Predicates2(xy)
    sides = sector_sides(pred, 0, np.array([1], dtype=np.intp), np.array([2, 3], dtype=np.intp), exact_floats=True)
    assert sides[:, 0].tolist() == [True, False]
    assert pred.orient2d_sign(0, 1, 2) == 0 and pred.orient2d_sign(0, 1, 3) < 0


def test_small_integer_points() -> None:
    assert small_integer_points(np.array([[0.0, 3.0], [-(2.0**25), 2.0**25]]))
    assert not small_integer_points(np.array([[0.5, 3.0]]))
    assert not small_integer_points(np.array([[2.0**25 + 1, 0.0]]))


def test_sector_of_closed_ring_and_open_chain() -> None:
    # Ring of 4 rays around p: a sample between rays 2 and 3 has sides + + + − … read cyclically.
    sides = np.array([[False, True, True, False], [True, True, False, False], [True, False, False, True]])
    assert sector_of(sides, True).tolist() == [2, 1, 0]
    # Zeros read as +: a sample on ray 1 may go to sector 0 or 1 — here the change is at 1.
    assert sector_of(np.array([[True, True, False, False]]), True).tolist() == [1]
    # Open chain with two inner vertices: ends fixed at + and −.
    chain = np.array([[True, True], [True, False], [False, False]])
    assert sector_of(chain, False).tolist() == [2, 1, 0]
    with pytest.raises(ValueError, match="changes side"):
        sector_of(np.array([[True, False, True, False]]), True, check=True)
