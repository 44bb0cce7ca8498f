"""The bulldozer convex hull: agreement with Qhull, exact verification, degenerate and bad input, history."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial import ConvexHull

from persistri.impl.geometry.predicates import affine_dimension
from persistri.impl.hull.api import convex_hull
from persistri.impl.hull.bulldozer import BulldozerCheckError
from persistri.impl.hull.distributions import DISTRIBUTIONS, generate
from persistri.impl.hull.errors import DegenerateInputError
from persistri.impl.hull.verify import verify_hull
from persistri.impl.maps import UnknownBackendError
from persistri.impl.stats import Stats


def facets(simplices: np.ndarray) -> set[frozenset[int]]:
    return {frozenset(t) for t in simplices.tolist()}


def outward(points: np.ndarray, simplices: np.ndarray) -> bool:
    """Every triangle's right-hand normal points away from the centroid of the points (float, generic data)."""
    g = points.mean(axis=0)
    a, b, c = (points[simplices[:, i]] for i in range(3))
    normal = np.cross(b - a, c - a)
    return bool(np.all(np.einsum("ij,ij->i", normal, a - g) > 0))


@pytest.mark.parametrize("dist", sorted(DISTRIBUTIONS))
def test_agrees_with_qhull(dist: str) -> None:
    pts = generate(dist, 400, seed=7)
    hull = convex_hull(pts, seed=1)
    assert facets(hull.simplices) == facets(ConvexHull(pts).simplices)
    assert outward(pts, hull.simplices)
    assert verify_hull(pts, hull.simplices).ok
    assert hull.vertices.tolist() == sorted(set(hull.simplices.ravel().tolist()))


@pytest.mark.parametrize("dist", sorted(DISTRIBUTIONS))
def test_check_mode_asserts_the_theorems(dist: str) -> None:
    pts = generate(dist, 150, seed=3)
    hull = convex_hull(pts, check=True, seed=2)  # raises BulldozerCheckError / HullVerificationError on failure
    assert verify_hull(pts, hull.simplices).ok


@pytest.mark.parametrize("backend", ["red_black", "hamt", "assoc_list", "immutables", "pyrsistent"])
def test_every_backend_gives_the_same_hull(backend: str) -> None:
    pts = generate("InBall", 300, seed=5)
    ref = convex_hull(pts, seed=4)
    got = convex_hull(pts, seed=4, backend=backend)
    assert got.simplices.tolist() == ref.simplices.tolist()


def test_same_seed_same_result_and_seeds_agree_on_the_hull() -> None:
    pts = generate("OnSphere", 300, seed=9)
    a, b, c = convex_hull(pts, seed=11), convex_hull(pts, seed=11), convex_hull(pts, seed=12)
    assert a.simplices.tolist() == b.simplices.tolist()
    assert facets(a.simplices) == facets(c.simplices)  # general position: the hull is unique


@pytest.mark.parametrize("k", [2, 3, 5, 10])
def test_integer_grid_cube(k: int) -> None:
    grid = np.array([[x, y, z] for x in range(k) for y in range(k) for z in range(k)], dtype=float)
    hull = convex_hull(grid, seed=k)
    report = verify_hull(grid, hull.simplices)
    assert report.ok, str(report)
    corners = {i for i, p in enumerate(grid.tolist()) if all(v in (0, k - 1) for v in p)}
    assert corners <= set(hull.vertices.tolist())  # every extreme point is a vertex
    interior = {i for i, p in enumerate(grid.tolist()) if all(0 < v < k - 1 for v in p)}
    assert not interior & set(hull.vertices.tolist())


def test_points_on_a_few_planes_and_coplanar_facet_points() -> None:
    rng = np.random.default_rng(0)
    planes = []
    for z in (0.0, 1.0, 2.5):
        xy = rng.integers(-5, 6, size=(40, 2)).astype(float)
        planes.append(np.column_stack([xy, np.full(40, z)]))
    pts = np.vstack(planes)
    hull = convex_hull(pts, check=True)
    assert verify_hull(pts, hull.simplices).ok


@pytest.mark.parametrize("offset", [1e9, 1e12])
def test_large_offsets_are_exact(offset: float) -> None:
    rng = np.random.default_rng(3)
    pts = rng.random((100, 3)) + offset
    hull = convex_hull(pts)
    assert verify_hull(pts, hull.simplices).ok


def test_tiny_and_mixed_scales_are_exact() -> None:
    rng = np.random.default_rng(4)
    tiny = rng.random((80, 3)) * 1e-300
    assert verify_hull(tiny, convex_hull(tiny).simplices).ok
    mixed = np.vstack([rng.random((30, 3)) * 1e-300, rng.random((30, 3)) * 1e300])
    assert verify_hull(mixed, convex_hull(mixed).simplices).ok


def test_the_first_tetrahedron_at_the_edge_of_the_double_range(monkeypatch: pytest.MonkeyPatch) -> None:
    """Coordinates near ±1e308: the fat first tetrahedron is found by the float heuristic (scaled before
    any difference, so nothing overflows), without the exact greedy fallback."""
    from persistri.impl.geometry.predicates import Predicates3
    from persistri.impl.hull.bulldozer import initial_tetrahedron

    pts = generate("InBall", 200, seed=4) * 1.5e308
    pred = Predicates3(pts)

    def no_fallback(*_: object) -> tuple[int, ...]:
        raise AssertionError("the heuristic tetrahedron should have been found")

    monkeypatch.setattr(Predicates3, "affine_basis", no_fallback)
    tetra = initial_tetrahedron(pred, len(pts))
    monkeypatch.undo()
    assert len(set(tetra)) == 4 and pred.orient3d_sign(*tetra) != 0
    verify_hull(pts, convex_hull(pts).simplices).raise_if_failed()


def test_duplicates_are_merged_and_reported() -> None:
    pts = generate("InBall", 60, seed=1)
    doubled = np.vstack([pts, pts[:10], pts[:1]])
    hull = convex_hull(doubled)
    assert len(hull.duplicates) == 11
    assert all(doubled[r].tolist() == doubled[rep].tolist() and rep < r for r, rep in hull.duplicates)
    assert set(hull.vertices.tolist()) <= set(range(60))
    assert facets(hull.simplices) == facets(convex_hull(pts).simplices)


@pytest.mark.parametrize(
    ("points", "dim"),
    [
        (np.ones((6, 3)), 0),
        (np.outer(np.arange(7.0), [1.0, 2.0, 3.0]), 1),
        (np.column_stack([np.random.default_rng(0).random((9, 2)), np.zeros(9)]), 2),
        (np.eye(3), 2),
        (np.array([[0.0, 0, 0], [1, 0, 0]]), 1),
    ],
)
def test_degenerate_input_names_the_affine_dimension(points: np.ndarray, dim: int) -> None:
    with pytest.raises(DegenerateInputError, match=f"affine dimension {dim}") as err:
        convex_hull(points)
    assert err.value.affine_dimension == dim


@pytest.mark.parametrize(
    ("bad", "exc", "message"),
    [
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, np.nan]], ValueError, "row 3"),
        ([[0, 0, 0], [np.inf, 0, 0], [0, 1, 0], [0, 0, 1]], ValueError, "row 1"),
        (np.zeros((5, 2)), ValueError, r"\(n, 3\)"),
        (np.zeros(6), ValueError, r"\(n, 3\)"),
        ("points", TypeError, "real numbers"),
        ([["a", "b", "c"]] * 4, TypeError, "real"),
        ([[0, 0, 0], [1, 0]], ValueError, "rectangular.*row 1 has 2 entries, not 3"),
        ([[0, 0, 0], 7], ValueError, "rectangular.*row 1 is int, not a row of 3 numbers"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, None]], TypeError, "row 3 holds NoneType None, not a real number"),
        ([[0, 0, 0], [2**53 + 1, 0, 0], [0, 1, 0], [0, 0, 1]], ValueError, "row 1 is not exactly representable"),
        ([[0, 0, 0], [10**400, 0, 0], [0, 1, 0], [0, 0, 1]], ValueError, r"row 1 is not exactly representable as float64: \[1000"),
    ],
)
def test_bad_input_gets_a_clear_error(bad: object, exc: type[Exception], message: str) -> None:
    with pytest.raises(exc, match=message):
        convex_hull(bad)  # type: ignore[arg-type]


def test_python_numbers_beyond_int64_are_taken_exactly() -> None:
    """Big ints and Fractions that a float64 holds exactly are the same points as their floats."""
    from fractions import Fraction

    big = [[0, 0, 0], [2**70, 0, 0], [0, Fraction(2**69, 1), 0], [0, 0, Fraction(2**70, 2)]]
    exact = convex_hull(big)  # type: ignore[arg-type]
    assert exact.simplices.tolist() == convex_hull(np.array(big, dtype=float)).simplices.tolist()


def test_unknown_backend() -> None:
    with pytest.raises(UnknownBackendError, match="known backends"):
        convex_hull(generate("InBall", 10), backend="btree")


@settings(max_examples=40)
@given(arrays(np.int8, st.tuples(st.integers(4, 24), st.just(3)), elements=st.integers(-2, 2)))
def test_small_integer_clouds_are_exact(raw: np.ndarray) -> None:
    pts = raw.astype(float)
    if affine_dimension(pts) < 3:
        with pytest.raises(DegenerateInputError):
            convex_hull(pts)
        return
    hull = convex_hull(pts, check=True)
    report = verify_hull(pts, hull.simplices)
    assert report.ok, str(report)


def test_history_versions_are_the_hulls_of_their_prefixes() -> None:
    pts = generate("BordHeavy", 120, seed=2)
    hull = convex_hull(pts, history=True, seed=3)
    hist = hull.history
    assert hist is not None and len(hist) == hull.insertions + 1
    tetra = list(hist.vertices(0))
    assert len(tetra) == 4
    seen = list(tetra)
    snapshots = [hist.simplices(k) for k in range(len(hist))]
    for k in range(1, len(hist)):
        seen.append(hist.inserted[k])
        sub = np.array(sorted(seen))
        local = {row: i for i, row in enumerate(sub.tolist())}
        tri = np.vectorize(local.__getitem__)(snapshots[k])
        assert verify_hull(pts[sub], tri).ok
        # every pending point of version k is outside it, every other point inside or on it
        pending = set(hist.pending(k).tolist())
        assert pending.isdisjoint(seen)
    # persistence: re-reading every version after the run gives the same triangles
    for k in range(len(hist)):
        assert np.array_equal(hist.simplices(k), snapshots[k])
    assert np.array_equal(hist.simplices(len(hist) - 1), hull.simplices) or hull.slivers_flipped


def test_counts_are_reported() -> None:
    stats = Stats()
    convex_hull(generate("OnSphere", 500, seed=1), stats=stats)
    assert stats.plane_side_tests > 0 and stats.key_comparisons > 0 and stats.dict_ops > 0
    assert stats.flops > stats.plane_side_tests
    assert stats.faces_created - stats.faces_deleted == 2 * 500 - 4  # a sphere with 500 vertices


def test_check_error_type_is_an_assertion() -> None:
    assert issubclass(BulldozerCheckError, AssertionError)


@pytest.mark.parametrize("dist", ["OnSphere", "InBall"])
def test_spatial_and_input_labels_insert_the_same_points(dist: str) -> None:
    """The two labellings insert the same points in the same order: the same hull, version by version."""
    pts = generate(dist, 300, seed=6)
    spatial = convex_hull(pts, seed=2, history=True)
    by_input = convex_hull(pts, seed=2, history=True, labels="input")
    assert spatial.history is not None and by_input.history is not None
    assert spatial.history.inserted == by_input.history.inserted
    for k in range(0, len(spatial.history), 37):
        assert np.array_equal(spatial.history.simplices(k), by_input.history.simplices(k))
    assert np.array_equal(spatial.simplices, by_input.simplices)
    # The labels are different, and Hull.rows maps each to its input row.
    assert by_input.rows is not None and spatial.rows is not None
    assert by_input.rows.tolist() == list(range(300))
    assert sorted(spatial.rows.tolist()) == list(range(300)) and spatial.rows.tolist() != list(range(300))
    for hull in (spatial, by_input):
        assert hull.rows is not None
        labels = np.array([[int(v) for v in t] for t, _ in hull.structure.items(hull.complex)], dtype=np.intp)
        assert facets(hull.rows[labels]) == facets(hull.simplices)


def test_labels_must_be_spatial_or_input() -> None:
    with pytest.raises(ValueError, match="labels must be 'spatial' or 'input'"):
        convex_hull(generate("InBall", 10), labels="hilbert")


def _first_cones(pts: np.ndarray) -> tuple[dict[frozenset[int], list[int]], dict[frozenset[int], list[int]]]:
    """The cones of the first tetrahedron's faces by their definition and by the decision tree."""
    from persistri.impl.complex.simpcomp import two_complex
    from persistri.impl.geometry.predicates import Predicates3
    from persistri.impl.hull.bulldozer import Bulldozer, all_but, initial_tetrahedron
    from persistri.impl.hull.first_hull import cones_by_planes, cones_by_tree

    pred = Predicates3(pts)
    tetra = initial_tetrahedron(pred, len(pts))
    bd = Bulldozer(pred.with_centroid(*tetra), two_complex("red_black", None), tetra)
    others = all_but(len(pts), tetra)
    faces = [tri for tri, _ in bd.faces.values()]
    by_planes = {k: v.tolist() for k, v in cones_by_planes(bd, faces, others).items()}
    by_tree = {k: v.tolist() for k, v in cones_by_tree(bd, tetra, others).items()}
    return by_planes, by_tree


@pytest.mark.parametrize("dist", sorted(DISTRIBUTIONS))
def test_the_first_cones_by_decision_tree_are_the_cones_by_definition(dist: str) -> None:
    """Uncounted runs split the points among the first faces' cones by three tests per point instead of six
    planes per point: the same lists, on random points, on an integer grid (points on the planes through
    the centre: Simulation of Simplicity decides) and on a few points (scalar partitions)."""
    for pts in (generate(dist, 3000, seed=2), generate(dist, 40, seed=3)):
        by_planes, by_tree = _first_cones(pts)
        assert by_planes == by_tree and sum(map(len, by_tree.values())) == len(pts) - 4
    grid = np.stack(np.meshgrid(*[np.arange(7.0)] * 3), axis=-1).reshape(-1, 3)
    by_planes, by_tree = _first_cones(grid)
    assert by_planes == by_tree and sum(map(len, by_tree.values())) == len(grid) - 4


@settings(max_examples=40)
@given(arrays(np.int8, st.tuples(st.integers(5, 80), st.just(3)), elements=st.integers(-3, 3)))
def test_the_first_cones_agree_on_small_integer_clouds(raw: np.ndarray) -> None:
    pts = np.unique(raw.astype(float), axis=0)
    if len(pts) < 5 or affine_dimension(pts) < 3:
        return
    by_planes, by_tree = _first_cones(pts)
    assert by_planes == by_tree


def _first_lists(pts: np.ndarray) -> tuple[list[list[int]], list[list[int]], list[list[int]]]:
    """Each first face's list three ways: its cone by definition partitioned by the face, ``seen_in_cones``
    (whole columns), and the list an uncounted run stored."""
    from persistri.impl.complex.simpcomp import two_complex
    from persistri.impl.geometry.predicates import Predicates3
    from persistri.impl.hull.bulldozer import Bulldozer, all_but, initial_tetrahedron
    from persistri.impl.hull.first_hull import cones_by_planes, seen_in_cones

    pred = Predicates3(pts)
    tetra = initial_tetrahedron(pred, len(pts))
    bd = Bulldozer(pred.with_centroid(*tetra), two_complex("red_black", None), tetra)
    entries = sorted(bd.faces.values(), key=lambda e: e[1][0])
    faces = [tri for tri, _ in entries]
    cones = cones_by_planes(bd, faces, all_but(len(pts), tetra))
    by_definition = [[int(q) for q in bd._partition(*tri, cones[frozenset(tri)])[0]] for tri in faces]
    fast = seen_in_cones(bd, tetra, faces)
    assert fast is not None  # these point sets have the semi-static stage
    stored = [[int(q) for q in datum[1]] for _, datum in entries]
    return by_definition, [lst.tolist() for lst in fast], stored


@pytest.mark.parametrize("dist", sorted(DISTRIBUTIONS))
def test_the_first_lists_over_whole_columns_are_the_cones_seen_by_definition(dist: str) -> None:
    """Uncounted runs give each first face the points of its cone that see it by testing every point against
    the decision tree's planes at once (undecided tests settled exactly where the tree asks them): the same
    lists as the cones by definition partitioned by their faces — on random points, on an integer grid (exact
    zeros on planes through the centre: the undecided path) and on a few points."""
    grid = np.stack(np.meshgrid(*[np.arange(7.0)] * 3), axis=-1).reshape(-1, 3)
    for pts in (generate(dist, 3000, seed=2), generate(dist, 40, seed=3), grid):
        by_definition, fast, stored = _first_lists(pts)
        assert fast == by_definition == stored
        assert sum(map(len, fast)) > 0


@settings(max_examples=40)
@given(arrays(np.int8, st.tuples(st.integers(5, 80), st.just(3)), elements=st.integers(-3, 3)))
def test_the_first_lists_agree_on_small_integer_clouds(raw: np.ndarray) -> None:
    pts = np.unique(raw.astype(float), axis=0)
    if len(pts) < 5 or affine_dimension(pts) < 3:
        return
    by_definition, fast, stored = _first_lists(pts)
    assert fast == by_definition == stored
