"""Independent views of red-black trees in tests: height, the height bound, shape, a small map.

Shared by the ``tests/test_red_black_*.py`` modules (not collected: no ``test_``
prefix); :mod:`tree_helpers` holds what the complex tests share with them (every
node of a tree, the preorder with values).  A node is ``(colour, left, key,
value, right)`` and a tree a node or ``None`` (:mod:`persistri.impl.maps.red_black`).
"""

from __future__ import annotations

import math
from typing import Any

from persistri.impl.maps.red_black import RBMap, Tree, red_black


def height(t: Tree[Any, Any]) -> int:
    """Nodes on the longest root-to-leaf path."""
    if t is None:
        return 0
    return 1 + max(height(t[1]), height(t[4]))


def check_all(m: RBMap[Any, Any]) -> None:
    """``_check`` plus the height bound the invariants imply."""
    red_black._check(m)
    n = red_black.numItems(m)
    assert height(m[1]) <= 2 * math.log2(n + 1), (n, height(m[1]))


def shape(t: Tree[Any, Any]) -> list[tuple[Any, Any]]:
    """Every node's ``(colour, key)`` and every leaf's ``(None, None)``, in preorder: the shape without the values."""
    if t is None:
        return [(None, None)]
    return [(t[0], t[2]), *shape(t[1]), *shape(t[4])]


def small_int_map() -> RBMap[int, int]:
    """The map ``{1: 1, 3: 3, 5: 5, 9: 9}``, inserted as 5, 1, 9, 3."""
    m: RBMap[int, int] = red_black.empty()
    for k in (5, 1, 9, 3):
        m = red_black.insert(m, k, k)
    return m
