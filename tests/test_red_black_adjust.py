"""The red-black tree's batched update with one key inserted in the same descent (``adjust_insert``).

``RedBlackMap.adjust_insert`` must be exactly ``adjust_sorted`` followed by
``insert_absent`` of ``keys[j]`` when that key is absent: the same tree (shape,
colours, keys, values), the same number of new nodes (persistence by sharing,
counted by identity), the argument unchanged — and a valid red-black tree.
"""

from __future__ import annotations

import bisect
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.maps.red_black import RBMap, red_black
from tree_helpers import nodes, preorder

S = red_black


def _new_nodes(old: RBMap[Any, Any], new: RBMap[Any, Any]) -> int:
    seen = {id(x) for x in nodes(old[1])}
    return sum(id(x) not in seen for x in nodes(new[1]))


def _add_or_empty(old: tuple[int, ...], new: tuple[int, ...]) -> tuple[int, ...]:
    """A combine that empties the value when given ``()``: what the 2-complex's ``replace`` does to a vertex."""
    return old + new if new else ()


def _map(keys: list[int]) -> RBMap[int, tuple[int, ...]]:
    m: RBMap[int, tuple[int, ...]] = S.empty()
    for k in keys:
        m = S.insert(m, k, (k,))
    return m


@given(
    st.lists(st.integers(0, 300), max_size=150),
    st.lists(st.integers(-10, 310), min_size=1, max_size=30, unique=True),
    st.data(),
)
def test_adjust_insert_is_adjust_sorted_then_insert_absent(keys: list[int], probe: list[int], data: Any) -> None:
    """The same map, absent and emptied keys as ``adjust_sorted`` then ``insert_absent`` of ``keys[j]``; it
    inserts exactly when ``keys[j]`` is absent and no other absent key ends at its leaf (the same gap between
    the map's keys), else it is ``adjust_sorted``; the result is valid and the argument unchanged."""
    m = _map(keys)
    before = preorder(m[1])
    ks = sorted(probe)
    vs: list[tuple[int, ...]] = [(-k,) if k % 3 else () for k in ks]
    j = data.draw(st.integers(0, len(ks) - 1))
    out, absent, emptied, inserted = S.adjust_insert(_add_or_empty, m, ks, vs, j, (1000 + j,))
    want, want_absent, want_emptied = S.adjust_sorted(_add_or_empty, m, ks, vs)
    S._check(out)
    present = sorted(set(keys))

    def gap(k: int) -> int:
        return bisect.bisect_left(present, k)

    alone = not any(i != j and gap(ks[i]) == gap(ks[j]) for i in want_absent)
    assert inserted == (j in want_absent and bool(present) and alone)
    assert emptied == want_emptied
    if inserted:
        want = S.insert_absent(want, ks[j], (1000 + j,))
        assert absent == [i for i in want_absent if i != j]
    else:
        assert absent == want_absent
    assert S.numItems(out) == S.numItems(want)
    assert preorder(out[1]) == preorder(want[1])
    assert _new_nodes(m, out) == _new_nodes(m, want)
    assert preorder(m[1]) == before


def test_adjust_insert_at_every_leaf_of_a_tree() -> None:
    """Every gap of a tree of 200 keys (each leaf, so each of Okasaki's rewrites somewhere), with present
    neighbours updated in the same call: the tree ``adjust_sorted`` + ``insert_absent`` makes, valid."""
    m = _map(list(range(0, 400, 2)))
    for k in range(-1, 401, 2):
        ks = [x for x in (k - 3, k - 1, k, k + 1, k + 3) if 0 <= x < 400 or x == k]
        j = ks.index(k)
        vs = [(x,) for x in ks]
        out, absent, emptied, inserted = S.adjust_insert(_add_or_empty, m, ks, vs, j, (-k,))
        want, want_absent, _ = S.adjust_sorted(_add_or_empty, m, ks, vs)
        want = S.insert_absent(want, k, (-k,))
        S._check(out)
        assert inserted and absent == [] and want_absent == [j] and emptied == []
        assert preorder(out[1]) == preorder(want[1]) and S.numItems(out) == 201
        assert _new_nodes(m, out) == _new_nodes(m, want)


def test_adjust_insert_of_a_present_key_updates_it() -> None:
    m = _map([1, 3, 5, 9])
    out, absent, emptied, inserted = S.adjust_insert(_add_or_empty, m, [3, 5], [(7,), ()], 0, (0,))
    assert not inserted and absent == [] and emptied == [1]
    assert S.listItemsi(out) == [(1, (1,)), (3, (3, 7)), (5, ()), (9, (9,))]


def test_adjust_insert_edge_cases() -> None:
    """The empty map inserts nothing; ``keys[j]`` sharing its leaf with another absent key is reported absent
    with it; an exception of ``f`` propagates unchanged."""
    assert S.adjust_insert(_add_or_empty, S.empty(), [1, 2], [(1,), (2,)], 1, (0,)) == (S.empty(), [0, 1], [], False)
    m = _map([1, 5, 9])
    out, absent, emptied, inserted = S.adjust_insert(_add_or_empty, m, [2, 3, 5], [(2,), (3,), (0,)], 1, (0,))
    assert (absent, emptied, inserted) == ([0, 1], [], False) and S.numItems(out) == 3

    def f(old: Any, new: Any) -> Any:
        raise KeyError("f says no")

    with pytest.raises(KeyError, match="f says no"):
        S.adjust_insert(f, m, [4, 5], [0, 0], 0, (0,))
    out, absent, emptied, inserted = S.adjust_insert(f, m, [4], [0], 0, (4,))
    assert inserted and absent == [] and S.listItemsi(out) == [(1, (1,)), (4, (4,)), (5, (5,)), (9, (9,))]
