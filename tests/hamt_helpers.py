"""Looking inside HAMT tries in tests: keys with chosen hashes, the trie's nodes, and building maps.

Shared by the ``tests/test_hamt_*.py`` modules (not collected: no ``test_`` prefix).  :class:`HKey`
and :data:`HASHES` make full collisions, partial collisions and long shared hash prefixes on demand;
the node readers follow the layout of :mod:`persistri.impl.maps.hamt` (bitmap nodes
``(datamap, nodemap, k, v, …, children…)``, collision nodes ``(0, 0, hash, k, v, …)``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from persistri.impl.maps.hamt import HMap, hamt

P = 2**61 - 1
"""The modulus of Python's integer hash on 64-bit builds: ``hash(n + P) == hash(n)`` for n ≥ 0."""


def signed64(x: int) -> int:
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
    "shared-58-bits": lambda n: signed64(n << 58),
    "sign-bit-only": lambda n: signed64((n % 2) << 63) + 5,
    "identity": lambda n: n,
    "spread": lambda n: signed64(n * 0x9E3779B97F4A7C15),
}
"""Hash functions for :class:`HKey`: full collisions, partial collisions, long shared prefixes, spread."""


def key_maker(name: str) -> Callable[[int], HKey]:
    fn = HASHES[name]
    return lambda n: HKey(n, fn(n))


def combine(old: int, new: int) -> int:
    """Not commutative, so swapped arguments of ``insertWith``'s ``f`` show."""
    return old * 31 + new


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
