"""The HAMT map's API boundary (:mod:`persistri.impl.maps.hamt`): errors, the listing, identity.

An exception from ``insertWith``'s ``f`` propagates unchanged and leaves the
map intact; unhashable and unorderable keys get a clear ``TypeError`` from the
public operation, keys not ordered with a map's keys are reported where they
are ordered, and a failed insert leaves the version as it was.  The listing is
in key order although the trie is in hash order; the structure is registered
as ``hamt`` and ``SOME None`` is not ``NONE``.
"""

from __future__ import annotations

import random
from collections.abc import Callable
from typing import Any

import pytest

from persistri.impl.maps import backend
from persistri.impl.maps.hamt import HamtMap, HMap, hamt
from persistri.spec.order import NATURAL_ORDER

from hamt_helpers import P, HKey, build, combine


# -- an exception from insertWith's f ----------------------------------------------------


def test_insert_with_exception_leaves_the_map() -> None:
    """An exception from ``f`` propagates unchanged; the map passed in is intact (f is called once)."""
    m = build([(k, k) for k in range(500)])
    calls: list[int] = []

    def boom(old: int, new: int) -> int:
        calls.append(old)
        raise LookupError("from f")

    for k in (3, 499, 256):
        with pytest.raises(LookupError, match="from f"):
            hamt.insertWith(boom, m, k, 0)
    assert calls == [3, 499, 256]
    hamt._check(m)
    assert hamt.listItemsi(m) == [(k, k) for k in range(500)]
    assert hamt.insertWith(boom, m, 1000, 7).size == 501  # absent: f is not called


# -- the API boundary --------------------------------------------------------------


@pytest.mark.parametrize(
    "call",
    [
        lambda m: hamt.insert(m, [1], 0),
        lambda m: hamt.insertWith(combine, m, [1], 0),
        lambda m: hamt.find(m, [1]),
        lambda m: hamt.lookup(m, [1]),
        lambda m: hamt.inDomain(m, [1]),
        lambda m: hamt.remove(m, [1]),
        lambda m: hamt.singleton([1], 0),
        lambda m: hamt.search_cost(m, [1]),
    ],
)
def test_unhashable_key_is_a_clear_type_error(call: Callable[[HMap[Any, Any]], object]) -> None:
    m = build([(1, 1)])
    with pytest.raises(TypeError, match=r"hamt: key \[1\] of type list is not hashable") as info:
        call(m)
    assert info.value.__cause__ is None and info.value.__suppress_context__


def test_unorderable_keys() -> None:
    o = object()
    makers: list[Callable[[], object]] = [lambda: hamt.singleton(o, 1), lambda: hamt.insert(build([(1, 1)]), o, 1)]
    for make in makers:
        with pytest.raises(TypeError, match="hamt: key .* of type object is not orderable"):
            make()
    # Replacing a present key skips the check (the key was checked when it came in).
    assert hamt.find(hamt.insert(build([(1, 1)]), 1, 2), 1) == (2,)


def test_keys_not_mutually_ordered() -> None:
    """Keys that order among themselves but not with each other: reported where they are ordered."""
    m = build([(1, 1), ("a", 2)])
    hamt._check(m)
    for call in (hamt.listItemsi, hamt.listKeys, lambda m: hamt.foldli(lambda k, v, acc: acc, 0, m)):
        with pytest.raises(TypeError, match="hamt: the keys of this map are not mutually ordered"):
            call(m)

    class Other:
        def __lt__(self, other: object) -> bool:
            if not isinstance(other, Other):
                return NotImplemented
            return False

        def __hash__(self) -> int:
            return 0

    c = build([(HKey(1, 0), 1)])
    with pytest.raises(TypeError, match="is not ordered with the keys of this map"):
        hamt.insert(c, Other(), 2)
    c2 = build([(HKey(1, 0), 1), (HKey(2, 0), 2)])
    with pytest.raises(TypeError, match="is not ordered with the keys of this map"):
        hamt.insert(c2, Other(), 3)
    hamt._check(c2)  # a failed insert leaves the version intact


# -- the listing, identity, registry ----------------------------------------------------


def test_listing_is_in_key_order() -> None:
    rng = random.Random(3)
    ks = rng.sample(range(-10**6, 10**6), 300) + [-1, -2, P, 2 * P]
    m = build([(k, str(k)) for k in ks])
    assert hamt.listKeys(m) == sorted(ks)
    assert hamt.listItemsi(m) == [(k, str(k)) for k in sorted(ks)]
    assert hamt.foldli(lambda k, v, acc: [*acc, k], [], m) == sorted(ks)


def test_structure_identity() -> None:
    assert hamt.name == "hamt" and repr(hamt) == "hamt"
    assert backend("hamt") is hamt
    assert isinstance(hamt, HamtMap)
    assert hamt.Key is NATURAL_ORDER
    assert hamt.empty() == HMap(0, (0, 0))
    assert hamt.singleton(3, "x") == hamt.insert(hamt.empty(), 3, "x")
    assert hamt.find(build([(2, None)]), 2) == (None,)  # SOME None is not NONE
    with pytest.raises(TypeError, match="not orderable"):
        hamt.singleton(None, 1)
