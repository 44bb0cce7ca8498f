"""``neighbour (c, e)``: the law ``neighbour(c, e) == (findi(c, e)[0] if findi(c, e) else None)`` on every 2-complex.

``neighbour`` is persistri's addition for the walks across an edge.  Checked
here, with hypothesis, on every 2-complex structure (each map backend, the
functor, the dispatcher, the ephemeral baseline, the tracing recorder) over
complexes that need not be surfaces (an edge may be in several triangles in one
direction: then the first ``findi`` gives), with bad arguments (the same
exception type as ``findi``, a message naming ``neighbour``), stale ephemeral
versions, the counts, and the trace's ``findi`` events with ``arg`` 1.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from complex_helpers import BACKEND_NAMES, STRUCTURE_IDS, STRUCTURES, Make, build, fresh, icosahedron
from persistri.impl.complex import complex_structure, two_complex
from persistri.impl.complex.errors import DuplicateSimplexError, OppositeOrientationError, StaleVersionError
from persistri.impl.complex.ephemeral import EphemeralTwoComplex
from persistri.impl.complex.trace import FIRST, OPERATIONS, Trace, TraceFormatError, TracingTwoComplex, replay
from persistri.impl.maps import backend
from persistri.impl.stats import Stats


def _tracing(inner: str) -> Make:
    return lambda n, stats=None: TracingTwoComplex(two_complex(inner, stats))


TWO_COMPLEXES: list[tuple[str, Make]] = [
    *STRUCTURES,
    ("ephemeral", lambda n, stats=None: EphemeralTwoComplex(stats)),
    ("tracing-red_black", _tracing("red_black")),
    ("tracing-ephemeral", _tracing("ephemeral")),
]
IDS = [*STRUCTURE_IDS, "ephemeral", "tracing-red_black", "tracing-ephemeral"]

N = 7  # vertices; few, so that random triangles share directed edges often


def outcome(call: Any) -> tuple[str, Any]:
    try:
        return "ok", call()
    except Exception as exc:  # noqa: BLE001 - the law compares whatever is raised
        return type(exc).__name__, str(exc)


def first_of_findi(C: Any, c: Any, e: Any) -> Any:
    found = C.findi(c, e)
    return found[0] if found else None


def add_all(C: Any, c: Any, vs: list[Any], tris: list[list[int]], tag: str = "") -> Any:
    """``c`` with each triangle of ``tris`` added that ``add`` accepts (carrying its indices, after ``tag``)."""
    for t in tris:
        try:
            c = C.add(c, tuple(vs[i] for i in t), (tag, *t) if tag else tuple(t))
        except (DuplicateSimplexError, OppositeOrientationError):
            pass
    return c


triangles = st.lists(st.lists(st.integers(0, N - 1), min_size=3, max_size=3, unique=True), max_size=14)
edges = st.lists(st.tuples(st.integers(0, N), st.integers(0, N)), min_size=1, max_size=12)


@pytest.mark.parametrize("make", [m for _, m in TWO_COMPLEXES], ids=IDS)
@given(tris=triangles, probes=edges)
def test_neighbour_is_the_first_of_findi(make: Make, tris: list[list[int]], probes: list[tuple[int, int]]) -> None:
    vs = fresh(N + 1)  # vertex N is in no triangle
    C = make(2)
    c = add_all(C, C.new(2), vs, tris)
    for i, j in probes:
        e = (vs[i], vs[j])  # i == j: a repeated vertex, refused by both
        want = outcome(lambda: first_of_findi(C, c, e))
        got = outcome(lambda: C.neighbour(c, e))
        assert got[0] == want[0]
        if got[0] == "ok":
            assert got[1] == want[1]
            if got[1] is not None:
                tri, x = got[1]
                assert tri[:2] == e and C.data(c, tri) == (x,)
        else:
            assert "neighbour" in got[1]


def _bad_arguments(C: Any, c: Any, vs: list[Any]) -> list[tuple[Any, Any]]:
    """(complex, edge) pairs every 2-complex refuses: foreign values, wrong dimensions, other lineages."""
    other = fresh(3)
    return [
        (c, (vs[0], vs[1], vs[2])),  # a triangle, not an edge
        (c, (vs[0],)),
        (c, ()),
        (c, (vs[0], vs[0])),
        (c, (vs[0], other[1])),  # vertices of two lineages
        (c, (other[0], other[1])),  # a lineage not the complex's
        (c, 7),
        (c, (1, 2)),
        (c, None),
        ("not a complex", (vs[0], vs[1])),
        (None, (vs[0], vs[1])),
        (complex_structure(1, "assoc_list").new(1), (vs[0], vs[1])),  # a complex of another family
    ]


@pytest.mark.parametrize("make", [m for _, m in TWO_COMPLEXES], ids=IDS)
def test_bad_arguments_raise_what_findi_raises(make: Make) -> None:
    n, tris = icosahedron()
    vs = fresh(n)
    C = make(2)
    c = build(C, vs, tris)
    for k, e in _bad_arguments(C, c, vs):
        want = outcome(lambda: C.findi(k, e))
        got = outcome(lambda: C.neighbour(k, e))
        assert want[0] != "ok" and got[0] == want[0], (k, e, got, want)
        assert "neighbour" in got[1]
    # A list of vertices is accepted as findi accepts it.
    a, b = vs[tris[0][0]], vs[tris[0][1]]
    assert C.neighbour(c, [a, b]) == first_of_findi(C, c, [a, b]) is not None


def test_stale_ephemeral_versions_raise() -> None:
    E: EphemeralTwoComplex[Any] = EphemeralTwoComplex()
    a, b, c, d = fresh(4)
    c0 = E.new(2)
    c1 = E.add(c0, (a, b, c), "x")
    c2 = E.add(c1, (a, c, d), "y")
    for old in (c0, c1):
        with pytest.raises(StaleVersionError, match="neighbour"):
            E.neighbour(old, (a, b))
    assert E.neighbour(c2, (c, a)) == ((c, a, b), "x") and E.neighbour(c2, (a, c)) == ((a, c, d), "y")
    assert E.neighbour(c2, (b, a)) is None and E.neighbour(c2, (d, b)) is None


COSTED = [name for name in BACKEND_NAMES if hasattr(backend(name), "search_cost")]


@pytest.mark.parametrize("name", COSTED)
def test_counts_are_one_lookup_and_the_entries_up_to_the_hit(name: str) -> None:
    B = backend(name)
    stats = Stats()
    C = complex_structure(2, B, stats=stats)
    n, tris = icosahedron()
    vs = fresh(n + 1)
    c = build(C, vs, tris)
    for t in tris:
        for i in range(3):
            u, w = vs[t[i]], vs[t[(i + 1) % 3]]
            lst = B.lookup(c.rep, u)
            hit = next(j for j, e in enumerate(lst) if e[0] == w)
            stats.reset()
            assert C.neighbour(c, (u, w)) is not None
            assert stats.dict_ops == 1 and stats.key_comparisons == B.search_cost(c.rep, u) + hit + 1
            assert stats.faces_created == stats.faces_deleted == 0
            stats.reset()
            assert C.neighbour(c, (w, u)) is not None  # the other side: a closed surface
            stats.reset()
            assert C.neighbour(c, (u, vs[n])) is None  # u's whole list visited
            assert stats.dict_ops == 1 and stats.key_comparisons == B.search_cost(c.rep, u) + len(lst)
    stats.reset()
    assert C.neighbour(c, (vs[n], vs[0])) is None  # no list: the lookup only
    assert stats.dict_ops == 1 and stats.key_comparisons == B.search_cost(c.rep, vs[n])


def test_ephemeral_counts() -> None:
    stats = Stats()
    E: EphemeralTwoComplex[Any] = EphemeralTwoComplex(stats)
    n, tris = icosahedron()
    vs = fresh(n + 1)
    c = build(E, vs, tris)
    u, w = vs[tris[3][0]], vs[tris[3][1]]
    lst = c.rep[0].lists[u]
    hit = next(j for j, e in enumerate(lst) if e[0] == w)
    stats.reset()
    assert E.neighbour(c, (u, w)) is not None
    assert stats.dict_ops == 1 and stats.key_comparisons == 1 + hit + 1
    stats.reset()
    assert E.neighbour(c, (u, vs[n])) is None
    assert stats.dict_ops == 1 and stats.key_comparisons == 1 + len(lst)
    stats.reset()
    assert E.neighbour(c, (vs[n], u)) is None
    assert stats.dict_ops == 1 and stats.key_comparisons == 1


def test_a_recorded_neighbour_is_a_findi_event_replayed_with_neighbour() -> None:
    n, tris = icosahedron()
    vs = fresh(n + 1)
    rec: TracingTwoComplex[Any] = TracingTwoComplex(two_complex("red_black"))
    c = build(rec, vs, tris)
    a, b, x = vs[tris[0][0]], vs[tris[0][1]], vs[n]
    c = rec.add(c, (a, b, x), "second")  # (a, b) is now in two triangles: findi gives 2, neighbour 1
    assert len(rec.findi(c, (a, b))) == 2
    assert rec.neighbour(c, (a, b)) == rec.findi(c, (a, b))[0]
    assert rec.neighbour(c, (x, b)) is None  # (a, b, x) holds (b, x), not (x, b)
    trace = rec.stop()
    events = list(trace.events())
    assert events[-4:] == [
        ("findi", len(tris) + 1, (int(a), int(b)), 0, 2),
        ("findi", len(tris) + 1, (int(a), int(b)), 1, 1),
        ("findi", len(tris) + 1, (int(a), int(b)), 0, 2),
        ("findi", len(tris) + 1, (int(x), int(b)), 1, 0),
    ]
    for name in ["hamt", "assoc_list", "ephemeral"]:
        S = two_complex(name)
        assert len(S.items(replay(trace, S))) == len(tris) + 1  # verified event by event
    # After stop, neighbour is forwarded unrecorded.
    assert rec.neighbour(c, (a, b)) is not None and len(rec.trace()) == len(trace)


def test_neighbour_events_are_validated() -> None:
    assert OPERATIONS.index("findi") == 8 and FIRST == 1

    def one_findi(arg: int, result: int) -> Trace:
        op = np.array([0, 8], dtype=np.uint8)
        return Trace(2, op, np.array([-1, 0]), np.array([[-1, -1, -1], [0, 1, -1]]), np.array([2, arg]), np.array([0, result]))

    assert one_findi(0, 3).event(1) == ("findi", 0, (0, 1), 0, 3)
    assert one_findi(1, 1).event(1) == ("findi", 0, (0, 1), 1, 1)
    with pytest.raises(TraceFormatError, match="findi event 1 has arg 2"):
        one_findi(2, 0)
    with pytest.raises(TraceFormatError, match="neighbour event 1"):
        one_findi(1, 2)


# -- neighbours(c): neighbour for one version, each vertex's list read once ----------------------------

WALKERS = [(name, make) for name, make in TWO_COMPLEXES if hasattr(make(2), "neighbours")]


@pytest.mark.parametrize("make", [m for _, m in WALKERS], ids=[name for name, _ in WALKERS])
@given(tris=triangles, later=triangles, probes=edges)
def test_neighbours_of_a_version_is_neighbour_on_it(
    make: Make, tris: list[list[int]], later: list[list[int]], probes: list[tuple[int, int]]
) -> None:
    """``neighbours(c)(e)`` is ``neighbour(c, e)``, probe after probe (vertices met again are read from what
    the function kept), and stays so for an old version after newer ones are made from it."""
    vs = fresh(N + 1)
    C = make(2)
    c = add_all(C, C.new(2), vs, tris)
    across = C.neighbours(c)
    persistent = not isinstance(C.inner if isinstance(C, TracingTwoComplex) else C, EphemeralTwoComplex)
    for round_ in range(2):
        for i, j in probes:
            e = (vs[i], vs[j])
            want = outcome(lambda: C.neighbour(c, e))
            got = outcome(lambda: across(e))
            assert got[0] == want[0] and (got[1] == want[1] or got[0] != "ok"), (e, got, want)
            if got[0] != "ok":
                assert "neighbour" in got[1]
        if round_ == 0 and persistent:
            add_all(C, c, vs, later, "later")  # newer versions; c and what across kept are unchanged


@pytest.mark.parametrize("make", [m for _, m in WALKERS], ids=[name for name, _ in WALKERS])
def test_neighbours_refuses_what_neighbour_refuses(make: Make) -> None:
    n, tris = icosahedron()
    vs = fresh(n)
    C = make(2)
    c = build(C, vs, tris)
    across = C.neighbours(c)
    for k, e in _bad_arguments(C, c, vs):
        want = outcome(lambda: C.neighbour(k, e))
        got = outcome(lambda: C.neighbours(k)(e)) if k is not c else outcome(lambda: across(e))
        assert want[0] != "ok" and got[0] == want[0], (k, e, got, want)
        assert "neighbour" in got[1]
    a, b = vs[tris[0][0]], vs[tris[0][1]]
    assert across([a, b]) == C.neighbour(c, [a, b]) is not None


@pytest.mark.parametrize("walk", ["neighbours", "neighbours_unchecked"])
def test_neighbours_reads_each_vertex_list_once(walk: str) -> None:
    """The specialised, uncounted 2-complex: one map lookup per vertex however many edges leave it."""
    n, tris = icosahedron()
    vs = fresh(n)
    C = two_complex("red_black")
    c = build(C, vs, tris)
    crossings = [(vs[t[(i + 1) % 3]], vs[t[i]]) for t in tris for i in range(3)]
    expected = [first_of_findi(C, c, e) for e in crossings]
    looked_up: list[Any] = []
    real = C._m

    class Counting:
        def find(self, rep: Any, k: Any) -> Any:
            looked_up.append(k)
            return real.find(rep, k)

    C._m = Counting()
    try:
        across = getattr(C, walk)(c)
        assert [across(e) for e in crossings] == expected
    finally:
        C._m = real
    assert sorted(looked_up) == sorted(vs)  # every vertex once


def test_counted_neighbours_count_each_call_as_neighbour_does() -> None:
    stats = Stats()
    C = two_complex("red_black", stats)
    n, tris = icosahedron()
    vs = fresh(n)
    c = build(C, vs, tris)
    edges_ = [(vs[t[1]], vs[t[0]]) for t in tris]
    stats.reset()
    for e in edges_:
        C.neighbour(c, e)
    by_neighbour = (stats.dict_ops, stats.key_comparisons)
    stats.reset()
    across = C.neighbours(c)
    for e in edges_:
        across(e)
    assert (stats.dict_ops, stats.key_comparisons) == by_neighbour == (len(edges_), by_neighbour[1])


# -- neighbours_unchecked(c): the same answers on edges of distinct vertices, without checking each -----------

UNCHECKED = [(name, make) for name, make in TWO_COMPLEXES if hasattr(make(2), "neighbours_unchecked")]


def test_every_two_complex_has_the_unchecked_walk() -> None:
    assert [name for name, _ in UNCHECKED] == [name for name, _ in WALKERS]


@pytest.mark.parametrize("make", [m for _, m in UNCHECKED], ids=[name for name, _ in UNCHECKED])
@given(tris=triangles, later=triangles, probes=edges)
def test_neighbours_unchecked_is_neighbour_on_valid_edges(
    make: Make, tris: list[list[int]], later: list[list[int]], probes: list[tuple[int, int]]
) -> None:
    """On an edge of two distinct vertices of the version's lineage, ``neighbours_unchecked(c)(e)`` is
    ``neighbour(c, e)``, and stays so for an old version after newer ones are made from it."""
    vs = fresh(N + 1)
    C = make(2)
    c = add_all(C, C.new(2), vs, tris)
    across = C.neighbours_unchecked(c)
    persistent = not isinstance(C.inner if isinstance(C, TracingTwoComplex) else C, EphemeralTwoComplex)
    valid = [(vs[i], vs[j]) for i, j in probes if i != j]
    for round_ in range(2):
        for e in valid:
            assert across(e) == C.neighbour(c, e), e
        if round_ == 0 and persistent:
            add_all(C, c, vs, later, "later")


def test_neighbours_unchecked_skips_the_edge_checks() -> None:
    """An edge from a vertex to itself: neighbour refuses it, the unchecked walk does not look (the caller's duty)."""
    n, tris = icosahedron()
    vs = fresh(n)
    C = two_complex("red_black")
    c = build(C, vs, tris)
    with pytest.raises(ValueError, match="neighbour"):
        C.neighbour(c, (vs[0], vs[0]))
    assert C.neighbours_unchecked(c)((vs[0], vs[0])) is None


def test_the_red_black_walk_is_the_generic_one_with_find_written_out() -> None:
    """Over the red-black map the unchecked walk searches the tuple tree itself
    (``neighbours_unchecked_in_tree``): every answer that of the generic walk with the map's ``find``, on
    every directed edge of the icosahedron, its reversals, edges to a vertex with no list and from one, and
    for an old version after newer ones are made from it."""
    from persistri.impl.complex.neighbours import neighbours_unchecked_in, neighbours_unchecked_in_tree
    from persistri.impl.maps.red_black_tree import find

    n, tris = icosahedron()
    vs = fresh(n + 2)
    C = two_complex("red_black")
    c = build(C, vs[:n], tris)
    rep = c[1]
    probes = [(vs[t[i]], vs[t[(i + 1) % 3]]) for t in tris for i in range(3)]
    probes += [(w, u) for u, w in probes] + [(vs[0], vs[n]), (vs[n], vs[0]), (vs[n + 1], vs[n])]
    expected = [neighbours_unchecked_in(rep, find)(e) for e in probes]
    assert sum(x is not None for x in expected) == 6 * len(tris)  # a closed surface: both directions
    assert expected[-3:] == [None, None, None]
    walk = C.neighbours_unchecked(c)
    tree_walk = neighbours_unchecked_in_tree(rep[1])
    newer = C.rem(c, (vs[tris[0][0]], vs[tris[0][1]], vs[tris[0][2]]))
    assert C.neighbours_unchecked(newer)(probes[0]) is None
    assert [walk(e) for e in probes] == [tree_walk(e) for e in probes] == expected
    assert [first_of_findi(C, c, e) for e in probes] == expected


def test_neighbours_unchecked_checks_the_version_once() -> None:
    n, tris = icosahedron()
    vs = fresh(n)
    for C in (two_complex("red_black"), EphemeralTwoComplex()):
        c = build(C, vs, tris)
        with pytest.raises(TypeError, match="neighbour"):
            C.neighbours_unchecked(("not", "a", "version"))  # type: ignore[arg-type]
    E = EphemeralTwoComplex()
    old = build(E, vs, tris)
    E.rem(old, (vs[tris[0][0]], vs[tris[0][1]], vs[tris[0][2]]))  # old is now stale
    with pytest.raises(StaleVersionError, match="neighbour"):
        E.neighbours_unchecked(old)


def test_counted_and_recorded_structures_walk_checked_and_counted() -> None:
    """Counted structures and the recorder get ``neighbours``: every call counted (or recorded) as one."""
    n, tris = icosahedron()
    vs = fresh(n)
    edges_ = [(vs[t[1]], vs[t[0]]) for t in tris]
    for C, stats in ((two_complex("red_black", s := Stats()), s), (EphemeralTwoComplex(s2 := Stats()), s2)):
        c = build(C, vs, tris)
        stats.reset()
        for e in edges_:
            C.neighbour(c, e)
        by_neighbour = (stats.dict_ops, stats.key_comparisons)
        stats.reset()
        across = C.neighbours_unchecked(c)
        assert [across(e) for e in edges_] == [C.neighbour(c, e) for e in edges_]
        stats.reset()
        for e in edges_:
            across(e)
        assert (stats.dict_ops, stats.key_comparisons) == by_neighbour
        with pytest.raises(ValueError, match="neighbour"):
            across((vs[0], vs[0]))  # checked: refused, as neighbour refuses it
