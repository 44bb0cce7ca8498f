"""The exceptions of the convex hull: what is wrong with an input, said plainly."""

from __future__ import annotations

__all__ = ["DegenerateInputError", "BulldozerCheckError"]


class DegenerateInputError(ValueError):
    """The distinct input points do not span 3D space, so they have no 3D convex hull.

    ``affine_dimension`` is the dimension of the affine hull actually found:
    0 (all points identical), 1 (collinear), 2 (coplanar); ``distinct`` is the
    number of distinct points.
    """

    def __init__(self, message: str, *, affine_dimension: int, distinct: int) -> None:
        super().__init__(message)
        self.affine_dimension = affine_dimension
        self.distinct = distinct


class BulldozerCheckError(AssertionError):
    """A ``check=True`` assertion of the bulldozer failed: a theorem of Appendix A did not hold.

    Also importable from :mod:`persistri.impl.hull.bulldozer`, which raises it.
    """
