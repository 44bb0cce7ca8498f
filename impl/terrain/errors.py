"""The exceptions of the terrain and Delaunay layer: what is wrong with an input, said plainly."""

from __future__ import annotations

__all__ = ["DegenerateInputError", "TriangulationCheckError"]


class DegenerateInputError(ValueError):
    """The distinct input points have no 2D triangulation: fewer than 3 of them, or all on one line.

    ``distinct`` is the number of distinct points.
    """

    def __init__(self, message: str, *, distinct: int) -> None:
        super().__init__(message)
        self.distinct = distinct


class TriangulationCheckError(AssertionError):
    """A ``check=True`` assertion of the incremental Delaunay triangulation failed (the message says which).

    Defined here, not in :mod:`persistri.impl.terrain.delaunay` (which re-exports it), because that
    module is compiled in the compiled twin and mypyc does not compile subclasses of builtin exceptions.
    """
