"""``signature ORD_MAP``: persistent finite maps over totally ordered keys.

A transcription of the subset of the SML/NJ library's ``ORD_MAP`` that the
simplicial complexes of the paper (§2) need.  An SML *structure* matching
``ORD_MAP`` becomes a Python object whose methods are the signature's values
(:class:`OrdMap`); an SML map value (``'a map``) stays a plain immutable value
of type ``M`` that only the structure's operations look inside.

Transcription rules (see the docs' SML → Python table):

* names stay SML's (``isEmpty``, ``insertWith``, ``listItemsi``, ``foldli``);
* curried arguments are uncurried, function arguments first:
  ``insertWith f (m, k, v)`` is ``insertWith(f, m, k, v)``,
  ``foldli f init m`` is ``foldli(f, init, m)``;
* ``'a option`` is :data:`persistri.spec.option.Option` (``(v,)`` or ``None``);
* SML's ``LibBase.NotFound`` is :class:`NotFound`;
* lists are Python lists, in increasing key order.

Python has no higher-kinded types, so ``'a map`` cannot be written as a type
constructor applied to ``'a``.  The protocol is therefore generic in the key
type ``K``, the value type ``V`` and the map type ``M`` (a map from ``K`` to
``V``): ``RedBlackMap[int, str]`` is an ``OrdMap[int, str, RBMap[int, str]]``.
A structure used at ``Any`` (the module constants) is polymorphic in ``V``, as
an SML structure is.  Returning ``M`` from every operation plays the role of
opaque signature ascription: code typed against ``OrdMap`` cannot look inside.

Every operation is *persistent*: it never changes a map it is given (nor any
map sharing structure with it) and returns a new one.  The laws of the
signature are executable, in :mod:`persistri.spec.ord_map_laws`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol, TypeVar

from persistri.spec.option import Option
from persistri.spec.order import OrdKey

__all__ = ["OrdMap", "ORD_MAP", "NotFound"]

K = TypeVar("K")
V = TypeVar("V")
M = TypeVar("M")
B = TypeVar("B")


class NotFound(KeyError):
    """SML/NJ's ``LibBase.NotFound``: ``lookup`` or ``remove`` of a key that is absent.

    A subclass of :class:`KeyError`, so ``except KeyError`` also catches it.
    """


class OrdMap(Protocol[K, V, M]):
    """``signature ORD_MAP``: a structure of operations on persistent maps ``M`` from ``K`` to ``V``.

    Complexities are those of a balanced-tree structure (the red-black map);
    each backend's docstrings state its own.
    """

    @property
    def Key(self) -> OrdKey[K]:
        """``structure Key : ORD_KEY``: the total order on keys (``listItemsi`` follows it)."""
        ...

    def empty(self) -> M:
        """``empty``: the map with no items."""
        ...

    def isEmpty(self, m: M, /) -> bool:
        """``isEmpty m``: whether ``m`` has no items."""
        ...

    def singleton(self, k: K, v: V, /) -> M:
        """``singleton (k, v)``: the map with the single item ``k ↦ v``."""
        ...

    def insert(self, m: M, k: K, v: V, /) -> M:
        """``insert (m, k, v)``: ``m`` with ``k ↦ v``, replacing any earlier value of ``k``.

        A key is replaced by any key that ``Key.compare`` calls EQUAL.  Which of two
        equal but distinguishable key objects (``1``, ``1.0``, ``True``) the result
        stores is not part of the signature, and no law checks it: persistri's own
        backends store ``k``, as SML/NJ's ``RedBlackMapFn`` does, the adapters for
        ``immutables`` and ``pyrsistent`` keep the stored key, as ``dict`` does.
        """
        ...

    def insertWith(self, f: Callable[[V, V], V], m: M, k: K, v: V, /) -> M:
        """``insertWith f (m, k, v)``: like ``insert``, but ``k ↦ f(old, v)`` when ``k ↦ old`` is in ``m``."""
        ...

    def find(self, m: M, k: K, /) -> Option[V]:
        """``find (m, k)``: ``(v,)`` (SOME v) when ``k ↦ v`` is in ``m``, else ``None`` (NONE)."""
        ...

    def lookup(self, m: M, k: K, /) -> V:
        """``lookup (m, k)``: the value of ``k`` in ``m``; raises :class:`NotFound` when absent."""
        ...

    def inDomain(self, m: M, k: K, /) -> bool:
        """``inDomain (m, k)``: whether ``k`` has a value in ``m``."""
        ...

    def remove(self, m: M, k: K, /) -> tuple[M, V]:
        """``remove (m, k)``: ``(m without k, the value k had)``; raises :class:`NotFound` when absent."""
        ...

    def numItems(self, m: M, /) -> int:
        """``numItems m``: the number of items in ``m``."""
        ...

    def listItemsi(self, m: M, /) -> list[tuple[K, V]]:
        """``listItemsi m``: the ``(key, value)`` items of ``m`` in increasing key order."""
        ...

    def listKeys(self, m: M, /) -> list[K]:
        """``listKeys m``: the keys of ``m`` in increasing order."""
        ...

    def foldli(self, f: Callable[[K, V, B], B], init: B, m: M, /) -> B:
        """``foldli f init m``: ``f(kn, vn, … f(k1, v1, init))`` over the items in increasing key order."""
        ...


ORD_MAP = OrdMap
"""The SML name of :class:`OrdMap`."""
