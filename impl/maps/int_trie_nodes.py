"""The integer trie's nodes and the algorithms over them (a persistent radix trie; paper §2, §4).

:mod:`persistri.impl.maps.int_trie` is the ``ORD_MAP`` structure built on
these functions; its docstring describes the map, the invariants and the
costs.  They are a module of their own because they are where the map's time
goes: the compiled twin compiles this module and leaves the structure, which
validates keys and raises the signature's errors, interpreted.

A trie of *height* ``s`` (a multiple of :data:`BITS`) holds non-negative
integer indices below ``2**(s + BITS)``.  At ``s == 0`` it is a *leaf*, the
33-tuple ``(keys, v0, …, v31)``: slot ``1 + (k & 31)`` holds the value of
index ``k`` (:data:`~persistri.impl.maps.int_trie_absent.ABSENT` when there is
none) and ``keys``, a 32-tuple, the key object stored for it (``None`` when
absent).  Above, an *internal node* is the 32-tuple of its children, child
``(k >> s) & 31`` holding index ``k`` (``None``: an empty child).  Updating
values copies the path's nodes and shares the leaf's ``keys`` tuple, which
changes only when a key is inserted or removed.  Nodes are typed as tuples of
any length (as in :mod:`~persistri.impl.maps.red_black_tree`, so that mypyc
keeps each node the one object older versions share).  No function changes a
node it is given; each returns new nodes along the paths it changes and
shares every other subtree.  The functions trust their arguments: valid
tries, indices in range.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final, TypeAlias

from persistri.impl.maps.int_trie_absent import ABSENT

__all__ = [
    "BITS",
    "MASK",
    "Node",
    "FailedWith",
    "EMPTY_KEYS",
    "EMPTY_LEAF",
    "EMPTY_INNER",
    "height_for",
    "find",
    "path",
    "put",
    "delete",
    "grow",
    "adjust",
    "put_map",
    "find_unchecked",
    "adjust_insert_map",
    "adjust_sorted_map",
]

BITS: Final = 5
"""Index bits a level (32-way nodes)."""

MASK: Final = 31
"""``2**BITS - 1``."""

Node: TypeAlias = tuple[Any, ...]
"""A leaf ``(keys, v0, …, v31)`` or an internal node ``(c0, …, c31)`` (see the module docstring)."""

Combine: TypeAlias = Callable[[Any, Any], Any]

EMPTY_KEYS: Final[tuple[Any, ...]] = (None,) * 32
EMPTY_LEAF: Final[tuple[Any, ...]] = (EMPTY_KEYS,) + (ABSENT,) * 32
EMPTY_INNER: Final[tuple[Any, ...]] = (None,) * 32


class FailedWith(Exception):
    """A combining function raised ``exc``: carried out of the descent unchanged."""

    def __init__(self, exc: Exception) -> None:
        super().__init__(exc)
        self.exc = exc


def height_for(k: int) -> int:
    """The least height (a multiple of :data:`BITS`) of a trie that can hold the index ``k ≥ 0``.  O(bits of k)."""
    s = 0
    while k >> (s + BITS):
        s += BITS
    return s


def find(t: Node | None, s: int, k: int) -> Any:
    """The value of index ``k`` in the trie ``t`` of height ``s``, or :data:`ABSENT`.  O(s / BITS)."""
    if t is None or k >> (s + BITS):
        return ABSENT
    n: Node = t
    while s:
        c = n[(k >> s) & MASK]
        if c is None:
            return ABSENT
        n = c
        s -= BITS
    return n[(k & MASK) + 1]


def path(s: int, k: int, key: Any, v: Any) -> Node:
    """A trie of height ``s`` holding only index ``k`` (key object ``key``) with value ``v``.  O(s / BITS) new nodes."""
    i = k & MASK
    kl = list(EMPTY_KEYS)
    kl[i] = key
    ll = list(EMPTY_LEAF)
    ll[0] = tuple(kl)
    ll[i + 1] = v
    n: Node = tuple(ll)
    h = BITS
    while h <= s:
        cl = list(EMPTY_INNER)
        cl[(k >> h) & MASK] = n
        n = tuple(cl)
        h += BITS
    return n


def grow(t: Node, s: int, to: int) -> Node:
    """The trie ``t`` of height ``s`` as one of height ``to ≥ s`` (the same items: ``t`` becomes child 0).  O((to − s) / BITS)."""
    while s < to:
        cl = list(EMPTY_INNER)
        cl[0] = t
        t = tuple(cl)
        s += BITS
    return t


def put(t: Node | None, s: int, k: int, key: Any, v: Any, f: Combine | None, added: list[int]) -> Node:
    """``t`` (height ``s``, ``k`` in range) with index ``k`` mapped: to ``f(old, v)`` when present and ``f`` is
    given (the stored key object kept), else to ``v`` with ``key`` stored.  Appends 1 to ``added`` when ``k``
    was absent.  Exceptions of ``f`` are raised as :class:`FailedWith`.  O(s / BITS) new nodes.
    """
    if t is None:
        added.append(1)
        return path(s, k, key, v)
    n: Node = t
    if s == 0:
        i = (k & MASK) + 1
        old = n[i]
        ll = list(n)
        if old is ABSENT:
            added.append(1)
            kl = list(n[0])
            kl[i - 1] = key
            ll[0] = tuple(kl)
            ll[i] = v
        elif f is not None:
            try:
                ll[i] = f(old, v)
            except Exception as exc:
                raise FailedWith(exc) from None
        else:
            ks: Node = n[0]
            if ks[i - 1] is not key:
                kl = list(ks)
                kl[i - 1] = key
                ll[0] = tuple(kl)
            ll[i] = v
        return tuple(ll)
    d = (k >> s) & MASK
    c = put(n[d], s - BITS, k, key, v, f, added)
    cl = list(n)
    cl[d] = c
    return tuple(cl)


def delete(t: Node, s: int, k: int) -> Node | None:
    """``t`` (height ``s``) without the present index ``k``; ``None`` when nothing is left (no empty node is
    kept).  O(s / BITS) new nodes, plus a 32-slot scan a level to see whether a node emptied."""
    if s == 0:
        i = k & MASK
        ks: Node = t[0]
        kl = list(ks)
        kl[i] = None
        kt = tuple(kl)
        if kt == EMPTY_KEYS:
            return None
        ll = list(t)
        ll[0] = kt
        ll[i + 1] = ABSENT
        return tuple(ll)
    d = (k >> s) & MASK
    c = delete(t[d], s - BITS, k)
    cl = list(t)
    cl[d] = c
    n = tuple(cl)
    if c is None and n == EMPTY_INNER:
        return None
    return n


def adjust(
    t: Node,
    s: int,
    keys: list[Any],
    vals: list[Any],
    lo: int,
    hi: int,
    f: Combine,
    absent: list[int],
    emptied: list[int],
    j: int,
    v: Any,
    added: list[int],
) -> Node:
    """``t`` (height ``s``) with ``x ↦ f(x, vals[i])`` at each present index ``keys[i]``, ``lo ≤ i < hi``
    (strictly increasing, in range), and, when ``lo ≤ j < hi`` and ``keys[j]`` is absent, ``keys[j] ↦ v``
    inserted (``j`` appended to ``added``).

    One descent for the slice: the keys under one child are consecutive, so each
    child on their paths is copied once, and each leaf is copied once for all
    its keys (its ``keys`` tuple shared unless ``keys[j]`` is inserted there).
    The indices of absent keys (other than an inserted ``keys[j]``) go to
    ``absent``, those whose new value is falsy to ``emptied``; ``t`` itself is
    returned when nothing changed.  O(hi − lo + new nodes · 32).
    """
    if s == 0:
        ll: list[Any] | None = None
        for i in range(lo, hi):
            k: int = keys[i]
            p = (k & MASK) + 1
            old = t[p]
            if old is ABSENT:
                if i == j:
                    if ll is None:
                        ll = list(t)
                    kl = list(ll[0])
                    kl[p - 1] = keys[i]
                    ll[0] = tuple(kl)
                    ll[p] = v
                    added.append(i)
                else:
                    absent.append(i)
                continue
            try:
                x = f(old, vals[i])
            except Exception as exc:
                raise FailedWith(exc) from None
            if not x:
                emptied.append(i)
            if ll is None:
                ll = list(t)
            ll[p] = x
        return t if ll is None else tuple(ll)
    cl: list[Any] | None = None
    i = lo
    while i < hi:
        k0: int = keys[i]
        d = (k0 >> s) & MASK
        e = i + 1
        while e < hi:
            ke: int = keys[e]
            if (ke >> s) & MASK != d:
                break
            e += 1
        c = t[d]
        if c is None:
            if i <= j < e:
                n: Node = path(s - BITS, keys[j], keys[j], v)
                added.append(j)
                absent.extend(range(i, j))
                absent.extend(range(j + 1, e))
                if cl is None:
                    cl = list(t)
                cl[d] = n
            else:
                absent.extend(range(i, e))
        elif s == BITS:  # the child is a leaf: its level written out here (a call costs as much as its work)
            leaf: Node = c
            ll = None
            for r in range(i, e):
                kr: int = keys[r]
                p = (kr & MASK) + 1
                old = leaf[p]
                if old is ABSENT:
                    if r == j:
                        if ll is None:
                            ll = list(leaf)
                        kl = list(ll[0])
                        kl[p - 1] = keys[r]
                        ll[0] = tuple(kl)
                        ll[p] = v
                        added.append(r)
                    else:
                        absent.append(r)
                    continue
                try:
                    x = f(old, vals[r])
                except Exception as exc:
                    raise FailedWith(exc) from None
                if not x:
                    emptied.append(r)
                if ll is None:
                    ll = list(leaf)
                ll[p] = x
            if ll is not None:
                if cl is None:
                    cl = list(t)
                cl[d] = tuple(ll)
        else:
            n = adjust(c, s - BITS, keys, vals, i, e, f, absent, emptied, j, v, added)
            if n is not c:
                if cl is None:
                    cl = list(t)
                cl[d] = n
        i = e
    return t if cl is None else tuple(cl)


# -- the map-level operations (the map value is described in :mod:`persistri.impl.maps.int_trie`) --------


def put_map(m: Any, k: Any, v: Any, f: Combine | None) -> Any:
    """The map ``m = (size, s, root, ns, nroot)`` (:mod:`~persistri.impl.maps.int_trie`) with the int ``k ↦ v``
    (or ``f(old, v)`` when present and ``f`` is given); exceptions of ``f`` propagate unchanged.  O(b)."""
    n, s, root, ns, nroot = m
    i = k if k >= 0 else ~k
    h = s if k >= 0 else ns
    t = root if k >= 0 else nroot
    if t is None:
        h = height_for(i)
    elif i >> (h + BITS):
        to = height_for(i)
        t = grow(t, h, to)
        h = to
    added: list[int] = []
    try:
        new = put(t, h, i, k, v, f, added)
    except FailedWith as failed:
        raise failed.exc from None
    n += len(added)
    return (n, h, new, ns, nroot) if k >= 0 else (n, s, root, h, new)


def find_unchecked(m: Any, k: Any) -> Any:
    """``find`` for a key known to be an ``int``: persistri's addition, for the 2-complex's walks (the
    vertices are validated before).  The descent of :func:`~persistri.impl.maps.int_trie_nodes.find`
    written out here (on the interpreter a call costs about as much as two levels).  O(b)."""
    if k >= 0:
        t: Any = m[2]
        s = m[1]
    else:
        t = m[4]
        s = m[3]
        k = ~k
    if t is None or k >> (s + 5):
        return None
    while s:
        t = t[(k >> s) & 31]
        if t is None:
            return None
        s -= 5
    v = t[(k & 31) + 1]
    return None if v is ABSENT else (v,)


def adjust_insert_map(
    f: Combine, m: Any, keys: list[Any], vals: list[Any], j: int, v: Any
) -> tuple[Any, list[int], list[int], bool]:
    """``(m', absent, emptied, inserted)``: ``m`` with ``x ↦ f(x, vals[i])`` at each present ``keys[i]``
    (strictly increasing ints; nothing checked), and, when ``0 ≤ j < len(keys)`` and ``keys[j]`` is absent,
    ``keys[j] ↦ v`` inserted in the same descent (``inserted``).  ``absent``: the indices of the other keys
    not in ``m``; ``emptied``: those whose new value is falsy.  Exceptions of ``f`` propagate unchanged.
    O(k + new nodes).  ``j = -1``: :meth:`~persistri.impl.maps.int_trie.IntTrieMap.adjust_sorted`.
    """
    n, s, root, ns, nroot = m
    absent: list[int] = []
    emptied: list[int] = []
    hi = len(keys)
    if hi and keys[0] < 0:  # negative keys (the Delaunay's ghost vertex, -1): those one at a time, then the rest
        neg = 1
        while neg < hi and keys[neg] < 0:
            neg += 1
        m, absent, emptied, inserted = _adjust_slowly(f, m, keys[:neg], vals[:neg], j if j < neg else -1, v)
        if neg == hi:
            return m, absent, emptied, inserted
        m, a2, e2, i2 = adjust_insert_map(f, m, keys[neg:], vals[neg:], j - neg if j >= neg else -1, v)
        absent.extend([i + neg for i in a2])
        emptied.extend([i + neg for i in e2])
        return m, absent, emptied, inserted or i2
    if 0 <= j < hi and (root is None or keys[j] >> (s + BITS)):  # the new key needs a taller trie
        to = height_for(keys[j])
        root = grow(root, s, to) if root is not None else None
        s = to
    while hi and keys[hi - 1] >> (s + BITS):  # beyond the trie: absent
        hi -= 1
        absent.append(hi)
    absent.reverse()
    added: list[int] = []
    if root is None:
        if 0 <= j < hi:
            root = path(s, keys[j], keys[j], v)
            added.append(j)
        absent = [i for i in range(hi) if i != j] + absent
        return (n + len(added), s, root, ns, nroot), absent, emptied, bool(added)
    beyond = absent
    absent = []
    try:
        new = adjust(root, s, keys, vals, 0, hi, f, absent, emptied, j, v, added) if hi else root
    except FailedWith as failed:
        raise failed.exc from None
    if beyond:
        absent.extend(beyond)
    return (n + len(added), s, new, ns, nroot), absent, emptied, bool(added)


def _adjust_slowly(
    f: Combine, m: Any, keys: list[Any], vals: list[Any], j: int, v: Any
) -> tuple[Any, list[int], list[int], bool]:
    """:func:`adjust_insert_map` one key at a time (for negative keys).  O(k·b)."""
    absent: list[int] = []
    emptied: list[int] = []
    inserted = False
    for i, k in enumerate(keys):
        if find_unchecked(m, k) is None:
            if i == j:
                m = put_map(m, k, v, None)
                inserted = True
            else:
                absent.append(i)
            continue
        m = put_map(m, k, vals[i], f)
        found = find_unchecked(m, k)
        assert found is not None
        if not found[0]:
            emptied.append(i)
    return m, absent, emptied, inserted


def adjust_sorted_map(
    f: Combine, m: Any, keys: list[Any], vals: list[Any]
) -> tuple[Any, list[int], list[int]]:
    """``(m', absent, emptied)``: :func:`adjust_insert_map` with no key to insert.  O(k + new nodes)."""
    out, absent, emptied, _ = adjust_insert_map(f, m, keys, vals, -1, None)
    return out, absent, emptied
