"""The hash array mapped trie: a persistent ``ORD_MAP`` after Bagwell (2001), *Ideal Hash Trees*.

One of the map backends the paper's simplicial complexes (§2) can be built on,
beside the red-black tree the paper uses and the association-list baseline.

A map is its number of items and a trie of **bitmap nodes** indexed by the bits
of ``hash(key)``, 4 bits (16 slots) per level.  Following Steindorfer and
Vinju's refinement of Bagwell's node (CHAMP, OOPSLA 2015), a node carries two
16-bit bitmaps and one flat tuple::

    (datamap, nodemap, k_1, v_1, …, k_d, v_d, child_1, …, child_c)

* bit ``s`` of ``datamap`` is set when slot ``s`` holds a **leaf**, the pair
  ``k, v`` stored inline in the tuple;
* bit ``s`` of ``nodemap`` is set when slot ``s`` holds a **child**: a bitmap
  node one level down, or a **collision node** ``(0, 0, hash, k_1, v_1, …)``:
  two or more keys whose full hashes are equal, in increasing key order (both
  bitmaps 0, which no bitmap node but the empty root has);
* the bitmaps are disjoint; the leaves come first, then the children, each in
  slot order.  A slot's position is a population count (``int.bit_count``) of
  its bitmap below the slot, so a node spends memory only on what it holds:
  leaf ``s``'s key is at ``2 + 2·popcount(datamap & (2**s − 1))``, child ``s``
  at ``2 + 2·popcount(datamap) + popcount(nodemap & (2**s − 1))`` (leaves
  first: a search ends at a leaf once, but passes children at every level,
  and a full node has no leaves).

At depth ``d`` a key's slot is bits ``4d … 4d+3`` of ``hash(key)``.  Python's
hashes have 64 bits on a 64-bit build (``sys.hash_info.width``), so two
different hashes part within 16 levels (levels 0–15; the last reads bits 60–63
with the sign); keys whose whole hashes are equal share a collision node,
placed where they would otherwise need a deeper node.

Why this layout, measured on the 2-complex workload (``persistri bench
complex``): CPython pays for every int operation and for every item of a tuple
it copies.  Bagwell's single bitmap with tagged two-item entries paid for the
tag test and copied 2 items per child; two bitmaps tell leaves from children
with no tag, and a child costs one item.  16 slots instead of Bagwell's 32 keep
bitmaps below 2**30 (one-digit ints, the fast path of CPython's int
operations) and halve the tuples copied per level, for one more level per
16-fold growth.  A node whose 16 slots all hold children stores the module's
one ``_FULL`` int object as its nodemap (an invariant: every operation and
unpickling restore it), so a search recognises it by identity and indexes the
slot directly; the top levels of a large map are full.  ``insertWith`` of a
present key descends once and copies the path on the way back.

**Persistence** is by path copying: an operation rebuilds the ≤ 16 nodes on the
path to its key and shares every other node with the old version; no node of
any version is ever mutated (they are tuples).

**Canonical form.**  Every map has exactly one representation, whatever
sequence of ``insert`` and ``remove`` built it: for the keys that reach a slot,

* one key → a leaf;
* two or more keys, all with the same hash → a collision node (sorted);
* otherwise → a bitmap node one level down, built by the same rule.

So no node except the root is empty, no node except the root holds a single
leaf or a single collision node (``remove`` pulls such an entry up into the
parent), and a collision node left with one key becomes a leaf.  Canonical form
matters because it makes the shape a function of the key set: the cost of an
operation does not drift as a long-lived map is edited (no chains of
half-empty nodes left behind by deletions), two maps with the same items are
equal as values, and ``_check`` can verify the shape exactly.

======================  ====================  ======================================
operation               time                  notes
======================  ====================  ======================================
find, lookup, inDomain  O(log₁₆ n) expected   one key equality test (or a scan of a
                                              collision node)
insert, insertWith      O(log₁₆ n) expected   copies the path: ≤ 34 items per node;
                                              one descent for a present key or a
                                              new one in an empty slot
remove                  O(log₁₆ n) expected   copies the path, pulls lone entries up
numItems, isEmpty       O(1)                  the size is stored
listItemsi, listKeys,   O(n log n)            ``ORD_MAP`` lists in increasing key
foldli                                        order, so the items are sorted
======================  ====================  ======================================

The paper's §4 counts *key comparisons* of the dictionary code; for the HAMT
those are the key **equality tests** a search makes (:meth:`HamtMap.search_cost`):
one at a leaf, one per key scanned in a collision node, none where the slot is
empty or a collision node's hash differs.

Keys must be hashable (``TypeError`` otherwise) and ordered by ``<`` (the
listing sorts them).  ``insert`` checks cheaply that a new key orders against
itself (``k < k`` must not raise); keys of different types that each order
among themselves but not with each other (``1`` and ``"a"``) cannot be caught
at ``insert`` without an ordered structure, and are reported with a clear
``TypeError`` by the first operation that orders them (the listing, or an
insertion into the same collision node).  As for Python's ``dict``, equal keys
must have equal hashes, and equality (``==``) must agree with the order.

Where it lives: the node layout, its bit arithmetic and the path-copying node
builders in :mod:`~persistri.impl.maps.hamt_nodes` (with :class:`HMap` and
:class:`HashKey`, re-exported here); the exact check of every invariant in
:mod:`~persistri.impl.maps.hamt_check`; the ``ORD_MAP`` operations, which walk
the nodes, here.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Generic, TypeVar

from persistri.impl.maps.hamt_check import check as _check_map
from persistri.impl.maps.keys import not_totally_ordered
from persistri.impl.maps.hamt_nodes import (
    _BIT,
    _BITS,
    _CKEYS,
    _EMPTY_ROOT,
    _ENTRIES,
    _FULL,
    _LOW,
    _MASK,
    HashKey,
    HMap,
    _Absent,
    _check_orderable,
    _child_to_leaf,
    _collision_insert,
    _collision_pair,
    _collision_remove,
    _full,
    _hash,
    _join,
    _new_map,
    _Node,
    _replace,
    _sorted_items,
    _unhashable,
    _unorderable,
    _unpickle,  # noqa: F401 - pickles made before the split name persistri.impl.maps.hamt._unpickle
    _update,
)
from persistri.spec.option import Option
from persistri.spec.ord_map import NotFound
from persistri.spec.order import NATURAL_ORDER, NaturalOrder

__all__ = ["HashKey", "HamtMap", "HMap", "hamt"]

K = TypeVar("K", bound=HashKey)
V = TypeVar("V")
B = TypeVar("B")


def _refuse_nan(k: Any) -> None:
    """Refuse a new key unequal to itself (a NaN): hashing would keep each NaN apart, but no order can list them,
    and ``find`` could never reach one (a present key is found by ``is`` or ``==``). O(1)."""
    if k != k:
        raise not_totally_ordered("hamt", k, k)


class HamtMap(Generic[K, V]):
    """``structure HamtMap : ORD_MAP``: Bagwell's hash array mapped trie (see the module docstring)."""

    __slots__ = ()

    def __reduce__(self) -> str | tuple[type[HamtMap[K, V]], tuple[()]]:
        """Pickle the module's ``hamt`` by name, so that an unpickled complex (or map) is a value of
        *that* structure (complexes compare their backends by identity); another instance by its class."""
        return "hamt" if self is hamt else (type(self), ())

    name = "hamt"

    @property
    def Key(self) -> NaturalOrder[Any]:
        """Keys are ordered by Python's natural order (``<``, ``==``); the listing follows it."""
        return NATURAL_ORDER

    def empty(self) -> HMap[K, V]:
        """The empty map (an empty root). O(1)."""
        return HMap(0, _EMPTY_ROOT)

    def isEmpty(self, m: HMap[K, V], /) -> bool:
        """Whether ``m`` is empty. O(1)."""
        return m[0] == 0

    def singleton(self, k: K, v: V, /) -> HMap[K, V]:
        """The map ``{k ↦ v}``: a root holding one leaf. O(1)."""
        h = _hash(k)
        _check_orderable(k)
        return HMap(1, (_BIT[h & _MASK], 0, k, v))

    def insert(self, m: HMap[K, V], k: K, v: V, /) -> HMap[K, V]:
        """``m`` with ``k ↦ v`` (replacing key and value if ``k`` is present). O(log₁₆ n) expected."""
        return self.insertWith(_replace, m, k, v)

    def insertWith(self, f: Callable[[V, V], V], m: HMap[K, V], k: K, v: V, /) -> HMap[K, V]:
        """``m`` with ``k ↦ f(old, v)`` if ``k ↦ old`` is in ``m``, else ``k ↦ v``. O(log₁₆ n) expected.

        A key stored as a leaf, or an absent key whose slot is empty, costs one
        descent (:func:`_update`); a key meeting another key or a collision
        node, a second one (:meth:`_insert`).  Exceptions raised by ``f``
        propagate unchanged, and ``m`` is unaffected.
        """
        try:
            h = hash(k)
        except TypeError:
            raise _unhashable(k) from None
        grew: list[bool] = []
        try:
            root = _update(m[1], h, k, f, v, grew)
        except _Absent:
            return self._insert(m, k, v, f, h)
        if grew:
            _refuse_nan(k)
        return _new_map(HMap, (m[0] + 1 if grew else m[0], root))

    def _insert(self, m: HMap[K, V], k: K, v: V, f: Callable[[V, V], V], h0: int) -> HMap[K, V]:
        """Path-copying insertion: walk down to ``k``'s slot, change it, rebuild the path upwards."""
        _refuse_nan(k)
        size, node = m
        h = h0
        path: list[tuple[_Node, int]] = []
        while True:
            datamap = node[0]
            nodemap = node[1]
            s = h & _MASK
            bit = _BIT[s]
            if nodemap & bit:
                j = (datamap.bit_count() << 1) + (nodemap & _LOW[s]).bit_count() + _ENTRIES
                child = node[j]
                if child[1] or child[0]:  # a bitmap node: one level down
                    path.append((node, j))
                    node = child
                    h >>= _BITS
                    continue
                # A collision node in k's slot: k joins it, or they part one level down.
                if child[2] == h0:
                    child, grew = _collision_insert(child, k, v, f)
                    size += grew
                else:
                    _check_orderable(k)
                    child = _join(child[2] >> (_BITS * (len(path) + 1)), child, h >> _BITS, k, v)
                    size += 1
                copy = list(node)
                copy[j] = child
                node = tuple(copy)
                break
            i = ((datamap & _LOW[s]).bit_count() << 1) + _ENTRIES
            if datamap & bit:
                key = node[i]
                if key is k or key == k:
                    copy = list(node)
                    copy[i] = k
                    copy[i + 1] = f(node[i + 1], v)
                    node = tuple(copy)
                    break
                # Another key in k's slot: the leaf becomes a child holding both.
                _check_orderable(k)
                hk = hash(key)
                if hk == h0:
                    child = _collision_pair(h0, key, node[i + 1], k, v)
                else:
                    child = _join(hk >> (_BITS * (len(path) + 1)), (key, node[i + 1]), h >> _BITS, k, v)
                j = (datamap.bit_count() << 1) + (nodemap & _LOW[s]).bit_count() + _ENTRIES  # where the child goes
                node = (datamap ^ bit, _full(nodemap | bit), *node[_ENTRIES:i], *node[i + 2 : j], child, *node[j:])
                size += 1
                break
            try:
                k < k  # noqa: B015 - the cheap orderability check, inlined
            except TypeError:
                raise _unorderable(k) from None
            node = (datamap | bit, nodemap, *node[_ENTRIES:i], k, v, *node[i:])
            size += 1
            break
        while path:
            parent, j = path.pop()
            copy = list(parent)
            copy[j] = node
            node = tuple(copy)
        return _new_map(HMap, (size, node))

    def find(self, m: HMap[K, V], k: K, /) -> Option[V]:
        """``(v,)`` if ``k ↦ v`` is in ``m``, else ``None``. O(log₁₆ n) expected, one equality test."""
        try:
            h = hash(k)
        except TypeError:
            raise _unhashable(k) from None
        # Literals 15, 4, 2 for _MASK, _BITS, _ENTRIES: a constant load is cheaper than a global one.
        node = m[1]
        nodemap = node[1]
        while True:
            while nodemap is _FULL:  # the top levels of a large map: the slot is the child's index
                node = node[(h & 15) + 2]
                h >>= 4
                nodemap = node[1]
            s = h & 15
            bit = _BIT[s]
            datamap = node[0]
            if datamap & bit:
                i = ((datamap & _LOW[s]).bit_count() << 1) + 2
                key = node[i]
                if key is k or key == k:
                    return (node[i + 1],)
                return None
            if nodemap & bit:
                node = node[(datamap.bit_count() << 1) + (nodemap & _LOW[s]).bit_count() + 2]
                h >>= 4
                nodemap = node[1]
                continue
            if datamap or nodemap or len(node) == 2:  # an empty slot of a bitmap node (or the empty root)
                return None
            if node[2] != hash(k):  # a collision node of another hash
                return None
            for j in range(_CKEYS, len(node), 2):
                key = node[j]
                if key is k or key == k:
                    return (node[j + 1],)
            return None

    def lookup(self, m: HMap[K, V], k: K, /) -> V:
        """The value of ``k``; raises :class:`NotFound` if absent. O(log₁₆ n) expected."""
        found = self.find(m, k)
        if found is None:
            raise NotFound(k)
        return found[0]

    def inDomain(self, m: HMap[K, V], k: K, /) -> bool:
        """Whether ``k`` is in ``m``. O(log₁₆ n) expected."""
        return self.find(m, k) is not None

    def remove(self, m: HMap[K, V], k: K, /) -> tuple[HMap[K, V], V]:
        """``(m without k, value of k)``; raises :class:`NotFound` if absent. O(log₁₆ n) expected.

        Keeps the canonical form: a non-root node left holding one leaf or one
        collision node is replaced, in its parent, by that entry, repeatedly up
        the path; a collision node left with one key becomes a leaf.
        """
        h0 = _hash(k)
        size, node = m
        h = h0
        path: list[tuple[_Node, int, int]] = []  # (node, index of the child taken, its slot)
        value: Any
        while True:
            datamap = node[0]
            nodemap = node[1]
            s = h & _MASK
            bit = _BIT[s]
            if nodemap & bit:
                j = (datamap.bit_count() << 1) + (nodemap & _LOW[s]).bit_count() + _ENTRIES
                child = node[j]
                if child[1] or child[0]:  # a bitmap node: one level down
                    path.append((node, j, s))
                    node = child
                    h >>= _BITS
                    continue
                if child[2] != h0:
                    raise NotFound(k)
                entry, value = _collision_remove(child, k)
                if len(entry) == 2:  # one key left: the collision node becomes a leaf
                    node = _child_to_leaf(node, j, s, entry[0], entry[1])
                else:
                    copy = list(node)
                    copy[j] = entry
                    node = tuple(copy)
                break
            if datamap & bit:
                i = ((datamap & _LOW[s]).bit_count() << 1) + _ENTRIES
                key = node[i]
                if key is k or key == k:
                    value = node[i + 1]
                    node = (datamap ^ bit, nodemap, *node[_ENTRIES:i], *node[i + 2 :])
                    break
            raise NotFound(k)
        while path:
            parent, j, s = path.pop()
            if node[1] == 0 and len(node) == _ENTRIES + 2:
                # A non-root node left with a lone leaf: the leaf moves up.
                node = _child_to_leaf(parent, j, s, node[2], node[3])
                continue
            if node[0] == 0 and len(node) == _ENTRIES + 1 and not (node[2][0] or node[2][1]):
                node = node[2]  # a non-root node left with a lone collision node: it moves up
            copy = list(parent)
            copy[j] = node
            node = tuple(copy)
        return _new_map(HMap, (size - 1, node)), value

    def numItems(self, m: HMap[K, V], /) -> int:
        """The number of items. O(1)."""
        return m[0]

    def listItemsi(self, m: HMap[K, V], /) -> list[tuple[K, V]]:
        """The items in increasing key order. O(n log n): the trie is in hash order, so they are sorted."""
        return _sorted_items(m[1])

    def listKeys(self, m: HMap[K, V], /) -> list[K]:
        """The keys in increasing order. O(n log n)."""
        return [k for k, _ in _sorted_items(m[1])]

    def foldli(self, f: Callable[[K, V, B], B], init: B, m: HMap[K, V], /) -> B:
        """``f`` folded over the items in increasing key order. O(n log n), then n calls of ``f``."""
        acc = init
        for k, v in _sorted_items(m[1]):
            acc = f(k, v, acc)
        return acc

    # -- instrumentation and invariants ---------------------------------------

    def search_cost(self, m: HMap[K, V], k: K, /) -> int:
        """The key comparisons a search for ``k`` makes (paper §4, adapted to hashing): its equality tests.

        One at a leaf; one per key scanned in a collision node of ``k``'s hash;
        none where the slot is empty or a collision node's hash differs.
        Walks the same path as :meth:`find`.
        """
        h0 = _hash(k)
        h = h0
        node = m[1]
        while True:
            datamap, nodemap = node[0], node[1]
            if not (datamap or nodemap):  # a collision node, or the empty root
                if len(node) == 2 or node[2] != h0:
                    return 0
                cost = 0
                for j in range(_CKEYS, len(node), 2):
                    cost += 1
                    key = node[j]
                    if key is k or key == k:
                        break
                return cost
            s = h & _MASK
            if datamap & _BIT[s]:
                return 1
            if not nodemap & _BIT[s]:
                return 0
            node = node[(datamap.bit_count() << 1) + (nodemap & _LOW[s]).bit_count() + _ENTRIES]
            h >>= _BITS

    def _check(self, m: HMap[K, V], /) -> None:
        """Assert every representation invariant, with a message naming the broken one.

        See :func:`persistri.impl.maps.hamt_check.check`.  O(n · depth).
        """
        _check_map(m)

    def __repr__(self) -> str:
        return "hamt"


hamt: HamtMap[Any, Any] = HamtMap()
"""The HAMT structure, polymorphic in keys and values."""
