"""The empty slot of an integer trie's leaf: one object, kept by identity through copies and pickles.

A leaf of :mod:`persistri.impl.maps.int_trie` holds a value in each of its 32
slots, and a slot without a key holds :data:`ABSENT`.  Values may be anything,
``None`` included, so the empty slot is an object no caller can hold: this
module's one instance of a private class, which pickles by name (so an unpickled
map's empty slots are this object again) and copies as itself.  Its own module,
interpreted on both builds, because the compiled twin makes compiled classes
native types, which pickle differently.  O(1).
"""

from __future__ import annotations

from typing import Any, Final

__all__ = ["ABSENT"]


class _Absent:
    __slots__ = ()

    def __reduce__(self) -> str:
        return "ABSENT"

    def __copy__(self) -> _Absent:
        return self

    def __deepcopy__(self, memo: dict[int, Any]) -> _Absent:
        return self

    def __repr__(self) -> str:
        return "ABSENT"

    def __bool__(self) -> bool:
        return False


ABSENT: Final = _Absent()
"""The value of a leaf slot that holds no key."""
