"""Yes/no arguments are True or False (or NumPy's booleans): ``check="no"`` is an error, not a check."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import persistri
from persistri.impl.flags import flag

PTS = np.random.default_rng(0).random((20, 3))

CALLS: dict[str, Any] = {
    "convex_hull check": lambda v: persistri.convex_hull(PTS, check=v),
    "convex_hull history": lambda v: persistri.convex_hull(PTS, history=v),
    "ConvexHull history": lambda v: persistri.ConvexHull(PTS, history=v),
    "delaunay check": lambda v: persistri.delaunay(PTS[:, :2], check=v),
    "Delaunay history": lambda v: persistri.Delaunay(PTS[:, :2], history=v),
}


@pytest.mark.parametrize("call", sorted(CALLS))
@pytest.mark.parametrize("value", ["no", "yes", 1, None, [True]], ids=repr)
def test_a_value_that_is_not_a_bool_is_refused(call: str, value: object) -> None:
    name = call.split()[1]
    with pytest.raises(TypeError, match=rf"^{name} must be True or False, not "):
        CALLS[call](value)


@pytest.mark.parametrize("value", [True, False, np.True_, np.False_])
def test_bools_and_numpy_bools_are_flags(value: object) -> None:
    assert flag("check", value) is bool(value)
    CALLS["convex_hull history"](value)


@pytest.mark.parametrize("value", [-1, 0, 1.5, True])
def test_verify_hull_max_problems_is_a_positive_integer(value: object) -> None:
    hull = persistri.convex_hull(PTS)
    with pytest.raises(ValueError, match="max_problems must be a positive integer"):
        persistri.verify_hull(PTS, hull.simplices, max_problems=value)  # type: ignore[arg-type]
    assert persistri.verify_hull(PTS, hull.simplices, max_problems=np.int64(1)).ok  # type: ignore[arg-type]


@pytest.mark.parametrize(("name", "value"), [("min_angle", True), ("max_area", True), ("min_angle", "30"), ("rounding_ulps", None)])
def test_verify_mesh_bounds_are_real_numbers(name: str, value: object) -> None:
    square = {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]], "segments": [[0, 1], [1, 2], [2, 3], [3, 0]]}
    mesh = persistri.triangulate(square)
    if value is None:  # rounding_ulps has no "None"
        with pytest.raises(TypeError, match="rounding_ulps must be a real number, not NoneType"):
            persistri.verify_mesh(square, mesh.vertices, mesh.triangles, rounding_ulps=None)  # type: ignore[arg-type]
        return
    with pytest.raises(TypeError, match=rf"{name} must be a real number, not {type(value).__name__}"):
        persistri.verify_mesh(square, mesh.vertices, mesh.triangles, **{name: value})  # type: ignore[arg-type]
    assert persistri.verify_mesh(square, mesh.vertices, mesh.triangles, min_angle=np.float64(20)).ok
