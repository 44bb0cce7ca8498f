"""The fan's sector test: exact float signs on small integers, one + → − change per sample."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.stats import Stats
from persistri.impl.terrain.sectors import EXACT_LIMIT, fan_sectors, sector_of, sector_sides, small_integer_points


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


def _fan(n: int, closed: bool) -> tuple[Predicates2, np.ndarray, np.ndarray]:
    """p = 0 at the centre of a grid, a ring of boundary vertices around it (or half of one: an open chain), the rest samples."""
    side = 7
    xy = np.array([(c, r) for r in range(-3, side - 3) for c in range(-3, side - 3)], dtype=np.float64)
    xy = np.vstack([[0.0, 0.0], xy[np.any(xy != 0.0, axis=1)]])
    pred = Predicates2(xy)
    # The ring: the grid's boundary cells, counterclockwise by angle (exact order: they are distinct directions).
    border = [i for i in range(1, len(xy)) if max(abs(xy[i, 0]), abs(xy[i, 1])) == 3]
    border.sort(key=lambda i: float(np.arctan2(xy[i, 1], xy[i, 0])))
    ring = border[::n]
    if closed:
        rays = np.array(ring + ring[:1], dtype=np.intp)
        inside = [i for i in range(1, len(xy)) if i not in ring]
    else:
        # An open chain from the ray along -x to the ray along +x through y < 0 ... the lower half-plane.
        lower = sorted((i for i in border if xy[i, 1] < 0), key=lambda i: float(np.arctan2(xy[i, 1], xy[i, 0])))
        left = next(i for i in border if xy[i, 1] == 0 and xy[i, 0] < 0)
        right = next(i for i in border if xy[i, 1] == 0 and xy[i, 0] > 0)
        ring = [left] + lower[::n] + [right]
        rays = np.array(ring, dtype=np.intp)
        inside = [i for i in range(1, len(xy)) if i not in ring and xy[i, 1] <= 0]
    return pred, rays, np.array(inside, dtype=np.intp)


@pytest.mark.parametrize("closed", [True, False])
@pytest.mark.parametrize("step", [1, 2, 3])
@pytest.mark.parametrize("exact_floats", [True, False])
def test_fan_sectors_equals_sides_then_sector_of(closed: bool, step: int, exact_floats: bool) -> None:
    pred, rays, samples = _fan(step, closed)
    inner = rays[:-1] if closed else rays[1:-1]
    expect = sector_of(sector_sides(pred, 0, inner, samples, exact_floats=False), closed, check=True)
    order, sector = fan_sectors(pred, 0, rays, samples, closed, exact_floats=exact_floats, check=True)
    assert sorted(order.tolist()) == list(range(samples.size))
    assert sector.tolist() == expect[order].tolist()
    assert np.array_equal(order, np.argsort(expect, kind="stable"))  # grouped by sector, stable within


def test_fan_sectors_counts_the_same_tests() -> None:
    for closed in (True, False):
        pred, rays, samples = _fan(2, closed)
        inner = rays[:-1] if closed else rays[1:-1]
        a, b = Stats(), Stats()
        sector_sides(pred, 0, inner, samples, exact_floats=True, stats=a)
        fan_sectors(pred, 0, rays, samples, closed, exact_floats=True, stats=b)
        assert (a.plane_side_tests, a.flops) == (b.plane_side_tests, b.flops) and a.plane_side_tests > 0


def test_fan_sectors_rejects_a_ring_that_is_not_a_fan() -> None:
    # Rays that wind twice round p: some samples see two + → − changes.
    pred, rays, samples = _fan(2, True)
    twice = np.concatenate([rays[:-1], rays])
    with pytest.raises(ValueError, match="changes side"):
        fan_sectors(pred, 0, twice, samples, True, exact_floats=True)


def _grid_fan(step: int, closed: bool, seed: int) -> tuple[int, int, np.ndarray, np.ndarray]:
    """A fan on a 9 × 11 grid: p at (4, 4), a ring of the cells at distance 3 (or the lower half of one), the
    samples inside it in a shuffled order (samples on the rays included). Returns (cols, p, rays, samples)."""
    cols = 11
    p = 4 * cols + 4
    cells = [(c, r) for r in range(1, 8) for c in range(1, 8) if (c, r) != (4, 4)]
    border = [(c, r) for c, r in cells if max(abs(c - 4), abs(r - 4)) == 3]
    border.sort(key=lambda q: float(np.arctan2(q[1] - 4, q[0] - 4)))
    if closed:
        chain = border[::step]
        ring = chain + chain[:1]
        inner = [q for q in cells if q not in chain]
    else:
        lower = [q for q in border if q[1] < 4]
        ring = [(1, 4)] + lower[::step] + [(7, 4)]
        inner = [q for q in cells if q not in ring and q[1] <= 4]
    rng = np.random.default_rng(seed)
    samples = np.array([r * cols + c for c, r in inner], dtype=np.int32)[rng.permutation(len(inner))]
    return cols, p, np.array([r * cols + c for c, r in ring], dtype=np.intp), samples


@pytest.mark.parametrize("closed", [True, False])
@pytest.mark.parametrize("step", [1, 2, 3, 5])
@pytest.mark.parametrize("seed", [0, 1])
def test_fan_small_equals_the_numpy_block(closed: bool, step: int, seed: int) -> None:
    from persistri.impl.geometry.grid_predicates import GridPredicates2
    from persistri.impl.terrain.sectors import _fan_block, fan_small

    cols, p, rays, samples = _grid_fan(step, closed, seed)
    pred = GridPredicates2((9, cols))
    order, sector = fan_small(cols, p, rays, samples, closed)
    ref_order, ref_sector = _fan_block(pred, p, rays, samples, closed, None)
    assert order.dtype == ref_order.dtype == np.intp and sector.dtype == ref_sector.dtype == np.intp
    assert order.tolist() == ref_order.tolist() and sector.tolist() == ref_sector.tolist()
    # And the exact predicate says the same (fan_sectors dispatches to fan_small for few samples when compiled).
    general = Predicates2(pred.points)
    g_order, g_sector = fan_sectors(general, p, rays, samples, closed, exact_floats=False, check=True)
    assert g_order.tolist() == order.tolist() and g_sector.tolist() == sector.tolist()
    f_order, f_sector = fan_sectors(pred, p, rays, samples, closed, exact_floats=True)
    assert f_order.tolist() == order.tolist() and f_sector.tolist() == sector.tolist()


def test_fan_small_rejects_a_ring_that_is_not_a_fan() -> None:
    from persistri.impl.terrain.sectors import fan_small

    cols, p, rays, samples = _grid_fan(2, True, 0)
    twice = np.concatenate([rays[:-1], rays])
    with pytest.raises(ValueError, match="changes side from \\+ to - 2 times"):
        fan_small(cols, p, twice, samples, True)


@pytest.mark.parametrize("closed", [True, False])
@pytest.mark.parametrize("step", [1, 7])
def test_many_samples_take_the_flat_changes_and_agree(closed: bool, step: int) -> None:
    """Above FLAT_CHANGES samples _fan_block lists the + → − changes by their flat positions: the same
    (order, sector) as fan_small's loop and as the exact predicate, samples on the rays included."""
    from persistri.impl.geometry.grid_predicates import GridPredicates2
    from persistri.impl.terrain.sectors import FLAT_CHANGES, _fan_block, fan_small

    n, c = 41, 20
    cells = [(x, y) for y in range(n) for x in range(n) if (x, y) != (c, c)]
    border = [(x, y) for x, y in cells if max(abs(x - c), abs(y - c)) == c]
    border.sort(key=lambda q: float(np.arctan2(q[1] - c, q[0] - c)))
    if closed:
        chain = border[::step]
        ring = chain + chain[:1]
        inner = [q for q in cells if q not in chain]
    else:
        lower = [q for q in border if q[1] < c]
        ring = [(0, c)] + lower[::step] + [(n - 1, c)]
        inner = [q for q in cells if q not in ring and q[1] <= c]
    rng = np.random.default_rng(step)
    samples = np.array([y * n + x for x, y in inner], dtype=np.int32)[rng.permutation(len(inner))]
    rays = np.array([y * n + x for x, y in ring], dtype=np.intp)
    p = c * n + c
    assert samples.size > FLAT_CHANGES
    pred = GridPredicates2((n, n))
    order, sector = _fan_block(pred, p, rays, samples, closed, None)
    loop_order, loop_sector = fan_small(n, p, rays, samples, closed)
    assert order.dtype == sector.dtype == np.intp
    assert order.tolist() == loop_order.tolist() and sector.tolist() == loop_sector.tolist()
    general = Predicates2(pred.points)
    g_order, g_sector = fan_sectors(general, p, rays, samples, closed, exact_floats=False, check=True)
    assert g_order.tolist() == order.tolist() and g_sector.tolist() == sector.tolist()
    twice = np.concatenate([rays[:-1], rays]) if closed else np.concatenate([rays, rays[1:]])
    with pytest.raises(ValueError, match="changes side"):
        _fan_block(pred, p, twice, samples, closed, None)


@pytest.mark.parametrize("closed", [True, False])
@pytest.mark.parametrize("step", [1, 2, 3])
@pytest.mark.parametrize("few", [1, 2, 5, "bound"])
def test_few_samples_on_lists_equal_the_general_path(closed: bool, step: int, few: int | str) -> None:
    """insertion.fan_samples' list path for a few samples on a grid (_small_fan) makes the same lists, pool,
    counts, fan index (values and dtypes) and counted tests as the array path, with p among the cavity's lists."""
    from persistri.impl.geometry.grid_predicates import GridPredicates2
    from persistri.impl.terrain import insertion
    from persistri.impl.terrain.sectors import PYTHON_SECTORS

    cols, p, rays, samples = _grid_fan(step, closed, 1)
    m = min(PYTHON_SECTORS, samples.size) if few == "bound" else int(few)  # the grid fan has 24 to 45 samples
    taken = samples[:m]
    # The cavity's lists: the samples in three pieces, p inside the second one (it is left out of every result).
    cut = [taken[: m // 3], np.concatenate([taken[m // 3 : m // 2], np.array([p], np.int32), taken[m // 2 :]])]
    lists = [part for part in cut] + [np.zeros(0, np.int32)]
    ring = rays.tolist()
    nfan = len(ring) - 1
    grid = GridPredicates2((9, cols), stats=Stats())
    general = Predicates2(grid.points, stats=Stats())
    got = insertion._small_fan(grid, p, [s for s in lists if s.size], ring, closed, nfan)
    assert got is not None
    via = insertion.fan_samples(grid, p, lists, ring, closed, nfan, exact_floats=True, check=False)
    ref = insertion.fan_samples(general, p, lists, ring, closed, nfan, exact_floats=True, check=True)
    for own, pooled, counts, sector in (got, via):
        r_own, r_pooled, r_counts, r_sector = ref
        assert counts == r_counts and sum(counts) == m
        assert pooled.dtype == r_pooled.dtype == np.int32 and pooled.tolist() == r_pooled.tolist()
        assert sector.dtype == r_sector.dtype == np.intp and sector.tolist() == r_sector.tolist()
        assert [a.dtype for a in own if a.size] == [a.dtype for a in r_own if a.size]
        assert [a.tolist() for a in own] == [a.tolist() for a in r_own]
        assert not pooled.flags.writeable and not sector.flags.writeable and not any(a.flags.writeable for a in own)
    assert grid.stats is not None and general.stats is not None
    assert grid.stats.plane_side_tests == 2 * general.stats.plane_side_tests > 0
    assert grid.stats.flops == 2 * general.stats.flops
    # More samples than the bound: the general path's answer (None here).
    more = samples[: PYTHON_SECTORS + 1]
    if more.size > PYTHON_SECTORS:
        assert insertion._small_fan(grid, p, [more], ring, closed, nfan) is None


@pytest.mark.parametrize("closed", [True, False])
@pytest.mark.parametrize("m", [15, 16, 17, 19])
def test_few_samples_on_lists_make_the_fan_index_either_way(closed: bool, m: int) -> None:
    """_small_fan's fan index from a list (up to _INDEX_FROM_LIST samples) and by repeat (above it), with the
    bound raised so that both builds take both: the same lists, pool, counts and fan index as the general path."""
    from persistri.impl.geometry.grid_predicates import GridPredicates2
    from persistri.impl.terrain import insertion

    assert insertion._INDEX_FROM_LIST == 16
    cols, p, rays, samples = _grid_fan(2, closed, 1)
    taken = samples[:m]
    assert taken.size == m
    lists = [taken[: m // 2], np.concatenate([np.array([p], np.int32), taken[m // 2 :]])]
    ring = rays.tolist()
    nfan = len(ring) - 1
    grid = GridPredicates2((9, cols))
    got = insertion._small_fan(grid, p, lists, ring, closed, nfan, 64)
    assert got is not None
    ref = insertion.fan_samples(Predicates2(grid.points), p, lists, ring, closed, nfan, exact_floats=True, check=True)
    own, pooled, counts, sector = got
    r_own, r_pooled, r_counts, r_sector = ref
    assert counts == r_counts and sum(counts) == m and sum(1 for c in counts if c) > 1
    assert pooled.dtype == r_pooled.dtype and pooled.tolist() == r_pooled.tolist()
    assert sector.dtype == r_sector.dtype == np.intp and sector.tolist() == r_sector.tolist()
    assert [a.dtype for a in own if a.size] == [a.dtype for a in r_own if a.size]
    assert [a.tolist() for a in own] == [a.tolist() for a in r_own]
    assert not pooled.flags.writeable and not sector.flags.writeable and not any(a.flags.writeable for a in own)
    # Every list owns exactly its samples (a copy, not a view of the pool), unless it is the whole pool.
    assert all(a.base is None and a.flags.owndata for a in own if a.size)


def test_few_samples_on_lists_reject_a_ring_that_is_not_a_fan() -> None:
    from persistri.impl.geometry.grid_predicates import GridPredicates2
    from persistri.impl.terrain.errors import TriangulationCheckError
    from persistri.impl.terrain.insertion import fan_samples

    cols, p, rays, samples = _grid_fan(2, True, 0)
    twice = np.concatenate([rays[:-1], rays]).tolist()
    with pytest.raises(TriangulationCheckError, match="inserting point 48: sample row 0 changes side from \\+ to - 2 times"):
        fan_samples(GridPredicates2((9, cols)), p, [samples[:3]], twice, True, len(twice) - 1, exact_floats=True, check=False)
