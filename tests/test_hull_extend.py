"""extend_hull: adding points to a finished hull — the same hull as a rebuild, structure shared, the old hull intact."""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial import ConvexHull

from persistri.impl.complex.simpcomp import two_complex
from persistri.impl.geometry.predicates import Predicates3, affine_dimension
from persistri.impl.hull import extend as extend_module
from persistri.impl.hull.api import Hull, convex_hull
from persistri.impl.hull.bulldozer import Bulldozer, BulldozerCheckError, all_but
from persistri.impl.hull.distributions import generate
from persistri.impl.hull.extend import extend_hull, locate_in_cones
from persistri.impl.hull.verify import verify_hull


def facets(simplices: np.ndarray) -> set[frozenset[int]]:
    return {frozenset(t) for t in simplices.tolist()}


def oriented(simplices: np.ndarray) -> set[tuple[int, ...]]:
    """Triangles as their rotation starting at the smallest index (orientation kept)."""
    out = set()
    for t in simplices.tolist():
        k = t.index(min(t))
        out.add(tuple(t[k:] + t[:k]))
    return out


def grid(k: int) -> np.ndarray:
    return np.array([[x, y, z] for x in range(k) for y in range(k) for z in range(k)], dtype=float)


def snapshot(hull: Hull) -> dict[str, Any]:
    """Everything observable about a hull, recomputed from its complexes (not its cached arrays)."""
    from persistri.impl.hull.api import _triangles

    assert hull.rows is not None and hull.bulldozed is not None
    out: dict[str, Any] = {
        "complex": oriented(_triangles(hull.structure, hull.complex, hull.rows)),
        "bulldozed": oriented(_triangles(hull.structure, hull.bulldozed, hull.rows)),
        "simplices": hull.simplices.copy(),
        "points": hull.points.copy(),
        "rows": hull.rows.copy(),
        "bulldozed_faces": None if hull.bulldozed_faces is None else hull.bulldozed_faces.copy(),
    }
    if hull.history is not None:
        # A sample of the versions (every one would cost versions × faces): about 40, the first and last included.
        H = hull.history
        sample = sorted({*range(0, len(H), max(1, len(H) // 40)), len(H) - 1})
        out["history"] = [(k, oriented(H.simplices(k)), H.pending(k).tolist()) for k in sample]
    return out


def assert_unchanged(hull: Hull, before: dict[str, Any]) -> None:
    """``snapshot(hull)`` is still ``before``, key by key."""
    after = snapshot(hull)
    for key, value in before.items():
        if isinstance(value, np.ndarray):
            assert np.array_equal(after[key], value), key
        else:
            assert after[key] == value, key


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


# -- the same hull as a rebuild -------------------------------------------------------------------


@pytest.mark.parametrize("dist", ["InBall", "OnSphere", "BordHeavy", "PolHeavy"])
def test_extending_gives_the_hull_of_the_union(dist: str) -> None:
    """General position: the same faces (as row triples, outward) and vertices as the hull of A ∪ B."""
    A = generate(dist, 1500, seed=1)
    B = generate(dist, 700, seed=2) * 1.02
    old = convex_hull(A, seed=3)
    new = extend_hull(old, B)
    union = np.vstack([A, B])
    ref = convex_hull(union, seed=5)
    assert np.array_equal(new.points, union)
    assert oriented(new.simplices) == oriented(ref.simplices)
    assert new.vertices.tolist() == ref.vertices.tolist()
    assert facets(new.simplices) == facets(ConvexHull(union).simplices)
    assert verify_hull(union, new.simplices).ok
    assert new.insertions > old.insertions and new.seed == old.seed and new.backend == old.backend


@pytest.mark.parametrize("labels", ["spatial", "input"])
def test_check_mode_runs_the_appendix_checks_on_the_continuation(labels: str) -> None:
    A = generate("InBall", 300, seed=4)
    B = np.vstack([generate("OnSphere", 150, seed=5) * 1.1, generate("InBall", 100, seed=6) * 0.5])
    old = convex_hull(A, seed=1, labels=labels, check=True)
    new = extend_hull(old, B, check=True)
    assert new.labels == labels
    assert facets(new.simplices) == facets(ConvexHull(np.vstack([A, B])).simplices)


def test_a_chain_of_extensions_is_the_hull_of_everything() -> None:
    parts = [generate("InBall", 400, seed=s) * (1 + 0.05 * s) for s in range(5)]
    hull = convex_hull(parts[0], seed=2)
    for part in parts[1:]:
        hull = extend_hull(hull, part)
    union = np.vstack(parts)
    assert oriented(hull.simplices) == oriented(convex_hull(union).simplices)


def test_every_backend_extends_to_the_same_hull() -> None:
    A, B = generate("OnSphere", 300, seed=1), generate("OnSphere", 200, seed=2) * 1.01
    ref = extend_hull(convex_hull(A, seed=1), B).simplices
    for backend in ["hamt", "assoc_list", "immutables", "pyrsistent"]:
        got = extend_hull(convex_hull(A, seed=1, backend=backend), B)
        assert np.array_equal(got.simplices, ref), backend


def test_the_same_hull_extended_twice_gives_the_same_result() -> None:
    A, B = generate("InBall", 800, seed=1), generate("InBall", 300, seed=2) * 1.1
    old = convex_hull(A, seed=7, history=True)
    a, b = extend_hull(old, B), extend_hull(old, B)
    assert np.array_equal(a.simplices, b.simplices)
    assert a.history is not None and b.history is not None and a.history.inserted == b.history.inserted


# -- rows, duplicates, errors ---------------------------------------------------------------------


def test_duplicates_of_old_and_of_earlier_new_rows_are_merged_and_reported() -> None:
    A = generate("InBall", 100, seed=1)
    old = convex_hull(np.vstack([A, A[:3]]), seed=1)  # rows 100..102 repeat rows 0..2
    assert old.duplicates == ((100, 0), (101, 1), (102, 2))
    fresh = generate("OnSphere", 5, seed=9) * 2.0
    B = np.vstack([A[old.vertices[:4]], fresh, fresh[:2], A[:1]])
    new = extend_hull(old, B)
    n = 103
    expected = [(n + j, int(old.vertices[j])) for j in range(4)] + [(n + 9, n + 4), (n + 10, n + 5), (n + 11, 0)]
    assert new.duplicates == old.duplicates + tuple(expected)
    union = np.vstack([old.points, B])
    assert all(union[r].tolist() == union[rep].tolist() and rep < r for r, rep in new.duplicates)
    assert set(new.vertices.tolist()) == set(convex_hull(union).vertices.tolist())
    assert not set(new.vertices.tolist()) & {r for r, _ in new.duplicates}


@pytest.mark.parametrize(
    ("bad", "exc", "message"),
    [
        (np.array([[0.0, 0.0, 5.0], [1.0, np.nan, 1.0]]), ValueError, "new points: row 1 is not finite"),
        (np.array([[0.0, 0.0, np.inf]]), ValueError, "new points: row 0 is not finite"),
        (np.zeros((4, 2)), ValueError, r"must be an \(n, 3\) array, got shape \(4, 2\)"),
        (np.zeros(3), ValueError, r"must be an \(n, 3\) array, got shape \(3,\)"),
        ("1 2 3", TypeError, "must be an array of real numbers"),
        ([[1, 2, 3], [1, 2]], ValueError, "rectangular"),
        (np.array([[1 + 1j, 0, 0]]), TypeError, "must be real numbers"),
    ],
)
def test_bad_new_points_get_the_clear_errors_of_convex_hull(bad: object, exc: type[Exception], message: str) -> None:
    old = convex_hull(generate("InBall", 50, seed=1))
    before = snapshot(old)
    with pytest.raises(exc, match=message):
        extend_hull(old, bad)  # type: ignore[arg-type]
    after = snapshot(old)
    assert after["complex"] == before["complex"]


def test_hulls_that_cannot_be_continued_are_refused() -> None:
    pts = generate("InBall", 60, seed=1)
    with pytest.raises(ValueError, match="ephemeral complex keeps no old versions"):
        extend_hull(convex_hull(pts, backend="ephemeral"), pts + 1)
    with pytest.raises(ValueError, match="does not record the bulldozer run"):
        extend_hull(dataclasses.replace(convex_hull(pts), tetra=None), pts + 1)
    with pytest.raises(TypeError, match="must be a Hull"):
        extend_hull(pts, pts)  # type: ignore[arg-type]


def test_no_new_points_and_only_interior_ones_give_the_old_hull_back_sharing_everything() -> None:
    A = generate("OnSphere", 2000, seed=3)
    old = convex_hull(A, seed=1, history=True)
    for B in (np.zeros((0, 3)), generate("InBall", 500, seed=4) * 0.9, A[::7]):
        new = extend_hull(old, B)
        assert new.complex is old.complex and new.bulldozed is old.bulldozed
        assert np.array_equal(new.simplices, old.simplices) and new.simplices is not old.simplices
        assert new.insertions == old.insertions and new.points.shape[0] == len(A) + len(B)
        assert new.history is not None and old.history is not None
        assert all(x is y for x, y in zip(new.history.versions, old.history.versions))
        assert len(new.history) == len(old.history)


def test_progress_counts_every_distinct_new_point() -> None:
    old = convex_hull(generate("InBall", 300, seed=1))
    B = generate("InBall", 2500, seed=2) * 1.05
    seen: list[int] = []
    extend_hull(old, np.vstack([B, B[:10]]), progress=seen.append)
    assert sum(seen) == len(B)


# -- structure sharing and persistence -------------------------------------------------------------


def tree_nodes(tree: Any) -> Iterator[Any]:
    """The nodes of one red-black tree ``(colour, left, key, value, right)``."""
    stack = [tree]
    while stack:
        node = stack.pop()
        if node is not None:
            yield node
            stack += [node[1], node[4]]


def test_faces_the_new_points_do_not_touch_are_shared() -> None:
    """A few points beyond one spot of a big hull: every face they leave alone is the same object (its
    datum, the per-vertex lists holding it, the map nodes), and the new version is a few dozen new tree
    nodes, where a rebuild makes every node anew."""
    A = generate("OnSphere", 4000, seed=1)
    old = convex_hull(A, seed=2)
    spot = A[0] / np.linalg.norm(A[0])
    B = spot * 1.02 + generate("InBall", 10, seed=3) * 0.02
    new = extend_hull(old, B)
    S = old.structure
    old_faces = {t: x for t, x in S.items(old.complex)}
    new_faces = {t: x for t, x in S.items(new.complex)}
    common = old_faces.keys() & new_faces.keys()
    assert len(common) > 0.95 * len(old_faces)
    assert all(new_faces[t] is old_faces[t] for t in common)
    old_nodes = {id(node): node for node in tree_nodes(old.complex.rep[1])}
    new_nodes = list(tree_nodes(new.complex.rep[1]))
    made = [node for node in new_nodes if id(node) not in old_nodes]
    assert 0 < len(made) < 0.1 * len(new_nodes)
    # Each vertex's list is the old tuple unless a triangle at that vertex changed.
    changed = {v for t in old_faces.keys() ^ new_faces.keys() for v in t}
    lists_old = {node[2]: node[3] for node in old_nodes.values()}
    for node in new_nodes:
        if node[2] not in changed:
            assert node[3] is lists_old[node[2]]
    rebuilt = convex_hull(np.vstack([A, B]), seed=2)
    assert not {id(n) for n in tree_nodes(rebuilt.complex.rep[1])} & old_nodes.keys()
    assert oriented(new.simplices) == oriented(rebuilt.simplices)


def test_the_old_hull_and_its_history_are_unchanged_by_chains_and_branches() -> None:
    """Thousands of points, extended three times in a chain and twice from the same hull: every array
    recomputed from every kept complex (the old hull's, its bulldozer version, all its history) is as before."""
    A = generate("InBall", 4000, seed=1)
    base = convex_hull(A, seed=4, history=True)
    kept = [(base, snapshot(base))]
    hull = base
    for s in range(3):
        hull = extend_hull(hull, generate("OnSphere", 1500, seed=10 + s) * (1.0 + 0.01 * s))
        kept.append((hull, snapshot(hull)))
    left = extend_hull(base, generate("BordHeavy", 3000, seed=20) * 1.05)
    right = extend_hull(base, generate("OnSphere", 3000, seed=21) * 1.03)
    chained = extend_hull(kept[1][0], generate("InBall", 2000, seed=22) * 1.2)
    for h, snap in kept:
        assert_unchanged(h, snap)
    for h in (left, right, chained):
        assert verify_hull(h.points, h.simplices).ok
        assert h.history is not None and base.history is not None
        assert all(x is y for x, y in zip(h.history.versions, base.history.versions))
    assert snapshot(left)["complex"] != kept[0][1]["complex"]  # the comparison above can see a difference
    # The branches differ from each other and share the old versions.
    assert oriented(left.simplices) != oriented(right.simplices)
    assert facets(left.simplices) == facets(ConvexHull(left.points).simplices)
    assert facets(right.simplices) == facets(ConvexHull(right.points).simplices)


def test_the_history_continues_with_one_version_per_new_insertion() -> None:
    A, B = generate("BordHeavy", 200, seed=2), generate("OnSphere", 100, seed=3) * 1.3
    old = convex_hull(A, seed=3, history=True)
    new = extend_hull(old, B)
    H, O = new.history, old.history
    assert H is not None and O is not None
    assert len(H) == new.insertions + 1 == len(O) + (new.insertions - old.insertions)
    assert H.inserted[: len(O)] == O.inserted and all(r >= len(A) for r in H.inserted[len(O) :])
    # Each new version is the hull of the one before and the point inserted; the old ones read as before.
    for k in range(len(O), len(H)):
        sub = np.array(sorted(set(H.vertices(k - 1).tolist()) | {H.inserted[k]}))
        local = {row: i for i, row in enumerate(sub.tolist())}
        tri = np.vectorize(local.__getitem__)(H.simplices(k))
        assert verify_hull(new.points[sub], tri).ok
    for k in range(len(O)):
        assert np.array_equal(H.simplices(k), O.simplices(k))
    assert H.pending(len(H) - 1).size == 0
    without = extend_hull(convex_hull(A, seed=3), B)
    assert without.history is None and np.array_equal(without.simplices, new.simplices)


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


def test_counts_go_on_into_the_old_hulls_stats() -> None:
    from persistri.impl.stats import Stats

    stats = Stats()
    old = convex_hull(generate("InBall", 500, seed=1), stats=stats)
    tests, created = stats.plane_side_tests, stats.faces_created
    new = extend_hull(old, generate("OnSphere", 100, seed=2) * 1.2)
    assert new.stats is stats and stats.plane_side_tests > tests and stats.faces_created > created


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


# -- locating the new points -----------------------------------------------------------------------


def _cones_by_definition(pred: Predicates3, corners: np.ndarray, queries: np.ndarray) -> np.ndarray:
    c = pred.centre
    assert c is not None
    out = []
    for q in queries.tolist():
        inside = np.ones(len(corners), dtype=bool)
        for i, j in ((0, 1), (1, 2), (2, 0)):
            inside &= pred.orient3d_many(corners[:, i], corners[:, j], c, q) == -1
        (hit,) = np.flatnonzero(inside)
        out.append(hit)
    return np.array(out)


def _located(A: np.ndarray, B: np.ndarray, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    old = convex_hull(A, seed=1)
    assert old.rows is not None and old.tetra is not None and old.bulldozed_faces is not None
    pts = np.vstack([A[old.rows], B])
    pred = Predicates3(pts).with_centroid(*old.tetra)
    corners = old.bulldozed_faces[:, 1:]
    queries = np.arange(len(old.rows), len(pts))
    return locate_in_cones(pred, corners, queries, seed=seed), _cones_by_definition(pred, corners, queries)


@pytest.mark.parametrize("case", ["random", "grid"])
def test_the_walk_finds_the_cone_of_the_definition(case: str) -> None:
    if case == "random":
        A, B = generate("OnSphere", 500, seed=1), generate("InBall", 300, seed=2) * 2
    else:
        A, B = grid(4), grid(6) - 1  # rays through vertices and edges: SoS decides
    got, ref = _located(A, B)
    assert np.array_equal(got, ref)
    other, _ = _located(A, B, seed=9)
    assert np.array_equal(other, ref)  # the random walk's choices do not change the answer


def test_stragglers_are_located_by_every_cone(monkeypatch: pytest.MonkeyPatch) -> None:
    """Walks that do not finish in their rounds (here: none allowed, all from one face) are decided exactly."""
    monkeypatch.setattr(extend_module, "_walk_rounds", lambda h: 0)
    A, B = generate("OnSphere", 200, seed=1), generate("InBall", 100, seed=2) * 3
    got, ref = _located(A, B)
    assert np.array_equal(got, ref)


def test_check_mode_catches_a_wrong_location(monkeypatch: pytest.MonkeyPatch) -> None:
    def misplaced(pred: Predicates3, corners: np.ndarray, queries: np.ndarray, *, seed: int = 0) -> np.ndarray:
        right = locate_in_cones(pred, corners, queries, seed=seed)
        return (right + 1) % len(corners)

    old = convex_hull(generate("InBall", 200, seed=1))
    B = generate("OnSphere", 20, seed=2) * 2
    monkeypatch.setattr(extend_module, "locate_in_cones", misplaced)
    with pytest.raises(BulldozerCheckError, match="not in the cone of face"):
        extend_hull(old, B, check=True)


def test_a_surface_with_a_hole_is_refused() -> None:
    old = convex_hull(generate("InBall", 100, seed=1))
    assert old.rows is not None and old.tetra is not None and old.bulldozed_faces is not None
    pred = Predicates3(old.points[old.rows]).with_centroid(*old.tetra)
    with pytest.raises(BulldozerCheckError, match="not a closed, oriented surface"):
        locate_in_cones(pred, old.bulldozed_faces[1:, 1:], np.array([0]))
