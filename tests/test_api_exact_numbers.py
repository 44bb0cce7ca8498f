"""Numbers at the edges of float64 through the public entry points: exact on the values given, or refused.

numpy reads a Python list mixing integers with floats as float64 and rounds the integers a double cannot
hold (2^53 + 1 becomes 2^53): such input is refused naming the cell, never rounded.  Python numbers a
double holds exactly (2^70, Fraction(1, 2), Decimal("0.5")) are taken as those doubles.
"""

from __future__ import annotations

from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest

import persistri

B = 2**53


@pytest.mark.parametrize(
    ("heights", "cell"),
    [
        ([[B + 1, 0.5, 0.0], [0, 0, 0], [0, 0, 0]], "cell (row 0, col 0) is 9007199254740993"),
        ([[0.0, 1.5], [0, -(B + 3)]], "cell (row 1, col 1) is -9007199254740995"),
        ([[Fraction(1, 3), 0], [0, 0]], "cell (row 0, col 0) is Fraction(1, 3)"),
    ],
)
def test_a_height_a_double_cannot_hold_is_refused_naming_its_cell(heights: list[list[object]], cell: str) -> None:
    with pytest.raises(ValueError, match="heights: " + cell.replace("(", r"\(").replace(")", r"\)") + ", not exactly representable as float64"):
        persistri.greedy_insertion(heights, max_error=0.0)


def test_exact_python_numbers_are_taken_as_their_doubles() -> None:
    exact = [[2**70, Fraction(1, 2)], [Decimal("0.25"), 0]]
    tin = persistri.greedy_insertion(exact, max_error=0.0)
    same = persistri.greedy_insertion(np.array([[2.0**70, 0.5], [0.25, 0.0]]), max_error=0.0)
    assert tin.n_points == same.n_points == 4 and tin.max_error == same.max_error == 0.0
    with pytest.raises(ValueError, match=r"cell \(row 0, col 1\) holds NoneType None, not a real number \(a no-data cell is NaN\)"):
        persistri.greedy_insertion([[0, None], [0, 0]], max_error=0.0)


def test_a_mixed_list_that_fits_is_unchanged() -> None:
    mixed = [[B, 0.5, 0], [1, 2, 3], [4, 5, 6.25]]
    a = persistri.greedy_insertion(mixed, max_error=0.0)
    b = persistri.greedy_insertion(np.array(mixed, dtype=np.float64), max_error=0.0)
    assert a.n_points == b.n_points and a.max_error == b.max_error


def test_a_long_double_height_with_more_precision_is_refused() -> None:
    heights = np.zeros((3, 3), dtype=np.longdouble)
    heights[1, 1] = np.longdouble(1) + np.longdouble(2) ** -60
    if heights[1, 1] == 1:  # a platform whose long double is a double: nothing to refuse
        pytest.skip("long double is float64 here")
    with pytest.raises(ValueError, match=r"heights: a float\d+ height is not exactly representable as float64: cell \(row 1, col 1\)"):
        persistri.greedy_insertion(heights, max_error=0.0)
    exact = np.zeros((3, 3), dtype=np.longdouble)
    exact[1, 1] = 0.5
    assert persistri.greedy_insertion(exact, max_error=0.0).n_points == 5
    with pytest.raises(ValueError, match=r"an integer height is not exactly representable as float64: cell \(row 0, col 1\)"):
        persistri.greedy_insertion(np.array([[0, B + 1], [0, 0]], dtype=np.int64), max_error=0.0)


def test_numpy_integer_scalars_in_a_list_are_compared_exactly() -> None:
    with pytest.raises(ValueError, match=r"cell \(row 0, col 0\) is np.int64\(9007199254740993\), not exactly representable"):
        persistri.greedy_insertion([[np.int64(B + 1), 0.5], [0, 0]], max_error=0.0)
