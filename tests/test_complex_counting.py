"""Counting through Stats: dictionary operations, key comparisons (tree nodes or cells visited by
the map plus list entries visited by the complex), faces created and deleted — computed here
independently from the backend's ``search_cost`` and the lists, and compared exactly."""

from __future__ import annotations

from typing import Any

import pytest

from complex_helpers import BACKEND_NAMES, build, fresh, icosahedron, tetrahedron
from persistri.impl.complex import complex_structure
from persistri.impl.complex.checks import check_closed_surface
from persistri.impl.maps import backend
from persistri.impl.stats import Stats

COSTED = [name for name in BACKEND_NAMES if hasattr(backend(name), "search_cost")]


def cost(B: Any, m: Any, k: Any) -> int:
    return int(B.search_cost(m, k))


@pytest.mark.parametrize("name", COSTED)
def test_two_complex_counts_what_the_paper_counts(name: str) -> None:
    B = backend(name)
    st = Stats()
    C = complex_structure(2, B, stats=st)
    k, tris = icosahedron()
    vs = fresh(k)
    c = build(C, vs, tris)
    assert st.faces_created == len(tris) and st.dict_ops == 3 * len(tris) and st.faces_deleted == 0

    t = C.simplices(c, 2)[5]
    a, b, cc = t
    rep = c.rep
    lst = B.lookup(rep, a)
    pos = next(i for i, e in enumerate(lst) if e[0] == b and e[1] == cc)

    st.reset()
    assert len(C.find(c, (a, b))) == 1
    assert st.dict_ops == 1 and st.key_comparisons == cost(B, rep, a) + len(lst)

    st.reset()
    assert C.data(c, t) is not None
    assert st.dict_ops == 1 and st.key_comparisons == cost(B, rep, a) + pos + 1

    st.reset()
    assert len(C.findi(c, (a, b))) == 1
    assert st.dict_ops == 1 and st.key_comparisons == cost(B, rep, a) + len(lst)

    # rem: three updates (the first also finds the triangle), each costing its search, plus the entries visited
    st.reset()
    d = C.rem(c, t)
    r1 = B.insert(rep, a, lst[:pos] + lst[pos + 1 :])
    lb = B.lookup(r1, b)
    pb = next(i for i, e in enumerate(lb) if e[0] == cc and e[1] == a)
    r2 = B.insert(r1, b, lb[:pb] + lb[pb + 1 :])
    lc = B.lookup(r2, cc)
    pc = next(i for i, e in enumerate(lc) if e[0] == a and e[1] == b)
    expected = cost(B, rep, a) + pos + 1 + cost(B, r1, b) + pb + 1 + cost(B, r2, cc) + pc + 1
    assert st.dict_ops == 3 and st.faces_deleted == 1
    assert st.key_comparisons == expected

    # add it back: three insertWith, the first scanning a's list for either orientation
    st.reset()
    e = C.add(d, t, "again")
    rd = d.rep
    la = B.lookup(rd, a)
    r1 = B.insertWith(lambda o, n: o + n, rd, a, ((b, cc, 0),))
    r2 = B.insertWith(lambda o, n: o + n, r1, b, ((cc, a, 0),))
    expected = cost(B, rd, a) + len(la) + cost(B, r1, b) + cost(B, r2, cc)
    assert st.dict_ops == 3 and st.faces_created == 1 and st.key_comparisons == expected
    assert C.data(e, (b, cc, a)) == ("again",)


def test_counting_changes_no_result_and_is_free_when_detached() -> None:
    k, tris = icosahedron()
    vs = fresh(k)
    st = Stats()
    counted_C = complex_structure(2, "red_black", stats=st)
    plain_C = complex_structure(2, "red_black")
    assert plain_C._m is plain_C.family.backend  # no wrapper: the uncounted fast path
    c1, c2 = build(counted_C, vs, tris), build(plain_C, vs, tris)
    assert counted_C.items(c1) == plain_C.items(c2)
    for t, _ in plain_C.items(c2):
        assert counted_C.find(c1, t[:2]) == plain_C.find(c2, t[:2])
    assert st.key_comparisons > 0 and st.dict_ops > 0
    before = st.as_dict()
    check_closed_surface(c1)  # checks read through the uncounted structure
    assert st.as_dict() == before


def test_emptied_vertex_costs_one_remove_more() -> None:
    st = Stats()
    C = complex_structure(2, "assoc_list", stats=st)
    a, b, c_ = fresh(3)
    c = C.add(C.new(2), (a, b, c_), 0)
    st.reset()
    d = C.rem(c, (a, b, c_))
    # (insertWith, which finds the list emptied, then remove) for a, for b and for c
    assert st.dict_ops == 6 and C.isEmpty(d)


def test_functor_counts_its_inner_complexes() -> None:
    st = Stats()
    C = complex_structure(3, "assoc_list", stats=st)
    vs = fresh(5)
    c = C.add(C.new(3), tuple(vs[:4]), 0)
    # 4 vertices × (find + insert) outside, 4 × (2-complex add: 3 insertWith) inside
    assert st.dict_ops == 4 * 2 + 4 * 3 and st.faces_created == 1
    st.reset()
    assert C.data(c, tuple(vs[:4])) == (0,)
    assert st.dict_ops == 2  # a lookup outside, one inside
    st.reset()
    assert len(C.find(c, tuple(vs[1:4]))) == 1
    assert st.dict_ops == 2 and st.key_comparisons > 0
    st.reset()
    C.rem(c, tuple(vs[:4]))
    assert st.faces_deleted == 1 and st.dict_ops > 0


def test_one_complex_counts() -> None:
    st = Stats()
    C = complex_structure(1, "assoc_list", stats=st)
    k, tris = tetrahedron()
    vs = fresh(k)
    c = C.new(1)
    for i, (p, q, _) in enumerate(tris):
        c = C.add(c, (vs[p], vs[q]), i)
    assert st.dict_ops == 2 * len(tris)
    st.reset()
    u = vs[tris[0][0]]
    incident = C.find(c, (u,))
    assert st.dict_ops == 1 and st.key_comparisons == cost(backend("assoc_list"), c.rep, u) + len(incident)
