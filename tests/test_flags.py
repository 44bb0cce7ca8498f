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
