"""SML's ``'a option`` in Python.

``find : 'a map * ord_key -> 'a option`` must tell "absent" from "present with a
value that happens to be ``None``".  A bare ``V | None`` cannot, so persistri
transcribes ``'a option`` as a *1-tuple or None*:

=============  ===============
SML            Python
=============  ===============
``SOME v``     ``(v,)``
``NONE``       ``None``
=============  ===============

A 1-tuple costs one small allocation, is immutable, compares by value, and reads
naturally with ``match``::

    match structure.find(m, k):
        case (v,):
            ...          # present, with value v (which may itself be None)
        case None:
            ...          # absent

>>> SOME(None) is not NONE
True
>>> valOf(SOME(3))
3
"""

from __future__ import annotations

from typing import TypeAlias, TypeVar

__all__ = ["Option", "SOME", "NONE", "isSome", "valOf"]

T = TypeVar("T")

Option: TypeAlias = "tuple[T] | None"
"""``'a option``: ``(v,)`` for ``SOME v``, ``None`` for ``NONE``."""

NONE = None
"""``NONE``: the absent option."""


def SOME(v: T) -> tuple[T]:
    """``SOME v``: the present option holding ``v`` (a 1-tuple)."""
    return (v,)


def isSome(o: Option[T]) -> bool:
    """``Option.isSome``: whether ``o`` holds a value."""
    return o is not None


def valOf(o: Option[T]) -> T:
    """``Option.valOf``: the value in ``o``; raises :class:`ValueError` (SML's ``Option``) on ``NONE``."""
    if o is None:
        raise ValueError("valOf NONE")
    return o[0]
