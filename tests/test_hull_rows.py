"""The canonical triangle rows of a hull (``_as_rows``) and its vertex rows (``_vertex_rows``) against the plain
numpy statements they replace: the same arrays, on both sides of the packed-key limit (rows of 21 bits)."""

from __future__ import annotations

import numpy as np
import pytest

from persistri.impl.hull.api import _as_rows, _vertex_rows


def _reference_rows(corners: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """Each triangle rotated to start at its least row (argmin), then the rows sorted lexicographically."""
    arr = rows[corners]
    k = np.argmin(arr, axis=1)
    arr = np.take_along_axis(arr, (k[:, None] + np.arange(3)[None, :]) % 3, axis=1)
    return arr[np.lexsort(arr.T[::-1])]


def _triangles(rng: np.random.Generator, n: int, m: int) -> np.ndarray:
    """``m`` triangles of three distinct indices below ``n``, in every rotation."""
    tri = np.array([rng.choice(n, size=3, replace=False) for _ in range(m)], dtype=np.intp)
    return tri


@pytest.mark.parametrize("top", [100, 2**21 - 1, 2**21, 2**40])
@pytest.mark.parametrize("seed", [0, 1])
def test_as_rows_is_the_rotated_lexicographic_order(top: int, seed: int) -> None:
    rng = np.random.default_rng(seed)
    n = 60
    # Row labels: a permutation, with the greatest one set to top (so the packed key's width is decided by it).
    rows = rng.permutation(n).astype(np.intp)
    rows[rows == n - 1] = top
    corners = _triangles(rng, n, 400)
    label = int(np.flatnonzero(rows == top)[0])
    corners[0] = [label, (label + 1) % n, (label + 2) % n]  # a triangle at the top row
    got = _as_rows(corners, rows)
    want = _reference_rows(corners, rows)
    assert got.dtype == np.intp and got.shape == want.shape == (400, 3)
    assert np.array_equal(got, want)
    assert int(got.max()) == top


def test_as_rows_keeps_orientation_and_empty_input() -> None:
    rows = np.arange(10, dtype=np.intp)[::-1].copy()  # row of label i is 9 - i
    corners = np.array([[0, 1, 2], [5, 3, 4], [7, 9, 8]], dtype=np.intp)
    # (9, 8, 7) -> (7, 9, 8); (4, 6, 5) -> (4, 6, 5); (2, 0, 1) -> (0, 1, 2): each a rotation, never a reflection.
    assert _as_rows(corners, rows).tolist() == [[0, 1, 2], [4, 6, 5], [7, 9, 8]]
    assert _as_rows(np.zeros((0, 3), dtype=np.intp), rows).shape == (0, 3)


def test_vertex_rows_is_unique() -> None:
    rng = np.random.default_rng(3)
    simplices = rng.integers(0, 1000, size=(700, 3)).astype(np.intp)
    got = _vertex_rows(simplices, 1200)
    assert got.dtype == np.intp
    assert np.array_equal(got, np.unique(simplices))
    assert _vertex_rows(np.zeros((0, 3), dtype=np.intp), 5).size == 0
