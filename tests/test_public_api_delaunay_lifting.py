"""``persistri.Delaunay``'s float measurements in scipy's shape: ``transform``, the paraboloid lifting, bounds.

``transform`` is checked entry by entry against exact rationals (within 2⁻⁴⁰ relative,
thin triangles included), and used for barycentric
interpolation as scipy users do; ``equations``/``plane_distance`` against the lift's
definition and, away from ties, against the exact ``incircle``.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial import Delaunay as QhullDelaunay

import persistri
from persistri.impl.geometry.barycentric import barycentric_transforms


def exact_inverse(points: np.ndarray, tri: list[int]) -> list[Fraction]:
    """``T⁻¹`` row by row for ``T = [a − c, b − c]``, in rationals."""
    (ax, ay), (bx, by), (cx, cy) = ([Fraction(float(v)) for v in points[i]] for i in tri)
    t00, t01, t10, t11 = ax - cx, bx - cx, ay - cy, by - cy
    det = t00 * t11 - t01 * t10
    return [t11 / det, -t01 / det, -t10 / det, t00 / det]


def assert_close_to_exact(points: np.ndarray, simplices: np.ndarray, transform: np.ndarray) -> None:
    for i, tri in enumerate(simplices.tolist()):
        got = transform[i, :2, :2].ravel().tolist()
        for g, want in zip(got, exact_inverse(points, tri)):
            assert abs(Fraction(g) - want) <= abs(want) * Fraction(1, 2**40), (i, g, float(want))
        assert transform[i, 2].tolist() == points[tri[2]].tolist()


def test_transform_is_within_2_to_the_minus_40_of_exact() -> None:
    pts = np.random.default_rng(4).random((300, 2))
    tri = persistri.Delaunay(pts)
    assert tri.transform.shape == (tri.nsimplex, 3, 2) and tri.transform.dtype == np.float64
    assert not tri.transform.flags.writeable
    assert_close_to_exact(pts, tri.simplices, tri.transform)


def test_thin_triangles_get_their_true_transform() -> None:
    # Nearly collinear points at an offset (inexact differences): the float formula alone is off by ~1e-10 here.
    for bend in (1e-8, 1e-11, 1e-12):
        i = np.arange(12.0)
        x = 1e5 + 0.1 * i
        pts = np.column_stack([x, 1e5 + 0.3 * x + bend * (i - 5.5) ** 2])
        tri = persistri.Delaunay(pts)
        assert np.isfinite(tri.transform).all()
        assert_close_to_exact(pts, tri.simplices, tri.transform)
        a, b, c = (pts[tri.simplices[:, k]] for k in range(3))
        naive = (b[:, 1] - c[:, 1]) / ((a[:, 0] - c[:, 0]) * (b[:, 1] - c[:, 1]) - (b[:, 0] - c[:, 0]) * (a[:, 1] - c[:, 1]))
        assert not np.allclose(naive, tri.transform[:, 0, 0], rtol=2.0**-40, atol=0.0)  # the exact path ran


@given(st.lists(st.tuples(st.integers(-40, 40), st.integers(-40, 40)), min_size=3, max_size=40, unique=True))
def test_transform_on_integer_sets(coords: list[tuple[int, int]]) -> None:
    pts = np.array(coords, dtype=np.float64) * 0.1 + 1e5  # inexact differences at an offset
    try:
        tri = persistri.Delaunay(pts)
    except ValueError:
        return  # collinear: nothing to transform
    assert_close_to_exact(pts, tri.simplices, tri.transform)


def test_barycentric_interpolation_as_scipy_users_write_it() -> None:
    rng = np.random.default_rng(5)
    pts = rng.random((200, 2))
    values = 3.0 * pts[:, 0] - 2.0 * pts[:, 1] + 1.0  # linear: interpolation reproduces it
    xi = rng.random((500, 2)) * 0.9 + 0.05
    for tri in (persistri.Delaunay(pts), QhullDelaunay(pts)):
        k = tri.find_simplex(xi)
        inside = k >= 0
        T = tri.transform[k[inside]]
        b = np.einsum("ijk,ik->ij", T[:, :2], xi[inside] - T[:, 2])
        bary = np.column_stack([b, 1 - b.sum(axis=1)])
        got = (values[tri.simplices[k[inside]]] * bary).sum(axis=1)
        want = 3.0 * xi[inside, 0] - 2.0 * xi[inside, 1] + 1.0
        assert np.allclose(got, want, rtol=0, atol=1e-12)
        assert (bary >= -1e-12).all()


def test_lifting_is_consistent_and_decides_incircle_away_from_ties() -> None:
    rng = np.random.default_rng(6)
    pts = rng.random((150, 2))
    tri = persistri.Delaunay(pts)
    scale, shift = tri.paraboloid_scale, tri.paraboloid_shift
    lifted = tri.lift_points(pts)
    assert lifted.shape == (150, 3)
    assert np.allclose(lifted[:, 2], scale * (pts**2).sum(axis=1) + shift, rtol=1e-15, atol=0)
    assert lifted[:, 2].min() == pytest.approx(0.0, abs=1e-15)
    eq = tri.equations
    assert eq.shape == (tri.nsimplex, 4)
    assert np.allclose(np.linalg.norm(eq[:, :3], axis=1), 1.0) and (eq[:, 2] < 0).all()
    d = tri.plane_distance(pts)
    assert d.shape == (150, tri.nsimplex)
    at_vertices = d[tri.simplices, np.arange(tri.nsimplex)[:, None]]
    assert np.abs(at_vertices).max() < 1e-12  # each triangle's own vertices lie on its plane
    # Every other input point is outside each circumcircle (the triangulation is Delaunay): on or above the plane.
    assert d.max() < 1e-12
    # A triangle's circumcentre is inside its circumcircle: positive distance.
    a, b, c = (pts[tri.simplices[:, k]] for k in range(3))
    centroid = (a + b + c) / 3
    assert (np.diagonal(tri.plane_distance(centroid)) > 0).all()
    assert tri.plane_distance([[0.5, 0.5]]).shape == (1, tri.nsimplex)


def test_bounds_and_scipy_flags() -> None:
    pts = np.random.default_rng(7).random((40, 2)) * [3.0, 5.0] - 1.0
    tri = persistri.Delaunay(pts)
    ref = QhullDelaunay(pts)
    assert tri.min_bound.tolist() == ref.min_bound.tolist()
    assert tri.max_bound.tolist() == ref.max_bound.tolist()
    assert tri.furthest_site is False and ref.furthest_site is False
    assert tri.close() is None
    assert tri.find_simplex([[0.0, 0.0]]).shape == (1,)  # still usable after close, as nothing was released


def test_lifting_rejects_bad_queries_in_one_line() -> None:
    tri = persistri.Delaunay([[0, 0], [1, 0], [0, 1]])
    for bad, kind in (("ab", TypeError), ([[1.0, 2.0, 3.0]], ValueError), ([[np.nan, 0.0]], ValueError), ([[0, 0], [1]], ValueError)):
        with pytest.raises(kind) as info:
            tri.plane_distance(bad)
        assert "\n" not in str(info.value)


def test_barycentric_transforms_of_a_unit_triangle() -> None:
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    out = barycentric_transforms(pts, np.array([[1, 2, 0]]))
    assert out[0].tolist() == [[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]]


@pytest.mark.parametrize("shape", ["unit", "offset", "centred", "tall"])
def test_lifting_and_planes_are_scipys(shape: str) -> None:
    rng = np.random.default_rng(0)
    pts = {"unit": rng.random((60, 2)), "offset": rng.random((60, 2)) * [3, 1] + [5, -2],
           "centred": rng.random((60, 2)) - 0.5, "tall": rng.random((50, 2)) * [1, 10] - [20, 0]}[shape]
    tri, ref = persistri.Delaunay(pts), QhullDelaunay(pts)
    assert tri.paraboloid_scale == pytest.approx(ref.paraboloid_scale, rel=1e-15)
    assert tri.paraboloid_shift == pytest.approx(ref.paraboloid_shift, rel=1e-15)
    q = rng.random((7, 2))
    assert np.allclose(tri.lift_points(q), ref.lift_points(q), rtol=1e-14, atol=0)
    index = {tuple(sorted(t)): i for i, t in enumerate(ref.simplices.tolist())}
    order = [index[tuple(sorted(t))] for t in tri.simplices.tolist()]
    assert np.allclose(tri.equations, ref.equations[order], rtol=1e-9, atol=1e-12)
    assert np.allclose(tri.plane_distance(q), ref.plane_distance(q)[:, order], rtol=1e-9, atol=1e-12)
