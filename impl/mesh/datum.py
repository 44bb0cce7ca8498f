"""What a version of the mesh holds: triangle data, constraints, and the records of one insertion (paper §1).

The types :mod:`~persistri.impl.mesh.triangulation` reads and makes versions of,
shared by its insertion, its deletion (:mod:`~persistri.impl.mesh.deletion`) and
its walks (:mod:`~persistri.impl.mesh.walk`):

* a triangle ``(a, b, c)`` of vertices (counterclockwise; a *ghost* ``(u, w, ∞)``
  on every hull edge, ``∞`` the symbolic vertex :data:`INFINITE`), whose datum
  (:data:`MeshDatum`) holds a run-unique id, its region (:data:`EXTERIOR` for the
  eaten concavities, the holes and the ghosts) and the constrained edges among its
  own (:data:`Constraint`: an edge on an input segment, and which) — so a version
  knows its own constraints;
* :class:`Insertion` — what one insertion or deletion did (the new version, the
  triangles removed and made); :class:`Cavity` — a point's conflict region found
  in a version before anything is built; :class:`Pending` — steps taken but not
  yet made into a version (Chew's deletions before the split that completes them).

Everything here is an immutable value but :class:`Pending`, the refinement's
record of one step in progress; O(1) per operation unless said.  The names are also
importable from :mod:`persistri.impl.mesh.triangulation`, where they were first defined.
"""

from __future__ import annotations

from typing import Final, NamedTuple

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.vertex import Vertex

__all__ = [
    "EXTERIOR",
    "INFINITE",
    "Constraint",
    "MeshDatum",
    "Tri",
    "Insertion",
    "Cavity",
    "Pending",
    "MeshError",
    "edge_key",
    "constraint_of",
]

EXTERIOR: Final[int] = -1
"""The region of exterior triangles (eaten concavities, holes) and of ghosts."""

INFINITE: Final[int] = -1
"""The label of the symbolic vertex at infinity."""

Constraint = tuple[int, int, int]
"""``(lo, hi, segment)``: the edge between vertex labels ``lo < hi`` lies on input segment ``segment``."""

MeshDatum = tuple[int, int, tuple[Constraint, ...]]
"""The datum of a triangle: ``(id, region, constraints)``; ids are unique over the run (never reused)."""

Tri = tuple[Vertex, Vertex, Vertex]


class MeshError(ValueError):
    """A meshing step met input it cannot handle (crossing segments, a precision limit); the message says which."""


class Insertion(NamedTuple):
    """One insertion: the new ``version``, the cavity ``removed`` and the fan ``created`` (each ``(triangle, datum)``).

    A named tuple (one is made per step of a run: cheaper to build than a frozen dataclass)."""

    version: Complex[MeshDatum]
    removed: tuple[tuple[Tri, MeshDatum], ...]
    created: tuple[tuple[Tri, MeshDatum], ...]


class Cavity(NamedTuple):
    """The conflict region of a point, before anything is built: what :meth:`MeshTriangulation.cavity` found.

    ``triangles`` — the triangles to remove, by id; ``boundary`` — its boundary edges ``(u, w, region, segment)``
    in cavity order (``u → w`` as in the cavity triangle beside it, ``region`` of the triangle to make on it,
    ``segment`` -1 if none); ``beyond`` — for a rounded split point, the exterior triangle beyond the split edge
    that stays, rewritten without the constraint (else None); ``split`` as :meth:`MeshTriangulation.insert`'s.
    """

    version: Complex[MeshDatum]
    point: int
    triangles: dict[int, tuple[Tri, MeshDatum]]
    boundary: list[tuple[Vertex, Vertex, int, int]]
    beyond: tuple[Tri, MeshDatum] | None
    split: tuple[int, int, int] | None


class Pending(NamedTuple):
    """Steps a refinement has taken but made no version of yet: Chew's deletions before the split that completes
    the step (:meth:`MeshTriangulation.build`'s ``before``).

    ``base`` — the version they start from; ``removed`` — its triangles they removed; ``made`` — the triangles they
    made that are still there, by id, in the order they were made."""

    base: Complex[MeshDatum]
    removed: list[Tri]
    made: dict[int, tuple[Tri, MeshDatum]]

    def then(
        self, removed: tuple[tuple[Tri, MeshDatum], ...], created: tuple[tuple[Tri, MeshDatum], ...]
    ) -> tuple[list[Tri], list[tuple[Tri, MeshDatum]]]:
        """``replace``'s two arguments from :attr:`base` for these steps followed by one that removes ``removed`` and
        makes ``created`` (a triangle made and removed again is in neither).  O(number of triangles)."""
        made = dict(self.made)
        gone = list(self.removed)
        for t, d in removed:
            if made.pop(d[0], None) is None:
                gone.append(t)
        return gone, [*made.values(), *created]

    def after(self, removed: tuple[tuple[Tri, MeshDatum], ...], created: tuple[tuple[Tri, MeshDatum], ...]) -> Pending:
        """These steps followed by one more (changed in place and returned). O(number of triangles)."""
        made = self.made
        for t, d in removed:
            if made.pop(d[0], None) is None:
                self.removed.append(t)
        for td in created:
            made[td[1][0]] = td
        return self


def edge_key(u: int, w: int) -> tuple[int, int]:
    """The unordered edge ``{u, w}`` as ``(lo, hi)``."""
    return (u, w) if u < w else (w, u)


def constraint_of(datum: MeshDatum, u: int, w: int) -> int:
    """The input segment the edge ``{u, w}`` of a triangle with ``datum`` lies on, or -1. O(1)."""
    lo, hi = (u, w) if u < w else (w, u)
    for a, b, s in datum[2]:
        if a == lo and b == hi:
            return s
    return -1
