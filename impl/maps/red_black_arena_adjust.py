"""The arena red-black tree's batched update: several sorted keys in one descent, one of them inserted in it (paper §2, §4).

The functions of :mod:`persistri.impl.maps.red_black_adjust` and
:mod:`persistri.impl.maps.red_black_adjust_insert` transcribed to
the arena of :mod:`persistri.impl.maps.red_black_arena_tree` (nodes are
indices; :data:`~persistri.impl.maps.red_black_arena_tree.NIL` is the empty
leaf; a node's key and value are its item, reused by every copy of the node and
replaced only where ``f`` gives a new value): the same descents, the same
trees, the same number of new nodes.  Read those modules for the algorithms; the
docstrings here say only what differs.
They are the hot path of the 2-complex's ``replace`` on the arena backend.
Recursive, depth at most the tree height.
"""

from __future__ import annotations

from typing import Any

from persistri.impl.maps.red_black_arena_tree import (
    BLACK,
    NIL,
    RED,
    Arena,
    Combine,
    FailedWith,
    _balance_left,
    _balance_right,
)

__all__ = ["adjust", "adjust_one", "adjust_insert", "adjust_one_insert"]


def adjust(
    A: Arena,
    t: int,
    keys: list[Any],
    vals: list[Any],
    lo: int,
    hi: int,
    f: Combine,
    absent: list[int],
    emptied: list[int],
) -> int:
    """``t`` (a node) with ``x ↦ f(x, vals[i])`` at each present key ``keys[i]``, ``lo ≤ i < hi`` (increasing
    keys): path copying; ``t`` itself when no key of the slice is in it (see
    :func:`~persistri.impl.maps.red_black_adjust.adjust`).  Requires ``hi - lo ≥ 1``.  O(hi − lo + new nodes)."""
    yi = A.item[t]
    y = A.key[yi]
    last = hi - 1
    if keys[last] < y:  # the whole slice is below y
        a = A.left[t]
        if not a:
            absent.extend(range(lo, hi))
            return t
        a2 = adjust_one(A, a, keys[lo], vals[lo], f, lo, absent, emptied) if lo == last else adjust(
            A, a, keys, vals, lo, hi, f, absent, emptied
        )
        return t if a2 == a else A.node(A.red[t], a2, yi, A.right[t])
    if y < keys[lo]:  # the whole slice is above y
        b = A.right[t]
        if not b:
            absent.extend(range(lo, hi))
            return t
        b2 = adjust_one(A, b, keys[lo], vals[lo], f, lo, absent, emptied) if lo == last else adjust(
            A, b, keys, vals, lo, hi, f, absent, emptied
        )
        return t if b2 == b else A.node(A.red[t], A.left[t], yi, b2)
    # keys[lo] <= y <= keys[last]: the scan below stops at the first key not below y.
    a = A.left[t]
    b = A.right[t]
    i = lo
    while keys[i] < y:
        i += 1
    changed = False
    if i > lo:
        if not a:
            absent.extend(range(lo, i))
        else:
            a2 = adjust_one(A, a, keys[lo], vals[lo], f, lo, absent, emptied) if i - lo == 1 else adjust(
                A, a, keys, vals, lo, i, f, absent, emptied
            )
            if a2 != a:
                changed = True
                a = a2
    if not y < keys[i]:  # keys[i] is y's key
        try:
            yv = f(A.val[yi], vals[i])
        except Exception as exc:
            raise FailedWith(exc) from None
        if not yv:
            emptied.append(i)
        yi = A.pair(y, yv)
        changed = True
        i += 1
    if i < hi:
        if not b:
            absent.extend(range(i, hi))
        else:
            b2 = adjust_one(A, b, keys[i], vals[i], f, i, absent, emptied) if i == last else adjust(
                A, b, keys, vals, i, hi, f, absent, emptied
            )
            if b2 != b:
                changed = True
                b = b2
    return A.node(A.red[t], a, yi, b) if changed else t


def adjust_one(
    A: Arena, t: int, k: Any, v: Any, f: Combine, i: int, absent: list[int], emptied: list[int]
) -> int:
    """:func:`adjust` for the one key ``k`` (index ``i``): the single-key descent, two comparisons a level."""
    yi = A.item[t]
    y = A.key[yi]
    if k < y:
        a = A.left[t]
        if not a:
            absent.append(i)
            return t
        a2 = adjust_one(A, a, k, v, f, i, absent, emptied)
        return t if a2 == a else A.node(A.red[t], a2, yi, A.right[t])
    if y < k:
        b = A.right[t]
        if not b:
            absent.append(i)
            return t
        b2 = adjust_one(A, b, k, v, f, i, absent, emptied)
        return t if b2 == b else A.node(A.red[t], A.left[t], yi, b2)
    try:
        x = f(A.val[yi], v)
    except Exception as exc:
        raise FailedWith(exc) from None
    if not x:
        emptied.append(i)
    return A.node(A.red[t], A.left[t], A.pair(y, x), A.right[t])


def adjust_insert(
    A: Arena,
    t: int,
    keys: list[Any],
    vals: list[Any],
    lo: int,
    hi: int,
    f: Combine,
    absent: list[int],
    emptied: list[int],
    j: int,
    new: list[Any],
) -> int:
    """:func:`adjust` of ``keys[lo:hi]``, and ``keys[j] ↦ new[0]`` inserted if ``keys[j]`` is absent
    (``lo ≤ j < hi``), with Okasaki's repairs on the way back up (see
    :func:`~persistri.impl.maps.red_black_adjust_insert.adjust_insert`; an insertion empties ``new``)."""
    yi = A.item[t]
    y = A.key[yi]
    last = hi - 1
    if keys[last] < y:  # the whole slice is below y
        a = A.left[t]
        if not a:
            if lo == last:
                return A.node(A.red[t], A.node(RED, NIL, A.pair(keys[j], new.pop()), NIL), yi, A.right[t])
            absent.extend(range(lo, hi))
            return t
        a2 = adjust_one_insert(A, a, keys[j], vals[j], f, j, absent, emptied, new) if lo == last else adjust_insert(
            A, a, keys, vals, lo, hi, f, absent, emptied, j, new
        )
        if a2 == a:
            return t
        if not A.red[t]:
            if A.red[a2]:
                return _balance_left(A, a2, yi, A.right[t])
            return A.node(BLACK, a2, yi, A.right[t])
        return A.node(RED, a2, yi, A.right[t])
    if y < keys[lo]:  # the whole slice is above y
        b = A.right[t]
        if not b:
            if lo == last:
                return A.node(A.red[t], A.left[t], yi, A.node(RED, NIL, A.pair(keys[j], new.pop()), NIL))
            absent.extend(range(lo, hi))
            return t
        b2 = adjust_one_insert(A, b, keys[j], vals[j], f, j, absent, emptied, new) if lo == last else adjust_insert(
            A, b, keys, vals, lo, hi, f, absent, emptied, j, new
        )
        if b2 == b:
            return t
        if not A.red[t]:
            if A.red[b2]:
                return _balance_right(A, A.left[t], yi, b2)
            return A.node(BLACK, A.left[t], yi, b2)
        return A.node(RED, A.left[t], yi, b2)
    # keys[lo] <= y <= keys[last]: the slice splits at y, as in adjust; j's part inserts.
    a = A.left[t]
    b = A.right[t]
    i = lo
    while keys[i] < y:
        i += 1
    changed = False
    on_left = j < i  # j's part: the keys below y, y's own key, or the keys above y
    if i > lo:
        if not a:
            if on_left and i - lo == 1:
                a = A.node(RED, NIL, A.pair(keys[j], new.pop()), NIL)
                changed = True
            else:
                absent.extend(range(lo, i))
        else:
            if not on_left:
                a2 = adjust_one(A, a, keys[lo], vals[lo], f, lo, absent, emptied) if i - lo == 1 else adjust(
                    A, a, keys, vals, lo, i, f, absent, emptied
                )
            elif i - lo == 1:
                a2 = adjust_one_insert(A, a, keys[j], vals[j], f, j, absent, emptied, new)
            else:
                a2 = adjust_insert(A, a, keys, vals, lo, i, f, absent, emptied, j, new)
            if a2 != a:
                changed = True
                a = a2
    if not y < keys[i]:  # keys[i] is y's key
        try:
            yv = f(A.val[yi], vals[i])
        except Exception as exc:
            raise FailedWith(exc) from None
        if not yv:
            emptied.append(i)
        yi = A.pair(y, yv)
        changed = True
        i += 1
    if i < hi:
        if not b:
            if j >= i and i == last:
                b = A.node(RED, NIL, A.pair(keys[j], new.pop()), NIL)
                changed = True
            else:
                absent.extend(range(i, hi))
        else:
            if j < i:
                b2 = adjust_one(A, b, keys[i], vals[i], f, i, absent, emptied) if i == last else adjust(
                    A, b, keys, vals, i, hi, f, absent, emptied
                )
            elif i == last:
                b2 = adjust_one_insert(A, b, keys[j], vals[j], f, j, absent, emptied, new)
            else:
                b2 = adjust_insert(A, b, keys, vals, i, hi, f, absent, emptied, j, new)
            if b2 != b:
                changed = True
                b = b2
    if not changed:
        return t
    c = A.red[t]
    if not c:
        # Only the side that holds j can have a red child with a red child.
        if on_left:
            if A.red[a]:
                return _balance_left(A, a, yi, b)
        elif j >= i and A.red[b]:
            return _balance_right(A, a, yi, b)
    return A.node(c, a, yi, b)


def adjust_one_insert(
    A: Arena, t: int, k: Any, v: Any, f: Combine, i: int, absent: list[int], emptied: list[int], new: list[Any]
) -> int:
    """:func:`adjust_one` of the key ``k`` (index ``i``), or ``k ↦ new[0]`` inserted where ``k`` is absent."""
    yi = A.item[t]
    y = A.key[yi]
    if k < y:
        a = A.left[t]
        if not a:
            return A.node(A.red[t], A.node(RED, NIL, A.pair(k, new.pop()), NIL), yi, A.right[t])
        a2 = adjust_one_insert(A, a, k, v, f, i, absent, emptied, new)
        if not A.red[t]:
            if A.red[a2]:
                return _balance_left(A, a2, yi, A.right[t])
            return A.node(BLACK, a2, yi, A.right[t])
        return A.node(RED, a2, yi, A.right[t])
    if y < k:
        b = A.right[t]
        if not b:
            return A.node(A.red[t], A.left[t], yi, A.node(RED, NIL, A.pair(k, new.pop()), NIL))
        b2 = adjust_one_insert(A, b, k, v, f, i, absent, emptied, new)
        if not A.red[t]:
            if A.red[b2]:
                return _balance_right(A, A.left[t], yi, b2)
            return A.node(BLACK, A.left[t], yi, b2)
        return A.node(RED, A.left[t], yi, b2)
    try:
        x = f(A.val[yi], v)
    except Exception as exc:
        raise FailedWith(exc) from None
    if not x:
        emptied.append(i)
    return A.node(A.red[t], A.left[t], A.pair(y, x), A.right[t])
