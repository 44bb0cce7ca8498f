"""The unvalidated fast path of orient3d (Orient3dKernel) and the setup shortcuts: same answers as the checked API.

That the kernel's written-out filter expressions are the proved functions is
checked in ``test_predicates_kernel_filters.py``.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray
from test_predicates import point_sets

from persistri.impl.geometry.filter import FLOPS_ORIENT3D, FLOPS_PLANE, FLOPS_PLANE_SIDE
from persistri.impl.geometry.points import unique_rows
from persistri.impl.geometry.kernel import KERNEL_BATCH, MASK_BELOW, SCALAR_BELOW
from persistri.impl.geometry.predicates import Predicates3
from persistri.impl.stats import Stats


def _split(p: Predicates3, a: int, b: int, c: int, qs: list[int]) -> tuple[list[int], list[int]]:
    """The reference: the checked scalar test, point by point, order kept."""
    signs = [p.orient3d(a, b, c, q) for q in qs]
    return [q for q, s in zip(qs, signs) if s < 0], [q for q, s in zip(qs, signs) if s > 0]


def _lists(pair: tuple[object, object]) -> tuple[list[int], list[int]]:
    minus, plus = pair
    return [int(q) for q in minus], [int(q) for q in plus]  # type: ignore[attr-defined]  # list or array


@settings(max_examples=60)
@given(point_sets(min_size=5, max_size=9), st.data())
def test_kernel_agrees_with_the_checked_predicates(pts: NDArray[np.float64], data: st.DataObject) -> None:
    """Degenerate sets (grids, planes, lines, duplicates, extreme scales): the filter fails, exact and SoS decide."""
    p = Predicates3(pts)
    n = len(p)
    k = p.kernel()
    a, b, c = data.draw(st.permutations(range(n)))[:3]
    rest = [q for q in range(n) if q not in (a, b, c)]
    for q in rest:
        assert k.orient3d(a, b, c, q) == p.orient3d(a, b, c, q)
    expected = _split(p, a, b, c, rest)
    assert _lists(k.partition(a, b, c, rest)) == expected
    assert _lists(k.partition(a, b, c, tuple(rest))) == expected
    assert _lists(k.partition(a, b, c, np.array(rest, dtype=np.intp))) == expected


def _grid_with_planes() -> NDArray[np.float64]:
    """A 6×6×6 integer grid: most plane-side tests through grid points are exact zeros (SoS decides)."""
    g = np.arange(6, dtype=float)
    return np.array([[x, y, z] for x in g for y in g for z in g])


def _point_set(kind: str, rng: np.random.Generator, n: int) -> NDArray[np.float64]:
    """``n`` random points in the unit cube, the 6×6×6 grid, or ``n`` grid points of step 1e-3 offset by 1e9."""
    if kind == "random":
        return rng.random((n, 3))
    if kind == "grid":
        return _grid_with_planes()
    return rng.integers(-50, 50, size=(n, 3)).astype(float) * 1e-3 + 1e9


@pytest.mark.parametrize("kind", ["random", "grid", "offset"])
def test_partition_vectorised_path_agrees(kind: str) -> None:
    rng = np.random.default_rng(3)
    pts = _point_set(kind, rng, 400)
    p = Predicates3(pts)
    k = p.kernel()
    n = len(p)
    for a, b, c in ((0, 1, 2), (0, 7, 42), (5, 36, 200)):
        qs = [q for q in rng.permutation(n).tolist() if q not in (a, b, c)]
        assert len(qs) >= KERNEL_BATCH  # the vectorised path
        minus, plus = k.partition(a, b, c, np.array(qs, dtype=np.intp))
        assert isinstance(minus, np.ndarray) and isinstance(plus, np.ndarray)
        assert _lists((minus, plus)) == _split(p, a, b, c, qs)
        assert k.signs(a, b, c, np.array(qs, dtype=np.intp)).tolist() == [p.orient3d(a, b, c, q) for q in qs]
        small = qs[: KERNEL_BATCH - 1]
        got = k.partition(a, b, c, small)
        assert isinstance(got[0], list)
        assert _lists(got) == _split(p, a, b, c, small)



@pytest.mark.parametrize("kind", ["random", "offset"])
def test_partition_by_masks_and_by_index_lists_agree(kind: str) -> None:
    """Below :data:`MASK_BELOW` points the vectorised partition gathers each side by its boolean mask, from there
    on through index lists: either way the checked predicates' lists, in the order given, of the type given."""
    rng = np.random.default_rng(11)
    p = Predicates3(_point_set(kind, rng, 1600))
    k = p.kernel()
    n = len(p)
    for a, b, c in ((0, 1, 2), (3, 500, 900)):
        qs = [q for q in rng.permutation(n).tolist() if q not in (a, b, c)]
        for m in (SCALAR_BELOW, MASK_BELOW - 1, MASK_BELOW, len(qs)):
            part = qs[:m]
            expected = _split(p, a, b, c, part)
            for dtype in (np.int32, np.intp):
                minus, plus = k.partition(a, b, c, np.array(part, dtype=dtype))
                assert isinstance(minus, np.ndarray) and isinstance(plus, np.ndarray)
                assert minus.dtype == plus.dtype == np.dtype(dtype)
                assert _lists((minus, plus)) == expected

def test_partition_with_the_exact_centroid_and_empty_input() -> None:
    """A needle tetrahedron: the float centroid is not inside, the exact one has no float copy (NaN row)."""
    third = 1 / 3
    rng = np.random.default_rng(2)
    pts = np.vstack([[[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0], [third, third, third + 2.0**-52]], rng.random((100, 3)) - 0.2])
    base = Predicates3(pts)
    c = base.with_centroid(0, 1, 2, 3)
    assert not c.centre_is_float
    k = c.kernel()
    centre = len(c) - 1
    qs = list(range(4, centre))
    assert len(qs) >= KERNEL_BATCH
    for arg in (qs, np.array(qs, dtype=np.intp), qs[:5]):
        q_list = [int(q) for q in arg]
        assert _lists(k.partition(centre, 0, 1, arg)) == _split(c, centre, 0, 1, q_list)
        assert _lists(k.partition(0, 1, centre, arg)) == _split(c, 0, 1, centre, q_list)
    assert [k.orient3d(centre, 0, 1, q) for q in qs] == [c.orient3d(centre, 0, 1, q) for q in qs]
    assert k.signs(centre, 0, 1, np.array(qs)).tolist() == [c.orient3d(centre, 0, 1, q) for q in qs]
    assert k.signs(0, 1, 2, np.zeros(0, dtype=np.intp)).tolist() == []
    assert _lists(k.partition(0, 1, 2, [])) == ([], [])
    assert _lists(k.partition(0, 1, 2, np.zeros(0, dtype=np.intp))) == ([], [])


def test_wide_dynamic_range_falls_back_to_the_checked_path() -> None:
    """Grains too far apart for one filter scale: the kernel uses the per-test grain checks, same signs."""
    pts = np.array([[1e300, 0.0, 0.0], [0.0, 1e-300, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0],
                    [2.0**-1000, 3.0, 1e300], [-1e300, 1e-300, 5.0], [7.0, -2.0**-1000, 1.0]] * 6, dtype=float)
    pts = pts + np.arange(pts.shape[0])[:, None] * np.array([[0.0, 0.0, 1.0]])
    p = Predicates3(pts)
    assert p.filter_scale[1] is False
    k = p.kernel()
    qs = list(range(3, len(p)))
    assert _lists(k.partition(0, 1, 2, qs)) == _split(p, 0, 1, 2, qs)
    assert _lists(k.partition(0, 1, 2, np.array(qs))) == _split(p, 0, 1, 2, qs)
    assert [k.orient3d(0, 1, 2, q) for q in qs] == [p.orient3d(0, 1, 2, q) for q in qs]
    assert k.signs(0, 1, 2, np.array(qs)).tolist() == [p.orient3d(0, 1, 2, q) for q in qs]


def test_kernel_counts_like_the_checked_predicates() -> None:
    rng = np.random.default_rng(5)
    stats = Stats()
    p = Predicates3(rng.random((300, 3)), stats=stats)
    k = p.kernel()
    k.orient3d(0, 1, 2, 3)
    assert (stats.plane_side_tests, stats.flops, stats.filter_failures) == (1, FLOPS_ORIENT3D, 0)
    for m in (5, 200):
        stats.reset()
        k.partition(0, 1, 2, list(range(3, 3 + m)))
        assert (stats.plane_side_tests, stats.flops) == (m, FLOPS_PLANE + m * FLOPS_PLANE_SIDE)
    # The grid: exact zeros everywhere on the plane z = 0, each one a filter failure.
    stats = Stats()
    g = Predicates3(_grid_with_planes(), stats=stats)
    a, b, c = 0, 1, 6  # (0,0,0), (0,0,1), (0,1,0): the plane x = 0
    qs = [q for q in range(216) if q not in (a, b, c)]
    g.kernel().partition(a, b, c, qs)
    assert stats.filter_failures == sum(1 for q in qs if g.points[q, 0] == 0.0) > 0


@settings(max_examples=40)
@given(st.integers(4, 40), st.integers(0, 2**32 - 1), st.sampled_from([1.0, 1e-5, 1e5, 2.0**-200]),
       st.sampled_from([0.0, 3.0, 1e9]))
def test_centroid_shortcut_builds_what_the_full_setup_builds(n: int, seed: int, scale: float, offset: float) -> None:
    """with_centroid appends the float centroid without redoing the setup when the filter scale stays: same object."""
    rng = np.random.default_rng(seed)
    pts = rng.random((n, 3)) * scale + offset
    p = Predicates3(pts)
    if p.orient3d_sign(0, 1, 2, 3) == 0:
        return
    guess = ((pts[0] + pts[1]) + (pts[2] + pts[3])) * 0.25 + 0.0
    fast = p._with_row(guess)
    full = Predicates3.__new__(Predicates3)
    full._setup(np.vstack([pts, guess[None, :]]), exact_rows=n + 1, extra=0, stats=None)
    if fast is None:
        assert full.filter_scale != p.filter_scale or not full.filter_scale[1]
        return
    for attr in ("_n", "_dim", "_shift", "_span", "_scale", "_uniform"):
        assert getattr(fast, attr) == getattr(full, attr), attr
    # Rows are made on first use: the same floats once made, whichever were made before.
    assert [fast._row(i) for i in range(n + 1)] == [full._row(i) for i in range(n + 1)]
    assert fast._grain is None and full._grain is None  # uniform sets keep no per-point grains
    assert all(np.array_equal(x, y) for x, y in zip(fast._cols, full._cols))
    assert np.array_equal(fast.points, full.points)


def test_unique_rows_on_real_valued_data_with_planted_duplicates() -> None:
    """Distinct first coordinates take a shortcut; any repeat goes through the full lexicographic sort."""
    rng = np.random.default_rng(11)
    pts = rng.random((500, 3))
    u = unique_rows(pts)
    assert u.first.tolist() == list(range(500)) and u.inverse.tolist() == list(range(500))
    dup = np.vstack([pts, pts[[3, 3, 17]], pts[[17]] * np.array([[1.0, 1.0, 2.0]])])
    u = unique_rows(dup)
    assert u.first.tolist() == list(range(500)) + [503]
    assert u.inverse[500:].tolist() == [3, 3, 17, 500]
    assert np.array_equal(dup[u.first][u.inverse], dup)


@pytest.mark.parametrize("kind", ["random", "grid", "offset"])
def test_counted_and_uncounted_partitions_agree(kind: str) -> None:
    """Uncounted, the partition tests against the semi-static threshold first; counted, every point against
    its own: the same exact answers (the grid's exact zeros included), at every size."""
    p = Predicates3(_point_set(kind, np.random.default_rng(5), 300))
    k = p.kernel()
    for a, b, c in ((0, 1, 2), (0, 7, 42), (5, 36, 200)):
        qs = [q for q in range(len(p)) if q not in (a, b, c)]
        for part in (qs[:5], qs):
            p.stats = None
            fast = _lists(k.partition(a, b, c, part))
            p.stats = Stats()
            counted = _lists(k.partition(a, b, c, np.array(part, dtype=np.intp)))
            assert fast == counted == _split(p, a, b, c, part)


def test_rows_are_made_on_first_use_and_are_the_scaled_copy() -> None:
    """Predicates3 makes a point's tuple of floats (the scalar tests' operands) when a test first reads it,
    with its block; the kernel's scalar paths and the checked API make them alike, to the same floats."""
    rng = np.random.default_rng(8)
    pts = rng.random((200, 3)) * 3.0 - 1.0
    p = Predicates3(pts)
    assert not any(p._rows)  # nothing made yet
    k = p.kernel()
    assert k.orient3d(150, 3, 77, 199) == p.orient3d(150, 3, 77, 199)
    made = [i for i, r in enumerate(p._rows) if r]
    assert 0 < len(made) < 200 and {150, 3, 77, 199} <= set(made)
    assert _lists(k.partition(120, 5, 60, [180, 181, 40])) == _split(p, 120, 5, 60, [180, 181, 40])
    shift, _ = p.filter_scale
    for i in range(200):
        assert p._row(i) == tuple(np.ldexp(pts[i], shift).tolist())


# -- split: three partitions in one pass ----------------------------------------------------------------


def _split_reference(
    p: Predicates3, a: int, b: int, c: int, qs: list[int], lo: tuple[int, int, int] | None, hi: tuple[int, int, int] | None
) -> tuple[list[int], list[int], list[int], list[int]]:
    """What ``split`` stands for: the checked test by (a, b, c), then each side by its own plane (or whole)."""
    minus, plus = _split(p, a, b, c, qs)
    mm, mp = _split(p, *lo, minus) if lo is not None else (minus, [])
    pm, pp = _split(p, *hi, plus) if hi is not None else (plus, [])
    return mm, mp, pm, pp


def _four(got: tuple[object, object, object, object]) -> tuple[list[int], ...]:
    return tuple([int(q) for q in part] for part in got)  # type: ignore[attr-defined]  # list, tuple or array


@pytest.mark.parametrize("kind", ["random", "grid", "offset"])
def test_split_is_the_three_partitions_it_stands_for(kind: str) -> None:
    """The same lists in the same order as the partitions (the grid's exact zeros decided by SoS), short
    (one pass) and long (the partitions themselves), with either second plane absent, counted or not —
    and counted alike: the same tests, flops and filter failures as the three partition calls."""
    rng = np.random.default_rng(11)
    p = Predicates3(_point_set(kind, rng, 300))
    k = p.kernel()
    planes = ((0, 1, 2), (0, 7, 42), (5, 36, 200), (3, 9, 27))
    for a, b, c in planes[:3]:
        used = {i for plane in planes for i in plane}  # no point is tested against a plane through it
        rest = [q for q in rng.permutation(len(p)).tolist() if q not in used]
        for lo, hi in ((planes[3], planes[1]), (None, planes[3]), (planes[2], None), (None, None)):
            for part in (rest[:1], rest[:9], rest[: KERNEL_BATCH - 1], rest):
                want = _split_reference(p, a, b, c, part, lo, hi)
                p.stats = None
                assert _four(k.split(a, b, c, part, lo, hi)) == want
                assert _four(k.split(a, b, c, tuple(part), lo, hi)) == want
                assert _four(k.split(a, b, c, np.array(part, dtype=np.intp), lo, hi)) == want
                p.stats = fused = Stats()
                assert _four(k.split(a, b, c, part, lo, hi)) == want
                p.stats = separate = Stats()
                minus, plus = k.partition(a, b, c, part)
                if lo is not None:
                    k.partition(*lo, minus)
                if hi is not None:
                    k.partition(*hi, plus)
                assert fused.as_dict() == separate.as_dict()
    p.stats = None
    assert k.split(0, 1, 2, [], planes[3], None) == ((), (), (), ())


def test_split_on_the_checked_path() -> None:
    """A point set with per-test grain checks: split is the checked partitions, composed."""
    pts = np.array([[1e300, 0.0, 0.0], [0.0, 1e-300, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0],
                    [2.0**-1000, 3.0, 1e300], [-1e300, 1e-300, 5.0], [7.0, -2.0**-1000, 1.0]] * 6, dtype=float)
    pts = pts + np.arange(pts.shape[0])[:, None] * np.array([[0.0, 0.0, 1.0]])
    p = Predicates3(pts)
    assert p.filter_scale[1] is False
    k = p.kernel()
    qs = list(range(6, len(p)))
    assert _four(k.split(0, 1, 2, qs, (3, 4, 5), (1, 3, 5))) == _split_reference(p, 0, 1, 2, qs, (3, 4, 5), (1, 3, 5))
