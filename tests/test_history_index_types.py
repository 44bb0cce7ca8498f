"""``history[k]`` and ``history.simplices(k)`` with a ``k`` that is not an integer: one plain TypeError.

``history["a"]`` used to fail inside the range check ("'<=' not supported between 'int' and 'str'").
"""

from __future__ import annotations

import numpy as np
import pytest

import persistri
from persistri.impl.hull.distributions import generate


@pytest.fixture(scope="module")
def history() -> persistri.impl.hull.api.HullHistory:
    hull = persistri.convex_hull(generate("InBall", 60, seed=1), seed=1, history=True)
    assert hull.history is not None
    return hull.history


@pytest.mark.parametrize(("k", "name"), [("a", "str"), (1.0, "float"), (None, "NoneType")])
def test_a_non_integer_index_is_named(history: persistri.impl.hull.api.HullHistory, k: object, name: str) -> None:
    with pytest.raises(TypeError, match=rf"^history indices must be integers or slices, not {name}$"):
        history[k]  # type: ignore[index]
    with pytest.raises(TypeError, match=rf"not {name}$"):
        history.simplices(k)  # type: ignore[arg-type]


def test_integers_of_any_kind_index(history: persistri.impl.hull.api.HullHistory) -> None:
    assert history[np.int64(2)] is history[2]
    assert history[-1] is history[len(history) - 1]
    with pytest.raises(IndexError, match=r"version 99 of a history of \d+ versions"):
        history[99]
