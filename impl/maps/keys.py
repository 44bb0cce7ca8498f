"""The key checks every backend makes, with errors that name the backend (``ORD_MAP``'s ``Key``, paper §2).

``ORD_MAP`` orders its keys by ``Key.compare``; persistri's backends use
Python's ``<`` (:data:`persistri.spec.order.NATURAL_ORDER`).  A key that
cannot be ordered even against itself (``object()``) is refused where it
enters a map, and a key that cannot be ordered against the keys already there
(``1`` among strings) is reported where the comparison fails — each as a
:class:`TypeError` whose message starts with the backend's name, so that the
error says which structure refused what.  All O(1).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

__all__ = ["check_increasing", "check_orderable", "check_same_key", "not_ordered_with", "not_totally_ordered", "unorderable"]


def unorderable(owner: str, k: object) -> TypeError:
    """The error for a key ``k`` that Python cannot order (no ``<`` with itself), naming ``owner``."""
    return TypeError(f"{owner}: key {k!r} of type {type(k).__name__} is not orderable (no '<')")


def check_orderable(owner: str, k: Any) -> None:
    """Raise :func:`unorderable`'s error unless ``k < k`` is defined (e.g. not for ``object()``), and
    :func:`not_totally_ordered`'s unless ``k == k`` (not for a NaN, which no total order can place)."""
    try:
        k < k  # noqa: B015 - evaluated for its TypeError only
        unequal = bool(k != k)
    except (TypeError, ValueError):  # ValueError: an array's truth value
        raise unorderable(owner, k) from None
    if unequal:
        raise not_totally_ordered(owner, k, k)


def not_totally_ordered(owner: str, k: object, y: object) -> ValueError:
    """The error for keys ``k`` and ``y`` of which neither is ``<`` the other, yet ``k != y`` (a NaN, or sets
    under inclusion): ``ORD_MAP`` needs a total order, and these would be taken for one key."""
    which = f"key {k!r} is not equal to itself" if k is y else f"keys {k!r} and {y!r} are neither '<' nor '=='"
    return ValueError(f"{owner}: {which}: a map's keys must be totally ordered (a NaN never is)")


def check_same_key(owner: str, k: Any, y: Any) -> None:
    """Raise :func:`not_totally_ordered`'s error unless ``k`` is ``y`` or ``k == y``: for a search that found ``y``
    because neither is ``<`` the other.  O(1)."""
    if y is not k and not y == k:
        raise not_totally_ordered(owner, k, y)


def check_sorted_strictly(owner: str, keys: Sequence[Any]) -> None:
    """Raise :func:`not_totally_ordered`'s error unless each of ``keys`` (just sorted) is ``<`` the next: for
    the hash-based maps, which never compare keys on insert, the listing is where two keys that ``<`` cannot
    tell apart (sets under inclusion, tuples holding a NaN) show up.  O(len(keys))."""
    for j in range(1, len(keys)):
        a, b = keys[j - 1], keys[j]
        if not a < b:
            raise not_totally_ordered(owner, a, b)


def not_ordered_with(owner: str, k: object, exc: TypeError) -> TypeError:
    """The error for a key ``k`` that does not order with the map's keys (``exc``: the comparison's own)."""
    return TypeError(f"{owner}: key {k!r} is not ordered with the keys of this map ({exc})")


def check_increasing(owner: str, operation: str, items: Sequence[tuple[Any, Any]]) -> None:
    """Raise :class:`ValueError` unless the keys of ``items`` strictly increase (a batched operation's
    precondition), or :func:`not_ordered_with`'s error where two of them do not compare.  O(len(items))."""
    for j in range(1, len(items)):
        try:
            ordered = items[j - 1][0] < items[j][0]
        except TypeError as exc:
            raise not_ordered_with(owner, items[j][0], exc) from None
        if not ordered:
            raise ValueError(
                f"{owner}: {operation} needs strictly increasing keys, got {items[j - 1][0]!r} before {items[j][0]!r}"
            )
