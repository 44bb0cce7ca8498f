"""The exceptions of the terrain and Delaunay layer: what is wrong with an input, said plainly."""

from __future__ import annotations

__all__ = ["DegenerateInputError"]


class DegenerateInputError(ValueError):
    """The distinct input points have no 2D triangulation: fewer than 3 of them, or all on one line.

    ``distinct`` is the number of distinct points.
    """

    def __init__(self, message: str, *, distinct: int) -> None:
        super().__init__(message)
        self.distinct = distinct
