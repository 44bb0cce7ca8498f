"""The red-black tree in an append-only arena: ``ORD_MAP`` for keeping whole histories compactly (paper §2, §4).

The same tree as :mod:`persistri.impl.maps.red_black` — Okasaki's insertion,
Kahrs' deletion, the same shapes, colours and search paths, hence the same
key comparisons (§4) and the same number of new nodes per operation — stored
differently: a node is not a 5-tuple but an index into an :class:`Arena`, whose
node arrays hold its colour, its two children and its *item*, an index into
the arena's lists of keys and values.  A tuple node costs 80 bytes; an arena
node 13 (three 32-bit indices and a byte of colour), and a copied node keeps
its item, so a path copied for a new value costs one new item (16 bytes) and
13 bytes a level.  A history of versions keeps every node its operations
made, so this is the representation that makes a kept history small: the
full history of a 16K-point bulldozer hull holds a red-black node 19.5 times
per inserted point (docs/performance.md, "Memory of a full history").

Representation
--------------
A map value is an :class:`~persistri.impl.maps.red_black_arena_map.ArenaMap`:
one ``int``, ``number of items << 32 | root index``, whose class holds the arena
(one class per arena: a kept history holds one map value per version, about 56
bytes where a 3-tuple and its two ``int`` s took 128); the empty map is
``ArenaMap(0)`` (index 0 is the empty leaf, and an arena is made by the first
insertion).  Every map derived from one map shares its arena: operations
append the nodes they make and return a new root, as path copying does with
tuples.  **Nothing a returned map reaches is ever overwritten** (an operation
writes again only nodes it made itself, before returning: Okasaki's and
Kahrs' rewrites and a new root's blackening refill them instead of dropping
them; :meth:`ArenaRedBlackMap.adjust_insert_remove`'s deletions refill
the nodes its update made), so every
version ever returned stays valid: persistence by construction.  Along every path of a tree
the node indices decrease (a child is made before its parent), which
:meth:`ArenaRedBlackMap._check` checks with the red-black invariants of
:mod:`persistri.impl.maps.red_black`.

The trade
---------
**Nodes of dropped versions are not freed**: the arena only grows, and what it
holds is freed when no map of it remains.  Keeping every version (a history,
time travel) costs about a third of the tuple tree's memory; dropping old
versions as the algorithms go (the default, ``history=False``) keeps them all
anyway — a run that would free the tuple tree's old paths keeps their arena
nodes to the end.  So this is the backend for keeping histories, not the
default.  A failed operation (a combining function that raises, a key that
cannot be ordered) may leave unreachable nodes behind; they are never read.
Pickling a version pickles its whole arena.  One writer per arena at a time
(see :class:`~persistri.impl.maps.red_black_arena_tree.Arena`); readers are
free.  Time: each node field is a subscript of an array instead of a field of
a tuple (a key two: the node's item, then the key), and each new node four
appends; docs/performance.md has the
measured cost.

=====================  ==========  ==============================================
operation              time        notes
=====================  ==========  ==============================================
find, lookup, inDomain O(lg n)     one ``<`` a level (Andersson's descent)
insert, insert_absent  O(lg n)     O(lg n) new nodes, as the tuple tree
insertWith             O(lg n)     one descent when the key is present
adjust_many,           O(k lg n)   several keys in one descent (persistri's
adjust_sorted,                     addition, as the tuple tree's)
adjust_insert
adjust_insert_remove   O(k lg n)   adjust_insert, then its emptied keys removed,
                                   refilling the nodes the update made
remove                 O(lg n)     Kahrs' delete
numItems, isEmpty      O(1)        the size is stored
listItemsi, foldli     O(n)        iterative in-order walk
=====================  ==========  ==============================================
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final, Generic, TypeVar

from persistri.impl.maps import red_black_arena_adjust as _adjust
from persistri.impl.maps import red_black_arena_delete as _delete
from persistri.impl.maps import red_black_arena_tree as _tree
from persistri.impl.maps.keys import check_increasing, check_orderable, check_same_key, not_ordered_with
from persistri.impl.maps.red_black_arena_map import ONE, ArenaMap, map_class
from persistri.impl.maps.red_black_arena_tree import BLACK, NIL, RED, ROOT_BITS, ROOT_MASK, Arena, FailedWith
from persistri.spec.option import Option
from persistri.spec.ord_map import NotFound
from persistri.spec.order import NATURAL_ORDER, Comparable, NaturalOrder

__all__ = ["ArenaRedBlackMap", "ArenaMap", "Arena", "RED", "BLACK", "NIL", "red_black_arena"]

K = TypeVar("K", bound=Comparable)
V = TypeVar("V")
B = TypeVar("B")

_NAME: Final = "red_black_arena"

_EMPTY: Final = ArenaMap(0)


def _key_error(k: object, exc: TypeError) -> TypeError:
    return not_ordered_with(_NAME, k, exc)


def _check_orderable(k: Any) -> None:
    """Reject a key that Python cannot order even against itself (e.g. ``object()``)."""
    check_orderable(_NAME, k)


def _blacken_new(A: Arena, t: int) -> int:
    """The root ``t`` that the running operation made (no map refers to it yet), black: recoloured in place."""
    A.red[t] = BLACK
    return t


def _blacken(A: Arena, t: int, made: int) -> int:
    """The root ``t``, black: recoloured in place if it is red and the running operation made it (an index at
    least ``made``, the arena's length when the operation began: no map refers to it yet), else a black copy."""
    if A.red[t]:
        if t >= made:
            A.red[t] = BLACK
            return t
        return A.node(BLACK, A.left[t], A.item[t], A.right[t])
    return t


class ArenaRedBlackMap(Generic[K, V]):
    """``structure ArenaRedBlackMap : ORD_MAP``: persistent red-black trees in an append-only arena (module docstring).

    Keys must be totally ordered by Python's ``<`` among themselves; a key that
    cannot be compared with the map's keys raises :class:`TypeError` naming it.
    """

    __slots__ = ()

    def __reduce__(self) -> str | tuple[type[ArenaRedBlackMap[K, V]], tuple[()]]:
        """Pickle the module's ``red_black_arena`` by name, so that an unpickled complex (or map) is a value of
        *that* structure (complexes compare their backends by identity); another instance by its class."""
        return "red_black_arena" if self is red_black_arena else (type(self), ())

    name = _NAME

    @property
    def Key(self) -> NaturalOrder[Any]:
        """Keys are ordered by Python's natural order (``<``, ``==``)."""
        return NATURAL_ORDER

    def empty(self) -> ArenaMap:
        """The empty map (no arena yet). O(1)."""
        return _EMPTY

    def isEmpty(self, m: ArenaMap, /) -> bool:
        """Whether ``m`` is empty. O(1)."""
        return not m >> ROOT_BITS

    def singleton(self, k: K, v: V, /) -> ArenaMap:
        """The map ``{k ↦ v}``: one black node in a new arena. O(1)."""
        _check_orderable(k)
        A = Arena()
        return map_class(A)(ONE + A.node(BLACK, NIL, A.pair(k, v), NIL))

    def insert(self, m: ArenaMap, k: K, v: V, /) -> ArenaMap:
        """``m`` with ``k ↦ v``, replacing an earlier value of ``k`` (and its key object).

        Okasaki's insertion: O(lg n) time, O(lg n) new nodes.
        """
        t = m & ROOT_MASK
        A = m.arena
        if not t or A is None:
            _check_orderable(k)
            if A is None:
                A = Arena()
                return map_class(A)(ONE + A.node(BLACK, NIL, A.pair(k, v), NIL))
            return type(m)(m + ONE + A.node(BLACK, NIL, A.pair(k, v), NIL))
        try:
            new = _tree.ins(A, t, k, v)
        except TypeError as exc:
            raise _key_error(k, exc) from None
        if not new:  # present (ins checked that the key found is == k)
            return type(m)(m - t + _tree.replace(A, t, k, v))
        return type(m)(m - t + ONE + _blacken_new(A, new))

    def insert_absent(self, m: ArenaMap, k: K, v: V, /) -> ArenaMap:
        """``m`` with ``k ↦ v`` for a key known not to be in ``m`` and ordered with its keys: nothing is checked.

        As :meth:`~persistri.impl.maps.red_black.RedBlackMap.insert_absent`.  O(lg n).
        """
        t = m & ROOT_MASK
        A = m.arena
        if A is None:
            A = Arena()
            return map_class(A)(ONE + _blacken_new(A, _tree.ins_absent(A, t, k, v)))
        return type(m)(m - t + ONE + _blacken_new(A, _tree.ins_absent(A, t, k, v)))

    def insertWith(self, f: Callable[[V, V], V], m: ArenaMap, k: K, v: V, /) -> ArenaMap:
        """``m`` with ``k ↦ f(old, v)`` if ``k ↦ old`` is in ``m``, else ``k ↦ v``.

        O(lg n) plus one call of ``f``.  Exceptions raised by ``f`` propagate
        unchanged, and ``m`` is unaffected.  A present key costs one descent.
        """
        t = m & ROOT_MASK
        A = m.arena
        if not t or A is None:
            return self.insert(m, k, v)
        try:
            new = _tree.update(A, t, k, f, v)
        except FailedWith as failed:
            raise failed.exc from None
        except TypeError as exc:
            raise _key_error(k, exc) from None
        if not new:
            return self.insert(m, k, v)
        return type(m)(m - t + new)

    def adjust_many(
        self, f: Callable[[V, V], V], m: ArenaMap, items: list[tuple[K, V]], /
    ) -> tuple[ArenaMap, list[tuple[K, V]]]:
        """``(m', absent)``: ``m`` with ``k ↦ f(old, v)`` for each ``(k, v)`` of ``items`` whose key is in ``m``,
        and the items whose key is not (as :meth:`~persistri.impl.maps.red_black.RedBlackMap.adjust_many`:
        strictly increasing keys, else ValueError).  O(k + new nodes)."""
        t = m & ROOT_MASK
        A = m.arena
        check_increasing(_NAME, "adjust_many", items)
        if len(items) == 1:  # a NaN passes an order check of one key
            check_orderable(_NAME, items[0][0])
        if not t or A is None or not items:
            return m, list(items)
        keys = [k for k, _ in items]
        vals = [v for _, v in items]
        absent: list[int] = []
        try:
            new = _adjust.adjust(A, t, keys, vals, 0, len(keys), f, absent, [])
        except FailedWith as failed:
            raise failed.exc from None
        except TypeError as exc:
            raise _key_error(items[0][0], exc) from None
        return type(m)(m - t + new), [items[i] for i in absent]

    def adjust_sorted(
        self, f: Callable[[V, V], V], m: ArenaMap, keys: list[K], vals: list[V], /
    ) -> tuple[ArenaMap, list[int], list[int]]:
        """``(m', absent, emptied)``: :meth:`adjust_many` for keys known to be strictly increasing and ordered
        with the map's, nothing checked (as :meth:`~persistri.impl.maps.red_black.RedBlackMap.adjust_sorted`).
        O(k + new nodes)."""
        t = m & ROOT_MASK
        A = m.arena
        if not t or A is None or not keys:
            return m, list(range(len(keys))), []
        absent: list[int] = []
        emptied: list[int] = []
        try:
            new = _adjust.adjust(A, t, keys, vals, 0, len(keys), f, absent, emptied)
        except FailedWith as failed:
            raise failed.exc from None
        return type(m)(m - t + new), absent, emptied

    def adjust_insert(
        self, f: Callable[[V, V], V], m: ArenaMap, keys: list[K], vals: list[V], j: int, v: V, /
    ) -> tuple[ArenaMap, list[int], list[int], bool]:
        """``(m', absent, emptied, inserted)``: :meth:`adjust_sorted`, and ``keys[j] ↦ v`` inserted in the same
        descent if ``keys[j]`` is not in ``m`` (as :meth:`~persistri.impl.maps.red_black.RedBlackMap.adjust_insert`:
        the same trees as :meth:`adjust_sorted` then :meth:`insert_absent`).  O(k + new nodes)."""
        t = m & ROOT_MASK
        A = m.arena
        if not t or A is None or not keys:
            return m, list(range(len(keys))), [], False
        absent: list[int] = []
        emptied: list[int] = []
        new = [v]
        try:
            root = _adjust.adjust_insert(A, t, keys, vals, 0, len(keys), f, absent, emptied, j, new)
        except FailedWith as failed:
            raise failed.exc from None
        if new:
            return type(m)(m - t + root), absent, emptied, False
        return type(m)(m - t + ONE + _blacken_new(A, root)), absent, emptied, True

    def adjust_insert_remove(
        self, f: Callable[[V, V], V], m: ArenaMap, keys: list[K], vals: list[V], j: int, v: V, /
    ) -> tuple[ArenaMap, list[int], list[int], bool]:
        """:meth:`adjust_insert`, then, when no key is absent, its emptied keys removed (``emptied`` then empty):
        the trees of :meth:`adjust_insert` followed by :meth:`remove` of each emptied key in order.

        persistri's addition, for a 2-complex's ``replace`` (which removes the emptied vertices itself when
        some are absent, after inserting those).  The removals' Kahrs deletions refill in place the nodes the
        update made on their paths (no map refers to them yet), where :meth:`remove` would copy that path
        again: a full InBall 256K hull history holds 5.9 dropped nodes a point fewer (docs/performance.md,
        "Memory of a full history").  O(k + new nodes) plus O(lg n) a removed key."""
        A = m.arena
        made = len(A.item) if A is not None else 0  # nodes from here on are this operation's own
        m2, absent, emptied, inserted = self.adjust_insert(f, m, keys, vals, j, v)
        if not emptied or absent:
            return m2, absent, emptied, inserted
        assert A is not None
        root = m2 & ROOT_MASK
        n = m2 - root
        for i in emptied:
            root = _delete.delete(A, root, keys[i], made)
            root = _blacken(A, root, made) if root else NIL
        return type(m)(n - len(emptied) * ONE + root), absent, [], inserted

    def find(self, m: ArenaMap, k: K, /) -> Option[V]:
        """``(v,)`` if ``k ↦ v`` is in ``m``, else ``None``. O(lg n)."""
        t = m & ROOT_MASK
        A = m.arena
        if not t or A is None:
            return None
        try:
            node = _tree.search(A, t, k)
        except TypeError as exc:
            raise _key_error(k, exc) from None
        if not node:
            return None
        yi = A.item[node]
        check_same_key(_NAME, k, A.key[yi])
        return (A.val[yi],)

    find_unchecked = staticmethod(_tree.find)
    """``find`` for a key known to be ordered with the map's keys (a comparison's TypeError is not reworded):
    persistri's addition, for the 2-complex's walks."""

    def lookup(self, m: ArenaMap, k: K, /) -> V:
        """The value of ``k``; raises :class:`NotFound` if absent. O(lg n)."""
        found = self.find(m, k)
        if found is None:
            raise NotFound(k)
        value: V = found[0]
        return value

    def inDomain(self, m: ArenaMap, k: K, /) -> bool:
        """Whether ``k`` is in ``m``. O(lg n)."""
        return self.find(m, k) is not None

    def remove(self, m: ArenaMap, k: K, /) -> tuple[ArenaMap, V]:
        """``(m without k, value of k)``; raises :class:`NotFound` if absent (``m`` is unaffected).

        Kahrs' deletion after a search for the value: O(lg n) time, O(lg n) new nodes.
        """
        t = m & ROOT_MASK
        A = m.arena
        if not t or A is None:
            raise NotFound(k)
        try:
            node = _tree.search(A, t, k)
        except TypeError as exc:
            raise _key_error(k, exc) from None
        if not node:
            raise NotFound(k)
        check_same_key(_NAME, k, A.key[A.item[node]])
        value: V = A.val[A.item[node]]
        made = len(A.item)
        new = _delete.delete(A, t, k, made)
        return type(m)(m - t - ONE + (_blacken(A, new, made) if new else NIL)), value

    def numItems(self, m: ArenaMap, /) -> int:
        """The number of items. O(1)."""
        return m >> ROOT_BITS

    def _inorder(self, m: ArenaMap) -> list[int]:
        """The nodes of ``m`` in increasing key order.  O(n), iterative."""
        out: list[int] = []
        t, A = m & ROOT_MASK, m.arena
        if not t or A is None:
            return out
        left = A.left
        right = A.right
        stack: list[int] = []
        while True:
            while t:
                stack.append(t)
                t = left[t]
            if not stack:
                return out
            t = stack.pop()
            out.append(t)
            t = right[t]

    def listItemsi(self, m: ArenaMap, /) -> list[tuple[K, V]]:
        """The items in increasing key order. O(n), iterative."""
        A = m.arena
        if A is None:
            return []
        key = A.key
        val = A.val
        item = A.item
        return [(key[i], val[i]) for i in map(item.__getitem__, self._inorder(m))]

    def listKeys(self, m: ArenaMap, /) -> list[K]:
        """The keys in increasing order. O(n), iterative."""
        A = m.arena
        if A is None:
            return []
        key = A.key
        item = A.item
        return [key[item[t]] for t in self._inorder(m)]

    def foldli(self, f: Callable[[K, V, B], B], init: B, m: ArenaMap, /) -> B:
        """``f`` folded over the items in increasing key order. O(n) calls of ``f``, iterative."""
        acc = init
        A = m.arena
        if A is None:
            return acc
        key = A.key
        val = A.val
        item = A.item
        for t in self._inorder(m):
            i = item[t]
            acc = f(key[i], val[i], acc)
        return acc

    # -- instrumentation and invariants ---------------------------------------

    def search_cost(self, m: ArenaMap, k: K, /) -> int:
        """The key comparisons a search for ``k`` makes: the tree nodes on its search path (paper §4).

        The same count as the tuple tree's (the same tree).  O(lg n).
        """
        cost = 0
        t, A = m & ROOT_MASK, m.arena
        if A is None:
            return 0
        try:
            while t:
                cost += 1
                y = A.key[A.item[t]]
                if k < y:
                    t = A.left[t]
                elif y < k:
                    t = A.right[t]
                else:
                    break
        except TypeError as exc:
            raise _key_error(k, exc) from None
        return cost

    def _check(self, m: ArenaMap, /) -> None:
        """Assert every representation invariant of ``m``. O(n).

        The arena's node arrays are of one length and its item lists of
        another, with the empty leaf at 0; every node of the tree is in the
        arena and smaller than its parent's (made before it), and its item is
        in the arena; and the red-black invariants of
        :meth:`~persistri.impl.maps.red_black.RedBlackMap._check`: search
        order, no red node with a red child, equal black heights, a black root,
        the stored size.  Raises :class:`AssertionError` naming the first
        violation found.
        """
        assert isinstance(m, ArenaMap), f"{_NAME}: a map is an ArenaMap (size << 32 | root), got {m!r}"
        assert m >= 0, f"{_NAME}: a map's int is not negative, got {int(m)}"
        n, root, A = m >> ROOT_BITS, m & ROOT_MASK, m.arena
        if A is None:
            assert root == NIL and n == 0, f"{_NAME}: a map without an arena must be empty, got {m!r}"
            return
        assert isinstance(A, Arena), f"{_NAME}: the map class's arena is not an Arena: {A!r}"
        size = len(A.item)
        items = len(A.key)
        assert len(A.left) == len(A.right) == len(A.red) == size and len(A.val) == items, (
            f"{_NAME}: the arena's arrays have unequal lengths"
        )
        assert A.left[NIL] == NIL and A.right[NIL] == NIL and A.red[NIL] == BLACK and A.item[NIL] == 0, (
            f"{_NAME}: the empty leaf (index 0) has been written"
        )
        assert 0 <= root < size, f"{_NAME}: root {root} outside the arena of {size} nodes"
        assert not A.red[root], f"{_NAME}: the root is not black"
        count = 0
        leaf_blacks: int | None = None
        # (node, its parent's index, black nodes above it, lower bound, upper bound, key of its parent if red);
        # a bound or key is a 1-tuple so that None can mean "none" whatever the keys are.
        stack: list[tuple[int, int, int, tuple[Any] | None, tuple[Any] | None, tuple[Any] | None]] = [
            (root, size, 0, None, None, None)
        ]
        while stack:
            t, parent, blacks, lo, hi, red_parent = stack.pop()
            if not t:
                if leaf_blacks is None:
                    leaf_blacks = blacks
                assert blacks == leaf_blacks, (
                    f"{_NAME}: unequal black heights: {leaf_blacks} and {blacks} black nodes "
                    "on two root-to-leaf paths"
                )
                continue
            assert 0 < t < parent, f"{_NAME}: node {t} under node {parent}: a child must be made before its parent"
            i = A.item[t]
            assert 0 < i < items, f"{_NAME}: node {t} has item {i}, outside the arena's {items} items"
            c, k = A.red[t], A.key[i]
            assert c == RED or c == BLACK, f"{_NAME}: node {k!r} has colour {c!r}, not RED or BLACK"
            if lo is not None:
                assert lo[0] < k, f"{_NAME}: keys out of order: {k!r} in the right subtree of {lo[0]!r}"
            if hi is not None:
                assert k < hi[0], f"{_NAME}: keys out of order: {k!r} in the left subtree of {hi[0]!r}"
            if red_parent is not None:
                assert not c, f"{_NAME}: red node {red_parent[0]!r} has a red child {k!r}"
            count += 1
            below = blacks + (0 if c else 1)
            here = (k,) if c else None
            stack.append((A.right[t], t, below, (k,), hi, here))
            stack.append((A.left[t], t, below, lo, (k,), here))
        assert count == n, f"{_NAME}: stored size {n} but {count} nodes"

    def __repr__(self) -> str:
        return _NAME


red_black_arena: ArenaRedBlackMap[Any, Any] = ArenaRedBlackMap()
"""The arena red-black tree structure, polymorphic in keys and values."""
