"""The hash array mapped trie: a persistent ``ORD_MAP`` after Bagwell (2001), *Ideal Hash Trees*.

One of the map backends the paper's simplicial complexes (§2) can be built on,
beside the red-black tree the paper uses and the association-list baseline.

A map is its number of items and a trie of **bitmap nodes**.  A bitmap node is
the pair ``(bitmap, array)``: bit ``b`` of the 32-bit ``bitmap`` is set when slot
``b`` is occupied, and ``array`` is a tuple holding only the occupied slots, in
slot order, two items per slot:

* ``key, value``          — a leaf;
* ``_BRANCH, node``       — a sub-trie (a bitmap node one level down);
* ``_COLLISION, cnode``   — a **collision node** ``(hash, array)``: two or more
  keys whose full hashes are equal, ``array = (k1, v1, k2, v2, …)`` in
  increasing key order.

At depth ``d`` a key's slot is bits ``5d … 5d+4`` of ``hash(key)``; the slot's
index in ``array`` is twice the number of bitmap bits below it
(``int.bit_count``), so a node spends memory only on what it holds.  On a
64-bit build Python's hashes have 64 bits (``sys.hash_info.width``), so two
different hashes part within 13 levels (levels 0–12; the last reads bits 60–63
and the sign); keys whose whole hashes are equal share a collision node, placed
where they would otherwise need a deeper node.

**Persistence** is by path copying: an operation rebuilds the ≤ 14 nodes on the
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
find, lookup, inDomain  O(log₃₂ n) expected   one key equality test (or a scan of a
                                              collision node)
insert, insertWith      O(log₃₂ n) expected   copies the path: ≤ 32 slots per node
remove                  O(log₃₂ n) expected   copies the path, pulls lone entries up
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
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from operator import itemgetter
from typing import Any, Generic, NamedTuple, Protocol, TypeAlias, TypeVar

from persistri.spec.option import Option
from persistri.spec.ord_map import NotFound
from persistri.spec.order import NATURAL_ORDER, Comparable, NaturalOrder

__all__ = ["HashKey", "HamtMap", "HMap", "hamt"]


class HashKey(Hashable, Comparable, Protocol):
    """A key the HAMT accepts: hashable (the trie is indexed by ``hash``) and ordered by ``<``."""


K = TypeVar("K", bound=HashKey)
V = TypeVar("V")
B = TypeVar("B")

_Array: TypeAlias = tuple[Any, ...]
"""A node's compact array: two items per occupied slot (see the module docstring)."""

_Node: TypeAlias = tuple[int, _Array]
"""A bitmap node ``(bitmap, array)`` or a collision node ``(hash, array)``."""


class _Tag:
    """A marker in a key position of an array: the next item is a node, not a value."""

    __slots__ = ("_name",)

    def __init__(self, name: str) -> None:
        self._name = name

    def __repr__(self) -> str:
        return self._name


# Neither tag orders against itself, so ``insert`` can never store one as a key.
_BRANCH = _Tag("_BRANCH")
_COLLISION = _Tag("_COLLISION")

_BITS = 5
_MASK = (1 << _BITS) - 1
_WIDTH = 1 << _BITS


class HMap(NamedTuple, Generic[K, V]):
    """A HAMT map value: its number of items and its root bitmap node.

    Only :class:`HamtMap`'s operations look inside; the fields are public for
    tests and teaching.  Two maps with the same items are equal (canonical form).
    """

    size: int
    """The number of items, so ``numItems`` is O(1)."""
    root: _Node
    """The root bitmap node (the only node allowed to be empty or to hold a single leaf)."""


_EMPTY_ROOT: _Node = (0, ())
# ``HMap(size, root)`` goes through NamedTuple's Python-level ``__new__``; the
# tuple constructor builds the same value several times faster.
_new_map = tuple.__new__
_first = itemgetter(0)


# -- errors at the API boundary -------------------------------------------------


def _unhashable(k: object) -> TypeError:
    return TypeError(f"hamt: key {k!r} of type {type(k).__name__} is not hashable")


def _unorderable(k: object) -> TypeError:
    return TypeError(f"hamt: key {k!r} of type {type(k).__name__} is not orderable (no '<')")


def _check_orderable(k: Any) -> None:
    """Reject a key that Python cannot order even against itself (e.g. ``object()``). O(1)."""
    try:
        k < k  # noqa: B015 - evaluated for its TypeError only
    except TypeError:
        raise _unorderable(k) from None


def _not_ordered(k: object, exc: TypeError) -> TypeError:
    return TypeError(f"hamt: key {k!r} is not ordered with the keys of this map ({exc})")


# -- node builders ----------------------------------------------------------------


def _split(shift: int, k1: Any, v1: Any, h1: int, k2: Any, v2: Any, h2: int) -> _Node:
    """The bitmap node at ``shift`` holding two entries whose hashes ``h1 != h2`` agree below ``shift``.

    While the two slots agree, each level is a node with a single ``_BRANCH``
    (canonical: the entries cannot part any sooner).  At most 13 levels.
    """
    s1 = (h1 >> shift) & _MASK
    s2 = (h2 >> shift) & _MASK
    if s1 == s2:
        return (1 << s1, (_BRANCH, _split(shift + _BITS, k1, v1, h1, k2, v2, h2)))
    if s1 < s2:
        return ((1 << s1) | (1 << s2), (k1, v1, k2, v2))
    return ((1 << s1) | (1 << s2), (k2, v2, k1, v1))


def _collision_pair(h: int, k1: Any, v1: Any, k2: Any, v2: Any) -> _Node:
    """The collision node of two different keys with the same hash ``h``, in key order."""
    try:
        first = k2 < k1
    except TypeError as exc:
        raise _not_ordered(k2, exc) from None
    return (h, (k2, v2, k1, v1) if first else (k1, v1, k2, v2))


def _collision_insert(
    cnode: _Node, k: Any, v: Any, f: Callable[[Any, Any], Any] | None
) -> tuple[_Node, bool]:
    """``cnode`` with ``k ↦ v`` (or ``f(old, v)``), and whether it grew. O(c) for c colliding keys."""
    h, array = cnode
    n = len(array)
    for j in range(0, n, 2):
        key = array[j]
        if key is k or key == k:
            new_v = v if f is None else f(array[j + 1], v)
            return (h, array[:j] + (k, new_v) + array[j + 2 :]), False
    _check_orderable(k)
    j = 0
    try:
        while j < n and array[j] < k:
            j += 2
    except TypeError as exc:
        raise _not_ordered(k, exc) from None
    return (h, array[:j] + (k, v) + array[j:]), True


def _collision_remove(cnode: _Node, k: Any) -> tuple[_Array, Any]:
    """The entry replacing ``cnode`` once ``k`` is removed, and ``k``'s value; :class:`NotFound` if absent.

    The entry is ``(_COLLISION, smaller node)``, or the leaf ``(key, value)`` when
    one key is left (canonical form).
    """
    h, array = cnode
    for j in range(0, len(array), 2):
        key = array[j]
        if key is k or key == k:
            rest = array[:j] + array[j + 2 :]
            if len(rest) == 2:
                return rest, array[j + 1]
            return (_COLLISION, (h, rest)), array[j + 1]
    raise NotFound(k)


def _items(root: _Node) -> list[tuple[Any, Any]]:
    """Every ``(key, value)`` of the trie, in trie order. O(n), iterative."""
    out: list[tuple[Any, Any]] = []
    stack = [root[1]]
    while stack:
        array = stack.pop()
        for j in range(0, len(array), 2):
            key = array[j]
            if key is _BRANCH:
                stack.append(array[j + 1][1])
            elif key is _COLLISION:
                carray = array[j + 1][1]
                out.extend(zip(carray[0::2], carray[1::2]))
            else:
                out.append((key, array[j + 1]))
    return out


def _sorted_items(root: _Node) -> list[tuple[Any, Any]]:
    """Every item in increasing key order: O(n log n) key comparisons (keys only, never values)."""
    items = _items(root)
    try:
        items.sort(key=_first)
    except TypeError as exc:
        raise TypeError(f"hamt: the keys of this map are not mutually ordered ({exc})") from None
    return items


# -- the structure ----------------------------------------------------------------


class HamtMap(Generic[K, V]):
    """``structure HamtMap : ORD_MAP``: Bagwell's hash array mapped trie (see the module docstring)."""

    __slots__ = ()

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
        try:
            h = hash(k)
        except TypeError:
            raise _unhashable(k) from None
        _check_orderable(k)
        return HMap(1, (1 << (h & _MASK), (k, v)))

    def insert(self, m: HMap[K, V], k: K, v: V, /) -> HMap[K, V]:
        """``m`` with ``k ↦ v`` (replacing key and value if ``k`` is present). O(log₃₂ n) expected."""
        return self._insert(m, k, v, None)

    def insertWith(self, f: Callable[[V, V], V], m: HMap[K, V], k: K, v: V, /) -> HMap[K, V]:
        """``m`` with ``k ↦ f(old, v)`` if ``k ↦ old`` is in ``m``, else ``k ↦ v``. O(log₃₂ n) expected."""
        return self._insert(m, k, v, f)

    def _insert(self, m: HMap[K, V], k: K, v: V, f: Callable[[V, V], V] | None) -> HMap[K, V]:
        """Path-copying insertion: walk down to ``k``'s slot, change it, rebuild the path upwards."""
        try:
            h = hash(k)
        except TypeError:
            raise _unhashable(k) from None
        size, (bitmap, array) = m
        path: list[tuple[int, _Array, int]] = []
        shift = 0
        while True:
            bit = 1 << ((h >> shift) & _MASK)
            i = (bitmap & (bit - 1)).bit_count() << 1
            if not bitmap & bit:
                try:
                    k < k  # noqa: B015 - the cheap orderability check, inlined on the hot path
                except TypeError:
                    raise _unorderable(k) from None
                bitmap |= bit
                array = array[:i] + (k, v) + array[i:]
                size += 1
                break
            key = array[i]
            if key is _BRANCH:
                path.append((bitmap, array, i))
                bitmap, array = array[i + 1]
                shift += _BITS
                continue
            # The slot is taken: compute its new (key, value) entry ...
            new_key: Any
            new_val: Any
            if key is _COLLISION:
                cnode = array[i + 1]
                if cnode[0] == h:
                    cnode, grew = _collision_insert(cnode, k, v, f)
                    new_key, new_val = _COLLISION, cnode
                    size += grew
                else:
                    _check_orderable(k)
                    new_key, new_val = _BRANCH, _split(shift + _BITS, _COLLISION, cnode, cnode[0], k, v, h)
                    size += 1
            elif key is k or key == k:
                new_key, new_val = k, (v if f is None else f(array[i + 1], v))
            else:
                _check_orderable(k)
                h2 = hash(key)
                if h2 == h:
                    new_key, new_val = _COLLISION, _collision_pair(h, key, array[i + 1], k, v)
                else:
                    new_key, new_val = _BRANCH, _split(shift + _BITS, key, array[i + 1], h2, k, v, h)
                size += 1
            # ... and store it in a copy: a list copy with items replaced beats slicing and concatenating.
            copy = list(array)
            copy[i] = new_key
            copy[i + 1] = new_val
            array = tuple(copy)
            break
        node: _Node = (bitmap, array)
        while path:
            bitmap, array, i = path.pop()
            copy = list(array)
            copy[i + 1] = node
            node = (bitmap, tuple(copy))
        return _new_map(HMap, (size, node))

    def find(self, m: HMap[K, V], k: K, /) -> Option[V]:
        """``(v,)`` if ``k ↦ v`` is in ``m``, else ``None``. O(log₃₂ n) expected, one equality test."""
        try:
            h = hash(k)
        except TypeError:
            raise _unhashable(k) from None
        bitmap, array = m[1]
        shift = 0
        while True:
            bit = 1 << ((h >> shift) & _MASK)
            if not bitmap & bit:
                return None
            i = (bitmap & (bit - 1)).bit_count() << 1
            key = array[i]
            if key is _BRANCH:
                bitmap, array = array[i + 1]
                shift += _BITS
            elif key is _COLLISION:
                ch, carray = array[i + 1]
                if ch != h:
                    return None
                for j in range(0, len(carray), 2):
                    ck = carray[j]
                    if ck is k or ck == k:
                        return (carray[j + 1],)
                return None
            elif key is k or key == k:
                return (array[i + 1],)
            else:
                return None

    def lookup(self, m: HMap[K, V], k: K, /) -> V:
        """The value of ``k``; raises :class:`NotFound` if absent. O(log₃₂ n) expected."""
        found = self.find(m, k)
        if found is None:
            raise NotFound(k)
        return found[0]

    def inDomain(self, m: HMap[K, V], k: K, /) -> bool:
        """Whether ``k`` is in ``m``. O(log₃₂ n) expected."""
        return self.find(m, k) is not None

    def remove(self, m: HMap[K, V], k: K, /) -> tuple[HMap[K, V], V]:
        """``(m without k, value of k)``; raises :class:`NotFound` if absent. O(log₃₂ n) expected.

        Keeps the canonical form: a non-root node left holding one leaf or one
        collision node is replaced, in its parent, by that entry, repeatedly up
        the path.
        """
        try:
            h = hash(k)
        except TypeError:
            raise _unhashable(k) from None
        size, (bitmap, array) = m
        path: list[tuple[int, _Array, int]] = []
        shift = 0
        while True:
            bit = 1 << ((h >> shift) & _MASK)
            if not bitmap & bit:
                raise NotFound(k)
            i = (bitmap & (bit - 1)).bit_count() << 1
            key = array[i]
            if key is _BRANCH:
                path.append((bitmap, array, i))
                bitmap, array = array[i + 1]
                shift += _BITS
                continue
            if key is _COLLISION:
                cnode = array[i + 1]
                if cnode[0] != h:
                    raise NotFound(k)
                entry, value = _collision_remove(cnode, k)
                copy = list(array)
                copy[i : i + 2] = entry
                array = tuple(copy)
            elif key is k or key == k:
                value = array[i + 1]
                bitmap ^= bit
                array = array[:i] + array[i + 2 :]
            else:
                raise NotFound(k)
            break
        while path:
            parent_bitmap, parent, i = path.pop()
            copy = list(parent)
            if len(array) == 2 and array[0] is not _BRANCH:
                # A non-root node left with a lone leaf or collision node: the entry moves up.
                copy[i] = array[0]
                copy[i + 1] = array[1]
            else:
                copy[i + 1] = (bitmap, array)
            bitmap, array = parent_bitmap, tuple(copy)
        return _new_map(HMap, (size - 1, (bitmap, array))), value

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
        try:
            h = hash(k)
        except TypeError:
            raise _unhashable(k) from None
        bitmap, array = m[1]
        shift = 0
        while True:
            bit = 1 << ((h >> shift) & _MASK)
            if not bitmap & bit:
                return 0
            i = (bitmap & (bit - 1)).bit_count() << 1
            key = array[i]
            if key is _BRANCH:
                bitmap, array = array[i + 1]
                shift += _BITS
            elif key is _COLLISION:
                ch, carray = array[i + 1]
                if ch != h:
                    return 0
                cost = 0
                for j in range(0, len(carray), 2):
                    cost += 1
                    ck = carray[j]
                    if ck is k or ck == k:
                        break
                return cost
            else:
                return 1

    def _check(self, m: HMap[K, V], /) -> None:
        """Assert every representation invariant, with a message naming the broken one.

        Bitmaps are 32-bit and their popcount is the array's number of entries;
        every key sits in the slot its hash bits select at each level; a
        collision node holds ≥ 2 keys, all of its hash, in strictly increasing
        order, in the slot its hash selects; no node is empty and no node holds
        a single leaf or a single collision node, except the root; the stored
        size is the real count; no key occurs twice.  O(n · depth).
        """
        assert isinstance(m, tuple) and len(m) == 2, f"hamt: a map is (size, root), got {m!r}"
        size, root = m
        keys: list[Any] = []
        # (node, shift, slots on the path to it); the root has shift 0 and no slots.
        stack: list[tuple[Any, int, tuple[int, ...]]] = [(root, 0, ())]
        while stack:
            node, shift, slots = stack.pop()
            where = f"node at slots {list(slots)}"
            assert isinstance(node, tuple) and len(node) == 2, f"hamt: {where} is not (bitmap, array): {node!r}"
            bitmap, array = node
            assert isinstance(bitmap, int) and 0 <= bitmap < (1 << _WIDTH), (
                f"hamt: {where} has bitmap {bitmap!r}, not a {_WIDTH}-bit natural number"
            )
            assert isinstance(array, tuple), f"hamt: {where} has array {array!r}, not a tuple"
            entries = len(array) // 2
            assert len(array) == 2 * bitmap.bit_count(), (
                f"hamt: {where} has bitmap {bitmap:#034b} with {bitmap.bit_count()} bits set "
                f"but its array holds {len(array) / 2:g} entries"
            )
            if slots:
                assert entries > 0, f"hamt: {where} is an empty non-root node"
                assert entries > 1 or array[0] is _BRANCH, (
                    f"hamt: {where} is a non-root node holding a single "
                    f"{'collision node' if array[0] is _COLLISION else 'leaf'} (it belongs in its parent)"
                )
            j = 0
            for slot in range(_WIDTH):
                if not bitmap >> slot & 1:
                    continue
                here = (*slots, slot)
                key, val = array[j], array[j + 1]
                j += 2
                if key is _BRANCH:
                    stack.append((val, shift + _BITS, here))
                elif key is _COLLISION:
                    assert isinstance(val, tuple) and len(val) == 2, (
                        f"hamt: collision node at slots {list(here)} is not (hash, array): {val!r}"
                    )
                    ch, carray = val
                    assert isinstance(carray, tuple) and len(carray) % 2 == 0, (
                        f"hamt: collision node at slots {list(here)} has a malformed array {carray!r}"
                    )
                    assert len(carray) >= 4, (
                        f"hamt: collision node at slots {list(here)} holds {len(carray) // 2} key(s), not ≥ 2"
                    )
                    _check_slots(ch, here, f"collision node of hash {ch!r}")
                    ckeys = carray[0::2]
                    for ck in ckeys:
                        assert hash(ck) == ch, (
                            f"hamt: key {ck!r} (hash {hash(ck)}) is in the collision node of hash {ch}"
                        )
                    for a, b in zip(ckeys, ckeys[1:]):
                        assert a < b, f"hamt: collision node at slots {list(here)} has {a!r} before {b!r}"
                    keys.extend(ckeys)
                else:
                    _check_slots(hash(key), here, f"key {key!r}")
                    keys.append(key)
        assert len(keys) == size, f"hamt: stored size {size} but the trie holds {len(keys)} keys"
        assert len(set(keys)) == len(keys), "hamt: a key occurs twice in the trie"

    def __repr__(self) -> str:
        return "hamt"


def _check_slots(h: int, slots: tuple[int, ...], what: str) -> None:
    """Assert that hash ``h`` selects ``slots`` level by level (the path an entry sits on)."""
    for depth, slot in enumerate(slots):
        want = (h >> (_BITS * depth)) & _MASK
        assert want == slot, (
            f"hamt: {what} sits in slot {slot} at depth {depth} but its hash selects slot {want} "
            f"(path {list(slots)})"
        )


hamt: HamtMap[Any, Any] = HamtMap()
"""The HAMT structure, polymorphic in keys and values."""
