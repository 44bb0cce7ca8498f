"""The refinement's edge index: the triangles of the version it stands at, by directed edge (paper §1).

Ruppert's refinement (:mod:`~persistri.impl.mesh.ruppert`) reads one version at a
time — the one it stands at — and only ever moves forward from it: every step's
new version is made from the current one, and an undo is to stay where it is.
Its reads (the conflict search, the walk to a new point, the triangles beside a
subsegment) go through an :data:`EdgeIndex` of that version instead of the
persistent complex's maps: a dictionary from each directed edge ``(u, w)`` of a
triangle ``(u, w, x)`` (any rotation, counterclockwise) to ``(x, datum)``, one
O(1) look-up where the complex takes a search of a vertex's map and a scan of
its list.  The index is the run's own mutable cache, never a version: the
versions are made and kept exactly as before (one ``replace`` per step, the
history shares their structure), and the index follows the run — it is changed
only when the run adopts a step (:func:`advance`), so a candidate version that
is dropped (an undone or invalid insertion) never touches it, and it always
describes the version the run stands at.  The Delaunay triangulation of
:mod:`persistri.impl.terrain` keeps the same kind of index for the same reason.

Costs: :func:`index_of` O(N); :func:`advance` O(k) for a step that removes and
makes ``k`` triangles; a look-up O(1) expected.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.vertex import Vertex
from persistri.impl.mesh.datum import MeshDatum, Tri

__all__ = ["EdgeIndex", "EdgeReader", "index_of", "advance", "edge_reader"]

EdgeIndex = dict[tuple[Vertex, Vertex], tuple[Vertex, MeshDatum]]
"""Directed edge ``(u, w)`` of a triangle ``(u, w, x)`` → ``(x, datum)``: one version's triangles by edge."""

EdgeReader = Callable[[tuple[Vertex, Vertex]], "tuple[Vertex, MeshDatum] | None"]
"""``(u, w) ↦ (x, datum)`` of the triangle ``(u, w, x)`` holding the directed edge, or None: an index's ``get``."""


def index_of(items: Iterable[tuple[Tri, MeshDatum]]) -> EdgeIndex:
    """The edge index of the triangles ``items`` (a version's ``items``, each once). O(N)."""
    index: EdgeIndex = {}
    for (a, b, c), d in items:
        index[(a, b)] = (c, d)
        index[(b, c)] = (a, d)
        index[(c, a)] = (b, d)
    return index


def advance(index: EdgeIndex, removed: Iterable[tuple[Tri, MeshDatum]], created: Iterable[tuple[Tri, MeshDatum]]) -> None:
    """The index of a version made from the indexed one by removing the triangles ``removed`` and adding
    ``created`` (a step's :class:`~persistri.impl.mesh.datum.Insertion`), changed in place.  KeyError if a removed
    triangle is not indexed. O(k)."""
    for (a, b, c), _ in removed:
        del index[(a, b)]
        del index[(b, c)]
        del index[(c, a)]
    for (a, b, c), d in created:
        index[(a, b)] = (c, d)
        index[(b, c)] = (a, d)
        index[(c, a)] = (b, d)


def edge_reader(S: Any, c: Complex[MeshDatum]) -> EdgeReader:
    """An :data:`EdgeReader` of version ``c`` of the 2-complex ``S`` that reads the complex itself (for callers with no
    index: every look-up an unchecked ``neighbour``, :meth:`~persistri.impl.complex.two_complex.TwoComplex.neighbours_unchecked`)."""
    neighbour = S.neighbours_unchecked(c)

    def get(e: tuple[Vertex, Vertex]) -> tuple[Vertex, MeshDatum] | None:
        found = neighbour(e)
        return None if found is None else (found[0][2], found[1])

    return get
