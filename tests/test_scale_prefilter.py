"""The interior filter (:mod:`persistri.impl.scale.prefilter`) never drops a hull vertex, and drops most of a ball.

The strong form checked throughout: the hull of the points the filter keeps has exactly the
hull vertices and triangles of all the points (the kept rows keep their order, so the
one-process labelling — Morton order over the same bounding box, ties by row — and with it the
symbolic perturbation are the same): the filter changes the work, never the result.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

import persistri.impl.scale.prefilter as prefilter
from persistri.impl.hull.api import convex_hull
from persistri.impl.hull.distributions import generate
from persistri.impl.hull.errors import DegenerateInputError
from persistri.impl.scale.hull import parallel_hull
from persistri.impl.scale.prefilter import Prefilter, interior_filter

Points = NDArray[np.float64]


def assert_keeps_the_hull(pts: Points, got: Prefilter) -> None:
    """Every vertex kept, and the kept points' hull is the whole hull, triangle for triangle."""
    assert got.points == pts.shape[0]
    assert np.all(np.diff(got.keep) > 0)
    try:
        want = convex_hull(pts)
    except DegenerateInputError:
        assert got.dropped == 0
        return
    assert np.isin(want.vertices, got.keep).all(), "a hull vertex was dropped"
    sub = convex_hull(pts[got.keep])
    assert np.array_equal(got.keep[sub.vertices], want.vertices)
    mapped = got.keep[sub.simplices]
    k = np.argmin(mapped, axis=1)
    mapped = np.take_along_axis(mapped, (k[:, None] + np.arange(3)) % 3, axis=1)
    assert np.array_equal(mapped[np.lexsort(mapped.T[::-1])], want.simplices)


def grid(k: int) -> Points:
    """The k³ integer grid: coplanar faces, collinear edges, a face normal along every axis."""
    return np.array([[x, y, z] for x in range(k) for y in range(k) for z in range(k)], dtype=np.float64)


# --- drops: how many -----------------------------------------------------------------------------------


def test_drops_most_of_a_ball_chunk() -> None:
    pts = generate("InBall", 200_000, 1)
    got = interior_filter(pts)
    assert got.faces > 100
    assert got.dropped > 0.95 * pts.shape[0], got.dropped  # measured: 98.6 %
    assert_keeps_the_hull(pts, got)


def test_drops_most_of_a_cube_and_of_a_gaussian_cloud() -> None:
    rng = np.random.default_rng(5)
    for pts in (rng.random((50_000, 3)), rng.normal(size=(50_000, 3))):
        got = interior_filter(pts)
        assert got.dropped > 0.9 * pts.shape[0], got.dropped
        assert_keeps_the_hull(pts, got)


def test_on_a_sphere_every_vertex_stays() -> None:
    pts = generate("OnSphere", 20_000, 2)
    got = interior_filter(pts)
    want = convex_hull(pts)
    assert np.isin(want.vertices, got.keep).all()
    assert got.dropped <= pts.shape[0] - want.vertices.size
    assert got.faces == 0 and got.dropped == 0  # the sample says nothing would go: no search at all


def test_small_flat_or_failed_inputs_drop_nothing(monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(0)
    assert interior_filter(rng.random((1000, 3))).dropped == 0  # below MIN_POINTS
    flat = np.c_[rng.random((3000, 2)), np.full(3000, 0.5)]
    assert interior_filter(flat).dropped == 0
    collinear = np.outer(rng.random(3000), [1.0, 2.0, 3.0])
    assert interior_filter(collinear).dropped == 0
    # A surface that is not closed is refused: nothing is dropped.
    real = prefilter._surface
    monkeypatch.setattr(prefilter, "_surface", lambda pts, cand: (lambda t: None if t is None else t[1:])(real(pts, cand)))
    got = interior_filter(rng.random((5000, 3)))
    assert got.dropped == 0


def test_closed_oriented_check() -> None:
    tetra = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]], dtype=np.intp)
    assert prefilter._closed_oriented(tetra, 4)
    assert not prefilter._closed_oriented(tetra[:3], 4)
    flipped = tetra.copy()
    flipped[0] = flipped[0][::-1]
    assert not prefilter._closed_oriented(flipped, 4)
    assert not prefilter._closed_oriented(np.concatenate([tetra, tetra]), 4)


# --- never a vertex: degenerate inputs -----------------------------------------------------------------


def test_grids_with_duplicates_keep_every_vertex() -> None:
    rng = np.random.default_rng(1)
    g = grid(14)  # 2,744 points: faces along the axes, so the corner test falls back to eight corners
    pts = np.concatenate([g, g[rng.integers(0, len(g), 800)]])[rng.permutation(len(g) + 800)]
    got = interior_filter(pts)
    assert got.faces > 0 and got.dropped > 0.5 * pts.shape[0]
    assert_keeps_the_hull(pts, got)
    # Every point on the cube's boundary is kept (it is on the filter surface or outside it).
    boundary = np.any((pts == 0) | (pts == 13), axis=1)
    assert np.isin(np.flatnonzero(boundary), got.keep).all()


def test_points_on_the_filter_surface_are_kept() -> None:
    """An octahedron's vertices and many points exactly on its faces and edges, duplicates of its vertices,
    and interior points: only the interior ones may go."""
    rng = np.random.default_rng(2)
    octa = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64) * 64
    # Dyadic barycentric weights (multiples of 1/64 summing to 1): the points are exactly on the faces.
    faces = []
    for sx in (1, -1):
        for sy in (1, -1):
            for sz in (1, -1):
                w = rng.integers(0, 65, size=(400, 2))
                w = w[w.sum(axis=1) <= 64]
                x, y = w[:, 0].astype(np.float64), w[:, 1].astype(np.float64)
                faces.append(np.c_[sx * x, sy * y, sz * (64 - x - y)])
    surface = np.concatenate(faces)
    inside = rng.uniform(-20, 20, size=(4000, 3))
    pts = np.concatenate([octa, surface, octa[[0, 3, 5]], inside])
    pts = pts[rng.permutation(len(pts))]
    got = interior_filter(pts)
    on_surface = np.abs(pts).sum(axis=1) == 64
    assert np.isin(np.flatnonzero(on_surface), got.keep).all()
    assert got.dropped > 0.8 * len(inside)
    assert_keeps_the_hull(pts, got)


def test_coplanar_faces_of_a_box_with_inner_points() -> None:
    rng = np.random.default_rng(3)
    box = rng.integers(0, 9, size=(3000, 3)).astype(np.float64)
    box[:, 0] = np.where(rng.random(3000) < 0.3, rng.choice([0.0, 8.0], size=3000), box[:, 0])
    inner = rng.uniform(0.5, 7.5, size=(3000, 3))
    pts = np.concatenate([box, inner])
    got = interior_filter(pts)
    assert got.dropped > 0
    assert_keeps_the_hull(pts, got)


@settings(max_examples=40, deadline=None)
@given(
    coords=st.lists(st.tuples(*[st.integers(-3, 3)] * 3), min_size=5, max_size=120),
    scale=st.sampled_from([1.0, 2.0**-30, 3.0, 2.0**40]),
)
def test_small_integer_sets_with_the_filter_forced_on(coords: list[tuple[int, int, int]], scale: float) -> None:
    """Tiny degenerate sets, filtered even below MIN_POINTS: grids, ties and duplicates everywhere."""
    pts = np.array(coords, dtype=np.float64) * scale
    assert_keeps_the_hull(pts, interior_filter(pts, min_points=5))


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10**6), n=st.integers(5, 3000))
def test_random_clouds_with_the_filter_forced_on(seed: int, n: int) -> None:
    rng = np.random.default_rng(seed)
    pts = np.round(rng.normal(size=(n, 3)), int(rng.integers(0, 4)))  # rounded: ties and duplicates
    assert_keeps_the_hull(pts, interior_filter(pts, min_points=5))


def test_a_non_convex_surface_still_drops_only_inner_points(monkeypatch: pytest.MonkeyPatch) -> None:
    """The proof does not need Qhull's surface to be convex: a closed surface with a dent drops only points
    strictly inside the hull of its vertices (here: fewer points, never a vertex)."""
    rng = np.random.default_rng(4)
    pts = rng.uniform(-1, 1, size=(20_000, 3))

    def dented(p: Points, cand: NDArray[np.intp]) -> NDArray[np.intp] | None:
        from scipy.spatial import ConvexHull

        # The hull of the candidates, then one vertex moved inward: the star of the candidate nearest the
        # centre replaces the vertex nearest the top, with its triangles kept (still closed and oriented).
        tri = real(p, cand)
        assert tri is not None
        top = int(tri.ravel()[np.argmax(p[tri.ravel(), 2])])
        inner = int(np.argmin(np.linalg.norm(p, axis=1)))
        out = np.where(tri == top, inner, tri)
        ConvexHull(p[np.unique(out)])  # still spans space
        return out

    real = prefilter._surface
    monkeypatch.setattr(prefilter, "_surface", dented)
    monkeypatch.setattr(prefilter, "_WORTH", 0.0)  # search whatever the sample says: the dent cuts deep
    got = interior_filter(pts)
    assert got.dropped > 0
    assert_keeps_the_hull(pts, got)


# --- through parallel_hull ------------------------------------------------------------------------------


def test_parallel_hull_with_the_filter_equals_the_one_process_hull() -> None:
    rng = np.random.default_rng(6)
    ball = generate("InBall", 30_000, 3)
    g = grid(13)
    mixed = np.concatenate([g, g[rng.integers(0, len(g), 500)], rng.uniform(1, 11, size=(3000, 3))])
    mixed = mixed[rng.permutation(len(mixed))]
    for pts, rows in ((ball, 7_500), (mixed, 1_500)):
        want = convex_hull(pts)
        got = parallel_hull(pts, chunk_rows=rows, fan_in=2)
        plain = parallel_hull(pts, chunk_rows=rows, fan_in=2, prefilter=False)
        for h in (got, plain):
            assert np.array_equal(h.simplices, want.simplices)
            assert np.array_equal(h.vertices, want.vertices)
            assert h.duplicates == want.duplicates
        assert sum(c.filtered for c in got.chunks) > 0 and sum(c.filtered for c in plain.chunks) == 0
        assert [c.distinct for c in got.chunks] == [c.distinct for c in plain.chunks]
        if not want.duplicates:
            # Each chunk hull is its block's hull: the same vertices with or without the filter.
            assert [c.kept for c in got.chunks] == [c.kept for c in plain.chunks]
        else:
            # A block's filter also sees its rows that repeat rows of earlier blocks (the chunk hull leaves
            # them out): it may drop a point on the chunk hull that is strictly inside the block's rows' hull.
            assert all(a.kept <= b.kept for a, b in zip(got.chunks, plain.chunks, strict=True))
            assert any(a.kept < b.kept for a, b in zip(got.chunks, plain.chunks, strict=True))
    ball_run = parallel_hull(ball, chunk_rows=7_500)
    assert all(c.filtered > 0.9 * (c.stop - c.start) for c in ball_run.chunks)
