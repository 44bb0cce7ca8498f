"""Counting: an ``ORD_MAP`` structure that reports its work to a :class:`~persistri.impl.stats.Stats`.

``counted(structure, stats)`` returns a structure with the same operations and
the same results that also counts, the way the paper's §4 does:

* every operation is one **dictionary operation**;
* ``find``, ``lookup``, ``inDomain``, ``insert``, ``insertWith`` and ``remove`` of
  key ``k`` make as many **key comparisons** as a search for ``k`` visits nodes:
  the backend's ``search_cost(m, k)`` (red-black tree: nodes on the search path;
  association list: cells visited; HAMT: key equality tests).  A backend that
  cannot say (a third-party adapter) counts dictionary operations only.

Counting lives in this wrapper, not in the backends, so that an uncounted
structure runs its fast path and pays nothing for instrumentation.  The cost of
a counted operation is about twice the uncounted one (the search is walked a
second time); counts are for measurement, never for timing.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Generic, Protocol, TypeVar

from persistri.impl.stats import Stats
from persistri.spec.option import Option
from persistri.spec.ord_map import OrdMap
from persistri.spec.order import OrdKey

__all__ = ["counted", "CountedOrdMap", "SearchCost"]

K = TypeVar("K")
V = TypeVar("V")
M = TypeVar("M")
B = TypeVar("B")
K_contra = TypeVar("K_contra", contravariant=True)
M_contra = TypeVar("M_contra", contravariant=True)


class SearchCost(Protocol[K_contra, M_contra]):
    """A backend that can tell how many key comparisons a search makes."""

    def search_cost(self, m: M_contra, k: K_contra, /) -> int:
        """The key comparisons (nodes or cells visited) of a search for ``k`` in ``m``."""
        ...


class CountedOrdMap(Generic[K, V, M]):
    """``structure`` with every operation reported to ``stats`` (see the module docstring)."""

    __slots__ = ("_s", "_stats", "_cost", "name")

    def __init__(self, structure: OrdMap[K, V, M], stats: Stats) -> None:
        self._s = structure
        self._stats = stats
        cost = getattr(structure, "search_cost", None)
        self._cost: Callable[[M, K], int] | None = cost
        self.name: str = f"counted({getattr(structure, 'name', structure)!r})"

    def _count(self, m: M, k: K) -> None:
        st = self._stats
        st.dict_ops += 1
        if self._cost is not None:
            st.key_comparisons += self._cost(m, k)

    @property
    def Key(self) -> OrdKey[K]:
        return self._s.Key

    def empty(self) -> M:
        return self._s.empty()

    def isEmpty(self, m: M, /) -> bool:
        return self._s.isEmpty(m)

    def singleton(self, k: K, v: V, /) -> M:
        self._stats.dict_ops += 1
        return self._s.singleton(k, v)

    def insert(self, m: M, k: K, v: V, /) -> M:
        self._count(m, k)
        return self._s.insert(m, k, v)

    def insertWith(self, f: Callable[[V, V], V], m: M, k: K, v: V, /) -> M:
        self._count(m, k)
        return self._s.insertWith(f, m, k, v)

    def find(self, m: M, k: K, /) -> Option[V]:
        self._count(m, k)
        return self._s.find(m, k)

    def lookup(self, m: M, k: K, /) -> V:
        self._count(m, k)
        return self._s.lookup(m, k)

    def inDomain(self, m: M, k: K, /) -> bool:
        self._count(m, k)
        return self._s.inDomain(m, k)

    def remove(self, m: M, k: K, /) -> tuple[M, V]:
        self._count(m, k)
        return self._s.remove(m, k)

    def numItems(self, m: M, /) -> int:
        return self._s.numItems(m)

    def listItemsi(self, m: M, /) -> list[tuple[K, V]]:
        self._stats.dict_ops += 1
        return self._s.listItemsi(m)

    def listKeys(self, m: M, /) -> list[K]:
        self._stats.dict_ops += 1
        return self._s.listKeys(m)

    def foldli(self, f: Callable[[K, V, B], B], init: B, m: M, /) -> B:
        self._stats.dict_ops += 1
        return self._s.foldli(f, init, m)

    def _check(self, m: M, /) -> None:
        check = getattr(self._s, "_check", None)
        if check is not None:
            check(m)

    def __repr__(self) -> str:
        return self.name


def counted(structure: OrdMap[K, V, M], stats: Stats | None) -> OrdMap[K, V, M]:
    """``structure`` itself when ``stats`` is None (free), else a :class:`CountedOrdMap` reporting to it."""
    if stats is None:
        return structure
    return CountedOrdMap(structure, stats)


