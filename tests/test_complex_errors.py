"""Bad input at the complex boundary: each case raises its documented exception, in every
dimension and on every structure, and the version passed in is untouched and still valid."""

from __future__ import annotations

from collections.abc import Callable
from itertools import combinations
from typing import Any

import pytest

from complex_helpers import STRUCTURE_IDS, STRUCTURES, Make, fresh
from persistri.impl.complex import complex_structure
from persistri.impl.complex.checks import check_complex
from persistri.impl.complex.errors import (
    AbsentSimplexError,
    DimensionError,
    DuplicateSimplexError,
    ForeignComplexError,
    ForeignVertexError,
    NotAVertexError,
    OppositeOrientationError,
    RepeatedVertexError,
    SimplexPresentError,
)
from persistri.impl.complex.simplex import tuple_simplex
from persistri.impl.maps.assoc_list import AssocListMap
from persistri.spec import simpcomp_laws as laws
from persistri.spec.simpcomp_laws import oriented_key

S = tuple_simplex


def setup(make: Make, n: int) -> tuple[Any, Any, dict[Any, Any], list[Any]]:
    C = make(n)
    pool = fresh(n + 3)
    c = C.new(n)
    model: dict[Any, Any] = {}
    for i, t in enumerate(list(combinations(pool, n + 1))[:4]):
        c = C.add(c, t, i)
        model[oriented_key(S, t)] = i
    return C, c, model, pool


@pytest.mark.parametrize("n", [1, 2, 3, 4])
@pytest.mark.parametrize("make", [m for _, m in STRUCTURES], ids=STRUCTURE_IDS)
def test_bad_input_raises_and_leaves_the_version_intact(make: Make, n: int) -> None:
    C, c, model, pool = setup(make, n)
    held = next(iter(C.simplices(c, n)))
    absent = next(t for t in combinations(pool, n + 1) if oriented_key(S, t) not in model
                  and oriented_key(S, S.flip(t)) not in model)
    (alien,) = fresh(1)  # same label as pool[0], another lineage
    repeated = (pool[0],) * (n + 1)
    foreign = (alien,) + tuple(pool[1 : n + 1])
    plain_ints = tuple(range(n + 1))
    cases: list[tuple[type[BaseException], Callable[[], object]]] = [
        (RepeatedVertexError, lambda: C.add(c, repeated, 0)),
        (RepeatedVertexError, lambda: C.rem(c, repeated)),
        (RepeatedVertexError, lambda: C.data(c, repeated)),
        (RepeatedVertexError, lambda: C.update(c, repeated, lambda x: x)),
        (DimensionError, lambda: C.add(c, held[:n], 0)),
        (DimensionError, lambda: C.add(c, tuple(pool[: n + 2]), 0)),
        (DimensionError, lambda: C.find(c, held)),
        (DimensionError, lambda: C.data(c, held[:n])),
        (DimensionError, lambda: C.grep(c, n + 1, held)),
        (DimensionError, lambda: C.simplices(c, -1)),
        (DimensionError, lambda: C.new(n + 1)) if not hasattr(C, "structure") else (DimensionError, lambda: C.new(0)),
        (DuplicateSimplexError, lambda: C.add(c, held, 0)),
        (OppositeOrientationError, lambda: C.add(c, S.flip(held), 0)),
        (AbsentSimplexError, lambda: C.rem(c, absent)),
        (AbsentSimplexError, lambda: C.rem(c, S.flip(held))),
        (AbsentSimplexError, lambda: C.update(c, absent, lambda x: x)),
        (ForeignVertexError, lambda: C.add(c, foreign, 0)),
        (ForeignVertexError, lambda: C.data(c, foreign)),
        (ForeignVertexError, lambda: C.find(c, foreign[:n])),
        (ForeignVertexError, lambda: C.grep(c, 0, foreign[:1])),
        (NotAVertexError, lambda: C.add(c, plain_ints, 0)),
        (NotAVertexError, lambda: C.find(c, plain_ints[:n])),
        (TypeError, lambda: C.add(c, 42, 0)),
        (ForeignComplexError, lambda: C.add("not a complex", held, 0)),
        (ForeignComplexError, lambda: C.isEmpty(object())),
        # a complex over another backend object: its maps would be unreadable here
        (ForeignComplexError, lambda: C.data(complex_structure(n, AssocListMap()).new(n), held)),
    ]
    if n >= 2:  # another even order of a held simplex is the same oriented simplex
        rotated = held[1:3] + held[:1] + held[3:]
        cases.append((DuplicateSimplexError, lambda: C.add(c, rotated, 0)))
    for expected, call in cases:
        with pytest.raises(expected) as info:
            call()
        assert isinstance(info.value, (ValueError, TypeError)), info.value
        assert str(info.value), f"{expected.__name__} without a message"
    laws.law_agrees(C, c, n, model, "after the refused calls")
    check_complex(c)


def test_exception_hierarchy() -> None:
    assert issubclass(DuplicateSimplexError, SimplexPresentError)
    assert issubclass(OppositeOrientationError, SimplexPresentError)
    for e in (RepeatedVertexError, ForeignVertexError, DimensionError, SimplexPresentError, AbsentSimplexError):
        assert issubclass(e, ValueError)
    for e in (NotAVertexError, ForeignComplexError):
        assert issubclass(e, TypeError)


def test_a_complex_adopts_the_lineage_of_its_first_simplex() -> None:
    C = complex_structure(2, "assoc_list")
    a, b, c_ = fresh(3)
    x, y, z = fresh(3)
    empty = C.new(2)
    one = C.add(empty, (a, b, c_), 0)
    other = C.add(empty, (x, y, z), 0)  # the empty complex has no lineage yet: either may start it
    assert one.lineage is a.lineage and other.lineage is x.lineage and empty.lineage is None
    with pytest.raises(ForeignVertexError):
        C.add(one, (x, y, z), 1)
    with pytest.raises(ForeignVertexError):
        C.add(empty, (a, y, z), 1)  # one simplex mixing two lineages
    # removing everything keeps the lineage: the complex stays in its family of vertices
    assert C.rem(one, (a, b, c_)).lineage is a.lineage


def test_values_of_counted_and_uncounted_structures_mix() -> None:
    from persistri.impl.stats import Stats

    plain = complex_structure(2, "assoc_list")
    counted = complex_structure(2, plain.family.backend, stats=Stats())
    a, b, c_ = fresh(3)
    c = plain.add(plain.new(2), (a, b, c_), 0)
    assert counted.data(c, (b, c_, a)) == (0,)
    with pytest.raises(ForeignComplexError, match="given to a structure"):
        complex_structure(2, "assoc_list", specialised=False).data(c, (a, b, c_))
