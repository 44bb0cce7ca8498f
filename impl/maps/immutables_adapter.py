"""``ORD_MAP`` over ``immutables.Map``: a real third-party persistent map, plugged in.

``immutables.Map`` (MagicStack; the hash array mapped trie behind CPython's
``contextvars``, written in C) is a persistent map: ``set`` and ``delete``
return a new map by path copying and never change the one they are given.
:class:`ImmutablesMap` is the ``ORD_MAP`` structure whose map values *are*
``immutables.Map`` objects, so persistence is the library's, not ours; the
adapter only translates the signature:

==========================  ======================================  =============
ORD_MAP                     immutables.Map                          time
==========================  ======================================  =============
``find``/``lookup``         ``m.get(k, absent)``                    O(log₃₂ n)
``insert``                  ``m.set(k, v)``                         O(log₃₂ n)
``insertWith f``            ``get`` then ``set(k, f(old, v))``      O(log₃₂ n)
``remove``                  ``m[k]`` then ``m.delete(k)``           O(log₃₂ n)
``numItems``                ``len(m)``                              O(1)
``listItemsi``/``foldli``   sort ``m.items()`` by key               O(n log n)
==========================  ======================================  =============

The listing is sorted on every call because a HAMT iterates in hash order
(:mod:`persistri.impl.maps.unordered`).  Keys must be hashable and ordered by
``<``; any other key is rejected with a :class:`TypeError` at the operation.

There is no ``search_cost``: the C code does not say how many key comparisons
it makes, so :func:`persistri.impl.maps.counted.counted` counts dictionary
operations only for this backend.  There is no ``_check`` either: the
representation is the library's, with nothing of ours to check.
"""

from __future__ import annotations

from collections.abc import Callable
import enum
from typing import Any, Final, Generic, TypeVar

import immutables

from persistri.impl.maps.unordered import HashKey, check_key, sorted_items, sorted_keys
from persistri.spec.option import Option
from persistri.spec.ord_map import NotFound
from persistri.spec.order import NATURAL_ORDER, NaturalOrder

__all__ = ["ImmutablesMap", "immutables_map"]

K = TypeVar("K", bound=HashKey)
V = TypeVar("V")
B = TypeVar("B")

_NAME: Final = "immutables"


class _Absent(enum.Enum):
    """A private sentinel: ``get`` returns it only for an absent key (``None`` is a legal value)."""

    ABSENT = enum.auto()


_ABSENT: Final = _Absent.ABSENT


class ImmutablesMap(Generic[K, V]):
    """``structure ImmutablesMap : ORD_MAP`` over ``immutables.Map`` (see the module docstring)."""

    __slots__ = ()

    def __reduce__(self) -> str | tuple[type[ImmutablesMap[K, V]], tuple[()]]:
        """Pickle the module's ``immutables_map`` by name, so that an unpickled complex (or map) is a value of
        *that* structure (complexes compare their backends by identity); another instance by its class."""
        return "immutables_map" if self is immutables_map else (type(self), ())

    name = _NAME

    @property
    def Key(self) -> NaturalOrder[Any]:
        """Keys are ordered by Python's natural order (``<``, ``==``)."""
        return NATURAL_ORDER

    def empty(self) -> immutables.Map[K, V]:
        """The empty map. O(1)."""
        return immutables.Map()

    def isEmpty(self, m: immutables.Map[K, V], /) -> bool:
        """Whether ``m`` is empty. O(1)."""
        return len(m) == 0

    def singleton(self, k: K, v: V, /) -> immutables.Map[K, V]:
        """The map ``{k ↦ v}``. O(1)."""
        check_key(_NAME, k)
        return immutables.Map(((k, v),))

    def insert(self, m: immutables.Map[K, V], k: K, v: V, /) -> immutables.Map[K, V]:
        """``m`` with ``k ↦ v``. O(log₃₂ n), path copying (``Map.set``)."""
        check_key(_NAME, k)
        return m.set(k, v)

    def insertWith(self, f: Callable[[V, V], V], m: immutables.Map[K, V], k: K, v: V, /) -> immutables.Map[K, V]:
        """``m`` with ``k ↦ f(old, v)`` if ``k ↦ old`` is in ``m``, else ``k ↦ v``. O(log₃₂ n) plus ``f``."""
        check_key(_NAME, k)
        old = m.get(k, _ABSENT)
        return m.set(k, v if old is _ABSENT else f(old, v))

    def find(self, m: immutables.Map[K, V], k: K, /) -> Option[V]:
        """``(v,)`` if ``k ↦ v`` is in ``m``, else ``None``. O(log₃₂ n)."""
        check_key(_NAME, k)
        v = m.get(k, _ABSENT)
        return None if v is _ABSENT else (v,)

    def lookup(self, m: immutables.Map[K, V], k: K, /) -> V:
        """The value of ``k``; raises :class:`NotFound` if absent. O(log₃₂ n)."""
        check_key(_NAME, k)
        v = m.get(k, _ABSENT)
        if v is _ABSENT:
            raise NotFound(k)
        return v

    def inDomain(self, m: immutables.Map[K, V], k: K, /) -> bool:
        """Whether ``k`` is in ``m``. O(log₃₂ n)."""
        check_key(_NAME, k)
        return k in m

    def remove(self, m: immutables.Map[K, V], k: K, /) -> tuple[immutables.Map[K, V], V]:
        """``(m without k, value of k)``; raises :class:`NotFound` if absent. O(log₃₂ n)."""
        check_key(_NAME, k)
        v = m.get(k, _ABSENT)
        if v is _ABSENT:
            raise NotFound(k)
        return m.delete(k), v

    def numItems(self, m: immutables.Map[K, V], /) -> int:
        """The number of items (``len``). O(1)."""
        return len(m)

    def listItemsi(self, m: immutables.Map[K, V], /) -> list[tuple[K, V]]:
        """The items in increasing key order. O(n log n): the HAMT is unordered, so this sorts."""
        return sorted_items(_NAME, m.items())

    def listKeys(self, m: immutables.Map[K, V], /) -> list[K]:
        """The keys in increasing order. O(n log n) (sorted)."""
        return sorted_keys(_NAME, m.keys())

    def foldli(self, f: Callable[[K, V, B], B], init: B, m: immutables.Map[K, V], /) -> B:
        """``f`` folded over the items in increasing key order. O(n log n) to sort, then n calls of ``f``."""
        acc = init
        for k, v in self.listItemsi(m):
            acc = f(k, v, acc)
        return acc

    def __repr__(self) -> str:
        return _NAME


immutables_map: ImmutablesMap[Any, Any] = ImmutablesMap()
"""The ``immutables.Map`` structure, polymorphic in keys and values."""
