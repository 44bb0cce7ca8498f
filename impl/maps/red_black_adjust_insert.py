"""One key inserted in the red-black tree's batched update, in the same descent (paper §2, §4; Okasaki 1999).

When the 2-complex's ``replace`` puts a cone on a *fresh* vertex (every
insertion of the hull, the Delaunay triangulation and the terrain) it updates
the lists of the vertices it touches and adds that vertex to the map.  The
functions here do both in the one descent of
:func:`~persistri.impl.maps.red_black_adjust.adjust`, so that the top of the
tree, shared by all the search paths, is copied once and not twice:

* :func:`adjust_insert` and :func:`adjust_one_insert` update the present keys
  as :func:`~persistri.impl.maps.red_black_adjust.adjust` and
  :func:`~persistri.impl.maps.red_black_adjust.adjust_one` do and, where the
  descent finds the one key ``keys[j]`` absent, put it there as a red leaf and
  repair the tree on the way back up exactly as Okasaki's insertion does
  (:func:`~persistri.impl.maps.red_black_tree.ins`).  Updating values keeps
  every colour, so the repairs are those the insertion would make after the
  update: the result is the tree of ``adjust`` followed by
  :func:`~persistri.impl.maps.red_black_tree.ins_absent` — the same shape,
  colours and number of new nodes.  Only the subtree that holds ``keys[j]``
  goes through the inserting functions; the others take ``adjust``.
* :func:`adjust_insert_map` is the structure's operation over them on a whole
  map, and is :meth:`~persistri.impl.maps.red_black.RedBlackMap.adjust_insert`
  itself (a static method: on the twin a call of it runs no interpreted code).

The hot path of every insertion's ``replace``: the compiled twin compiles it
(``tools/compiled_twin.py``), nodes are typed as in
:mod:`~persistri.impl.maps.red_black_tree`, and the child's level is written out
in the parent's frame while the slice stays on one side, as in
:mod:`~persistri.impl.maps.red_black_adjust` (whose docstring has the reasons).
O(k + new nodes) for k keys; recursive, depth at most the tree height.
"""

from __future__ import annotations

from typing import Any

from persistri.impl.maps.red_black_adjust import adjust, adjust_one
from persistri.impl.maps.red_black_tree import BLACK, RED, Combine, FailedWith, Node

__all__ = ["adjust_insert", "adjust_one_insert", "adjust_insert_map"]

# Okasaki's repair, for a black node whose rebuilt child n is red: if n has a red child, the
# node becomes a red node with two black children (the four clauses of ``balance``; only the
# two of n's side can apply).  The callers test inline that the node is black, n red and one
# of n's children red, so the function is called only where a clause applies (on the hull's
# replay a fifth of the calls the test ``c is BLACK and n[0] is RED`` alone made).


def _repair_left(n: Node, y: Any, yv: Any, b: Any) -> Node:
    """The black node ``(n, y, b)`` whose left child ``n`` is red and rebuilt: Okasaki's two left clauses."""
    nl = n[1]
    if nl is not None and nl[0] is RED:
        # balance B (T R (T R a x b) y c) z d = T R (T B a x b) y (T B c z d)
        return (RED, (BLACK, nl[1], nl[2], nl[3], nl[4]), n[2], n[3], (BLACK, n[4], y, yv, b))
    nr = n[4]
    if nr is not None and nr[0] is RED:
        # balance B (T R a x (T R b y c)) z d = T R (T B a x b) y (T B c z d)
        return (RED, (BLACK, nl, n[2], n[3], nr[1]), nr[2], nr[3], (BLACK, nr[4], y, yv, b))
    return (BLACK, n, y, yv, b)


def _repair_right(a: Any, y: Any, yv: Any, n: Node) -> Node:
    """The black node ``(a, y, n)`` whose right child ``n`` is red and rebuilt: Okasaki's two right clauses."""
    nl = n[1]
    if nl is not None and nl[0] is RED:
        # balance B a x (T R (T R b y c) z d) = T R (T B a x b) y (T B c z d)
        return (RED, (BLACK, a, y, yv, nl[1]), nl[2], nl[3], (BLACK, nl[4], n[2], n[3], n[4]))
    nr = n[4]
    if nr is not None and nr[0] is RED:
        # balance B a x (T R b y (T R c z d)) = T R (T B a x b) y (T B c z d)
        return (RED, (BLACK, a, y, yv, nl), n[2], n[3], (BLACK, nr[1], nr[2], nr[3], nr[4]))
    return (BLACK, a, y, yv, n)


def adjust_insert(
    t: Node,
    keys: list[Any],
    vals: list[Any],
    lo: int,
    hi: int,
    f: Combine,
    absent: list[int],
    emptied: list[int],
    j: int,
    new: list[Any],
) -> Node:
    """:func:`adjust` of ``keys[lo:hi]``, and ``keys[j] ↦ new[0]`` inserted if ``keys[j]`` is absent
    (``lo ≤ j < hi``).

    Where the descent ends at a leaf with ``keys[j]`` alone it puts a red leaf
    there, takes the value out of ``new`` (so the caller tells an insertion by
    ``new`` being empty), and on the way back up repairs each black node whose
    rebuilt child is red with a red child, as Okasaki's insertion does.  The
    result may be red with a red child (only when ``t`` is red), which the
    level above repairs; the caller blackens the root.  A present ``keys[j]``
    is updated by ``f`` like the others, and ``keys[j]`` at a leaf with other
    keys of the slice is reported absent with them (``new`` is left full).  The
    parts of the slice without ``j`` go to :func:`adjust`.  Requires
    ``hi - lo ≥ 1``.  O(hi − lo + new nodes).
    """
    c, a, y, yv, b = t
    last = hi - 1
    if keys[last] < y:  # the whole slice is below y
        if a is None:
            if lo == last:
                return (c, (RED, None, keys[j], new.pop(), None), y, yv, b)
            absent.extend(range(lo, hi))
            return t
        if lo == last:
            a2 = adjust_one_insert(a, keys[j], vals[j], f, j, absent, emptied, new)
        else:  # a's level written out here (two levels a call) while the slice stays on one side
            an: Node = a
            ca, aa, ya, yva, ab = an
            if keys[last] < ya:
                if aa is None:
                    absent.extend(range(lo, hi))
                    return t
                n = adjust_insert(aa, keys, vals, lo, hi, f, absent, emptied, j, new)
                if n is aa:
                    return t
                if ca is BLACK and n[0] is RED and (
                    (n[1] is not None and n[1][0] is RED) or (n[4] is not None and n[4][0] is RED)
                ):
                    a2 = _repair_left(n, ya, yva, ab)
                else:
                    a2 = (ca, n, ya, yva, ab)
            elif ya < keys[lo]:
                if ab is None:
                    absent.extend(range(lo, hi))
                    return t
                n = adjust_insert(ab, keys, vals, lo, hi, f, absent, emptied, j, new)
                if n is ab:
                    return t
                if ca is BLACK and n[0] is RED and (
                    (n[1] is not None and n[1][0] is RED) or (n[4] is not None and n[4][0] is RED)
                ):
                    a2 = _repair_right(aa, ya, yva, n)
                else:
                    a2 = (ca, aa, ya, yva, n)
            else:
                a2 = adjust_insert(a, keys, vals, lo, hi, f, absent, emptied, j, new)
        if a2 is a:
            return t
        if c is BLACK and a2[0] is RED and (
            (a2[1] is not None and a2[1][0] is RED) or (a2[4] is not None and a2[4][0] is RED)
        ):
            return _repair_left(a2, y, yv, b)
        return (c, a2, y, yv, b)
    if y < keys[lo]:  # the whole slice is above y
        if b is None:
            if lo == last:
                return (c, a, y, yv, (RED, None, keys[j], new.pop(), None))
            absent.extend(range(lo, hi))
            return t
        if lo == last:
            b2 = adjust_one_insert(b, keys[j], vals[j], f, j, absent, emptied, new)
        else:  # b's level written out here, as a's above
            bn: Node = b
            cb, ba, yb, yvb, bb = bn
            if keys[last] < yb:
                if ba is None:
                    absent.extend(range(lo, hi))
                    return t
                n = adjust_insert(ba, keys, vals, lo, hi, f, absent, emptied, j, new)
                if n is ba:
                    return t
                if cb is BLACK and n[0] is RED and (
                    (n[1] is not None and n[1][0] is RED) or (n[4] is not None and n[4][0] is RED)
                ):
                    b2 = _repair_left(n, yb, yvb, bb)
                else:
                    b2 = (cb, n, yb, yvb, bb)
            elif yb < keys[lo]:
                if bb is None:
                    absent.extend(range(lo, hi))
                    return t
                n = adjust_insert(bb, keys, vals, lo, hi, f, absent, emptied, j, new)
                if n is bb:
                    return t
                if cb is BLACK and n[0] is RED and (
                    (n[1] is not None and n[1][0] is RED) or (n[4] is not None and n[4][0] is RED)
                ):
                    b2 = _repair_right(ba, yb, yvb, n)
                else:
                    b2 = (cb, ba, yb, yvb, n)
            else:
                b2 = adjust_insert(b, keys, vals, lo, hi, f, absent, emptied, j, new)
        if b2 is b:
            return t
        if c is BLACK and b2[0] is RED and (
            (b2[1] is not None and b2[1][0] is RED) or (b2[4] is not None and b2[4][0] is RED)
        ):
            return _repair_right(a, y, yv, b2)
        return (c, a, y, yv, b2)
    # keys[lo] <= y <= keys[last]: the slice splits at y, as in adjust; j's part inserts.
    i = lo
    while keys[i] < y:
        i += 1
    changed = False
    left = j < i  # j's part: the keys below y, y's own key, or the keys above y
    if i > lo:
        if a is None:
            if left and i - lo == 1:
                a = (RED, None, keys[j], new.pop(), None)
                changed = True
            else:
                absent.extend(range(lo, i))
        else:
            if not left:
                a2 = adjust_one(a, keys[lo], vals[lo], f, lo, absent, emptied) if i - lo == 1 else adjust(
                    a, keys, vals, lo, i, f, absent, emptied
                )
            elif i - lo == 1:
                a2 = adjust_one_insert(a, keys[j], vals[j], f, j, absent, emptied, new)
            else:
                a2 = adjust_insert(a, keys, vals, lo, i, f, absent, emptied, j, new)
            if a2 is not a:
                changed = True
                a = a2
    if not y < keys[i]:  # keys[i] is y's key
        try:
            yv = f(yv, vals[i])
        except Exception as exc:
            raise FailedWith(exc) from None
        if not yv:
            emptied.append(i)
        changed = True
        i += 1
    if i < hi:
        if b is None:
            if j >= i and i == last:
                b = (RED, None, keys[j], new.pop(), None)
                changed = True
            else:
                absent.extend(range(i, hi))
        else:
            if j < i:
                b2 = adjust_one(b, keys[i], vals[i], f, i, absent, emptied) if i == last else adjust(
                    b, keys, vals, i, hi, f, absent, emptied
                )
            elif i == last:
                b2 = adjust_one_insert(b, keys[j], vals[j], f, j, absent, emptied, new)
            else:
                b2 = adjust_insert(b, keys, vals, i, hi, f, absent, emptied, j, new)
            if b2 is not b:
                changed = True
                b = b2
    if not changed:
        return t
    if c is BLACK:
        # Only the side that holds j can have a red child with a red child.
        if left:
            if a is not None and a[0] is RED and (
                (a[1] is not None and a[1][0] is RED) or (a[4] is not None and a[4][0] is RED)
            ):
                return _repair_left(a, y, yv, b)
        elif j >= i and b is not None and b[0] is RED and (
            (b[1] is not None and b[1][0] is RED) or (b[4] is not None and b[4][0] is RED)
        ):
            return _repair_right(a, y, yv, b)
    return (c, a, y, yv, b)


def adjust_one_insert(
    t: Node, k: Any, v: Any, f: Combine, i: int, absent: list[int], emptied: list[int], new: list[Any]
) -> Node:
    """:func:`adjust_one` of the key ``k`` (index ``i``), or ``k ↦ new[0]`` inserted where ``k`` is absent.

    The single-key descent, two comparisons a level (``k`` may be present):
    present, its value becomes ``f(x, v)`` (``i`` to ``emptied`` when falsy);
    absent, a red leaf at the end of the search, the value taken out of
    ``new``, and Okasaki's repairs on the way back up (see :func:`adjust_insert`).
    """
    c, a, y, yv, b = t
    if k < y:
        if a is None:
            return (c, (RED, None, k, new.pop(), None), y, yv, b)
        a2 = adjust_one_insert(a, k, v, f, i, absent, emptied, new)
        if c is BLACK and a2[0] is RED and (
            (a2[1] is not None and a2[1][0] is RED) or (a2[4] is not None and a2[4][0] is RED)
        ):
            return _repair_left(a2, y, yv, b)
        return (c, a2, y, yv, b)
    if y < k:
        if b is None:
            return (c, a, y, yv, (RED, None, k, new.pop(), None))
        b2 = adjust_one_insert(b, k, v, f, i, absent, emptied, new)
        if c is BLACK and b2[0] is RED and (
            (b2[1] is not None and b2[1][0] is RED) or (b2[4] is not None and b2[4][0] is RED)
        ):
            return _repair_right(a, y, yv, b2)
        return (c, a, y, yv, b2)
    try:
        x = f(yv, v)
    except Exception as exc:
        raise FailedWith(exc) from None
    if not x:
        emptied.append(i)
    return (c, a, y, x, b)


def adjust_insert_map(
    f: Combine, m: Any, keys: list[Any], vals: list[Any], j: int, v: Any
) -> tuple[Any, list[int], list[int], bool]:
    """``(m', absent, emptied, inserted)``: :func:`~persistri.impl.maps.red_black_adjust.adjust_sorted_map`,
    and ``keys[j] ↦ v`` inserted in the same descent if ``keys[j]`` is absent (:func:`adjust_insert`; the root
    blackened, the size one more; ``inserted`` says whether it was).  Unchecked (``0 ≤ j < len(keys)``).  The body of
    :meth:`~persistri.impl.maps.red_black.RedBlackMap.adjust_insert`.  O(k + new nodes).
    """
    t = m[1]
    if t is None or not keys:
        return m, list(range(len(keys))), [], False
    absent: list[int] = []
    emptied: list[int] = []
    new = [v]
    try:
        root = adjust_insert(t, keys, vals, 0, len(keys), f, absent, emptied, j, new)
    except FailedWith as failed:
        raise failed.exc from None
    if new:
        return (m[0], root), absent, emptied, False
    if root[0] is RED:
        root = (BLACK, root[1], root[2], root[3], root[4])
    return (m[0] + 1, root), absent, emptied, True
