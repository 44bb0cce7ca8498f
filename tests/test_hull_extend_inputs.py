"""extend_hull's inputs (:mod:`persistri.impl.hull.extend`): rows, duplicates, errors, nothing new.

The new points' rows follow the old ones; duplicates of old rows and of earlier
new rows are merged and reported as convex_hull reports them; bad new points
get convex_hull's clear errors and leave the old hull as it was; hulls that
cannot be continued (ephemeral, or without their bulldozer run) are refused; no
new points, or only interior ones, give the old hull back sharing everything;
progress counts every distinct new point.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from persistri.impl.hull.api import convex_hull
from persistri.impl.hull.distributions import generate
from persistri.impl.hull.extend import extend_hull

from hull_extend_helpers import snapshot


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
