"""The ``ORD_MAP`` laws of ``remove`` and of the whole-map views, as executable code.

The laws of ``remove`` (of a present and of an absent key) and of the views
that read a whole map: ``listItemsi``, ``listKeys``, ``foldli`` and
``isEmpty``.  The conventions are those of :mod:`persistri.spec.ord_map_laws`,
which re-exports every law.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import Any, TypeVar

from persistri.spec.ord_map import NotFound, OrdMap
from persistri.spec.ord_map_laws_base import (
    LawViolation,
    _equal_keys,
    _find,
    _fingerprint,
    _law,
    _r,
    _same,
    _show,
    _show_option,
    _unchanged,
)
from persistri.spec.order import Order

__all__ = [
    "law_remove",
    "law_remove_absent",
    "law_listItemsi",
    "law_listKeys",
    "law_foldli",
    "law_isEmpty",
]

K = TypeVar("K")
V = TypeVar("V")
M = TypeVar("M")


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
    _fresh_list(s, m, "listItemsi", s.listItemsi, items)


def _fresh_list(s: OrdMap[K, V, M], m: M, law: str, listing: Callable[[M], Any], want: list[Any]) -> None:
    """``listing(m)`` returns a sequence (an iterator or generator is refused: it reads once), and a list it
    returns is the caller's: clearing it must leave ``m`` (and the next listing) as it was.  A map that hands out a list it holds breaks persistence through any caller that sorts,
    appends to or clears its result.  O(n)."""
    got = listing(m)
    if not isinstance(got, Sequence) or isinstance(got, (str, bytes)):
        raise LawViolation(
            law,
            f"{law}(m) returned a {type(got).__name__}, not a list: callers read a listing more than once, "
            "index it and take its len (return a fresh list)",
        )
    if isinstance(got, list) and got:
        got.clear()
        again = list(listing(m))
        if again != want or s.numItems(m) != len(want):
            raise LawViolation(
                law, f"{law}(m) returned a list that m itself holds: clearing it changed m to {_r(again)} (return a fresh list)"
            )


@_law("listKeys")
def law_listKeys(s: OrdMap[K, V, M], m: M) -> None:
    """``listKeys(m)`` is the list of keys of ``listItemsi(m)``, in the same order.  O(n)."""
    keys = list(s.listKeys(m))
    want = [k for k, _ in s.listItemsi(m)]
    if keys != want:
        raise LawViolation("listKeys", f"m = {_show(s, m)}: listKeys(m) = {_r(keys)}, want {_r(want)}")
    _fresh_list(s, m, "listKeys", s.listKeys, keys)


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
