"""Closed surfaces on the 2-complex: platonic solids, random convex polytopes, a torus; the
neighbour law, walking a surface through ``find``, every version kept, and closed 3- and 4-manifolds
(the boundaries of a 4- and a 5-simplex) on the functor."""

from __future__ import annotations

from itertools import combinations
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from complex_helpers import (
    STRUCTURE_IDS,
    STRUCTURES,
    Make,
    build,
    fresh,
    icosahedron,
    octahedron,
    random_polytope,
    tetrahedron,
    torus,
)
from persistri.impl.complex.checks import SurfaceReport, check_closed_surface, check_complex
from persistri.impl.complex.errors import DimensionError, EdgeError, NotASphereError, VertexLinkError
from persistri.impl.complex.simplex import canonical, tuple_simplex
from persistri.spec import simpcomp_laws as laws

structures = pytest.mark.parametrize("make", [m for _, m in STRUCTURES], ids=STRUCTURE_IDS)
SOLIDS = {"tetrahedron": tetrahedron, "octahedron": octahedron, "icosahedron": icosahedron}


def walk(C: Any, c: Any) -> set[tuple[Any, ...]]:
    """Every triangle reachable from the first across edges, by the neighbour law ``find(c, flip(e))``."""
    start = C.simplices(c, 2)[0]
    seen = {canonical(start)}
    todo = [start]
    while todo:
        t = todo.pop()
        for e in tuple_simplex.faces(t):
            (u,) = C.find(c, tuple_simplex.flip(e))
            if canonical(u) not in seen:
                seen.add(canonical(u))
                todo.append(u)
    return seen


@structures
@pytest.mark.parametrize("solid", list(SOLIDS))
def test_platonic_solids_are_spheres(make: Make, solid: str) -> None:
    C = make(2)
    k, tris = SOLIDS[solid]()
    vs = fresh(k)
    versions = [C.new(2)]
    for i, t in enumerate(tris):
        versions.append(C.add(versions[-1], tuple(vs[j] for j in t), i))
    c = versions[-1]
    report = check_closed_surface(c)
    F = len(tris)
    assert report == SurfaceReport(k, 3 * F // 2, F, 2, 1, (0,)) and report.is_sphere
    laws.law_neighbour(C, c, 2)
    assert len(walk(C, c)) == F
    # every earlier version is still the partial surface it was
    for i, v in enumerate(versions):
        assert sorted(x for _, x in C.items(v)) == list(range(i))
        assert len(C.simplices(v, 2)) == i
        check_complex(v)
    with pytest.raises(EdgeError, match="boundary"):
        check_closed_surface(versions[-2])


@settings(max_examples=max(5, settings.default.max_examples // 4))
@given(k=st.integers(5, 60), seed=st.integers(0, 2**32 - 1))
def test_random_convex_polytopes_are_spheres(k: int, seed: int) -> None:
    make = dict(STRUCTURES).get("red_black", STRUCTURES[0][1])
    C = make(2)
    k, tris = random_polytope(k, seed)
    c = build(C, fresh(k), tris)
    assert check_closed_surface(c).is_sphere
    laws.law_neighbour(C, c, 2)
    assert len(walk(C, c)) == len(tris)
    # remove the faces one by one: the full sphere stays a sphere, each version stays a complex
    d = c
    for t in C.simplices(c, 2)[: len(tris) // 2]:
        d = C.rem(d, t)
    check_complex(d)
    assert check_closed_surface(c).is_sphere


@structures
def test_torus_reports_genus_one(make: Make) -> None:
    C = make(2)
    k, tris = torus(4, 5)
    c = build(C, fresh(k), tris)
    report = check_closed_surface(c, sphere=False)
    assert report.genera == (1,) and report.euler == 0 and report.faces == 40 and report.edges == 60
    with pytest.raises(NotASphereError, match="genus 1") as info:
        check_closed_surface(c)
    assert info.value.genera == (1,)
    laws.law_neighbour(C, c, 2)


def test_two_spheres_are_two_components() -> None:
    C = STRUCTURES[0][1](2)
    k, tris = tetrahedron()
    vs = fresh(2 * k)
    c = build(C, vs, tris + [tuple(j + k for j in t) for t in tris])
    report = check_closed_surface(c, sphere=False)
    assert report.components == 2 and report.genera == (0, 0) and report.euler == 4
    with pytest.raises(NotASphereError, match="2 components"):
        check_closed_surface(c)
    with pytest.raises(NotASphereError, match="empty"):
        check_closed_surface(C.new(2))


def test_broken_surfaces_are_reported() -> None:
    C = STRUCTURES[0][1](2)
    k, tris = tetrahedron()
    vs = fresh(2 * k - 1)
    # a face turned over: two triangles hold one oriented edge
    a, b, c_ = tris[0]
    flipped = build(C, vs, [(a, c_, b)] + tris[1:])
    with pytest.raises(EdgeError, match="lies in two triangles"):
        check_closed_surface(flipped)
    # two tetrahedra sharing one vertex: its link is two cycles
    second = [tuple(0 if j == 0 else j + k - 1 for j in t) for t in tris]
    bowtie = build(C, vs, tris + second)
    with pytest.raises(VertexLinkError, match="link of v0 is not one cycle"):
        check_closed_surface(bowtie)
    with pytest.raises(DimensionError):
        check_closed_surface(STRUCTURES[0][1](3).new(3))


@structures
@pytest.mark.parametrize("n", [2, 3, 4])
def test_boundary_of_a_simplex_is_closed(make: Make, n: int) -> None:
    """The n+1 induced faces of an (n+1)-simplex form a closed, consistently oriented n-complex."""
    C = make(n)
    vs = tuple(fresh(n + 2))
    faces = tuple_simplex.faces(vs)
    c = C.new(n)
    for i, f in enumerate(faces):
        c = C.add(c, f, i)
    check_complex(c)
    laws.law_neighbour(C, c, n)
    for f in faces:
        for e in tuple_simplex.faces(f):
            assert len(C.find(c, tuple_simplex.flip(e))) == 1
    assert len(C.simplices(c, n - 1)) == len(list(combinations(vs, n)))
