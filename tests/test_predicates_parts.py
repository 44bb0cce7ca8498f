"""The parts under the predicates: binary exponents, integer scaling, filter decisions, SoS helpers, input checks."""

from __future__ import annotations

import itertools
from fractions import Fraction

import geometry_reference as ref
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.geometry.exact import ZERO_LOW, IntegerScale, binary_exponents, grain_span
from persistri.impl.geometry.filter import (
    ERRBOUND_INCIRCLE,
    ERRBOUND_ORIENT2D,
    ERRBOUND_ORIENT3D,
    GRAIN_MIN,
    TOP_MAX,
    choose_scaling,
    incircle_terms,
    orient2d_terms,
    orient3d_terms,
)
from persistri.impl.geometry.points import as_points, unique_rows
from persistri.impl.geometry.sos import ORIENT2D_SOS, ORIENT3D_SOS, minor, perturbed_sign, sort_with_parity

finite = st.floats(allow_nan=False, allow_infinity=False)


def _low_high(x: float) -> tuple[int, int]:
    """From ``as_integer_ratio``: ``x = num / 2^d``."""
    num, den = abs(x).as_integer_ratio()
    d = den.bit_length() - 1
    tz = (num & -num).bit_length() - 1
    return tz - d, num.bit_length() - d


@given(st.lists(finite.filter(lambda v: v != 0), min_size=1, max_size=6))
def test_binary_exponents_against_fractions(values: list[float]) -> None:
    low, high = binary_exponents(np.array(values))
    for v, lo, hi in zip(values, low.tolist(), high.tolist()):
        assert (lo, hi) == _low_high(v)


def test_binary_exponents_of_zero_and_subnormals() -> None:
    low, high = binary_exponents(np.array([0.0, -0.0, 5e-324, 2.0**-1030 * 3, 1.0]))
    assert low.tolist() == [ZERO_LOW, ZERO_LOW, -1074, -1030, 0]
    assert high.tolist()[2:] == [-1073, -1028, 1]


@given(st.lists(finite, min_size=1, max_size=12))
def test_grain_span_is_the_extremes_of_the_binary_exponents(values: list[float]) -> None:
    """The least grain and greatest magnitude over the nonzero values, from fractions (None if all are 0);
    values spanning more binades than a quotient can hold take the per-entry route, and agree too."""
    nonzero = [_low_high(v) for v in values if v != 0]
    expected = (min(lo for lo, _ in nonzero), max(hi for _, hi in nonzero)) if nonzero else None
    assert grain_span(np.array(values)) == expected


def test_grain_span_at_the_ends_of_the_doubles() -> None:
    assert grain_span(np.array([0.0, -0.0])) is None
    assert grain_span(np.array([5e-324, 1.0])) == (-1074, 1)
    assert grain_span(np.array([5e-324, -1.7e308])) == (-1074, 1024)  # the per-entry route
    assert grain_span(np.array([3.0, 6.0, 12.0])) == (0, 4)  # 3 = 0b11: grain 2^0
    assert grain_span(np.array([[0.5, 2.0**-60 * 5], [0.0, 8.0]])) == (-60, 4)


@given(st.lists(finite, min_size=1, max_size=8), st.sampled_from([0, 2]))
def test_integer_scale_is_exact(values: list[float], extra: int) -> None:
    arr = np.array(values)
    low, _ = binary_exponents(arr)
    scale = IntegerScale.of(low, extra)
    ints = scale.to_ints(arr)
    for v, i in zip(values, ints.tolist()):
        assert isinstance(i, int)
        assert Fraction(i) == Fraction(v) * Fraction(2) ** (extra - scale.exponent)
        assert scale.to_int(v) == i


def test_choose_scaling() -> None:
    empty = np.zeros(0, dtype=np.int64)
    assert choose_scaling(empty, empty).uniform
    s = choose_scaling(np.array([-80, -60]), np.array([0, 1]))
    assert s.uniform and -80 + s.shift >= GRAIN_MIN and 1 + s.shift <= TOP_MAX
    s = choose_scaling(np.array([-1100]), np.array([-1000]))  # tiny: scaled up
    assert s.uniform and -1100 + s.shift >= GRAIN_MIN
    s = choose_scaling(np.array([-1100, 900]), np.array([-1000, 1000]))  # too wide for one scale
    assert not s.uniform and 1000 + s.shift <= TOP_MAX


U = 2.0**-53


@st.composite
def near_line(draw: st.DrawFn) -> list[float]:
    """Kettner et al.'s configuration: (0.5 + iu, 0.5 + ju) next to the line through (A, A) and (B, B)."""
    a, b = draw(st.lists(st.integers(1, 30), min_size=2, max_size=2, unique=True))
    i, j = draw(st.integers(0, 63)), draw(st.integers(0, 63))
    pts = draw(st.permutations([(0.5 + i * U, 0.5 + j * U), (float(a), float(a)), (float(b), float(b))]))
    e = 2.0 ** draw(st.integers(-100, 100))
    return [v * e for p in pts for v in p]


@st.composite
def near_plane(draw: st.DrawFn) -> list[float]:
    """A probe within a few ulps of the plane x + y + z = 1.5 through three exact points."""
    i, j, k = (draw(st.integers(-6, 6)) for _ in range(3))
    fixed = [(12.0, 12.0, -22.5), (24.0, -10.0, -12.5), (-3.0, 24.0, -19.5), (1.5, 0.0, 0.0), (0.0, -6.0, 7.5)]
    pts = draw(st.permutations(draw(st.permutations(fixed))[:3] + [(0.5 + i * U, 0.5 + j * U, 0.5 + k * U)]))
    e = 2.0 ** draw(st.integers(-60, 60))
    return [v * e for p in pts for v in p]


@st.composite
def near_circle(draw: st.DrawFn) -> list[float]:
    """A probe within a few ulps of the circle x² + y² = 25 through three exact points."""
    circle = [(3.0, 4.0), (4.0, -3.0), (-5.0, 0.0), (0.0, 5.0), (-4.0, -3.0)]
    i, j = draw(st.integers(-6, 6)), draw(st.integers(-6, 6))
    probe = draw(st.sampled_from([(5.0 + i * 4 * U, j * U), (3.0 + i * 2 * U, -4.0 + j * 4 * U)]))
    pts = draw(st.permutations(draw(st.permutations(circle))[:3] + [probe]))
    e = 2.0 ** draw(st.integers(-60, 60))
    return [v * e for p in pts for v in p]


def _check_decision(det: float, perm: float, bound: float, exact: Fraction | int) -> bool:
    thr = bound * perm
    if det > thr:
        assert exact > 0
        return True
    if det < -thr:
        assert exact < 0
        return True
    return False


@given(near_line())
def test_orient2d_filter_decisions_are_right(coords: list[float]) -> None:
    det, perm = orient2d_terms(*coords)
    f = [Fraction(v) for v in coords]
    exact = ref.det([[f[0], f[1], 1], [f[2], f[3], 1], [f[4], f[5], 1]])
    _check_decision(det, perm, ERRBOUND_ORIENT2D, exact)


def test_orient2d_filter_on_kettners_grid() -> None:
    """All 64 × 64 probes (0.5 + iu, 0.5 + ju) against the line through (12, 12) and (24, 24), probe last.

    Plain floating point gets some signs wrong here (checked, so the sweep is
    meaningful); the filter must never decide one of them wrongly (here it
    rightly declines them all; with a too small constant it would not).
    """
    naive_wrong = 0
    for i in range(64):
        for j in range(64):
            coords = [12.0, 12.0, 24.0, 24.0, 0.5 + i * U, 0.5 + j * U]
            det, perm = orient2d_terms(*coords)
            f = [Fraction(v) for v in coords]
            exact = (f[0] - f[4]) * (f[3] - f[5]) - (f[1] - f[5]) * (f[2] - f[4])
            naive_wrong += det != 0 and (det > 0) != (exact > 0)
            _check_decision(det, perm, ERRBOUND_ORIENT2D, exact)
    assert naive_wrong > 0


@given(near_plane())
def test_orient3d_filter_decisions_are_right(coords: list[float]) -> None:
    det, perm = orient3d_terms(*coords)
    f = [Fraction(v) for v in coords]
    exact = ref.det([f[3 * i : 3 * i + 3] + [Fraction(1)] for i in range(4)])
    _check_decision(det, perm, ERRBOUND_ORIENT3D, exact)


@given(near_circle())
def test_incircle_filter_decisions_are_right(coords: list[float]) -> None:
    det, perm = incircle_terms(*coords)
    f = [Fraction(v) for v in coords]
    exact = ref.det([[f[2 * i], f[2 * i + 1], f[2 * i] ** 2 + f[2 * i + 1] ** 2, Fraction(1)] for i in range(4)])
    _check_decision(det, perm, ERRBOUND_INCIRCLE, exact)


def test_filter_never_decides_an_exact_zero_and_overflow_is_undecided() -> None:
    a, b, c, d = (0.1, 0.2, 0.3), (0.2, 0.4, 0.6), (0.7, 0.1, 0.9), (0.0, 0.0, 0.0)  # b = 2a: a, b, d collinear
    det, perm = orient3d_terms(*a, *b, *c, *d)
    thr = ERRBOUND_ORIENT3D * perm
    assert perm > 0 and not (det > thr or det < -thr)
    det, perm = orient3d_terms(1e308, 0.0, 0.0, 0.0, 1e308, 0.0, 0.0, 0.0, 1e308, -1e308, -1e308, -1e308)
    thr = ERRBOUND_ORIENT3D * perm
    assert not (det > thr or det < -thr)  # inf/NaN never pass the comparison


@given(st.lists(st.integers(0, 50), min_size=2, max_size=4, unique=True))
def test_sort_with_parity(indices: list[int]) -> None:
    order, parity = sort_with_parity(indices)
    assert order == sorted(indices)
    inversions = sum(1 for i, j in itertools.combinations(range(len(indices)), 2) if indices[i] > indices[j])
    assert parity == (-1) ** inversions
    with pytest.raises(ValueError, match="distinct"):
        sort_with_parity(indices + indices[:1])


@given(st.lists(st.integers(-9, 9), min_size=16, max_size=16))
def test_minor_is_the_determinant(entries: list[int]) -> None:
    m = [entries[4 * i : 4 * i + 4] for i in range(4)]
    for k in range(1, 5):
        for rows in itertools.combinations(range(4), k):
            for cols in itertools.combinations(range(4), k):
                assert minor(m, rows, cols) == ref.leibniz([[m[r][c] for c in cols] for r in rows])


def test_sos_tables_end_in_a_constant_and_decide_any_matrix() -> None:
    assert ORIENT2D_SOS[-1][1:] == ((2,), (2,)) and ORIENT3D_SOS[-1][1:] == ((3,), (3,))
    same = [(1, 1, 1, 1)] * 4  # four equal points: every minor but the constant vanishes
    assert perturbed_sign(same, ORIENT3D_SOS) == 1
    assert perturbed_sign([(0, 0, 1)] * 3, ORIENT2D_SOS) == 1


def test_as_points_conversions() -> None:
    pts = as_points([[-0.0, 1, True]], 3)
    assert pts.dtype == np.float64 and np.signbit(pts[0, 0]) == False  # noqa: E712 (numpy bool)
    assert as_points(np.zeros((0, 2)), 2).shape == (0, 2)
    assert as_points(np.array([[1.5, 2.5]], dtype=np.float32), 2).tolist() == [[1.5, 2.5]]
    assert as_points(np.array([[2**62, 1]], dtype=np.int64), 2)[0, 0] == 2.0**62
    with pytest.raises(ValueError, match="row 0"):
        as_points(np.array([[2**62 + 1, 1]], dtype=np.int64), 2)
    if np.finfo(np.longdouble).nmant > 52:
        with pytest.raises(ValueError, match="exactly"):
            as_points(np.array([[np.longdouble(1) / 3, 0]], dtype=np.longdouble), 2)
    with pytest.raises(TypeError):
        as_points(np.array([[object(), 1]], dtype=object), 2)
    with pytest.raises(ValueError, match="row 3"):
        as_points([[0.0, 0.0], [0.0, 0.0], [1.0, 1.0], [0.0, -float("inf")]], 2)


@given(st.lists(st.tuples(st.sampled_from([0.0, -0.0, 1.0, 2.5, 1e300]), st.sampled_from([0.0, 3.0])), max_size=12))
def test_unique_rows(rows: list[tuple[float, float]]) -> None:
    arr = np.array(rows, dtype=float).reshape(-1, 2)
    first, inverse = unique_rows(arr)
    seen: dict[tuple[float, float], int] = {}
    expected_first: list[int] = []
    expected_inverse: list[int] = []
    for i, r in enumerate(rows):
        key = (r[0] + 0.0, r[1] + 0.0)
        if key not in seen:
            seen[key] = len(expected_first)
            expected_first.append(i)
        expected_inverse.append(seen[key])
    assert first.tolist() == expected_first
    assert inverse.tolist() == expected_inverse
    if len(rows):
        assert np.array_equal(arr[first][inverse], arr)


@given(st.lists(st.tuples(finite, finite, finite), min_size=1, max_size=10), st.sampled_from([1.0, 2.0**-600, 2.0**600, 5e-324]))
def test_the_filter_copy_is_the_points_times_their_power_of_two(rows: list[tuple[float, float, float]], unit: float) -> None:
    """The filter's copy of the points is ``ldexp(points, shift)`` exactly, however it is computed (a product by
    ``2^shift`` where that is a double); rows the filter cannot hold (a non-uniform set) stay NaN."""
    from persistri.impl.geometry.predicates import Predicates3

    with np.errstate(all="ignore"):
        pts = np.array(rows, dtype=np.float64) * unit
    pts = pts[np.isfinite(pts).all(axis=1)] + 0.0
    if not len(pts):
        return
    p = Predicates3(pts)
    shift, _ = p.filter_scale
    with np.errstate(all="ignore"):
        expected = np.ldexp(pts, shift)
    for j, col in enumerate(p._cols):
        held = ~np.isnan(col)
        assert col[held].tobytes() == expected[held, j].tobytes()
