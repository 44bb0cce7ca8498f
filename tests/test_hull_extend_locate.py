"""Locating the new points (:func:`persistri.impl.hull.extend.locate_in_cones`): the cone of Definition 1's ray.

Each new point is located in the cone, from the centre, of the old bulldozed
face its ray leaves through: the walk finds the cone of the definition (random
input, and grids where SoS decides rays through vertices and edges), whatever
its random choices; walks that do not finish are decided exactly; check mode
catches a wrong location, and a surface with a hole is refused.
"""

from __future__ import annotations

import numpy as np
import pytest

from persistri.impl.geometry.predicates import Predicates3
from persistri.impl.hull import extend as extend_module
from persistri.impl.hull.api import convex_hull
from persistri.impl.hull.bulldozer import BulldozerCheckError
from persistri.impl.hull.distributions import generate
from persistri.impl.hull.extend import extend_hull, locate_in_cones

from hull_extend_helpers import grid


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
