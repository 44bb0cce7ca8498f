"""Deliberately broken ``ORD_MAP`` structures: the conformance suite must reject each, naming the law.

Each breaks exactly one promise and keeps every other one, so that a report
naming the wrong law (or none) is a defect of the suite:

* :data:`mutating` — ``insert`` updates the map it was given in place (persistence);
* :data:`lossy_remove` — ``remove`` also drops the smallest other key (remove);
* :data:`miscounting` — ``numItems`` grows when a key is overwritten (numItems_insert);
* :data:`bad_check` — externally correct, but its representation breaks the
  invariant its own ``_check`` asserts (invariants).

They are built on the association list (correct by the suite's own tests) so
that each break is a few lines.
"""

from __future__ import annotations

import bisect
from collections.abc import Callable
from typing import Any

from persistri.impl.maps.assoc_list import assoc_list
from persistri.spec.ord_map import NotFound
from persistri.spec.order import NATURAL_ORDER, NaturalOrder

__all__ = ["mutating", "lossy_remove", "miscounting", "bad_check", "BROKEN", "MutatingMap"]


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


mutating = MutatingMap()
lossy_remove = LossyRemoveMap()
miscounting = MiscountingMap()
bad_check = BadCheckMap()

BROKEN: dict[str, tuple[Any, str]] = {
    "mutating": (mutating, "persistence"),
    "lossy_remove": (lossy_remove, "remove"),
    "miscounting": (miscounting, "numItems_insert"),
    "bad_check": (bad_check, "invariants"),
}
"""Name → (broken structure, the law the suite must name)."""
