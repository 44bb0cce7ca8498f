"""GridPredicates2 answers as Predicates2 over the same grid points: every sign, checked and kernel, batches.

The terrain mesher tests its grid's points through
:class:`~persistri.impl.geometry.grid_predicates.GridPredicates2`, which computes a
point's coordinates from its index instead of keeping them; grids are the most
degenerate input there is (every row collinear, cocircular quadruples everywhere), so
the symbolic perturbation decides most tests, and it must decide them exactly as the
general :class:`~persistri.impl.geometry.predicates2.Predicates2` does.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.geometry.grid_predicates import GridPredicates2
from persistri.impl.geometry.predicates2 import Predicates2
from persistri.impl.terrain.plane_errors import grid_points


@st.composite
def grid_and_indices(draw: st.DrawFn) -> tuple[tuple[int, int], list[tuple[int, int, int, int]]]:
    rows = draw(st.integers(1, 9))
    cols = draw(st.integers(1, 9))
    n = rows * cols
    if n < 4:
        cols = 4
        n = rows * cols
    quads = draw(st.lists(st.lists(st.integers(0, n - 1), min_size=4, max_size=4, unique=True), min_size=1, max_size=30))
    return (rows, cols), [(a, b, c, d) for a, b, c, d in quads]


@given(grid_and_indices())
def test_every_sign_is_the_general_predicates_sign(case: tuple[tuple[int, int], list[tuple[int, int, int, int]]]) -> None:
    shape, quads = case
    grid = GridPredicates2(shape)
    general = Predicates2(grid_points(shape))
    assert np.array_equal(grid.points, general.points)
    gk, pk = grid.kernel(), general.kernel()
    for a, b, c, d in quads:
        assert grid.orient2d(a, b, c) == general.orient2d(a, b, c) == gk.orient2d(a, b, c) == pk.orient2d(a, b, c)
        assert grid.orient2d_sign(a, b, c) == general.orient2d_sign(a, b, c) == gk.orient2d_sign(a, b, c)
        assert grid.incircle(a, b, c, d) == general.incircle(a, b, c, d) == gk.incircle(a, b, c, d) == pk.incircle(a, b, c, d)
        assert grid.incircle_sign(a, b, c, d) == general.incircle_sign(a, b, c, d)
    a, b, c, _ = quads[0]
    qs = np.arange(shape[0] * shape[1], dtype=np.intp)
    qs = qs[(qs != a) & (qs != b) & (qs != c)]
    assert np.array_equal(grid.orient2d_batch(a, b, qs), general.orient2d_batch(a, b, qs))
    assert np.array_equal(grid.incircle_batch(a, b, c, qs), general.incircle_batch(a, b, c, qs))


def test_coordinates_of_every_sample_and_bad_indices() -> None:
    grid = GridPredicates2((5, 7))
    q = np.arange(35, dtype=np.int32)
    x, y = grid.coordinates(q)
    assert np.array_equal(np.column_stack([x, y]).astype(np.float64), grid_points((5, 7)))
    assert grid.xy(12) == (5.0, 1.0)
    with pytest.raises(IndexError):
        grid.orient2d(0, 1, 35)
    with pytest.raises(ValueError):
        grid.orient2d(0, 1, 1)


@pytest.mark.parametrize("shape", [(5, 7), (8, 8), (3, 9), (1, 6), (6, 1), (13, 2)])
def test_zorder_labels_decide_every_test_as_the_grid_index(shape: tuple[int, int]) -> None:
    """GridPredicates2(labels="zorder") indexes the samples by z-order label and ranks them by grid index for
    Simulation of Simplicity: every sign, ties included (grids are cocircular everywhere), is the row-major one."""
    from persistri.impl.geometry.grid_labels import GridZOrder

    rows_pred, z_pred = GridPredicates2(shape), GridPredicates2(shape, labels="zorder")
    n = shape[0] * shape[1]
    zorder = GridZOrder(shape)
    lab = [z_pred.label(q) for q in range(n)]
    assert lab == zorder.labels(np.arange(n)).tolist() == z_pred.labels(np.arange(n)).tolist()
    assert len(set(lab)) == n and max(lab) < len(z_pred) == zorder.size <= 4 * n
    assert [z_pred.grid_index(i) for i in lab] == list(range(n)) == z_pred.grid_indices(np.array(lab)).tolist()
    assert [zorder.decode(i) for i in lab] == [(q % shape[1], q // shape[1]) for q in range(n)]
    kr, kz = rows_pred.kernel(), z_pred.kernel()
    rng = np.random.default_rng(n)
    for _ in range(1500):
        a, b, c, d = (rng.choice(n, 4, replace=False) if n >= 4 else np.arange(4) % n).tolist()
        A, B, C, D = lab[a], lab[b], lab[c], lab[d]
        assert rows_pred.orient2d(a, b, c) == z_pred.orient2d(A, B, C) == kz.orient2d(A, B, C)
        assert rows_pred.orient2d_sign(a, b, c) == z_pred.orient2d_sign(A, B, C) == kz.orient2d_sign(A, B, C)
        assert rows_pred.incircle(a, b, c, d) == z_pred.incircle(A, B, C, D) == kz.incircle(A, B, C, D)
        assert kr.incircle(a, b, c, d) == kz.incircle(A, B, C, D)
    qs = np.arange(n)
    for _ in range(20):
        a, b, c = rng.choice(n, 3, replace=False).tolist()
        rest = qs[(qs != a) & (qs != b) & (qs != c)]
        assert (rows_pred.orient2d_batch(a, b, rest) == z_pred.orient2d_batch(lab[a], lab[b], z_pred.labels(rest))).all()
        assert (rows_pred.incircle_batch(a, b, c, rest) == z_pred.incircle_batch(lab[a], lab[b], lab[c], z_pred.labels(rest))).all()


def test_zorder_labels_of_no_sample_are_no_points() -> None:
    pred = GridPredicates2((3, 5), labels="zorder")
    holes = sorted(set(range(len(pred))) - {pred.label(q) for q in range(15)})
    assert holes and len(pred) == 32
    with pytest.raises(IndexError):
        pred.xy(holes[0])
    with pytest.raises(ValueError, match="labels"):
        GridPredicates2((3, 5), labels="hilbert")
