"""The integer trie map: ``structure IntTrieMap : ORD_MAP`` for integer keys (a persistent radix trie).

The paper's simplicial complexes key their maps by vertex identifiers (§2),
and persistri's vertices are integers (:class:`~persistri.impl.complex.vertex.Vertex`
is an ``int``), mostly dense from 0.  This backend is specialised to such keys:
Bagwell's array-mapped trie without the hashing (the shape of Clojure's
``PersistentVector``), indexed by the key's own bits, 5 a level.  A search is
a few shifts and tuple indexings with no key comparison; a key's slot order is
its numeric order, so ``listItemsi`` walks the trie in order without sorting.

Representation
--------------
A map is ``(size, s, root, ns, nroot)``: the keys ``k ≥ 0`` in the trie
``root`` of height ``s`` at index ``k``, the keys ``k < 0`` in ``nroot`` of
height ``ns`` at index ``~k`` (``-k - 1``).  A trie of height ``s`` (a
multiple of 5) holds the indices below ``2**(s + 5)``; its nodes
(:mod:`persistri.impl.maps.int_trie_nodes`) are 32-slot tuples, a leaf the
33-tuple ``(keys, v0, …, v31)`` with its key objects in the shared tuple
``keys``.  Tuples are immutable, so no node of any version can ever change; an
operation builds new nodes along the paths it changes and shares the rest.

Invariants (checked by :meth:`IntTrieMap._check`):

1. every node has its layout (an internal node 32 slots, a leaf 33 with a
   32-slot ``keys`` tuple); a leaf slot holds a value exactly when its key
   slot holds a key, and that key is an ``int`` whose index is the slot's
   path;
2. no node is empty (an empty trie is ``None``, of height 0);
3. the height is the least that holds the largest index (a root of height
   above 0 has a child other than child 0);
4. the stored size is the number of keys.

Keys are Python integers (``int`` and its subclasses, such as persistri's
vertices); any other key is refused with a :class:`TypeError` naming the
backend.  Key objects are stored as given (``insert`` stores its ``k``).

=====================  ================  =========================================
operation              time              notes
=====================  ================  =========================================
find, lookup, inDomain O(b)              b = bits of ``|k|`` / 5 levels (3 levels
                                         below 32,768, 4 below 1,048,576)
insert, insertWith     O(b)              copies a 32-slot node a level, one descent
insert_absent          O(b)              ``insert`` of a key known absent
remove                 O(b)              a search, then the path copied (an emptied
                                         node dropped, the height lowered)
adjust_sorted          O(k + new nodes)  several keys in one descent, each node on
adjust_insert                            their paths copied once (persistri's
                                         addition for the 2-complex's ``replace``)
numItems, isEmpty      O(1)              the size is stored
listItemsi, foldli     O(n + nodes)      a walk in index order
=====================  ================  =========================================

Here b is the height of the trie: it depends on the largest key, not on the
number of keys, so sparse keys cost more nodes (up to one leaf a key).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final, Generic, TypeAlias, TypeVar

from persistri.impl.maps import int_trie_nodes as _t
from persistri.impl.maps.int_trie_absent import ABSENT
from persistri.impl.maps.int_trie_nodes import BITS, EMPTY_INNER, EMPTY_KEYS, MASK, Node
from persistri.impl.maps.int_trie_nodes import adjust_insert_map, adjust_sorted_map, find_unchecked
from persistri.impl.maps.int_trie_nodes import put_map
from persistri.spec.option import Option
from persistri.spec.ord_map import NotFound
from persistri.spec.order import NATURAL_ORDER, NaturalOrder

__all__ = ["IntTrieMap", "TrieMap", "int_trie", "NotAnIntKey"]

K = TypeVar("K", bound=int)
V = TypeVar("V")
B = TypeVar("B")

TrieMap: TypeAlias = tuple[int, int, "Node | None", int, "Node | None"]
"""An integer trie map: ``(size, height, root, negative keys' height, their root)``."""

_NAME: Final = "int_trie"
_EMPTY: Final[TrieMap] = (0, 0, None, 0, None)

_put: Callable[[TrieMap, int, Any, Callable[[Any, Any], Any] | None], TrieMap] = put_map
"""``m`` with ``k ↦ v`` (or ``f(old, v)`` when present and ``f`` given): the nodes' ``put_map``.  O(b)."""


class NotAnIntKey(TypeError):
    """A key that is not a Python integer, given to the integer trie."""


def _key(k: Any) -> int:
    """``k`` if it is an ``int`` (or a subclass), else :class:`NotAnIntKey` naming the backend.  O(1)."""
    if isinstance(k, int):
        return k
    raise NotAnIntKey(f"{_NAME}: key {k!r} of type {type(k).__name__} is not an int (this backend's keys are integers)")


def _shrink(t: Node | None, s: int) -> tuple[Node | None, int]:
    """The trie ``t`` of height ``s`` at its least height (invariant 3).  O(levels dropped)."""
    if t is None:
        return None, 0
    while s and all(c is None for c in t[1:]):
        t = t[0]
        s -= BITS
    return t, s


def _walk(t: Node | None, s: int, neg: bool, out: list[tuple[Any, Any]]) -> None:
    """Append the items of the trie ``t`` (height ``s``) to ``out`` in increasing key order (slot order for
    the keys ``≥ 0``, reversed for the negative ones).  O(items + nodes)."""
    if t is None:
        return
    if s == 0:
        ks = t[0]
        order = range(31, -1, -1) if neg else range(32)
        for i in order:
            if ks[i] is not None:
                out.append((ks[i], t[i + 1]))
        return
    order = range(31, -1, -1) if neg else range(32)
    for d in order:
        c = t[d]
        if c is not None:
            _walk(c, s - BITS, neg, out)


def _items(m: TrieMap) -> list[tuple[Any, Any]]:
    out: list[tuple[Any, Any]] = []
    _walk(m[4], m[3], True, out)
    _walk(m[2], m[1], False, out)
    return out


# -- the structure ------------------------------------------------------------------


class IntTrieMap(Generic[K, V]):
    """``structure IntTrieMap : ORD_MAP`` over integer keys: a persistent radix trie (module docstring)."""

    __slots__ = ()

    def __reduce__(self) -> str | tuple[type[IntTrieMap[K, V]], tuple[()]]:
        """Pickle the module's ``int_trie`` by name (complexes compare their backends by identity)."""
        return "int_trie" if self is int_trie else (type(self), ())

    name = _NAME

    @property
    def Key(self) -> NaturalOrder[Any]:
        """Keys are ordered by Python's natural order of integers."""
        return NATURAL_ORDER

    def empty(self) -> TrieMap:
        """The empty map. O(1)."""
        return _EMPTY

    def isEmpty(self, m: TrieMap, /) -> bool:
        """Whether ``m`` is empty. O(1)."""
        return m[0] == 0

    def singleton(self, k: K, v: V, /) -> TrieMap:
        """The map ``{k ↦ v}``: one path. O(b)."""
        return _put(_EMPTY, _key(k), v, None)

    def insert(self, m: TrieMap, k: K, v: V, /) -> TrieMap:
        """``m`` with ``k ↦ v``, replacing an earlier value of ``k`` (and its key object). O(b)."""
        return _put(m, _key(k), v, None)

    def insert_absent(self, m: TrieMap, k: K, v: V, /) -> TrieMap:
        """``insert`` of a key known absent (persistri's addition, for the 2-complex's ``replace``). O(b)."""
        return _put(m, k, v, None)

    def insertWith(self, f: Callable[[V, V], V], m: TrieMap, k: K, v: V, /) -> TrieMap:
        """``m`` with ``k ↦ f(old, v)`` if ``k ↦ old`` is in ``m``, else ``k ↦ v``: one descent.  O(b) plus one
        call of ``f``, whose exceptions propagate unchanged (``m`` unaffected)."""
        return _put(m, _key(k), v, f)

    adjust_sorted: Callable[..., tuple[Any, list[int], list[int]]] = staticmethod(adjust_sorted_map)
    """``adjust_sorted(f, m, keys, vals)`` → ``(m', absent, emptied)``, as the red-black map's
    (:meth:`~persistri.impl.maps.red_black.RedBlackMap.adjust_sorted`): the keys strictly increasing
    ints, nothing checked.  O(k + new nodes)."""

    adjust_insert: Callable[..., tuple[Any, list[int], list[int], bool]] = staticmethod(adjust_insert_map)
    """``adjust_insert(f, m, keys, vals, j, v)`` → ``(m', absent, emptied, inserted)``, as the red-black
    map's (:meth:`~persistri.impl.maps.red_black.RedBlackMap.adjust_insert`); an absent ``keys[j]`` is
    always inserted.  O(k + new nodes)."""

    find_unchecked = staticmethod(find_unchecked)
    """``find`` for a key known to be an ``int`` (the 2-complex's walks).  O(b)."""

    def find(self, m: TrieMap, k: K, /) -> Option[V]:
        """``(v,)`` if ``k ↦ v`` is in ``m``, else ``None``: :func:`find_unchecked` after the key's type
        test, written out (the 2-complex's look-ups).  O(b)."""
        i: Any = k
        if not isinstance(i, int):
            _key(i)
        if i >= 0:
            t: Any = m[2]
            s = m[1]
        else:
            t = m[4]
            s = m[3]
            i = ~i
        if t is None or i >> (s + 5):
            return None
        while s:
            t = t[(i >> s) & 31]
            if t is None:
                return None
            s -= 5
        v = t[(i & 31) + 1]
        return None if v is ABSENT else (v,)

    def lookup(self, m: TrieMap, k: K, /) -> V:
        """The value of ``k``; raises :class:`NotFound` if absent. O(b)."""
        found = find_unchecked(m, _key(k))
        if found is None:
            raise NotFound(k)
        return found[0]  # type: ignore[no-any-return]

    def inDomain(self, m: TrieMap, k: K, /) -> bool:
        """Whether ``k`` is in ``m``. O(b)."""
        return find_unchecked(m, _key(k)) is not None

    def remove(self, m: TrieMap, k: K, /) -> tuple[TrieMap, V]:
        """``(m without k, value of k)``; raises :class:`NotFound` if absent (``m`` unaffected).  O(b)."""
        found = find_unchecked(m, _key(k))
        if found is None:
            raise NotFound(k)
        n, s, root, ns, nroot = m
        if k >= 0:
            root, s = _shrink(_t.delete(root, s, k), s)  # type: ignore[arg-type]
        else:
            nroot, ns = _shrink(_t.delete(nroot, ns, ~k), ns)  # type: ignore[arg-type]
        return (n - 1, s, root, ns, nroot), found[0]

    def numItems(self, m: TrieMap, /) -> int:
        """The number of items. O(1)."""
        return m[0]

    def listItemsi(self, m: TrieMap, /) -> list[tuple[K, V]]:
        """The items in increasing key order. O(n + nodes)."""
        return _items(m)

    def listKeys(self, m: TrieMap, /) -> list[K]:
        """The keys in increasing order. O(n + nodes)."""
        return [k for k, _ in _items(m)]

    def foldli(self, f: Callable[[K, V, B], B], init: B, m: TrieMap, /) -> B:
        """``f`` folded over the items in increasing key order. O(n + nodes) and n calls of ``f``."""
        acc = init
        for k, v in _items(m):
            acc = f(k, v, acc)
        return acc

    # -- instrumentation and invariants ---------------------------------------

    def search_cost(self, m: TrieMap, k: K, /) -> int:
        """The trie nodes a search for ``k`` visits (the paper's §4 counts these as its key comparisons;
        a trie compares no keys, and this is the work that stands for them).  O(b)."""
        i = _key(k)
        t, s = (m[2], m[1]) if i >= 0 else (m[4], m[3])
        if i < 0:
            i = ~i
        if t is None or i >> (s + BITS):
            return 0
        cost = 1
        while s:
            t = t[(i >> s) & MASK]
            if t is None:
                break
            cost += 1
            s -= BITS
        return cost

    def _check(self, m: TrieMap, /) -> None:
        """Assert every representation invariant of ``m`` (module docstring).  O(n + nodes).

        Raises :class:`AssertionError` naming the first violation found.
        """
        assert isinstance(m, tuple) and len(m) == 5, f"{_NAME}: a map is (size, s, root, ns, nroot), got {m!r}"
        n, s, root, ns, nroot = m
        count = 0
        for t, h, neg in ((root, s, False), (nroot, ns, True)):
            assert isinstance(h, int) and h >= 0 and h % BITS == 0, f"{_NAME}: height {h!r} is not a multiple of {BITS}"
            if t is None:
                assert h == 0, f"{_NAME}: an empty trie of height {h}"
                continue
            if h:
                assert any(c is not None for c in t[1:]), f"{_NAME}: a root of height {h} with child 0 only"
            stack: list[tuple[Any, int, int]] = [(t, h, 0)]
            while stack:
                node, hh, prefix = stack.pop()
                assert isinstance(node, tuple), f"{_NAME}: a node is a tuple, got {node!r}"
                if hh == 0:
                    assert len(node) == 33, f"{_NAME}: a leaf has 33 slots, got {len(node)}"
                    ks = node[0]
                    assert isinstance(ks, tuple) and len(ks) == 32, f"{_NAME}: a leaf's keys are 32 slots"
                    held = 0
                    for i in range(32):
                        key, val = ks[i], node[i + 1]
                        assert (key is None) == (val is ABSENT), f"{_NAME}: slot {prefix | i} has a key xor a value"
                        if key is None:
                            continue
                        held += 1
                        assert isinstance(key, int), f"{_NAME}: key {key!r} is not an int"
                        index = ~key if neg else key
                        assert index == prefix | i, f"{_NAME}: key {key!r} at the index {prefix | i}"
                    assert held, f"{_NAME}: an empty leaf at index {prefix}"
                    count += held
                    continue
                assert len(node) == 32, f"{_NAME}: an internal node has 32 slots, got {len(node)}"
                children = [(d, c) for d, c in enumerate(node) if c is not None]
                assert children, f"{_NAME}: an empty node at index {prefix}, height {hh}"
                for d, c in children:
                    stack.append((c, hh - BITS, prefix | (d << hh)))
        assert count == n, f"{_NAME}: stored size {n} but {count} keys"
        assert EMPTY_INNER == (None,) * 32 and EMPTY_KEYS == (None,) * 32

    def __repr__(self) -> str:
        return _NAME


int_trie: IntTrieMap[Any, Any] = IntTrieMap()
"""The integer trie structure, polymorphic in values."""
