"""The laws and the checks reject deliberately broken 2-complexes (tests/broken_complexes.py),
each under the right name, while the correct 2-complex passes the same scenario."""

from __future__ import annotations

from typing import Any

import pytest

from broken_complexes import OrientationBlindFind, StaleRem, correct, mutating_add
from complex_helpers import build, fresh, tetrahedron
from persistri.impl.complex.checks import check_complex
from persistri.impl.complex.errors import RepresentationError
from persistri.impl.maps.assoc_list import assoc_list
from persistri.spec import simpcomp_laws as laws
from persistri.spec.simpcomp_laws import oriented_key


def tetra(C: Any) -> tuple[Any, dict[Any, Any], list[Any]]:
    k, tris = tetrahedron()
    vs = fresh(k)
    c = build(C, vs, tris)
    model = {oriented_key(C.Simplex, tuple(vs[j] for j in t)): i for i, t in enumerate(tris)}
    return c, model, vs


def test_orientation_blind_find_is_rejected() -> None:
    C = OrientationBlindFind(assoc_list)
    c, model, _ = tetra(C)
    t = next(iter(C.simplices(c, 2)))
    with pytest.raises(laws.LawViolation) as info:
        laws.law_find(C, c, 2, model, t[:2])
    assert info.value.law == "find"
    with pytest.raises(laws.LawViolation, match="neighbour"):
        laws.law_neighbour(C, c, 2)
    good = correct()
    c, model, _ = tetra(good)
    for t in good.simplices(c, 2):
        laws.law_find(good, c, 2, model, t[:2])
    laws.law_neighbour(good, c, 2)


def test_stale_rem_is_rejected() -> None:
    for C, broken in ((StaleRem(assoc_list), True), (correct(), False)):
        a, b, c_ = fresh(3)
        c0 = C.new(2)
        c1, m1 = laws.law_add(C, c0, 2, {}, (a, b, c_), "x")
        if broken:
            with pytest.raises(laws.LawViolation) as info:
                laws.law_rem(C, c1, 2, m1, (a, b, c_))
            assert info.value.law == "rem"
            with pytest.raises(RepresentationError, match="in the list of"):
                check_complex(C.rem(c1, (a, b, c_)))
        else:
            c2, _ = laws.law_rem(C, c1, 2, m1, (a, b, c_))
            check_complex(c2)


def test_mutating_add_is_rejected() -> None:
    C = mutating_add()
    a, b, c_, d = fresh(4)
    c0 = C.new(2)
    c1, m1 = laws.law_add(C, c0, 2, {}, (a, b, c_), 1, recheck=False)
    with pytest.raises(laws.LawViolation) as info:
        laws.law_add(C, c1, 2, m1, (a, c_, d), 2)
    assert info.value.law == "persistence"
    good = correct()
    c0 = good.new(2)
    c1, m1 = laws.law_add(good, c0, 2, {}, (a, b, c_), 1)
    laws.law_add(good, c1, 2, m1, (a, c_, d), 2)
