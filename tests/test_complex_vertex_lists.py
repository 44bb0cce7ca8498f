"""The flat vertex lists of the 2-complex (impl/complex/vertex_lists.py) against lists of entry tuples.

A vertex's list is one flat tuple, its entries ``b, c, x`` laid end to end,
and each function that ``insertWith`` combines lists with is checked
here against its definition over the list of entries ``(b, c, x)`` it stands
for: ``entries``/``from_entries``/``from_flat`` are inverse, ``index`` finds the
first entry of a pair, ``cat``, ``cat_first``, ``drop``, ``put`` and
``cat_new`` do to the entries what their docstrings say, and refuse what they
must refuse.
"""

from __future__ import annotations

from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.complex.vertex_lists import (
    Emptied,
    Missing,
    Present,
    cat,
    cat_first,
    cat_new,
    drop,
    entries,
    from_entries,
    from_flat,
    index,
    put,
    size,
    visited,
)

LABELS = st.integers(0, 6)
ENTRY = st.tuples(LABELS, LABELS, st.text(max_size=2)).filter(lambda e: e[0] != e[1])


@given(st.lists(ENTRY, max_size=8))
def test_layout_round_trips(es: list[tuple[Any, Any, Any]]) -> None:
    lst = from_entries(es)
    assert len(lst) == 3 * len(es) and size(lst) == len(es)
    assert entries(lst) == es
    assert from_flat([y for e in es for y in e]) == lst
    assert lst == tuple(y for e in es for y in e)
    if len(es) == 1:
        assert lst == es[0]  # a list of one entry is that entry


@given(st.lists(ENTRY, max_size=8), LABELS, LABELS)
def test_index_and_visited(es: list[tuple[Any, Any, Any]], b: int, c: int) -> None:
    lst = from_entries(es)
    want = next((i for i, e in enumerate(es) if e[0] == b and e[1] == c), -1)
    assert index(lst, b, c) == want
    assert visited(lst, b, c) == (len(es) if want < 0 else want + 1)
    if want >= 0:
        assert lst[3 * want + 2] == es[want][2]


@given(st.lists(ENTRY, max_size=6), st.lists(ENTRY, min_size=1, max_size=3))
def test_cat_and_cat_new(es: list[tuple[Any, Any, Any]], new: list[tuple[Any, Any, Any]]) -> None:
    old = from_entries(es)
    assert entries(cat(old, from_entries(new))) == es + new
    clash = any({(e[0], e[1]), (e[1], e[0])} & {(n[0], n[1])} for e in es for n in new)
    if clash:
        with pytest.raises(Present):
            cat_new(old, from_entries(new))
    else:
        assert entries(cat_new(old, from_entries(new))) == es + new


@given(st.lists(ENTRY, max_size=6), ENTRY)
def test_cat_first(es: list[tuple[Any, Any, Any]], new: tuple[Any, Any, Any]) -> None:
    old = from_entries(es)
    b, c, _ = new
    same = any(e[0] == b and e[1] == c for e in es)
    opposite = any(e[0] == c and e[1] == b for e in es)
    if same or opposite:
        with pytest.raises(Present):
            cat_first(old, new)
    else:
        assert entries(cat_first(old, new)) == es + [new]


@given(st.lists(ENTRY, max_size=6), LABELS, LABELS)
def test_drop_and_put(es: list[tuple[Any, Any, Any]], b: int, c: int) -> None:
    old = from_entries(es)
    i = next((j for j, e in enumerate(es) if e[0] == b and e[1] == c), -1)
    if i < 0:
        with pytest.raises(Missing):
            drop(old, (b, c))
        with pytest.raises(Missing):
            put(old, (b, c, "y"))
        return
    if len(es) == 1:
        with pytest.raises(Emptied):
            drop(old, (b, c))
    else:
        assert entries(drop(old, (b, c))) == es[:i] + es[i + 1 :]
    assert entries(put(old, (b, c, "y"))) == es[:i] + [(b, c, "y")] + es[i + 1 :]
    assert entries(old) == es  # the old list is a tuple: unchanged
