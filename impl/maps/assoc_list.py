"""The association-list map: the teaching baseline of ``ORD_MAP`` (SML/NJ's ``ListMapFn``).

A map is a sorted, immutable singly linked list of ``(key, value)`` cells,
together with its length.  A cell is the tuple ``(key, value, rest)``; the empty
list is ``None``.  Every operation is *persistent by path copying*: to change the
cell of a key, the cells before it are copied and the cells after it are shared
with the old version, so the old version is never touched.

=====================  ==========  =====================================
operation              time        notes
=====================  ==========  =====================================
find, lookup, inDomain O(i)        i = position of the key (early exit: sorted)
insert, insertWith     O(i)        copies the i cells before the key
remove                 O(i)        copies the i cells before the key
numItems, isEmpty      O(1)        the length is stored
listItemsi, foldli     O(n)
=====================  ==========  =====================================

Every loop is iterative, so maps of any length work (no recursion limit).
This is the baseline the red-black tree and the HAMT are measured against; it
also documents the contract each backend meets, including ``_check`` and
``search_cost`` (the key comparisons a search makes, for :mod:`~persistri.impl.stats`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Generic, Optional, TypeAlias, TypeVar

from persistri.impl.maps.keys import check_orderable, check_same_key, not_ordered_with
from persistri.spec.option import Option
from persistri.spec.ord_map import NotFound
from persistri.spec.order import NATURAL_ORDER, Comparable, NaturalOrder

__all__ = ["AssocListMap", "ALMap", "assoc_list"]

K = TypeVar("K", bound=Comparable)
V = TypeVar("V")
B = TypeVar("B")

Cells: TypeAlias = Optional[tuple[K, V, "Cells[K, V]"]]
"""A sorted cons list: ``(key, value, rest)`` or ``None``."""

ALMap: TypeAlias = tuple[int, "Cells[K, V]"]
"""An association-list map: ``(number of items, cells)``."""


def _key_error(k: object, exc: TypeError) -> TypeError:
    return not_ordered_with("assoc_list", k, exc)


class AssocListMap(Generic[K, V]):
    """``structure AssocListMap : ORD_MAP``: sorted association lists (see the module docstring)."""

    __slots__ = ()

    def __reduce__(self) -> str | tuple[type[AssocListMap[K, V]], tuple[()]]:
        """Pickle the module's ``assoc_list`` by name, so that an unpickled complex (or map) is a value of
        *that* structure (complexes compare their backends by identity); another instance by its class."""
        return "assoc_list" if self is assoc_list else (type(self), ())

    name = "assoc_list"

    @property
    def Key(self) -> NaturalOrder[Any]:
        """Keys are ordered by Python's natural order (``<``, ``==``)."""
        return NATURAL_ORDER

    def empty(self) -> ALMap[K, V]:
        """The empty map. O(1)."""
        return (0, None)

    def isEmpty(self, m: ALMap[K, V], /) -> bool:
        """Whether ``m`` is empty. O(1)."""
        return m[0] == 0

    def singleton(self, k: K, v: V, /) -> ALMap[K, V]:
        """The map ``{k ↦ v}``. O(1)."""
        _check_orderable(k)
        return (1, (k, v, None))

    def insert(self, m: ALMap[K, V], k: K, v: V, /) -> ALMap[K, V]:
        """``m`` with ``k ↦ v``. O(i), copying the cells before ``k``."""
        return self._insert(m, k, v, None)

    def insertWith(self, f: Callable[[V, V], V], m: ALMap[K, V], k: K, v: V, /) -> ALMap[K, V]:
        """``m`` with ``k ↦ f(old, v)`` if ``k ↦ old`` is in ``m``, else ``k ↦ v``. O(i)."""
        return self._insert(m, k, v, f)

    def _insert(self, m: ALMap[K, V], k: K, v: V, f: Callable[[V, V], V] | None) -> ALMap[K, V]:
        n, cells = m
        if cells is None:
            _check_orderable(k)
        prefix: list[tuple[K, V]] = []
        try:
            while cells is not None and cells[0] < k:
                prefix.append((cells[0], cells[1]))
                cells = cells[2]
            if cells is not None and not (k < cells[0]):
                # k is present: replace its cell, share the rest.
                check_same_key("assoc_list", k, cells[0])
                new_v = v if f is None else f(cells[1], v)
                rest: Cells[K, V] = (k, new_v, cells[2])
            else:
                rest = (k, v, cells)
                n += 1
        except TypeError as exc:
            raise _key_error(k, exc) from None
        for pk, pv in reversed(prefix):
            rest = (pk, pv, rest)
        return (n, rest)

    def _cell(self, m: ALMap[K, V], k: K) -> Cells[K, V]:
        """The cell holding ``k``, or None."""
        cells = m[1]
        try:
            while cells is not None and cells[0] < k:
                cells = cells[2]
            if cells is not None and not (k < cells[0]):
                check_same_key("assoc_list", k, cells[0])
                return cells
        except TypeError as exc:
            raise _key_error(k, exc) from None
        return None

    def find(self, m: ALMap[K, V], k: K, /) -> Option[V]:
        """``(v,)`` if ``k ↦ v`` is in ``m``, else ``None``. O(i)."""
        cell = self._cell(m, k)
        return None if cell is None else (cell[1],)

    def lookup(self, m: ALMap[K, V], k: K, /) -> V:
        """The value of ``k``; raises :class:`NotFound` if absent. O(i)."""
        cell = self._cell(m, k)
        if cell is None:
            raise NotFound(k)
        return cell[1]

    def inDomain(self, m: ALMap[K, V], k: K, /) -> bool:
        """Whether ``k`` is in ``m``. O(i)."""
        return self._cell(m, k) is not None

    def remove(self, m: ALMap[K, V], k: K, /) -> tuple[ALMap[K, V], V]:
        """``(m without k, value of k)``; raises :class:`NotFound` if absent. O(i)."""
        n, cells = m
        prefix: list[tuple[K, V]] = []
        try:
            while cells is not None and cells[0] < k:
                prefix.append((cells[0], cells[1]))
                cells = cells[2]
            if cells is None or k < cells[0]:
                raise NotFound(k)
        except TypeError as exc:
            raise _key_error(k, exc) from None
        check_same_key("assoc_list", k, cells[0])
        value = cells[1]
        rest = cells[2]
        for pk, pv in reversed(prefix):
            rest = (pk, pv, rest)
        return (n - 1, rest), value

    def numItems(self, m: ALMap[K, V], /) -> int:
        """The number of items. O(1)."""
        return m[0]

    def listItemsi(self, m: ALMap[K, V], /) -> list[tuple[K, V]]:
        """The items in increasing key order. O(n)."""
        out: list[tuple[K, V]] = []
        cells = m[1]
        while cells is not None:
            out.append((cells[0], cells[1]))
            cells = cells[2]
        return out

    def listKeys(self, m: ALMap[K, V], /) -> list[K]:
        """The keys in increasing order. O(n)."""
        return [k for k, _ in self.listItemsi(m)]

    def foldli(self, f: Callable[[K, V, B], B], init: B, m: ALMap[K, V], /) -> B:
        """``f`` folded over the items in increasing key order. O(n) calls of ``f``."""
        acc = init
        cells = m[1]
        while cells is not None:
            acc = f(cells[0], cells[1], acc)
            cells = cells[2]
        return acc

    # -- instrumentation and invariants ---------------------------------------

    def search_cost(self, m: ALMap[K, V], k: K, /) -> int:
        """The key comparisons a search for ``k`` makes: list elements visited (paper §4)."""
        cost = 0
        cells = m[1]
        while cells is not None:
            cost += 1
            if not (cells[0] < k):
                break
            cells = cells[2]
        return cost

    def _check(self, m: ALMap[K, V], /) -> None:
        """Assert the representation invariants: keys strictly increasing, stored length exact."""
        n, cells = m
        count = 0
        prev: Any = None
        while cells is not None:
            if count > 0:
                assert prev < cells[0], f"assoc_list: keys out of order: {prev!r} before {cells[0]!r}"
            prev = cells[0]
            count += 1
            cells = cells[2]
        assert count == n, f"assoc_list: stored length {n} but {count} cells"

    def __repr__(self) -> str:
        return "assoc_list"


def _check_orderable(k: Any) -> None:
    """Reject a key that Python cannot order even against itself (e.g. ``object()``)."""
    check_orderable("assoc_list", k)


assoc_list: AssocListMap[Any, Any] = AssocListMap()
"""The association-list structure, polymorphic in keys and values."""
