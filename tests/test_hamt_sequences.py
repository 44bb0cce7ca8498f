"""The HAMT map (:mod:`persistri.impl.maps.hamt`) under operation sequences: every version kept, canonical form.

Random ``insert``/``insertWith``/``remove`` sequences, on Python ints and on
keys whose hashes collide fully or partly (:data:`hamt_helpers.HASHES`), are
checked step by step against a dict model: ``_check`` after every step, every
earlier version rechecked at the end (persistence), and the last version equal
to a fresh build of its items (canonical form).  Any history of deletions
leaves the shape of a direct build of the remaining keys, and so does deleting
half of a 10^5-key map.
"""

from __future__ import annotations

import operator
import random
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.maps.hamt import HMap, hamt
from persistri.spec.ord_map import NotFound

from hamt_helpers import HASHES, P, build, combine, depth, key_maker


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
