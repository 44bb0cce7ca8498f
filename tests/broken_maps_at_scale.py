"""Deliberately broken ``ORD_MAP`` structures that only big maps, replays or a second instance reveal.

The half of the gallery of :mod:`broken_maps` built on the red-black tree, so
that the whole suite runs on them at its default size (10^5 keys); each breaks
exactly one promise and keeps every other one:

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

:class:`RedBlackDelegate` (every operation by the red-black tree) is the base
other tests break one operation of.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable
from typing import Any, ClassVar

from persistri.impl.maps.red_black import red_black
from persistri.spec.ord_map import NotFound
from persistri.spec.order import NATURAL_ORDER, NaturalOrder

__all__ = [
    "grows_mutating",
    "grows_mutating_late",
    "ancestor_mutating",
    "stale_find_cache",
    "shared_table",
    "AT_SCALE",
    "RedBlackDelegate",
    "GrowsMutatingMap",
    "GrowsMutatingLateMap",
    "AncestorMutatingMap",
    "StaleFindCacheMap",
    "SharedTableMap",
]


class _Cell:
    """A mutable cell holding a red-black map: the map value of :class:`GrowsMutatingMap`.

    ``parent`` refers weakly to the version it was made from (only :class:`AncestorMutatingMap` reads it).
    """

    __slots__ = ("tree", "parent", "__weakref__")

    def __init__(self, tree: Any, parent: _Cell | None = None) -> None:
        self.tree = tree
        self.parent = None if parent is None else weakref.ref(parent)


class GrowsMutatingMap:
    """The red-black tree in a cell, persistent until a map holds ``threshold`` items: from then on ``insert``
    and ``insertWith`` put the new tree into the cell they were given ("large maps are expensive to copy")."""

    threshold: ClassVar[int] = 40

    @property
    def Key(self) -> NaturalOrder[Any]:
        return NATURAL_ORDER

    def _result(self, m: _Cell, tree: Any) -> _Cell:
        if red_black.numItems(m.tree) >= self.threshold:
            m.tree = tree  # the broken promise: the caller's version has changed too
            return m
        return _Cell(tree)

    def empty(self) -> _Cell:
        return _Cell(red_black.empty())

    def isEmpty(self, m: _Cell) -> bool:
        return red_black.isEmpty(m.tree)

    def singleton(self, k: Any, v: Any) -> _Cell:
        return _Cell(red_black.singleton(k, v))

    def insert(self, m: _Cell, k: Any, v: Any) -> _Cell:
        return self._result(m, red_black.insert(m.tree, k, v))

    def insertWith(self, f: Callable[[Any, Any], Any], m: _Cell, k: Any, v: Any) -> _Cell:
        return self._result(m, red_black.insertWith(f, m.tree, k, v))

    def find(self, m: _Cell, k: Any) -> Any:
        return red_black.find(m.tree, k)

    def lookup(self, m: _Cell, k: Any) -> Any:
        return red_black.lookup(m.tree, k)

    def inDomain(self, m: _Cell, k: Any) -> bool:
        return red_black.inDomain(m.tree, k)

    def remove(self, m: _Cell, k: Any) -> tuple[_Cell, Any]:
        tree, v = red_black.remove(m.tree, k)
        return _Cell(tree), v

    def numItems(self, m: _Cell) -> int:
        return red_black.numItems(m.tree)

    def listItemsi(self, m: _Cell) -> list[tuple[Any, Any]]:
        return red_black.listItemsi(m.tree)

    def listKeys(self, m: _Cell) -> list[Any]:
        return red_black.listKeys(m.tree)

    def foldli(self, f: Callable[[Any, Any, Any], Any], init: Any, m: _Cell) -> Any:
        return red_black.foldli(f, init, m.tree)

    def _check(self, m: _Cell) -> None:
        red_black._check(m.tree)


class GrowsMutatingLateMap(GrowsMutatingMap):
    """:class:`GrowsMutatingMap` persistent up to 2,000 items: thousands, not dozens."""

    threshold = 2_000


class AncestorMutatingMap(GrowsMutatingMap):
    """Leaves the map it is given alone, but once maps hold 1,000 items an insert into one also "compacts" the
    version that one was made from, giving it the new tree: an older version changes, not the operand."""

    threshold = 1_000

    def _result(self, m: _Cell, tree: Any) -> _Cell:
        if red_black.numItems(m.tree) >= self.threshold and m.parent is not None:
            older = m.parent()
            if older is not None:
                older.tree = tree  # the broken promise, one version back
        return _Cell(tree, m)


class RedBlackDelegate:
    """Every operation by the red-black tree (whose map values are immutable tuples)."""

    @property
    def Key(self) -> NaturalOrder[Any]:
        return NATURAL_ORDER

    def empty(self) -> Any:
        return red_black.empty()

    def isEmpty(self, m: Any) -> bool:
        return red_black.isEmpty(m)

    def singleton(self, k: Any, v: Any) -> Any:
        return red_black.singleton(k, v)

    def insert(self, m: Any, k: Any, v: Any) -> Any:
        return red_black.insert(m, k, v)

    def insertWith(self, f: Callable[[Any, Any], Any], m: Any, k: Any, v: Any) -> Any:
        return red_black.insertWith(f, m, k, v)

    def find(self, m: Any, k: Any) -> Any:
        return red_black.find(m, k)

    def lookup(self, m: Any, k: Any) -> Any:
        found = self.find(m, k)
        if found is None:
            raise NotFound(k)
        return found[0]

    def inDomain(self, m: Any, k: Any) -> bool:
        return self.find(m, k) is not None

    def remove(self, m: Any, k: Any) -> tuple[Any, Any]:
        return red_black.remove(m, k)

    def numItems(self, m: Any) -> int:
        return red_black.numItems(m)

    def listItemsi(self, m: Any) -> list[tuple[Any, Any]]:
        return red_black.listItemsi(m)

    def listKeys(self, m: Any) -> list[Any]:
        return red_black.listKeys(m)

    def foldli(self, f: Callable[[Any, Any, Any], Any], init: Any, m: Any) -> Any:
        return red_black.foldli(f, init, m)

    def _check(self, m: Any) -> None:
        red_black._check(m)


_MISS = object()


class StaleFindCacheMap(RedBlackDelegate):
    """The red-black tree with ``find`` (and so ``lookup``, ``inDomain``) memoised by ``(id(m), k)``.

    The memo keeps the last 4,096 answers and is never told that a version
    died: a new version that gets a freed version's id answers with its bindings.
    """

    def __init__(self) -> None:
        self._memo: dict[tuple[int, Any], Any] = {}

    def find(self, m: Any, k: Any) -> Any:
        key = (id(m), k)
        hit = self._memo.get(key, _MISS)
        if hit is not _MISS:
            return hit
        found = red_black.find(m, k)
        if len(self._memo) >= 4_096:
            del self._memo[next(iter(self._memo))]
        self._memo[key] = found
        return found


class _Handle:
    """A version of :class:`SharedTableMap`: the number of its map in the table."""

    __slots__ = ("serial", "__weakref__")

    def __init__(self, serial: int) -> None:
        self.serial = serial

    def __repr__(self) -> str:
        return f"<version {self.serial}>"


class SharedTableMap(RedBlackDelegate):
    """Versions are handles into a table of red-black maps; each instance numbers its handles from 0.

    The table is a class attribute — meant to be one per instance — so the
    handles of two instances collide: a second instance's versions overwrite
    the first's.  (A handle's entry leaves the table when the handle dies.)
    """

    _table: ClassVar[dict[int, Any]] = {}

    def __init__(self) -> None:
        self._next = 0

    def _new(self, tree: Any) -> _Handle:
        h = _Handle(self._next)
        self._next += 1
        self._table[h.serial] = tree
        weakref.finalize(h, self._table.pop, h.serial, None)
        return h

    def _map(self, h: _Handle) -> Any:
        return self._table[h.serial]

    def empty(self) -> _Handle:
        return self._new(red_black.empty())

    def isEmpty(self, m: _Handle) -> bool:
        return red_black.isEmpty(self._map(m))

    def singleton(self, k: Any, v: Any) -> _Handle:
        return self._new(red_black.singleton(k, v))

    def insert(self, m: _Handle, k: Any, v: Any) -> _Handle:
        return self._new(red_black.insert(self._map(m), k, v))

    def insertWith(self, f: Callable[[Any, Any], Any], m: _Handle, k: Any, v: Any) -> _Handle:
        return self._new(red_black.insertWith(f, self._map(m), k, v))

    def find(self, m: _Handle, k: Any) -> Any:
        return red_black.find(self._map(m), k)

    def remove(self, m: _Handle, k: Any) -> tuple[_Handle, Any]:
        tree, v = red_black.remove(self._map(m), k)
        return self._new(tree), v

    def numItems(self, m: _Handle) -> int:
        return red_black.numItems(self._map(m))

    def listItemsi(self, m: _Handle) -> list[tuple[Any, Any]]:
        return red_black.listItemsi(self._map(m))

    def listKeys(self, m: _Handle) -> list[Any]:
        return red_black.listKeys(self._map(m))

    def foldli(self, f: Callable[[Any, Any, Any], Any], init: Any, m: _Handle) -> Any:
        return red_black.foldli(f, init, self._map(m))

    def _check(self, m: _Handle) -> None:
        red_black._check(self._map(m))


grows_mutating = GrowsMutatingMap()
grows_mutating_late = GrowsMutatingLateMap()
ancestor_mutating = AncestorMutatingMap()
stale_find_cache = StaleFindCacheMap()
shared_table = SharedTableMap()

AT_SCALE: dict[str, tuple[Any, str, str]] = {
    "grows_mutating": (grows_mutating, "persistence", "growth"),
    "grows_mutating_late": (grows_mutating_late, "persistence", "growth"),
    "ancestor_mutating": (ancestor_mutating, "persistence", "growth"),
    "stale_find_cache": (stale_find_cache, "determinism", "determinism"),
    "shared_table": (shared_table, "isolation", "isolation"),
}
"""Name → (broken structure, the law the suite must name, the test that finds it) for the breaks that only
big maps, replays or a second instance reveal."""
