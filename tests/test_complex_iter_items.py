"""``iter_items``: the simplices of ``items``, one at a time and in the same order, on every structure."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

from complex_helpers import STRUCTURE_IDS, STRUCTURES, Make, build, fresh, random_polytope
from persistri.impl.complex import complex_structure
from persistri.impl.complex.ephemeral import EphemeralTwoComplex
from persistri.impl.complex.trace_record import TracingTwoComplex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.maps.red_black import RedBlackMap

N, TRIS = random_polytope(40, seed=3)

MAKERS: list[tuple[str, Make]] = [
    *STRUCTURES,
    ("ephemeral", lambda n, stats=None: EphemeralTwoComplex(stats)),
    ("traced", lambda n, stats=None: TracingTwoComplex(TwoComplex(RedBlackMap()))),
]


@pytest.mark.parametrize("make", [m for _, m in MAKERS], ids=[*STRUCTURE_IDS, "ephemeral", "traced"])
def test_iter_items_is_items_one_at_a_time(make: Make) -> None:
    C = make(2)
    c = build(C, fresh(N), TRIS)
    it = C.iter_items(c)
    assert isinstance(it, Iterator)
    got = list(it)
    assert got == list(C.items(c))
    assert len(got) == len(TRIS) and sorted(x for _, x in got) == list(range(len(TRIS)))


def test_iter_items_of_a_one_complex() -> None:
    C = complex_structure(1, "red_black")
    c = build(C, fresh(5), [(0, 1), (1, 2), (3, 4)], n=1)
    assert list(C.iter_items(c)) == list(C.items(c)) and len(C.items(c)) == 3


def test_iter_items_of_a_traced_structure_is_recorded() -> None:
    C: Any = TracingTwoComplex(TwoComplex(RedBlackMap()))
    c = build(C, fresh(N), TRIS)
    before = C.trace().counts().get("items", 0)
    list(C.iter_items(c))
    assert C.trace().counts()["items"] == before + 1
