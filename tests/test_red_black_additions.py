"""persistri's additions to ``ORD_MAP`` in the red-black map (:mod:`persistri.impl.maps.red_black`).

``adjust_many`` is ``insertWith`` at each present key in one descent, the
absent items handed back, its only new nodes on the union of the present keys'
search paths (so neighbouring keys share them); ``adjust_sorted`` is the same
without the order check and reports the values it emptied; ``find_unchecked``
answers as ``find``; ``insert_absent`` builds the tree ``insert`` builds for an
absent key.  These are what the 2-complex's ``replace`` and walks use.
"""

from __future__ import annotations

from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.maps.red_black import RBMap, red_black

from red_black_helpers import check_all, shape, small_int_map
from tree_helpers import nodes

S = red_black


# -- adjust_many: insertWith at several present keys in one descent ------------------------


def _union_of_paths(m: RBMap[int, Any], keys: list[int]) -> int:
    """The distinct nodes on the search paths of ``keys``, found by separate searches."""
    seen: set[int] = set()
    for k in keys:
        t = m[1]
        while t is not None:
            seen.add(id(t))
            if k < t[2]:
                t = t[1]
            elif t[2] < k:
                t = t[4]
            else:
                break
    return len(seen)


@given(st.lists(st.integers(0, 500), max_size=200), st.lists(st.integers(-20, 520), max_size=40, unique=True))
def test_adjust_many_is_insert_with_at_the_present_keys(keys: list[int], probe: list[int]) -> None:
    """``adjust_many`` = ``insertWith`` at each present key, absent items reported; only the paths' union is new."""
    m: RBMap[int, tuple[int, ...]] = S.empty()
    for k in keys:
        m = S.insert(m, k, (k,))
    before = S.listItemsi(m)
    items = [(k, (-k,)) for k in sorted(probe)]
    out, absent = S.adjust_many(lambda old, new: old + new, m, items)
    expected = m
    for k, v in items:
        if S.inDomain(m, k):
            expected = S.insertWith(lambda old, new: old + new, expected, k, v)
    S._check(out)
    assert S.listItemsi(out) == S.listItemsi(expected)
    assert absent == [(k, v) for k, v in items if not S.inDomain(m, k)]
    assert S.listItemsi(m) == before  # the argument is unchanged
    # Shape and colours kept; every new node is on the union of the present keys' search paths.
    assert [c for c, *_ in shape(out[1])] == [c for c, *_ in shape(m[1])]
    old = {id(x) for x in nodes(m[1])}
    fresh = sum(id(x) not in old for x in nodes(out[1]))
    present = [k for k, _ in items if S.inDomain(m, k)]
    assert fresh == (_union_of_paths(m, present) if present else 0)


def test_adjust_many_shares_the_common_path() -> None:
    """Neighbouring keys share their search paths: far fewer new nodes than separate updates."""
    m: RBMap[int, int] = S.empty()
    for k in range(1 << 12):
        m = S.insert(m, k, 0)
    near = list(range(2000, 2008))
    old = {id(x) for x in nodes(m[1])}
    out, absent = S.adjust_many(lambda old, new: old + new, m, [(k, 1) for k in near])
    assert absent == [] and all(S.lookup(out, k) == 1 for k in near)
    fresh = sum(id(x) not in old for x in nodes(out[1]))
    separate = sum(S.search_cost(m, k) for k in near)
    assert fresh == _union_of_paths(m, near) and fresh < separate // 3, (fresh, separate)


def test_adjust_many_errors() -> None:
    m = small_int_map()
    with pytest.raises(ValueError, match="strictly increasing"):
        S.adjust_many(lambda o, n: n, m, [(3, 0), (1, 0)])
    with pytest.raises(ValueError, match="strictly increasing"):
        S.adjust_many(lambda o, n: n, m, [(3, 0), (3, 0)])
    with pytest.raises(TypeError, match="not ordered"):
        S.adjust_many(lambda o, n: n, m, [(1, 0), ("x", 0)])

    def f(old: int, new: int) -> int:
        raise TypeError("f says no")

    with pytest.raises(TypeError, match="^f says no$"):
        S.adjust_many(f, m, [(3, 0)])
    # Nothing present: f is not called, every item is reported absent; the empty map likewise.
    assert S.adjust_many(f, m, [(-5, 1)]) == (m, [(-5, 1)])
    assert S.adjust_many(f, S.empty(), [(1, 2)]) == (S.empty(), [(1, 2)])
    assert S.adjust_many(f, m, []) == (m, [])


def _add_or_empty(old: tuple[int, ...], new: tuple[int, ...]) -> tuple[int, ...]:
    """A combine that empties the value when given ``()``: what the 2-complex's ``replace`` does to a vertex."""
    return old + new if new else ()


@given(st.lists(st.integers(0, 500), max_size=200), st.lists(st.integers(-20, 520), max_size=40, unique=True))
def test_adjust_sorted_is_adjust_many(keys: list[int], probe: list[int]) -> None:
    """The unchecked form the 2-complex's ``replace`` uses: the same map (the same new nodes, by count) and
    the same absent items as ``adjust_many`` on strictly increasing keys, by index; the indices of the
    values it emptied; the argument unchanged."""
    m: RBMap[int, tuple[int, ...]] = S.empty()
    for k in keys:
        m = S.insert(m, k, (k,))
    before = S.listItemsi(m)
    ks = sorted(probe)
    vs: list[tuple[int, ...]] = [(-k,) if k % 3 else () for k in ks]
    out, absent, emptied = S.adjust_sorted(_add_or_empty, m, ks, vs)
    want, want_absent = S.adjust_many(_add_or_empty, m, list(zip(ks, vs)))
    S._check(out)
    assert S.listItemsi(out) == S.listItemsi(want) and [(ks[i], vs[i]) for i in absent] == want_absent
    assert absent == sorted(absent) and emptied == sorted(emptied)
    assert emptied == [i for i, k in enumerate(ks) if S.inDomain(m, k) and not vs[i]]
    assert all(S.lookup(out, ks[i]) == () for i in emptied)
    assert S.listItemsi(m) == before
    old = {id(x) for x in nodes(m[1])}
    assert sum(id(x) not in old for x in nodes(out[1])) == sum(id(x) not in old for x in nodes(want[1]))


def test_adjust_sorted_lets_f_raise() -> None:
    m = small_int_map()

    def f(old: int, new: int) -> int:
        raise KeyError("f says no")

    with pytest.raises(KeyError, match="f says no"):
        S.adjust_sorted(f, m, [1, 3], [0, 0])
    assert S.adjust_sorted(f, m, [-5], [1]) == (m, [0], [])
    assert S.adjust_sorted(f, S.empty(), [1], [2]) == (S.empty(), [0], [])


@given(st.lists(st.integers(0, 200), max_size=100), st.lists(st.integers(-10, 210), max_size=30))
def test_find_unchecked_is_find(keys: list[int], probes: list[int]) -> None:
    """The unchecked find the 2-complex's walks use answers as ``find`` (keys ordered with the map's)."""
    m: RBMap[int, int] = S.empty()
    for k in keys:
        m = S.insert(m, k, -k)
    for k in probes:
        assert S.find_unchecked(m, k) == S.find(m, k)


@given(st.lists(st.integers(0, 300), max_size=150), st.lists(st.integers(-10, 310), max_size=30, unique=True))
def test_insert_absent_is_insert_of_an_absent_key(keys: list[int], probes: list[int]) -> None:
    """The unchecked insertion ``replace`` uses for new vertices: the same tree as ``insert`` (shape, colours,
    the same number of new nodes) for every absent key; the argument unchanged."""
    m: RBMap[int, int] = S.empty()
    for k in keys:
        m = S.insert(m, k, k)
    before = S.listItemsi(m)
    old = {id(x) for x in nodes(m[1])}
    for k in probes:
        if S.inDomain(m, k):
            continue
        got, want = S.insert_absent(m, k, -k), S.insert(m, k, -k)
        check_all(got)
        assert shape(got[1]) == shape(want[1]) and S.numItems(got) == S.numItems(want)
        assert sum(id(x) not in old for x in nodes(got[1])) == sum(id(x) not in old for x in nodes(want[1]))
    assert S.listItemsi(m) == before
