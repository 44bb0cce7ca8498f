"""``Versions``: a run's kept versions as a read-only sequence — time travel's common shape (paper §1).

The histories of the hull (:class:`~persistri.impl.hull.api.HullHistory`), of the
scattered Delaunay triangulation
(:class:`~persistri.impl.terrain.delaunay_history.DelaunayHistory`) and of a quality
mesh (:class:`~persistri.impl.mesh.api.MeshHistory`) each hold a tuple
``versions`` of complexes, oldest first, and read like it: ``len``, iteration,
``history[k]`` (negative ``k`` from the end) and slices (tuples of versions).  An
index out of range names the range.  Every operation O(1), a slice O(its length):
the versions are shared, never copied.
"""

from __future__ import annotations

import operator
from collections.abc import Iterator
from typing import Generic, TypeVar, overload

from persistri.impl.complex.structure import Complex

__all__ = ["Versions"]

D = TypeVar("D")


class Versions(Generic[D]):
    """A sequence view of ``self.versions`` (a tuple of complexes, set by the subclass). Module docstring."""

    __slots__ = ()

    versions: tuple[Complex[D], ...]

    def __len__(self) -> int:
        return len(self.versions)

    @overload
    def __getitem__(self, k: int) -> Complex[D]: ...

    @overload
    def __getitem__(self, k: slice) -> tuple[Complex[D], ...]: ...

    def __getitem__(self, k: int | slice) -> Complex[D] | tuple[Complex[D], ...]:
        """Version ``k`` (negative ``k`` counts from the end; a slice gives a tuple of versions);
        :class:`IndexError` naming the range for a ``k`` outside it."""
        if isinstance(k, slice):
            return self.versions[k]
        try:
            k = operator.index(k)  # an int, a NumPy integer or a bool; not 1.0 or "1"
        except TypeError:
            raise TypeError(f"history indices must be integers or slices, not {type(k).__name__}") from None
        n = len(self.versions)
        if not -n <= k < n:
            raise IndexError(f"version {k} of a history of {n} versions (0 to {n - 1})")
        return self.versions[k]

    def __iter__(self) -> Iterator[Complex[D]]:
        return iter(self.versions)
