"""The ephemeral baseline (impl/complex/ephemeral.py): the 2-complex's results over a mutable dict,
the same validation, stale old versions, and its place in the factories and the convex hull."""

from __future__ import annotations

from collections.abc import Callable
from itertools import combinations
from typing import Any

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from complex_helpers import build, fresh, icosahedron, torus
from persistri.impl.complex import complex_structure
from persistri.impl.complex.checks import check_closed_surface, check_complex
from persistri.impl.complex.ephemeral import EPHEMERAL, EphemeralTwoComplex
from persistri.impl.complex.errors import (
    AbsentSimplexError,
    DimensionError,
    DuplicateSimplexError,
    ForeignComplexError,
    ForeignVertexError,
    NotAVertexError,
    OppositeOrientationError,
    RepeatedVertexError,
    StaleVersionError,
)
from persistri.impl.complex.simpcomp import two_complex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.hull.api import convex_hull
from persistri.impl.hull.distributions import on_sphere
from persistri.impl.maps.red_black import red_black
from persistri.impl.stats import Stats
from persistri.spec import simpcomp_laws as laws
from persistri.spec.simpcomp_laws import oriented_key

E = EphemeralTwoComplex[Any]()
P = TwoComplex[Any](red_black)


def observe(C: Any, c: Any, probes: list[Any]) -> tuple[Any, ...]:
    """Everything a 2-complex says about ``c``: items, every query on the probes, the faces."""
    return (
        sorted(C.items(c)),
        C.isEmpty(c),
        sorted(C.vertices(c)),
        sorted(C.simplices(c, 1)),
        [C.data(c, t) for t in probes],
        [sorted(C.find(c, t[:2])) for t in probes],
        [sorted(C.findi(c, t[1:])) for t in probes],
        [sorted(C.grep(c, 2, t[:1])) for t in probes],
        [sorted(C.grep(c, 1, t[:1])) for t in probes],
    )


@st.composite
def programs(draw: st.DrawFn) -> list[tuple[str, int]]:
    return draw(st.lists(st.tuples(st.sampled_from(["add", "add_flipped", "rem", "update"]), st.integers(0, 200)), max_size=40))


@given(programs())
def test_agrees_with_the_persistent_two_complex_on_linear_histories(program: list[tuple[str, int]]) -> None:
    vs = fresh(6)
    tris = list(combinations(vs, 3))
    probes = tris + [(t[0], t[2], t[1]) for t in tris]
    ce, cp = E.new(2), P.new(2)
    model: dict[Any, Any] = {}
    for op, i in program:
        t = probes[i % len(probes)]
        if op.startswith("add"):
            if op == "add_flipped":
                t = (t[0], t[2], t[1])
            outcome = []
            for C, c in ((E, ce), (P, cp)):
                try:
                    outcome.append(C.add(c, t, i))
                except ValueError as exc:
                    outcome.append(type(exc))
            if isinstance(outcome[0], type):
                assert outcome[0] is outcome[1], f"ephemeral raised {outcome[0]}, persistent gave {outcome[1]}"
                continue
            ce, cp = outcome
            model[oriented_key(E.Simplex, t)] = i
        elif op == "rem" and model:
            key = sorted(model)[i % len(model)]
            t = laws.representative(E.Simplex, key)
            ce, cp = E.rem(ce, t), P.rem(cp, t)
            del model[key]
        elif op == "update" and model:
            key = sorted(model)[i % len(model)]
            t = laws.representative(E.Simplex, key)
            ce, cp = E.update(ce, t, lambda x: (x, i)), P.update(cp, t, lambda x: (x, i))
            model[key] = (model[key], i)
        assert observe(E, ce, probes) == observe(P, cp, probes)
        laws.law_agrees(E, ce, 2, model)
        check_complex(ce)


def test_old_versions_are_stale() -> None:
    a, b, c, d = fresh(4)
    c0 = E.new(2)
    c1 = E.add(c0, (a, b, c), "x")
    c2 = E.add(c1, (a, c, d), "y")
    stale_calls: list[Callable[[Any], object]] = [
        lambda k: E.data(k, (a, b, c)),
        lambda k: E.find(k, (a, b)),
        lambda k: E.findi(k, (a, b)),
        lambda k: E.add(k, (b, d, c), "z"),
        lambda k: E.rem(k, (a, b, c)),
        lambda k: E.update(k, (a, b, c), lambda x: x),
        lambda k: E.items(k),
        lambda k: E.isEmpty(k),
        lambda k: E.vertices(k),
        lambda k: E.simplices(k, 1),
        lambda k: E.grep(k, 2, (a,)),
        lambda k: E.check(k),
    ]
    for old in (c0, c1):
        for call in stale_calls:
            with pytest.raises(StaleVersionError, match="stale"):
                call(old)
    # The newest version is intact after all those refusals.
    assert sorted(E.items(c2)) == [((a, b, c), "x"), ((a, c, d), "y")]
    # A fresh complex has a table of its own: the other one stays current.
    other = E.add(E.new(2), (a, b, c), 1)
    assert E.data(c2, (b, c, a)) == ("x",) and E.data(other, (a, b, c)) == (1,)


def test_bad_input_raises_like_the_persistent_complex_and_keeps_the_version_current() -> None:
    pool = fresh(6)
    (alien,) = fresh(1)
    a, b, c, d = pool[:4]
    results = {}
    for name, C in (("ephemeral", E), ("persistent", P)):
        k = C.add(C.add(C.new(2), (a, b, c), 0), (a, c, d), 1)
        cases: list[tuple[type[BaseException], Callable[[], object]]] = [
            (RepeatedVertexError, lambda: C.add(k, (a, a, b), 0)),
            (DimensionError, lambda: C.add(k, (a, b), 0)),
            (DimensionError, lambda: C.find(k, (a, b, c))),
            (DuplicateSimplexError, lambda: C.add(k, (b, c, a), 0)),
            (OppositeOrientationError, lambda: C.add(k, (a, c, b), 0)),
            (AbsentSimplexError, lambda: C.rem(k, (a, c, b))),
            (AbsentSimplexError, lambda: C.rem(k, (pool[4], pool[5], a))),
            (AbsentSimplexError, lambda: C.update(k, (b, d, c), lambda x: x)),
            (ForeignVertexError, lambda: C.add(k, (alien, b, c), 0)),
            (NotAVertexError, lambda: C.add(k, (0, 1, 2), 0)),
            (ForeignComplexError, lambda: C.add("no complex", (a, b, c), 0)),
        ]
        for exc, call in cases:
            with pytest.raises(exc):
                call()
        with pytest.raises(ZeroDivisionError):  # update's function raising changes nothing either
            C.update(k, (a, b, c), lambda x: 1 // 0)
        results[name] = sorted(C.items(k))
        if C is E:
            check_complex(k)  # still the current version
    assert results["ephemeral"] == results["persistent"] == [((a, b, c), 0), ((a, c, d), 1)]


def test_values_of_other_structures_are_refused() -> None:
    a, b, c = fresh(3)
    with pytest.raises(ForeignComplexError):
        E.add(P.new(2), (a, b, c), 0)
    with pytest.raises(ForeignComplexError):
        P.add(E.new(2), (a, b, c), 0)


@pytest.mark.parametrize("surface", [icosahedron(), torus(4, 5)], ids=["icosahedron", "torus"])
def test_closed_surfaces_and_their_neighbours(surface: tuple[int, list[tuple[int, int, int]]]) -> None:
    k, tris = surface
    vs = fresh(k)
    c = build(E, vs, tris)
    report = check_closed_surface(c, sphere=False)
    assert report.faces == len(tris)
    laws.law_neighbour(E, c, 2)
    # Dismantle it; every intermediate version is the only valid one.
    for t in tris:
        c = E.rem(c, tuple(vs[j] for j in t))
    assert E.isEmpty(c) and list(E.vertices(c)) == []


def test_factories_select_it_by_name() -> None:
    assert isinstance(complex_structure(2, EPHEMERAL), EphemeralTwoComplex)
    assert isinstance(two_complex("ephemeral"), EphemeralTwoComplex)
    assert type(two_complex("red_black")) is TwoComplex
    for n in (1, 3):
        with pytest.raises(ValueError, match="2-complex only"):
            complex_structure(n, EPHEMERAL)
    with pytest.raises(ValueError, match="specialised"):
        complex_structure(2, EPHEMERAL, specialised=False)


def test_counts() -> None:
    st_ = Stats()
    C = EphemeralTwoComplex[Any](st_)
    a, b, c, d = fresh(4)
    k = C.add(C.add(C.new(2), (a, b, c), 0), (a, c, d), 1)
    assert (st_.faces_created, st_.dict_ops) == (2, 12)
    C.findi(k, (a, c))
    assert st_.dict_ops == 13 and st_.key_comparisons == 12 + 1 + 1 + 2  # 12 from adds (+1 entry scanned), the lookup, 2 entries
    C.rem(k, (a, b, c))
    assert st_.faces_deleted == 1
    # Counted and uncounted ephemeral structures share one family: their values are interchangeable.
    assert C.family == E.family


def test_convex_hull_on_the_ephemeral_complex() -> None:
    pts = on_sphere(300, seed=5)
    reference = convex_hull(pts, backend="red_black", seed=3)
    hull = convex_hull(pts, backend="ephemeral", seed=3, check=True)
    assert np.array_equal(hull.simplices, reference.simplices)
    assert isinstance(hull.structure, EphemeralTwoComplex)
    with pytest.raises(ValueError, match="history"):
        convex_hull(pts, backend="ephemeral", history=True)
