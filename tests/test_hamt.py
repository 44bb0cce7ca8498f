"""Backend-specific tests of the HAMT map (:mod:`persistri.impl.maps.hamt`).

The generic ``ORD_MAP`` conformance suite runs on every backend; these tests
look inside the trie: invariants after every step (``_check``), every version
kept and rechecked (persistence), hash collisions (collision nodes), deep tries,
canonical shape after deletions, structural sharing, ``search_cost`` against
the equality tests really made, ``_check`` catching hand-broken tries, and the
``TypeError`` cases at the API boundary.
"""

from __future__ import annotations

import copy as copy_module
import operator
import pickle
import random
from collections.abc import Callable
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.maps import backend
from persistri.impl.maps.counted import counted
from persistri.impl.maps.hamt import _BIT, _FULL, HamtMap, HMap, hamt
from persistri.impl.stats import Stats
from persistri.spec.ord_map import NotFound
from persistri.spec.order import NATURAL_ORDER

P = 2**61 - 1
"""The modulus of Python's integer hash on 64-bit builds: ``hash(n + P) == hash(n)`` for n ≥ 0."""


def _signed64(x: int) -> int:
    """``x`` wrapped into a signed 64-bit hash value."""
    x &= (1 << 64) - 1
    return x - (1 << 64) if x >= 1 << 63 else x


class HKey:
    """A key with a chosen hash: equal and ordered by ``n``, hashed by ``h``.

    Counts its equality tests (``eq_calls``) so ``search_cost`` can be checked
    against the tests a search really makes.
    """

    __slots__ = ("n", "h")
    eq_calls = 0

    def __init__(self, n: int, h: int) -> None:
        self.n = n
        self.h = h

    def __eq__(self, other: object) -> bool:
        HKey.eq_calls += 1
        return isinstance(other, HKey) and self.n == other.n

    def __lt__(self, other: object) -> bool:
        if not isinstance(other, HKey):
            return NotImplemented
        return self.n < other.n

    def __hash__(self) -> int:
        return self.h

    def __repr__(self) -> str:
        return f"HKey({self.n}, h={self.h:#x})"


HASHES: dict[str, Callable[[int], int]] = {
    "constant": lambda n: 7,
    "n//3": lambda n: n // 3,
    "n%4<<60": lambda n: (n % 4) << 60,
    "shared-58-bits": lambda n: _signed64(n << 58),
    "sign-bit-only": lambda n: _signed64((n % 2) << 63) + 5,
    "identity": lambda n: n,
    "spread": lambda n: _signed64(n * 0x9E3779B97F4A7C15),
}
"""Hash functions for :class:`HKey`: full collisions, partial collisions, long shared prefixes, spread."""


def key_maker(name: str) -> Callable[[int], HKey]:
    fn = HASHES[name]
    return lambda n: HKey(n, fn(n))


# -- looking inside the trie ----------------------------------------------------


def is_collision(node: tuple[Any, ...]) -> bool:
    """Whether a child is a collision node ``(0, 0, hash, k, v, …)``."""
    return len(node) > 2 and node[0] == 0 and node[1] == 0


def children(node: tuple[Any, ...]) -> tuple[Any, ...]:
    """The children of a bitmap node (bitmap nodes and collision nodes), in slot order, after its leaves."""
    return node[2 + 2 * node[0].bit_count() :]


def leaves(node: tuple[Any, ...]) -> list[tuple[Any, Any]]:
    """The inline ``(key, value)`` leaves of a bitmap node, in slot order."""
    split = 2 + 2 * node[0].bit_count()
    return list(zip(node[2:split:2], node[3:split:2]))


def nodes(m: HMap[Any, Any]) -> list[tuple[int, tuple[Any, ...]]]:
    """Every bitmap node of ``m`` with its depth (root = 0)."""
    out = []
    stack = [(0, m.root)]
    while stack:
        depth, node = stack.pop()
        out.append((depth, node))
        stack.extend((depth + 1, c) for c in children(node) if not is_collision(c))
    return out


def depth(m: HMap[Any, Any]) -> int:
    """The depth of the deepest bitmap node (root = 0)."""
    return max(d for d, _ in nodes(m))


def collision_nodes(m: HMap[Any, Any]) -> list[tuple[Any, ...]]:
    return [c for _, node in nodes(m) for c in children(node) if is_collision(c)]


def collision_keys(c: tuple[Any, ...]) -> list[Any]:
    return list(c[3::2])


def build(items: list[tuple[Any, Any]]) -> HMap[Any, Any]:
    m = hamt.empty()
    for k, v in items:
        m = hamt.insert(m, k, v)
    return m


def agrees(m: HMap[Any, Any], model: dict[Any, Any], universe: list[Any]) -> None:
    """``m`` passes ``_check`` and holds exactly ``model``."""
    hamt._check(m)
    assert hamt.numItems(m) == len(model)
    assert hamt.isEmpty(m) == (not model)
    assert hamt.listItemsi(m) == sorted(model.items(), key=operator.itemgetter(0))
    for k in universe:
        assert hamt.find(m, k) == ((model[k],) if k in model else None)
        assert hamt.inDomain(m, k) == (k in model)


# -- random operation sequences against a dict model, every version kept -------

OPS = st.sampled_from(["insert", "insertWith", "remove"])


def combine(old: int, new: int) -> int:
    """Not commutative, so swapped arguments of ``insertWith``'s ``f`` show."""
    return old * 31 + new


def run_ops(ops: list[tuple[str, Any, int]], universe: list[Any]) -> None:
    m = hamt.empty()
    model: dict[Any, Any] = {}
    versions = [(m, dict(model))]
    for op, k, v in ops:
        if op == "insert":
            m = hamt.insert(m, k, v)
            model[k] = v
        elif op == "insertWith":
            m = hamt.insertWith(combine, m, k, v)
            model[k] = combine(model[k], v) if k in model else v
        elif k in model:
            m, removed = hamt.remove(m, k)
            assert removed == model.pop(k)
        else:
            with pytest.raises(NotFound):
                hamt.remove(m, k)
        hamt._check(m)
        assert hamt.numItems(m) == len(model)
        assert hamt.find(m, k) == ((model[k],) if k in model else None)
        versions.append((m, dict(model)))
    # Persistence: every earlier version is still exactly what it was.
    for old, snapshot in versions:
        agrees(old, snapshot, universe)
    # Canonical form: the last version has the shape of a fresh build of its items.
    fresh = build(sorted(model.items(), key=operator.itemgetter(0)))
    assert fresh == m


INT_KEYS = st.integers(-40, 40) | st.sampled_from([-1, -2, P, P + 1, 2 * P, -P, P - 1, 1 << 60, -(1 << 60)])
"""Small ints plus ints whose hashes collide with them (``hash(-1) == hash(-2)``, ``hash(n + P) == hash(n)``)."""
INT_UNIVERSE = list(range(-40, 41)) + [P, P + 1, 2 * P, -P, P - 1, 1 << 60, -(1 << 60)]


@given(st.lists(st.tuples(OPS, INT_KEYS, st.integers(0, 9)), max_size=80))
def test_int_operations_against_model(ops: list[tuple[str, int, int]]) -> None:
    run_ops(ops, INT_UNIVERSE)


@given(
    st.sampled_from(sorted(HASHES)),
    st.lists(st.tuples(OPS, st.integers(0, 30), st.integers(0, 9)), max_size=80),
)
def test_colliding_keys_against_model(hash_name: str, raw: list[tuple[str, int, int]]) -> None:
    key = key_maker(hash_name)
    run_ops([(op, key(n), v) for op, n, v in raw], [key(n) for n in range(31)])


@given(
    st.sampled_from(sorted(HASHES)),
    st.lists(st.integers(0, 60), unique=True, max_size=40),
    st.data(),
)
def test_canonical_shape_after_deletes(hash_name: str, ns: list[int], data: st.DataObject) -> None:
    """Any insert/remove history leaves the shape of a direct build of the remaining keys."""
    key = key_maker(hash_name)
    gone = data.draw(st.sets(st.sampled_from(ns))) if ns else set()
    m = build([(key(n), n) for n in ns])
    for n in data.draw(st.permutations(sorted(gone))):
        m, _ = hamt.remove(m, key(n))
        hamt._check(m)
    kept = [n for n in ns if n not in gone]
    order = data.draw(st.permutations(kept))
    fresh = build([(key(n), n) for n in order])
    assert m.root == fresh.root
    assert m == fresh


# -- collisions -----------------------------------------------------------------


def test_python_int_collisions() -> None:
    """``-1`` and ``-2`` hash alike, as do ``0, P, 2P, -P``: they share collision nodes."""
    assert hash(-1) == hash(-2) and hash(0) == hash(P) == hash(2 * P) == hash(-P)
    m = build([(-1, "a"), (-2, "b"), (0, "z"), (P, "p"), (2 * P, "pp"), (-P, "-p"), (5, "five")])
    hamt._check(m)
    sizes = sorted(len(collision_keys(c)) for c in collision_nodes(m))
    assert sizes == [2, 4]
    assert hamt.find(m, -1) == ("a",) and hamt.find(m, -2) == ("b",)
    assert hamt.find(m, P) == ("p",) and hamt.find(m, 3 * P) is None
    assert hamt.listKeys(m) == [-P, -2, -1, 0, 5, P, 2 * P]
    # Each collision node keeps its keys in increasing order, whatever the insertion order.
    assert build([(2 * P, 1), (-P, 1), (P, 1), (0, 1)]) == build([(0, 1), (P, 1), (-P, 1), (2 * P, 1)])
    # Removing down to one key turns the collision node back into a leaf.
    m2, v = hamt.remove(m, -2)
    assert v == "b"
    hamt._check(m2)
    assert sorted(len(collision_keys(c)) for c in collision_nodes(m2)) == [4]
    assert hamt.find(m2, -1) == ("a",) and hamt.find(m2, -2) is None
    # The old version still has both.
    assert hamt.find(m, -2) == ("b",)


def test_collision_node_meets_a_different_hash() -> None:
    """A key whose hash differs from a collision node's, in the same slot, pushes both one level down."""
    a, b = HKey(1, 0), HKey(2, 0)
    c = HKey(3, 1 << 5)  # same level-0 slot (0), different level-1 slot
    m = build([(a, "a"), (b, "b")])
    assert m.root[:2] == (0, 1) and is_collision(m.root[2])
    m2 = hamt.insert(m, c, "c")
    hamt._check(m2)
    assert m2.root[:2] == (0, 1) and not is_collision(m2.root[2]) and depth(m2) == 1
    assert len(children(m2.root[2])) == 1 and leaves(m2.root[2]) == [(c, "c")]
    assert [hamt.find(m2, k) for k in (a, b, c)] == [("a",), ("b",), ("c",)]
    m3, _ = hamt.remove(m2, c)
    assert m3 == m  # the collision node moves back up into the root


def test_insert_with_in_collision_node() -> None:
    a, b = HKey(1, 9), HKey(2, 9)
    m = build([(a, 10), (b, 20)])
    m = hamt.insertWith(combine, m, HKey(2, 9), 1)
    m = hamt.insertWith(combine, m, HKey(3, 9), 4)
    hamt._check(m)
    assert hamt.listItemsi(m) == [(a, 10), (b, 20 * 31 + 1), (HKey(3, 9), 4)]


def test_remove_not_found_everywhere() -> None:
    """NotFound (a KeyError) from an empty slot, another leaf, a foreign collision node, an absent colliding key."""
    m = build([(HKey(1, 0), 1), (HKey(2, 0), 2), (HKey(3, 1), 3)])
    for absent in (HKey(4, 2), HKey(4, 1), HKey(4, 32), HKey(4, 0)):
        with pytest.raises(NotFound):
            hamt.remove(m, absent)
        with pytest.raises(KeyError):
            hamt.lookup(m, absent)
        assert hamt.find(m, absent) is None
    with pytest.raises(NotFound):
        hamt.remove(hamt.empty(), 0)


# -- deep tries -------------------------------------------------------------------


def test_deep_trie_ints() -> None:
    """``0`` and ``2**60`` agree on hash bits 0–59: a chain of single-child nodes, parting at depth 15."""
    m = build([(0, "a"), (1 << 60, "b")])
    hamt._check(m)
    assert depth(m) == 15
    assert all(node[:2] == (0, 1) and len(node) == 3 for d, node in nodes(m) if d < 15)
    assert [leaves(node) for d, node in nodes(m) if d == 15] == [[(0, "a"), (1 << 60, "b")]]
    m2, _ = hamt.remove(m, 0)
    hamt._check(m2)
    assert depth(m2) == 0 and m2 == hamt.singleton(1 << 60, "b")


def test_deep_trie_sign_bit() -> None:
    """Hashes differing only in bit 63 (the sign) part at the last level."""
    a, b = HKey(0, 5), HKey(1, _signed64((1 << 63) + 5))
    assert hash(b) < 0
    m = build([(a, 0), (b, 1)])
    hamt._check(m)
    assert depth(m) == 15 and not collision_nodes(m)
    c = HKey(2, 5)  # same full hash as a: a collision node at the bottom
    m2 = hamt.insert(m, c, 2)
    hamt._check(m2)
    assert depth(m2) == 15 and len(collision_nodes(m2)) == 1
    m3, _ = hamt.remove(m2, b)
    hamt._check(m3)
    # The collision node rises to the root.
    assert depth(m3) == 0 and m3.root[:2] == (0, _BIT[5]) and collision_keys(m3.root[2]) == [a, c]


def test_many_deep_keys() -> None:
    key = key_maker("shared-58-bits")
    m = build([(key(n), n) for n in range(64)])
    hamt._check(m)
    assert depth(m) == 15
    for n in range(0, 64, 2):
        m, _ = hamt.remove(m, key(n))
        hamt._check(m)
    assert m == build([(key(n), n) for n in range(1, 64, 2)])


# -- persistence by path copying ----------------------------------------------------


def test_structural_sharing() -> None:
    """An insert copies only the path to its key: every other entry of the root is the same object."""
    rng = random.Random(7)
    keys = list(range(5000))
    rng.shuffle(keys)
    m = build([(k, k) for k in keys])
    m2 = hamt.insert(m, 12345, 0)
    old, new = m.root, m2.root
    assert old[1] is new[1] is _FULL and len(old) == len(new) == 18  # the two bitmaps and 16 children
    changed = [j for j in range(len(old)) if old[j] is not new[j]]
    assert changed == [2 + (12345 & 15)]
    m3, _ = hamt.remove(m2, 12345)
    assert m3 == m and m3.root[2 + (12345 & 15)] is not m.root[2 + (12345 & 15)]
    hamt._check(m)
    # insertWith on a present key shares just as much, and leaves the old version alone.
    m4 = hamt.insertWith(combine, m, 777, 1)
    assert [j for j in range(18) if m4.root[j] is not m.root[j]] == [2 + (777 & 15)]
    assert hamt.find(m4, 777) == (777 * 31 + 1,) and hamt.find(m, 777) == (777,)


# -- search_cost ---------------------------------------------------------------


def test_search_cost_ints() -> None:
    m = build([(0, 0), (1, 1), (-1, -1), (-2, -2)])
    assert hamt.search_cost(m, 0) == 1  # a leaf
    assert hamt.search_cost(m, 32) == 1  # absent, but its slot holds the leaf 0
    assert hamt.search_cost(m, 5) == 0  # an empty slot
    assert hamt.search_cost(m, -2) == 1  # first in its collision node
    assert hamt.search_cost(m, -1) == 2  # second
    assert hamt.search_cost(hamt.empty(), 3) == 0


def test_search_cost_collision_scan() -> None:
    m = build([(HKey(n, 0), n) for n in range(5)])
    assert [hamt.search_cost(m, HKey(n, 0)) for n in range(5)] == [1, 2, 3, 4, 5]
    assert hamt.search_cost(m, HKey(9, 0)) == 5  # absent with the same hash: the whole node
    assert hamt.search_cost(m, HKey(9, 32)) == 0  # same slot, different hash: no key test


@given(st.sampled_from(sorted(HASHES)), st.lists(st.integers(0, 40), max_size=30), st.integers(0, 40))
def test_search_cost_counts_equality_tests(hash_name: str, ns: list[int], probe: int) -> None:
    """``search_cost`` is exactly the number of ``==`` calls ``find`` makes (with an equal, non-identical probe)."""
    key = key_maker(hash_name)
    m = build([(key(n), n) for n in ns])
    k = key(probe)
    HKey.eq_calls = 0
    hamt.find(m, k)
    assert HKey.eq_calls == hamt.search_cost(m, k)


def test_counted_wrapper_uses_search_cost() -> None:
    stats = Stats()
    s = counted(hamt, stats)
    m = s.insert(s.empty(), -1, "a")  # empty map: 0 comparisons
    m = s.insert(m, -2, "b")  # meets leaf -1: 1
    assert s.find(m, -1) == ("a",)  # collision node, second: 2
    assert stats.dict_ops == 3 and stats.key_comparisons == 3
    s._check(m)


# -- _check catches broken tries ------------------------------------------------------


def broken(size: int, root: Any) -> HMap[Any, Any]:
    return HMap(size, root)


def _chain(levels: int, bottom: tuple[Any, ...]) -> tuple[Any, ...]:
    """``bottom`` under ``levels`` single-child nodes whose one child sits in slot 15 (a root in slot 14)."""
    node = bottom
    for _ in range(levels):
        node = (0, _BIT[15], node)
    return (0, _BIT[14], node)


@pytest.mark.parametrize(
    ("m", "message"),
    [
        (broken(1, (0b11, 0, 1, "a")), r"holds 2 item\(s\), not 4"),
        (broken(1, (0b100, 0, 1, "a")), "hash selects slot 1"),
        (broken(1, (1 << 16, 0, 1, "a")), "16-bit"),
        (broken(1, (0b1, 0b1, 0, "a", (0b1, 0, 0, "a"))), "both leaf and child"),
        (broken(1, (0, 0b1, (0b1, 0, 0, "a"))), "single leaf"),
        (broken(0, (0, 0b1, (0, 0))), "empty non-root node"),
        (broken(2, (0, 0b1, (0, 0b1, (0, 0, 0, 0, "a", P, "b")))), "single collision node"),
        (broken(1, (0, 0b1, (0, 0, 0, 0, "a"))), "not ≥ 2"),
        (broken(2, (0, 0b1, (0, 0, 0, P, "b", 0, "a"))), "before"),
        (broken(2, (0, 0b1, (0, 0, 0, 0, "a", 0, "b"))), "before"),
        (broken(2, (0, 0b1, (0, 0, 0, 0, "a", 1, "b"))), "is in the collision node of hash 0"),
        (broken(2, (0, 0b10, (0, 0, 0, 0, "a", P, "b"))), "collision node of hash 0 sits in slot 1"),
        (broken(2, (0, 0b1, (0, 0, 0, 0, "a", P))), "malformed"),
        (broken(3, (0b11, 0, 0, "a", 1, "b")), "stored size 3"),
        (broken(1, (0b11, 0, 0, "a", 1)), r"holds 3 item\(s\), not 4"),
        (broken(1, [0b1, 0, 0, "a"]), "not a bitmap node"),
        (broken(1, (0, 0b1, 7)), "is not a node"),
        (broken(2, _chain(16, (0b11, 0, 0, "a", 1, "b"))), "below the 16 levels"),
    ],
)
def test_check_detects_broken_tries(m: HMap[Any, Any], message: str) -> None:
    with pytest.raises(AssertionError, match=message):
        hamt._check(m)


def test_check_detects_flipped_bitmap_in_real_trie() -> None:
    m = build([(k, k) for k in range(200)])
    hamt._check(m)
    assert m.root[1] is _FULL
    child = m.root[2]  # the level-1 node under slot 0: the keys 0, 16, …, 192 as leaves
    assert child[1] == 0 and [k for k, _ in leaves(child)] == list(range(0, 200, 16))
    for bad in ((child[0] ^ 1, *child[1:]), (child[0] ^ (1 << 15), *child[1:]), (child[0], 0b1, *child[2:])):
        bad_root = (m.root[0], m.root[1], bad, *m.root[3:])
        with pytest.raises(AssertionError):
            hamt._check(HMap(m.size, bad_root))
    # A full nodemap must be the shared _FULL object (find tests it by identity).
    copied = int(str(_FULL))
    assert copied == _FULL and copied is not _FULL
    with pytest.raises(AssertionError, match="full nodemap that is not _FULL"):
        hamt._check(HMap(m.size, (m.root[0], copied, *m.root[2:])))


def test_full_nodes_share_the_full_bitmap() -> None:
    """Every nodemap with all 16 slots set, however it came about, is ``_FULL`` itself."""
    rng = random.Random(5)
    keys = list(range(3000))
    rng.shuffle(keys)
    m = build([(k, k) for k in keys])
    full = [node for _, node in nodes(m) if node[1] == _FULL]
    assert len(full) == 1 + 16 and all(node[1] is _FULL for node in full)  # the root and its 16 children
    for k in keys[:2000]:
        m, _ = hamt.remove(m, k)
    for k in keys[:2000]:
        m = hamt.insertWith(combine, m, k, k)
    hamt._check(m)
    assert all(node[1] is _FULL for _, node in nodes(m) if node[1] == _FULL)


def test_pickle_round_trip_keeps_full_nodes_shared() -> None:
    """Unpickled ints are new objects: the map rebuilds its full nodemaps as ``_FULL`` (``_check`` holds)."""
    m = build([(k, str(k)) for k in range(3000)] + [(-1, "a"), (-2, "b")])
    for copy in (pickle.loads(pickle.dumps(m)), copy_module.deepcopy(m), copy_module.copy(m)):
        assert type(copy) is HMap and copy == m
        hamt._check(copy)
        assert copy.root[1] is _FULL
        assert hamt.find(copy, 2999) == ("2999",) and hamt.find(copy, -2) == ("b",)
    assert pickle.loads(pickle.dumps(hamt.empty())) == hamt.empty()


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
    for make in (lambda: hamt.singleton(o, 1), lambda: hamt.insert(build([(1, 1)]), o, 1)):
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


# -- a 10^5-key workload ------------------------------------------------------------------


def test_workload_100k() -> None:
    rng = random.Random(2001)
    keys = list(range(100_000))
    rng.shuffle(keys)
    m = build([(k, -k) for k in keys])
    hamt._check(m)
    assert hamt.numItems(m) == 100_000
    assert depth(m) == 4  # 17 bits of hash: levels of 4, 4, 4, 4 and 1 bit
    gone = keys[::2]
    for k in gone:
        m, v = hamt.remove(m, k)
        assert v == -k
    hamt._check(m)
    kept = sorted(keys[1::2])
    assert m == build([(k, -k) for k in kept])
    assert all(hamt.find(m, k) == (-k,) for k in kept[:1000])
    assert all(hamt.find(m, k) is None for k in gone[:1000])
