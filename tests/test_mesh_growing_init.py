"""GrowingPredicates2's set-up (impl/geometry/growing.py): the scale and the stored points from one pass of exact parts.

The constructor reads each coordinate's exact parts once and takes the filter's scale from their extremes instead of
from the vectorised ``binary_exponents``; these tests compare it with that vectorised definition, and the stored
points with a set grown one ``append`` at a time, on zeros, subnormals, huge and UTM-like coordinates.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from persistri.impl.geometry.exact import ZERO_LOW, binary_exponents
from persistri.impl.geometry.filter import choose_scaling
from persistri.impl.geometry.growing import GrowingPredicates2

coords = st.one_of(
    st.just(0.0),
    st.integers(-4, 4).map(float),
    st.floats(-1e300, 1e300, allow_nan=False, allow_infinity=False),
    st.floats(-1e-300, 1e-300, allow_nan=False, allow_infinity=False),  # subnormals among them
    st.integers(-8, 8).map(lambda k: 4.0e6 + k * 2.0**-31),
)


def reference_shift(pts: np.ndarray) -> int:
    low, high = binary_exponents(pts)
    nonzero = low < ZERO_LOW
    return choose_scaling(low[nonzero], high[nonzero]).shift


@settings(max_examples=200)
@given(st.lists(st.tuples(coords, coords), min_size=1, max_size=8))
def test_scale_and_points_as_the_vectorised_definition(rows: list[tuple[float, float]]) -> None:
    pts = np.array(rows, dtype=np.float64)
    P = GrowingPredicates2(pts)
    assert P.shift == reference_shift(pts + 0.0)
    # The stored points as if appended one by one onto a set of the same scale.
    grown = GrowingPredicates2(pts[:1])
    grown._shift = P.shift
    grown._xy, grown._rows, grown._exact = [], [], []
    for x, y in pts.tolist():
        grown.append(x, y)
    assert P._exact == grown._exact and P._xy == grown._xy
    assert [tuple(map(math.isnan, r)) for r in P._rows] == [tuple(map(math.isnan, r)) for r in grown._rows]
    assert [r for r in P._rows if not math.isnan(r[0])] == [r for r in grown._rows if not math.isnan(r[0])]


def test_all_zero_points_have_scale_zero() -> None:
    P = GrowingPredicates2(np.zeros((3, 2)))
    assert P.shift == reference_shift(np.zeros((3, 2))) == 0 and P.filter_rows == [(0.0, 0.0)] * 3


def test_negative_zero_is_stored_as_zero() -> None:
    P = GrowingPredicates2(np.array([[-0.0, 1.0], [1.0, -0.0], [2.0, 3.0]]))
    assert [math.copysign(1.0, v) for x, y in P._xy for v in (x, y)] == [1.0] * 6
