"""GrowingPredicates2 (impl/geometry/growing.py): the same signs as Predicates2, over a point set that grows."""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from persistri.impl.geometry.growing import GrowingPredicates2, exact_parts
from persistri.impl.geometry.predicates import Predicates2

coords = st.one_of(
    st.integers(-4, 4).map(float),
    st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False),
    st.integers(-8, 8).map(lambda k: 4.0e6 + k * 2.0**-31),  # UTM northings, a few ulps apart
)


@settings(max_examples=60)
@given(st.lists(st.tuples(coords, coords), min_size=5, max_size=9), st.integers(1, 4))
def test_same_signs_as_predicates2_when_grown(rows: list[tuple[float, float]], k: int) -> None:
    pts = np.array(rows, dtype=np.float64)
    ref = Predicates2(pts)
    grown = GrowingPredicates2(pts[:k])
    for x, y in pts[k:].tolist():
        grown.append(x, y)
    n = len(rows)
    for a, b, c in itertools.permutations(range(n), 3):
        assert grown.orient2d_sign(a, b, c) == ref.orient2d_sign(a, b, c)
        assert grown.orient2d(a, b, c) == ref.orient2d(a, b, c)
    for a, b, c, d in itertools.islice(itertools.permutations(range(n), 4), 300):
        assert grown.incircle_sign(a, b, c, d) == ref.incircle_sign(a, b, c, d)
        assert grown.incircle(a, b, c, d) == ref.incircle(a, b, c, d)


@settings(max_examples=60)
@given(st.lists(st.tuples(coords, coords), min_size=3, max_size=3))
def test_dot_sign_is_exact(rows: list[tuple[float, float]]) -> None:
    P = GrowingPredicates2(np.array(rows[:1]))
    for x, y in rows[1:]:
        P.append(x, y)
    (ax, ay), (bx, by), (px, py) = ((Fraction(x), Fraction(y)) for x, y in rows)
    exact = (ax - px) * (bx - px) + (ay - py) * (by - py)  # (a - p)·(b - p) with a, b, p = rows 0, 1, 2
    assert P.dot_sign(0, 1, 2) == (exact > 0) - (exact < 0)


def test_points_too_fine_for_the_filter_are_decided_exactly() -> None:
    P = GrowingPredicates2([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    tiny = P.append(2.0**-1070, 2.0**-1070)  # subnormal: no filtered copy, every test exact
    assert P.orient2d_sign(0, 1, tiny) == 1 and P.incircle_sign(0, 1, 2, tiny) == 1
    on = P.append(0.5, 0.0)
    assert P.orient2d_sign(0, 1, on) == 0 and P.orient2d(0, 1, on) in (-1, 1)
    assert P.dot_sign(0, 1, on) == -1 and P.between(0, 1, on)


def test_append_refuses_non_finite_and_keeps_indices() -> None:
    P = GrowingPredicates2([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    with pytest.raises(ValueError, match="finite"):
        P.append(float("nan"), 0.0)
    assert len(P) == 3 and P.append(0.25, 0.25) == 3 and P.points.shape == (4, 2)


@pytest.mark.parametrize("x", [0.0, 1.0, -3.5, 0.1, 2.0**-1074, 1e308])
def test_exact_parts(x: float) -> None:
    m, e = exact_parts(x)
    assert Fraction(m) * Fraction(2) ** e == Fraction(x) if m else x == 0.0
    assert m == 0 or m % 2 == 1


def test_same_as_any_finds_the_first_equal_point() -> None:
    P = GrowingPredicates2([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    p = P.append(1.0, -0.0)  # equal to point 1 (the sign of zero is not a different point)
    q = P.append(0.5, 0.5)
    twin = P.append(0.5, 0.5)
    assert P.same_as_any(p, (0, 1, 2)) == 1 and P.same_as_any(p, (2, 0)) is None
    assert P.same_as_any(q, (0, twin, 1)) == twin and P.same_as_any(q, ()) is None
    assert all((P.same_as_any(i, (j,)) is not None) == P.same(i, j) for i in range(6) for j in range(6))


@given(st.lists(st.tuples(coords, coords), min_size=1, max_size=6))
def test_integers_are_the_points_at_their_least_exponent(rows: list[tuple[float, float]]) -> None:
    P = GrowingPredicates2([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    idx = [P.append(x, y) for x, y in rows]
    pairs, e = P.integers(*idx)
    assert len(pairs) == len(idx)
    for i, (ix, iy) in zip(idx, pairs):
        x, y = P.xy(i)
        assert Fraction(ix) * Fraction(2) ** e == Fraction(x) and Fraction(iy) * Fraction(2) ** e == Fraction(y)
