"""``replace_trusted``: the algorithms' compiled entry to ``replace`` gives what ``replace`` gives, in every case.

:func:`persistri.impl.complex.replace.replace_trusted` is the body of
``TwoComplex.replace`` in a compiled module (the scattered Delaunay's
insertion calls it).  These tests check that on every 2-complex structure it
returns the same complex as ``replace`` or raises the same error with the same
message, with the version given unchanged; that it calls the structure's own
``replace`` where that is overridden or counted; and that ``same_replace``, the
comparison ``check=True`` makes, tells different results apart.
"""

from __future__ import annotations

from typing import Any

import pytest
from hypothesis import given

from complex_helpers import Make, build, fresh
from test_complex_replace import ICOSA, IDS, N_VERTS, TWO_COMPLEXES, batches, items_of, outcome
from persistri.impl.complex import two_complex
from persistri.impl.complex.replace import replace_cone, replace_trusted, same_replace
from persistri.impl.complex.structure import Complex
from persistri.impl.complex.trace_record import TracingTwoComplex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.maps.red_black import red_black
from persistri.impl.stats import Stats


@pytest.mark.parametrize("entry", [replace_trusted, replace_cone], ids=["replace_trusted", "replace_cone"])
@pytest.mark.parametrize("make", [m for _, m in TWO_COMPLEXES], ids=IDS)
@given(batch=batches)
def test_replace_trusted_is_replace(entry: Any, make: Make, batch: Any) -> None:
    """Any change (for ``replace_cone`` mostly not a cone: ``replace_trusted`` or ``replace`` decide), on every
    2-complex: the same outcome as the public ``replace``, and the operand unchanged."""
    removed_ix, added_ix = batch
    vs = fresh(N_VERTS + 3)
    removed = [tuple(vs[i] for i in t) for t in removed_ix]
    added = [(tuple(vs[i] for i in t), x) for t, x in added_ix]
    C = make(2)
    R = make(2)
    c = build(C, vs, ICOSA)
    before = items_of(C, c)
    want = outcome(lambda: items_of(R, R.replace(build(R, vs, ICOSA), removed, added)))
    got = outcome(lambda: items_of(C, entry(C, c, removed, added)))
    assert got == want
    if got[0] != "ok" or type(C) is TwoComplex:
        assert items_of(C, c) == before


def _star_and_cone(vs: list[Any], v: int, p: int) -> tuple[list[Any], list[Any]]:
    star = [tuple(vs[i] for i in t) for t in ICOSA if v in t]
    star = [t[t.index(vs[v]) :] + t[: t.index(vs[v])] for t in star]
    return star, [((t[1], t[2], vs[p]), k) for k, t in enumerate(star)]


@pytest.mark.parametrize("backend", ["red_black", "red_black_arena", "hamt", "assoc_list"])
def test_a_history_of_trusted_replaces_is_that_of_replace(backend: str) -> None:
    """Six cones in turn (the Delaunay's kind of step): every version equal to replace's, and still valid."""
    C = two_complex(backend)
    vs = fresh(N_VERTS + 6)
    c = d = build(C, vs, ICOSA)
    history = []
    for k in range(6):
        v = vs[k]
        star = [t for t, _ in C.items(c) if v in t]
        star = [t[t.index(v) :] + t[: t.index(v)] for t in star]
        cone = [((t[1], t[2], vs[N_VERTS + k]), k) for t in star]
        c2, d = replace_trusted(C, c, star, cone), C.replace(d, star, cone)
        assert type(c2) is Complex and c2.family is C.family
        assert items_of(C, c2) == items_of(C, d) and same_replace(C, c2, d, star, cone)
        c = c2
        history.append((c, items_of(C, c)))
    for version, model in history:
        assert items_of(C, version) == model
        C.check(version)


def test_the_structures_own_replace_is_called_where_it_is_overridden_or_counted() -> None:
    calls: list[int] = []

    class Overriding(TwoComplex[Any]):
        def replace(self, c: Any, removed: Any, added: Any, /) -> Any:
            calls.append(len(removed))
            return super().replace(c, removed, added)

    vs = fresh(N_VERTS + 1)
    star, cone = _star_and_cone(vs, 0, N_VERTS)
    plain = two_complex("red_black")
    assert plain._batched is not None
    stats = Stats()
    counted = two_complex("red_black", stats)
    assert counted._batched is None
    c = build(counted, vs, ICOSA)
    stats.reset()
    replace_trusted(counted, c, star, cone)
    assert stats.faces_deleted == len(star) and stats.faces_created == len(cone)
    mine = Overriding(red_black)
    assert mine._batched is None
    replace_trusted(mine, build(mine, vs, ICOSA), star, cone)
    assert calls == [len(star)]
    tracing = TracingTwoComplex(two_complex("red_black"))
    assert getattr(tracing, "_batched", None) is None
    t = build(tracing, vs, ICOSA)
    n = len(tracing._ops)
    replace_trusted(tracing, t, star, cone)
    assert len(tracing._ops) > n  # recorded: the tracing structure's replace ran


def test_same_replace_tells_different_results_apart() -> None:
    C = two_complex("red_black")
    vs = fresh(N_VERTS + 2)
    c = build(C, vs, ICOSA)
    star, cone = _star_and_cone(vs, 0, N_VERTS)
    a = replace_trusted(C, c, star, cone)
    assert same_replace(C, a, C.replace(c, star, cone), star, cone)
    other = [(t, x + 1) for t, x in cone]  # the same triangles, other data
    assert not same_replace(C, a, C.replace(c, star, other), star, cone)
    star1, cone1 = _star_and_cone(vs, 1, N_VERTS + 1)
    assert not same_replace(C, a, C.replace(c, star1, cone1), star, cone)
