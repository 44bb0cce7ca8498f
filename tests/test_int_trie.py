"""The integer trie map (:mod:`persistri.impl.maps.int_trie`): keys, errors, persistence at scale, sharing.

The ``ORD_MAP`` conformance suite runs on it from ``tests/test_conformance_maps.py``;
here are what the suite does not reach: the refusal of keys that are not
integers, naming the backend; thousands of versions kept and all rechecked
after later operations (with ``_check``); the batched operations the 2-complex
calls, against the red-black map's; path copying by identity; pickling; and
``_check`` catching each broken invariant.
"""

from __future__ import annotations

import copy
import pickle
import random
from collections.abc import Callable
from typing import Any

import pytest

from persistri.impl.maps import backend
from persistri.impl.maps.int_trie import IntTrieMap, NotAnIntKey, TrieMap, int_trie
from persistri.impl.maps.int_trie_absent import ABSENT
from persistri.impl.maps.int_trie_nodes import EMPTY_INNER
from persistri.impl.maps.red_black import red_black
from persistri.spec.ord_map import NotFound, OrdMap

S = int_trie

# A type-level check: the structure matches the ORD_MAP Protocol (mypy on this file).
_typed: OrdMap[int, str, TrieMap] = IntTrieMap[int, str]()


def _filled(keys: Any) -> TrieMap:
    m = S.empty()
    for k in keys:
        m = S.insert(m, k, str(k))
    return m


def test_the_registry_names_it() -> None:
    assert backend("int_trie") is S and repr(S) == "int_trie"


# -- keys that are not integers ------------------------------------------------------------


@pytest.mark.parametrize("key", ["a", 1.0, 2.5, float("nan"), None, (1,), object(), 1j])
@pytest.mark.parametrize(
    "operation",
    ["singleton", "insert", "insertWith", "find", "lookup", "inDomain", "remove", "search_cost"],
)
def test_a_key_that_is_not_an_int_is_refused_naming_the_backend(key: Any, operation: str) -> None:
    m = _filled([1, 2, 3])
    calls: dict[str, Callable[[], Any]] = {
        "singleton": lambda: S.singleton(key, 0),
        "insert": lambda: S.insert(m, key, 0),
        "insertWith": lambda: S.insertWith(lambda a, b: a, m, key, 0),
        "find": lambda: S.find(m, key),
        "lookup": lambda: S.lookup(m, key),
        "inDomain": lambda: S.inDomain(m, key),
        "remove": lambda: S.remove(m, key),
        "search_cost": lambda: S.search_cost(m, key),
    }
    with pytest.raises(NotAnIntKey, match=r"^int_trie: key .* of type \w+ is not an int") as info:
        calls[operation]()
    assert isinstance(info.value, TypeError)
    assert S.listItemsi(m) == [(1, "1"), (2, "2"), (3, "3")]
    S._check(m)


def test_int_subclasses_are_keys_and_their_objects_are_kept() -> None:
    class V(int):
        pass

    a, b = V(5), V(70)
    m = S.insert(S.insert(S.empty(), b, "b"), a, "a")
    keys = S.listKeys(m)
    assert keys == [5, 70] and keys[0] is a and keys[1] is b
    c = V(5)
    m2 = S.insert(m, c, "c")  # insert stores its key object
    assert S.listKeys(m2)[0] is c and S.listKeys(m)[0] is a
    m3 = S.insertWith(lambda x, y: x + y, m2, V(5), "!")  # insertWith keeps the stored one
    assert S.listItemsi(m3)[0] == (5, "c!") and S.listKeys(m3)[0] is c


def test_negative_and_huge_keys_in_order() -> None:
    keys = [0, -1, 1, -32, 31, 32, -33, 2**70, -(2**70), 1023, -1024, 1024, 5]
    m = _filled(keys)
    S._check(m)
    assert S.listKeys(m) == sorted(keys)
    for k in keys:
        assert S.find(m, k) == (str(k),)
    for k in (2, -2, 2**70 + 1, -(2**71), 2**200):
        assert S.find(m, k) is None and not S.inDomain(m, k)
    for k in keys:
        m, v = S.remove(m, k)
        assert v == str(k)
        S._check(m)
    assert m == S.empty()


def test_errors_of_the_signature_leave_the_map() -> None:
    m = _filled([3, 40])
    with pytest.raises(NotFound):
        S.lookup(m, 4)
    with pytest.raises(NotFound):
        S.remove(m, -4)

    def boom(a: Any, b: Any) -> Any:
        raise ZeroDivisionError("f")

    with pytest.raises(ZeroDivisionError, match="f") as info:
        S.insertWith(boom, m, 3, "x")
    assert info.value.__cause__ is None
    with pytest.raises(ZeroDivisionError):
        S.adjust_sorted(boom, m, [3, 40], ["x", "y"])
    assert S.insertWith(boom, m, 4, "x") == S.insert(m, 4, "x")  # f is not called for an absent key
    assert S.listItemsi(m) == [(3, "3"), (40, "40")]


def test_some_none_is_not_none() -> None:
    m = S.insert(S.empty(), 7, None)
    assert S.find(m, 7) == (None,) and S.find(m, 8) is None and S.lookup(m, 7) is None


# -- persistence at scale -----------------------------------------------------------------


@pytest.mark.parametrize("span", [4_000, 1 << 22])
def test_every_version_of_thousands_of_updates_is_kept(span: int) -> None:
    """Keep every version of 2,000 mixed operations; recheck all of them at the end, after every later
    operation has run: every version's items, and the invariants of every 25th and of the last."""
    rnd = random.Random(span)
    m = S.empty()
    d: dict[int, Any] = {}
    versions: list[tuple[TrieMap, list[tuple[int, Any]]]] = []
    for step in range(2_000):
        r = rnd.random()
        k = rnd.randrange(span) if rnd.random() < 0.9 else -rnd.randrange(1, span)
        if r < 0.45:
            m = S.insert(m, k, step)
            d[k] = step
        elif r < 0.6:
            m = S.insertWith(lambda a, b: a + b, m, k, step)
            d[k] = d.get(k, 0) + step if k in d else step
        elif r < 0.75 and d:
            k = rnd.choice(list(d))
            m, v = S.remove(m, k)
            assert v == d.pop(k)
        else:
            base = rnd.randrange(span)
            ks = sorted({min(span - 1, base + rnd.randrange(64)) for _ in range(rnd.randint(1, 8))})
            j = rnd.randrange(len(ks))
            m, absent, emptied, inserted = S.adjust_insert(lambda a, b: a + b, m, ks, [1] * len(ks), j, -step)
            assert inserted == (ks[j] not in d)
            assert absent == [i for i, x in enumerate(ks) if x not in d and i != j]
            for i, x in enumerate(ks):
                if x in d:
                    d[x] += 1
            if inserted:
                d[ks[j]] = -step
            assert emptied == [i for i, x in enumerate(ks) if x in d and not d[x] and not (inserted and i == j)]
        versions.append((m, sorted(d.items())))
    for i, (old, items) in enumerate(versions):
        assert S.listItemsi(old) == items
        assert S.numItems(old) == len(items)
        if i % 25 == 0 or i == len(versions) - 1:
            S._check(old)


def test_the_batched_update_is_the_red_black_maps() -> None:
    """``adjust_insert`` and ``adjust_sorted`` give the red-black map's items and reports (the 2-complex's
    replace relies on them), on the same random batches, some with negative keys (the Delaunay's ghost vertex
    is -1)."""
    rnd = random.Random(3)
    t, r = S.empty(), red_black.empty()
    for k in rnd.sample(range(-40, 3000), 1500):
        t, r = S.insert(t, k, (k,)), red_black.insert(r, k, (k,))

    def f(old: Any, v: Any) -> Any:
        return old[1:] + v

    for _ in range(500):
        ks = sorted(rnd.sample(range(-40, 3000) if rnd.random() < 0.3 else range(3000), rnd.randint(1, 9)))
        vals = [(i,) for i in range(len(ks))]
        t2, ta, te = S.adjust_sorted(f, t, ks, vals)
        r2, ra, re_ = red_black.adjust_sorted(f, r, ks, vals)
        assert (ta, te) == (ra, re_) and S.listItemsi(t2) == red_black.listItemsi(r2)
        j = rnd.randrange(len(ks))
        t3, ta, te, ti = S.adjust_insert(f, t, ks, vals, j, ("new",))
        r3, ra, re_, ri = red_black.adjust_insert(f, r, ks, vals, j, ("new",))
        if ri or ks[j] not in [k for k, _ in red_black.listItemsi(r)]:  # the red-black map may leave it absent
            if not ri:
                ra.remove(j)
                r3 = red_black.insert(r3, ks[j], ("new",))
            assert ti
        assert (ta, te) == (ra, re_) and S.listItemsi(t3) == red_black.listItemsi(r3)
        S._check(t3)
        t, r = t3, r3


# -- sharing -----------------------------------------------------------------------------


def test_an_update_copies_its_paths_and_shares_the_rest() -> None:
    m = _filled(range(0, 3000, 3))
    s, root = m[1], m[2]
    assert root is not None
    assert s == 10  # three levels below 32,768
    m2, absent, emptied, inserted = S.adjust_insert(lambda a, b: b, m, [3, 6, 1500, 1501], ["a", "b", "c", "d"], 3, "e")
    assert (absent, emptied, inserted) == ([], [], True)
    new: Any = m2[2]
    assert new is not root and S.listItemsi(m) == [(k, str(k)) for k in range(0, 3000, 3)]
    # Children of the root off the keys' paths are the old objects; so are the leaves off them.
    changed = {3 >> 10, 1500 >> 10}
    for d in range(32):
        if d not in changed:
            assert new[d] is root[d]
    leaf_old, leaf_new = root[0][0], new[0][0]  # keys 0..31: 3 and 6 updated, no key inserted there
    assert leaf_new is not leaf_old and leaf_new[0] is leaf_old[0]  # the key objects' tuple shared
    assert root[0][1] is new[0][1]  # keys 32..63 untouched
    m3, *_ = S.adjust_sorted(lambda a, b: b, m, [2, 4], ["x", "y"])  # both absent: nothing copied
    assert m3[2] is root


def test_pickle_and_copies_keep_the_empty_slot() -> None:
    m = _filled([1, 40, -3, 2**40])
    for m2 in (pickle.loads(pickle.dumps(m)), copy.deepcopy(m)):
        S._check(m2)
        assert S.listItemsi(m2) == S.listItemsi(m)
        leaf: Any = m2[2]
        while len(leaf) != 33:  # down child 0 to the leaf of the keys 0..31
            leaf = leaf[0]
        assert leaf[1] is ABSENT  # index 0's empty slot: the one object again
    assert pickle.loads(pickle.dumps(S)) is S


def test_search_cost_is_the_nodes_visited() -> None:
    m = _filled([0, 5, 2000])
    assert S.search_cost(m, 5) == 3 and S.search_cost(m, 2000) == 3
    assert S.search_cost(m, 1 << 20) == 0 and S.search_cost(m, -1) == 0
    assert S.search_cost(m, 40) == 2  # the leaf of 32..63 is absent


# -- the invariant check catches each broken invariant ---------------------------------------


def _broken(m: TrieMap) -> list[TrieMap]:
    n, s, root, ns, nroot = m
    assert root is not None
    leaf = root[0][0]
    wrong_key = list(leaf[0])
    wrong_key[1] = 2  # index 1 holds key 2
    value_without_key = list(leaf)
    value_without_key[3] = "x"
    empty_leaf = (leaf[0].__class__((None,) * 32),) + (ABSENT,) * 32
    return [
        (n + 1, s, root, ns, nroot),  # size
        (n, s + 5, (root,) + EMPTY_INNER[1:], ns, nroot),  # height not the least
        (n, s, (((tuple(wrong_key),) + leaf[1:],) + root[0][1:],) + root[1:], ns, nroot),
        (n, s, ((tuple(value_without_key),) + root[0][1:],) + root[1:], ns, nroot),
        (n, s, (root[0][:1] + (empty_leaf,) + root[0][2:],) + root[1:], ns, nroot),
        (n, s, (root[0][:1] + (EMPTY_INNER,) + root[0][2:],) + root[1:], ns, nroot),
        (n, 3, root, ns, nroot),
    ]


def test_check_catches_each_broken_invariant() -> None:
    m = _filled([1, 5, 40, 3000])
    S._check(m)
    for bad in _broken(m):
        with pytest.raises(AssertionError, match="^int_trie: "):
            S._check(bad)
