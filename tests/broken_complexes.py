"""Deliberately broken 2-complexes: the laws and the checks must reject each, naming what broke.

Each breaks one promise of the specialised 2-complex and keeps the others:

* :class:`OrientationBlindFind` — ``find(c, (u, w))`` also returns the triangles
  holding the reverse edge (w, u): orientation ignored (law ``find``);
* :class:`StaleRem` — ``rem`` forgets to drop the triangle from its third
  vertex's list (law ``rem``; :func:`check_complex` reports the representation);
* :func:`mutating_add` — a 2-complex over a map backend whose ``insertWith``
  updates the map it was given in place, so ``add`` changes the previous
  version (law ``persistence``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from persistri.impl.complex.simplex import Simplex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.maps.assoc_list import assoc_list
from persistri.spec.option import Option
from persistri.spec.order import NATURAL_ORDER, NaturalOrder

__all__ = ["OrientationBlindFind", "StaleRem", "MutatingDictMap", "mutating_add"]


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
