"""The ``ORD_MAP`` laws about versions, as executable code: persistence and representation invariants.

:func:`law_persistence` is the one law that compares versions with model
snapshots (every earlier version unchanged by any later operation);
:func:`law_invariants` runs a structure's own ``_check``.  The conventions are
those of :mod:`persistri.spec.ord_map_laws`, which re-exports every law.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import TypeVar

from persistri.spec.ord_map import OrdMap
from persistri.spec.ord_map_laws_base import (
    LawViolation,
    _find,
    _law,
    _r,
    _same,
    _show_option,
)
from persistri.spec.law import raised
from persistri.spec.order import Order

__all__ = ["law_persistence", "law_invariants"]

K = TypeVar("K")
V = TypeVar("V")
M = TypeVar("M")


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
        raise LawViolation("invariants", f"_check(m){at} raised {raised(exc)}") from exc
