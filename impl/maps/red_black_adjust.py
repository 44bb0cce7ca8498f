"""Several sorted keys of a red-black tree updated in one descent (paper §2, §4).

The 2-complex's ``replace`` changes the lists of a few vertices at once.  The
functions here are that change of the red-black tree: one descent for all the
keys, so that the nodes their search paths share, the top of the tree above
all, are copied once.

* :func:`adjust` and :func:`adjust_one` update present keys only (path
  copying; shape and colours kept) and report the absent ones;
* :func:`adjust_sorted_map` is the structure's operation over them on a whole
  map, and is :meth:`~persistri.impl.maps.red_black.RedBlackMap.adjust_sorted`
  itself (a static method: on the twin a call of it runs no interpreted code).

When ``replace`` puts a cone on a fresh vertex it also inserts that vertex in
the same descent: :mod:`persistri.impl.maps.red_black_adjust_insert`, built on
these functions.  A module of its own because these are the hot path of every
``replace`` (a third to a half of each algorithm's profile): the compiled twin
compiles it (``tools/compiled_twin.py``), and nodes are typed as in
:mod:`~persistri.impl.maps.red_black_tree` (tuples of any length, so that
mypyc keeps each node the one object that older versions share).  Recursive,
depth at most the tree height.  :func:`adjust_one`, and :func:`adjust` where
the slice lies on one side of a node, write the child's level out in their own
frame, two levels a call (as ``adjust_insert`` does): on the interpreter a
Python call costs about as much as a level's own work (on the OnSphere hull's
``replace`` calls, the descent's instructions −6.6 %).  The child is first
bound to a name typed ``Node``: mypyc unpacks a tuple by index, a value typed
``Any`` by iterating over it.
"""

from __future__ import annotations

from typing import Any

from persistri.impl.maps.red_black_tree import Combine, FailedWith, Node

__all__ = ["adjust", "adjust_one", "adjust_sorted_map"]


def adjust(
    t: Node, keys: list[Any], vals: list[Any], lo: int, hi: int, f: Combine, absent: list[int], emptied: list[int]
) -> Node:
    """``t`` with ``x ↦ f(x, vals[i])`` at each present key ``keys[i]``, ``lo ≤ i < hi`` (increasing keys):
    path copying.

    One descent for the whole slice: while every key of the slice is on one
    side of a node (one comparison with its last key, or two with its first and
    last) the descent goes on there; where the slice straddles a node it splits
    into the keys below it, its own key, and the keys above it.  Only subtrees
    that hold keys of the slice are rebuilt, so paths are copied once where they
    are shared; a part left with one key goes to :func:`adjust_one`, the
    single-key descent.  The indices of keys that end at a leaf are appended to
    ``absent``, those whose new value is falsy (an emptied collection) to
    ``emptied``; a subtree holding none of the present keys is returned as it
    is.  Shape and colours are kept, and so are the key objects of the tree.
    Requires ``hi - lo ≥ 1``.  O(hi − lo + new nodes).
    """
    c, a, y, yv, b = t
    last = hi - 1
    if keys[last] < y:  # the whole slice is below y
        if a is None:
            absent.extend(range(lo, hi))
            return t
        if lo == last:
            a2 = adjust_one(a, keys[lo], vals[lo], f, lo, absent, emptied)
        else:  # a's level written out here (two levels a call) while the slice stays on one side
            an: Node = a
            ca, aa, ya, yva, ab = an
            if keys[last] < ya:
                if aa is None:
                    absent.extend(range(lo, hi))
                    return t
                n = adjust(aa, keys, vals, lo, hi, f, absent, emptied)
                return t if n is aa else (c, (ca, n, ya, yva, ab), y, yv, b)
            if ya < keys[lo]:
                if ab is None:
                    absent.extend(range(lo, hi))
                    return t
                n = adjust(ab, keys, vals, lo, hi, f, absent, emptied)
                return t if n is ab else (c, (ca, aa, ya, yva, n), y, yv, b)
            a2 = adjust(a, keys, vals, lo, hi, f, absent, emptied)
        return t if a2 is a else (c, a2, y, yv, b)
    if y < keys[lo]:  # the whole slice is above y
        if b is None:
            absent.extend(range(lo, hi))
            return t
        if lo == last:
            b2 = adjust_one(b, keys[lo], vals[lo], f, lo, absent, emptied)
        else:  # b's level written out here, as a's above
            bn: Node = b
            cb, ba, yb, yvb, bb = bn
            if keys[last] < yb:
                if ba is None:
                    absent.extend(range(lo, hi))
                    return t
                n = adjust(ba, keys, vals, lo, hi, f, absent, emptied)
                return t if n is ba else (c, a, y, yv, (cb, n, yb, yvb, bb))
            if yb < keys[lo]:
                if bb is None:
                    absent.extend(range(lo, hi))
                    return t
                n = adjust(bb, keys, vals, lo, hi, f, absent, emptied)
                return t if n is bb else (c, a, y, yv, (cb, ba, yb, yvb, n))
            b2 = adjust(b, keys, vals, lo, hi, f, absent, emptied)
        return t if b2 is b else (c, a, y, yv, b2)
    # keys[lo] <= y <= keys[last]: the scan below stops at the first key not below y.
    i = lo
    while keys[i] < y:
        i += 1
    changed = False
    if i > lo:
        if a is None:
            absent.extend(range(lo, i))
        else:
            a2 = adjust_one(a, keys[lo], vals[lo], f, lo, absent, emptied) if i - lo == 1 else adjust(
                a, keys, vals, lo, i, f, absent, emptied
            )
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
            absent.extend(range(i, hi))
        else:
            b2 = adjust_one(b, keys[i], vals[i], f, i, absent, emptied) if i == last else adjust(
                b, keys, vals, i, hi, f, absent, emptied
            )
            if b2 is not b:
                changed = True
                b = b2
    return (c, a, y, yv, b) if changed else t


def adjust_one(t: Node, k: Any, v: Any, f: Combine, i: int, absent: list[int], emptied: list[int]) -> Node:
    """:func:`adjust` for the one key ``k`` (index ``i``) with argument ``v``: ``t`` with ``x ↦ f(x, v)`` at ``k``,
    or ``t`` itself with ``i`` appended to ``absent`` when ``k`` is not in ``t``.

    The single-key descent, two comparisons a level; ``i`` goes to ``emptied``
    when the new value is falsy.  Recursive, two levels a call (the child's
    level is written out in the parent's frame: a Python call costs about as
    much as a level's own work), depth at most half the tree height.
    """
    c, a, y, yv, b = t
    if k < y:
        if a is None:
            absent.append(i)
            return t
        an: Node = a
        ca, aa, ya, yva, ab = an
        if k < ya:
            if aa is None:
                absent.append(i)
                return t
            n = adjust_one(aa, k, v, f, i, absent, emptied)
            return t if n is aa else (c, (ca, n, ya, yva, ab), y, yv, b)
        if ya < k:
            if ab is None:
                absent.append(i)
                return t
            n = adjust_one(ab, k, v, f, i, absent, emptied)
            return t if n is ab else (c, (ca, aa, ya, yva, n), y, yv, b)
        try:
            x = f(yva, v)
        except Exception as exc:
            raise FailedWith(exc) from None
        if not x:
            emptied.append(i)
        return (c, (ca, aa, ya, x, ab), y, yv, b)
    if y < k:
        if b is None:
            absent.append(i)
            return t
        bn: Node = b
        cb, ba, yb, yvb, bb = bn
        if k < yb:
            if ba is None:
                absent.append(i)
                return t
            n = adjust_one(ba, k, v, f, i, absent, emptied)
            return t if n is ba else (c, a, y, yv, (cb, n, yb, yvb, bb))
        if yb < k:
            if bb is None:
                absent.append(i)
                return t
            n = adjust_one(bb, k, v, f, i, absent, emptied)
            return t if n is bb else (c, a, y, yv, (cb, ba, yb, yvb, n))
        try:
            x = f(yvb, v)
        except Exception as exc:
            raise FailedWith(exc) from None
        if not x:
            emptied.append(i)
        return (c, a, y, yv, (cb, ba, yb, x, bb))
    try:
        x = f(yv, v)
    except Exception as exc:
        raise FailedWith(exc) from None
    if not x:
        emptied.append(i)
    return (c, a, y, x, b)


# -- the structure's operations on a whole map ------------------------------------------


def adjust_sorted_map(f: Combine, m: Any, keys: list[Any], vals: list[Any]) -> tuple[Any, list[int], list[int]]:
    """``(m', absent, emptied)`` for the map ``m = (size, tree)``: :func:`adjust` of every key (``keys``
    strictly increasing, ordered with the map's; nothing checked), the indices of the keys not in ``m``,
    and those whose new value ``f(old, vals[i])`` is falsy.  ``m`` itself when ``keys`` is empty or the map
    is.  Exceptions raised by ``f`` propagate unchanged.  The body of
    :meth:`~persistri.impl.maps.red_black.RedBlackMap.adjust_sorted`.  O(k + new nodes).
    """
    t = m[1]
    if t is None or not keys:
        return m, list(range(len(keys))), []
    absent: list[int] = []
    emptied: list[int] = []
    try:
        new = adjust(t, keys, vals, 0, len(keys), f, absent, emptied)
    except FailedWith as failed:
        raise failed.exc from None
    return (m[0], new), absent, emptied
