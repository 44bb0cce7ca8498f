"""The red-black map (:mod:`persistri.impl.maps.red_black`) under operation sequences: invariants, every version.

Random ``insert``/``insertWith``/``remove`` sequences are checked against a dict
model with every version kept: after each step the tree passes ``_check`` and
the height bound its invariants imply (no path longer than 2·log2(n + 1)), and
at the end every earlier version is still intact and valid (persistence).  The
bound holds while a tree grows and shrinks to empty; Kahrs' deletion keeps the
invariants through the deletion of all 10^4 keys in three orders, and Okasaki's
insertion through 10^5 sequential keys.
"""

from __future__ import annotations

import random
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.maps.red_black import RBMap, red_black
from persistri.spec.ord_map import NotFound

from red_black_helpers import check_all

S = red_black


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
