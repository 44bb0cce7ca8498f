"""The arena red-black tree's nodes, its search and Okasaki's insertion (paper §2, §4).

:mod:`persistri.impl.maps.red_black_arena` is the ``ORD_MAP`` structure built
on these functions; its docstring describes the representation, the trade it
makes and the costs.  This module holds the arena and the search and insertion
of :mod:`persistri.impl.maps.red_black_tree` transcribed to it, clause for
clause (the same trees, the same rewrites, the same number of new nodes);
Kahrs' deletion is in :mod:`persistri.impl.maps.red_black_arena_delete`, and
the batched update of several keys in one descent in
:mod:`persistri.impl.maps.red_black_arena_adjust`.

A node is an index into the arena's four parallel node arrays — item, left
child, right child, colour — and its item an index into the two item lists,
key and value.  Path copying makes new nodes and *reuses items*: a node copied
because a child changed keeps its key and value by pointing at the same item,
and Okasaki's and Kahrs' rewrites move items between nodes; only a new or
changed value makes a new item.  Index 0 is the empty leaf (a black node
whose fields are never read) and the placeholder item, so ``if t:`` tests for
a node and ``red[t]`` is false for the leaf, as the empty tree counts as
black.  Nodes and items are appended (:meth:`Arena.node`, :meth:`Arena.pair`),
and a node is written again only by the operation that made it, before any
map refers to it (Okasaki's rewrites refill the red nodes the same insertion
made, a new red root is blackened in place, and Kahrs' rewrites recolour the
nodes the same deletion made, or, after an update in the same operation,
refill the update's nodes on the deleted key's path,
:func:`~persistri.impl.maps.red_black_arena_delete._put`): no index that a returned map
reaches is ever written, so every tree ever returned stays valid —
persistence by construction, the same path copying as the tuple tree's with
indices instead of references.  A child is always made before its
parent, so along every path the node indices decrease (checked by the
structure's ``_check``).

The functions trust their arguments: valid trees of the arena they are given,
and keys that Python can order among the tree's (the structure checks).
Recursion depth is the tree height.
"""

from __future__ import annotations

from array import array
from collections.abc import Callable
from typing import Any, Final, TypeAlias

from persistri.impl.maps.keys import not_totally_ordered

__all__ = [
    "RED",
    "BLACK",
    "NIL",
    "ROOT_BITS",
    "ROOT_MASK",
    "Arena",
    "Combine",
    "FailedWith",
    "search",
    "find",
    "ins",
    "ins_absent",
    "replace",
    "update",
]

RED: Final = 1
"""The colour of a red node (``arena.red[t]``)."""

BLACK: Final = 0
"""The colour of a black node, and of the empty leaf :data:`NIL`."""

NIL: Final = 0
"""The empty tree: the index of the arena's placeholder leaf."""

ROOT_BITS: Final = 32
"""A map value is the ``int`` ``size << ROOT_BITS | root`` (:mod:`~persistri.impl.maps.red_black_arena_map`)."""

ROOT_MASK: Final = (1 << ROOT_BITS) - 1
"""A map value's root index: ``m & ROOT_MASK`` (node indices are unsigned 32-bit)."""

Combine: TypeAlias = Callable[[Any, Any], Any]
"""``insertWith``'s function: ``(old value, given value) -> new value``."""

_NAME: Final = "red_black_arena"


class Arena:
    """The append-only store of one family of red-black trees: node arrays and item lists, indexed.

    A node is 13 bytes: ``item``, ``left`` and ``right``, typed arrays of
    unsigned 32-bit indices (``"I"``: their items are written without the
    argument parser that signed typecodes go through), and ``red``, a
    ``bytearray`` of colours.  An item is 16: ``key`` and ``val``, lists of
    references to the map's keys and values.  A tuple node of
    :mod:`~persistri.impl.maps.red_black_tree` takes 80 bytes, and a copied
    path has one node per level but new items only where values changed.
    Slot 0 of each is the empty leaf.  Nothing a map reaches is ever removed
    or overwritten: the arena grows by :meth:`node` and :meth:`pair`, an
    operation may refill the nodes it made itself before returning (module
    docstring), and what it holds is freed when no map of it remains.

    One writer at a time: the appends of :meth:`node` are not atomic, so two
    threads adding versions to one arena at once may build wrong *new* nodes
    (never damaging an existing one).  Reading is free.
    """

    __slots__ = ("key", "val", "item", "left", "right", "red")

    key: list[Any]
    val: list[Any]
    item: array[int]
    left: array[int]
    right: array[int]
    red: bytearray

    def __init__(self) -> None:
        self.key = [None]
        self.val = [None]
        self.item = array("I", (0,))
        self.left = array("I", (NIL,))
        self.right = array("I", (NIL,))
        self.red = bytearray(1)

    def node(self, c: int, l: int, i: int, r: int) -> int:
        """A new node of colour ``c``, children ``l`` and ``r``, and item ``i``: its index.  O(1) amortised."""
        n = len(self.item)
        self.item.append(i)
        self.left.append(l)
        self.right.append(r)
        self.red.append(c)
        return n

    def pair(self, k: Any, v: Any) -> int:
        """A new item ``k ↦ v``: its index.  O(1) amortised."""
        n = len(self.key)
        self.key.append(k)
        self.val.append(v)
        return n

    def __len__(self) -> int:
        """The nodes made so far, the empty leaf included."""
        return len(self.item)

    def __repr__(self) -> str:
        return f"<{_NAME} arena of {len(self.item) - 1} nodes, {len(self.key) - 1} items>"


# -- search -------------------------------------------------------------------


def search(A: Arena, t: int, k: Any) -> int:
    """The node holding ``k`` in ``t``, or :data:`NIL`; comparisons may raise TypeError.

    One ``<`` per level (Andersson's descent, as
    :func:`~persistri.impl.maps.red_black_tree.search`).  O(lg n).
    """
    key = A.key
    item = A.item
    left = A.left
    right = A.right
    cand = NIL
    while t:
        if k < key[item[t]]:
            t = left[t]
        else:
            cand = t
            t = right[t]
    if cand and not key[item[cand]] < k:
        return cand
    return NIL


def find(m: Any, k: Any) -> tuple[Any, ...] | None:
    """``find`` of the map value ``m`` (an :class:`~persistri.impl.maps.red_black_arena_map.ArenaMap`: ``size << 32 |
    root``, its class holding the arena): ``(v,)`` if ``k ↦ v`` is in it, else None; for a key known to be ordered
    with the map's keys.  O(lg n), one ``<`` per level."""
    t: int = m & ROOT_MASK
    if not t:
        return None
    A: Arena = m.arena
    key = A.key
    item = A.item
    left = A.left
    right = A.right
    cand = NIL
    while t:
        if k < key[item[t]]:
            t = left[t]
        else:
            cand = t
            t = right[t]
    if cand:
        i = item[cand]
        if not key[i] < k:
            return (A.val[i],)
    return None


# -- insertion (Okasaki 1999) ----------------------------------------------------


def _balance_left(A: Arena, n: int, yi: int, b: int) -> int:
    """The black node ``(n, yi, b)`` whose left child ``n`` is red: Okasaki's two left clauses, or the node.

    ``n`` and its red child are nodes the running insertion made (an older red
    node has black children), referenced by nothing but the node being built:
    a rewrite recolours or refills them in place — they are written only by the
    operation that made them, before any map refers to them — and appends one
    node, where the tuple tree makes three and drops two.  The refilled slot
    must stay above its children: when ``b`` was made after ``n`` (the batched
    descent updates the right side after the left), that node is appended.
    """
    left = A.left
    right = A.right
    red = A.red
    nl = left[n]
    if red[nl]:
        # balance B (T R (T R a x b) y c) z d = T R (T B a x b) y (T B c z d)
        item = A.item
        red[nl] = BLACK
        xi = item[n]
        c = right[n]
        if b < n:  # n's slot becomes T B c z d
            red[n] = BLACK
            left[n] = c
            item[n] = yi
            right[n] = b
            return A.node(RED, nl, xi, n)
        return A.node(RED, nl, xi, A.node(BLACK, c, yi, b))
    nr = right[n]
    if red[nr]:
        # balance B (T R a x (T R b y c)) z d = T R (T B a x b) y (T B c z d)
        item = A.item
        xi = item[nr]
        c = right[nr]
        red[n] = BLACK  # n's slot becomes T B a x b
        right[n] = left[nr]
        if b < nr:  # nr's slot becomes T B c z d
            red[nr] = BLACK
            left[nr] = c
            item[nr] = yi
            right[nr] = b
            return A.node(RED, n, xi, nr)
        return A.node(RED, n, xi, A.node(BLACK, c, yi, b))
    return A.node(BLACK, n, yi, b)


def _balance_right(A: Arena, a: int, yi: int, n: int) -> int:
    """The black node ``(a, yi, n)`` whose right child ``n`` is red: Okasaki's two right clauses, or the node.

    The mirror image of :func:`_balance_left`, rewriting in place the same way (``a`` was made before
    ``n`` except in a failed check, where the node is appended).
    """
    left = A.left
    right = A.right
    red = A.red
    nl = left[n]
    if red[nl]:
        # balance B a x (T R (T R b y c) z d) = T R (T B a x b) y (T B c z d)
        item = A.item
        xi = item[nl]
        b = left[nl]
        red[n] = BLACK  # n's slot becomes T B c z d
        left[n] = right[nl]
        if a < nl:  # nl's slot becomes T B a x b
            red[nl] = BLACK
            left[nl] = a
            item[nl] = yi
            right[nl] = b
            return A.node(RED, nl, xi, n)
        return A.node(RED, A.node(BLACK, a, yi, b), xi, n)
    nr = right[n]
    if red[nr]:
        # balance B a x (T R b y (T R c z d)) = T R (T B a x b) y (T B c z d)
        item = A.item
        red[nr] = BLACK
        xi = item[n]
        if a < n:  # n's slot becomes T B a x b
            red[n] = BLACK
            left[n] = a
            item[n] = yi
            right[n] = nl
            return A.node(RED, n, xi, nr)
        return A.node(RED, A.node(BLACK, a, yi, nl), xi, nr)
    return A.node(BLACK, a, yi, n)


def ins(A: Arena, t: int, k: Any, v: Any) -> int:
    """Okasaki's ``ins``: ``t`` with a new red leaf ``k ↦ v``, or :data:`NIL` when ``k`` is already in ``t``.

    As :func:`~persistri.impl.maps.red_black_tree.ins`: the result keeps the
    black height of ``t`` and may be red with a red child (only when ``t`` is
    red); nothing is made for a present key.
    """
    if not t:
        return A.node(RED, NIL, A.pair(k, v), NIL)
    yi = A.item[t]
    y = A.key[yi]
    if k < y:
        n = ins(A, A.left[t], k, v)
        if not n:
            return NIL
        if not A.red[t]:
            if A.red[n]:
                return _balance_left(A, n, yi, A.right[t])
            return A.node(BLACK, n, yi, A.right[t])
        return A.node(RED, n, yi, A.right[t])
    if y < k:
        n = ins(A, A.right[t], k, v)
        if not n:
            return NIL
        if not A.red[t]:
            if A.red[n]:
                return _balance_right(A, A.left[t], yi, n)
            return A.node(BLACK, A.left[t], yi, n)
        return A.node(RED, A.left[t], yi, n)
    if y is not k and not y == k:  # neither '<' nor '==': a NaN, say, is no key of the map
        raise not_totally_ordered(_NAME, k, y)
    return NIL


def ins_absent(A: Arena, t: int, k: Any, v: Any) -> int:
    """:func:`ins` of a key known not to be in ``t``: one ``<`` a level.  A present key would be added twice."""
    if not t:
        return A.node(RED, NIL, A.pair(k, v), NIL)
    yi = A.item[t]
    if k < A.key[yi]:
        n = ins_absent(A, A.left[t], k, v)
        if not A.red[t]:
            if A.red[n]:
                return _balance_left(A, n, yi, A.right[t])
            return A.node(BLACK, n, yi, A.right[t])
        return A.node(RED, n, yi, A.right[t])
    n = ins_absent(A, A.right[t], k, v)
    if not A.red[t]:
        if A.red[n]:
            return _balance_right(A, A.left[t], yi, n)
        return A.node(BLACK, A.left[t], yi, n)
    return A.node(RED, A.left[t], yi, n)


def replace(A: Arena, t: int, k: Any, v: Any) -> int:
    """``t`` with the value of the present key ``k`` replaced by ``v`` (and its key object by ``k``): path copying,
    same shape and colours."""
    if not t:
        # Only an order that changed between two descents can get here.
        raise AssertionError(f"{_NAME}: key {k!r} vanished between two searches (inconsistent '<')")
    yi = A.item[t]
    y = A.key[yi]
    if k < y:
        return A.node(A.red[t], replace(A, A.left[t], k, v), yi, A.right[t])
    if y < k:
        return A.node(A.red[t], A.left[t], yi, replace(A, A.right[t], k, v))
    return A.node(A.red[t], A.left[t], A.pair(k, v), A.right[t])


class FailedWith(Exception):
    """Carries an exception raised by ``insertWith``'s function out of the descents (as the tuple tree's)."""

    def __init__(self, exc: BaseException) -> None:
        super().__init__()
        self.exc = exc


def update(A: Arena, t: int, k: Any, f: Combine, v: Any) -> int:
    """``t`` (a node) with the value ``x`` of the present key ``k`` replaced by ``f(x, v)`` (and its key object by
    ``k``): path copying.  :data:`NIL` if ``k`` is not in ``t`` (nothing made, ``f`` not called).
    Recursive, depth at most the tree height.
    """
    yi = A.item[t]
    y = A.key[yi]
    if k < y:
        a = A.left[t]
        if not a:
            return NIL
        a2 = update(A, a, k, f, v)
        return NIL if not a2 else A.node(A.red[t], a2, yi, A.right[t])
    if y < k:
        b = A.right[t]
        if not b:
            return NIL
        b2 = update(A, b, k, f, v)
        return NIL if not b2 else A.node(A.red[t], A.left[t], yi, b2)
    if y is not k and not y == k:  # neither '<' nor '==': a NaN, say (reported by insertWith)
        raise FailedWith(not_totally_ordered(_NAME, k, y))
    try:
        x = f(A.val[yi], v)
    except Exception as exc:
        raise FailedWith(exc) from None
    return A.node(A.red[t], A.left[t], A.pair(k, x), A.right[t])
