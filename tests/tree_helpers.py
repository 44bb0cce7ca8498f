"""Reading red-black trees in tests: every node, and the shape in preorder (shared by the tree and complex tests)."""

from __future__ import annotations

from typing import Any


def nodes(t: Any) -> list[Any]:
    """Every node of the tree ``t`` (nodes ``(colour, left, key, value, right)``; any order)."""
    out, stack = [], [t]
    while stack:
        x = stack.pop()
        if x is not None:
            out.append(x)
            stack.append(x[1])
            stack.append(x[4])
    return out


def preorder(t: Any) -> list[Any]:
    """Every node's colour, key and value, and every leaf, in preorder: the tree's shape and contents."""
    out: list[Any] = []
    stack = [t]
    while stack:
        x = stack.pop()
        if x is None:
            out.append(None)
            continue
        out.append((x[0], x[2], x[3]))
        stack.append(x[4])
        stack.append(x[1])
    return out
