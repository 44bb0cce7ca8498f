"""What greedy insertion keeps per sample, and the block-wise paths that keep its peak memory down (issue 17).

The memory properties are counted in bytes of the arrays the mesher keeps, never measured as resident
memory: every sample list owns exactly its samples (no view holding a larger pool alive), and the
block-wise computations (the fan's lists of a large cavity, a level's maximum and RMS error) give bit
for bit what the whole-array computations give.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.geometry.grid_predicates import GridPredicates2
from persistri.impl.maps import backend as map_backend
from persistri.impl.stats import Stats
from persistri.impl.terrain.check import RMS_BLOCK, ScaledSquares, largest_magnitude, root_mean_square
from persistri.impl.terrain.delaunay import sample_dtype
from persistri.impl.terrain.greedy import Tin, _finite_triangles, _level_summary, greedy_insertion
from persistri.impl.terrain.greedy_run import ID_BITS, GreedyRun, QueueKeys
from persistri.impl.terrain.plane_errors import apex_first, level_errors, ranks
from persistri.impl.terrain.sectors import fan_lists, fan_sectors


def _terrain(rows: int, cols: int, seed: int) -> NDArray[np.float64]:
    rng = np.random.default_rng(seed)
    return np.cumsum(np.cumsum(rng.normal(size=(rows, cols)), axis=0), axis=1)


def _lists(tin: Tin) -> list[NDArray[np.integer[Any]]]:
    """The sample lists of the mesh's triangles that hold samples (the ghosts' and the empty ones share one array)."""
    return [d[1] for _, d in tin.structure.items(tin.complex) if d[1].size]


@pytest.mark.parametrize("history", [False, True])
def test_every_sample_list_owns_exactly_its_samples(history: bool) -> None:
    heights = _terrain(70, 90, 3)
    tin = greedy_insertion(heights, max_points=400, history=history)
    lists = _lists(tin)
    listed = sum(a.size for a in lists)
    assert listed == heights.size - tin.n_points  # every sample but the vertices, once
    # No list is a view: a view would keep the whole pool it was cut from alive.
    assert all(a.base is None and a.flags.owndata and not a.flags.writeable for a in lists)
    # 4 bytes a listed sample: int32 indices (the grid has fewer than 2^31 samples).
    assert all(a.dtype == np.int32 for a in lists)
    assert sum(a.nbytes for a in lists) == 4 * listed
    if history:
        # The older versions' lists own their samples too (each kept list is one pool's part).
        h = tin.history
        assert h is not None
        old = [d[1] for _, d in h.structure.items(h.versions[50]) if d[1].size]
        assert all(a.base is None for a in old)


def test_sample_lists_are_int32_while_every_index_fits() -> None:
    assert sample_dtype(2**31) == np.dtype(np.int32)
    assert sample_dtype(2**31 + 1) == np.dtype(np.intp)
    assert np.iinfo(sample_dtype(2**31)).max == 2**31 - 1


def _fan_case(n: int) -> tuple[GridPredicates2, int, NDArray[np.intp], bool, NDArray[np.intp]]:
    """The centre sample of an ``n × n`` grid, a ring of samples round it, and every other sample (centre included)."""
    pred = GridPredicates2((n, n))
    c = n // 2
    p = c * n + c
    ring_rc = [(0, 0), (0, c), (0, n - 1), (c, n - 1), (n - 1, n - 1), (n - 1, c), (n - 1, 0), (c, 0)]
    # Counterclockwise in (x, y) = (col, row): along row 0 to the right, then up the rows.
    ring = [r * n + cc for r, cc in ring_rc]
    rays = np.array(ring + ring[:1], dtype=np.intp)
    others = np.setdiff1d(np.arange(n * n, dtype=np.intp), rays)
    return pred, p, rays, True, others


@pytest.mark.parametrize("block", [7, 64, 1 << 18])
@pytest.mark.parametrize("dtype", [np.intp, np.int32])
def test_fan_lists_from_several_arrays_equal_fan_sectors_of_the_pool(block: int, dtype: type) -> None:
    pred, p, rays, closed, others = _fan_case(21)
    rng = np.random.default_rng(5)
    pool: NDArray[Any] = rng.permutation(others).astype(dtype)  # p among them, once
    cuts = np.sort(rng.choice(np.arange(1, pool.size), 3, replace=False))
    arrays = np.split(pool, cuts)
    joined = pool[pool != p]
    expect_stats, stats = Stats(), Stats()
    order, sector = fan_sectors(pred, p, rays, joined, closed, exact_floats=True, stats=expect_stats)
    ends = np.searchsorted(sector, np.arange(rays.size))
    expect = [joined[order][ends[i] : ends[i + 1]] for i in range(rays.size - 1)]
    got = fan_lists(pred, p, rays, arrays, closed, exact_floats=True, stats=stats, block=block)
    assert len(got) == len(expect)
    for a, b in zip(got, expect):
        assert a.dtype == np.dtype(dtype) and np.array_equal(a, b)
    assert (stats.plane_side_tests, stats.flops) == (expect_stats.plane_side_tests, expect_stats.flops)


@settings(max_examples=25, deadline=None)
@given(st.integers(1, 3 * RMS_BLOCK + 5), st.lists(st.integers(0, 3 * RMS_BLOCK + 5), max_size=6), st.integers(0, 2**32 - 1))
def test_scaled_squares_in_parts_equal_root_mean_square(size: int, cuts: list[int], seed: int) -> None:
    errors = np.abs(np.random.default_rng(seed).normal(scale=10.0, size=size))
    largest = largest_magnitude(errors)
    assert largest == float(np.max(np.abs(errors)))
    acc = ScaledSquares(largest)
    for part in np.split(errors, sorted(c for c in cuts if c < size)):
        acc.add(part)
    count = size + 17  # samples with no error count too
    assert acc.rms(count) == root_mean_square(errors, count)


def test_a_level_summary_equals_the_errors_of_the_whole_level() -> None:
    heights = _terrain(60, 50, 11)
    tin = greedy_insertion(heights, max_points=300)
    h = tin.history
    assert h is not None
    inf = h.infinite
    items = [(t, d) for t, d in h.structure.items(tin.complex) if inf not in t]
    tri = np.array([[int(v) for v in t] for t, _ in items], dtype=np.intp).reshape(-1, 3)
    lists = [d[1] for _, d in items]
    counts = np.array([a.size for a in lists], dtype=np.intp)
    apex = apex_first(tri, ranks(tri.ravel(), h.inserted).reshape(-1, 3))
    z = heights.ravel()
    err = level_errors(heights.shape[1], z, apex, counts, lists, int(counts.sum()))
    whole = (float(err.max()), root_mean_square(err, z.size))
    assert (tin.max_error, tin.rms_error) == whole
    # The queue's maximum as the scale (one pass), none (two passes), a wrong one (a second pass): the same floats.
    for expected in (tin.max_error, None, 2.0 * tin.max_error, 0.0):
        assert _level_summary(heights.shape[1], z, apex, counts, lists, z.size, expected) == whole


_POSITIVE = st.floats(min_value=5e-324, max_value=float("inf"), allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(_POSITIVE, st.integers(0, 2**64 - 1), st.integers(0, 2**22 - 1)), max_size=40), st.data())
def test_queue_keys_order_as_the_tuples_and_give_back_their_fields(
    entries: list[tuple[float, int, int]], data: st.DataObject
) -> None:
    # Ties in the error, as the mesher makes them (equal floats from different triangles).
    if entries:
        e = data.draw(st.sampled_from([e for e, _, _ in entries]))
        entries = entries + [(e, t + 1 if t < 2**64 - 1 else 0, s) for _, t, s in entries[:3]]
    keys = QueueKeys(2**22)
    packed = {keys.key(keys.bits(e), t, s): (e, t, s) for e, t, s in entries}
    for key, (e, t, s) in packed.items():
        assert type(key) is int
        assert keys.error(key) == e and keys.tid(key) == t and keys.sample(key) == s
        assert key.bit_length() <= 63 + ID_BITS + 22  # 48 bytes as a CPython int (5 or 6 digits of 30 bits)
    assert [packed[k] for k in sorted(packed)] == sorted(set(entries), key=lambda x: (-x[0], x[1], x[2]))


def test_queue_key_bits_are_the_float64_bits() -> None:
    errors = np.array([5e-324, 1e-300, 0.5, 1.0, 1.0000000000000002, 3.0, 1e300, np.inf])
    bits = errors.view(np.int64).tolist()
    keys = QueueKeys(100)
    assert bits == [keys.bits(float(e)) for e in errors]
    assert bits == sorted(bits) and len(set(bits)) == len(bits)


def test_the_queue_holds_one_integer_per_live_candidate() -> None:
    heights = _terrain(64, 80, 7)
    run = GreedyRun(heights.ravel().copy(), heights.shape, TwoComplex(map_backend("red_black"), None), None, False)
    for _ in range(300):
        run.current_error()
        run.step()
    top = run.current_error()
    assert run.heap and all(type(k) is int for k in run.heap)
    alive = run.T.tri_of
    live = [k for k in run.heap if run.keys.tid(k) in alive]
    # Each live entry is its triangle's candidate: the first sample of largest error, at that error.
    structure, cx = run.structure, run.T.complex
    for key in live[:50]:
        tri = alive[run.keys.tid(key)]
        found = structure.data(cx, tri)
        assert found is not None
        own = found[0][1]
        assert int(run.keys.sample(key)) in own.tolist()
    assert top == max(run.keys.error(k) for k in live)
    assert len(live) == len({run.keys.tid(k) for k in live})  # one entry per triangle


def test_reading_a_mesh_makes_no_list_of_its_items(monkeypatch: pytest.MonkeyPatch) -> None:
    heights = _terrain(50, 40, 2)
    expected = greedy_insertion(heights, max_points=200, history=False)

    def no_list(self: Any, c: Any) -> Any:
        raise AssertionError("the mesher read a list of every triangle (items)")

    # A run and its final mesh read through iter_items only, with the same result.
    with monkeypatch.context() as m:
        m.setattr(TwoComplex, "items", no_list)
        tin = greedy_insertion(heights, max_points=200, history=False)
    assert np.array_equal(tin.triangles, expected.triangles) and np.array_equal(tin.vertices, expected.vertices)
    assert (tin.max_error, tin.rms_error) == (expected.max_error, expected.rms_error)
    inf = heights.size  # the symbolic vertex's label
    tri, lists = _finite_triangles(tin.structure, tin.complex, inf)
    items = [(t, d) for t, d in tin.structure.items(tin.complex) if inf not in t]
    assert tri.dtype == np.intp and tri.shape == (len(items), 3)
    assert tri.tolist() == [[int(v) for v in t] for t, _ in items]
    assert len(lists) == len(items) and all(a is d[1] for a, (_, d) in zip(lists, items))


def test_grid_rows_share_their_floats_and_keys() -> None:
    rows, cols = 30, 40
    pred = GridPredicates2((rows, cols))
    rng = np.random.default_rng(4)
    points = [int(i) for i in rng.choice(rows * cols, 500, replace=False)]
    for q in points:
        assert pred.xy(q) == (float(q % cols), float(q // cols))
    table = pred._rows
    assert isinstance(table, dict) and len(table) == len(points)
    floats = {id(f) for row in table.values() for f in row}
    assert len(floats) <= rows + cols  # one float object per distinct coordinate, not two per point
    keys = {id(k) for k in table}
    assert keys == {id(q) for q in points}  # kept under the integers asked for, not copies
