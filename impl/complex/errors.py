"""The exceptions of the complex layer: bad input, and failed invariant checks.

Bad input is rejected at the API boundary with one of the classes below (each a
:class:`ValueError` or :class:`TypeError`), before anything is built.  Because
every complex is persistent, a rejected call leaves the version it was given
untouched and still valid: there is nothing to roll back.

=================================  ==============  ==============================================
exception                          base            raised when
=================================  ==============  ==============================================
:class:`NotAVertexError`           TypeError       a simplex holds something that is not a vertex
:class:`RepeatedVertexError`       ValueError      a simplex repeats a vertex
:class:`ForeignVertexError`        ValueError      a vertex of another state lineage is used
:class:`DimensionError`            ValueError      a simplex or dimension is wrong for the call
:class:`DuplicateSimplexError`     ValueError      ``add`` of a simplex already present
:class:`OppositeOrientationError`  ValueError      ``add`` of a simplex whose reverse is present
:class:`AbsentSimplexError`        ValueError      ``rem``/``update`` of a simplex not present
:class:`ForeignComplexError`       TypeError       a complex made by another structure
:class:`StaleVersionError`         RuntimeError    an old version of the *ephemeral* baseline
=================================  ==============  ==============================================

:class:`DuplicateSimplexError` and :class:`OppositeOrientationError` share the
base :class:`SimplexPresentError`.  The executable invariants of
:mod:`persistri.impl.complex.checks` raise subclasses of
:class:`ComplexCheckError` (an :class:`AssertionError`: a broken complex is a
bug, not bad input).
"""

from __future__ import annotations

__all__ = [
    "NotAVertexError",
    "RepeatedVertexError",
    "ForeignVertexError",
    "DimensionError",
    "SimplexPresentError",
    "DuplicateSimplexError",
    "OppositeOrientationError",
    "AbsentSimplexError",
    "ForeignComplexError",
    "StaleVersionError",
    "ComplexCheckError",
    "RepresentationError",
    "OrientationError",
    "ClosureError",
    "LineageError",
    "SurfaceError",
    "EdgeError",
    "VertexLinkError",
    "NotASphereError",
]


# -- bad input -------------------------------------------------------------------


class NotAVertexError(TypeError):
    """A simplex (or ``loc``) was given something that is not a :class:`~persistri.impl.complex.vertex.Vertex`.

    Plain integers are rejected too: a vertex carries its point and its lineage.
    """


class RepeatedVertexError(ValueError):
    """A simplex lists one vertex twice: an n-simplex needs n+1 *distinct* vertices (paper §2)."""


class ForeignVertexError(ValueError):
    """A vertex of another state lineage: it was made by a different ``VertexState.initial()``.

    A complex adopts the lineage of the first simplex added to it; its later
    simplices, and the simplices it is asked about, must come from the same one.
    """


class DimensionError(ValueError):
    """A simplex of the wrong dimension for the call (``add`` of a non-n-simplex to an
    n-complex, ``find`` of a non-(n−1)-simplex, …) or a dimension out of range."""


class SimplexPresentError(ValueError):
    """``add`` of a simplex that the complex already holds, in this orientation or the other."""


class DuplicateSimplexError(SimplexPresentError):
    """``add`` of a simplex already present with the same orientation (use ``update`` to change its datum)."""


class OppositeOrientationError(SimplexPresentError):
    """``add`` of a simplex whose opposite orientation is present: a complex holds each simplex once."""


class AbsentSimplexError(ValueError):
    """``rem`` or ``update`` of a simplex that is not present (in this orientation)."""


class ForeignComplexError(TypeError):
    """A complex value that this structure did not make (another representation, backend or dimension),
    or something that is not a complex at all."""


class StaleVersionError(RuntimeError):
    """A version of the *ephemeral* 2-complex (:mod:`persistri.impl.complex.ephemeral`) used after a later
    operation changed its table in place.

    Not bad input but the price of giving up persistence: only the newest
    version of an ephemeral complex is valid.  The persistent complexes never raise it.
    """


# -- failed invariant checks -------------------------------------------------------


class ComplexCheckError(AssertionError):
    """An executable invariant of :mod:`persistri.impl.complex.checks` does not hold; the message says which and where."""


class RepresentationError(ComplexCheckError):
    """The representation is inconsistent (e.g. a triangle missing from one of its three vertex lists)."""


class OrientationError(ComplexCheckError):
    """A simplex is held twice, or in both orientations."""


class ClosureError(ComplexCheckError):
    """Conditions 1–3 of the paper's definition of an n-complex (§2) fail."""


class LineageError(ComplexCheckError):
    """The vertices of a complex do not all come from its state lineage, or two differ under one label."""


class SurfaceError(ComplexCheckError):
    """A 2-complex is not a closed, consistently oriented surface."""


class EdgeError(SurfaceError):
    """An oriented edge lies in more than one triangle, or its reverse in none (a boundary or a fold)."""


class VertexLinkError(SurfaceError):
    """The link of a vertex is not one simple cycle (a pinch point, a boundary vertex)."""


class NotASphereError(SurfaceError):
    """A closed surface that is not a sphere: ``genera`` holds the genus of each connected component."""

    genera: tuple[int, ...]

    def __init__(self, message: str, genera: tuple[int, ...]) -> None:
        super().__init__(message)
        self.genera = genera
