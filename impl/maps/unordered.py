"""What an *unordered* (hash-based) persistent map needs to match ``ORD_MAP``.

``ORD_MAP`` promises two things a hash map does not give by itself:

* **ordered listing** — ``listItemsi``, ``listKeys`` and ``foldli`` run in
  increasing key order.  A hash map iterates in hash order, so the adapters sort
  on every listing: O(n log n) key comparisons instead of a tree's O(n).
* **ordered keys** — ``Key.compare`` must order every key.  A hash map accepts
  any hashable key, so the adapters check each key at the public operation
  (:func:`check_key`): hashable (the library needs it) and orderable against
  itself (``k < k`` must not raise), with a clear :class:`TypeError` naming the
  backend.  Keys of *different* types that each order among themselves but not
  with each other (``1`` and ``"a"``) cannot be caught at ``insert`` without an
  extra probe of an existing key; the listing reports them
  (:func:`sorted_items` raises a :class:`TypeError` naming the backend).

A hash map finds keys by ``hash`` and ``==``, where ``ORD_MAP`` identifies keys
that ``Key.compare`` calls ``EQUAL``.  The two agree only for keys whose ``==``
matches their order (``a == b`` exactly when neither ``a < b`` nor ``b < a``)
and whose hash matches ``==`` — true of numbers, strings, tuples of them and
well-behaved dataclasses, but not of a class that defines ``<`` and leaves
``==`` as identity: two separately built, order-equal keys would be two
different keys to an adapter and one key to a tree.  That is a precondition of
the adapters, documented rather than checked (checking it would cost a
comparison with a neighbour the hash map does not have).

Python's ``sorted`` uses only ``<``, the same order as
:data:`persistri.spec.order.NATURAL_ORDER`, and compares keys only (never values,
which need not be orderable).
"""

from __future__ import annotations

from collections.abc import Hashable, Iterable
from operator import itemgetter
from typing import Any, Protocol, TypeVar

from persistri.impl.maps.keys import check_orderable, check_sorted_strictly

__all__ = ["HashKey", "check_key", "sorted_items", "sorted_keys"]


class HashKey(Hashable, Protocol):
    """A key a hash-based ``ORD_MAP`` adapter accepts: hashable and ordered by ``<``."""

    def __lt__(self, other: Any, /) -> bool: ...


K = TypeVar("K", bound=HashKey)
V = TypeVar("V")

_first = itemgetter(0)


def check_key(owner: str, k: Any) -> None:
    """Raise a :class:`TypeError` naming ``owner`` unless ``k`` is hashable and ``k < k`` is defined. O(1)."""
    try:
        hash(k)
    except TypeError:
        raise TypeError(f"{owner}: key {k!r} of type {type(k).__name__} is not hashable") from None
    check_orderable(owner, k)


def _unordered_keys(owner: str, exc: TypeError) -> TypeError:
    return TypeError(f"{owner}: the keys of this map are not mutually ordered by '<' ({exc})")


def sorted_items(owner: str, items: Iterable[tuple[K, V]]) -> list[tuple[K, V]]:
    """``items`` in increasing key order. O(n log n); a :class:`TypeError` naming ``owner`` if keys do not order."""
    try:
        out = sorted(items, key=_first)
    except TypeError as exc:
        raise _unordered_keys(owner, exc) from None
    check_sorted_strictly(owner, [k for k, _ in out])
    return out


def sorted_keys(owner: str, keys: Iterable[K]) -> list[K]:
    """``keys`` in increasing order. O(n log n); a :class:`TypeError` naming ``owner`` if they do not order."""
    try:
        out = sorted(keys)
    except TypeError as exc:
        raise _unordered_keys(owner, exc) from None
    check_sorted_strictly(owner, out)
    return out
