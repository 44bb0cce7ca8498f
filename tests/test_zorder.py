"""Z-order labels (:mod:`persistri.impl.geometry.zorder`): a permutation, the Z curve, locality."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from persistri.impl.geometry.zorder import morton_order, morton_order_distinct


def test_the_z_curve_on_a_grid() -> None:
    """On the 4 × 4 grid the order is the Z curve: quadrant by quadrant, each a Z (x is the low bit)."""
    pts = np.array([[x, y] for y in range(4) for x in range(4)], dtype=float)  # row-major
    order = morton_order(pts)
    visited = [(int(pts[i, 0]), int(pts[i, 1])) for i in order]
    assert visited[:8] == [(0, 0), (1, 0), (0, 1), (1, 1), (2, 0), (3, 0), (2, 1), (3, 1)]
    assert visited[8:] == [(0, 2), (1, 2), (0, 3), (1, 3), (2, 2), (3, 2), (2, 3), (3, 3)]


@given(arrays(np.float64, st.tuples(st.integers(0, 60), st.integers(1, 3)),
              elements=st.floats(-1e300, 1e300, allow_nan=False)))
def test_a_stable_permutation(pts: np.ndarray) -> None:
    order = morton_order(pts)
    assert sorted(order.tolist()) == list(range(len(pts)))
    # Equal points are adjacent in input order (stable), whatever the range.
    again = morton_order(np.concatenate([pts, pts]))
    pos = np.empty(2 * len(pts), dtype=np.intp)
    pos[again] = np.arange(2 * len(pts))
    for i in range(len(pts)):
        assert pos[i] < pos[i + len(pts)]


def test_locality_on_a_cube_grid() -> None:
    """Consecutive points of the order are mostly grid neighbours (a shuffled order almost never is)."""
    g = np.array([[x, y, z] for x in range(16) for y in range(16) for z in range(16)], dtype=float)
    shuffled = g[np.random.default_rng(0).permutation(len(g))]
    steps = np.abs(np.diff(shuffled[morton_order(shuffled)], axis=0)).sum(axis=1)
    assert np.mean(steps == 1) >= 0.5
    assert np.mean(np.abs(np.diff(shuffled, axis=0)).sum(axis=1) == 1) < 0.05


def test_degenerate_and_bad_shapes() -> None:
    assert morton_order(np.zeros((0, 3))).tolist() == []
    assert morton_order(np.zeros((5, 3))).tolist() == [0, 1, 2, 3, 4]  # every axis constant
    with pytest.raises(ValueError, match="shape"):
        morton_order(np.zeros((3, 4)))
    with pytest.raises(ValueError, match="shape"):
        morton_order(np.zeros(3))


def _reference_order(pts: np.ndarray) -> list[int]:
    """Rows by their full 3 × 21-bit Morton code, ties in input order: codes interleaved bit by bit in Python."""
    top = (1 << 21) - 1
    codes = []
    cols = []
    for j in range(pts.shape[1]):
        col = pts[:, j]
        lo, hi = float(col.min()) / 2, float(col.max()) / 2
        q = np.clip(np.floor((col / 2 - lo) / (hi - lo) * top), 0, top).astype(np.int64) if hi > lo else np.zeros(len(col), dtype=np.int64)
        cols.append(q.tolist())
    for i in range(len(pts)):
        codes.append(sum(((cols[j][i] >> b) & 1) << (3 * b + j) for j in range(len(cols)) for b in range(21)))
    return sorted(range(len(pts)), key=lambda i: codes[i])


def test_codes_that_share_their_leading_bits_are_still_ordered_by_the_whole_code() -> None:
    """The fast path sorts the codes' leading bits with the row index below them; points closer than its
    resolution (here pairs 2^-22 apart, in input order opposite to their codes) must still come in the
    order of their whole codes."""
    rng = np.random.default_rng(5)
    base = rng.random((300, 3))
    pts = np.concatenate([base + 2.0**-22, base])  # the second copy has the smaller codes
    assert morton_order(pts).tolist() == _reference_order(pts)
    spread_out = rng.random((500, 3))  # no shared leading bits: the fast path
    assert morton_order(spread_out).tolist() == _reference_order(spread_out)


@given(arrays(np.float64, st.tuples(st.integers(0, 60), st.integers(1, 3)),
              elements=st.one_of(st.floats(-1e300, 1e300, allow_nan=False), st.sampled_from([0.0, 1.0, 2.0]))))
def test_distinct_codes_prove_distinct_rows(pts: np.ndarray) -> None:
    """``morton_order_distinct`` gives :func:`morton_order`'s permutation, and says True only for pairwise
    distinct rows (what lets the hull skip ``unique_rows``); with a row repeated it must say False."""
    order, distinct = morton_order_distinct(pts)
    assert order.tolist() == morton_order(pts).tolist()
    if distinct:
        assert len({tuple(r) for r in (pts + 0.0).tolist()}) == len(pts)
    if len(pts):
        assert morton_order_distinct(np.concatenate([pts, pts[:1]]))[1] is False
