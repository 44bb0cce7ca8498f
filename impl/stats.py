"""Instrumentation: the operation counts of the paper's §4.

The paper measures the cost of the two halves of its algorithms in
machine-independent counts:

* the *topological* half — the simplicial complex — in **dictionary
  operations** and **key comparisons**: the red-black tree nodes visited plus
  the association-list elements visited (for the HAMT: key equality tests);
* the *numerical* half in **plane-side tests** (3D orientation tests) and the
  floating-point operations they imply.

A :class:`Stats` is attached to the code that should report to it (a map
structure through :func:`persistri.impl.maps.counted.counted`, a complex, an
algorithm).  Attaching one never changes a result; code with no ``Stats``
attached runs its uncounted fast path and pays nothing.

A ``Stats`` is *instrumentation*, not data: it is the one deliberately mutable
object in persistri, a bank of counters.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

__all__ = ["Stats"]


@dataclass(slots=True)
class Stats:
    """Counters of the work an algorithm does (paper §4, Figs. 6, 7 and 11)."""

    dict_ops: int = 0
    """Dictionary operations: calls of a map structure's operations (insert, find, remove, …)."""
    key_comparisons: int = 0
    """Key comparisons: tree nodes visited plus association-list elements visited (HAMT: key equality tests)."""
    plane_side_tests: int = 0
    """Plane-side (3D orientation) tests, and in-circle tests counted as their lifted orientation tests."""
    flops: int = 0
    """Floating-point operations implied by the geometric tests (each test documents its count)."""
    filter_failures: int = 0
    """Geometric tests the floating-point filter could not decide (settled by exact arithmetic)."""
    faces_created: int = 0
    """Faces (top simplices) added to a complex."""
    faces_deleted: int = 0
    """Faces (top simplices) removed from a complex."""

    def reset(self) -> None:
        """Set every counter back to zero."""
        for f in dataclasses.fields(self):
            setattr(self, f.name, 0)

    def as_dict(self) -> dict[str, int]:
        """The counters by name, in declaration order."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}

    def __iadd__(self, other: Stats) -> Stats:
        for f in dataclasses.fields(self):
            setattr(self, f.name, getattr(self, f.name) + getattr(other, f.name))
        return self
