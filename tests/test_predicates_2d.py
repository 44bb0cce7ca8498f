"""Exact 2D predicates: orient2d and incircle against Fractions, their SoS, batches, counting, errors."""

from __future__ import annotations

import itertools
from fractions import Fraction

import geometry_reference as ref
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numpy.typing import NDArray

from persistri.impl.geometry.filter import FLOPS_INCIRCLE, FLOPS_ORIENT2D
from persistri.impl.geometry.predicates import SMALL_BATCH, Predicates2
from persistri.impl.stats import Stats

# Integer points on the circle x² + y² = 25: twelve cocircular points.
CIRCLE = [(3, 4), (4, 3), (5, 0), (4, -3), (3, -4), (0, -5), (-3, -4), (-4, -3), (-5, 0), (-4, 3), (-3, 4), (0, 5)]


@st.composite
def planar_sets(draw: st.DrawFn, min_size: int = 4, max_size: int = 8) -> NDArray[np.float64]:
    """Small 2D sets rich in degeneracies: grids, lines, circles, duplicates, extreme scales and offsets."""
    n = draw(st.integers(min_size, max_size))
    kind = draw(st.sampled_from(["grid", "circle", "line", "floats", "mixed"]))
    small = st.integers(-3, 3)
    if kind == "grid":
        pts = np.array([[draw(small), draw(small)] for _ in range(n)], dtype=float)
    elif kind == "circle":
        chosen = draw(st.lists(st.sampled_from(CIRCLE), min_size=n - 1, max_size=n - 1))
        pts = np.array(chosen + [(draw(small), draw(small))], dtype=float)
    elif kind == "line":
        pts = np.array([[t, 2 * t + 1] for t in (draw(small) for _ in range(n - 1))] + [[draw(small), draw(small)]], dtype=float)
    elif kind == "floats":
        fl = st.floats(allow_nan=False, allow_infinity=False, min_value=-1e300, max_value=1e300)
        pts = np.array([[draw(fl), draw(fl)] for _ in range(n)], dtype=float)
    else:
        scale = st.sampled_from([1.0, 2.0**-1000, 2.0**997, 1e300, 1e-300])
        pts = np.array([[draw(small) * draw(scale), draw(small) * draw(scale)] for _ in range(n)], dtype=float)
    if kind in ("grid", "circle", "line"):
        pts = pts * draw(st.sampled_from([1.0, 2.0**-1000, 2.0**500, 2.0**-40])) + draw(st.sampled_from([0.0, 1e9, 1e12]))
    if draw(st.booleans()):
        pts = np.vstack([pts, pts[:1]])
    return pts


@given(planar_sets(max_size=7))
def test_orient2d_and_incircle_match_fractions(pts: NDArray[np.float64]) -> None:
    p = Predicates2(pts)
    n = len(pts)
    for a, b, c in itertools.combinations(range(n), 3):
        true = ref.orient(pts, a, b, c)
        assert p.orient2d_sign(a, b, c) == true
        s = p.orient2d(a, b, c)
        assert s in (-1, 1) and (not true or s == true)
        assert p.orient2d(b, a, c) == -s and p.orient2d(a, c, b) == -s and p.orient2d(b, c, a) == s
    for a, b, c, d in itertools.combinations(range(n), 4):
        true = ref.incircle(pts, a, b, c, d)
        assert p.incircle_sign(a, b, c, d) == true
        s = p.incircle(a, b, c, d)
        assert s in (-1, 1) and (not true or s == true)
        assert p.incircle(b, a, c, d) == -s and p.incircle(a, b, d, c) == -s and p.incircle(d, a, b, c) == -s


@given(planar_sets(min_size=6, max_size=6))
def test_batches_equal_scalar(pts: NDArray[np.float64]) -> None:
    p = Predicates2(pts)
    n = len(pts)
    triples = np.array([t for t in itertools.permutations(range(n), 3)][::3], dtype=np.intp)
    got = p.orient2d_many(triples[:, 0], triples[:, 1], triples[:, 2])
    assert got.tolist() == [p.orient2d(*map(int, t)) for t in triples]
    quads = np.array([q for q in itertools.permutations(range(n), 4)][::9], dtype=np.intp)
    assert min(len(triples), len(quads)) >= SMALL_BATCH  # the vectorised path
    got = p.incircle_many(quads[:, 0], quads[:, 1], quads[:, 2], quads[:, 3])
    assert got.tolist() == [p.incircle(*map(int, q)) for q in quads]
    qs = np.array(list(range(3, n)) * 16, dtype=np.intp)
    assert qs.size >= SMALL_BATCH
    assert p.orient2d_batch(0, 1, qs).tolist() == [p.orient2d(0, 1, int(q)) for q in qs]
    assert p.orient2d_sign_batch(0, 1, qs).tolist() == [ref.orient(pts, 0, 1, int(q)) for q in qs]
    assert p.incircle_batch(0, 1, 2, qs).tolist() == [p.incircle(0, 1, 2, int(q)) for q in qs]
    assert p.incircle_sign_batch(0, 1, 2, qs).tolist() == [ref.incircle(pts, 0, 1, 2, int(q)) for q in qs]


def test_orient2d_sos_matches_explicit_perturbation() -> None:
    pts = np.array([[0, 0], [1, 1], [2, 2], [1, 1], [0, 3], [3, 0], [-1, -1]], dtype=float)
    p = Predicates2(pts)
    checked = 0
    for tri in itertools.permutations(range(len(pts)), 3):
        if ref.orient(pts, *tri) == 0:
            assert p.orient2d(*tri) == ref.sos_sign(ref.rows(pts, tri), tri), tri
            checked += 1
    assert checked > 30


def test_incircle_sos_matches_explicit_perturbation_of_the_lift() -> None:
    """Cocircular quadruples: SoS equals the lifted determinant with (x, y, lift) perturbed independently (δ = 3)."""
    pts = np.array(CIRCLE[:6] + [(0, 0), (0, 0)], dtype=float)
    p = Predicates2(pts)
    quads = [q for q in itertools.combinations(range(6), 4)][:8] + [(6, 7, 0, 1), (0, 6, 7, 2)]
    for k, quad in enumerate(quads):
        perm = list(itertools.permutations(quad))[(7 * k) % 24]
        assert ref.incircle(pts, *perm) == 0
        assert p.incircle(*perm) == ref.sos_sign(ref.lifted(pts, perm), perm), perm


def test_incircle_perturbation_restricts_to_the_orient2d_perturbation() -> None:
    """The consistency claim: orient2d's SoS sign equals the projection of the incircle scheme.

    Perturbing x, y with the δ = 3 exponents (as incircle does) and evaluating the
    2D orientation gives the same sign as orient2d's own δ = 2 scheme.
    """
    pts = np.array([[0, 0], [1, 1], [2, 2], [3, 3], [0, 2], [2, 0]], dtype=float)
    p = Predicates2(pts)
    for tri in itertools.permutations(range(4), 3):  # collinear triples
        coords = ref.rows(pts, tri)
        lifted_scheme = _sos_xy_of_delta3(coords, tri)
        assert p.orient2d(*tri) == lifted_scheme == ref.sos_sign(coords, tri)


def _sos_xy_of_delta3(coords: list[list[Fraction]], indices: tuple[int, ...]) -> int:
    """orient2d perturbed with exponents 2^(3r - 1) (x) and 2^(3r - 2) (y): the (x, y) part of the δ = 3 scheme."""
    rank = {i: r + 1 for r, i in enumerate(sorted(indices))}
    big_k = 40
    top = 2 ** (3 * 3 - 1)
    matrix = []
    for (x, y), i in zip(coords, indices):
        r = rank[i]
        matrix.append(
            [
                int(x) * 2 ** (big_k * top) + 2 ** (big_k * (top - 2 ** (3 * r - 1))),
                int(y) * 2 ** (big_k * top) + 2 ** (big_k * (top - 2 ** (3 * r - 2))),
                2 ** (big_k * top),
            ]
        )
    return ref.sign(ref.det(matrix))


def test_counting_and_filter_failures() -> None:
    rng = np.random.default_rng(5)
    pts = rng.random((100, 2))
    stats = Stats()
    p = Predicates2(pts, stats=stats)
    for _ in range(50):
        a, b, c, d = map(int, rng.choice(100, 4, replace=False))
        assert p.orient2d(a, b, c) == ref.orient(pts, a, b, c)
        assert p.incircle(a, b, c, d) == ref.incircle(pts, a, b, c, d)
    assert stats.plane_side_tests == 100
    assert stats.flops == 50 * (FLOPS_ORIENT2D + FLOPS_INCIRCLE)
    assert stats.filter_failures == 0
    cocircular = Predicates2(np.array(CIRCLE, dtype=float), stats=stats)
    stats.reset()
    for quad in itertools.combinations(range(12), 4):
        cocircular.incircle(*quad)
    assert stats.filter_failures == stats.plane_side_tests == 495  # every quadruple is an exact zero
    qs = np.arange(3, 12).repeat(4)
    assert qs.size >= SMALL_BATCH
    cocircular.incircle_batch(0, 1, 2, qs)
    assert stats.filter_failures == stats.plane_side_tests == 495 + qs.size


def test_near_degenerate_orient2d_where_plain_floats_fail() -> None:
    """Kettner et al.'s classroom example: (0.5 + i u, 0.5 + j u) against the line through (12, 12) and (24, 24)."""
    u = 2.0**-53
    pts = [(12.0, 12.0), (24.0, 24.0)] + [(0.5 + i * u, 0.5 + j * u) for i in range(16) for j in range(16)]
    arr = np.array(pts)
    p = Predicates2(arr)
    naive_wrong = 0
    for q in range(2, len(arr)):
        true = ref.orient(arr, q, 0, 1)
        assert p.orient2d_sign(q, 0, 1) == true
        (px, py), (qx, qy), (rx, ry) = (map(float, arr[k]) for k in (q, 0, 1))
        naive = (qx - px) * (ry - py) - (qy - py) * (rx - px)
        naive_wrong += (naive > 0) - (naive < 0) != true
    assert naive_wrong > 0
    batch = p.orient2d_sign_batch(0, 1, np.arange(2, len(arr)))
    assert batch.tolist() == [ref.orient(arr, 0, 1, q) for q in range(2, len(arr))]


def test_bad_input() -> None:
    with pytest.raises(ValueError, match="row 1"):
        Predicates2([[0.0, 0.0], [np.nan, 1.0]])
    with pytest.raises(ValueError, match=r"\(n, 2\)"):
        Predicates2(np.zeros((3, 3)))
    with pytest.raises(TypeError):
        Predicates2([["x", "y"]])
    p = Predicates2([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    with pytest.raises(IndexError):
        p.orient2d(0, 1, 4)
    with pytest.raises(IndexError):
        p.incircle(0, 1, 2, -2)
    with pytest.raises(ValueError, match="distinct"):
        p.incircle(0, 1, 2, 2)
    with pytest.raises(ValueError, match="distinct"):
        p.orient2d(0, 0, 1)
    assert p.incircle_sign(0, 1, 2, 3) == 0  # a square is cocircular
    assert p.orient2d_sign(0, 0, 1) == 0
