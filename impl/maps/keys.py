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

from typing import Any

__all__ = ["check_orderable", "not_ordered_with", "unorderable"]


def unorderable(owner: str, k: object) -> TypeError:
    """The error for a key ``k`` that Python cannot order (no ``<`` with itself), naming ``owner``."""
    return TypeError(f"{owner}: key {k!r} of type {type(k).__name__} is not orderable (no '<')")


def check_orderable(owner: str, k: Any) -> None:
    """Raise :func:`unorderable`'s error unless ``k < k`` is defined (e.g. not for ``object()``)."""
    try:
        k < k  # noqa: B015 - evaluated for its TypeError only
    except TypeError:
        raise unorderable(owner, k) from None


def not_ordered_with(owner: str, k: object, exc: TypeError) -> TypeError:
    """The error for a key ``k`` that does not order with the map's keys (``exc``: the comparison's own)."""
    return TypeError(f"{owner}: key {k!r} is not ordered with the keys of this map ({exc})")
