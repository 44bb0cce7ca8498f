"""The red-black tree's nodes and the algorithms over them: Okasaki's insertion, Kahrs' deletion (paper §2, §4).

:mod:`persistri.impl.maps.red_black` is the ``ORD_MAP`` structure built on
these functions; its docstring describes the representation, the invariants
and the costs.  They are a module of their own because they are where the
map's time goes: the compiled twin (``make compiled``, docs/performance.md)
compiles this module with mypyc and leaves the structure, which validates keys
and raises the signature's errors, interpreted.  The batched update of several
keys in one descent (``adjust_sorted``) is in
:mod:`persistri.impl.maps.red_black_adjust`, and the insertion fused into it in
:mod:`persistri.impl.maps.red_black_adjust_insert`, compiled too.

A node is the 5-tuple ``(colour, left, key, value, right)``; a tree is a node
or ``None``.  Here a node is typed as a tuple of *any* length,
``tuple[Any, ...]``: mypyc stores a fixed-length tuple type unboxed and boxes
it again on the way out, so a node passing through a compiled function would
come back as a new, equal tuple — no longer the node older versions share.
Typed this way it stays one object, and persistence, which lives on that
sharing, survives compilation (``tests/test_red_black_path_copying.py`` counts the new nodes
of every operation by identity).  The functions trust their arguments: valid
trees, and keys that Python can order among the tree's (the structure checks).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final, TypeAlias

from persistri.impl.maps.keys import not_totally_ordered

__all__ = [
    "RED",
    "BLACK",
    "Node",
    "Tree",
    "Combine",
    "FailedWith",
    "search",
    "find",
    "ins",
    "ins_absent",
    "replace",
    "update",
    "balance",
    "balleft",
    "balright",
    "app",
    "delete",
]

RED: Final = True
"""The colour of a red node (``node[0]``)."""

BLACK: Final = False
"""The colour of a black node (``node[0]``); the empty tree ``None`` counts as black."""

Node: TypeAlias = tuple[Any, ...]
"""A tree node ``(colour, left, key, value, right)`` (see the module docstring for the variable length)."""

Tree: TypeAlias = Node | None
"""A red-black tree: a node, or ``None`` (the empty, black leaf)."""

Combine: TypeAlias = Callable[[Any, Any], Any]
"""``insertWith``'s function: ``(old value, given value) -> new value``."""

_NAME: Final = "red_black"


# -- search -------------------------------------------------------------------


def search(t: Tree, k: Any) -> Tree:
    """The node holding ``k`` in ``t``, or None; comparisons may raise TypeError.

    One ``<`` per level (Andersson's descent): the last node whose key is not
    above ``k`` is the candidate, and one more comparison at the leaf says
    whether it holds ``k`` (the order is total).  The descent always reaches a
    leaf, about one level more than stopping at the node, but a right turn no
    longer costs a second comparison: measured on 8,192 vertex keys (an ``int``
    subclass, whose ``<`` CPython 3.11 does not specialise), 18 % fewer
    instructions per search than ``<`` then ``>`` at every level.
    """
    cand: Tree = None
    while t is not None:
        if k < t[2]:
            t = t[1]
        else:
            cand = t
            t = t[4]
    if cand is not None and not cand[2] < k:
        return cand
    return None


def find(m: tuple[Any, ...], k: Any) -> tuple[Any, ...] | None:
    """``find`` of the map ``m = (size, tree)``: ``(v,)`` if ``k ↦ v`` is in it, else None; for a key known to be
    ordered with the map's keys (a comparison's TypeError is not reworded).  O(lg n), one ``<`` per level
    (as :func:`search`)."""
    t: Tree = m[1]
    cand: Tree = None
    while t is not None:
        if k < t[2]:
            t = t[1]
        else:
            cand = t
            t = t[4]
    if cand is not None and not cand[2] < k:
        return (cand[3],)
    return None


# -- insertion (Okasaki 1999) ----------------------------------------------------


def ins(t: Tree, k: Any, v: Any) -> Node | None:
    """Okasaki's ``ins``: ``t`` with a new red leaf ``k ↦ v``, or None when ``k`` is already in ``t``
    (a :class:`ValueError` when the key met is neither ``<``, ``>`` nor ``==`` ``k``: ``not_totally_ordered``).

    The result keeps the black height of ``t``; its root may be red with a red
    child (only when ``t``'s root was red), which the caller above repairs.
    Returning None for a present key lets :meth:`~persistri.impl.maps.red_black.RedBlackMap.insert` know
    whether the size grows without allocating a flag on every level.
    """
    if t is None:
        return (RED, None, k, v, None)
    c, a, y, yv, b = t
    if k < y:
        n = ins(a, k, v)
        if n is None:
            return None
        if c is BLACK and n[0] is RED:
            nl = n[1]
            if nl is not None and nl[0] is RED:
                # balance B (T R (T R a x b) y c) z d = T R (T B a x b) y (T B c z d)
                return (RED, (BLACK, nl[1], nl[2], nl[3], nl[4]), n[2], n[3], (BLACK, n[4], y, yv, b))
            nr = n[4]
            if nr is not None and nr[0] is RED:
                # balance B (T R a x (T R b y c)) z d = T R (T B a x b) y (T B c z d)
                return (RED, (BLACK, nl, n[2], n[3], nr[1]), nr[2], nr[3], (BLACK, nr[4], y, yv, b))
        return (c, n, y, yv, b)
    if y < k:
        n = ins(b, k, v)
        if n is None:
            return None
        if c is BLACK and n[0] is RED:
            nl = n[1]
            if nl is not None and nl[0] is RED:
                # balance B a x (T R (T R b y c) z d) = T R (T B a x b) y (T B c z d)
                return (RED, (BLACK, a, y, yv, nl[1]), nl[2], nl[3], (BLACK, nl[4], n[2], n[3], n[4]))
            nr = n[4]
            if nr is not None and nr[0] is RED:
                # balance B a x (T R b y (T R c z d)) = T R (T B a x b) y (T B c z d)
                return (RED, (BLACK, a, y, yv, nl), n[2], n[3], (BLACK, nr[1], nr[2], nr[3], nr[4]))
        return (c, a, y, yv, n)
    if y is not k and not y == k:  # neither '<' nor '==': a NaN, say, is no key of the map
        raise not_totally_ordered(_NAME, k, y)
    return None


def ins_absent(t: Tree, k: Any, v: Any) -> Node:
    """:func:`ins` of a key known not to be in ``t``: one ``<`` a level (a key not below ``y`` is above it).

    For the 2-complex's ``replace``, whose new vertices the batched update has
    just found absent.  A present ``k`` would be added a second time: callers
    must know.  Same rewrites, same result as :func:`ins` on an absent key.
    """
    if t is None:
        return (RED, None, k, v, None)
    c, a, y, yv, b = t
    if k < y:
        n = ins_absent(a, k, v)
        if c is BLACK and n[0] is RED:
            nl = n[1]
            if nl is not None and nl[0] is RED:
                # balance B (T R (T R a x b) y c) z d = T R (T B a x b) y (T B c z d)
                return (RED, (BLACK, nl[1], nl[2], nl[3], nl[4]), n[2], n[3], (BLACK, n[4], y, yv, b))
            nr = n[4]
            if nr is not None and nr[0] is RED:
                # balance B (T R a x (T R b y c)) z d = T R (T B a x b) y (T B c z d)
                return (RED, (BLACK, nl, n[2], n[3], nr[1]), nr[2], nr[3], (BLACK, nr[4], y, yv, b))
        return (c, n, y, yv, b)
    n = ins_absent(b, k, v)
    if c is BLACK and n[0] is RED:
        nl = n[1]
        if nl is not None and nl[0] is RED:
            # balance B a x (T R (T R b y c) z d) = T R (T B a x b) y (T B c z d)
            return (RED, (BLACK, a, y, yv, nl[1]), nl[2], nl[3], (BLACK, nl[4], n[2], n[3], n[4]))
        nr = n[4]
        if nr is not None and nr[0] is RED:
            # balance B a x (T R b y (T R c z d)) = T R (T B a x b) y (T B c z d)
            return (RED, (BLACK, a, y, yv, nl), n[2], n[3], (BLACK, nr[1], nr[2], nr[3], nr[4]))
    return (c, a, y, yv, n)


def replace(t: Tree, k: Any, v: Any) -> Node:
    """``t`` with the value of the present key ``k`` replaced by ``v``: path copying, same shape and colours."""
    if t is None:
        # Only an order that changed between two descents can get here.
        raise AssertionError(f"{_NAME}: key {k!r} vanished between two searches (inconsistent '<')")
    c, a, y, yv, b = t
    if k < y:
        return (c, replace(a, k, v), y, yv, b)
    if y < k:
        return (c, a, y, yv, replace(b, k, v))
    return (c, a, k, v, b)


class FailedWith(Exception):
    """Carries an exception raised by ``insertWith``'s function out of :func:`update`.

    So that the TypeError of an unorderable key, which :meth:`~persistri.impl.maps.red_black.RedBlackMap.insertWith`
    rewords, is never confused with a TypeError of the caller's function, which
    must propagate unchanged.
    """

    def __init__(self, exc: BaseException) -> None:
        super().__init__()
        self.exc = exc


def update(t: Node, k: Any, f: Combine, v: Any) -> Node | None:
    """``t`` with the value ``x`` of the present key ``k`` replaced by ``f(x, v)``: path copying.

    None if ``k`` is not in ``t`` (the descent reached a leaf; nothing has been
    built, ``f`` not called) — a result, not an exception: absent keys are routine
    (every new vertex of a 2-complex's ``replace``), and an exception unwinding the
    recursion costs a traceback entry per level, in the compiled twin most of all.
    Recursive, depth at most the tree height: measured on CPython 3.11 at 50K
    keys, a quarter faster than an explicit stack of the path (the interpreter's
    frames are cheaper than a list of nodes unpacked twice).
    """
    c, a, y, yv, b = t
    if k < y:
        if a is None:
            return None
        a2 = update(a, k, f, v)
        return None if a2 is None else (c, a2, y, yv, b)
    if y < k:
        if b is None:
            return None
        b2 = update(b, k, f, v)
        return None if b2 is None else (c, a, y, yv, b2)
    if y is not k and not y == k:  # neither '<' nor '==': a NaN, say (reported by insertWith)
        raise FailedWith(not_totally_ordered(_NAME, k, y))
    try:
        x = f(yv, v)
    except Exception as exc:
        raise FailedWith(exc) from None
    return (c, a, k, x, b)


# -- deletion (Kahrs 2001) ---------------------------------------------------------


def balance(l: Tree, k: Any, v: Any, r: Tree) -> Node:
    """Kahrs' ``balance``: the black node ``l k r``, rewritten when ``l`` or ``r`` holds a red pair.

    A red child with a red child of its own (or two red children) becomes a red
    node with two black children, keeping the black height.

    Okasaki's four rewrites plus Kahrs' first clause (both children red), which
    deletion needs because it may hand ``balance`` two red subtrees.
    """
    if l is not None and l[0] is RED:
        if r is not None and r[0] is RED:
            # balance (T R a x b) y (T R c z d) = T R (T B a x b) y (T B c z d)
            return (RED, (BLACK, l[1], l[2], l[3], l[4]), k, v, (BLACK, r[1], r[2], r[3], r[4]))
        ll = l[1]
        if ll is not None and ll[0] is RED:
            # balance (T R (T R a x b) y c) z d = T R (T B a x b) y (T B c z d)
            return (RED, (BLACK, ll[1], ll[2], ll[3], ll[4]), l[2], l[3], (BLACK, l[4], k, v, r))
        lr = l[4]
        if lr is not None and lr[0] is RED:
            # balance (T R a x (T R b y c)) z d = T R (T B a x b) y (T B c z d)
            return (RED, (BLACK, ll, l[2], l[3], lr[1]), lr[2], lr[3], (BLACK, lr[4], k, v, r))
    if r is not None and r[0] is RED:
        rl = r[1]
        if rl is not None and rl[0] is RED:
            # balance a x (T R (T R b y c) z d) = T R (T B a x b) y (T B c z d)
            return (RED, (BLACK, l, k, v, rl[1]), rl[2], rl[3], (BLACK, rl[4], r[2], r[3], r[4]))
        rr = r[4]
        if rr is not None and rr[0] is RED:
            # balance a x (T R b y (T R c z d)) = T R (T B a x b) y (T B c z d)
            return (RED, (BLACK, l, k, v, rl), r[2], r[3], (BLACK, rr[1], rr[2], rr[3], rr[4]))
    return (BLACK, l, k, v, r)


def sub1(t: Tree) -> Node:
    """Kahrs' ``sub1``: a black node repainted red, lowering its black height by one."""
    assert t is not None and t[0] is BLACK, f"{_NAME}: sub1 of a non-black tree (invariant broken)"
    return (RED, t[1], t[2], t[3], t[4])


def balleft(l: Tree, k: Any, v: Any, r: Tree) -> Node:
    """Kahrs' ``balleft``: the node ``l k r`` whose left subtree ``l`` is one black level short.

    The result has the black height of ``r`` plus one if it is black (that of
    ``r`` if red); it may be red with a red child, which the level above repairs.
    """
    if l is not None and l[0] is RED:
        # balleft (T R a x b) y c = T R (T B a x b) y c
        return (RED, (BLACK, l[1], l[2], l[3], l[4]), k, v, r)
    assert r is not None, f"{_NAME}: balleft with an empty sibling (invariant broken)"
    if r[0] is BLACK:
        # balleft bl x (T B a y b) = balance bl x (T R a y b)
        return balance(l, k, v, (RED, r[1], r[2], r[3], r[4]))
    # balleft bl x (T R (T B a y b) z c) = T R (T B bl x a) y (balance b z (sub1 c))
    rl = r[1]
    assert rl is not None, f"{_NAME}: balleft with a red sibling without a left child (invariant broken)"
    return (RED, (BLACK, l, k, v, rl[1]), rl[2], rl[3], balance(rl[4], r[2], r[3], sub1(r[4])))


def balright(l: Tree, k: Any, v: Any, r: Tree) -> Node:
    """Kahrs' ``balright``: the mirror image of :func:`balleft` (``r`` is one black level short)."""
    if r is not None and r[0] is RED:
        # balright a x (T R b y c) = T R a x (T B b y c)
        return (RED, l, k, v, (BLACK, r[1], r[2], r[3], r[4]))
    assert l is not None, f"{_NAME}: balright with an empty sibling (invariant broken)"
    if l[0] is BLACK:
        # balright (T B a x b) y bl = balance (T R a x b) y bl
        return balance((RED, l[1], l[2], l[3], l[4]), k, v, r)
    # balright (T R a x (T B b y c)) z bl = T R (balance (sub1 a) x b) y (T B c z bl)
    lr = l[4]
    assert lr is not None, f"{_NAME}: balright with a red sibling without a right child (invariant broken)"
    return (RED, balance(sub1(l[1]), l[2], l[3], lr[1]), lr[2], lr[3], (BLACK, lr[4], k, v, r))


def app(a: Tree, b: Tree) -> Tree:
    """Kahrs' ``app``: the fusion of two trees of equal black height, every key of ``a`` below every key of ``b``.

    This replaces a deleted node by its two subtrees; it walks down the inner
    spines (the right spine of ``a``, the left spine of ``b``), so O(lg n).
    """
    if a is None:
        return b
    if b is None:
        return a
    if a[0] is RED:
        if b[0] is RED:
            # app (T R a x b) (T R c y d)
            bc = app(a[4], b[1])
            if bc is not None and bc[0] is RED:
                return (RED, (RED, a[1], a[2], a[3], bc[1]), bc[2], bc[3], (RED, bc[4], b[2], b[3], b[4]))
            return (RED, a[1], a[2], a[3], (RED, bc, b[2], b[3], b[4]))
        # app (T R a x b) c = T R a x (app b c)
        return (RED, a[1], a[2], a[3], app(a[4], b))
    if b[0] is RED:
        # app a (T R b x c) = T R (app a b) x c
        return (RED, app(a, b[1]), b[2], b[3], b[4])
    # app (T B a x b) (T B c y d)
    bc = app(a[4], b[1])
    if bc is not None and bc[0] is RED:
        return (RED, (BLACK, a[1], a[2], a[3], bc[1]), bc[2], bc[3], (BLACK, bc[4], b[2], b[3], b[4]))
    return balleft(a[1], a[2], a[3], (BLACK, bc, b[2], b[3], b[4]))


def delete(t: Tree, k: Any) -> Tree:
    """Kahrs' ``del``: ``t`` without the present key ``k``.

    If ``t`` is black its black height drops by one and the result may be red
    with a red child; the caller's ``balleft``/``balright`` (or the final
    blackening of the root) repairs both.  If ``t`` is red its black height is
    kept.
    """
    if t is None:
        # Only an order that changed between two descents can get here.
        raise AssertionError(f"{_NAME}: key {k!r} vanished between two searches (inconsistent '<')")
    _, a, y, yv, b = t
    if k < y:
        if a is not None and a[0] is BLACK:
            # delformLeft a@(T B _ _ _) y b = balleft (del a) y b
            return balleft(delete(a, k), y, yv, b)
        # delformLeft a y b = T R (del a) y b
        return (RED, delete(a, k), y, yv, b)
    if y < k:
        if b is not None and b[0] is BLACK:
            # delformRight a y b@(T B _ _ _) = balright a y (del b)
            return balright(a, y, yv, delete(b, k))
        # delformRight a y b = T R a y (del b)
        return (RED, a, y, yv, delete(b, k))
    return app(a, b)
