"""The ``ORD_MAP`` laws of construction and lookup, as executable code.

The laws of ``Key.compare`` (the order every other law relies on), ``empty``,
``singleton``, ``insert`` (with ``find``), ``lookup``, ``inDomain``,
``insertWith`` and ``numItems`` after an insert.  The conventions (options,
value equality, the ``result`` argument, costs) are those of
:mod:`persistri.spec.ord_map_laws`, which re-exports every law.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import TypeVar

from persistri.spec.option import Option
from persistri.spec.ord_map import NotFound, OrdMap
from persistri.spec.ord_map_laws_base import (
    LawViolation,
    _equal_keys,
    _find,
    _fingerprint,
    _law,
    _r,
    _result,
    _same,
    _same_option,
    _show,
    _show_option,
    _unchanged,
)
from persistri.spec.order import Order

__all__ = [
    "law_key_order",
    "law_empty",
    "law_singleton",
    "law_find_insert",
    "law_find_insert_other",
    "law_lookup",
    "law_inDomain",
    "law_insertWith",
    "law_numItems_insert",
]

K = TypeVar("K")
V = TypeVar("V")
M = TypeVar("M")


@_law("key_order")
def law_key_order(s: OrdMap[K, V, M], keys: Sequence[K]) -> None:
    """``Key.compare`` is a total order on ``keys`` (reflexive, antisymmetric, transitive).

    Also checks that ``compare`` returns an :class:`~persistri.spec.order.Order`
    and is EQUAL exactly when the keys are ``==`` (antisymmetry of a total order;
    the suite's model relies on it).  O(len(keys)³) comparisons: pass a few keys.
    """
    compare = s.Key.compare
    ks = list(keys)
    table: dict[tuple[int, int], Order] = {}
    for i, a in enumerate(ks):
        for j, b in enumerate(ks):
            c = compare(a, b)
            if not isinstance(c, Order):
                raise LawViolation(
                    "key_order",
                    f"Key.compare({_r(a)}, {_r(b)}) returned {_r(c)}, not an Order (persistri.spec.order.Order: "
                    "LESS, EQUAL or GREATER); the laws that compare keys fail with it",
                )
            table[i, j] = c
    for i, a in enumerate(ks):
        if table[i, i] is not Order.EQUAL:
            raise LawViolation("key_order", f"not reflexive: Key.compare({_r(a)}, {_r(a)}) = {table[i, i].name}")
        for j, b in enumerate(ks):
            if table[j, i] is not -table[i, j]:
                raise LawViolation(
                    "key_order",
                    f"not antisymmetric: Key.compare({_r(a)}, {_r(b)}) = {table[i, j].name} "
                    f"but Key.compare({_r(b)}, {_r(a)}) = {table[j, i].name}",
                )
            if (table[i, j] is Order.EQUAL) != (a == b):
                raise LawViolation(
                    "key_order",
                    f"Key.compare({_r(a)}, {_r(b)}) = {table[i, j].name} but {_r(a)} {'==' if a == b else '!='} {_r(b)}",
                )
    n = len(ks)
    for i in range(n):
        for j in range(n):
            if table[i, j] is Order.GREATER:
                continue
            for k in range(n):
                # a ≤ b and b ≤ c must give a ≤ c, strictly when either step is strict.
                if table[j, k] is Order.GREATER:
                    continue
                strict = table[i, j] is Order.LESS or table[j, k] is Order.LESS
                want = (Order.LESS,) if strict else (Order.EQUAL,)
                if table[i, k] not in want:
                    raise LawViolation(
                        "key_order",
                        f"not transitive: {_r(ks[i])} {'<' if table[i, j] is Order.LESS else '='} {_r(ks[j])} "
                        f"{'<' if table[j, k] is Order.LESS else '='} {_r(ks[k])} "
                        f"but Key.compare({_r(ks[i])}, {_r(ks[k])}) = {table[i, k].name}",
                    )


@_law("empty")
def law_empty(s: OrdMap[K, V, M], probes: Iterable[K] = ()) -> M:
    """``empty`` is empty: ``isEmpty``, 0 items, no items listed or folded, ``find`` NONE on ``probes``.

    Returns ``empty()``.  O(len(probes)).
    """
    e = s.empty()
    if s.isEmpty(e) is not True:
        raise LawViolation("empty", f"isEmpty(empty) = {_r(s.isEmpty(e))}")
    if s.numItems(e) != 0:
        raise LawViolation("empty", f"numItems(empty) = {_r(s.numItems(e))}")
    items = list(s.listItemsi(e))
    if items:
        raise LawViolation("empty", f"listItemsi(empty) = {_r(items)}")
    keys = list(s.listKeys(e))
    if keys:
        raise LawViolation("empty", f"listKeys(empty) = {_r(keys)}")
    init = object()
    folded = s.foldli(lambda k, v, acc: acc, init, e)
    if folded is not init:
        raise LawViolation("empty", f"foldli(f, init, empty) returned {_r(folded)}, not init")
    for p in probes:
        o = _find(s, e, p, "empty", "empty")
        if o is not None:
            raise LawViolation("empty", f"find(empty, {_r(p)}) = {_show_option(o)}")
    return e


@_law("singleton")
def law_singleton(s: OrdMap[K, V, M], k: K, v: V, probes: Iterable[K] = ()) -> M:
    """``singleton(k, v)`` behaves as ``insert(empty, k, v)``: same items, count and ``find`` on ``k`` and ``probes``.

    Returns ``singleton(k, v)``.  O(len(probes)).
    """
    one = s.singleton(k, v)
    ins = s.insert(s.empty(), k, v)
    a, b = list(s.listItemsi(one)), list(s.listItemsi(ins))
    if len(a) != len(b) or not all(ka == kb and _same(va, vb) for (ka, va), (kb, vb) in zip(a, b)):
        raise LawViolation(
            "singleton", f"listItemsi(singleton({_r(k)}, {_r(v)})) = {_r(a)} but listItemsi(insert(empty, k, v)) = {_r(b)}"
        )
    if s.numItems(one) != s.numItems(ins):
        raise LawViolation(
            "singleton", f"numItems(singleton({_r(k)}, {_r(v)})) = {s.numItems(one)}, of insert(empty, k, v) {s.numItems(ins)}"
        )
    for p in [k, *probes]:
        x, y = _find(s, one, p, "singleton", "singleton(k, v)"), _find(s, ins, p, "singleton", "insert(empty, k, v)")
        if not _same_option(x, y):
            raise LawViolation(
                "singleton",
                f"find(singleton({_r(k)}, {_r(v)}), {_r(p)}) = {_show_option(x)} "
                f"but find(insert(empty, k, v), {_r(p)}) = {_show_option(y)}",
            )
    return one


@_law("find_insert")
def law_find_insert(s: OrdMap[K, V, M], m: M, k: K, v: V, *, result: Option[M] = None) -> M:
    """``find(insert(m, k, v), k) = SOME v`` (``v`` may be ``None``: then ``find`` returns ``(None,)``).

    ``result`` is ``SOME insert(m, k, v)`` when the caller computed it.  Returns
    ``insert(m, k, v)``.  One ``insert`` and one ``find`` (plus O(n) for the
    persistence check when the insert is done here).
    """
    before = _fingerprint(s, m) if result is None else None
    m2, here = _result(result, lambda: s.insert(m, k, v))
    got = _find(s, m2, k, "find_insert", "insert(m, k, v)")
    if got is None or not _same(got[0], v):
        raise LawViolation(
            "find_insert",
            f"m = {_show(s, m)}, k = {_r(k)}, v = {_r(v)}: find(insert(m, k, v), k) = {_show_option(got)}",
        )
    if here and before is not None:
        _unchanged(s, m, before, lambda: f"insert(m, {_r(k)}, {_r(v)})")
    return m2


@_law("find_insert_other")
def law_find_insert_other(
    s: OrdMap[K, V, M], m: M, k: K, v: V, others: Iterable[K], *, result: Option[M] = None
) -> M:
    """``find(insert(m, k, v), j) = find(m, j)`` for every ``j`` in ``others`` other than ``k``.

    ``find(m, j)`` is read before the insert.  Returns ``insert(m, k, v)``.
    O(len(others)) finds.
    """
    js = [j for j in others if not _equal_keys(s, j, k)]
    olds = [_find(s, m, j, "find_insert_other") for j in js]
    before = _fingerprint(s, m) if result is None else None
    m2, here = _result(result, lambda: s.insert(m, k, v))
    for j, old in zip(js, olds):
        new = _find(s, m2, j, "find_insert_other", "insert(m, k, v)")
        if not _same_option(old, new):
            raise LawViolation(
                "find_insert_other",
                f"m = {_show(s, m)}, k = {_r(k)}, v = {_r(v)}, j = {_r(j)}: "
                f"find(m, j) = {_show_option(old)} but find(insert(m, k, v), j) = {_show_option(new)}",
            )
    if here and before is not None:
        _unchanged(s, m, before, lambda: f"insert(m, {_r(k)}, {_r(v)})")
    return m2


@_law("lookup")
def law_lookup(s: OrdMap[K, V, M], m: M, k: K) -> None:
    """``lookup(m, k)`` returns ``v`` when ``find(m, k) = SOME v`` and raises :class:`NotFound` when NONE.

    One ``find`` and one ``lookup``.
    """
    o = _find(s, m, k, "lookup")
    if o is None:
        try:
            got = s.lookup(m, k)
        except NotFound:
            return
        raise LawViolation("lookup", f"m = {_show(s, m)}: find(m, {_r(k)}) = NONE but lookup returned {_r(got)}")
    try:
        got = s.lookup(m, k)
    except NotFound as exc:
        raise LawViolation(
            "lookup", f"m = {_show(s, m)}: find(m, {_r(k)}) = {_show_option(o)} but lookup raised NotFound"
        ) from exc
    if not _same(got, o[0]):
        raise LawViolation(
            "lookup", f"m = {_show(s, m)}: find(m, {_r(k)}) = {_show_option(o)} but lookup(m, k) = {_r(got)}"
        )


@_law("inDomain")
def law_inDomain(s: OrdMap[K, V, M], m: M, k: K) -> None:
    """``inDomain(m, k)`` is the ``bool`` ``isSome(find(m, k))``.  One ``find`` and one ``inDomain``."""
    o = _find(s, m, k, "inDomain")
    got = s.inDomain(m, k)
    if got is not (o is not None):
        raise LawViolation("inDomain", f"m = {_show(s, m)}: find(m, {_r(k)}) = {_show_option(o)} but inDomain = {_r(got)}")


@_law("insertWith")
def law_insertWith(
    s: OrdMap[K, V, M], f: Callable[[V, V], V], m: M, k: K, v: V, others: Iterable[K] = ()
) -> M:
    """``insertWith(f, m, k, v)`` stores ``f(old, v)`` when ``k ↦ old`` is in ``m``, else ``v``.

    ``f`` must be called exactly once, as ``f(old, v)`` (old first), when ``k``
    is present and not at all when it is absent; the stored value is what that
    call returned.  No key in ``others`` changes, and ``numItems`` changes as for
    ``insert``.  Returns the new map.  O(len(others)) finds plus O(n).
    """
    old = _find(s, m, k, "insertWith")
    js = [j for j in others if not _equal_keys(s, j, k)]
    olds = [_find(s, m, j, "insertWith") for j in js]
    n0 = s.numItems(m)
    before = _fingerprint(s, m)
    calls: list[tuple[V, V, V]] = []

    def recording(a: V, b: V) -> V:
        r = f(a, b)
        calls.append((a, b, r))
        return r

    m2 = s.insertWith(recording, m, k, v)

    def where() -> str:
        return f"m = {_r(dict(before[0]))}, k = {_r(k)}, v = {_r(v)}"

    got = _find(s, m2, k, "insertWith", "insertWith(f, m, k, v)")
    if old is None:
        if calls:
            raise LawViolation("insertWith", f"{where()}: k is absent but f was called with {_r(calls[0][:2])}")
        if got is None or not _same(got[0], v):
            raise LawViolation("insertWith", f"{where()}: k is absent but find(insertWith(f, m, k, v), k) = {_show_option(got)}")
        want_n = n0 + 1
    else:
        if len(calls) != 1 or not (_same(calls[0][0], old[0]) and _same(calls[0][1], v)):
            shown = ", ".join(f"f{_r(c[:2])}" for c in calls) or "none"
            raise LawViolation("insertWith", f"{where()}: k ↦ {_r(old[0])} is present; want one call f(old, v), got: {shown}")
        if got is None or not _same(got[0], calls[0][2]):
            raise LawViolation(
                "insertWith",
                f"{where()}: f(old, v) = {_r(calls[0][2])} but find(insertWith(f, m, k, v), k) = {_show_option(got)}",
            )
        want_n = n0
    if s.numItems(m2) != want_n:
        raise LawViolation("insertWith", f"{where()}: numItems(m) = {n0} but numItems(insertWith(f, m, k, v)) = {s.numItems(m2)}")
    for j, o in zip(js, olds):
        new = _find(s, m2, j, "insertWith", "insertWith(f, m, k, v)")
        if not _same_option(o, new):
            raise LawViolation(
                "insertWith",
                f"{where()}, j = {_r(j)}: find(m, j) = {_show_option(o)} but find(insertWith(f, m, k, v), j) = {_show_option(new)}",
            )
    _unchanged(s, m, before, lambda: f"insertWith(f, m, {_r(k)}, {_r(v)})")
    return m2


@_law("numItems_insert")
def law_numItems_insert(s: OrdMap[K, V, M], m: M, k: K, v: V, *, result: Option[M] = None) -> M:
    """``numItems(insert(m, k, v))`` is ``numItems(m) + 1`` for a new key, ``numItems(m)`` for a present one.

    Presence is read with ``find(m, k)`` before the insert.  Returns
    ``insert(m, k, v)``.
    """
    present = _find(s, m, k, "numItems_insert") is not None
    n0 = s.numItems(m)
    before = _fingerprint(s, m) if result is None else None
    m2, here = _result(result, lambda: s.insert(m, k, v))
    n1 = s.numItems(m2)
    want = n0 if present else n0 + 1
    if n1 != want:
        what = "overwriting the present key" if present else "inserting the new key"
        raise LawViolation(
            "numItems_insert",
            f"m = {_show(s, m)} has numItems {n0}; after {what} {_r(k)} (v = {_r(v)}), numItems = {_r(n1)}, want {want}",
        )
    if here and before is not None:
        _unchanged(s, m, before, lambda: f"insert(m, {_r(k)}, {_r(v)})")
    return m2
