"""The arena red-black tree's deletion: Kahrs' ``del`` and its rebalancing, refilling the nodes it made (paper §2, §4).

Kahrs' deletion (*Red-black trees with types*, JFP 2001: ``del`` with
``balleft``, ``balright``, ``app``, ``sub1`` and ``balance``) over the arena of
:mod:`persistri.impl.maps.red_black_arena_tree`, clause for clause as the
tuple tree's :func:`~persistri.impl.maps.red_black_tree.delete`: the same
trees.  A node's key and value travel as its item index (``ki``): the
rewrites move items, never make them.

Every function takes ``made``, the arena's length when the running operation
began: a node from ``made`` on was made by this operation, no map refers to
it yet, and a rewrite that drops it may recolour or refill it in place
(:func:`_black`, :func:`_red`, :func:`_put`) instead of appending a copy — so
a deletion makes fewer nodes than the tuple tree makes and drops, and nothing
a returned map reaches is ever written.  A deletion alone finds no such node
on its path (its nodes are older than it);
:meth:`~persistri.impl.maps.red_black_arena.ArenaRedBlackMap.adjust_insert_remove`
deletes along the path its own update has just copied, and refills it.

The functions trust their arguments (valid trees of the arena, a key present
and ordered with the tree's: the structure checks).  O(lg n) time and new
nodes; recursive, depth at most the tree height.  Compiled on the twin
(``tools/compiled_twin.py``).
"""

from __future__ import annotations

from typing import Any, Final

from persistri.impl.maps.red_black_arena_tree import BLACK, NIL, RED, Arena

__all__ = ["balance", "sub1", "balleft", "balright", "app", "delete"]

_NAME: Final = "red_black_arena"


def _black(A: Arena, t: int, made: int) -> int:
    """The red node ``t``, black: recoloured in place if the running deletion made it (an index from ``made``
    on; the rewrite that calls this drops ``t``, its one reference), else a black copy."""
    if t >= made:
        A.red[t] = BLACK
        return t
    return A.node(BLACK, A.left[t], A.item[t], A.right[t])


def _red(A: Arena, t: int, made: int) -> int:
    """The black node ``t``, red: in place if the running deletion made it (as :func:`_black`), else a red copy."""
    if t >= made:
        A.red[t] = RED
        return t
    return A.node(RED, A.left[t], A.item[t], A.right[t])


def _put(A: Arena, s: int, made: int, c: int, l: int, i: int, r: int) -> int:
    """The node ``(c, l, i, r)`` that replaces node ``s``: ``s`` refilled in place when the running operation made
    it (an index from ``made`` on, referred to by no map, dropped by the rewrite) and the slot stays above the
    children (a child is made before its parent), else a new node.  A deletion alone never refills: its
    path's nodes are older than it; :meth:`~persistri.impl.maps.red_black_arena.ArenaRedBlackMap.adjust_insert_remove`
    deletes along the path its own update copied."""
    if s >= made and l < s and r < s:
        A.red[s] = c
        A.left[s] = l
        A.item[s] = i
        A.right[s] = r
        return s
    return A.node(c, l, i, r)


def balance(A: Arena, l: int, ki: int, r: int, made: int, s: int = NIL) -> int:
    """Kahrs' ``balance``: the black node ``l ki r``, rewritten when ``l`` or ``r`` holds a red pair.

    ``made``: the arena's length when the deletion began.  Here and in the functions below, a node the
    rewrite takes apart or recolours is refilled in place when the deletion made it (an index from
    ``made`` on, which no map refers to yet, and which the rewrite drops): fewer nodes than the tuple tree
    makes and drops, the same tree."""
    left = A.left
    right = A.right
    red = A.red
    item = A.item
    node = A.node
    if red[l]:
        if red[r]:
            # balance (T R a x b) y (T R c z d) = T R (T B a x b) y (T B c z d)
            return _put(A, s, made, RED, _black(A, l, made), ki, _black(A, r, made))
        ll = left[l]
        if red[ll]:
            # balance (T R (T R a x b) y c) z d = T R (T B a x b) y (T B c z d)
            return node(RED, _black(A, ll, made), item[l], _put(A, s, made, BLACK, right[l], ki, r))
        lr = right[l]
        if red[lr]:
            # balance (T R a x (T R b y c)) z d = T R (T B a x b) y (T B c z d)
            return node(RED, _put(A, s, made, BLACK, ll, item[l], left[lr]), item[lr], node(BLACK, right[lr], ki, r))
    if red[r]:
        rl = left[r]
        if red[rl]:
            # balance a x (T R (T R b y c) z d) = T R (T B a x b) y (T B c z d)
            return node(
                RED, _put(A, s, made, BLACK, l, ki, left[rl]), item[rl], node(BLACK, right[rl], item[r], right[r])
            )
        rr = right[r]
        if red[rr]:
            # balance a x (T R b y (T R c z d)) = T R (T B a x b) y (T B c z d)
            return node(RED, _put(A, s, made, BLACK, l, ki, rl), item[r], _black(A, rr, made))
    return _put(A, s, made, BLACK, l, ki, r)


def sub1(A: Arena, t: int, made: int) -> int:
    """Kahrs' ``sub1``: a black node repainted red, lowering its black height by one."""
    assert t and not A.red[t], f"{_NAME}: sub1 of a non-black tree (invariant broken)"
    return _red(A, t, made)


def balleft(A: Arena, l: int, ki: int, r: int, made: int, s: int = NIL) -> int:
    """Kahrs' ``balleft``: the node ``l ki r`` whose left subtree ``l`` is one black level short; ``s`` the node
    it replaces (:func:`balance`)."""
    if A.red[l]:
        # balleft (T R a x b) y c = T R (T B a x b) y c
        return _put(A, s, made, RED, _black(A, l, made), ki, r)
    assert r, f"{_NAME}: balleft with an empty sibling (invariant broken)"
    if not A.red[r]:
        # balleft bl x (T B a y b) = balance bl x (T R a y b)
        return balance(A, l, ki, _red(A, r, made), made, s)
    # balleft bl x (T R (T B a y b) z c) = T R (T B bl x a) y (balance b z (sub1 c))
    rl = A.left[r]
    assert rl, f"{_NAME}: balleft with a red sibling without a left child (invariant broken)"
    return A.node(
        RED,
        _put(A, s, made, BLACK, l, ki, A.left[rl]),
        A.item[rl],
        balance(A, A.right[rl], A.item[r], sub1(A, A.right[r], made), made),
    )


def balright(A: Arena, l: int, ki: int, r: int, made: int, s: int = NIL) -> int:
    """Kahrs' ``balright``: the mirror image of :func:`balleft` (``r`` is one black level short)."""
    if A.red[r]:
        # balright a x (T R b y c) = T R a x (T B b y c)
        return _put(A, s, made, RED, l, ki, _black(A, r, made))
    assert l, f"{_NAME}: balright with an empty sibling (invariant broken)"
    if not A.red[l]:
        # balright (T B a x b) y bl = balance (T R a x b) y bl
        return balance(A, _red(A, l, made), ki, r, made, s)
    # balright (T R a x (T B b y c)) z bl = T R (balance (sub1 a) x b) y (T B c z bl)
    lr = A.right[l]
    assert lr, f"{_NAME}: balright with a red sibling without a right child (invariant broken)"
    return A.node(
        RED,
        balance(A, sub1(A, A.left[l], made), A.item[l], A.left[lr], made),
        A.item[lr],
        _put(A, s, made, BLACK, A.right[lr], ki, r),
    )


def app(A: Arena, a: int, b: int, made: int, s: int = NIL) -> int:
    """Kahrs' ``app``: the fusion of two trees of equal black height, every key of ``a`` below every key of ``b``;
    ``s`` the deleted node whose children they are (refilled by one new node, :func:`balance`)."""
    if not a:
        return b
    if not b:
        return a
    red = A.red
    node = A.node
    item = A.item
    left = A.left
    right = A.right
    if red[a]:
        if red[b]:
            # app (T R a x b) (T R c y d)
            bc = app(A, right[a], left[b], made)
            if red[bc]:
                return node(
                    RED,
                    _put(A, s, made, RED, left[a], item[a], left[bc]),
                    item[bc],
                    node(RED, right[bc], item[b], right[b]),
                )
            return node(RED, left[a], item[a], _put(A, s, made, RED, bc, item[b], right[b]))
        # app (T R a x b) c = T R a x (app b c)
        return _put(A, s, made, RED, left[a], item[a], app(A, right[a], b, made))
    if red[b]:
        # app a (T R b x c) = T R (app a b) x c
        return _put(A, s, made, RED, app(A, a, left[b], made), item[b], right[b])
    # app (T B a x b) (T B c y d)
    bc = app(A, right[a], left[b], made)
    if red[bc]:
        return node(
            RED, _put(A, s, made, BLACK, left[a], item[a], left[bc]), item[bc], node(BLACK, right[bc], item[b], right[b])
        )
    return balleft(A, left[a], item[a], _put(A, s, made, BLACK, bc, item[b], right[b]), made)


def delete(A: Arena, t: int, k: Any, made: int) -> int:
    """Kahrs' ``del``: ``t`` without the present key ``k`` (see :func:`~persistri.impl.maps.red_black_tree.delete`)."""
    if not t:
        # Only an order that changed between two descents can get here.
        raise AssertionError(f"{_NAME}: key {k!r} vanished between two searches (inconsistent '<')")
    a = A.left[t]
    yi = A.item[t]
    y = A.key[yi]
    b = A.right[t]
    if k < y:
        if a and not A.red[a]:
            # delformLeft a@(T B _ _ _) y b = balleft (del a) y b
            return balleft(A, delete(A, a, k, made), yi, b, made, t)
        # delformLeft a y b = T R (del a) y b
        return _put(A, t, made, RED, delete(A, a, k, made), yi, b)
    if y < k:
        if b and not A.red[b]:
            # delformRight a y b@(T B _ _ _) = balright a y (del b)
            return balright(A, a, yi, delete(A, b, k, made), made, t)
        # delformRight a y b = T R a y (del b)
        return _put(A, t, made, RED, a, yi, delete(A, b, k, made))
    return app(A, a, b, made, t)
