"""Persistence of the red-black map by path copying (:mod:`persistri.impl.maps.red_black`), counted by identity.

Every operation allocates O(height) new nodes and shares the rest with its
argument: an insertion copies the search path plus at most one sibling per
rotation, Kahrs' deletion a constant number of nodes per level, and replacing a
value copies exactly the search path and keeps the shape and colours.  New nodes
are the nodes of the result that are not (by ``id``) nodes of the argument.
"""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.maps.red_black import RBMap, red_black

from red_black_helpers import height, shape
from tree_helpers import nodes

S = red_black


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
        assert [c for c, *_ in shape(m2[1])] == [c for c, *_ in shape(m[1])]  # same shape and colours
        assert S.numItems(m2) == 100
        assert S.lookup(m2, k) == "new" and S.lookup(m, k) == "old"
