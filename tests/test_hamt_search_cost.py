"""The HAMT's ``search_cost`` (:mod:`persistri.impl.maps.hamt`): §4's key comparisons, as equality tests.

For a HAMT, §4's key comparisons are the key equality tests a search makes:
one at a leaf, one per key scanned in a collision node, none at an empty slot.
``search_cost`` is checked on small tries by hand, against the ``==`` calls
``find`` really makes (on keys of every hash family), and as what the
``counted`` wrapper adds to its statistics.
"""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.maps.counted import CountedOrdMap, counted
from persistri.impl.maps.hamt import hamt
from persistri.impl.stats import Stats

from hamt_helpers import HASHES, HKey, build, key_maker


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
    assert isinstance(s, CountedOrdMap)  # for mypy: _check is not part of ORD_MAP
    s._check(m)
