"""The red-black map's API boundary (:mod:`persistri.impl.maps.red_black`): errors, values, identity.

The structure matches the ``ORD_MAP`` Protocol (a type-level check, by mypy on
this file).  Keys that cannot be ordered, or not with a map's keys, get a clear
``TypeError`` raised from the public operation and leave the map intact; an
error of ``insertWith``'s ``f`` propagates unchanged (and ``f`` is not called for
an absent key); ``NotFound`` for absent keys; ``insert`` replaces where
``insertWith`` combines; ``SOME None`` is not ``NONE``; the registry names it.
"""

from __future__ import annotations

from typing import Any

import pytest

from persistri.impl.maps import backend
from persistri.impl.maps.red_black import RBMap, RedBlackMap, red_black
from persistri.spec.ord_map import NotFound, OrdMap

from red_black_helpers import check_all, small_int_map

S = red_black

# A type-level check: the structure matches the ORD_MAP Protocol (mypy on this file).
_typed: OrdMap[int, str, RBMap[int, str]] = RedBlackMap[int, str]()


# -- errors -------------------------------------------------------------------------------


def test_unorderable_key_into_empty_map() -> None:
    with pytest.raises(TypeError, match=r"red_black: key <object object at .*> of type object is not orderable"):
        S.singleton(object(), 1)
    with pytest.raises(TypeError, match="red_black: .* not orderable"):
        S.insert(S.empty(), object(), 1)
    with pytest.raises(TypeError, match="red_black: .* not orderable"):
        S.insertWith(lambda a, b: a, S.empty(), 1j, 1)  # complex numbers have no order


@pytest.mark.parametrize(
    "call",
    [
        lambda m: S.insert(m, "a", 0),
        lambda m: S.insertWith(lambda a, b: a, m, "a", 0),
        lambda m: S.find(m, "a"),
        lambda m: S.lookup(m, "a"),
        lambda m: S.inDomain(m, "a"),
        lambda m: S.remove(m, "a"),
        lambda m: S.search_cost(m, "a"),
        lambda m: S.insert(m, object(), 0),
    ],
)
def test_key_of_the_wrong_type(call: Any) -> None:
    m = small_int_map()
    before = S.listItemsi(m)
    with pytest.raises(TypeError, match=r"red_black: key .* is not ordered with the keys of this map") as info:
        call(m)
    # Raised from the public operation, not chained to the comparison deep inside.
    assert info.value.__cause__ is None and info.value.__suppress_context__
    S._check(m)
    assert S.listItemsi(m) == before


def test_insert_with_propagates_errors_of_f_unchanged() -> None:
    m = small_int_map()

    def f(old: int, new: int) -> int:
        raise TypeError("f says no")

    with pytest.raises(TypeError, match="^f says no$"):
        S.insertWith(f, m, 3, 0)
    # Absent key: f is not called.
    assert S.lookup(S.insertWith(f, m, 4, 0), 4) == 0


def test_not_found() -> None:
    m = small_int_map()
    with pytest.raises(NotFound):
        S.remove(m, 4)
    with pytest.raises(NotFound):
        S.remove(S.empty(), 4)
    with pytest.raises(KeyError):
        S.lookup(m, 4)
    S._check(m)
    assert S.listKeys(m) == [1, 3, 5, 9]


def test_insert_replaces_and_insert_with_combines() -> None:
    m = small_int_map()
    m2 = S.insert(m, 3, 30)
    assert S.numItems(m2) == 4 and S.lookup(m2, 3) == 30 and S.lookup(m, 3) == 3
    m3 = S.insertWith(lambda old, new: old + new, m2, 3, 1)
    assert S.lookup(m3, 3) == 31 and S.numItems(m3) == 4
    m4 = S.insertWith(lambda old, new: old + new, m3, 4, 1)
    assert S.lookup(m4, 4) == 1 and S.numItems(m4) == 5
    for x in (m, m2, m3, m4):
        check_all(x)


def test_none_values_are_present() -> None:
    m = S.singleton(1, None)
    assert S.find(m, 1) == (None,)
    assert S.find(m, 2) is None


def test_identity() -> None:
    assert backend("red_black") is red_black
    assert repr(red_black) == "red_black" == red_black.name
    assert red_black.Key.compare(1, 2).name == "LESS"
