"""Adapter-specific tests of the ``immutables`` and ``pyrsistent`` ORD_MAP structures.

The generic ORD_MAP laws run on both adapters through the conformance suite
(tests/test_conformance_maps.py); this file covers what is particular to
adapting an unordered third-party hash map: ``None`` values, sorted listing,
``NotFound``, key checking, and that the map values really are the library's.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

immutables = pytest.importorskip("immutables")
pyrsistent = pytest.importorskip("pyrsistent")

from persistri.impl.maps import backend  # noqa: E402 - after the optional imports
from persistri.impl.maps.counted import counted  # noqa: E402
from persistri.impl.maps.immutables_adapter import ImmutablesMap, immutables_map  # noqa: E402
from persistri.impl.maps.pyrsistent_adapter import PyrsistentMap, pyrsistent_map  # noqa: E402
from persistri.impl.stats import Stats  # noqa: E402
from persistri.spec.ord_map import NotFound  # noqa: E402

ADAPTERS: list[tuple[Any, type, str]] = [
    (immutables_map, immutables.Map, "immutables"),
    (pyrsistent_map, pyrsistent.PMap, "pyrsistent"),
]
ids = [name for _, _, name in ADAPTERS]
adapters = pytest.mark.parametrize(("s", "library_map", "name"), ADAPTERS, ids=ids)


def build(s: Any, items: list[tuple[Any, Any]]) -> Any:
    m = s.empty()
    for k, v in items:
        m = s.insert(m, k, v)
    return m


# Ints whose hashes collide in CPython (hash(-1) == hash(-2) == -2), plus a wide spread.
int_keys = st.one_of(st.sampled_from([-1, -2, 0, 1, 2**61 - 1, 2**61]), st.integers(-(10**6), 10**6))


@adapters
def test_registry_resolves_the_adapter(s: Any, library_map: type, name: str) -> None:
    assert backend(name) is s
    assert repr(s) == name


@adapters
def test_maps_are_the_librarys_own(s: Any, library_map: type, name: str) -> None:
    m0 = s.empty()
    m1 = s.insert(m0, 1, "a")
    m2 = s.insert(m1, 2, "b")
    m3, _ = s.remove(m2, 1)
    for m in (m0, m1, m2, m3, s.singleton(5, "e"), s.insertWith(lambda o, v: o + v, m2, 2, "c")):
        assert type(m) is library_map
    # The adapter's insert and remove are the library's set and delete/remove, nothing more.
    assert s.insert(m2, 3, "c") == m2.set(3, "c")
    assert dict(m3.items()) == {2: "b"}
    # Persistence is the library's: earlier versions, as the library itself sees them, are intact.
    assert len(m0) == 0
    assert dict(m1.items()) == {1: "a"}
    assert dict(m2.items()) == {1: "a", 2: "b"}


@adapters
def test_none_is_a_value_not_absence(s: Any, library_map: type, name: str) -> None:
    m = build(s, [(1, None), (2, 0)])
    assert s.find(m, 1) == (None,)
    assert s.find(m, 3) is None
    assert s.lookup(m, 1) is None
    assert s.inDomain(m, 1)
    assert not s.inDomain(m, 3)
    m_without, v = s.remove(m, 1)
    assert v is None
    assert s.find(m_without, 1) is None
    assert s.numItems(m_without) == 1
    # insertWith sees the stored None as an old value, old first.
    m_with = s.insertWith(lambda old, new: (old, new), m, 1, "n")
    assert s.find(m_with, 1) == ((None, "n"),)
    assert s.listItemsi(m) == [(1, None), (2, 0)]


@adapters
def test_insertWith_absent_stores_v_without_calling_f(s: Any, library_map: type, name: str) -> None:
    def f(old: Any, new: Any) -> Any:
        raise AssertionError("f must not be called for an absent key")

    m = s.insertWith(f, s.empty(), 7, "v")
    assert s.find(m, 7) == ("v",)


@adapters
@given(items=st.dictionaries(int_keys, st.integers(), max_size=60), data=st.data())
def test_listing_is_sorted_by_key(s: Any, library_map: type, name: str, items: dict[int, int], data: st.DataObject) -> None:
    order = data.draw(st.permutations(sorted(items.items())))
    m = build(s, order)
    expected = sorted(items.items())
    assert s.listItemsi(m) == expected
    assert s.listKeys(m) == [k for k, _ in expected]
    assert s.foldli(lambda k, v, acc: [*acc, (k, v)], [], m) == expected
    assert s.numItems(m) == len(items)
    assert s.isEmpty(m) == (not items)


@adapters
def test_listing_sorts_by_key_only(s: Any, library_map: type, name: str) -> None:
    # Values need be neither hashable nor orderable.
    values = [[3], {"x": 1}, object()]
    m = build(s, [(2, values[0]), (0, values[1]), (1, values[2])])
    assert [v for _, v in s.listItemsi(m)] == [values[1], values[2], values[0]]


@adapters
def test_absent_key_raises_NotFound_and_leaves_the_map(s: Any, library_map: type, name: str) -> None:
    m = build(s, [(1, "a"), (2, "b")])
    with pytest.raises(NotFound):
        s.lookup(m, 3)
    with pytest.raises(NotFound):
        s.remove(m, 3)
    with pytest.raises(NotFound):
        s.remove(s.empty(), 3)
    with pytest.raises(KeyError):  # NotFound is a KeyError
        s.remove(m, 3)
    assert s.listItemsi(m) == [(1, "a"), (2, "b")]


UNHASHABLE: list[Any] = [[1], {1: 2}, {1}]
UNORDERABLE: list[Any] = [object(), 1j, None]


@adapters
@pytest.mark.parametrize(
    "key", UNHASHABLE + UNORDERABLE, ids=lambda k: "object()" if type(k) is object else repr(k)
)  # object()'s repr holds an address, which differs between xdist workers
def test_bad_keys_raise_TypeError_at_every_keyed_operation(s: Any, library_map: type, name: str, key: Any) -> None:
    m = build(s, [(1, "a")])
    reason = "not hashable" if any(key is k for k in UNHASHABLE) else "not orderable"
    calls: dict[str, Callable[[], object]] = {
        "singleton": lambda: s.singleton(key, 0),
        "insert": lambda: s.insert(m, key, 0),
        "insert into empty": lambda: s.insert(s.empty(), key, 0),
        "insertWith": lambda: s.insertWith(lambda o, v: v, m, key, 0),
        "find": lambda: s.find(m, key),
        "lookup": lambda: s.lookup(m, key),
        "inDomain": lambda: s.inDomain(m, key),
        "remove": lambda: s.remove(m, key),
    }
    for op, call in calls.items():
        with pytest.raises(TypeError, match=rf"^{name}: key .* {reason}") as info:
            call()
        assert not isinstance(info.value, KeyError), op
    assert s.listItemsi(m) == [(1, "a")]


@adapters
def test_mutually_unordered_keys_are_reported_by_the_listing(s: Any, library_map: type, name: str) -> None:
    # 1 and "a" each order among their own kind, so insert accepts both (documented);
    # the ordered listing is where they cannot be ordered, and says so.
    m = build(s, [(1, "x"), ("a", "y")])
    for listing in (s.listItemsi, s.listKeys, lambda m: s.foldli(lambda k, v, acc: acc, None, m)):
        with pytest.raises(TypeError, match=rf"^{name}: the keys of this map are not mutually ordered"):
            listing(m)


@adapters
def test_counting_sees_dictionary_operations_only(s: Any, library_map: type, name: str) -> None:
    # The library cannot say how many key comparisons it makes: no search_cost.
    assert not hasattr(s, "search_cost")
    stats = Stats()
    c = counted(s, stats)
    m = c.insert(c.empty(), 1, "a")
    m = c.insert(m, 2, "b")
    assert c.find(m, 1) == ("a",)
    m, _ = c.remove(m, 2)
    assert stats.dict_ops == 4
    assert stats.key_comparisons == 0
    assert type(m) is library_map


def test_structures_are_generic_classes() -> None:
    assert isinstance(immutables_map, ImmutablesMap)
    assert isinstance(pyrsistent_map, PyrsistentMap)
    assert ImmutablesMap[int, str]().insert(immutables.Map(), 1, "a") == immutables.Map({1: "a"})
