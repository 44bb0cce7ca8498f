"""A ragged list of rows given as heights: the error names the first row whose length differs, in one line."""

from __future__ import annotations

import pytest

import persistri
from persistri.impl.terrain.grids import as_heights


@pytest.mark.parametrize(
    ("heights", "said"),
    [([[1, 2], [3]], "row 1 has 1 entry, not 2"), ([[1, 2, 3], [4, 5, 6], [7, 8]], "row 2 has 2 entries, not 3")],
)
def test_the_first_short_row_is_named(heights: list[list[int]], said: str) -> None:
    with pytest.raises(ValueError) as caught:
        as_heights(heights)
    assert str(caught.value) == f"heights: not a rectangular 2D array: {said}"
    with pytest.raises(ValueError, match=f"not a rectangular 2D array: {said}$"):
        persistri.greedy_insertion(heights, max_points=4)


def test_nested_deeper_still_reads_as_ragged() -> None:
    with pytest.raises(ValueError, match=r"^heights: not a rectangular 2D array \(ragged rows\?\): "):
        as_heights([[1, [2]], [3, 4]])
