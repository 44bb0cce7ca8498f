"""``replace``'s list rebuild (``drop_add`` of impl/complex/vertex_lists.py) against its definition.

``drop_add(old, (drops, checked, plain))`` is one vertex's list after a
``replace``: ``old`` without the entries of the pairs ``drops``, then the
entries ``checked`` (refused if their triangle is kept, in either orientation)
and ``plain``.  Its fast path (exactly one checked entry: every vertex a star
replacement keeps) and its general path are checked here against a direct
transcription of that definition on random lists, including pairs that are
absent or asked twice, triangles already present and lists left empty.
"""

from __future__ import annotations

from typing import Any

from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.complex.vertex_lists import Emptied, Missing, Present, drop_add, rebuild_fresh

LABELS = st.integers(0, 6)


def reference(old: tuple[Any, ...], drops: list[Any], checked: list[Any], plain: list[Any]) -> tuple[str, Any]:
    """The definition, step by step: ("ok", list) or the name of the failure."""
    pairs = [(e[0], e[1]) for e in old]
    if len(set(drops)) != len(drops) or any(d not in pairs for d in drops):
        return "missing", None
    kept = [e for e in old if (e[0], e[1]) not in set(drops)]
    kept_pairs = {(e[0], e[1]) for e in kept}
    if any((b, c) in kept_pairs or (c, b) in kept_pairs for b, c, _ in checked):
        return "present", None
    out = tuple(kept + checked + plain)
    return ("ok", out) if out else ("emptied", None)


def run(old: tuple[Any, ...], drops: list[Any], checked: list[Any], plain: list[Any]) -> tuple[str, Any]:
    try:
        return "ok", drop_add(old, (list(drops), list(checked), list(plain)))
    except Missing:
        return "missing", None
    except Present:
        return "present", None
    except Emptied:
        return "emptied", None


@st.composite
def lists(draw: st.DrawFn) -> tuple[tuple[Any, ...], list[Any], list[Any], list[Any]]:
    """A valid list (distinct pairs, no triangle in both orientations) and a change to it."""
    raw = draw(st.lists(st.tuples(LABELS, LABELS).filter(lambda p: p[0] != p[1]), max_size=8))
    pairs: list[tuple[int, int]] = []
    for b, c in raw:
        if (b, c) not in pairs and (c, b) not in pairs:
            pairs.append((b, c))
    old = tuple((b, c, f"x{i}") for i, (b, c) in enumerate(pairs))
    drops = draw(st.lists(st.sampled_from(pairs), max_size=len(pairs))) if pairs else []
    if draw(st.integers(0, 5)) == 0:  # sometimes a pair that is not there
        drops.append(draw(st.tuples(LABELS, LABELS)))
    entry = st.tuples(LABELS, LABELS, st.just("new")).filter(lambda e: e[0] != e[1])
    checked = draw(st.lists(entry, max_size=2))
    if draw(st.integers(0, 2)) != 0:  # mostly the star's case: one checked entry
        checked = checked[:1] or [draw(entry)]
    plain = draw(st.lists(entry, max_size=2))
    return old, drops, checked, plain


@given(lists())
def test_drop_add_is_its_definition(case: tuple[tuple[Any, ...], list[Any], list[Any], list[Any]]) -> None:
    old, drops, checked, plain = case
    want = reference(old, drops, checked, plain)
    got = run(old, drops, checked, plain)
    if want[0] in ("missing", "present"):
        # Either refusal sends replace to the fold, which raises the precise error.
        assert got[0] in ("missing", "present"), (case, got)
    else:
        assert got == want, case


def test_the_paths_by_hand() -> None:
    old = ((1, 2, "a"), (2, 3, "b"), (3, 4, "c"))
    # One drop, one checked (the fast path), one plain.
    assert drop_add(old, ([(2, 3)], [(5, 6, "n")], [(6, 7, "p")])) == ((1, 2, "a"), (3, 4, "c"), (5, 6, "n"), (6, 7, "p"))
    # Two drops: the set path.
    assert drop_add(old, ([(3, 4), (1, 2)], [(5, 6, "n")], [])) == ((2, 3, "b"), (5, 6, "n"))
    for bad in ([(2, 9)], [(2, 3), (2, 3)]):
        try:
            drop_add(old, (bad, [(5, 6, "n")], []))
        except Missing:
            pass
        else:
            raise AssertionError(f"{bad} should be missing")
    for checked in ([(4, 3, "n")], [(1, 2, "n")], [(5, 6, "n"), (4, 3, "n")]):  # kept, in either orientation
        try:
            drop_add(old, ([(2, 3)], checked, []))
        except Present:
            pass
        else:
            raise AssertionError(f"{checked} should be present")
    # The dropped triangle itself may come back (removed, then added: the fold's order).
    assert drop_add(old, ([(2, 3)], [(3, 2, "n")], [])) == ((1, 2, "a"), (3, 4, "c"), (3, 2, "n"))
    # No checked entry: the general path, which can empty the list.
    try:
        drop_add(old, ([(1, 2), (2, 3), (3, 4)], [], []))
    except Emptied:
        pass
    else:
        raise AssertionError("the list should be emptied")
    assert drop_add(old, ([(1, 2), (2, 3), (3, 4)], [], [(9, 8, "p")])) == ((9, 8, "p"),)


@given(lists())
def test_rebuild_fresh_is_the_definition_without_the_presence_check(
    case: tuple[tuple[Any, ...], list[Any], list[Any], list[Any]],
) -> None:
    """``rebuild_fresh`` (a replace whose added triangles all name a vertex with no list) drops and appends as
    ``drop_add`` does, refuses the same missing pairs, and never looks for the added triangles in ``old``."""
    old, drops, checked, plain = case
    want = reference(old, drops, [], checked + plain)  # the same list, nothing checked
    try:
        got: tuple[str, Any] = ("ok", rebuild_fresh(old, (list(drops), list(checked), list(plain), None)))
    except Missing:
        got = ("missing", None)
    if want[0] == "emptied":
        assert got == ("ok", ()), case  # the tree reports an emptied list: () is its new value
    else:
        assert got == want, case
        if want[0] == "ok":  # the kept entries are old's own objects (shared with older versions), in order
            assert all(g is w for g, w in zip(got[1], want[1])), case
