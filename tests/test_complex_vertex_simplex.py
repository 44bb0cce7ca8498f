"""VERTEX and SIMPLEX: the laws of spec/vertex_laws.py and spec/simplex_laws.py on int_vertex and
tuple_simplex, the canonical form, and the bad-input exceptions of vertices and simplices."""

from __future__ import annotations

import copy
import pickle
from itertools import permutations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from complex_helpers import fresh
from persistri.impl.complex.errors import (
    DimensionError,
    ForeignVertexError,
    NotAVertexError,
    RepeatedVertexError,
)
from persistri.impl.complex.simplex import canonical, check_simplex, parity, same_orientation, tuple_simplex
from persistri.impl.complex.vertex import Vertex, VertexState, int_vertex
from persistri.spec import simplex_laws, vertex_laws
from persistri.spec.law import LawViolation
from persistri.spec.order import Order

S = tuple_simplex


# -- VERTEX ------------------------------------------------------------------------------


@given(st.lists(st.integers(), min_size=1, max_size=8))
def test_vertex_laws(points: list[int]) -> None:
    s0 = VertexState.initial()
    made = vertex_laws.law_new_fresh(int_vertex, s0, points)
    vertex_laws.law_compare_total(int_vertex, made)
    vertex_laws.law_new_loc(int_vertex, s0, points[0])
    vertex_laws.law_new_deterministic(int_vertex, s0, points[0], points[-1])


def test_new_is_purely_functional() -> None:
    s0 = VertexState.initial()
    s1, a = int_vertex.new(s0, "p")
    s1b, a2 = int_vertex.new(s0, "p")
    assert a == a2 and a.lineage is a2.lineage and s1 == s1b
    assert s0.next_label == 0 and s1.next_label == 1  # s0 untouched
    s2, b = int_vertex.new(s1, "q")
    assert b == 1 and b.point == "q" and int_vertex.loc(b) == "q"
    assert int_vertex.compare(a, b) is Order.LESS and int_vertex.compare(b, a) is Order.GREATER
    # new_many labels consecutively and agrees with repeated new
    s3, vs = int_vertex.new_many(s0, ["p", "q", "r"])
    assert vs == [0, 1, 2] and s3.next_label == 3 and [v.point for v in vs] == ["p", "q", "r"]


def test_vertex_is_an_immutable_int_with_point_and_lineage() -> None:
    a, b = fresh(2, [(0, 0), (1, 1)])
    assert isinstance(a, int) and a < b and hash(a) == hash(0)
    with pytest.raises(AttributeError):
        a.point = (5, 5)  # type: ignore[misc]  # the point of the test: immutable
    with pytest.raises(AttributeError):
        del a.lineage  # type: ignore[misc]
    assert repr(a) == "v0" and a.label == 0
    c = copy.deepcopy(a)
    assert c == a and c.lineage is a.lineage and c.point == a.point
    d = pickle.loads(pickle.dumps([a, b]))
    assert d == [a, b] and d[0].lineage is d[1].lineage and d[1].point == (1, 1)


def test_vertices_have_no_dict_and_keep_their_points() -> None:
    """A vertex is as small as an int: its point is None, its own label, or in its lineage's table; a second
    point for one label (two branches of one state) gets a vertex of its own, and no point ever changes."""
    s0 = VertexState.initial()
    lin = s0.lineage
    none, own, table = Vertex(0, None, lin), Vertex(1, 1, lin), Vertex(2, ("p", 2), lin)
    for v, point in ((none, None), (own, 1), (table, ("p", 2))):
        assert not hasattr(v, "__dict__") and v.point == point and v.lineage is lin and isinstance(v, Vertex)
        assert type(v) is not Vertex and type(v).__name__ == "Vertex"
        c = copy.deepcopy(v)
        assert c == v and c.point == v.point and c.lineage is lin
        d = pickle.loads(pickle.dumps(v))
        assert d == v and d.point == v.point and d.lineage is not lin
    _, a = int_vertex.new(s0, [1.0, 2.0])
    _, b = int_vertex.new(s0, [3.0, 4.0])  # a fork: the same label, another point
    _, a2 = int_vertex.new(s0, a.point)  # the same point object again: the same vertex
    assert a == b == a2 == 0 and a.point == [1.0, 2.0] and b.point == [3.0, 4.0] and a2.point is a.point
    assert hasattr(b, "__dict__") and not hasattr(a2, "__dict__") and a.lineage is b.lineage is lin
    with pytest.raises(AttributeError):
        b.point = (0, 0)  # type: ignore[misc]  # the point of the test: immutable
    assert copy.deepcopy(b).point == [3.0, 4.0] and copy.copy(table) == table
    # A pickled complex of many vertices of one lineage comes back with one lineage.
    e = pickle.loads(pickle.dumps([none, own, table, a, b]))
    assert [v.point for v in e] == [None, 1, ("p", 2), [1.0, 2.0], [3.0, 4.0]] and len({id(v.lineage) for v in e}) == 1


def test_vertex_bad_input() -> None:
    with pytest.raises(TypeError, match="VertexState"):
        int_vertex.new("not a state", 1)  # type: ignore[arg-type]
    with pytest.raises(NotAVertexError):
        int_vertex.loc(3)  # type: ignore[arg-type]


def test_vertex_laws_catch_a_broken_vertex_structure() -> None:
    class Forgetful:
        """Every new vertex gets label 0: not fresh."""

        def compare(self, a: Vertex, b: Vertex) -> Order:
            return int_vertex.compare(a, b)

        def new(self, s: VertexState, p: object) -> tuple[VertexState, Vertex]:
            return s, Vertex(0, p, s.lineage)

        def loc(self, v: Vertex) -> object:
            return v.point

    with pytest.raises(LawViolation, match="new_fresh"):
        vertex_laws.law_new_fresh(Forgetful(), VertexState.initial(), [1, 2])


# -- SIMPLEX -----------------------------------------------------------------------------


@st.composite
def simplices(draw: st.DrawFn, min_dim: int = 0, max_dim: int = 4) -> tuple[Vertex, ...]:
    n = draw(st.integers(min_dim, max_dim))
    vs = fresh(max_dim + 3)
    return tuple(draw(st.permutations(vs))[: n + 1])


@given(simplices())
def test_simplex_laws(s: tuple[Vertex, ...]) -> None:
    simplex_laws.check_simplex_laws(S, s)


@given(st.data())
def test_compare_is_a_total_order(data: st.DataObject) -> None:
    vs = fresh(5)
    ss = [tuple(data.draw(st.permutations(vs))[: data.draw(st.integers(1, 4))]) for _ in range(5)]
    simplex_laws.law_compare_order(S, ss)


def test_faces_of_a_triangle_and_a_tetrahedron() -> None:
    a, b, c, d = fresh(4)
    assert S.faces((a, b, c)) == [(b, c), (c, a), (a, b)]
    assert S.faces((a, b, c, d)) == [(b, c, d), (a, d, c), (a, b, d), (a, c, b)]
    assert S.faces((a, b)) == [(b,), (a,)]
    assert S.flip((a, b, c)) == (a, c, b) and S.flip((a, b)) == (b, a) and S.flip((a,)) == (a,)
    assert S.down((a, b, c)) == (a, (b, c)) and S.join(a, (b, c)) == (a, b, c)
    assert S.down((a,)) == (a, ()) and S.join(a, ()) == (a,)
    # join(t[i], faces(t)[i]) is t's orientation for every i from dimension 2 (the functor relies on it);
    # an edge loses it, since a vertex has one orientation: hence the special 1-complex's flag.
    for t in [(a, b, c), (a, b, c, d)]:
        for v, f in zip(t, S.faces(t)):
            assert S.compare(S.join(v, f), t) is Order.EQUAL
    assert S.compare(S.join(b, S.faces((a, b))[1]), (a, b)) is Order.GREATER


@given(simplices(min_dim=1))
def test_canonical_form(s: tuple[Vertex, ...]) -> None:
    k = canonical(s)
    assert sorted(k) == sorted(s)
    assert same_orientation(k, s) and canonical(k) == k
    assert canonical(S.flip(s)) != k
    even = sum(1 for p in permutations(range(len(s))) if parity(p) == 0)
    assert len({canonical(tuple(s[i] for i in p)) for p in permutations(range(len(s)))}) == (2 if len(s) >= 2 else 1)
    assert even * 2 == len(list(permutations(range(len(s)))))


def test_simplex_laws_catch_broken_simplex_structures() -> None:
    class NoOrientation(type(S)):  # type: ignore[misc]  # a deliberately broken subclass
        """compare ignores orientation: both orientations EQUAL."""

        def compare(self, s: tuple[Vertex, ...], t: tuple[Vertex, ...]) -> Order:
            return super().compare(tuple(sorted(s)), tuple(sorted(t)))

    class BadFaces(type(S)):  # type: ignore[misc]
        """faces never flips: (a, b, c) gets (b, c), (a, c), (a, b)."""

        def faces(self, s: tuple[Vertex, ...]) -> list[tuple[Vertex, ...]]:
            return [s[:i] + s[i + 1 :] for i in range(len(s))]

    a, b, c = fresh(3)
    with pytest.raises(simplex_laws.LawViolation, match="compare_orientation"):
        simplex_laws.law_compare_orientation(NoOrientation(), (a, b, c))
    with pytest.raises(simplex_laws.LawViolation, match="flip"):
        simplex_laws.law_flip(NoOrientation(), (a, b, c))
    with pytest.raises(simplex_laws.LawViolation, match="faces_induced"):
        simplex_laws.law_faces_induced(BadFaces(), (a, b, c))


def test_simplex_bad_input() -> None:
    a, b = fresh(2)
    (x,) = fresh(1)
    with pytest.raises(RepeatedVertexError):
        S.simplex([a, b, a])
    with pytest.raises(RepeatedVertexError):
        S.join(a, (b, a))
    with pytest.raises(NotAVertexError):
        S.simplex([a, 7])  # type: ignore[list-item]
    with pytest.raises(ForeignVertexError):
        S.simplex([a, x])
    with pytest.raises(TypeError):
        S.faces(42)  # type: ignore[arg-type]
    with pytest.raises(DimensionError):
        S.down(())
    assert S.simplex([a, b]) == (a, b) and S.dim((a, b)) == 1 and S.vertices([a, b]) == (a, b)  # type: ignore[arg-type]
    assert check_simplex((a, b), "t", a.lineage) == ((a, b), a.lineage)
