"""Deliberately broken ``ORD_MAP`` structures: the conformance suite must reject each, naming the law.

Each breaks exactly one promise and keeps every other one, so that a report
naming the wrong law (or none) is a defect of the suite:

* :data:`mutating` — ``insert`` updates the map it was given in place (persistence);
* :data:`lossy_remove` — ``remove`` also drops the smallest other key (remove);
* :data:`miscounting` — ``numItems`` grows when a key is overwritten (numItems_insert);
* :data:`absent_remove` — ``remove`` of an absent key returns the map instead of
  raising ``NotFound`` (remove_absent); its map values print with Python's default
  repr, which names a memory address that differs on every run;
* :data:`iterator_listing` — ``listItemsi`` returns an iterator over the items, which a
  caller can read only once (listItemsi);
* :data:`bad_check` — externally correct, but its representation breaks the
  invariant its own ``_check`` asserts (invariants);
* :data:`shared_listing` — ``listItemsi`` returns the list a version holds, so a
  caller that edits it edits the version (listItemsi);
* :data:`grows_mutating` and :data:`grows_mutating_late` — persistent while
  small, but once a map holds 40 (or 2,000) items ``insert`` and ``insertWith``
  write the new tree into the map they were given (persistence: only the growth
  workload makes maps that big);
* :data:`ancestor_mutating` — leaves its operand alone, but once maps hold
  1,000 items an insert also rewrites the version its operand was made from
  (persistence, pinned by replays to the insert that did it);
* :data:`stale_find_cache` — ``find`` memoised by ``(id(m), k)`` and never
  invalidated: once a version is freed, a new version with its id answers with
  the old one's bindings (determinism);
* :data:`shared_table` — versions are handles into a table that is a class
  attribute, each instance numbering its handles from 0: a second instance's
  versions overwrite the first's (isolation).

The first seven are built on the association list (correct by the suite's own
tests) so that each break is a few lines, and defined here; the others on the
red-black tree, so that the whole suite runs on them at its default size
(10^5 keys), defined in :mod:`broken_maps_at_scale` and re-exported here.
:class:`BareAssertCheckMap` (not in the galleries) is the red-black tree with a
``_check`` that fails a bare ``assert``: its report must name the line.
"""

from __future__ import annotations

import bisect
from collections.abc import Callable
from typing import Any

from broken_maps_at_scale import (
    AT_SCALE,
    AncestorMutatingMap,
    GrowsMutatingLateMap,
    GrowsMutatingMap,
    RedBlackDelegate,
    SharedTableMap,
    StaleFindCacheMap,
    ancestor_mutating,
    grows_mutating,
    grows_mutating_late,
    shared_table,
    stale_find_cache,
)
from persistri.impl.maps.assoc_list import assoc_list
from persistri.spec.ord_map import NotFound
from persistri.spec.order import NATURAL_ORDER, NaturalOrder

__all__ = [
    "mutating",
    "lossy_remove",
    "miscounting",
    "bad_check",
    "grows_mutating",
    "grows_mutating_late",
    "ancestor_mutating",
    "stale_find_cache",
    "shared_table",
    "shared_listing",
    "absent_remove",
    "iterator_listing",
    "BROKEN",
    "AT_SCALE",
    "MutatingMap",
    "RedBlackDelegate",
    "GrowsMutatingMap",
    "GrowsMutatingLateMap",
    "AncestorMutatingMap",
    "StaleFindCacheMap",
    "SharedTableMap",
    "SharedListingMap",
    "AbsentRemoveMap",
    "IteratorListingMap",
    "BareAssertCheckMap",
]


class _Delegating:
    """Every operation by the association list on the wrapped map ``self._wrap``/``self._unwrap``."""

    @property
    def Key(self) -> NaturalOrder[Any]:
        return NATURAL_ORDER

    def _wrap(self, inner: Any) -> Any:
        return inner

    def _unwrap(self, m: Any) -> Any:
        return m

    def empty(self) -> Any:
        return self._wrap(assoc_list.empty())

    def isEmpty(self, m: Any) -> bool:
        return self.numItems(m) == 0

    def singleton(self, k: Any, v: Any) -> Any:
        return self.insert(self.empty(), k, v)

    def insert(self, m: Any, k: Any, v: Any) -> Any:
        return self._wrap(assoc_list.insert(self._unwrap(m), k, v))

    def insertWith(self, f: Callable[[Any, Any], Any], m: Any, k: Any, v: Any) -> Any:
        return self._wrap(assoc_list.insertWith(f, self._unwrap(m), k, v))

    def find(self, m: Any, k: Any) -> Any:
        return assoc_list.find(self._unwrap(m), k)

    def lookup(self, m: Any, k: Any) -> Any:
        return assoc_list.lookup(self._unwrap(m), k)

    def inDomain(self, m: Any, k: Any) -> bool:
        return assoc_list.inDomain(self._unwrap(m), k)

    def remove(self, m: Any, k: Any) -> tuple[Any, Any]:
        inner, v = assoc_list.remove(self._unwrap(m), k)
        return self._wrap(inner), v

    def numItems(self, m: Any) -> int:
        return assoc_list.numItems(self._unwrap(m))

    def listItemsi(self, m: Any) -> list[tuple[Any, Any]]:
        return assoc_list.listItemsi(self._unwrap(m))

    def listKeys(self, m: Any) -> list[Any]:
        return assoc_list.listKeys(self._unwrap(m))

    def foldli(self, f: Callable[[Any, Any, Any], Any], init: Any, m: Any) -> Any:
        return assoc_list.foldli(f, init, self._unwrap(m))


class MutatingMap(_Delegating):
    """An ephemeral map posing as persistent: a map is a mutable sorted list, ``insert`` edits it in place."""

    def empty(self) -> Any:
        return []

    def insert(self, m: Any, k: Any, v: Any) -> Any:
        keys = [kk for kk, _ in m]
        i = bisect.bisect_left(keys, k)
        if i < len(m) and m[i][0] == k:
            m[i] = (k, v)
        else:
            m.insert(i, (k, v))
        return m  # the broken promise: the caller's version has changed too

    def insertWith(self, f: Callable[[Any, Any], Any], m: Any, k: Any, v: Any) -> Any:
        o = self.find(m, k)
        return self.insert(m, k, v if o is None else f(o[0], v))

    def find(self, m: Any, k: Any) -> Any:
        for kk, vv in m:
            if kk == k:
                return (vv,)
        return None

    def lookup(self, m: Any, k: Any) -> Any:
        o = self.find(m, k)
        if o is None:
            raise NotFound(k)
        return o[0]

    def inDomain(self, m: Any, k: Any) -> bool:
        return self.find(m, k) is not None

    def remove(self, m: Any, k: Any) -> tuple[Any, Any]:
        o = self.find(m, k)
        if o is None:
            raise NotFound(k)
        return [(kk, vv) for kk, vv in m if kk != k], o[0]  # remove itself copies correctly

    def numItems(self, m: Any) -> int:
        return len(m)

    def listItemsi(self, m: Any) -> list[tuple[Any, Any]]:
        return list(m)

    def listKeys(self, m: Any) -> list[Any]:
        return [k for k, _ in m]

    def foldli(self, f: Callable[[Any, Any, Any], Any], init: Any, m: Any) -> Any:
        acc = init
        for k, v in list(m):
            acc = f(k, v, acc)
        return acc


class LossyRemoveMap(_Delegating):
    """``remove(m, k)`` also loses the smallest other key of ``m``, when there is one."""

    def remove(self, m: Any, k: Any) -> tuple[Any, Any]:
        inner, v = assoc_list.remove(m, k)
        others = assoc_list.listKeys(inner)
        if others:
            inner, _ = assoc_list.remove(inner, others[0])
        return inner, v


class MiscountingMap(_Delegating):
    """A map is ``(association list, count)``; the count grows on every insert, overwrite or not."""

    def _wrap(self, inner: Any) -> Any:
        raise AssertionError("every operation below builds its own pair")

    def _unwrap(self, m: Any) -> Any:
        return m[0]

    def empty(self) -> Any:
        return (assoc_list.empty(), 0)

    def insert(self, m: Any, k: Any, v: Any) -> Any:
        return (assoc_list.insert(m[0], k, v), m[1] + 1)

    def insertWith(self, f: Callable[[Any, Any], Any], m: Any, k: Any, v: Any) -> Any:
        return (assoc_list.insertWith(f, m[0], k, v), m[1] + 1)

    def remove(self, m: Any, k: Any) -> tuple[Any, Any]:
        inner, v = assoc_list.remove(m[0], k)
        return (inner, m[1] - 1), v

    def numItems(self, m: Any) -> int:
        return int(m[1])


class BadCheckMap(_Delegating):
    """Correct from outside, but a map is a tuple of items in *insertion* order (sorted only when
    listed) while its ``_check`` asserts the items are stored sorted."""

    def empty(self) -> Any:
        return ()

    def _unwrap(self, m: Any) -> Any:
        cells = None  # the association list of the sorted items, built directly: O(n log n)
        for k, v in sorted(m, key=lambda kv: kv[0], reverse=True):
            cells = (k, v, cells)
        return (len(m), cells)

    def insert(self, m: Any, k: Any, v: Any) -> Any:
        return tuple((kk, vv) for kk, vv in m if kk != k) + ((k, v),)

    def insertWith(self, f: Callable[[Any, Any], Any], m: Any, k: Any, v: Any) -> Any:
        o = self.find(m, k)
        return self.insert(m, k, v if o is None else f(o[0], v))

    def remove(self, m: Any, k: Any) -> tuple[Any, Any]:
        v = self.lookup(m, k)
        return tuple((kk, vv) for kk, vv in m if kk != k), v

    def _check(self, m: Any) -> None:
        keys = [k for k, _ in m]
        assert keys == sorted(keys), f"bad_check: items stored out of order: {keys}"


class SharedListingMap(_Delegating):
    """A map is the list of its items, copied by every update; ``listItemsi`` returns that list itself, so a
    caller that sorts, appends to or clears its result changes the version."""

    def _wrap(self, inner: Any) -> Any:
        return assoc_list.listItemsi(inner)

    def _unwrap(self, m: Any) -> Any:
        inner = assoc_list.empty()
        for k, v in m:
            inner = assoc_list.insert(inner, k, v)
        return inner

    def listItemsi(self, m: Any) -> list[tuple[Any, Any]]:
        return m  # type: ignore[no-any-return]


class _Box:
    """A map value of :class:`AbsentRemoveMap`: an association list in an object printed by Python's default
    repr (``<broken_maps._Box object at 0x7f…>``), as an outside backend's tree nodes often are."""

    __slots__ = ("inner",)

    def __init__(self, inner: Any) -> None:
        self.inner = inner


class AbsentRemoveMap(_Delegating):
    """``remove(m, k)`` of an absent ``k`` returns ``(m', None)`` with ``m'`` holding what ``m`` holds, instead of
    raising ``NotFound``.  The same wrong answer every time; only the addresses in its printed form change, so a
    suite that compared a failure's text with its rerun's, addresses included, would call it hidden state."""

    def _wrap(self, inner: Any) -> Any:
        return _Box(inner)

    def _unwrap(self, m: Any) -> Any:
        return m.inner

    def remove(self, m: Any, k: Any) -> tuple[Any, Any]:
        if not assoc_list.inDomain(m.inner, k):
            return _Box(m.inner), None
        return super().remove(m, k)


class IteratorListingMap(_Delegating):
    """``listItemsi`` returns an iterator over the right items, in the right order: a caller that reads the
    listing twice, indexes it or takes its ``len`` gets nothing or an error."""

    def listItemsi(self, m: Any) -> Any:
        return iter(assoc_list.listItemsi(m))


class BareAssertCheckMap(RedBlackDelegate):
    """The red-black tree with a ``_check`` written as outside authors write them, a bare ``assert`` (here one
    that fails from three items on): its ``AssertionError`` has no message, so a report must name the line.
    (Defined here, not in a test module, so that pytest does not rewrite the ``assert`` and add one.)"""

    def _check(self, m: Any) -> None:
        assert self.numItems(m) < 3


mutating = MutatingMap()
lossy_remove = LossyRemoveMap()
miscounting = MiscountingMap()
bad_check = BadCheckMap()
shared_listing = SharedListingMap()
absent_remove = AbsentRemoveMap()
iterator_listing = IteratorListingMap()

BROKEN: dict[str, tuple[Any, str]] = {
    "mutating": (mutating, "persistence"),
    "lossy_remove": (lossy_remove, "remove"),
    "miscounting": (miscounting, "numItems_insert"),
    "bad_check": (bad_check, "invariants"),
    "shared_listing": (shared_listing, "listItemsi"),
    "absent_remove": (absent_remove, "remove_absent"),
    "iterator_listing": (iterator_listing, "listItemsi"),
}
"""Name → (broken structure, the law the suite must name) for the breaks hypothesis's small maps find."""
