"""An arena red-black map's value: one ``int``, of a class that holds its arena (paper §2; issue 17's memory).

A map of :mod:`persistri.impl.maps.red_black_arena` is its number of items and
the index of its root node, packed in one ``int`` (``size << 32 | root``), and
its arena.  A kept history holds one map value per version, so the value's own
bytes count: a 3-tuple ``(size, root, arena)`` and its two ``int`` s take 128
bytes (tracemalloc), an :class:`ArenaMap` about 56 — an ``int`` of a subclass
whose *class attribute* is the arena.  CPython allows no instance slot on a
subclass of ``int``, so each arena gets its own subclass (made once, on first
use, by :func:`map_class`), as each vertex lineage makes its own vertex classes
(:mod:`persistri.impl.complex.vertex`).  The empty map without an arena is
:class:`ArenaMap` ``(0)`` itself (``arena`` None).

A map value is immutable (an ``int``).  ``==`` is that of the maps' fields:
two values are equal when they have one arena, one size and one root (not
when only their ints are equal), and hash as their ``int``.  Copying returns
the same value; deep copying and pickling copy the arena and give a value of
the copy's class (:func:`map_class`: one class per arena, so the values of one
unpickled arena share theirs).  The arena and its class refer to each other
through the class's attribute and the class's own cycles: an arena whose maps
are all dropped is freed by the cyclic garbage collector, not at once.

All O(1).
"""

from __future__ import annotations

import weakref
from typing import Any, ClassVar, Final

from persistri.impl.maps.red_black_arena_tree import ROOT_BITS, ROOT_MASK, Arena

__all__ = ["ArenaMap", "map_class", "make", "fields", "ROOT_BITS", "ROOT_MASK", "ONE"]

ONE: Final = 1 << ROOT_BITS
"""One item, in a map value's ``int``: ``size << ROOT_BITS | root``."""


class ArenaMap(int):
    """An arena red-black map: ``size << 32 | root`` as an ``int`` whose class holds the arena (module docstring).

    ``ArenaMap(0)`` is the empty map without an arena; every other value is an
    instance of its arena's class (:func:`map_class`).  Read the fields with
    :attr:`size`, :attr:`root` and :attr:`arena` (or :func:`fields`).
    """

    __slots__ = ()

    arena: ClassVar[Arena | None] = None
    """The arena of the map's nodes (a class attribute: one class per arena); None for the empty map without one."""

    @property
    def size(self) -> int:
        """The number of items."""
        return self >> ROOT_BITS

    @property
    def root(self) -> int:
        """The index of the root node in :attr:`arena` (0, the empty leaf, for an empty map)."""
        return self & ROOT_MASK

    def __eq__(self, other: object) -> bool:
        return isinstance(other, ArenaMap) and other.arena is self.arena and int(self) == int(other)

    def __ne__(self, other: object) -> bool:
        return not self == other

    __hash__ = int.__hash__

    def __copy__(self) -> ArenaMap:
        return self

    def __reduce__(self) -> tuple[Any, tuple[int, Arena | None]]:
        # Rebuilt through the (copied) arena's class: the classes themselves are not picklable.
        return (_rebuilt, (int(self), self.arena))

    def __repr__(self) -> str:
        return f"ArenaMap(size={self >> ROOT_BITS}, root={self & ROOT_MASK})"


_classes: weakref.WeakValueDictionary[int, type[ArenaMap]] = weakref.WeakValueDictionary()
"""Each live arena's class, by the arena's ``id`` (the class holds the arena, so the id is not reused while the
entry lives)."""


def map_class(A: Arena) -> type[ArenaMap]:
    """The class of the map values of the arena ``A``: made on first use, then the same.  O(1) amortised."""
    cls = _classes.get(id(A))
    if cls is None or cls.arena is not A:
        ns: dict[str, Any] = {"__slots__": (), "arena": A, "__module__": __name__, "__qualname__": "ArenaMap"}
        cls = type("ArenaMap", (ArenaMap,), ns)
        _classes[id(A)] = cls
    return cls


def _rebuilt(p: int, A: Arena | None) -> ArenaMap:
    """The map value ``p`` of arena ``A`` (unpickling, deep copy)."""
    return ArenaMap(p) if A is None else map_class(A)(p)


def make(n: int, root: int, A: Arena | None) -> ArenaMap:
    """The map value of ``n`` items under the node ``root`` of ``A`` (:func:`fields`' inverse).  O(1)."""
    return _rebuilt(n << ROOT_BITS | root, A)


def fields(m: ArenaMap) -> tuple[int, int, Arena | None]:
    """``(number of items, root index, arena)`` of the map ``m``.  O(1)."""
    return m >> ROOT_BITS, m & ROOT_MASK, m.arena
