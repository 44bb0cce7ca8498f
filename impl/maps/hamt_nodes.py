"""The HAMT's nodes: their layout, the bit arithmetic that indexes them, and the functions that build them.

The node kinds (bitmap nodes with inline leaves and children, collision
nodes) and the canonical form are described in :mod:`persistri.impl.maps.hamt`,
whose :class:`~persistri.impl.maps.hamt.HamtMap` operations walk them.  This
module holds the layout constants (4 hash bits per level, the shared ``_FULL``
nodemap, precomputed bit masks), the map value :class:`HMap`, pickling, the
errors raised at the API boundary, and the path-copying node builders:
joining two entries, collision nodes, the one-descent update of
``insertWith``, and the listings.  Every function returns new tuples; none
mutates a node.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from operator import itemgetter
from typing import Any, Final, Generic, NamedTuple, Protocol, TypeAlias, TypeVar

from persistri.impl.maps.keys import check_orderable, check_sorted_strictly, unorderable
from persistri.spec.ord_map import NotFound
from persistri.spec.order import Comparable

__all__ = ["HashKey", "HMap"]


class HashKey(Hashable, Comparable, Protocol):
    """A key the HAMT accepts: hashable (the trie is indexed by ``hash``) and ordered by ``<``."""


K = TypeVar("K", bound=HashKey)
V = TypeVar("V")

_Node: TypeAlias = tuple[Any, ...]
"""A bitmap node ``(datamap, nodemap, k, v, …, children…)`` or a collision node ``(0, 0, hash, k, v, …)``."""

_BITS: Final = 4
"""Hash bits read per level."""
_WIDTH: Final = 1 << _BITS
"""Slots per node (16)."""
_MASK: Final = _WIDTH - 1
_LEVELS: Final = 16
"""Levels that separate any two different 64-bit hashes (64 / 4)."""
_FULL: Final = (1 << _WIDTH) - 1
"""The nodemap of a node whose every slot holds a child: always this very object (see :func:`_full`)."""
_BIT: Final = tuple(1 << s for s in range(_WIDTH))
"""``_BIT[s] = 2**s``: precomputed, so the hot paths allocate no int for it."""
_LOW: Final = tuple((1 << s) - 1 for s in range(_WIDTH))
"""``_LOW[s]``: the bits below slot ``s``, whose population count is the slot's position."""

_ENTRIES: Final = 2
"""Index of a bitmap node's first entry (after its two bitmaps): its first leaf, or its first child."""
_CKEYS: Final = 3
"""Index of a collision node's first key (after ``0, 0, hash``)."""


class HMap(NamedTuple, Generic[K, V]):
    """A HAMT map value: its number of items and its root bitmap node.

    Only :class:`HamtMap`'s operations look inside; the fields are public for
    tests and teaching.  Two maps with the same items are equal (canonical form).
    """

    size: int
    """The number of items, so ``numItems`` is O(1)."""
    root: _Node
    """The root bitmap node (the only node allowed to be empty or to hold a single leaf or collision node)."""

    def __reduce__(self) -> tuple[Callable[[int, _Node], HMap[K, V]], tuple[int, _Node]]:
        """Pickle as ``(size, root)``, rebuilt by :func:`_unpickle` (which restores the shared ``_FULL``)."""
        return (_unpickle, (self[0], self[1]))


_EMPTY_ROOT: _Node = (0, 0)
# ``HMap(size, root)`` goes through NamedTuple's Python-level ``__new__``; the
# tuple constructor builds the same value several times faster.
_new_map = tuple.__new__
_first = itemgetter(0)


def _full(nodemap: int) -> int:
    """``nodemap``, as the shared ``_FULL`` object when every slot is set (the identity test of ``find``)."""
    return _FULL if nodemap == _FULL else nodemap


def _interned(node: _Node) -> _Node:
    """``node`` with every full nodemap below it made the shared ``_FULL`` (an unpickled int is a new object)."""
    datamap, nodemap = node[0], node[1]
    if not (datamap or nodemap):  # a collision node, or the empty root
        return node
    split = (datamap.bit_count() << 1) + _ENTRIES
    return (datamap, _full(nodemap), *node[_ENTRIES:split], *map(_interned, node[split:]))


def _unpickle(size: int, root: _Node) -> HMap[Any, Any]:
    """The map ``(size, root)`` of a pickle, its full nodemaps shared again. O(n)."""
    return HMap(size, _interned(root))


class _Absent(Exception):
    """Raised by :func:`_update` when it cannot do the change in one descent: ``insertWith`` then inserts in full."""


# -- errors at the API boundary -------------------------------------------------


def _unhashable(k: object) -> TypeError:
    return TypeError(f"hamt: key {k!r} of type {type(k).__name__} is not hashable")


def _unorderable(k: object) -> TypeError:
    return unorderable("hamt", k)


def _check_orderable(k: Any) -> None:
    """Reject a key that Python cannot order even against itself (e.g. ``object()``). O(1)."""
    check_orderable("hamt", k)


def _not_ordered(k: object, exc: TypeError) -> TypeError:
    return TypeError(f"hamt: key {k!r} is not ordered with the keys of this map ({exc})")


def _hash(k: object) -> int:
    try:
        return hash(k)
    except TypeError:
        raise _unhashable(k) from None


# -- node builders ----------------------------------------------------------------


def _join(hx: int, x: _Node, h: int, k: Any, v: Any) -> _Node:
    """The bitmap node holding the entry ``x`` and the new leaf ``k ↦ v``, whose hashes differ.

    ``x`` is a leaf ``(key, value)`` or a collision node; ``hx`` and ``h`` are
    the two hashes shifted to this node's level.  While their slots agree, each
    level is a node with a single child (canonical: the entries cannot part any
    sooner).  At most 16 levels.
    """
    sx = hx & _MASK
    s = h & _MASK
    if sx == s:
        return (0, _BIT[s], _join(hx >> _BITS, x, h >> _BITS, k, v))
    bx, b = _BIT[sx], _BIT[s]
    if len(x) == 2:  # two leaves, in slot order
        return (bx | b, 0, *x, k, v) if sx < s else (bx | b, 0, k, v, *x)
    return (b, bx, k, v, x)


def _collision_pair(h: int, k1: Any, v1: Any, k2: Any, v2: Any) -> _Node:
    """The collision node of two different keys with the same hash ``h``, in key order."""
    try:
        first = k2 < k1
    except TypeError as exc:
        raise _not_ordered(k2, exc) from None
    return (0, 0, h, k2, v2, k1, v1) if first else (0, 0, h, k1, v1, k2, v2)


def _collision_insert(cnode: _Node, k: Any, v: Any, f: Callable[[Any, Any], Any]) -> tuple[_Node, bool]:
    """``cnode`` with ``k ↦ v`` (or ``f(old, v)``), and whether it grew. O(c) for c colliding keys."""
    n = len(cnode)
    for j in range(_CKEYS, n, 2):
        key = cnode[j]
        if key is k or key == k:
            return (*cnode[:j], k, f(cnode[j + 1], v), *cnode[j + 2 :]), False
    _check_orderable(k)
    j = _CKEYS
    try:
        while j < n and cnode[j] < k:
            j += 2
    except TypeError as exc:
        raise _not_ordered(k, exc) from None
    return (*cnode[:j], k, v, *cnode[j:]), True


def _collision_remove(cnode: _Node, k: Any) -> tuple[_Node, Any]:
    """The entry replacing ``cnode`` once ``k`` is removed, and ``k``'s value; :class:`NotFound` if absent.

    The entry is the smaller collision node, or the leaf ``(key, value)`` when
    one key is left (canonical form).
    """
    for j in range(_CKEYS, len(cnode), 2):
        key = cnode[j]
        if key is k or key == k:
            rest = cnode[:j] + cnode[j + 2 :]
            if len(rest) == _CKEYS + 2:
                return rest[_CKEYS:], cnode[j + 1]
            return rest, cnode[j + 1]
    raise NotFound(k)


def _child_to_leaf(node: _Node, j: int, s: int, k: Any, v: Any) -> _Node:
    """``node`` with its child at index ``j`` (slot ``s``) replaced by the leaf ``k ↦ v``."""
    datamap, nodemap = node[0], node[1]
    bit = _BIT[s]
    q = ((datamap & _LOW[s]).bit_count() << 1) + _ENTRIES  # after the leaves below slot s (q < j)
    return (datamap | bit, nodemap ^ bit, *node[_ENTRIES:q], k, v, *node[q:j], *node[j + 1 :])


def _replace(old: Any, new: Any) -> Any:
    """``insert``'s combining function: the new value replaces the old."""
    return new


def _update(node: _Node, h: int, k: Any, f: Callable[[Any, Any], Any], v: Any, grew: list[bool]) -> _Node:
    """``node`` with ``k ↦ f(old, v)`` if ``k ↦ old`` is a leaf, or the new leaf ``k ↦ v`` in an empty slot.

    The hot path of ``insertWith``: one descent, the path copied on the way
    back.  ``h`` is ``k``'s hash shifted to this level; a new leaf appends to
    ``grew`` (the caller's own list, so a reentrant ``f`` cannot disturb it).
    Where the change needs more (``k``'s slot holds another key, or a
    collision node, whose bitmaps are both 0), raises :class:`_Absent`.
    """
    # Literals 15, 4, 2 for _MASK, _BITS, _ENTRIES: a constant load is cheaper than a global one.
    nodemap = node[1]
    if nodemap is _FULL:
        j = (h & 15) + 2
    else:
        s = h & 15
        bit = _BIT[s]
        datamap = node[0]
        if datamap & bit:
            i = ((datamap & _LOW[s]).bit_count() << 1) + 2
            key = node[i]
            if key is k or key == k:
                # A list copy with items replaced beats slicing and concatenating.
                copy = list(node)
                copy[i] = k
                copy[i + 1] = f(node[i + 1], v)
                return tuple(copy)
            raise _Absent
        if not nodemap & bit:
            if not (datamap or nodemap):
                raise _Absent
            try:
                k < k  # noqa: B015 - the cheap orderability check of a new key
            except TypeError:
                raise _unorderable(k) from None
            grew.append(True)
            i = ((datamap & _LOW[s]).bit_count() << 1) + 2
            return (datamap | bit, nodemap, *node[2:i], k, v, *node[i:])
        j = (datamap.bit_count() << 1) + (nodemap & _LOW[s]).bit_count() + 2
    copy = list(node)
    copy[j] = _update(node[j], h >> 4, k, f, v, grew)
    return tuple(copy)


def _items(root: _Node) -> list[tuple[Any, Any]]:
    """Every ``(key, value)`` of the trie, in trie order. O(n), iterative."""
    out: list[tuple[Any, Any]] = []
    stack = [root]
    while stack:
        node = stack.pop()
        nodemap = node[1]
        if not (nodemap or node[0]):  # a collision node (or the empty root)
            out.extend(zip(node[_CKEYS::2], node[_CKEYS + 1 :: 2]))
            continue
        split = (node[0].bit_count() << 1) + _ENTRIES
        out.extend(zip(node[_ENTRIES:split:2], node[_ENTRIES + 1 : split : 2]))
        stack.extend(node[split:])
    return out


def _sorted_items(root: _Node) -> list[tuple[Any, Any]]:
    """Every item in increasing key order: O(n log n) key comparisons (keys only, never values)."""
    items = _items(root)
    try:
        items.sort(key=_first)
    except TypeError as exc:
        raise TypeError(f"hamt: the keys of this map are not mutually ordered ({exc})") from None
    check_sorted_strictly("hamt", [k for k, _ in items])
    return items
