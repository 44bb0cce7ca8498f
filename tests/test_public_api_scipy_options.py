"""scipy's constructor arguments on persistri.ConvexHull and persistri.Delaunay: incremental mode, qhull_options.

Code written for scipy.spatial must run unchanged on persistri's classes, with
the same meaning: the drop-in tests run one function on both modules.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import persistri

scipy_spatial = pytest.importorskip("scipy.spatial")


def _triangles(simplices: np.ndarray) -> set[frozenset[int]]:
    return {frozenset(map(int, t)) for t in simplices}


def _scipy_style_delaunay(module: Any, pts: np.ndarray) -> Any:
    """What scipy's documentation shows for incremental mode: construct, add, add again, close."""
    tri = module.Delaunay(pts[:40], incremental=True)
    tri.add_points(pts[40:90])
    tri.add_points(pts[90:])
    tri.close()
    return tri


def _scipy_style_hull(module: Any, pts: np.ndarray) -> Any:
    hull = module.ConvexHull(pts[:30], True)  # incremental, by position as scipy's signature has it
    hull.add_points(pts[30:])
    hull.close()
    return hull


@pytest.mark.parametrize("seed", range(3))
def test_scipy_incremental_code_runs_unchanged(seed: int) -> None:
    rng = np.random.default_rng(seed)
    pts2 = rng.random((150, 2))
    ours, theirs = _scipy_style_delaunay(persistri, pts2), _scipy_style_delaunay(scipy_spatial, pts2)
    assert ours.npoints == theirs.npoints == 150
    assert _triangles(ours.simplices) == _triangles(theirs.simplices)
    pts3 = rng.standard_normal((120, 3))
    ours_h, theirs_h = _scipy_style_hull(persistri, pts3), _scipy_style_hull(scipy_spatial, pts3)
    assert sorted(ours_h.vertices.tolist()) == sorted(theirs_h.vertices.tolist())
    assert _triangles(ours_h.simplices) == _triangles(theirs_h.simplices)


def test_incremental_delaunay_changes_in_place_and_keeps_its_versions() -> None:
    rng = np.random.default_rng(1)
    pts = rng.random((300, 2))
    tri = persistri.Delaunay(pts[:200], False, True, history=True)  # scipy's positions: furthest_site, incremental
    before, result_before = tri.simplices, tri.result
    assert tri.add_points(pts[200:]) is tri
    assert tri.npoints == 300 and np.array_equal(tri.simplices, persistri.Delaunay(pts).simplices)
    # What was read before is a value: unchanged, and the old version is still there underneath.
    assert before.shape[0] < tri.nsimplex and np.array_equal(before, result_before.triangles)
    assert tri.history is not None and result_before.history is not None
    assert tri.history.versions[: len(result_before.history)] == result_before.history.versions
    tri.close()
    with pytest.raises(RuntimeError, match="closed"):
        tri.add_points([[0.5, 0.5]])
    assert tri.npoints == 300


def test_incremental_hull_changes_in_place() -> None:
    rng = np.random.default_rng(2)
    pts = rng.standard_normal((200, 3))
    hull = persistri.ConvexHull(pts[:100], incremental=True, history=True)
    old = hull.result
    assert hull.add_points(pts[100:]) is hull
    assert hull.npoints == 200 and old.points.shape[0] == 100
    assert sorted(hull.vertices.tolist()) == sorted(persistri.ConvexHull(pts).vertices.tolist())
    hull.close()
    with pytest.raises(RuntimeError, match="closed"):
        hull.add_points(pts[:3])


def test_without_incremental_add_points_returns_new_objects_even_after_close() -> None:
    tri = persistri.Delaunay([[0, 0], [4, 0], [0, 4]])
    tri.close()
    more = tri.add_points([[1, 1]])
    assert more is not tri and (tri.npoints, more.npoints) == (3, 4)
    hull = persistri.ConvexHull(np.eye(3).tolist() + [[0, 0, 0]])
    hull.close()
    assert hull.add_points([[1, 1, 1]]).npoints == 5 and hull.npoints == 4


@pytest.mark.parametrize("incremental", [False, True])
def test_restart_recomputes_the_same_result(incremental: bool) -> None:
    rng = np.random.default_rng(3)
    pts = rng.random((120, 2))
    a = persistri.Delaunay(pts[:80], incremental=incremental, history=True)
    b = persistri.Delaunay(pts[:80], incremental=incremental, history=True)
    cont, fresh = a.add_points(pts[80:]), b.add_points(pts[80:], restart=True)
    assert np.array_equal(cont.simplices, fresh.simplices)
    assert fresh.history is not None and len(fresh.history) == len(cont.history or ())
    pts3 = rng.standard_normal((100, 3))
    h1 = persistri.ConvexHull(pts3[:60], incremental=incremental).add_points(pts3[60:], True)
    assert sorted(h1.vertices.tolist()) == sorted(persistri.ConvexHull(pts3).vertices.tolist())


def test_qhull_options_moot_ones_accepted_others_named() -> None:
    pts = np.random.default_rng(4).random((30, 2))
    for options in ("Qbb Qc Qz Q12", "Qbb Qc Qz Qx Q12", "QJ", "Qt Pp", ""):
        assert persistri.Delaunay(pts, qhull_options=options).nsimplex > 0
    assert persistri.ConvexHull(np.random.default_rng(5).random((20, 3)), False, "Qx").nsimplex > 0
    with pytest.raises(ValueError, match=r"'QG4'.*would change the result"):
        persistri.ConvexHull(np.random.default_rng(5).random((20, 3)), qhull_options="Qt QG4")
    with pytest.raises(ValueError, match=r"'Qu'"):
        persistri.Delaunay(pts, qhull_options="Qbb Qu")
    with pytest.raises(TypeError, match="qhull_options must be a string"):
        persistri.Delaunay(pts, qhull_options=3)  # type: ignore[arg-type]  # deliberately wrong


def test_furthest_site_is_refused_clearly() -> None:
    with pytest.raises(NotImplementedError, match="furthest_site"):
        persistri.Delaunay([[0, 0], [1, 0], [0, 1]], furthest_site=True)
    assert persistri.Delaunay([[0, 0], [1, 0], [0, 1]], False).furthest_site is False


def test_every_public_attribute_of_scipys_objects_exists() -> None:
    rng = np.random.default_rng(6)
    p3, p2 = rng.random((40, 3)), rng.random((40, 2))
    for ours, theirs in (
        (persistri.ConvexHull(p3), scipy_spatial.ConvexHull(p3)),
        (persistri.Delaunay(p2), scipy_spatial.Delaunay(p2)),
    ):
        missing = [a for a in dir(theirs) if not a.startswith("_") and not hasattr(ours, a)]
        assert not missing, f"{type(ours).__name__} lacks scipy's {missing}"
    hull = persistri.ConvexHull(p3)
    assert hull.good is None and scipy_spatial.ConvexHull(p3).good is None
    tri, theirs_tri = persistri.Delaunay(p2), scipy_spatial.Delaunay(p2)
    assert tri.good.dtype == theirs_tri.good.dtype and tri.good.tolist() == theirs_tri.good.tolist()


def test_hull_coplanar_reports_the_merged_duplicates_of_vertices() -> None:
    cube = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
    pts = np.vstack([cube, [[0.5, 0.5, 0.5]], cube[[3]], [[0.5, 0.5, 0.5]]])  # rows 9, 10 repeat rows 3 and 8
    assert persistri.ConvexHull(pts).coplanar.shape == (0, 3)  # scipy's: Qhull keeps them only with Qc
    hull = persistri.ConvexHull(pts, qhull_options="Qc")
    assert hull.duplicates.tolist() == [[9, 3], [10, 8]]
    cop = hull.coplanar
    assert cop.dtype == np.intc and cop.shape == (1, 3)
    row, facet, twin = cop[0].tolist()
    assert (row, twin) == (9, 3) and 3 in hull.simplices[facet].tolist()  # the interior centre's repeat is not listed
    assert persistri.ConvexHull(cube, qhull_options="Qc").coplanar.shape == (0, 3)


def test_find_simplex_takes_scipys_arguments() -> None:
    tri = persistri.Delaunay([[0, 0], [2, 0], [0, 2], [2, 2]])
    q = [[0.5, 0.5], [3.0, 3.0], [2.0, 1.0]]
    exact = tri.find_simplex(q)
    assert exact.tolist()[1] == -1 and exact.tolist()[2] >= 0
    assert np.array_equal(tri.find_simplex(q, bruteforce=True), exact)
    assert np.array_equal(tri.find_simplex(q, False, 0), exact)
    with pytest.raises(ValueError, match="exact"):
        tri.find_simplex(q, tol=1e-9)


@pytest.mark.parametrize(
    "cls, points, instead",
    [
        ("ConvexHull", np.random.default_rng(0).random((20, 2)), r"persistri\.Delaunay\(points\)\.convex_hull"),
        ("ConvexHull", [[0, 0], [1, 0], [0, 1]], r"persistri\.Delaunay\(points\)\.convex_hull"),
        ("Delaunay", np.random.default_rng(0).random((20, 3)), r"persistri\.ConvexHull\(points\)"),
    ],
)
def test_the_other_dimension_says_what_to_use(cls: str, points: object, instead: str) -> None:
    # scipy's two classes take any dimension; persistri's take one each.  The error names the one to use.
    with pytest.raises(ValueError, match=instead):
        getattr(persistri, cls)(points)


def test_the_hint_names_an_exact_hull_of_2d_points() -> None:
    # What the hint sends a user to is right: the 2D hull's edges, the same cycle as scipy's ConvexHull.
    pts = np.random.default_rng(3).random((200, 2))
    edges = persistri.Delaunay(pts).convex_hull
    assert sorted(set(edges.ravel().tolist())) == sorted(scipy_spatial.ConvexHull(pts).vertices.tolist())


def test_qhull_options_that_only_tune_round_off_are_accepted() -> None:
    # (QbB is not among them: scipy's volume, area and equations are then of the input rescaled to a unit cube,
    # and persistri refuses it: tests/test_api_qhull_options.py.)
    pts = np.random.default_rng(0).random((30, 3))
    plain = persistri.ConvexHull(pts)
    for options in ("Qs", "Tv", "Qs Tv Qt"):
        hull = persistri.ConvexHull(pts, qhull_options=options)
        assert hull.simplices.tolist() == plain.simplices.tolist()
        ref = scipy_spatial.ConvexHull(pts, qhull_options=options)  # scipy's hull is unchanged by them too
        assert sorted(map(sorted, ref.simplices.tolist())) == sorted(map(sorted, plain.simplices.tolist()))
