"""check_complex detects broken complexes: hand-corrupted representations of each kind
(the 1-complex, the 2-complex, the functor), mixed lineages, and structures whose
reports break conditions 1–3 of the paper's definition."""

from __future__ import annotations

from typing import Any

import pytest

from complex_helpers import build, fresh, tetrahedron
from persistri.impl.complex import Complex, TwoComplex, complex_structure
from persistri.impl.complex.checks import check_closed_surface, check_complex
from persistri.impl.complex.errors import (
    ClosureError,
    ForeignComplexError,
    LineageError,
    OrientationError,
    RepresentationError,
)
from persistri.impl.complex.vertex import VertexState, int_vertex
from persistri.impl.maps.assoc_list import assoc_list

M = assoc_list


def with_rep(c: Complex[Any], rep: Any) -> Complex[Any]:
    """``c`` with its representation replaced (how a buggy structure would leave it)."""
    return Complex(c.family, rep, c.lineage)


def tetra2() -> tuple[Any, Complex[Any], list[Any]]:
    C = complex_structure(2, M)
    k, tris = tetrahedron()
    vs = fresh(k)
    return C, build(C, vs, tris), vs


def test_two_complex_corruptions() -> None:
    C, c, vs = tetra2()
    check_closed_surface(c)
    rep = c.rep
    a = vs[0]
    lst = M.lookup(rep, a)
    # one entry dropped from one list: the triangle is missing under a
    with pytest.raises(RepresentationError, match=r"0 times in the list of v0"):
        check_complex(with_rep(c, M.insert(rep, a, lst[1:])))
    # a different datum under one vertex
    b, cc, x = lst[0]
    with pytest.raises(RepresentationError, match="different data"):
        check_complex(with_rep(c, M.insert(rep, a, ((b, cc, "other"),) + lst[1:])))
    # both orientations in one list
    with pytest.raises(OrientationError, match="both orientations"):
        check_complex(with_rep(c, M.insert(rep, a, lst + ((cc, b, x),))))
    # the same entry twice
    with pytest.raises(OrientationError, match="twice"):
        check_complex(with_rep(c, M.insert(rep, a, lst + (lst[0],))))
    # a vertex left with an empty list
    (extra,) = int_vertex.new_many(VertexState(a.lineage, 99), [None])[1]
    with pytest.raises(RepresentationError, match="empty list"):
        check_complex(with_rep(c, M.insert(rep, extra, ())))
    # a degenerate entry
    with pytest.raises(RepresentationError, match="degenerate"):
        check_complex(with_rep(c, M.insert(rep, a, lst + ((a, b, 0),))))
    check_complex(c)  # the original is untouched by all of the above


def test_one_complex_corruptions() -> None:
    C = complex_structure(1, M)
    a, b, c_ = fresh(3)
    c = C.add(C.add(C.new(1), (a, b), 0), (b, c_), 1)
    check_complex(c)
    rep = c.rep
    with pytest.raises(RepresentationError, match="0 times in the list of v1"):
        check_complex(with_rep(c, M.insert(rep, b, M.lookup(rep, b)[1:])))
    with pytest.raises(OrientationError, match="both orientations"):
        check_complex(with_rep(c, M.insert(rep, a, M.lookup(rep, a) + ((b, False, 0),))))
    with pytest.raises(RepresentationError, match="loop"):
        check_complex(with_rep(c, M.insert(rep, a, M.lookup(rep, a) + ((a, True, 0),))))


def test_functor_corruptions() -> None:
    C = complex_structure(3, M)
    vs = fresh(5)
    c = C.new(3)
    c = C.add(c, tuple(vs[:4]), "t")
    c = C.add(c, (vs[0], vs[2], vs[1], vs[4]), "u")
    check_complex(c)
    rep = c.rep
    inner = M.lookup(rep, vs[3])
    sub = C.sub  # type: ignore[attr-defined]
    (face, _), *_ = sub.items(Complex(sub.family, inner, c.lineage))
    broken_inner = sub._rem(inner, face)
    with pytest.raises(RepresentationError, match="missing under v3"):
        check_complex(with_rep(c, M.insert(rep, vs[3], broken_inner) if not sub._is_empty(broken_inner)
                               else M.remove(rep, vs[3])[0]))
    (extra,) = int_vertex.new_many(VertexState(vs[0].lineage, 99), [None])[1]
    with pytest.raises(RepresentationError, match="v99 is mapped to an empty inner complex"):
        check_complex(with_rep(c, M.insert(rep, extra, sub._empty())))


def test_mixed_lineages_and_branches() -> None:
    C = complex_structure(2, M)
    s0 = VertexState.initial()
    s1, a = int_vertex.new(s0, "a")
    s2, b = int_vertex.new(s1, "b")
    s3, c_ = int_vertex.new(s2, "c")
    _, d = int_vertex.new(s3, "d")
    _, b_other = int_vertex.new(s1, "another b")  # a branch from s1: label 1 again
    c = C.add(C.add(C.new(2), (a, b, c_), 0), (a, c_, d), 1)
    check_complex(c)
    mixed = C.add(c, (a, d, b_other), 2)  # accepted: same lineage, and labels are what maps compare
    with pytest.raises(LineageError, match="label 1 names two vertices"):
        check_complex(mixed)
    (alien,) = fresh(1)
    rep = M.insert(c.rep, a, M.lookup(c.rep, a))
    forged = Complex(c.family, M.insert(rep, alien, ((b, c_, 9),)), c.lineage)
    with pytest.raises((LineageError, RepresentationError)):
        check_complex(forged)
    with pytest.raises(ForeignComplexError):
        check_complex("nope")  # type: ignore[arg-type]


class LossyReports(TwoComplex[Any]):
    """A 2-complex whose ``simplices``/``vertices`` reports break conditions 1–3 as chosen."""

    def __init__(self, fault: str) -> None:
        super().__init__(assoc_list)
        self.fault = fault

    def vertices(self, c: Complex[Any], /) -> list[Any]:
        vs = super().vertices(c)
        return vs + [fresh(9)[8]] if self.fault == "extra_vertex" else vs

    def simplices(self, c: Complex[Any], d: int, /) -> list[Any]:
        out = super().simplices(c, d)
        if d == 1 and self.fault == "missing_edge":
            return out[1:]
        if d == 1 and self.fault == "stray_edge":
            return out + [tuple(fresh(9)[7:9])]
        if d == 1 and self.fault == "repeated_edge":
            return out + out[:1]
        return out


@pytest.mark.parametrize(
    ("fault", "message"),
    [
        ("missing_edge", "condition 2"),
        ("stray_edge", "condition 3"),
        ("extra_vertex", "condition 1"),
        ("repeated_edge", "more than once"),
    ],
)
def test_closure_conditions(fault: str, message: str) -> None:
    C = LossyReports(fault)
    k, tris = tetrahedron()
    c = build(C, fresh(k), tris)
    with pytest.raises(ClosureError, match=message):
        check_complex(c)
