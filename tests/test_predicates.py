"""Exact 3D predicates: orient3d against Fraction determinants, SoS, batches, counting, the centre, affine rank."""

from __future__ import annotations

import itertools
from fractions import Fraction

import geometry_reference as ref
import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from numpy.typing import NDArray

from persistri.impl.geometry.filter import FLOPS_ORIENT3D
from persistri.impl.geometry.predicates import SMALL_BATCH, Predicates2, Predicates3, affine_dimension
from persistri.impl.stats import Stats

# -- point sets ------------------------------------------------------------------------------

SCALES = [1.0, 2.0**-1000, 2.0**997, 2.0**-60, 2.0**60, 1e-300]
OFFSETS = [0.0, 1e9, 1e12]


@st.composite
def point_sets(draw: st.DrawFn, min_size: int = 4, max_size: int = 9) -> NDArray[np.float64]:
    """Small 3D sets rich in degeneracies: integer grids, planes, lines, duplicates, extreme scales."""
    n = draw(st.integers(min_size, max_size))
    kind = draw(st.sampled_from(["grid", "plane", "line", "floats", "mixed"]))
    small = st.integers(-3, 3)
    if kind == "grid":
        pts = np.array([[draw(small) for _ in range(3)] for _ in range(n)], dtype=float)
    elif kind == "plane":
        a, b, c = draw(small), draw(small), draw(small)
        xy = [(draw(small), draw(small)) for _ in range(n)]
        pts = np.array([[x, y, a * x + b * y + c] for x, y in xy], dtype=float)
        pts = pts[:, draw(st.permutations([0, 1, 2]))]
    elif kind == "line":
        p, d = [draw(small) for _ in range(3)], [draw(small) for _ in range(3)]
        ts = [draw(small) for _ in range(n - 1)]
        extra = [draw(small) for _ in range(3)]
        pts = np.array([[p[j] + t * d[j] for j in range(3)] for t in ts] + [extra], dtype=float)
    elif kind == "floats":
        fl = st.floats(allow_nan=False, allow_infinity=False, min_value=-1e300, max_value=1e300)
        pts = np.array([[draw(fl) for _ in range(3)] for _ in range(n)], dtype=float)
    else:  # each point at its own extreme scale: mixtures of 1e300 and 1e-300
        pts = np.array(
            [[draw(small) * draw(st.sampled_from([1.0, 2.0**-1000, 2.0**997, 1e300, 1e-300])) for _ in range(3)] for _ in range(n)],
            dtype=float,
        )
    if kind != "mixed" and kind != "floats":
        pts = pts * draw(st.sampled_from(SCALES)) + draw(st.sampled_from(OFFSETS))
    if draw(st.booleans()):  # duplicates
        pts = np.vstack([pts, pts[: draw(st.integers(1, 2))]])
    return pts


def distinct_quads(n: int) -> list[tuple[int, int, int, int]]:
    return [(a, b, c, d) for a, b, c, d in itertools.product(range(n), repeat=4) if len({a, b, c, d}) == 4]


# -- orient3d and its true sign ----------------------------------------------------------------


@given(point_sets(max_size=7))
def test_orient3d_matches_fraction_determinant_and_sos_is_consistent(pts: NDArray[np.float64]) -> None:
    p = Predicates3(pts)
    n = len(pts)
    for a, b, c, d in itertools.combinations(range(n), 4):
        true = ref.orient(pts, a, b, c, d)
        assert p.orient3d_sign(a, b, c, d) == true
        s = p.orient3d(a, b, c, d)
        assert s in (-1, 1)
        if true:
            assert s == true
        # Antisymmetry under each transposition, invariance under even permutations.
        assert p.orient3d(b, a, c, d) == -s
        assert p.orient3d(a, c, b, d) == -s
        assert p.orient3d(a, b, d, c) == -s
        assert p.orient3d(d, b, c, a) == -s
        assert p.orient3d(b, c, a, d) == s
        assert p.orient3d(d, a, b, c) == -s  # a cyclic shift of four is odd


@given(point_sets(min_size=5, max_size=5))
def test_many_and_batch_equal_scalar(pts: NDArray[np.float64]) -> None:
    p = Predicates3(pts)
    quads = np.array(distinct_quads(len(pts))[::3], dtype=np.intp)
    assert len(quads) >= SMALL_BATCH  # the vectorised path, not the scalar loop
    many = p.orient3d_many(quads[:, 0], quads[:, 1], quads[:, 2], quads[:, 3])
    assert many.dtype == np.int8
    assert many.tolist() == [p.orient3d(*map(int, q)) for q in quads]
    a, b, c = 0, 1, 2
    others = np.array([q for q in range(len(pts)) if q not in (a, b, c)] * 16, dtype=np.intp)
    assert others.size >= SMALL_BATCH
    batch = p.orient3d_batch(a, b, c, others)
    assert batch.tolist() == [p.orient3d(a, b, c, int(q)) for q in others]
    signs = p.orient3d_sign_batch(a, b, c, others)
    assert signs.tolist() == [ref.orient(pts, a, b, c, int(q)) for q in others[: len(pts) - 3]] * 16


@pytest.mark.parametrize("kind", ["random", "grid"])
def test_many_with_fixed_points_in_any_position(kind: str) -> None:
    """Fixed points are moved to the filter's translation slot with a parity correction: check every placement."""
    rng = np.random.default_rng(11)
    pts = rng.random((40, 3)) if kind == "random" else rng.integers(0, 3, size=(40, 3)).astype(float)
    p = Predicates3(pts)
    q = np.arange(3, 40)
    for perm in itertools.permutations(range(4)):
        args: list[object] = [0, 1, 2, q]
        args = [args[k] for k in perm]
        got = p.orient3d_many(*args)  # type: ignore[arg-type]  # a mix of ints and an array
        expected = [p.orient3d(*[int(a) if isinstance(a, int) else int(x) for a in args]) for x in q]
        assert got.tolist() == expected, perm
    q2 = np.arange(2, 40)
    p2 = Predicates2(pts[:, :2])
    for perm in itertools.permutations(range(3)):
        args2: list[object] = [0, 1, q2]
        args2 = [args2[k] for k in perm]
        got = p2.orient2d_many(*args2)  # type: ignore[arg-type]  # a mix of ints and an array
        assert got.tolist() == [p2.orient2d(*[int(a) if isinstance(a, int) else int(x) for a in args2]) for x in q2]


def test_orient3d_sos_matches_explicit_perturbation() -> None:
    """SoS against the perturbed determinant evaluated at an explicit tiny ε (independent of the tables)."""
    rng = np.random.default_rng(7)
    pts = rng.integers(-2, 3, size=(10, 3)).astype(float)
    pts[5] = pts[4]  # a duplicate point
    p = Predicates3(pts)
    zeros = [q for q in itertools.combinations(range(10), 4) if ref.orient(pts, *q) == 0]
    assert len(zeros) >= 12
    for k, quad in enumerate(zeros[:12]):
        perm = list(itertools.permutations(quad))[(5 * k) % 24]  # arguments in varied orders
        assert p.orient3d(*perm) == ref.sos_sign(ref.rows(pts, perm), perm), perm


def test_sos_on_a_coplanar_square_follows_index_order() -> None:
    """A point's SoS index is its row: every ordering of a coplanar quadruple matches the explicit perturbation."""
    pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1]], dtype=float)
    p = Predicates3(pts)
    for quad in itertools.permutations(range(4)):
        assert p.orient3d(*quad) == ref.sos_sign(ref.rows(pts, quad), quad)


def test_filter_decides_random_input_and_counts() -> None:
    rng = np.random.default_rng(1)
    pts = rng.random((300, 3))
    stats = Stats()
    p = Predicates3(pts, stats=stats)
    quads = [tuple(map(int, rng.choice(300, 4, replace=False))) for _ in range(200)]
    for q in quads:
        assert p.orient3d(*q) == ref.orient(pts, *q)
    assert stats.plane_side_tests == 200
    assert stats.flops == 200 * FLOPS_ORIENT3D
    assert stats.filter_failures == 0
    qs = np.arange(3, 300)
    p.orient3d_batch(0, 1, 2, qs)
    assert stats.plane_side_tests == 200 + qs.size
    assert stats.flops == (200 + qs.size) * FLOPS_ORIENT3D
    assert stats.filter_failures == 0


def test_filter_failures_counted_on_degenerate_input() -> None:
    grid = np.array(list(itertools.product(range(3), repeat=3)), dtype=float)
    stats = Stats()
    p = Predicates3(grid, stats=stats)
    zeros = 0
    ints = grid.astype(int).tolist()
    for quad in itertools.combinations(range(27), 4):
        zeros += ref.det([ints[i] + [1] for i in quad]) == 0
        p.orient3d(*quad)
    assert zeros > 0
    # The filter cannot decide an exact zero (its decisions are proved), and it decides the rest here.
    assert stats.filter_failures == zeros
    before = stats.filter_failures
    qs = np.tile(np.arange(3, 27), 2)
    assert qs.size >= SMALL_BATCH
    expected = sum(ref.orient(grid, 0, 1, 2, int(q)) == 0 for q in qs)
    p.orient3d_batch(0, 1, 2, qs)  # 0, 1, 2 are collinear: every test is an exact zero
    assert expected == qs.size
    assert stats.filter_failures - before == expected


def test_near_degenerate_input_where_plain_floats_fail() -> None:
    """Points within a few ulps of a plane: naive float orientation gets signs wrong, the filter falls back."""
    u = 2.0**-53
    # A plane x + y + z = 1.5 through three exact points, probes (0.5 + iu, 0.5 + ju, 0.5) near it.
    pts = [np.array([12.0, 12.0, -22.5]), np.array([24.0, -10.0, -12.5]), np.array([-3.0, 24.0, -19.5])]
    for i in range(-6, 6):
        for j in range(-6, 6):
            pts.append(np.array([0.5 + i * u, 0.5 + j * u, 0.5]))
    arr = np.array(pts)
    stats = Stats()
    p = Predicates3(arr, stats=stats)
    naive_wrong = 0
    for q in range(3, len(arr)):
        true = ref.orient(arr, 0, 1, 2, q)
        assert p.orient3d_sign(0, 1, 2, q) == true
        if true:
            assert p.orient3d(0, 1, 2, q) == true
        m = arr[[0, 1, 2]] - arr[q]
        naive = float(np.linalg.det(m))
        naive_wrong += (naive > 0) - (naive < 0) != true
    assert naive_wrong > 0  # the test set really is beyond plain floating point
    assert stats.filter_failures > 0
    batch = p.orient3d_batch(0, 1, 2, np.arange(3, len(arr)))
    assert batch.tolist() == [p.orient3d(0, 1, 2, q) for q in range(3, len(arr))]


@pytest.mark.parametrize("scale", [1e300, 1e-300, 2.0**-1070, 1e150])
def test_extreme_magnitudes_are_scaled_into_the_filter_range(scale: float) -> None:
    rng = np.random.default_rng(3)
    pts = rng.random((60, 3)) * scale
    stats = Stats()
    p = Predicates3(pts, stats=stats)
    shift, uniform = p.filter_scale
    assert uniform
    for quad in itertools.islice(itertools.combinations(range(60), 4), 0, 3000, 97):
        assert p.orient3d_sign(*quad) == ref.orient(pts, *quad)
    if scale != 2.0**-1070:  # subnormal coordinates carry few bits; the rest are decided by the filter
        assert stats.filter_failures == 0


def test_mixture_of_huge_and_tiny_is_exact_with_per_test_grain_checks() -> None:
    rng = np.random.default_rng(4)
    pts = rng.random((40, 3))
    pts[::3] *= 1e300
    pts[1::3] *= 1e-300
    p = Predicates3(pts)
    assert not p.filter_scale[1]
    for quad in itertools.islice(itertools.combinations(range(40), 4), 0, 5000, 37):
        assert p.orient3d_sign(*quad) == ref.orient(pts, *quad)
        true = ref.orient(pts, *quad)
        if true:
            assert p.orient3d(*quad) == true
    qs = np.arange(3, 40)
    assert p.orient3d_sign_batch(0, 1, 2, qs).tolist() == [ref.orient(pts, 0, 1, 2, int(q)) for q in qs]


# -- the centre --------------------------------------------------------------------------------


def _barycentric_signs(pts: list[list[Fraction]], centre: list[Fraction]) -> list[int]:
    out = []
    for k in range(4):
        m = [row + [Fraction(1)] for row in pts]
        m[k] = centre + [Fraction(1)]
        out.append(ref.sign(ref.det(m)))
    return out


@given(point_sets(min_size=4, max_size=6))
def test_centroid_is_strictly_inside_and_indexed_last(pts: NDArray[np.float64]) -> None:
    p = Predicates3(pts)
    basis = p.affine_basis()
    assume(len(basis) == 4)
    c = p.with_centroid(*basis)
    n = len(pts)
    assert c.centre == n and len(c) == n + 1
    tetra = ref.rows(pts, basis)
    if c.centre_is_float:
        centre = [Fraction(float(v)) for v in c.points[n]]
    else:
        centre = [sum((t[j] for t in tetra), Fraction(0)) / 4 for j in range(3)]
    whole = [row + [Fraction(1)] for row in tetra]
    s = ref.sign(ref.det(whole))
    assert _barycentric_signs(tetra, centre) == [s] * 4
    # Tests involving the centre agree with the exact reference; a few exact zeros against explicit SoS.
    all_rows = ref.rows(pts, range(n)) + [centre]
    sos_checks = 0
    for a, b in itertools.combinations(range(n), 2):
        for q in range(min(a, b) + 1, n):
            if q in (a, b):
                continue
            m = [all_rows[i] + [Fraction(1)] for i in (a, b, n, q)]
            true = ref.sign(ref.det(m))
            assert c.orient3d_sign(a, b, n, q) == true
            got = c.orient3d(a, b, n, q)
            if true:
                assert got == true
            elif sos_checks < 1 and ref.small([all_rows[i] for i in (a, b, n, q)]):
                assert got == ref.sos_sign([all_rows[i] for i in (a, b, n, q)], (a, b, n, q))
                sos_checks += 1
            assert c.orient3d(b, a, n, q) == -got


def test_needle_tetrahedron_falls_back_to_the_exact_centroid() -> None:
    third = 1 / 3
    pts = np.array([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0], [third, third, third + 2.0**-52]])
    tetra = ref.rows(pts, range(4))
    guess = ((pts[0] + pts[1]) + (pts[2] + pts[3])) * 0.25
    s = ref.orient(pts, 0, 1, 2, 3)
    assert s != 0
    assert _barycentric_signs(tetra, [Fraction(float(v)) for v in guess]) != [s] * 4  # the float centroid fails
    stats = Stats()
    p = Predicates3(pts, stats=stats)
    c = p.with_centroid(0, 1, 2, 3)
    assert not c.centre_is_float
    assert c.stats is stats
    exact = [sum((t[j] for t in tetra), Fraction(0)) / 4 for j in range(3)]
    assert _barycentric_signs(tetra, exact) == [s] * 4
    before = stats.filter_failures
    for k in range(4):
        quad = [0, 1, 2, 3]
        quad[k] = 4
        assert c.orient3d(*quad) == s
    assert stats.filter_failures - before == 4  # the exact centre is never filtered
    qs = np.array([0, 1, 2, 3] * 8)
    assert qs.size >= SMALL_BATCH
    batch = c.orient3d_many(qs, np.roll(qs, 1), 4, np.roll(qs, 2))
    assert batch.tolist() == [c.orient3d(int(a), int(b), 4, int(d)) for a, b, d in zip(qs, np.roll(qs, 1), np.roll(qs, 2))]


def test_with_centroid_rejects_bad_tetrahedra() -> None:
    pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1]], dtype=float)
    p = Predicates3(pts)
    with pytest.raises(ValueError, match="coplanar"):
        p.with_centroid(0, 1, 2, 3)
    with pytest.raises(ValueError, match="distinct"):
        p.with_centroid(0, 1, 1, 4)
    c = p.with_centroid(0, 1, 2, 4)
    with pytest.raises(ValueError, match="already"):
        c.with_centroid(0, 1, 2, 4)
    with pytest.raises(IndexError):
        p.with_centroid(0, 1, 2, 5)


# -- affine dimension ----------------------------------------------------------------------------


def _rank(pts: NDArray[np.float64]) -> int:
    """Affine rank by exact Gaussian elimination on Fractions."""
    if len(pts) == 0:
        return -1
    rows_ = ref.rows(pts, range(len(pts)))
    m = [[v - w for v, w in zip(r, rows_[0])] for r in rows_[1:]]
    rank = 0
    for col in range(3):
        pivot = next((i for i in range(rank, len(m)) if m[i][col] != 0), None)
        if pivot is None:
            continue
        m[rank], m[pivot] = m[pivot], m[rank]
        for i in range(len(m)):
            if i != rank and m[i][col] != 0:
                f = m[i][col] / m[rank][col]
                m[i] = [a - f * b for a, b in zip(m[i], m[rank])]
        rank += 1
    return rank


@given(point_sets(min_size=1, max_size=9))
def test_affine_dimension_and_basis(pts: NDArray[np.float64]) -> None:
    dim = affine_dimension(pts)
    assert dim == _rank(pts)
    basis = Predicates3(pts).affine_basis()
    assert len(basis) == dim + 1
    assert _rank(pts[list(basis)]) == dim


def test_affine_dimension_cases() -> None:
    assert affine_dimension(np.zeros((0, 3))) == -1
    assert affine_dimension([[1.0, 2.0, 3.0]] * 5) == 0
    line = np.array([[t, 2 * t, 1e12 - t] for t in range(50)], dtype=float)
    assert affine_dimension(line) == 1
    big = np.array(list(itertools.product(range(20), range(20), [7.0])))
    assert affine_dimension(big) == 2
    assert affine_dimension(np.vstack([big, [[0.0, 0.0, 7.0 + 2.0**-40]]])) == 3
    p = Predicates3(np.vstack([big, [[0.5, 0.5, 8.0]]]))
    basis = p.affine_basis(order=np.arange(len(big), -1, -1))
    assert basis[0] == len(big) and len(basis) == 4
    assert affine_dimension(p) == 3
    assert p.collinear(0, 1, 2) and not p.collinear(0, 1, 20)


# -- bad input -----------------------------------------------------------------------------------


def test_bad_points_raise_clear_errors() -> None:
    with pytest.raises(ValueError, match="row 2"):
        Predicates3([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [float("nan"), 0.0, 0.0]])
    with pytest.raises(ValueError, match="row 1"):
        Predicates3([[0.0, 0.0, 0.0], [float("inf"), 1.0, 1.0]])
    with pytest.raises(ValueError, match=r"\(n, 3\)"):
        Predicates3(np.zeros((4, 2)))
    with pytest.raises(ValueError, match=r"\(n, 3\)"):
        Predicates3(np.zeros(4))
    with pytest.raises(TypeError):
        Predicates3([["a", "b", "c"]])
    with pytest.raises(TypeError):
        Predicates3(np.zeros((2, 3), dtype=complex))
    with pytest.raises(TypeError):
        Predicates3("points")
    with pytest.raises((TypeError, ValueError)):
        Predicates3([[0, 0, 0], [1, 1]])
    with pytest.raises(ValueError, match="exactly"):
        Predicates3(np.array([[2**53 + 1, 0, 0]], dtype=np.int64))
    exact_big = Predicates3(np.array([[2**60, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], dtype=np.int64))
    assert exact_big.points[0, 0] == 2.0**60
    assert len(Predicates3(np.zeros((3, 3), dtype=np.float32))) == 3


def test_bad_indices_raise_clear_errors() -> None:
    p = Predicates3(np.eye(3).tolist() + [[0.0, 0.0, 0.0]])
    with pytest.raises(IndexError, match="out of range"):
        p.orient3d(0, 1, 2, 4)
    with pytest.raises(IndexError):
        p.orient3d(0, 1, 2, -1)
    with pytest.raises(TypeError, match="integers"):
        p.orient3d(0, 1, 2, 3.0)  # type: ignore[arg-type]  # the point of the test
    with pytest.raises(ValueError, match="distinct"):
        p.orient3d(0, 1, 1, 2)
    assert p.orient3d_sign(0, 1, 1, 2) == 0  # a repeated point is a genuine zero
    with pytest.raises(ValueError, match="distinct"):
        p.orient3d_batch(0, 1, 2, np.array([3, 2] * 20))
    with pytest.raises(TypeError):
        p.orient3d_batch(0, 1, 2, np.array([3.0]))
    with pytest.raises(ValueError, match="1-D"):
        p.orient3d_batch(0, 1, 2, np.array([[3]]))
    with pytest.raises(IndexError):
        p.orient3d_batch(0, 1, 2, np.array([3, 9]))
    with pytest.raises(ValueError, match="lengths"):
        p.orient3d_many([0, 1], [1, 2, 3], 2, 3)
    assert p.orient3d_batch(0, 1, 2, np.array([], dtype=np.intp)).shape == (0,)
