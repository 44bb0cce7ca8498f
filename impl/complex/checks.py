"""Executable invariants of complexes: :func:`check_complex` and :func:`check_closed_surface`.

Each check returns quietly when the invariant holds and otherwise raises a
subclass of :class:`~persistri.impl.complex.errors.ComplexCheckError` whose
message names the simplex, edge or vertex at fault.  They read a complex
through the *uncounted* structure of its family, so running a check never
changes the counts of an attached :class:`~persistri.impl.stats.Stats`.

:func:`check_complex` (any n) — the paper's definition of an n-complex (§2):

1. every vertex determines a 0-simplex, and lies in an n-simplex;
2. every sub-simplex of a simplex of the complex is a simplex of it
   (``simplices(c, d)`` reports every d-face of every n-simplex);
3. every simplex is a sub-simplex of some n-simplex (``simplices(c, d)``
   reports nothing else);

plus: each simplex held once and in one orientation only, all vertices of the
complex's lineage with one point per label, and the representation's own
consistency (for the 2-complex: each triangle in the lists of all three of its
vertices, with the same datum; for the functor: each face under each vertex).

:func:`check_closed_surface` (n = 2) — a closed, consistently oriented surface:
every oriented edge lies in exactly one triangle and its reverse in exactly
one; the link of every vertex is one simple cycle; and, unless
``sphere=False``, one component of Euler characteristic 2.  It returns a
:class:`SurfaceReport` with the genus of each component.

Both are O(N) map reads plus O(N · 2^(n+1)) set operations for N n-simplices.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from itertools import combinations
from typing import Any

from persistri.impl.complex.errors import (
    ClosureError,
    DimensionError,
    EdgeError,
    ForeignComplexError,
    LineageError,
    NotASphereError,
    OrientationError,
    RepresentationError,
    VertexLinkError,
)
from persistri.impl.complex.simplex import Simplex, canonical
from persistri.impl.complex.structure import Complex, ComplexStructure, Family, same_datum
from persistri.impl.complex.vertex import Vertex

__all__ = ["check_complex", "check_closed_surface", "check_vertex_lists", "SurfaceReport"]


def _plain(c: Any, what: str) -> tuple[ComplexStructure[Any], Complex[Any]]:
    fam = getattr(c, "family", None)
    if not isinstance(c, Complex) or not isinstance(fam, Family):
        raise ForeignComplexError(f"{what}: expected a persistri complex, got {type(c).__name__}")
    return fam.plain, c


def check_complex(c: Complex[Any]) -> None:
    """Raise unless ``c`` is a well-formed n-complex in a consistent representation (module docstring).

    Raises RepresentationError, OrientationError, LineageError or ClosureError.
    """
    S, c = _plain(c, "check_complex")
    n = S.n
    S.check(c)
    tops = S.items(c)

    # Each n-simplex once, in one orientation; n+1 distinct vertices.
    by_set: dict[frozenset[Vertex], Simplex] = {}
    for t, _ in tops:
        if len(t) != n + 1 or len(set(t)) != n + 1:
            raise RepresentationError(f"check_complex: {t!r} is not an {n}-simplex of distinct vertices")
        key = frozenset(t)
        if key in by_set:
            other = by_set[key]
            how = "twice" if canonical(other) == canonical(t) else f"in both orientations, {other!r} and {t!r}"
            raise OrientationError(f"check_complex: the {n}-simplex on {sorted(key)!r} is held {how}")
        by_set[key] = t

    # Lineage: every vertex of the complex's lineage, and one vertex object per label.
    seen: dict[int, Vertex] = {}
    for key in by_set:
        for v in key:
            if c.lineage is not None and getattr(v, "lineage", None) is not c.lineage:
                raise LineageError(
                    f"check_complex: vertex {v!r} has lineage {getattr(v, 'lineage', None)!r}, "
                    f"the complex {c.lineage!r}"
                )
            first = seen.setdefault(int(v), v)
            if first is not v and (first.point is not v.point and first.point != v.point):
                raise LineageError(
                    f"check_complex: label {int(v)} names two vertices, at {first.point!r} and {v.point!r} "
                    "(vertices of two branches of one state were mixed)"
                )
    if tops and c.lineage is None:
        raise LineageError("check_complex: a non-empty complex has no lineage")

    if S.isEmpty(c) != (not tops):
        raise RepresentationError(f"check_complex: isEmpty is {S.isEmpty(c)} but the complex holds {len(tops)} simplices")

    # Condition 1: the vertices are exactly the vertices of the n-simplices.
    verts = S.vertices(c)
    if len(set(verts)) != len(verts):
        raise ClosureError(f"check_complex: vertices(c) repeats a vertex: {verts!r}")
    in_tops = set().union(*by_set) if by_set else set()
    if set(verts) != in_tops:
        extra = sorted(set(verts) - in_tops)
        missing = sorted(in_tops - set(verts))
        if extra:
            raise ClosureError(f"condition 1: vertices {extra!r} of the complex lie in no {n}-simplex")
        raise ClosureError(f"condition 1: vertices {missing!r} of {n}-simplices are not vertices of the complex")

    # Conditions 2 and 3, dimension by dimension.
    for d in range(n + 1):
        reported = S.simplices(c, d)
        sets = [frozenset(s) for s in reported]
        for s in reported:
            if len(s) != d + 1 or len(set(s)) != d + 1:
                raise ClosureError(f"simplices(c, {d}) reports {s!r}, not a {d}-simplex of distinct vertices")
        if len(set(sets)) != len(sets):
            dup = next(s for s in reported if sets.count(frozenset(s)) > 1)
            raise ClosureError(f"simplices(c, {d}) reports the {d}-simplex {dup!r} more than once")
        closure = {frozenset(f) for key in by_set for f in combinations(sorted(key), d + 1)}
        missing_faces = closure - set(sets)
        if missing_faces:
            f = sorted(next(iter(missing_faces)))
            owner = next(by_set[k] for k in by_set if set(f) <= k)
            raise ClosureError(f"condition 2: the face {tuple(f)!r} of {owner!r} is not among simplices(c, {d})")
        strays = set(sets) - closure
        if strays:
            stray = tuple(sorted(next(iter(strays))))
            raise ClosureError(f"condition 3: the {d}-simplex {stray!r} is a face of no {n}-simplex")


@dataclass(frozen=True, slots=True)
class SurfaceReport:
    """What :func:`check_closed_surface` found: counts, Euler characteristic and genus per component."""

    vertices: int
    edges: int
    faces: int
    euler: int
    """V − E + F over the whole surface."""
    components: int
    genera: tuple[int, ...]
    """The genus of each connected component (0 for a sphere, 1 for a torus), by smallest vertex."""

    @property
    def is_sphere(self) -> bool:
        """One component of genus 0."""
        return self.genera == (0,)


def check_closed_surface(c: Complex[Any], *, sphere: bool = True) -> SurfaceReport:
    """Raise unless the 2-complex ``c`` is a closed, consistently oriented surface (module docstring).

    Runs :func:`check_complex` first.  Raises EdgeError (an oriented edge in
    two triangles, or one whose reverse is in none), VertexLinkError (a link
    that is not one simple cycle), and, when ``sphere`` is true, NotASphereError
    (carrying the genera) for anything but one component of genus 0.
    """
    S, c = _plain(c, "check_closed_surface")
    if S.n != 2:
        raise DimensionError(f"check_closed_surface: needs a 2-complex, got a {S.n}-complex")
    check_complex(c)
    tops = [t for t, _ in S.items(c)]

    owner: dict[tuple[Vertex, Vertex], Simplex] = {}
    for t in tops:
        a, b, cc = t
        for e in ((a, b), (b, cc), (cc, a)):
            if e in owner:
                raise EdgeError(
                    f"closed surface: the oriented edge {e!r} lies in two triangles, {owner[e]!r} and {t!r} "
                    "(their orientations disagree, or more than two triangles meet at the edge)"
                )
            owner[e] = t
    for (u, w), t in owner.items():
        if (w, u) not in owner:
            raise EdgeError(
                f"closed surface: edge {(u, w)!r} of {t!r} has no triangle on its other side "
                f"(no triangle holds {(w, u)!r}): the surface has a boundary"
            )

    # The link of v: the edge b -> c of each triangle (v, b, c) around it.
    succ: dict[Vertex, dict[Vertex, Vertex]] = {}
    for t in tops:
        a, b, cc = t
        for v, p, q in ((a, b, cc), (b, cc, a), (cc, a, b)):
            succ.setdefault(v, {})[p] = q
    for v, nxt in succ.items():
        start = next(iter(nxt))
        w, length = start, 0
        while True:
            w = nxt[w]
            length += 1
            if w == start:
                break
        if length != len(nxt):
            raise VertexLinkError(
                f"closed surface: the link of {v!r} is not one cycle: {length} of its {len(nxt)} link edges "
                f"form the cycle through {start!r} (a pinch point: two or more fans meet at {v!r})"
            )

    # Components (union-find over vertices) and the Euler characteristic of each.
    parent: dict[Vertex, Vertex] = {v: v for v in succ}

    def root(v: Vertex) -> Vertex:
        while parent[v] != v:
            parent[v] = parent[parent[v]]
            v = parent[v]
        return v

    for u, w in owner:
        ru, rw = root(u), root(w)
        if ru != rw:
            parent[max(ru, rw)] = min(ru, rw)
    chi: dict[Vertex, int] = {}
    for v in succ:
        chi[root(v)] = chi.get(root(v), 0) + 1
    for u, w in owner:
        if u < w:
            chi[root(u)] -= 1
    for t in tops:
        chi[root(t[0])] += 1
    genera = tuple((2 - chi[r]) // 2 for r in sorted(chi))
    V, E, F = len(succ), len(owner) // 2, len(tops)
    report = SurfaceReport(V, E, F, V - E + F, len(chi), genera)
    if sphere and not report.is_sphere:
        if report.components == 0:
            raise NotASphereError("closed surface: the complex is empty, not a sphere", genera)
        if report.components == 1:
            raise NotASphereError(
                f"closed surface of genus {genera[0]} (Euler characteristic {report.euler}), not a sphere "
                f"(V={V}, E={E}, F={F})",
                genera,
            )
        raise NotASphereError(
            f"closed surface of {report.components} components of genera {genera!r}, not one sphere", genera
        )
    return report


def check_vertex_lists(table: Mapping[Vertex, tuple[tuple[Any, ...], ...]], name: str) -> None:
    """The per-vertex lists of a specialised 2-complex (§4) hold each triangle once per vertex, consistently.

    ``table`` maps each vertex a to its entries ``(b, c, datum)``, one per
    triangle ``(a, b, c)``; ``name`` ("2-complex", "ephemeral 2-complex") starts
    each message.  Raises RepresentationError for an empty list, a degenerate
    entry, or a triangle not held exactly once, with the same datum, under each
    of its other two vertices; OrientationError for a triangle held twice or in
    both orientations.  O(Σ δ²) for lists of length δ (about 6).
    """
    for a, lst in table.items():
        if not lst:
            raise RepresentationError(f"{name}: vertex {a!r} is mapped to an empty list (it is in no triangle)")
        pairs: set[tuple[Vertex, Vertex]] = set()
        for b, c, x in lst:
            if len({a, b, c}) != 3:
                raise RepresentationError(f"{name}: the list of {a!r} holds {(b, c)!r}, a degenerate triangle")
            if (b, c) in pairs:
                raise OrientationError(f"{name}: triangle {(a, b, c)!r} is held twice in the list of {a!r}")
            if (c, b) in pairs:
                raise OrientationError(f"{name}: triangle {(a, b, c)!r} is held in both orientations ({(a, c, b)!r} too)")
            pairs.add((b, c))
            for key, p, q in ((b, c, a), (c, a, b)):
                copies = [e for e in table.get(key, ()) if e[0] == p and e[1] == q]
                if len(copies) != 1:
                    raise RepresentationError(
                        f"{name}: triangle {(a, b, c)!r} is in the list of {a!r} but "
                        f"{len(copies)} times in the list of {key!r} (as {(p, q)!r})"
                    )
                if not same_datum(copies[0][2], x):
                    raise RepresentationError(f"{name}: triangle {(a, b, c)!r} carries different data under {a!r} and {key!r}")
