"""Backend-specific tests of the red-black map (:mod:`persistri.impl.maps.red_black`).

The generic ``ORD_MAP`` laws run on every backend in the conformance suite;
these tests look inside the tree: its invariants after random operation
sequences, persistence of every version, the height bound, ``search_cost``
against an independent count, path copying, long deletion runs, that
``_check`` really rejects broken trees, and the errors bad keys raise.
"""

from __future__ import annotations

import math
import random
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.maps import backend
from tree_helpers import nodes
from persistri.impl.maps.red_black import BLACK, RED, RBMap, RedBlackMap, Tree, red_black
from persistri.spec.ord_map import NotFound, OrdMap

S = red_black

# A type-level check: the structure matches the ORD_MAP Protocol (mypy on this file).
_typed: OrdMap[int, str, RBMap[int, str]] = RedBlackMap[int, str]()


# -- independent views of a tree ------------------------------------------------


def height(t: Tree[Any, Any]) -> int:
    """Nodes on the longest root-to-leaf path."""
    if t is None:
        return 0
    return 1 + max(height(t[1]), height(t[4]))


def on_search_path(t: Tree[Any, Any], k: Any) -> int:
    """The nodes a search for ``k`` visits, counted without searching.

    A node is on the search path exactly when ``k`` lies strictly inside the
    key interval its ancestors allot to its subtree: that holds for every
    node above the one holding ``k`` (or above the leaf where ``k`` would go)
    and for that node itself, and for no other node.
    """
    count = 0
    stack: list[tuple[Tree[Any, Any], Any, Any]] = [(t, None, None)]
    while stack:
        x, lo, hi = stack.pop()
        if x is None:
            continue
        if (lo is None or lo < k) and (hi is None or k < hi):
            count += 1
        stack.append((x[1], lo, x[2]))
        stack.append((x[4], x[2], hi))
    return count


def check_all(m: RBMap[Any, Any]) -> None:
    """``_check`` plus the height bound the invariants imply."""
    S._check(m)
    n = S.numItems(m)
    assert height(m[1]) <= 2 * math.log2(n + 1), (n, height(m[1]))


def agrees(m: RBMap[Any, Any], model: dict[Any, Any]) -> None:
    assert S.numItems(m) == len(model)
    assert S.isEmpty(m) == (not model)
    assert S.listItemsi(m) == sorted(model.items())
    assert S.listKeys(m) == sorted(model)
    init: list[tuple[Any, Any]] = []
    assert S.foldli(lambda k, v, acc: acc + [(k, v)], init, m) == sorted(model.items())


# -- random operation sequences, every version kept ----------------------------------

KEYS = st.integers(min_value=0, max_value=60)
OPS = st.lists(
    st.tuples(st.sampled_from(["insert", "insertWith", "remove", "remove"]), KEYS, st.integers(-5, 5)),
    max_size=150,
)


def combine(old: int, new: int) -> int:
    return old * 7 + new


@given(OPS)
def test_random_operations_keep_invariants_and_every_version(ops: list[tuple[str, int, int]]) -> None:
    versions: list[tuple[RBMap[int, int], dict[int, int]]] = [(S.empty(), {})]
    for op, k, v in ops:
        m, model = versions[-1]
        if op == "insert":
            m2 = S.insert(m, k, v)
            model2 = {**model, k: v}
        elif op == "insertWith":
            m2 = S.insertWith(combine, m, k, v)
            model2 = {**model, k: combine(model[k], v) if k in model else v}
        elif k in model:
            m2, got = S.remove(m, k)
            assert got == model[k]
            model2 = {j: w for j, w in model.items() if j != k}
        else:
            with pytest.raises(NotFound):
                S.remove(m, k)
            m2, model2 = m, model
        check_all(m2)
        assert S.listItemsi(m2) == sorted(model2.items())
        versions.append((m2, model2))
    # Persistence: every earlier version is still intact and still valid.
    for m, model in versions:
        check_all(m)
        agrees(m, model)
        for k in range(-1, 62):
            assert S.find(m, k) == ((model[k],) if k in model else None)
            assert S.inDomain(m, k) == (k in model)


@given(st.lists(st.integers(), unique=True, max_size=400), st.randoms(use_true_random=False))
def test_height_bound_while_growing_and_shrinking(keys: list[int], rnd: random.Random) -> None:
    m: RBMap[int, None] = S.empty()
    for k in keys:
        m = S.insert(m, k, None)
        check_all(m)
    rnd.shuffle(keys)
    for k in keys:
        m, _ = S.remove(m, k)
        check_all(m)
    assert m == S.empty()


# -- search cost ---------------------------------------------------------------------


@given(st.lists(st.integers(0, 1000), max_size=300), st.lists(st.integers(-10, 1010), max_size=40))
def test_search_cost_is_the_search_path(keys: list[int], probes: list[int]) -> None:
    m: RBMap[int, int] = S.empty()
    for k in keys:
        m = S.insert(m, k, k)
    h = height(m[1])
    for k in probes + keys[:20]:
        cost = S.search_cost(m, k)
        assert cost == on_search_path(m[1], k)
        assert cost <= h
        if k in keys:
            assert cost >= 1


def test_search_cost_examples() -> None:
    m: RBMap[int, str] = S.empty()
    assert S.search_cost(m, 5) == 0
    for k in (2, 1, 3):
        m = S.insert(m, k, str(k))
    # 2 is the black root with red children 1 and 3.
    assert m[1] is not None and m[1][2] == 2
    assert S.search_cost(m, 2) == 1
    assert S.search_cost(m, 1) == 2
    assert S.search_cost(m, 0) == 2
    assert S.search_cost(m, 4) == 2


# -- path copying --------------------------------------------------------------------


@given(st.lists(st.integers(0, 2000), min_size=1, max_size=300), st.data())
def test_operations_copy_only_a_path(keys: list[int], data: st.DataObject) -> None:
    """Each operation allocates O(height) nodes and shares the rest with its argument."""
    m: RBMap[int, int] = S.empty()
    for k in keys:
        old = {id(x) for x in nodes(m[1])}
        m2 = S.insert(m, k, k)
        fresh = sum(id(x) not in old for x in nodes(m2[1]))
        # The copied search path plus at most one new sibling per rotation.
        assert fresh <= 2 * height(m2[1]), (fresh, height(m2[1]))
        m = m2
    for k in data.draw(st.lists(st.sampled_from(sorted(set(keys))), unique=True)):
        old = {id(x) for x in nodes(m[1])}
        m2, _ = S.remove(m, k)
        fresh = sum(id(x) not in old for x in nodes(m2[1]))
        # Kahrs' delete rebuilds a constant number of nodes per level of the old tree.
        assert fresh <= 4 * height(m[1]), (fresh, height(m[1]))
        m = m2


def test_replacing_a_value_copies_exactly_the_path() -> None:
    m: RBMap[int, str] = S.empty()
    for k in range(100):
        m = S.insert(m, k, "old")
    old = {id(x) for x in nodes(m[1])}
    for k in (0, 37, 99):
        m2 = S.insert(m, k, "new")
        assert sum(id(x) not in old for x in nodes(m2[1])) == S.search_cost(m, k)
        assert [c for c, *_ in _preorder(m2[1])] == [c for c, *_ in _preorder(m[1])]  # same shape and colours
        assert S.numItems(m2) == 100
        assert S.lookup(m2, k) == "new" and S.lookup(m, k) == "old"


def _preorder(t: Tree[Any, Any]) -> list[tuple[Any, Any]]:
    if t is None:
        return [(None, None)]
    return [(t[0], t[2]), *_preorder(t[1]), *_preorder(t[4])]


# -- long runs ------------------------------------------------------------------------

N_DELETE = 10_000


@pytest.mark.parametrize("order", ["ascending", "descending", "random"])
def test_deleting_every_key_keeps_invariants(order: str) -> None:
    keys = list(range(N_DELETE))
    m: RBMap[int, int] = S.empty()
    for k in random.Random(7).sample(keys, len(keys)):
        m = S.insert(m, k, -k)
    check_all(m)
    if order == "descending":
        keys.reverse()
    elif order == "random":
        random.Random(11).shuffle(keys)
    remaining = set(keys)
    for i, k in enumerate(keys):
        m, v = S.remove(m, k)
        assert v == -k
        remaining.discard(k)
        if i % 100 == 0:
            check_all(m)
            assert S.listKeys(m) == sorted(remaining)
    assert m == S.empty()


@pytest.mark.slow
def test_sequential_insert_of_100k_keys() -> None:
    n = 100_000
    m: RBMap[int, int] = S.empty()
    for k in range(n):
        m = S.insert(m, k, k)
    check_all(m)
    assert S.numItems(m) == n
    assert S.listKeys(m) == list(range(n))
    assert S.foldli(lambda k, v, acc: acc + 1, 0, m) == n


# -- _check rejects broken trees ---------------------------------------------------------


def leaf(k: int, colour: bool = RED) -> Tree[int, str]:
    return (colour, None, k, str(k), None)


VALID: RBMap[int, str] = (3, (BLACK, leaf(1), 2, "2", leaf(3)))


@pytest.mark.parametrize(
    ("m", "message"),
    [
        ((1, leaf(1)), "root is not black"),
        ((4, (BLACK, (RED, leaf(1), 2, "2", None), 3, "3", leaf(4))), "red node 2 has a red child 1"),
        ((2, (BLACK, leaf(1, BLACK), 2, "2", None)), "unequal black heights"),
        ((3, (BLACK, leaf(5), 3, "3", leaf(4))), "5 in the left subtree of 3"),
        # 7 is in order with its parent 1 but not with the root 5: a local check would miss it.
        (
            (4, (BLACK, (BLACK, None, 1, "1", leaf(7)), 5, "5", leaf(9, BLACK))),
            "7 in the left subtree of 5",
        ),
        ((3, (BLACK, leaf(2), 2, "2", leaf(3))), "2 in the left subtree of 2"),
        ((4, VALID[1]), "stored size 4 but 3 nodes"),
        ((3, (BLACK, ("red", None, 1, "1", None), 2, "2", leaf(3))), "colour 'red'"),
        ((3, (BLACK, (RED, None, 1), 2, "2", leaf(3))), "5-tuple"),
    ],
)
def test_check_detects_broken_trees(m: Any, message: str) -> None:
    with pytest.raises(AssertionError, match=message):
        S._check(m)


def test_check_accepts_valid_hand_built_trees() -> None:
    S._check(VALID)
    S._check(S.empty())
    S._check((4, (BLACK, (BLACK, None, 1, "1", leaf(3)), 5, "5", leaf(9, BLACK))))


# -- errors -------------------------------------------------------------------------------


def _int_map() -> RBMap[int, int]:
    m: RBMap[int, int] = S.empty()
    for k in (5, 1, 9, 3):
        m = S.insert(m, k, k)
    return m


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
    m = _int_map()
    before = S.listItemsi(m)
    with pytest.raises(TypeError, match=r"red_black: key .* is not ordered with the keys of this map") as info:
        call(m)
    # Raised from the public operation, not chained to the comparison deep inside.
    assert info.value.__cause__ is None and info.value.__suppress_context__
    S._check(m)
    assert S.listItemsi(m) == before


def test_insert_with_propagates_errors_of_f_unchanged() -> None:
    m = _int_map()

    def f(old: int, new: int) -> int:
        raise TypeError("f says no")

    with pytest.raises(TypeError, match="^f says no$"):
        S.insertWith(f, m, 3, 0)
    # Absent key: f is not called.
    assert S.lookup(S.insertWith(f, m, 4, 0), 4) == 0


def test_not_found() -> None:
    m = _int_map()
    with pytest.raises(NotFound):
        S.remove(m, 4)
    with pytest.raises(NotFound):
        S.remove(S.empty(), 4)
    with pytest.raises(KeyError):
        S.lookup(m, 4)
    S._check(m)
    assert S.listKeys(m) == [1, 3, 5, 9]


def test_insert_replaces_and_insert_with_combines() -> None:
    m = _int_map()
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
    assert [c for c, *_ in _preorder(out[1])] == [c for c, *_ in _preorder(m[1])]
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
    m = _int_map()
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
    m = _int_map()

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
        assert _preorder(got[1]) == _preorder(want[1]) and S.numItems(got) == S.numItems(want)
        assert sum(id(x) not in old for x in nodes(got[1])) == sum(id(x) not in old for x in nodes(want[1]))
    assert S.listItemsi(m) == before
