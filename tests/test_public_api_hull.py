"""``persistri.ConvexHull``: scipy.spatial's attributes, checked against Qhull and against exact rationals."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial import ConvexHull as QhullHull

import persistri
from persistri.impl.complex.adjacency import triangle_neighbors
from persistri.impl.hull.distributions import generate
from persistri.impl.hull.measures import enclosed_volume, facet_equations, facet_normals, surface_area

U = 2.0**-53


def facet_keys(simplices: np.ndarray) -> list[frozenset[int]]:
    return [frozenset(t) for t in simplices.tolist()]


def exact_cross(points: np.ndarray, tri: list[int]) -> tuple[Fraction, Fraction, Fraction]:
    a, b, c = ([Fraction(float(v)) for v in points[i]] for i in tri)
    u = [q - p for p, q in zip(a, b)]
    v = [q - p for p, q in zip(a, c)]
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def exact_volume(points: np.ndarray, simplices: np.ndarray) -> Fraction:
    """The sum of the signed tetrahedra (origin, face), each a 3×3 determinant in Fractions, over 6."""
    total = Fraction(0)
    for tri in simplices.tolist():
        a, b, c = ([Fraction(float(v)) for v in points[i]] for i in tri)
        total += (
            a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])
        )
    return total / 6


def unit(v: tuple[Fraction, Fraction, Fraction]) -> np.ndarray:
    """The exact vector's direction, rounded: each component to 64 leading bits, then normalised (reference)."""
    big = max(abs(x) for x in v)
    f = [float(x / big) for x in v]
    n = math.hypot(*f)
    return np.array([x / n for x in f])


# -- agreement with Qhull on general-position input ------------------------------------------------


@pytest.mark.parametrize("dist", ["InBall", "OnSphere", "EqHeavy", "PolHeavy", "BordHeavy"])
def test_agrees_with_qhull(dist: str) -> None:
    pts = generate(dist, 500, seed=11)
    ours = persistri.ConvexHull(pts, seed=3)
    ref = QhullHull(pts)
    assert ours.vertices.tolist() == sorted(ref.vertices.tolist())
    assert set(facet_keys(ours.simplices)) == set(facet_keys(ref.simplices))
    assert ours.volume == pytest.approx(ref.volume, rel=1e-12)
    assert ours.area == pytest.approx(ref.area, rel=1e-12)
    # The facet equations, matched facet by facet: Qhull's normals are outward and unit too.
    at = {k: i for i, k in enumerate(facet_keys(ref.simplices))}
    match = np.array([at[k] for k in facet_keys(ours.simplices)])
    np.testing.assert_allclose(ours.equations[:, :3], ref.equations[match, :3], rtol=0, atol=1e-12)
    np.testing.assert_allclose(ours.equations[:, 3], ref.equations[match, 3], rtol=0, atol=1e-12)
    # The neighbours, matched the same way: across the edge opposite the same vertex, the same facet.
    for i, tri in enumerate(ours.simplices.tolist()):
        r = match[i]
        for j, v in enumerate(tri):
            k = ours.neighbors[i, j]
            rj = ref.simplices[r].tolist().index(v)
            assert match[k] == ref.neighbors[r, rj]
    assert ours.min_bound.tolist() == ref.min_bound.tolist() == pts.min(axis=0).tolist()
    assert ours.max_bound.tolist() == ref.max_bound.tolist() == pts.max(axis=0).tolist()
    assert ours.close() is None and ours.add_points([[0.0, 0.0, 0.0]]).npoints == 501


def test_arrays_have_scipys_shapes_and_dtypes_and_are_values() -> None:
    pts = generate("InBall", 200, seed=1)
    hull = persistri.ConvexHull(pts)
    ref = QhullHull(pts)
    m = hull.nsimplex
    assert (hull.npoints, hull.ndim) == (200, 3) and m == len(ref.simplices)
    for name, shape in (("simplices", (m, 3)), ("neighbors", (m, 3)), ("vertices", (len(ref.vertices),))):
        arr = getattr(hull, name)
        assert arr.dtype == getattr(ref, name).dtype == np.intc and arr.shape == shape, name
    assert hull.points.dtype == np.float64 and hull.points.shape == (200, 3)
    assert hull.equations.dtype == np.float64 and hull.equations.shape == (m, 4)
    assert hull.duplicates.shape == (0, 2) and hull.duplicates.dtype == np.intc
    for arr in (hull.points, hull.simplices, hull.vertices, hull.neighbors, hull.equations, hull.duplicates):
        with pytest.raises(ValueError, match="read-only"):
            arr[0] = 0
    with pytest.raises(AttributeError):
        hull.volume = 1.0  # type: ignore[misc]
    assert np.array_equal(hull.points, pts)
    assert "200 points" in repr(hull) and "backend='red_black'" in repr(hull)


def test_neighbors_are_the_triangles_across_each_edge() -> None:
    hull = persistri.ConvexHull(generate("OnSphere", 300, seed=2))
    s, nb = hull.simplices, hull.neighbors
    for i in range(hull.nsimplex):
        for j in range(3):
            k = int(nb[i, j])
            u, w = int(s[i, (j + 1) % 3]), int(s[i, (j + 2) % 3])
            row = s[k].tolist()
            # k holds the reversed edge (w, u), and i is k's neighbour across it.
            p = row.index(w)
            assert row[(p + 1) % 3] == u
            assert nb[k, (p + 2) % 3] == i


# -- the exact hull's measures ---------------------------------------------------------------------


def test_equations_are_outward_and_every_point_inside() -> None:
    pts = generate("EqHeavy", 400, seed=5)
    hull = persistri.ConvexHull(pts)
    eq = hull.equations
    side = eq[:, :3] @ pts.T + eq[:, 3:]
    # On or inside every plane: the vertices on their own facets are 0 up to the offset's rounding.
    assert side.max() <= 8 * U * np.abs(pts).max()
    assert np.allclose(np.linalg.norm(eq[:, :3], axis=1), 1.0, rtol=0, atol=4 * U)
    centroid = pts[hull.vertices].mean(axis=0)
    assert np.all(eq[:, :3] @ centroid + eq[:, 3] < 0)


@pytest.mark.parametrize("offset", [0.0, 1e9, 1e12])
def test_normals_are_the_exact_directions(offset: float) -> None:
    """Far from the origin the edge vectors cancel; each normal still matches the exact rational one."""
    rng = np.random.default_rng(4)
    pts = rng.random((300, 3)) + offset
    hull = persistri.ConvexHull(pts)
    normals, lengths = facet_normals(pts, hull.simplices)
    for i, tri in enumerate(hull.simplices.tolist()):
        exact = exact_cross(pts, tri)
        np.testing.assert_allclose(normals[i], unit(exact), rtol=0, atol=2.0**-43)
        assert lengths[i] == pytest.approx(math.sqrt(float(sum(x * x for x in exact))), rel=2.0**-43)
    np.testing.assert_array_equal(hull.equations[:, :3], normals)


def test_needle_triangles_take_the_exact_path() -> None:
    """A triangle almost degenerate (two vertices 2^-40 apart, far from the third) gets its exact normal."""
    eps = 2.0**-40
    pts = np.array([[0, 0, 0], [1, 0, 0], [1, eps, 0], [0, 0, 1], [0.5, 0.5, -1]], dtype=float)
    hull = persistri.ConvexHull(pts)
    normals, _ = facet_normals(pts, hull.simplices)
    for i, tri in enumerate(hull.simplices.tolist()):
        np.testing.assert_allclose(normals[i], unit(exact_cross(pts, tri)), rtol=0, atol=2.0**-43)
    assert verify_ok(pts, hull)


def verify_ok(pts: np.ndarray, hull: persistri.ConvexHull) -> bool:
    return persistri.verify_hull(pts, hull.simplices).ok


def test_volume_is_exact_where_qhull_is_not() -> None:
    """At 1e12 the float volume loses digits (Qhull's is off in the fourth); persistri's is the exact one, rounded."""
    rng = np.random.default_rng(1)
    pts = rng.random((100, 3)) + 1e12
    hull = persistri.ConvexHull(pts)
    exact = exact_volume(pts, hull.simplices)
    assert hull.volume == float(exact)
    assert abs(QhullHull(pts).volume - float(exact)) > 1e-6  # Qhull, same input: wrong in the fourth digit
    # A unit cube far out: exact answers, where Qhull fails altogether at 1e15.
    cube = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float) + 1e15
    far = persistri.ConvexHull(cube)
    assert (far.volume, far.area) == (1.0, 6.0)


def test_volume_and_area_of_known_solids() -> None:
    tetra = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    t = persistri.ConvexHull(tetra)
    assert t.volume == 1 / 6
    assert t.area == pytest.approx(1.5 + math.sqrt(3) / 2, rel=4 * U)
    # Tiny and huge scales: the volume is exact at any binade (no underflow, no overflow in between).
    assert persistri.ConvexHull(tetra * 2.0**-300).volume == 2.0**-900 / 6
    assert persistri.ConvexHull(tetra * 2.0**300).volume == 2.0**900 / 6
    assert persistri.ConvexHull(tetra * 2.0**400).volume == math.inf  # the true value exceeds every double


@given(st.lists(st.tuples(*(st.integers(-4, 4),) * 3), min_size=4, max_size=40))
def test_integer_clouds(coords: list[tuple[int, int, int]]) -> None:
    """Degenerate integer sets (coplanar faces, collinear edges, duplicates): exact volume, closed adjacency."""
    pts = np.array(coords, dtype=float)
    try:
        hull = persistri.ConvexHull(pts)
    except ValueError as exc:
        assert "no 3D convex hull" in str(exc)  # flat sets: one line, naming why
        return
    assert hull.volume == float(exact_volume(pts, hull.simplices)) > 0
    assert (hull.neighbors >= 0).all()
    assert np.array_equal(hull.neighbors, triangle_neighbors(hull.simplices))
    dup = hull.duplicates
    for row, first in dup.tolist():
        assert first < row and coords[first] == coords[row] and row not in hull.vertices
    assert hull.area == pytest.approx(QhullHull(np.unique(pts, axis=0)).area, rel=1e-12)


def test_measures_reject_bad_arrays() -> None:
    pts = np.zeros((4, 3))
    for bad in (np.zeros((2, 2), dtype=int), np.array([[0, 1, 2.5]]), np.array([[0, 1, 4]])):
        with pytest.raises(ValueError, match="simplices"):
            facet_equations(pts, bad)
        with pytest.raises(ValueError, match="simplices"):
            enclosed_volume(pts, bad)
    assert surface_area(pts, np.zeros((0, 3), dtype=int)) == 0.0 and enclosed_volume(pts, np.zeros((0, 3), dtype=int)) == 0.0
    normals, lengths = facet_normals(pts, np.array([[0, 1, 2]]))  # a zero-area triangle has no normal
    assert np.isnan(normals).all() and lengths.tolist() == [0.0]


# -- arguments, errors, history ----------------------------------------------------------------------


def test_errors_are_the_deep_apis_one_line() -> None:
    with pytest.raises(ValueError, match=r"must be an \(n, 3\) array, got shape \(4, 2\)"):
        persistri.ConvexHull(np.zeros((4, 2)))
    with pytest.raises(ValueError, match="row 1 is not finite"):
        persistri.ConvexHull(np.array([[0, 0, 0], [np.nan, 0, 0], [0, 1, 0], [0, 0, 1]]))
    with pytest.raises(ValueError, match="coplanar|affine dimension 2"):
        persistri.ConvexHull([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    with pytest.raises(TypeError, match="real numbers"):
        persistri.ConvexHull(np.array([["a", "b", "c"]] * 4))
    with pytest.raises(FileNotFoundError, match="No such file or directory: 'points'"):
        persistri.ConvexHull("points")  # a string is the path of a file of points (chunked input)
    with pytest.raises(ValueError, match="unknown map backend 'btree'"):
        persistri.ConvexHull(generate("InBall", 10, seed=0), backend="btree")
    with pytest.raises(TypeError, match="needs a persistri Hull"):
        persistri.ConvexHull.from_hull("hull")  # type: ignore[arg-type]


def test_history_backend_seed_and_the_deep_result() -> None:
    pts = generate("OnSphere", 120, seed=3)
    stats = persistri.Stats()
    hull = persistri.ConvexHull(pts, history=True, backend="hamt", seed=5, stats=stats, check=True)
    assert hull.history is not None and len(hull.history) == hull.result.insertions + 1
    assert hull.result.slivers_flipped == 0  # points on a sphere: the last version is the final hull
    assert np.array_equal(hull.history.simplices(len(hull.history) - 1), hull.simplices)
    assert hull.backend == "hamt" and hull.seed == 5 and stats.dict_ops > 0
    assert hull.result.backend == "hamt"
    assert persistri.ConvexHull(pts).history is None
    again = persistri.ConvexHull.from_hull(persistri.convex_hull(pts, seed=5, backend="hamt"))
    assert np.array_equal(again.simplices, hull.simplices)
    assert "history of" in repr(hull)


def test_duplicates_are_reported_as_an_array() -> None:
    pts = np.vstack([generate("EqHeavy", 30, seed=1), generate("EqHeavy", 30, seed=1)[:3]])
    hull = persistri.ConvexHull(pts)
    assert hull.duplicates.tolist() == [[30, 0], [31, 1], [32, 2]]


# -- add_points: a new hull, the old one unchanged ---------------------------------------------------


def test_add_points_returns_a_new_hull_and_keeps_the_old_one() -> None:
    first = generate("InBall", 200, seed=8)
    more = generate("InBall", 100, seed=9) * 1.2
    old = persistri.ConvexHull(first, history=True)
    before = (old.simplices.copy(), old.vertices.copy(), old.volume, old.area, len(old.history or ()))
    new = old.add_points(more)
    assert isinstance(new, persistri.ConvexHull) and new is not old
    # The old hull is exactly what it was.
    assert np.array_equal(old.simplices, before[0]) and np.array_equal(old.vertices, before[1])
    assert (old.volume, old.area, len(old.history or ())) == before[2:]
    # The new one is the hull of both sets, rows numbered old first.
    both = np.vstack([first, more])
    fresh = persistri.ConvexHull(both)
    assert np.array_equal(new.points, both)
    assert new.vertices.tolist() == fresh.vertices.tolist()
    assert set(facet_keys(new.simplices)) == set(facet_keys(fresh.simplices))
    assert new.volume == fresh.volume
    assert persistri.verify_hull(both, new.simplices).ok
    # Its history continues the old one's: the same version objects, then one per new insertion.
    assert new.history is not None and old.history is not None
    assert len(new.history) > len(old.history)
    assert all(a is b for a, b in zip(new.history.versions, old.history.versions))


def test_add_points_inside_shares_the_whole_complex() -> None:
    old = persistri.ConvexHull(generate("OnSphere", 150, seed=1))
    new = old.add_points(generate("InBall", 40, seed=2) * 0.5)
    assert new.result.complex is old.result.complex
    assert np.array_equal(new.simplices, old.simplices) and new.npoints == 190


def test_add_points_errors_name_the_new_rows() -> None:
    old = persistri.ConvexHull(generate("InBall", 50, seed=1))
    with pytest.raises(ValueError, match="row 1 is not finite"):
        old.add_points([[0.0, 0.0, 0.0], [np.inf, 0.0, 0.0]])
    with pytest.raises(ValueError, match=r"\(n, 3\)"):
        old.add_points(np.zeros((2, 2)))


def test_area_beyond_the_largest_double_is_inf_not_an_overflow_error() -> None:
    pts = np.random.default_rng(3).random((20, 3)) * 1e154
    hull = persistri.ConvexHull(pts)
    assert hull.area == float("inf") and hull.volume == float("inf")
    # Near the edge: the area (2.37 a²) fits in a double, the sum of the lengths (twice it) does not.
    big = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float) * 7.5e153
    assert np.isfinite(persistri.ConvexHull(big).area)
