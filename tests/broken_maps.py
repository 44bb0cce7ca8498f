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
tests) so that each break is a few lines; the others on the red-black tree,
so that the whole suite runs on them at its default size (10^5 keys).
:class:`BareAssertCheckMap` (not in the galleries) is the red-black tree with a
``_check`` that fails a bare ``assert``: its report must name the line.
"""

from __future__ import annotations

import bisect
import weakref
from collections.abc import Callable
from typing import Any, ClassVar

from persistri.impl.maps.assoc_list import assoc_list
from persistri.impl.maps.red_black import red_black
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
grows_mutating = GrowsMutatingMap()
grows_mutating_late = GrowsMutatingLateMap()
ancestor_mutating = AncestorMutatingMap()
stale_find_cache = StaleFindCacheMap()
shared_table = SharedTableMap()

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

AT_SCALE: dict[str, tuple[Any, str, str]] = {
    "grows_mutating": (grows_mutating, "persistence", "growth"),
    "grows_mutating_late": (grows_mutating_late, "persistence", "growth"),
    "ancestor_mutating": (ancestor_mutating, "persistence", "growth"),
    "stale_find_cache": (stale_find_cache, "determinism", "determinism"),
    "shared_table": (shared_table, "isolation", "isolation"),
}
"""Name → (broken structure, the law the suite must name, the test that finds it) for the breaks that only
big maps, replays or a second instance reveal."""
