"""The laws of ``signature ORD_MAP``, as executable code.

Each ``law_*`` function checks one law of :class:`~persistri.spec.ord_map.OrdMap`
on the inputs it is given and raises :class:`LawViolation` (an
:class:`AssertionError`, via :class:`persistri.spec.law.LawViolation`, carrying
the law's name and its one-line statement) when the structure breaks it.  :data:`ORD_MAP_LAWS` lists every law by name; the
conformance suite (:mod:`persistri.spec.conformance`) drives these functions
with hypothesis, and its reports name the law that failed.

The laws are stated *algebraically*, in terms of the structure's own
operations (``find(insert(m, k, v), j) = find(m, j)``), so they need no model of
what ``m`` contains; only :func:`law_persistence` compares versions with model
snapshots.  Conventions:

* ``SOME v`` is the 1-tuple ``(v,)`` and ``NONE`` is ``None``
  (:mod:`persistri.spec.option`); a ``find`` that returns anything else breaks
  the law being checked;
* values are compared with ``is`` or ``==``, keys with ``Key.compare`` (and the
  keys the suite uses satisfy ``compare(a, b) = EQUAL`` exactly when ``a == b``:
  :func:`law_key_order` checks it);
* a law that performs the operation itself also checks that the operation left
  its operand unchanged, and reports a change under ``persistence``; the laws
  of ``insert`` accept the operation's ``result`` (as ``SOME m2``) when the
  caller has already computed it, so that one ``insert`` can be checked by
  several laws;
* an unexpected exception from the structure inside a law is reported as a
  violation of that law (the original exception is chained).

Costs are stated per function; ``n`` is ``numItems(m)`` and a ``find`` is
counted as one operation of the structure.
"""

from __future__ import annotations

import functools
import reprlib
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any, TypeVar

from persistri.spec.law import SignatureLawViolation, law_decorator
from persistri.spec.option import Option
from persistri.spec.ord_map import NotFound, OrdMap
from persistri.spec.order import Order

__all__ = [
    "ORD_MAP_LAWS",
    "LawViolation",
    "law_key_order",
    "law_empty",
    "law_singleton",
    "law_find_insert",
    "law_find_insert_other",
    "law_lookup",
    "law_inDomain",
    "law_insertWith",
    "law_numItems_insert",
    "law_remove",
    "law_remove_absent",
    "law_listItemsi",
    "law_listKeys",
    "law_foldli",
    "law_isEmpty",
    "law_persistence",
    "law_invariants",
]

K = TypeVar("K")
V = TypeVar("V")
M = TypeVar("M")

ORD_MAP_LAWS: dict[str, str] = {
    "key_order": "Key.compare is a total order on the keys used: reflexive, antisymmetric "
    "(EQUAL exactly when the keys are equal; compare(b, a) = -compare(a, b)) and transitive",
    "empty": "isEmpty(empty) and numItems(empty) = 0; empty has no items",
    "singleton": "singleton(k, v) = insert(empty, k, v)",
    "find_insert": "find(insert(m, k, v), k) = SOME v",
    "find_insert_other": "find(insert(m, k, v), j) = find(m, j) for every j ≠ k",
    "lookup": "lookup(m, k) = v when find(m, k) = SOME v, and lookup(m, k) raises NotFound when find(m, k) = NONE",
    "inDomain": "inDomain(m, k) = isSome(find(m, k))",
    "insertWith": "insertWith(f, m, k, v) stores f(old, v) (old first) when find(m, k) = SOME old, "
    "v otherwise, and changes no other key",
    "numItems_insert": "numItems(insert(m, k, v)) = numItems(m) + 1 for a new key k, numItems(m) for a present one",
    "remove": "remove(m, k) of a present key is (m', v) with find(m, k) = SOME v, k absent from m', "
    "numItems(m') = numItems(m) - 1 and every other item unchanged",
    "remove_absent": "remove(m, k) raises NotFound when k is absent from m",
    "listItemsi": "listItemsi(m) is strictly increasing by Key.compare, agrees with find and has numItems(m) entries",
    "listKeys": "listKeys(m) = the keys of listItemsi(m)",
    "foldli": "foldli(f, init, m) applies f to the items of listItemsi(m) in increasing key order, threading the accumulator",
    "isEmpty": "isEmpty(m) exactly when numItems(m) = 0",
    "persistence": "every earlier version is unchanged by any later operation",
    "invariants": "the structure's _check(m) accepts every map its operations produce",
    "determinism": "answers depend only on the versions and arguments given: the same operations replayed later, "
    "on the same or another instance, give the same answers, whatever was made or freed in between "
    "(no cache keyed by object identity, no hidden state)",
    "isolation": "instances share no mutable state: operations on one instance of the structure never change "
    "what the versions of another answer",
}
"""Every ``ORD_MAP`` law: name → one-line statement (for docs and reports)."""


class LawViolation(SignatureLawViolation):
    """A structure broke an ``ORD_MAP`` law: ``law`` is its name, ``statement`` the law, ``detail`` the evidence.

    A subclass of the exception every executable law raises
    (:class:`persistri.spec.law.LawViolation`, itself an :class:`AssertionError`);
    ``statement`` is looked up in :data:`ORD_MAP_LAWS`, so an unknown law name
    is a :class:`ValueError`.
    """

    SIGNATURE = "ORD_MAP"
    LAWS = ORD_MAP_LAWS


# -- helpers ---------------------------------------------------------------------------

_repr = reprlib.Repr()
_repr.maxlist = _repr.maxtuple = _repr.maxdict = _repr.maxset = 12
_repr.maxstring = _repr.maxother = 80
_repr.maxlevel = 4


def _r(x: object) -> str:
    """A bounded ``repr`` for messages (maps in workloads have 10^5 items)."""
    return _repr.repr(x)


_law = law_decorator(LawViolation)


def _show(s: OrdMap[K, V, M], m: M) -> str:
    """``m`` as the items its ``listItemsi`` reports (or its repr when that fails)."""
    try:
        items = list(s.listItemsi(m))
    except Exception as exc:  # the map is shown in a message about another failure
        return f"{_r(m)} (listItemsi raised {type(exc).__name__})"
    shown = ", ".join(f"{_r(k)}: {_r(v)}" for k, v in items[:12])
    more = f", … ({len(items)} items)" if len(items) > 12 else ""
    return "{" + shown + more + "}"


def _same(a: object, b: object) -> bool:
    """Value equality as the laws use it: identity or ``==``."""
    return a is b or a == b


def _option(r: object, law: str, call: Callable[[], str]) -> Option[Any]:
    """Check that ``r`` (the result of the call ``call()`` describes) is an option: ``(v,)`` or ``None``."""
    if r is None or (isinstance(r, tuple) and len(r) == 1):
        return r
    raise LawViolation(law, f"{call()} returned {_r(r)}, which is not an option: SOME v is the 1-tuple (v,), NONE is None")


def _find(s: OrdMap[K, V, M], m: M, k: K, law: str, name: str = "m") -> Option[V]:
    """``find(m, k)``, checked to be an option (the message is only formatted on failure: this is hot)."""
    return _option(s.find(m, k), law, lambda: f"find({name}, {_r(k)})")


def _show_option(o: Option[Any]) -> str:
    return "NONE" if o is None else f"SOME {_r(o[0])}"


def _same_option(a: Option[Any], b: Option[Any]) -> bool:
    if a is None or b is None:
        return a is None and b is None
    return _same(a[0], b[0])


def _equal_keys(s: OrdMap[K, V, M], a: K, b: K) -> bool:
    return s.Key.compare(a, b) is Order.EQUAL


def _fingerprint(s: OrdMap[K, V, M], m: M) -> tuple[list[tuple[K, V]], int]:
    """What a later operation must not change: ``listItemsi(m)`` and ``numItems(m)``."""
    return list(s.listItemsi(m)), s.numItems(m)


def _unchanged(s: OrdMap[K, V, M], m: M, before: tuple[list[tuple[K, V]], int], call: Callable[[], str]) -> None:
    """Raise a ``persistence`` violation if ``m`` no longer has the fingerprint ``before`` (``call()`` names the operation)."""
    after = _fingerprint(s, m)
    items_before, n_before = before
    items_after, n_after = after
    same = n_before == n_after and len(items_before) == len(items_after)
    same = same and all(ka == kb and _same(va, vb) for (ka, va), (kb, vb) in zip(items_before, items_after))
    if not same:
        raise LawViolation(
            "persistence",
            f"{call()} changed its operand m: before it m had {n_before} items {_r(dict(items_before))}, "
            f"after it m has {n_after} items {_r(dict(items_after))}",
        )


def _result(result: Option[M], compute: Callable[[], M]) -> tuple[M, bool]:
    """The operation's result (``result`` when given as ``SOME m2``) and whether it was computed here."""
    if result is not None:
        return result[0], False
    return compute(), True


# -- the laws -----------------------------------------------------------------------


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
                raise LawViolation("key_order", f"Key.compare({_r(a)}, {_r(b)}) returned {_r(c)}, not an Order")
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


@_law("remove")
def law_remove(s: OrdMap[K, V, M], m: M, k: K) -> tuple[M, V]:
    """``remove(m, k)`` of a present key is ``(m', v)``: ``find(m, k) = SOME v``, ``k`` absent from ``m'``,
    one item fewer, every other item unchanged (by ``listItemsi`` and ``find``).

    ``k`` must be present (``find(m, k)`` is not NONE; otherwise that is reported).
    Returns ``remove(m, k)``.  O(n) plus n finds.
    """
    o = _find(s, m, k, "remove")
    if o is None:
        raise LawViolation("remove", f"m = {_show(s, m)}: the key {_r(k)} was put in m but find(m, k) = NONE")
    before = _fingerprint(s, m)
    items, n0 = before
    try:
        m2, got = s.remove(m, k)
    except NotFound as exc:
        raise LawViolation("remove", f"m = {_show(s, m)}: find(m, {_r(k)}) = {_show_option(o)} but remove raised NotFound") from exc

    def where() -> str:
        return f"m = {_r(dict(items))}, k = {_r(k)}"

    if not _same(got, o[0]):
        raise LawViolation("remove", f"{where()}: find(m, k) = {_show_option(o)} but remove returned the value {_r(got)}")
    gone = _find(s, m2, k, "remove", "m'")
    if gone is not None or s.inDomain(m2, k):
        raise LawViolation("remove", f"{where()}: after (m', v) = remove(m, k), find(m', k) = {_show_option(gone)}")
    want = [(kk, vv) for kk, vv in items if not _equal_keys(s, kk, k)]
    rest = list(s.listItemsi(m2))
    if len(rest) != len(want) or not all(a == c and _same(b, d) for (a, b), (c, d) in zip(want, rest)):
        lost = [kk for kk, _ in want if not any(kk == r for r, _ in rest)]
        extra = f" (lost {_r(lost)})" if lost else ""
        raise LawViolation("remove", f"{where()}: listItemsi(m') = {_r(rest)}, want {_r(want)}{extra}")
    if s.numItems(m2) != n0 - 1:
        raise LawViolation("remove", f"{where()}: numItems(m) = {n0} but numItems(m') = {s.numItems(m2)}")
    for kk, vv in want:
        f2 = _find(s, m2, kk, "remove", "m'")
        if f2 is None or not _same(f2[0], vv):
            raise LawViolation("remove", f"{where()}: the other key {_r(kk)} ↦ {_r(vv)} has find(m', {_r(kk)}) = {_show_option(f2)}")
    _unchanged(s, m, before, lambda: f"remove(m, {_r(k)})")
    return m2, got


@_law("remove_absent")
def law_remove_absent(s: OrdMap[K, V, M], m: M, k: K) -> None:
    """``remove(m, k)`` raises :class:`NotFound` when ``find(m, k) = NONE`` (and ``m`` is unchanged).  O(n)."""
    o = _find(s, m, k, "remove_absent")
    if o is not None:
        raise LawViolation("remove_absent", f"m = {_show(s, m)}: the key {_r(k)} should be absent but find(m, k) = {_show_option(o)}")
    before = _fingerprint(s, m)
    try:
        r = s.remove(m, k)
    except NotFound:
        _unchanged(s, m, before, lambda: f"remove(m, {_r(k)}) of an absent key")
        return
    raise LawViolation("remove_absent", f"m = {_show(s, m)}: remove(m, {_r(k)}) of an absent key returned {_r(r)}")


@_law("listItemsi")
def law_listItemsi(s: OrdMap[K, V, M], m: M, probes: Iterable[K] = ()) -> None:
    """``listItemsi(m)`` is strictly increasing by ``Key.compare``, has ``numItems(m)`` entries, agrees with
    ``find`` on every listed item, and lists each of ``probes`` exactly when ``find`` finds it.

    O(n) finds plus O(n·len(probes)) comparisons.
    """
    compare = s.Key.compare
    items = list(s.listItemsi(m))
    for it in items:
        if not (isinstance(it, tuple) and len(it) == 2):
            raise LawViolation("listItemsi", f"listItemsi(m) contains {_r(it)}, not a (key, value) pair")
    n = s.numItems(m)
    if len(items) != n:
        raise LawViolation("listItemsi", f"listItemsi(m) has {len(items)} entries {_r(items)} but numItems(m) = {n}")
    for (a, _), (b, _) in zip(items, items[1:]):
        if compare(a, b) is not Order.LESS:
            raise LawViolation("listItemsi", f"listItemsi(m) = {_r(items)} lists {_r(a)} before {_r(b)}")
    for k, v in items:
        o = _find(s, m, k, "listItemsi")
        if o is None or not _same(o[0], v):
            raise LawViolation("listItemsi", f"listItemsi(m) lists {_r(k)} ↦ {_r(v)} but find(m, {_r(k)}) = {_show_option(o)}")
    for p in probes:
        listed = any(compare(p, k) is Order.EQUAL for k, _ in items)
        o = _find(s, m, p, "listItemsi")
        if listed != (o is not None):
            raise LawViolation(
                "listItemsi",
                f"listItemsi(m) = {_r(items)} {'lists' if listed else 'does not list'} {_r(p)} "
                f"but find(m, {_r(p)}) = {_show_option(o)}",
            )


@_law("listKeys")
def law_listKeys(s: OrdMap[K, V, M], m: M) -> None:
    """``listKeys(m)`` is the list of keys of ``listItemsi(m)``, in the same order.  O(n)."""
    keys = list(s.listKeys(m))
    want = [k for k, _ in s.listItemsi(m)]
    if keys != want:
        raise LawViolation("listKeys", f"m = {_show(s, m)}: listKeys(m) = {_r(keys)}, want {_r(want)}")


@_law("foldli")
def law_foldli(s: OrdMap[K, V, M], m: M) -> None:
    """``foldli(f, init, m)`` calls ``f(k, v, acc)`` on the items of ``listItemsi(m)`` in order, each ``acc`` the
    previous call's result (``init`` first), and returns the last result.

    The fold records the sequence it visits.  O(n).
    """
    visited: list[tuple[K, V]] = []
    accs: list[int] = []

    def record(k: K, v: V, acc: int) -> int:
        visited.append((k, v))
        accs.append(acc)
        return acc + 1

    total = s.foldli(record, 0, m)
    items = list(s.listItemsi(m))
    if len(visited) != len(items) or not all(a == c and _same(b, d) for (a, b), (c, d) in zip(visited, items)):
        raise LawViolation("foldli", f"foldli visited {_r(visited)} but listItemsi(m) = {_r(items)}")
    if accs != list(range(len(accs))) or total != len(visited):
        raise LawViolation(
            "foldli", f"the accumulator was not threaded: f received {_r(accs)} (want 0, 1, 2, …) and foldli returned {_r(total)}"
        )


@_law("isEmpty")
def law_isEmpty(s: OrdMap[K, V, M], m: M) -> None:
    """``isEmpty(m)`` is the ``bool`` ``numItems(m) = 0``.  O(1) for most structures."""
    e, n = s.isEmpty(m), s.numItems(m)
    if e is not (n == 0):
        raise LawViolation("isEmpty", f"m = {_show(s, m)}: isEmpty(m) = {_r(e)} but numItems(m) = {_r(n)}")


def _agrees(
    s: OrdMap[K, V, M], m: M, snapshot: Mapping[K, V], probes: Iterable[K], law: str, describe: Callable[[], str]
) -> None:
    """Raise a violation of ``law`` unless ``m`` agrees with ``snapshot`` by listItemsi, numItems and find.

    ``describe()`` names the version in a message (formatted only on failure).
    """
    compare = s.Key.compare
    items = list(s.listItemsi(m))
    absent = object()
    # Increasing by compare and the same items as the snapshot is equal to the sorted snapshot:
    # O(n) comparisons, where sorting the snapshot would be O(n log n) calls of compare.
    same = len(items) == len(snapshot) and all(_same(snapshot.get(k, absent), v) for k, v in items)
    if not same or not all(compare(a[0], b[0]) is Order.LESS for a, b in zip(items, items[1:])):

        def by_key(a: tuple[K, V], b: tuple[K, V]) -> int:
            return compare(a[0], b[0]).value

        want = sorted(snapshot.items(), key=functools.cmp_to_key(by_key))
        raise LawViolation(law, f"{describe()}: listItemsi = {_r(items)}, but it was {_r(want)}")
    n = s.numItems(m)
    if n != len(snapshot):
        raise LawViolation(law, f"{describe()}: numItems = {_r(n)}, but it was {len(snapshot)} (items {_r(items)})")
    for k, v in snapshot.items():
        o = _find(s, m, k, law, "the version")
        if o is None or not _same(o[0], v):
            raise LawViolation(law, f"{describe()}: find({_r(k)}) = {_show_option(o)}, but it was SOME {_r(v)}")
    for p in probes:
        if p in snapshot:
            continue
        o = _find(s, m, p, law, "the version")
        if o is not None:
            raise LawViolation(law, f"{describe()}: find({_r(p)}) = {_show_option(o)}, but {_r(p)} was absent")


@_law("persistence")
def law_persistence(s: OrdMap[K, V, M], history: Sequence[tuple[M, Mapping[K, V]]], probes: Iterable[K] = ()) -> None:
    """Every version in ``history`` still agrees with the model snapshot taken when it was made.

    ``history`` holds ``(version, snapshot)`` pairs in the order the versions
    were made; a snapshot is a ``dict`` of the items the version had.  "Agrees"
    means: the same ``listItemsi`` and ``numItems``, ``find`` of every snapshot
    key gives its value, and ``find`` of each of ``probes`` absent from the
    snapshot gives NONE.  O(total items) finds.
    """
    ps = list(probes)
    for i, (m, snap) in enumerate(history):

        def describe(i: int = i, snap: Mapping[K, V] = snap) -> str:
            return f"version {i} of {len(history)} (made with items {_r(dict(snap))})"

        _agrees(s, m, snap, ps, "persistence", describe)


@_law("invariants")
def law_invariants(s: object, m: object, where: str = "") -> None:
    """The structure's ``_check(m)`` (its representation invariants) accepts ``m``.

    A structure without ``_check`` has nothing to check (the law holds
    vacuously).  The cost is ``_check``'s, typically O(n).
    """
    check = getattr(s, "_check", None)
    if check is None:
        return
    try:
        check(m)
    except Exception as exc:
        at = f" {where}" if where else ""
        raise LawViolation("invariants", f"_check(m){at} raised {type(exc).__name__}: {exc}") from exc
