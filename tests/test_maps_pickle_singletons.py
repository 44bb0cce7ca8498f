"""A pickled map structure singleton unpickles as itself, so a pickled complex stays a value of its structure.

Complexes compare their backends by identity (``Family``); pickling a version alone used to unpickle a
*new* ``RedBlackMap()``, and every operation of the hull's own structure then refused the value
(``ForeignComplexError: a value of 2-complex[two; red_black] given to a structure of 2-complex[two; red_black]``).
"""

from __future__ import annotations

import pickle

import pytest

import persistri
import persistri.maps as maps
from persistri.impl.hull.distributions import generate


@pytest.mark.parametrize("name", list(maps.BACKENDS))
def test_a_backend_singleton_unpickles_as_itself(name: str) -> None:
    if name in {"immutables", "pyrsistent"}:
        pytest.importorskip(name)
    S = maps.backend(name)
    assert pickle.loads(pickle.dumps(S)) is S
    m = S.insert(S.insert(S.empty(), 2, "b"), 1, "a")
    S2, m2 = pickle.loads(pickle.dumps((S, m)))
    assert S2 is S and S.listItemsi(m2) == [(1, "a"), (2, "b")]


def test_another_instance_unpickles_as_an_instance_of_its_class() -> None:
    other = maps.RedBlackMap()
    again = pickle.loads(pickle.dumps(other))
    assert type(again) is maps.RedBlackMap and again is not other and again is not maps.red_black


def test_a_pickled_version_is_read_by_the_structure_that_made_it() -> None:
    hull = persistri.convex_hull(generate("InBall", 60, seed=1), seed=1, history=True)
    v = hull.history[5]
    v2 = pickle.loads(pickle.dumps(v))
    S = hull.structure
    assert sorted(S.items(v2)) == sorted(S.items(v))
    face = next(iter(dict(S.items(v2))))
    assert len(list(S.items(S.rem(v2, face)))) == len(list(S.items(v))) - 1


def test_a_value_of_a_lookalike_structure_is_told_apart_in_words() -> None:
    """Two backends of one class print alike; the error says why the complex is still foreign."""
    from persistri.impl.complex.errors import ForeignComplexError
    from persistri.impl.complex.simpcomp import complex_structure

    A, B = complex_structure(2, maps.RedBlackMap()), complex_structure(2, maps.RedBlackMap())
    with pytest.raises(ForeignComplexError, match=r"red_black\] built on other backend objects .* given to a structure"):
        list(B.items(A.new(2)))
