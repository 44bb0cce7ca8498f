"""The red-black map's ``search_cost`` (:mod:`persistri.impl.maps.red_black`): the nodes a search visits.

§4 counts, for the red-black tree, the nodes visited.  ``search_cost`` is
checked against an independent count (the nodes whose ancestors' key interval
holds the key, found without searching), against the height, and on a small
tree by hand.
"""

from __future__ import annotations

from typing import Any

from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.maps.red_black import RBMap, Tree, red_black

from red_black_helpers import height

S = red_black


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
