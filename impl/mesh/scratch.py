"""A mutable scratch triangulation for building the constrained Delaunay triangulation in one version (paper §1).

The refinement's history starts at the constrained Delaunay triangulation of the
domain (``history[0]``); the steps that build it — each vertex inserted, each
segment recovered — are not versions anyone reads.  Making each of them a version
of the persistent 2-complex cost one ``replace`` per vertex, most of the time of
a small domain's whole mesh.  :class:`ScratchComplex` is the part of the
:class:`~persistri.impl.complex.two_complex.TwoComplex` interface that
:class:`~persistri.impl.mesh.triangulation.MeshTriangulation` and the CDT
builder use (``new``, ``add``, ``data``, ``neighbour``, ``neighbours``,
``replace``, ``items``, ``grep``), on one mutable dictionary: each "version" it
returns is the same object, changed in place, so it must only ever be used
forwards — as the builder does — and it is never a version of the history.  The
builder then writes the finished triangulation into the persistent complex with
one ``replace`` (:func:`~persistri.impl.mesh.cdt.constrained_delaunay`).

Representation: every triangle ``(a, b, c)`` (any rotation, counterclockwise) is
three directed edges ``(a, b) → (c, datum)``, ``(b, c) → (a, datum)``,
``(c, a) → (b, datum)``; on a closed surface (ghosts close the hull) each directed
edge is in at most one triangle.  ``out[v]`` is one directed edge leaving ``v``,
from which ``v``'s star is walked.  Costs: O(1) expected per lookup and per
triangle added or removed; ``grep`` O(degree); ``items`` O(N).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import Any

from persistri.impl.complex.vertex import Vertex
from persistri.impl.mesh.triangulation import MeshDatum, MeshError, Tri

__all__ = ["ScratchComplex"]

Edges = dict[tuple[Vertex, Vertex], tuple[Vertex, MeshDatum]]


class _Scratch:
    """The mutable state: the directed edges and one edge out of each vertex."""

    __slots__ = ("edges", "out")

    def __init__(self) -> None:
        self.edges: Edges = {}
        self.out: dict[Vertex, tuple[Vertex, Vertex]] = {}


class ScratchComplex:
    """The 2-complex interface of the CDT builder on one mutable :class:`_Scratch` (module docstring)."""

    def new(self, dim: int) -> Any:
        """An empty scratch triangulation (``dim`` must be 2)."""
        if dim != 2:
            raise ValueError(f"a scratch triangulation holds triangles, not {dim}-simplices")
        return _Scratch()

    def add(self, c: Any, s: Tri, x: MeshDatum) -> Any:
        """``c`` with the triangle ``s`` (datum ``x``) added; ``c`` itself, changed. O(1)."""
        self._put(c, s, x)
        return c

    def data(self, c: Any, s: Tri) -> tuple[MeshDatum] | None:
        """``(datum,)`` if the triangle ``s`` is held in this orientation, else None. O(1)."""
        a, b, cc = s
        found = c.edges.get((a, b))
        if found is None or found[0] != cc:
            return None
        return (found[1],)

    def neighbour(self, c: Any, s: tuple[Vertex, Vertex]) -> tuple[Tri, MeshDatum] | None:
        """The triangle holding the directed edge ``s = (u, w)``, as ``((u, w, x), datum)``, or None. O(1)."""
        found = c.edges.get(s)
        if found is None:
            return None
        return (s[0], s[1], found[0]), found[1]

    def neighbours(self, c: Any) -> Callable[[tuple[Vertex, Vertex]], tuple[Tri, MeshDatum] | None]:
        """``s ↦ neighbour(c, s)``."""
        edges = c.edges

        def neighbour(s: tuple[Vertex, Vertex]) -> tuple[Tri, MeshDatum] | None:
            found = edges.get(s)
            if found is None:
                return None
            return (s[0], s[1], found[0]), found[1]

        return neighbour

    def replace(self, c: Any, removed: Sequence[Tri], added: Iterable[tuple[Tri, MeshDatum]]) -> Any:
        """``c`` without the triangles ``removed`` (any rotation) and with ``added``; ``c`` itself, changed. O(k)."""
        edges = c.edges
        for a, b, cc in removed:
            for u, w, y in ((a, b, cc), (b, cc, a), (cc, a, b)):
                found = edges.pop((u, w), None)
                if found is None or found[0] != y:
                    raise MeshError(f"internal: the scratch triangulation holds no triangle {(u, w, y)}")
        for s, x in added:
            self._put(c, s, x)
        return c

    def items(self, c: Any) -> list[tuple[Tri, MeshDatum]]:
        """Each triangle once, as the rotation starting at its smallest vertex, with its datum. O(N)."""
        return [((u, w, x), d) for (u, w), (x, d) in c.edges.items() if u < w and u < x]

    def grep(self, c: Any, dim: int, s: tuple[Vertex, ...]) -> list[Tri]:
        """The triangles having the vertex ``s[0]`` (``dim`` 2, one vertex), each starting at it. O(degree)."""
        if dim != 2 or len(s) != 1:
            raise ValueError("a scratch triangulation answers grep for the triangles of one vertex only")
        (v,) = s
        first = c.out.get(v)
        if first is None:
            return []
        edges = c.edges
        out: list[Tri] = []
        u, w = first
        found = edges.get((u, w))
        if found is None:
            raise MeshError(f"internal: the scratch edge out of vertex {int(v)} is gone")
        while True:
            x = found[0]
            out.append((u, w, x))
            w = x
            if (u, w) == first:
                return out
            found = edges.get((u, w))
            if found is None:  # an open star (not on a closed surface): walk no further
                return out

    def _put(self, c: Any, s: Tri, x: MeshDatum) -> None:
        a, b, cc = s
        edges, out = c.edges, c.out
        for u, w, y in ((a, b, cc), (b, cc, a), (cc, a, b)):
            if (u, w) in edges:
                raise MeshError(f"internal: the scratch edge {(int(u), int(w))} is already in a triangle")
            edges[(u, w)] = (y, x)
            out[u] = (u, w)
