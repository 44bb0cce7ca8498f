"""``replace (c, removed, added)``: the law that it is the fold of ``rem`` then ``add``, on every 2-complex.

``replace`` is persistri's addition to the paper's signature (one change per
algorithm step).  Its meaning is the fold; these tests check, on every
2-complex structure (each map backend, the unspecialised functor, the
ephemeral baseline), that it returns the same complex as the fold or raises
the same error with the same message, that the version it was given is
unchanged, and that the specialised 2-complex really batches (fewer map
operations than the fold).
"""

from __future__ import annotations

from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from complex_helpers import STRUCTURE_IDS, STRUCTURES, Make, build, fresh, icosahedron, random_polytope
from tree_helpers import preorder
from persistri.impl.complex import complex_structure, two_complex
from persistri.impl.complex.errors import (
    AbsentSimplexError,
    DimensionError,
    DuplicateSimplexError,
    ForeignComplexError,
    OppositeOrientationError,
    RepeatedVertexError,
)
from persistri.impl.complex.ephemeral import EphemeralTwoComplex
from persistri.impl.complex.structure import Complex
from persistri.impl.complex.vertex_lists import group, rebuild_fresh
from persistri.impl.stats import Stats

TWO_COMPLEXES: list[tuple[str, Make]] = [*STRUCTURES, ("ephemeral", lambda n, stats=None: EphemeralTwoComplex(stats))]
IDS = [*STRUCTURE_IDS, "ephemeral"]

N_VERTS, ICOSA = icosahedron()
EXTRA = 3  # vertices in no triangle of the icosahedron, for triangles that are new


def items_of(C: Any, c: Complex[Any]) -> list[tuple[tuple[int, ...], Any]]:
    """The triangles of ``c`` with their data, each as labels rotated to its smallest label, sorted."""
    out = []
    for t, x in C.items(c):
        labels = [int(v) for v in t]
        i = labels.index(min(labels))
        out.append((tuple(labels[i:] + labels[:i]), x))
    return sorted(out)


def outcome(call: Any) -> tuple[str, Any]:
    try:
        return "ok", call()
    except Exception as exc:  # noqa: BLE001 - the law compares whatever is raised
        return type(exc).__name__, str(exc)


# A triangle is drawn as indices into the vertices; with a flag for "rotate" and "reverse" it reaches present
# triangles, their other rotations, their opposite orientations and triangles never added.
tri_index = st.integers(0, len(ICOSA) - 1)


@st.composite
def triangle(draw: st.DrawFn) -> tuple[int, int, int]:
    if draw(st.booleans()):
        a, b, c = ICOSA[draw(tri_index)]
        r = draw(st.integers(0, 2))
        a, b, c = ((a, b, c), (b, c, a), (c, a, b))[r]
        if draw(st.integers(0, 4)) == 0:
            b, c = c, b  # the opposite orientation
        return (a, b, c)
    a, b, c = draw(st.lists(st.integers(0, N_VERTS + EXTRA - 1), min_size=3, max_size=3, unique=True))
    return (a, b, c)


batches = st.tuples(
    st.lists(triangle(), max_size=6),
    st.lists(st.tuples(triangle(), st.integers(100, 120)), max_size=7),
)


@pytest.mark.parametrize("make", [m for _, m in TWO_COMPLEXES], ids=IDS)
@given(batch=batches)
def test_replace_is_the_fold_of_rem_then_add(make: Make, batch: Any) -> None:
    removed_ix, added_ix = batch
    vs = fresh(N_VERTS + EXTRA)
    removed = [tuple(vs[i] for i in t) for t in removed_ix]
    added = [(tuple(vs[i] for i in t), x) for t, x in added_ix]
    C = make(2)
    R = make(2)  # the reference: the same structure, folding by hand
    c = build(C, vs, ICOSA)
    before = items_of(C, c)

    def fold() -> list[tuple[tuple[int, ...], Any]]:
        r = build(R, vs, ICOSA)
        for s in removed:
            r = R.rem(r, s)
        for s, x in added:
            r = R.add(r, s, x)
        return items_of(R, r)

    want = outcome(fold)
    got = outcome(lambda: items_of(C, C.replace(c, removed, added)))
    assert got == want
    if got[0] != "ok" or not isinstance(C, EphemeralTwoComplex):
        # The version given is unchanged (the ephemeral one only when the call was refused).
        assert items_of(C, c) == before


@pytest.mark.parametrize("make", [m for _, m in TWO_COMPLEXES], ids=IDS)
def test_replacing_a_star_by_a_cone_keeps_a_closed_surface(make: Make) -> None:
    """The bulldozer's step: the star of vertex 0 replaced by the cone of its link from a new vertex."""
    vs = fresh(N_VERTS + 1)
    C = make(2)
    c = build(C, vs, ICOSA)
    v0, p = vs[0], vs[N_VERTS]
    star = [tuple(vs[i] for i in t) for t in ICOSA if 0 in t]
    link = [(t[(t.index(v0) + 1) % 3], t[(t.index(v0) + 2) % 3]) for t in star]
    cone = [((u, w, p), "new") for u, w in link]
    c2 = C.replace(c, star, cone)
    C.check(c2)
    assert len(C.items(c2)) == len(ICOSA) and v0 not in C.vertices(c2) and p in C.vertices(c2)
    for u, w in link:
        assert C.find(c2, (w, u)) != [] and C.data(c2, (u, w, p)) == ("new",)


@pytest.mark.parametrize("backend", ["red_black", "hamt", "assoc_list"])
def test_the_specialised_complex_batches(backend: str) -> None:
    """One map operation per vertex touched: fewer than the fold's three per triangle; same faces counted."""
    vs = fresh(N_VERTS + 1)
    star = [tuple(vs[i] for i in t) for t in ICOSA if 0 in t]
    link = [(t[(t.index(vs[0]) + 1) % 3], t[(t.index(vs[0]) + 2) % 3]) for t in star]
    cone = [((u, w, vs[N_VERTS]), 0) for u, w in link]
    batched, folded = Stats(), Stats()
    for stats, batch in ((batched, True), (folded, False)):
        C = two_complex(backend, stats)
        c = build(C, vs, ICOSA)
        stats.reset()
        if batch:
            C.replace(c, star, cone)
        else:
            C._replace_fold(c, star, cone)
    assert batched.faces_deleted == folded.faces_deleted == len(star)
    assert batched.faces_created == folded.faces_created == len(cone)
    # The star of a degree-5 vertex: 5 removed, 5 added; touched: v0, its 5 neighbours, the new vertex.
    assert folded.dict_ops >= 3 * (len(star) + len(cone))
    assert batched.dict_ops <= 2 * 7  # at most an insertWith (+ a remove) per vertex touched
    assert batched.dict_ops < folded.dict_ops / 2


def test_every_version_of_a_replace_history_stays_valid() -> None:
    C = two_complex("red_black")
    vs = fresh(N_VERTS + 6)
    c = build(C, vs, ICOSA)
    history = [(c, items_of(C, c))]
    for k in range(6):
        v = vs[k]
        star = [t for t, _ in C.items(c) if v in t]
        star = [t[t.index(v) :] + t[: t.index(v)] for t in star]
        p = vs[N_VERTS + k]
        c = C.replace(c, star, [((t[1], t[2], p), k) for t in star])
        C.check(c)
        history.append((c, items_of(C, c)))
    for version, model in history:
        assert items_of(C, version) == model
        C.check(version)


@pytest.mark.parametrize("make", [m for _, m in TWO_COMPLEXES], ids=IDS)
def test_bad_arguments_get_the_signature_errors(make: Make) -> None:
    vs = fresh(N_VERTS + 1)
    C = make(2)
    c = build(C, vs, ICOSA)
    a, b, cc = (vs[i] for i in ICOSA[0])
    with pytest.raises(AbsentSimplexError):
        C.replace(c, [(a, cc, b)], [])
    with pytest.raises(AbsentSimplexError):
        C.replace(c, [(a, b, cc), (b, cc, a)], [])  # removed twice
    with pytest.raises(DuplicateSimplexError):
        C.replace(c, [], [((a, b, vs[N_VERTS]), 0), ((b, vs[N_VERTS], a), 1)])  # added twice
    with pytest.raises(OppositeOrientationError):
        C.replace(c, [], [((a, cc, b), 0)])
    with pytest.raises(DimensionError):
        C.replace(c, [(a, b)], [])
    with pytest.raises(TypeError, match="pairs"):
        C.replace(c, [], [(a, b, cc)])
    with pytest.raises(TypeError, match="iterable"):
        C.replace(c, 5, [])
    for foreign in ("x", complex_structure(1, "red_black").new(1)):
        with pytest.raises(ForeignComplexError):
            C.replace(foreign, [], [])
    assert items_of(C, c) == items_of(C, build(make(2), vs, ICOSA))  # refused calls changed nothing


@pytest.mark.parametrize("make", [m for _, m in TWO_COMPLEXES], ids=IDS)
def test_a_cone_from_a_vertex_already_present_is_the_fold(make: Make) -> None:
    """Every added triangle ends with one vertex in no removed triangle (a star replaced by a cone): the batched
    path skips looking for the added triangles in the kept lists only when that vertex has no list; when it has
    one, the result or the error is the fold's (a triangle already there, in either orientation)."""
    vs = fresh(N_VERTS + 1)
    C = make(2)
    c = build(C, vs, ICOSA)
    a, b, cc = (vs[i] for i in ICOSA[0])
    nb = C.neighbour(c, (b, a))
    assert nb is not None
    d = nb[0][2]  # (b, a, d) is the triangle across the edge (a, b)
    cases: list[tuple[list[Any], list[Any], type[Exception] | None]] = [
        ([], [((b, a, d), 0)], DuplicateSimplexError),  # the cone's vertex d has a list: the triangle is there
        ([], [((a, b, d), 0)], OppositeOrientationError),
        ([(a, b, cc)], [((b, a, cc), 1)], None),  # cc is in a removed triangle (no cone): the triangle reversed
        ([(a, b, cc), (b, a, d)], [((b, cc, d), 2), ((cc, a, d), 3)], None),  # the flip of edge (a, b), to (cc, d)
    ]
    for removed, added, error in cases:
        c = build(C, vs, ICOSA)  # afresh: a successful replace makes an ephemeral version stale
        R = make(2)
        r = build(R, vs, ICOSA)
        if error is None:
            got = C.replace(c, removed, added)
            for s in removed:
                r = R.rem(r, s)
            for s, x in added:
                r = R.add(r, s, x)
            assert items_of(C, got) == items_of(R, r)
            C.check(got)
        else:
            with pytest.raises(error):
                C.replace(c, removed, added)
            with pytest.raises(error):
                for s in removed:
                    r = R.rem(r, s)
                for s, x in added:
                    r = R.add(r, s, x)
            assert items_of(C, c) == items_of(C, build(make(2), vs, ICOSA))  # refused: nothing changed


@pytest.mark.parametrize("make", [m for _, m in TWO_COMPLEXES], ids=IDS)
def test_a_repeated_vertex_is_refused_as_the_fold_refuses_it(make: Make) -> None:
    """A triangle naming one vertex twice, removed or added (the batched path tells it by two of its vertices
    sharing one change: on the compiled twin too), raises the fold's RepeatedVertexError."""
    vs = fresh(N_VERTS + 1)
    C = make(2)
    c = build(C, vs, ICOSA)
    a, b, cc = (vs[i] for i in ICOSA[0])
    p = vs[N_VERTS]
    for removed, added in (([(a, b, a)], []), ([(a, b, cc)], [((a, p, p), 0)]), ([], [((p, b, p), 0)])):
        with pytest.raises(RepeatedVertexError):
            C.replace(c, removed, added)


@pytest.mark.parametrize("backend", ["red_black", "hamt", "assoc_list"])
def test_replace_shares_what_it_does_not_change(backend: str) -> None:
    """Persistence by sharing, checked by identity: the lists of untouched vertices, the kept entries of the
    touched ones, and (red-black) every subtree off the touched vertices' search paths are the old version's
    very objects — which a compiled build that re-boxed tuples would break — and the old version is unchanged."""
    n_verts, tris = random_polytope(300, seed=5)
    C = two_complex(backend)
    vs = fresh(n_verts + 1)
    c = build(C, vs, tris)
    m = C._m
    old_lists = dict(m.listItemsi(c.rep))
    snapshot = {v: list(lst) for v, lst in old_lists.items()}
    v0, p = vs[0], vs[n_verts]
    star = [tuple(vs[i] for i in t) for t in tris if 0 in t]
    link = [(t[(t.index(v0) + 1) % 3], t[(t.index(v0) + 2) % 3]) for t in star]
    c2 = C.replace(c, star, [((u, w, p), "new") for u, w in link])
    touched = {v0, p, *(u for u, _ in link)}
    new_lists = dict(m.listItemsi(c2.rep))
    assert set(new_lists) == set(old_lists) - {v0} | {p}
    for v, lst in new_lists.items():
        if v not in touched:
            assert lst is old_lists[v], v
        elif v != p:
            kept = [e for e in old_lists[v] if v0 not in e[:2]]
            assert [e for e in lst if any(e is k for k in kept)] == kept, v  # the very entry objects, in order
    assert {v: list(lst) for v, lst in m.listItemsi(c.rep)} == snapshot
    assert all(old_lists[v] is lst for v, lst in m.listItemsi(c.rep))
    if backend == "red_black":
        # An edge flip keeps every vertex: exactly the nodes on the four vertices' search paths are new,
        # every subtree hanging off them is the old one itself (a build that re-boxed tuples would copy
        # the untouched children of each path node too).
        a, b, d = star[0]
        nb = C.neighbour(c, (b, a))
        assert nb is not None
        x = nb[0][2]
        flipped = C.replace(c, [(a, b, d), (b, a, x)], [((d, a, x), 0), ((x, b, d), 1)])
        C.check(flipped)
        old_nodes = _tree_nodes(c.rep[1])
        fresh_nodes = [i for i in _tree_nodes(flipped.rep[1]) if i not in old_nodes]
        on_paths = {id(n) for k in (a, b, d, x) for n in _search_path(c.rep[1], k)}
        assert len(fresh_nodes) == len(on_paths) < len(old_nodes) / 4, (len(fresh_nodes), len(on_paths))


def _tree_nodes(t: Any) -> dict[int, Any]:
    out: dict[int, Any] = {}
    stack = [t]
    while stack:
        x = stack.pop()
        if x is not None:
            out[id(x)] = x
            stack += [x[1], x[4]]
    return out


def _search_path(t: Any, k: Any) -> list[Any]:
    path = []
    while t is not None:
        path.append(t)
        t = t[1] if k < t[2] else t[4] if t[2] < k else None
    return path


def test_a_cone_from_a_fresh_vertex_is_inserted_in_the_update_s_descent() -> None:
    """The red-black complex inserts a cone's new vertex in the batched update's one descent
    (``adjust_insert``): the map is the one ``adjust_sorted``, ``insert_absent`` and ``remove`` make one after
    another — the same shape, colours and lists, the same number of new nodes — and the old version holds."""
    n_verts, tris = random_polytope(300, seed=5)
    C = two_complex("red_black")
    vs = fresh(n_verts + 1)
    c = build(C, vs, tris)
    before = items_of(C, c)
    m = C._m
    inner = C._adjust_insert
    assert inner is not None
    fused: list[int] = []

    def spy(*args: Any) -> Any:
        out = inner(*args)
        fused.append(out[3])
        return out

    C._adjust_insert = spy
    v0, p = vs[0], vs[n_verts]
    star = [tuple(vs[i] for i in t) for t in tris if 0 in t]
    link = [(t[(t.index(v0) + 1) % 3], t[(t.index(v0) + 2) % 3]) for t in star]
    cone = [((u, w, p), "new") for u, w in link]
    c2 = C.replace(c, star, cone)
    C.check(c2)
    assert fused == [True]  # one call, and it inserted the new vertex
    changes, _, new_vertex = group(star, cone, c.lineage)
    assert new_vertex is p
    keys = sorted(changes)
    vals = [changes[k] for k in keys]
    want, absent, emptied = m.adjust_sorted(rebuild_fresh, c.rep, keys, vals)
    assert [keys[i] for i in absent] == [p] and [keys[i] for i in emptied] == [v0]
    want = m.insert_absent(want, p, tuple(changes[p][1] + changes[p][2]))
    want = m.remove(want, v0)[0]
    assert preorder(c2.rep[1]) == preorder(want[1]) and m.numItems(c2.rep) == m.numItems(want)
    old = _tree_nodes(c.rep[1])
    assert sum(i not in old for i in _tree_nodes(c2.rep[1])) == sum(i not in old for i in _tree_nodes(want[1]))
    assert items_of(C, c) == before


def test_group_names_the_apex_of_a_cone_and_nothing_else() -> None:
    """``group``'s third result is the vertex every added triangle ends with when it is one object in no removed
    triangle (the batched path then skips the presence checks), else None: a later triangle that ends elsewhere,
    an apex that loses a triangle, or no added triangle at all give None; the changes are the same either way."""
    vs = fresh(N_VERTS + 2)
    C = two_complex("red_black")
    c = build(C, vs, ICOSA)
    v0 = vs[0]
    star = [tuple(vs[i] for i in t) for t in ICOSA if 0 in t]
    link = [(t[(t.index(v0) + 1) % 3], t[(t.index(v0) + 2) % 3]) for t in star]
    p, q = vs[N_VERTS], vs[N_VERTS + 1]
    cone = [((u, w, p), i) for i, (u, w) in enumerate(link)]
    changes, _, apex = group(star, cone, c.lineage)
    assert apex is p
    assert len(changes[v0][1]) == len(changes[p][1]) == 0 and all(len(changes[u][1]) == 1 for u, _ in link)
    assert [e[:2] for e in changes[p][2]] == link
    two_apexes = cone[:-1] + [((link[-1][0], link[-1][1], q), 9)]
    assert group(star, two_apexes, c.lineage)[2] is None
    first_elsewhere = [((link[0][0], link[0][1], q), 9)] + cone[1:]
    assert group(star, first_elsewhere, c.lineage)[2] is None
    a, b, d = star[0]
    apex_removed = [((b, a, d), 0)]  # d loses the triangle (a, b, d): it has a list
    assert group([star[0]], apex_removed, c.lineage)[2] is None
    assert group(star, [], c.lineage)[2] is None
    for removed, added in ((star, cone), (star, two_apexes), (star, first_elsewhere)):
        got = C.replace(c, removed, added)
        r = c
        for s in removed:
            r = C.rem(r, s)
        for s, x in added:
            r = C.add(r, s, x)
        assert items_of(C, got) == items_of(C, r)
