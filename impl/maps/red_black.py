"""The red-black tree map: ``structure RedBlackMap : ORD_MAP`` (Okasaki 1999, Kahrs 2001).

The paper's simplicial complexes are red-black trees keyed by vertex
identifiers (§2; §4 counts the tree nodes a search visits as key comparisons).
This module is that tree, persistent by construction.

Representation
--------------
A tree is ``None`` (the empty leaf, which counts as black) or a node, the
5-tuple ``(colour, left, key, value, right)`` with ``colour`` :data:`RED`
(``True``) or :data:`BLACK` (``False``).  Tuples are immutable, so no node of
any version can ever change; an operation builds new nodes along the search
path (*path copying*) and shares every other subtree with its argument.  A map
value is ``(number of items, tree)``, like SML/NJ's ``MAP of int * tree``, so
``numItems`` is O(1).

Invariants (checked by :meth:`RedBlackMap._check`):

1. search order: every key in a node's left subtree is below its key, every
   key in its right subtree above;
2. no red node has a red child;
3. every path from the root to a leaf has the same number of black nodes
   (the *black height*);
4. the root is black (insertion and deletion both blacken it at the end);
5. the stored size equals the number of nodes.

(2) and (3) bound the height by ``2·log2(n+1)``: a path alternates at worst
red and black, and a tree of black height ``b`` has at least ``2**b - 1``
nodes.

Algorithms
----------
* Search is the binary-tree descent, iterative, with one ``<`` per level
  (Andersson's: the last node not above the key is checked at the leaf).
* Insertion is Okasaki's (*Red-black trees in a functional setting*, JFP 9(4),
  1999): insert a red leaf, then on the way back up repair a red node with a
  red child under a black grandparent by one local rewrite, ``balance``.
* Deletion is Kahrs' (*Red-black trees with types*, JFP 11(4), 2001): the
  recursion removes the key from the subtree it came from; when that subtree
  was black, its black height dropped by one, and ``balleft``/``balright``
  restore it using the sibling; the deleted node's two subtrees are fused by
  ``app``.

=====================  ==========  ==============================================
operation              time        notes
=====================  ==========  ==============================================
find, lookup, inDomain O(lg n)     at most ``2·log2(n+1)`` nodes visited
insert                 O(lg n)     O(lg n) new nodes; a present key costs two descents
insert_absent          O(lg n)     for a key known absent: one comparison a level
insertWith             O(lg n)     one descent when the key is present (path copied
                                   back up), else a search and an insert
adjust_many             O(k lg n)   k present keys in one descent; shared path
                                   nodes copied once (persistri's addition;
                                   ``adjust_sorted``: the same, keys unchecked)
adjust_insert          O(k lg n)   ``adjust_sorted``, and one of the keys inserted
                                   in the same descent if absent
remove                 O(lg n)     one search for the value, then Kahrs' delete
numItems, isEmpty      O(1)        the size is stored
listItemsi, foldli     O(n)        iterative in-order walk
=====================  ==========  ==============================================

Why ``if`` chains instead of ``match``: Okasaki's ``balance`` reads as four
``case`` clauses, and a ``match`` statement over nested tuples transcribes it
literally; but measured at 10^5 random integer keys on CPython 3.11 the
``match`` insertion took more than twice as long as this one (≈69x the time
of a ``dict`` insert against ≈31x, CPU time, best of 3), outside the
project's performance target of 65x.  The
insertion here also knows which child it rebuilt, so it tests only the two
clauses that can apply on that side.  Each branch is commented with the
clause it implements.

Recursion depth is the tree height, at most ``2·log2(n+1)`` (34 at a million
keys), far below Python's recursion limit.

The algorithms over nodes are in :mod:`persistri.impl.maps.red_black_tree`
and, for several keys in one descent, :mod:`persistri.impl.maps.red_black_adjust`
and :mod:`persistri.impl.maps.red_black_adjust_insert` (the compiled twin compiles all
three); this module is the structure: the map
value, key validation, the signature's errors, the instrumentation and the
invariant check.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final, Generic, Optional, TypeAlias, TypeVar

from persistri.impl.maps import red_black_adjust as _adjust
from persistri.impl.maps import red_black_adjust_insert as _adjust_insert
from persistri.impl.maps import red_black_tree as _tree
from persistri.impl.maps.keys import check_increasing, check_orderable, check_same_key, not_ordered_with
from persistri.impl.maps.red_black_tree import BLACK, RED, FailedWith
from persistri.spec.option import Option
from persistri.spec.ord_map import NotFound
from persistri.spec.order import NATURAL_ORDER, Comparable, NaturalOrder

__all__ = ["RedBlackMap", "RBMap", "Tree", "Node", "RED", "BLACK", "red_black"]

K = TypeVar("K", bound=Comparable)
V = TypeVar("V")
B = TypeVar("B")


Node: TypeAlias = tuple[bool, "Tree[K, V]", K, V, "Tree[K, V]"]
"""A tree node: ``(colour, left, key, value, right)``."""

Tree: TypeAlias = Optional["Node[K, V]"]
"""A red-black tree: a :data:`Node` or ``None`` (the empty, black leaf)."""

RBMap: TypeAlias = tuple[int, "Tree[K, V]"]
"""A red-black map: ``(number of items, tree)``."""

_NAME: Final = "red_black"


def _key_error(k: object, exc: TypeError) -> TypeError:
    return not_ordered_with(_NAME, k, exc)


def _check_orderable(k: Any) -> None:
    """Reject a key that Python cannot order even against itself (e.g. ``object()``)."""
    check_orderable(_NAME, k)


# -- the structure ------------------------------------------------------------------


class RedBlackMap(Generic[K, V]):
    """``structure RedBlackMap : ORD_MAP``: persistent red-black trees (see the module docstring).

    Keys must be totally ordered by Python's ``<`` among themselves (``float('nan')``
    is not); a key that cannot be compared with the map's keys raises
    :class:`TypeError` naming it.
    """

    __slots__ = ()

    def __reduce__(self) -> str | tuple[type[RedBlackMap[K, V]], tuple[()]]:
        """Pickle the module's ``red_black`` by name, so that an unpickled complex (or map) is a value of
        *that* structure (complexes compare their backends by identity); another instance by its class."""
        return "red_black" if self is red_black else (type(self), ())

    name = _NAME

    @property
    def Key(self) -> NaturalOrder[Any]:
        """Keys are ordered by Python's natural order (``<``, ``==``)."""
        return NATURAL_ORDER

    def empty(self) -> RBMap[K, V]:
        """The empty map. O(1)."""
        return (0, None)

    def isEmpty(self, m: RBMap[K, V], /) -> bool:
        """Whether ``m`` is empty. O(1)."""
        return m[0] == 0

    def singleton(self, k: K, v: V, /) -> RBMap[K, V]:
        """The map ``{k ↦ v}``: one black node. O(1)."""
        _check_orderable(k)
        return (1, (BLACK, None, k, v, None))

    def insert(self, m: RBMap[K, V], k: K, v: V, /) -> RBMap[K, V]:
        """``m`` with ``k ↦ v``, replacing an earlier value of ``k`` (and its key object).

        Okasaki's insertion: O(lg n) time, O(lg n) new nodes.
        """
        n, t = m
        if t is None:
            _check_orderable(k)
            return (1, (BLACK, None, k, v, None))
        try:
            new = _tree.ins(t, k, v)
        except TypeError as exc:
            raise _key_error(k, exc) from None
        if new is None:  # present (ins checked that the key found is == k)
            return (n, _tree.replace(t, k, v))
        if new[0] is RED:
            new = (BLACK, new[1], new[2], new[3], new[4])
        return (n + 1, new)

    def insert_absent(self, m: RBMap[K, V], k: K, v: V, /) -> RBMap[K, V]:
        """``m`` with ``k ↦ v`` for a key known not to be in ``m`` and ordered with its keys: nothing is checked.

        persistri's addition, for the 2-complex's ``replace``, which inserts the
        vertices ``adjust_sorted`` has just reported absent: Okasaki's insertion
        with one comparison a level (:func:`~persistri.impl.maps.red_black_tree.ins_absent`).
        A present key would be stored twice.  O(lg n).
        """
        n, t = m
        new = _tree.ins_absent(t, k, v)
        if new[0] is RED:
            new = (BLACK, new[1], new[2], new[3], new[4])
        return (n + 1, new)

    def insertWith(self, f: Callable[[V, V], V], m: RBMap[K, V], k: K, v: V, /) -> RBMap[K, V]:
        """``m`` with ``k ↦ f(old, v)`` if ``k ↦ old`` is in ``m``, else ``k ↦ v``.

        O(lg n) plus one call of ``f``.  Exceptions raised by ``f`` propagate unchanged, and ``m`` is unaffected.
        A present key costs one descent (:func:`_update`): the path is copied on
        the way back up, keeping shape and colours; an absent key (the descent
        ends at a leaf) costs a second descent, Okasaki's insertion.
        """
        n, t = m
        if t is None:
            return self.insert(m, k, v)
        try:
            new = _tree.update(t, k, f, v)
        except FailedWith as failed:
            raise failed.exc from None
        except TypeError as exc:
            raise _key_error(k, exc) from None
        if new is None:
            return self.insert(m, k, v)
        return (n, new)

    def adjust_many(
        self, f: Callable[[V, V], V], m: RBMap[K, V], items: list[tuple[K, V]], /
    ) -> tuple[RBMap[K, V], list[tuple[K, V]]]:
        """``(m', absent)``: ``m`` with ``k ↦ f(old, v)`` for each ``(k, v)`` of ``items`` whose key is in ``m``,
        and the items whose key is not (in their order; ``m'`` has nothing for them).

        persistri's addition to ``ORD_MAP`` (the 2-complex's ``replace`` uses it
        when the backend has it): ``insertWith`` at several present keys in one
        descent.  ``items`` must have strictly increasing keys (ValueError
        otherwise).  Where the keys' search paths share nodes each shared node is
        copied once, so k keys that are near in key order cost about
        ``lg n + k·lg(n/k)`` new nodes instead of ``k·lg n``; far-apart keys cost
        what k ``insertWith`` cost.  Exceptions raised by ``f`` propagate
        unchanged, and ``m`` is unaffected.  O(k + new nodes) time.
        """
        n, t = m
        check_increasing(_NAME, "adjust_many", items)
        if len(items) == 1:  # a NaN passes an order check of one key
            check_orderable(_NAME, items[0][0])
        if t is None or not items:
            return m, list(items)
        keys = [k for k, _ in items]
        vals = [v for _, v in items]
        absent: list[int] = []
        try:
            new = _adjust.adjust(t, keys, vals, 0, len(keys), f, absent, [])
        except FailedWith as failed:
            raise failed.exc from None
        except TypeError as exc:
            raise _key_error(items[0][0], exc) from None
        return (n, new), [items[i] for i in absent]

    adjust_sorted: Callable[..., tuple[Any, list[int], list[int]]] = staticmethod(_adjust.adjust_sorted_map)
    """``adjust_sorted(f, m, keys, vals)`` → ``(m', absent, emptied)``: :meth:`adjust_many` of the items
    ``(keys[i], vals[i])``, for keys known to be strictly increasing and ordered with the map's: nothing is
    checked (a comparison's TypeError is not reworded).  ``absent``: the indices of the keys not in ``m``;
    ``emptied``: those whose new value ``f(old, vals[i])`` is falsy (an emptied collection, which the caller
    may then remove).

    persistri's addition, for the 2-complex's ``replace``, which sorts the
    vertices it touches itself and removes a vertex whose list it emptied.
    Exceptions raised by ``f`` propagate unchanged.  O(k + new nodes).  A static
    method, :func:`~persistri.impl.maps.red_black_adjust.adjust_sorted_map`: in the
    compiled twin a call of it runs no interpreted code."""

    adjust_insert: Callable[..., tuple[Any, list[int], list[int], bool]] = staticmethod(_adjust_insert.adjust_insert_map)
    """``adjust_insert(f, m, keys, vals, j, v)`` → ``(m', absent, emptied, inserted)``: :meth:`adjust_sorted`,
    and ``keys[j] ↦ v`` inserted in the same descent if ``keys[j]`` is not in ``m`` (``inserted`` says
    whether it was).

    persistri's addition, for the 2-complex's ``replace`` of a star by a cone
    from a new vertex, which updates the lists of the vertices it touches and
    adds the new vertex: where :meth:`adjust_sorted` and then :meth:`insert_absent`
    descend twice through the top of the tree, this copies it once
    (:func:`~persistri.impl.maps.red_black_adjust_insert.adjust_insert`).  The result
    is exactly theirs: the same shape and colours, the same number of new
    nodes.  Unchecked as :meth:`adjust_sorted` (``0 ≤ j < len(keys)``).  A
    present ``keys[j]`` is updated by ``f`` like the other keys; one absent
    together with other keys that end at the same leaf (or in an empty map) is
    not inserted but listed in ``absent`` with them.  O(k + new nodes).  A static
    method, :func:`~persistri.impl.maps.red_black_adjust_insert.adjust_insert_map`."""

    def find(self, m: RBMap[K, V], k: K, /) -> Option[V]:
        """``(v,)`` if ``k ↦ v`` is in ``m``, else ``None``. O(lg n)."""
        try:
            node: Tree[K, V] = _tree.search(m[1], k)
        except TypeError as exc:
            raise _key_error(k, exc) from None
        if node is None:
            return None
        check_same_key(_NAME, k, node[2])
        return (node[3],)

    find_unchecked = staticmethod(_tree.find)
    """``find`` for a key known to be ordered with the map's keys (a comparison's TypeError is not reworded):
    persistri's addition, for the 2-complex's walks, whose vertices are validated before; in the compiled
    twin a call of it runs no interpreted code."""

    def lookup(self, m: RBMap[K, V], k: K, /) -> V:
        """The value of ``k``; raises :class:`NotFound` if absent. O(lg n)."""
        try:
            node: Tree[K, V] = _tree.search(m[1], k)
        except TypeError as exc:
            raise _key_error(k, exc) from None
        if node is None:
            raise NotFound(k)
        check_same_key(_NAME, k, node[2])
        return node[3]

    def inDomain(self, m: RBMap[K, V], k: K, /) -> bool:
        """Whether ``k`` is in ``m``. O(lg n)."""
        try:
            node: Tree[K, V] = _tree.search(m[1], k)
        except TypeError as exc:
            raise _key_error(k, exc) from None
        if node is None:
            return False
        check_same_key(_NAME, k, node[2])
        return True

    def remove(self, m: RBMap[K, V], k: K, /) -> tuple[RBMap[K, V], V]:
        """``(m without k, value of k)``; raises :class:`NotFound` if absent (``m`` is unaffected).

        Kahrs' deletion after a search for the value: O(lg n) time, O(lg n) new nodes.
        """
        n, t = m
        try:
            node = _tree.search(t, k)
        except TypeError as exc:
            raise _key_error(k, exc) from None
        if node is None:
            raise NotFound(k)
        check_same_key(_NAME, k, node[2])
        new = _tree.delete(t, k)
        if new is not None and new[0] is RED:
            new = (BLACK, new[1], new[2], new[3], new[4])
        return (n - 1, new), node[3]

    def numItems(self, m: RBMap[K, V], /) -> int:
        """The number of items. O(1)."""
        return m[0]

    def listItemsi(self, m: RBMap[K, V], /) -> list[tuple[K, V]]:
        """The items in increasing key order. O(n), iterative."""
        out: list[tuple[K, V]] = []
        stack: list[Node[K, V]] = []
        t = m[1]
        while True:
            while t is not None:
                stack.append(t)
                t = t[1]
            if not stack:
                return out
            node = stack.pop()
            out.append((node[2], node[3]))
            t = node[4]

    def listKeys(self, m: RBMap[K, V], /) -> list[K]:
        """The keys in increasing order. O(n), iterative."""
        out: list[K] = []
        stack: list[Node[K, V]] = []
        t = m[1]
        while True:
            while t is not None:
                stack.append(t)
                t = t[1]
            if not stack:
                return out
            node = stack.pop()
            out.append(node[2])
            t = node[4]

    def foldli(self, f: Callable[[K, V, B], B], init: B, m: RBMap[K, V], /) -> B:
        """``f`` folded over the items in increasing key order. O(n) calls of ``f``, iterative."""
        acc = init
        stack: list[Node[K, V]] = []
        t = m[1]
        while True:
            while t is not None:
                stack.append(t)
                t = t[1]
            if not stack:
                return acc
            node = stack.pop()
            acc = f(node[2], node[3], acc)
            t = node[4]

    # -- instrumentation and invariants ---------------------------------------

    def search_cost(self, m: RBMap[K, V], k: K, /) -> int:
        """The key comparisons a search for ``k`` makes: the tree nodes on its search path (paper §4).

        Counts the nodes visited down to the node holding ``k`` (included) or to
        a leaf; at most the height of the tree, so O(lg n).
        """
        cost = 0
        t = m[1]
        try:
            while t is not None:
                cost += 1
                y = t[2]
                if k < y:
                    t = t[1]
                elif y < k:
                    t = t[4]
                else:
                    break
        except TypeError as exc:
            raise _key_error(k, exc) from None
        return cost

    def _check(self, m: RBMap[K, V], /) -> None:
        """Assert every representation invariant of ``m`` (see the module docstring). O(n).

        Raises :class:`AssertionError` naming the first violation found: a
        malformed node, keys out of search order, a red node with a red child,
        unequal black heights, a red root, or a stored size that is not the
        number of nodes.
        """
        assert isinstance(m, tuple) and len(m) == 2, f"{_NAME}: a map is (size, tree), got {m!r}"
        n, root = m
        assert root is None or (isinstance(root, tuple) and root[0] is BLACK), f"{_NAME}: the root is not black"
        count = 0
        leaf_blacks: int | None = None
        # (subtree, black nodes above it, lower bound, upper bound, key of its parent if red);
        # a bound or key is a 1-tuple so that None can mean "none" whatever the keys are.
        stack: list[tuple[Tree[K, V], int, tuple[K] | None, tuple[K] | None, tuple[K] | None]] = [
            (root, 0, None, None, None)
        ]
        while stack:
            t, blacks, lo, hi, red_parent = stack.pop()
            if t is None:
                if leaf_blacks is None:
                    leaf_blacks = blacks
                assert blacks == leaf_blacks, (
                    f"{_NAME}: unequal black heights: {leaf_blacks} and {blacks} black nodes "
                    "on two root-to-leaf paths"
                )
                continue
            assert isinstance(t, tuple) and len(t) == 5, f"{_NAME}: a node is a 5-tuple, got {t!r}"
            c, a, k, _, b = t
            assert c is RED or c is BLACK, f"{_NAME}: node {k!r} has colour {c!r}, not RED or BLACK"
            if lo is not None:
                assert lo[0] < k, f"{_NAME}: keys out of order: {k!r} in the right subtree of {lo[0]!r}"
            if hi is not None:
                assert k < hi[0], f"{_NAME}: keys out of order: {k!r} in the left subtree of {hi[0]!r}"
            if red_parent is not None:
                assert c is BLACK, f"{_NAME}: red node {red_parent[0]!r} has a red child {k!r}"
            count += 1
            below = blacks + (1 if c is BLACK else 0)
            here = (k,) if c is RED else None
            stack.append((b, below, (k,), hi, here))
            stack.append((a, below, lo, (k,), here))
        assert count == n, f"{_NAME}: stored size {n} but {count} nodes"

    def __repr__(self) -> str:
        return _NAME


red_black: RedBlackMap[Any, Any] = RedBlackMap()
"""The red-black tree structure, polymorphic in keys and values."""
