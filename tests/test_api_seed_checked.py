"""A seed that is not a non-negative integer: an error naming ``seed``, not numpy's "expected non-negative integer"."""

from __future__ import annotations

import numpy as np
import pytest

import persistri

PTS = np.random.default_rng(0).random((20, 3))


@pytest.mark.parametrize("make", [lambda s: persistri.ConvexHull(PTS, seed=s), lambda s: persistri.Delaunay(PTS[:, :2], seed=s)])
def test_a_bad_seed_is_named(make: object) -> None:
    with pytest.raises(ValueError, match=r"^seed must be a non-negative integer, got -1$"):
        make(-1)  # type: ignore[operator]
    with pytest.raises(TypeError, match=r"^seed must be an integer, not str$"):
        make("x")  # type: ignore[operator]
    with pytest.raises(TypeError, match=r"^seed must be an integer, not bool$"):
        make(True)  # type: ignore[operator]
    assert make(np.int64(3)).nsimplex > 0  # type: ignore[operator]
