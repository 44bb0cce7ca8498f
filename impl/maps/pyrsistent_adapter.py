"""``ORD_MAP`` over ``pyrsistent.pmap``: a second real third-party persistent map, plugged in.

pyrsistent's ``PMap`` is a persistent hash table: a persistent vector (a 32-way
trie, ``PVector``) of buckets, indexed by ``hash(k) % number of buckets``.  An
update copies the trie path to one bucket and shares the rest, so the map it
was given is never changed; when the table is two-thirds full the next new key
rehashes everything into a vector twice as long (a new vector: still
persistent).  :class:`PyrsistentMap` is the ``ORD_MAP`` structure whose map
values *are* ``PMap`` objects, so persistence is the library's; the adapter
only translates the signature:

==========================  ======================================  ======================
ORD_MAP                     pyrsistent.PMap                         time
==========================  ======================================  ======================
``find``/``lookup``         ``m.get(k, absent)``                    O(log₃₂ n) expected
``insert``                  ``m.set(k, v)``                         O(log₃₂ n) amortised
``insertWith f``            ``get`` then ``set(k, f(old, v))``      O(log₃₂ n) amortised
``remove``                  ``get`` then ``m.remove(k)``            O(log₃₂ n) expected
``numItems``                ``len(m)``                              O(1)
``listItemsi``/``foldli``   sort ``m.items()`` by key               O(n log n)
==========================  ======================================  ======================

(A single ``insert`` that triggers the rehash costs O(n); the doubling makes
that O(1) amortised per insert.)  The listing is sorted on every call because a
hash table is unordered (:mod:`persistri.impl.maps.unordered`).  Keys must be
hashable and ordered by ``<``; any other key is rejected with a
:class:`TypeError` at the operation.

There is no ``search_cost``: pyrsistent does not report the key comparisons it
makes, so :func:`persistri.impl.maps.counted.counted` counts dictionary
operations only for this backend.  There is no ``_check`` either: the
representation is the library's, with nothing of ours to check.
"""

from __future__ import annotations

from collections.abc import Callable
import enum
from typing import Any, Final, Generic, TypeVar

from pyrsistent import PMap, pmap

from persistri.impl.maps.unordered import HashKey, check_key, sorted_items, sorted_keys
from persistri.spec.option import Option
from persistri.spec.ord_map import NotFound
from persistri.spec.order import NATURAL_ORDER, NaturalOrder

__all__ = ["PyrsistentMap", "pyrsistent_map"]

K = TypeVar("K", bound=HashKey)
V = TypeVar("V")
B = TypeVar("B")

_NAME: Final = "pyrsistent"


class _Absent(enum.Enum):
    """A private sentinel: ``get`` returns it only for an absent key (``None`` is a legal value)."""

    ABSENT = enum.auto()


_ABSENT: Final = _Absent.ABSENT


class PyrsistentMap(Generic[K, V]):
    """``structure PyrsistentMap : ORD_MAP`` over ``pyrsistent.pmap`` (see the module docstring)."""

    __slots__ = ()

    def __reduce__(self) -> str | tuple[type[PyrsistentMap[K, V]], tuple[()]]:
        """Pickle the module's ``pyrsistent_map`` by name, so that an unpickled complex (or map) is a value of
        *that* structure (complexes compare their backends by identity); another instance by its class."""
        return "pyrsistent_map" if self is pyrsistent_map else (type(self), ())

    name = _NAME

    @property
    def Key(self) -> NaturalOrder[Any]:
        """Keys are ordered by Python's natural order (``<``, ``==``)."""
        return NATURAL_ORDER

    def empty(self) -> PMap[K, V]:
        """The empty map. O(1)."""
        return pmap()

    def isEmpty(self, m: PMap[K, V], /) -> bool:
        """Whether ``m`` is empty. O(1)."""
        return len(m) == 0

    def singleton(self, k: K, v: V, /) -> PMap[K, V]:
        """The map ``{k ↦ v}``. O(1)."""
        check_key(_NAME, k)
        return pmap({k: v})

    def insert(self, m: PMap[K, V], k: K, v: V, /) -> PMap[K, V]:
        """``m`` with ``k ↦ v``. O(log₃₂ n) amortised, path copying (``PMap.set``)."""
        check_key(_NAME, k)
        return m.set(k, v)

    def insertWith(self, f: Callable[[V, V], V], m: PMap[K, V], k: K, v: V, /) -> PMap[K, V]:
        """``m`` with ``k ↦ f(old, v)`` if ``k ↦ old`` is in ``m``, else ``k ↦ v``. O(log₃₂ n) amortised plus ``f``."""
        check_key(_NAME, k)
        old = m.get(k, _ABSENT)
        return m.set(k, v if old is _ABSENT else f(old, v))

    def find(self, m: PMap[K, V], k: K, /) -> Option[V]:
        """``(v,)`` if ``k ↦ v`` is in ``m``, else ``None``. O(log₃₂ n) expected."""
        check_key(_NAME, k)
        v = m.get(k, _ABSENT)
        return None if v is _ABSENT else (v,)

    def lookup(self, m: PMap[K, V], k: K, /) -> V:
        """The value of ``k``; raises :class:`NotFound` if absent. O(log₃₂ n) expected."""
        check_key(_NAME, k)
        v = m.get(k, _ABSENT)
        if v is _ABSENT:
            raise NotFound(k)
        return v

    def inDomain(self, m: PMap[K, V], k: K, /) -> bool:
        """Whether ``k`` is in ``m``. O(log₃₂ n) expected."""
        check_key(_NAME, k)
        return k in m

    def remove(self, m: PMap[K, V], k: K, /) -> tuple[PMap[K, V], V]:
        """``(m without k, value of k)``; raises :class:`NotFound` if absent. O(log₃₂ n) expected."""
        check_key(_NAME, k)
        v = m.get(k, _ABSENT)
        if v is _ABSENT:
            raise NotFound(k)
        return m.remove(k), v

    def numItems(self, m: PMap[K, V], /) -> int:
        """The number of items (``len``). O(1)."""
        return len(m)

    def listItemsi(self, m: PMap[K, V], /) -> list[tuple[K, V]]:
        """The items in increasing key order. O(n log n): the hash table is unordered, so this sorts."""
        return sorted_items(_NAME, m.items())

    def listKeys(self, m: PMap[K, V], /) -> list[K]:
        """The keys in increasing order. O(n log n) (sorted)."""
        return sorted_keys(_NAME, m.keys())

    def foldli(self, f: Callable[[K, V, B], B], init: B, m: PMap[K, V], /) -> B:
        """``f`` folded over the items in increasing key order. O(n log n) to sort, then n calls of ``f``."""
        acc = init
        for k, v in self.listItemsi(m):
            acc = f(k, v, acc)
        return acc

    def __repr__(self) -> str:
        return _NAME


pyrsistent_map: PyrsistentMap[Any, Any] = PyrsistentMap()
"""The ``pyrsistent.pmap`` structure, polymorphic in keys and values."""
