"""Deliberately broken 2-complexes: the laws and the checks must reject each, naming what broke.

Each breaks one promise of the specialised 2-complex and keeps the others:

* :class:`OrientationBlindFind` — ``find(c, (u, w))`` also returns the triangles
  holding the reverse edge (w, u): orientation ignored (law ``find``);
* :class:`StaleRem` — ``rem`` forgets to drop the triangle from its third
  vertex's list (law ``rem``; :func:`check_complex` reports the representation);
* :func:`mutating_add` — a 2-complex over a map backend whose ``insertWith``
  updates the map it was given in place, so ``add`` changes the previous
  version (law ``persistence``).

And, for the conformance suite's tests at scale (:data:`AT_SCALE`), 2-complexes over the red-black
2-complex that break only what big complexes, replays or a second instance reveal:

* :data:`grows_mutating` and :data:`grows_mutating_late` — persistent while small, but once a complex
  holds 40 (or 2,000) triangles ``add`` writes the new complex into the one it was given (persistence);
* :data:`stale_data_cache` — ``data`` memoised by ``(id(c), s)`` and never invalidated: a new version
  that gets a freed version's id answers with the old one's data (determinism);
* :data:`shared_table` — versions are handles into a table that is a class attribute, each instance
  numbering its handles from 0: a second instance's versions overwrite the first's (isolation).
"""

from __future__ import annotations

import weakref
from collections.abc import Callable, Sequence
from typing import Any, ClassVar

from persistri.impl.complex import complex_structure
from persistri.impl.complex.simplex import Simplex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.maps.assoc_list import assoc_list
from persistri.spec.option import Option
from persistri.spec.order import NATURAL_ORDER, NaturalOrder

__all__ = [
    "OrientationBlindFind",
    "StaleRem",
    "MutatingDictMap",
    "mutating_add",
    "GrowsMutatingComplex",
    "GrowsMutatingLateComplex",
    "StaleDataCacheComplex",
    "SharedTableComplex",
    "grows_mutating",
    "grows_mutating_late",
    "stale_data_cache",
    "shared_table",
    "AT_SCALE",
]


class OrientationBlindFind(TwoComplex[Any]):
    """``find`` returns every triangle on the edge {u, w}, whichever way round."""

    def _find(self, rep: Any, f: Simplex) -> list[Simplex]:
        u, w = f
        found = self._m.find(rep, u)
        if found is None:
            return []
        out: list[Simplex] = []
        for v, t, _ in found[0]:
            if v == w:
                out.append((u, w, t))
            elif t == w:
                out.append((u, v, w))
        return out

    def find(self, c: Any, s: Simplex, /) -> list[Any]:
        rep, lin = self._open(c, "find")
        t, _ = self._arg(s, 1, lin, "find")
        return self._find(rep, t)


class StaleRem(TwoComplex[Any]):
    """``rem`` drops the triangle from the lists of its first two vertices only."""

    def _rem(self, rep: Any, s: Simplex) -> Any:
        a, b, c = s
        lst, i = self._locate(rep, s, "rem")
        m = self._m
        rest = lst[:i] + lst[i + 1 :]
        rep = m.insert(rep, a, rest) if rest else m.remove(rep, a)[0]
        return self._change(rep, b, c, a, None, True)


class MutatingDictMap:
    """An ``ORD_MAP`` lookalike over one mutable ``dict``: every update changes the map in place."""

    name = "mutating_dict"

    @property
    def Key(self) -> NaturalOrder[Any]:
        return NATURAL_ORDER

    def empty(self) -> dict[Any, Any]:
        return {}

    def isEmpty(self, m: dict[Any, Any]) -> bool:
        return not m

    def singleton(self, k: Any, v: Any) -> dict[Any, Any]:
        return {k: v}

    def insert(self, m: dict[Any, Any], k: Any, v: Any) -> dict[Any, Any]:
        m[k] = v
        return m

    def insertWith(self, f: Callable[[Any, Any], Any], m: dict[Any, Any], k: Any, v: Any) -> dict[Any, Any]:
        m[k] = f(m[k], v) if k in m else v
        return m

    def find(self, m: dict[Any, Any], k: Any) -> Option[Any]:
        return (m[k],) if k in m else None

    def lookup(self, m: dict[Any, Any], k: Any) -> Any:
        return m[k]

    def inDomain(self, m: dict[Any, Any], k: Any) -> bool:
        return k in m

    def remove(self, m: dict[Any, Any], k: Any) -> tuple[dict[Any, Any], Any]:
        return m, m.pop(k)

    def numItems(self, m: dict[Any, Any]) -> int:
        return len(m)

    def listItemsi(self, m: dict[Any, Any]) -> list[tuple[Any, Any]]:
        return sorted(m.items())

    def listKeys(self, m: dict[Any, Any]) -> list[Any]:
        return sorted(m)

    def foldli(self, f: Callable[[Any, Any, Any], Any], init: Any, m: dict[Any, Any]) -> Any:
        for k, v in sorted(m.items()):
            init = f(k, v, init)
        return init


def mutating_add() -> TwoComplex[Any]:
    """The 2-complex over :class:`MutatingDictMap`: ``add`` mutates the version it is given."""
    return TwoComplex(MutatingDictMap())


def correct() -> TwoComplex[Any]:
    """The correct 2-complex over the association list, for contrast."""
    return TwoComplex(assoc_list)


_RB2 = complex_structure(2, "red_black")


class _Wrapping:
    """Every ``SIMPCOMP`` operation by the red-black 2-complex on the complex ``_inner(c)`` holds; results go
    through ``_outer`` (subclasses choose what a version is)."""

    @property
    def Simplex(self) -> Any:
        return _RB2.Simplex

    def _inner(self, c: Any) -> Any:
        return c

    def _outer(self, inner: Any, made_from: Any, change: int) -> Any:
        """The version holding ``inner``, made from ``made_from`` by a change of ``change`` triangles."""
        return inner

    def dim(self, c: Any) -> int:
        return _RB2.dim(self._inner(c))

    def new(self, n: int) -> Any:
        return self._outer(_RB2.new(n), None, 0)

    def isEmpty(self, c: Any) -> bool:
        return _RB2.isEmpty(self._inner(c))

    def vertices(self, c: Any) -> Sequence[Any]:
        return _RB2.vertices(self._inner(c))

    def simplices(self, c: Any, d: int) -> Sequence[Any]:
        return _RB2.simplices(self._inner(c), d)

    def data(self, c: Any, s: Any) -> Option[Any]:
        return _RB2.data(self._inner(c), s)

    def grep(self, c: Any, d: int, s: Any) -> Sequence[Any]:
        return _RB2.grep(self._inner(c), d, s)

    def find(self, c: Any, s: Any) -> Sequence[Any]:
        return _RB2.find(self._inner(c), s)

    def add(self, c: Any, s: Any, x: Any) -> Any:
        return self._outer(_RB2.add(self._inner(c), s, x), c, 1)

    def rem(self, c: Any, s: Any) -> Any:
        return self._outer(_RB2.rem(self._inner(c), s), c, -1)

    def update(self, c: Any, s: Any, f: Callable[[Any], Any]) -> Any:
        return self._outer(_RB2.update(self._inner(c), s, f), c, 0)

    def check(self, c: Any) -> None:
        _RB2.check(self._inner(c))


class _Box:
    """A mutable cell: a red-black 2-complex and how many triangles it holds."""

    __slots__ = ("inner", "triangles")

    def __init__(self, inner: Any, triangles: int) -> None:
        self.inner = inner
        self.triangles = triangles


class GrowsMutatingComplex(_Wrapping):
    """The red-black 2-complex in a cell, persistent until a complex holds ``threshold`` triangles: from then
    on ``add`` puts the new complex into the cell it was given ("large complexes are expensive to copy")."""

    threshold: ClassVar[int] = 40

    def _inner(self, c: _Box) -> Any:
        return c.inner

    def _outer(self, inner: Any, made_from: _Box | None, change: int) -> _Box:
        if made_from is None:
            return _Box(inner, 0)
        if change == 1 and made_from.triangles >= self.threshold:
            made_from.inner = inner  # the broken promise: the caller's version has changed too
            made_from.triangles += 1
            return made_from
        return _Box(inner, made_from.triangles + change)


class GrowsMutatingLateComplex(GrowsMutatingComplex):
    """:class:`GrowsMutatingComplex` persistent up to 2,000 triangles: thousands, not dozens."""

    threshold = 2_000


_MISS = object()


class StaleDataCacheComplex(_Wrapping):
    """The red-black 2-complex with ``data`` memoised by ``(id(c), s)``: the memo keeps the last 4,096 answers
    and is never told that a version died, so a new version that gets a freed one's id answers with its data."""

    def __init__(self) -> None:
        self._memo: dict[tuple[int, Any], Any] = {}

    def data(self, c: Any, s: Any) -> Option[Any]:
        key = (id(c), tuple(s))
        hit = self._memo.get(key, _MISS)
        if hit is not _MISS:
            return hit  # type: ignore[no-any-return]  # what the memo holds is data's answer
        found = _RB2.data(c, s)
        if len(self._memo) >= 4_096:
            del self._memo[next(iter(self._memo))]
        self._memo[key] = found
        return found


class _Handle:
    """A version of :class:`SharedTableComplex`: the number of its complex in the table."""

    __slots__ = ("serial", "__weakref__")

    def __init__(self, serial: int) -> None:
        self.serial = serial

    def __repr__(self) -> str:
        return f"<version {self.serial}>"


class SharedTableComplex(_Wrapping):
    """Versions are handles into a table of red-black 2-complexes; each instance numbers its handles from 0.

    The table is a class attribute — meant to be one per instance — so the handles of two instances collide:
    a second instance's versions overwrite the first's.  (A handle's entry leaves the table when it dies.)
    """

    _table: ClassVar[dict[int, Any]] = {}

    def __init__(self) -> None:
        self._next = 0

    def _inner(self, c: _Handle) -> Any:
        return self._table[c.serial]

    def _outer(self, inner: Any, made_from: Any, change: int) -> _Handle:
        h = _Handle(self._next)
        self._next += 1
        self._table[h.serial] = inner
        weakref.finalize(h, self._table.pop, h.serial, None)
        return h


grows_mutating = GrowsMutatingComplex()
grows_mutating_late = GrowsMutatingLateComplex()
stale_data_cache = StaleDataCacheComplex()
shared_table = SharedTableComplex()

AT_SCALE: dict[str, tuple[Any, str, str]] = {
    "grows_mutating": (grows_mutating, "persistence", "growth"),
    "grows_mutating_late": (grows_mutating_late, "persistence", "growth"),
    "stale_data_cache": (stale_data_cache, "determinism", "determinism"),
    "shared_table": (shared_table, "isolation", "isolation"),
}
"""Name → (broken 2-complex structure, the law the suite must name, the test that finds it)."""
