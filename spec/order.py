"""SML's ``order`` and the ``ORD_KEY`` signature.

SML's basis library has ``datatype order = LESS | EQUAL | GREATER``; the SML/NJ
library's ``ORD_KEY`` signature is a type of keys with a ``compare`` into it::

    signature ORD_KEY = sig
      type ord_key
      val compare : ord_key * ord_key -> order
    end

In Python the type ``ord_key`` is a type parameter ``K`` and the structure is any
object with a ``compare`` method (:class:`OrdKey`).  persistri's own maps order
keys by Python's natural order (``<`` and ``==``), whose ``ORD_KEY`` structure is
:data:`NATURAL_ORDER`.
"""

from __future__ import annotations

import enum
from typing import Any, Generic, Protocol, TypeVar

__all__ = ["Order", "OrdKey", "ORD_KEY", "Comparable", "NaturalOrder", "NATURAL_ORDER"]


class Order(enum.Enum):
    """SML's ``order``: the result of a three-way comparison."""

    LESS = -1
    EQUAL = 0
    GREATER = 1

    def __neg__(self) -> Order:
        """The comparison read the other way round: ``-compare(a, b) == compare(b, a)``."""
        return Order(-self.value)


K_contra = TypeVar("K_contra", contravariant=True)


class OrdKey(Protocol[K_contra]):
    """``signature ORD_KEY``: a total order on keys of type ``K``.

    Laws (:mod:`persistri.spec.ord_map_laws` runs them): ``compare`` is
    reflexive (``compare(a, a) is EQUAL``), antisymmetric
    (``compare(a, b) == -compare(b, a)``) and transitive.
    """

    def compare(self, a: K_contra, b: K_contra, /) -> Order:
        """``compare (a, b)``: LESS, EQUAL or GREATER as ``a`` is below, equal to or above ``b``."""
        ...


ORD_KEY = OrdKey
"""The SML name of :class:`OrdKey`."""


class Comparable(Protocol):
    """Keys in Python's natural order: ``<`` and ``==`` among themselves."""

    def __lt__(self, other: Any, /) -> bool: ...


C = TypeVar("C", bound=Comparable)


class NaturalOrder(Generic[C]):
    """The ``ORD_KEY`` structure of Python's natural order: ``<`` and ``==``.

    >>> NATURAL_ORDER.compare(1, 2)
    <Order.LESS: -1>
    >>> NATURAL_ORDER.compare("b", "b")
    <Order.EQUAL: 0>
    """

    __slots__ = ()

    def compare(self, a: C, b: C, /) -> Order:
        """Three-way comparison by ``<``; O(1) for integer keys."""
        if a < b:
            return Order.LESS
        if b < a:
            return Order.GREATER
        return Order.EQUAL

    def __repr__(self) -> str:
        return "NATURAL_ORDER"


NATURAL_ORDER: NaturalOrder[Any] = NaturalOrder()
"""The single :class:`NaturalOrder` structure every persistri map uses as its ``Key``."""
