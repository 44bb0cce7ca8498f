"""extend_hull on exact arithmetic and SoS (:mod:`persistri.impl.hull.extend`): old tests decided as before.

Simulation of Simplicity depends on the index order and on the exact
coordinates up to a positive scale: new points that change the filter's scale,
the integer scale or the uniformity of the set must not flip the sign of any
old test, ties and tests through the (float or exact) centre included.  So
degenerate input — integer grids split in two, points on the old hull's faces,
edges and vertices, coplanar additions, flipped slivers, far offsets, small
integer clouds — extends to a valid hull that is the unique hull of the
perturbed points of its labelling.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial import ConvexHull

from persistri.impl.complex.simpcomp import two_complex
from persistri.impl.geometry.predicates import Predicates3, affine_dimension
from persistri.impl.hull.api import Hull, convex_hull
from persistri.impl.hull.bulldozer import Bulldozer, all_but
from persistri.impl.hull.distributions import generate
from persistri.impl.hull.extend import extend_hull
from persistri.impl.hull.verify import verify_hull

from hull_extend_helpers import assert_unchanged, facets, grid, oriented, snapshot


# -- exactness: every old test decided as before ----------------------------------------------------


def _quadruples(m: int, centre: int, count: int, seed: int) -> np.ndarray:
    """Random quadruples of distinct indices among ``0 … m-1`` and the centre (index ``centre``)."""
    rng = np.random.default_rng(seed)
    quads = np.array([rng.choice(m + 1, size=4, replace=False) for _ in range(count)])
    quads[quads == m] = centre
    return quads


@pytest.mark.parametrize("added", ["offset", "tiny", "grid", "huge"])
@pytest.mark.parametrize("needle", [False, True])
def test_old_tests_are_decided_identically_over_old_and_new_points(added: str, needle: bool) -> None:
    """SoS depends on the index order and on the exact coordinates up to a positive scale: new points that change
    the filter's scale, the integer scale or the uniformity of the set must not flip a sign — including ties
    (a grid has many), and tests through the centre, float or exact (a needle tetrahedron)."""
    old = grid(5)
    tetra = (0, 1, 5, 25)
    if needle:
        # So thin that the float centroid (z = 5e-324 / 4 rounds to 0) is not strictly inside: the exact one is used.
        old = np.vstack([old, [[0.3, 0.3, 5e-324]]])
        tetra = (0, 25, 5, len(old) - 1)
    new = {
        "offset": generate("InBall", 50, seed=1) + 1e12,
        "tiny": generate("InBall", 50, seed=1) * 1e-300,
        "grid": grid(7) - 1,
        "huge": generate("InBall", 50, seed=1) * 1e300,
    }[added]
    m = len(old)
    p_old = Predicates3(old).with_centroid(*tetra)
    p_new = Predicates3(np.vstack([old, new])).with_centroid(*tetra)
    assert p_old.centre_is_float == p_new.centre_is_float == (not needle)
    assert p_old.points[m].tolist() == p_new.points[m + len(new)].tolist()
    quads = _quadruples(m, m, 3000, seed=2)
    q_new = np.where(quads == m, m + len(new), quads)
    got_old = p_old.orient3d_many(*quads.T)
    got_new = p_new.orient3d_many(*q_new.T)
    assert np.array_equal(got_old, got_new)
    assert [p_old.orient3d(*map(int, q)) for q in quads[:300]] == [p_new.orient3d(*map(int, q)) for q in q_new[:300]]
    assert sum(p_old.orient3d_sign(*map(int, q)) == 0 for q in quads[:300]) > 10  # ties were among them


# -- degenerate input ---------------------------------------------------------------------------------


def perturbed_hull(hull: Hull) -> set[tuple[int, ...]]:
    """The hull of the perturbed points of ``hull``'s labelling, built from scratch by a fresh bulldozer.

    Simulation of Simplicity puts the labelled points in general position, where the hull is unique:
    any correct run over the same labels (and the same centre) must end with exactly these faces.
    """
    assert hull.rows is not None and hull.tetra is not None
    pred = Predicates3(hull.points[hull.rows]).with_centroid(*hull.tetra)
    bd = Bulldozer(pred, two_complex("red_black", None), hull.tetra)
    for _ in bd.run(all_but(len(hull.rows), hull.tetra)):
        pass
    return oriented(hull.rows[bd.triangles()])


def bulldozed_faces(hull: Hull) -> set[tuple[int, ...]]:
    assert hull.rows is not None and hull.bulldozed_faces is not None
    return oriented(hull.rows[hull.bulldozed_faces[:, 1:]])


def check_degenerate(old: Hull, B: np.ndarray) -> Hull:
    """Extend with check=True; the result is valid, has every extreme point as a vertex, and is the hull
    of the perturbed points of its labelling (the unique hull a fresh run over the same labels makes)."""
    new = extend_hull(old, B, check=True)
    union = np.vstack([old.points, B])
    report = verify_hull(union, new.simplices)
    assert report.ok, str(report)
    extreme = set(ConvexHull(union).vertices.tolist())
    reps = dict(new.duplicates)
    assert {reps.get(v, v) for v in extreme} <= set(new.vertices.tolist())
    assert bulldozed_faces(new) == perturbed_hull(new)
    return new


@pytest.mark.parametrize("k", [3, 5])
def test_integer_grids_split_in_two(k: int) -> None:
    g = grid(k)
    rng = np.random.default_rng(k)
    for trial in range(4):
        perm = rng.permutation(len(g))
        cut = int(rng.integers(len(g) // 3, len(g) - 2))
        A, B = g[perm[:cut]], g[perm[cut:]]
        if affine_dimension(A) < 3:
            continue
        check_degenerate(convex_hull(A, seed=trial), B)


def test_points_on_old_faces_edges_and_vertices_and_coplanar_additions() -> None:
    cube = grid(2) * 4.0
    old = convex_hull(cube, seed=1)
    on_faces = np.array([[2.0, 2.0, 0.0], [4.0, 1.0, 3.0], [1.0, 4.0, 1.0]])
    on_edges = np.array([[2.0, 0.0, 0.0], [4.0, 4.0, 1.0], [0.0, 3.0, 4.0]])
    vertices = cube[[0, 3, 7]]
    coplanar = np.array([[x, y, 4.0] for x in (-1.0, 2.0, 5.0) for y in (-1.0, 2.0, 5.0)])  # the top plane, wider
    inside = np.array([[1.0, 2.0, 3.0], [2.0, 2.0, 2.0]])
    for B in (on_faces, on_edges, vertices, np.vstack([on_faces, on_edges, vertices, inside])):
        check_degenerate(old, B)
    new = check_degenerate(old, coplanar)
    assert set(new.vertices.tolist()) >= {8 + j for j in (0, 2, 6, 8)}  # the wider square's corners


def test_a_hull_with_flipped_slivers_continues_from_its_bulldozer_version() -> None:
    """A grid's perturbed hull has zero-area triangles on the cube's edges, flipped away in ``complex``; the run
    continues from ``bulldozed`` (the perturbed hull), and its end is flipped again."""
    old = convex_hull(grid(4), seed=1)
    assert old.slivers_flipped > 0 and old.bulldozed is not old.complex
    before = snapshot(old)
    new = check_degenerate(old, grid(6) * 0.6)  # a finer grid over the same cube: more points on its edges
    assert new.slivers_flipped > 0
    assert_unchanged(old, before)


@pytest.mark.parametrize("offset", [1e12, -3.5e9])
def test_far_offsets(offset: float) -> None:
    A = generate("InBall", 300, seed=1) + offset
    B = np.vstack([generate("OnSphere", 200, seed=2) * 1.01 + offset, grid(3) * 0.25 + offset])
    new = check_degenerate(convex_hull(A, seed=2), B)
    assert facets(new.simplices) == facets(convex_hull(np.vstack([A, B])).simplices)


@settings(max_examples=30, deadline=None)
@given(
    arrays(np.int8, st.tuples(st.integers(5, 30), st.just(3)), elements=st.integers(-2, 2)),
    arrays(np.int8, st.tuples(st.integers(0, 30), st.just(3)), elements=st.integers(-3, 3)),
    st.integers(0, 3),
)
def test_small_integer_clouds_extended_by_small_integer_clouds(raw_a: np.ndarray, raw_b: np.ndarray, seed: int) -> None:
    A, B = raw_a.astype(float), raw_b.astype(float)
    if affine_dimension(A) < 3:
        return
    check_degenerate(convex_hull(A, seed=seed), B)
