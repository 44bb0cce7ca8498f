"""The ``ORD_MAP`` law table, its violation, and the helpers every law shares.

:data:`ORD_MAP_LAWS` names each law of :class:`~persistri.spec.ord_map.OrdMap`
with its one-line statement; :class:`LawViolation` is what a broken law raises.
The private helpers (bounded reprs, option checks, the fingerprint a later
operation must not change) are shared by the law modules:
:mod:`persistri.spec.ord_map_laws_insert` (construction and queries),
:mod:`persistri.spec.ord_map_laws_contents` (``remove`` and the whole-map views)
and :mod:`persistri.spec.ord_map_laws_versions` (persistence and invariants).
Users import all of it from :mod:`persistri.spec.ord_map_laws`.
"""

from __future__ import annotations

import reprlib
from collections.abc import Callable
from typing import Any, TypeVar

from persistri.spec.law import SignatureLawViolation, law_decorator
from persistri.spec.option import Option
from persistri.spec.ord_map import OrdMap
from persistri.spec.order import Order

__all__ = ["ORD_MAP_LAWS", "LawViolation"]

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
    "listItemsi": "listItemsi(m) is a fresh list, strictly increasing by Key.compare, that agrees with find "
    "and has numItems(m) entries",
    "listKeys": "listKeys(m) = the keys of listItemsi(m), a fresh list",
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


def _items(n: object) -> str:
    """``n items``, singular for one."""
    return f"{n} item" if n == 1 else f"{n} items"


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
            f"{call()} changed its operand m: before it m had {_items(n_before)} {_r(dict(items_before))}, "
            f"after it m has {_items(n_after)} {_r(dict(items_after))}",
        )


def _result(result: Option[M], compute: Callable[[], M]) -> tuple[M, bool]:
    """The operation's result (``result`` when given as ``SOME m2``) and whether it was computed here."""
    if result is not None:
        return result[0], False
    return compute(), True

