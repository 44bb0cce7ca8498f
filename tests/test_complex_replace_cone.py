"""``replace_cone``: a cavity replaced by a cone, grouped from the cone's cycle, gives what ``replace`` gives.

:func:`persistri.impl.complex.replace.replace_cone` is the scattered Delaunay's
entry to ``replace`` (paper §5): its added triangles are the cone from a new
vertex over the cavity's boundary cycle, in the cycle's order, and
:func:`~persistri.impl.complex.vertex_changes.group_cone` reads each cycle vertex's
two new entries off it instead of grouping them through a dictionary.  These
tests check that its changes mean :func:`~persistri.impl.complex.vertex_changes.group`'s,
that its result is ``replace``'s list for list (the same entries in the same
order, the same tree), that it really takes its own path for a cone and hands
everything else to ``replace_trusted`` or ``replace`` (the same result or the
same error, the version given unchanged), and that
:func:`~persistri.impl.complex.vertex_changes.rebuild_cone` is
:func:`~persistri.impl.complex.vertex_lists.rebuild_fresh`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from hypothesis import given

from complex_helpers import Make, build, fresh, random_polytope
from test_complex_replace import ICOSA, IDS, N_VERTS, TWO_COMPLEXES, batches, items_of, outcome
from tree_helpers import preorder
from persistri.impl.complex import two_complex
from persistri.impl.complex.replace import replace_cone
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.complex import vertex_changes, vertex_lists
from persistri.impl.complex.vertex_changes import group, group_cone, rebuild_cone
from persistri.impl.complex.vertex_lists import Missing, Unbatched, rebuild_fresh
from persistri.impl.terrain.scattered import delaunay


def lists_of(C: Any, c: Any) -> Any:
    """Every vertex's list in its stored order (labels and data), and the tree's shape for a red-black map."""
    m = getattr(C, "_m", None)
    if m is None or not hasattr(m, "listItemsi"):
        return items_of(C, c)
    rep = c[1]
    lists = [(int(v), [(int(e[0]), int(e[1]), e[2]) for e in lst]) for v, lst in m.listItemsi(rep)]
    shape = preorder(rep[1]) if type(rep) is tuple and len(rep) == 2 and (rep[1] is None or len(rep[1]) == 5) else None
    return lists, shape


def boundary_cycle(removed: list[tuple[Any, ...]]) -> list[Any] | None:
    """The boundary of a set of triangles as one counterclockwise cycle of vertices, or None if it is not one."""
    edges = {(t[i], t[(i + 1) % 3]) for t in removed for i in range(3)}
    succ: dict[Any, Any] = {}
    for a, b in edges:
        if (b, a) not in edges:
            if a in succ:
                return None
            succ[a] = b
    if not succ:
        return None
    start = min(succ)
    cycle = [start]
    while succ[cycle[-1]] is not start:
        cycle.append(succ[cycle[-1]])
        if len(cycle) > len(succ):
            return None
    return cycle if len(cycle) == len(succ) else None


def cone_over(cycle: list[Any], apex: Any, shift: int = 0, tag: str = "x") -> list[Any]:
    """The cone from ``apex`` over ``cycle`` in its order, starting at ``cycle[shift]``; data ``(tag, i)``."""
    m = len(cycle)
    return [((cycle[(i + shift) % m], cycle[(i + shift + 1) % m], apex), (tag, i)) for i in range(m)]


def cavities(tris: list[tuple[int, int, int]], sizes: tuple[int, ...], starts: range) -> list[list[int]]:
    """Connected sets of triangles (indices) grown breadth-first from each start, of each size."""
    by_edge = {(t[i], t[(i + 1) % 3]): k for k, t in enumerate(tris) for i in range(3)}
    out = []
    for s in starts:
        grown = [s]
        frontier = [s]
        while frontier and len(grown) < max(sizes):
            k = frontier.pop(0)
            t = tris[k]
            for i in range(3):
                n = by_edge[(t[(i + 1) % 3], t[i])]
                if n not in grown and len(grown) < max(sizes):
                    grown.append(n)
                    frontier.append(n)
        out += [grown[:n] for n in sizes if n <= len(grown)]
    return out


def normalised(changes: Any) -> dict[int, tuple[list[Any], list[Any]]]:
    """Each vertex's drops (pairs, in order) and entries to append (in order), from either grouping."""
    out = {}
    for v, ch in changes.items():
        if len(ch) == 3:  # group_cone's (drops, tail, v): flat drops
            drops = [(ch[0][k], ch[0][k + 1]) for k in range(0, len(ch[0]), 2)]
            tail = list(ch[1])
        else:  # group's (drops, checked, plain, v)
            drops, tail = list(ch[0]), list(ch[1]) + list(ch[2])
        assert ch[-1] is v
        out[int(v)] = ([(int(b), int(c)) for b, c in drops], [(int(e[0]), int(e[1]), e[2]) for e in tail])
    return out


class Spy:
    """The red-black complex's ``_batched`` with its fused update recorded: which rebuild each call used."""

    def __init__(self, C: TwoComplex[Any]) -> None:
        assert C._batched is not None
        family, adjust, insert, remove, adjust_insert = C._batched
        self.rebuilds: list[str] = []

        def spied(f: Any, *args: Any) -> Any:
            self.rebuilds.append(f.__name__)
            return adjust_insert(f, *args)

        C._batched = (family, adjust, insert, remove, spied)


def test_a_cavity_and_its_cone_is_replace_list_for_list() -> None:
    """Cavities of 1 to 6 triangles on a random polytope, each boundary cycle coned from a new vertex from every
    starting point: group_cone's changes are group's, replace_cone takes its own path where the cavity has no
    interior vertex and hands the rest on, and the complex is replace's, list for list, tree for tree."""
    n_verts, tris = random_polytope(60, seed=3)
    C = two_complex("red_black")
    R = two_complex("red_black")
    vs = fresh(n_verts + 1)
    c = build(C, vs, tris)
    r = build(R, vs, tris)
    before = lists_of(C, c)
    spy = Spy(C)
    own = handed_on = 0
    stars = [[k for k, t in enumerate(tris) if v in t] for v in range(0, n_verts, 9)]  # v interior
    for cav in cavities(tris, (1, 2, 3, 4, 5, 6), range(0, len(tris), 7)) + stars:
        removed = [tuple(vs[i] for i in tris[k]) for k in cav]
        cycle = boundary_cycle(removed)
        if cycle is None:
            continue
        interior = {v for t in removed for v in t} - set(cycle)
        for shift in range(len(cycle)):
            added = cone_over(cycle, vs[n_verts], shift)
            if not interior:
                assert normalised(group_cone(removed, added, c.lineage)) == normalised(group(removed, added, c.lineage)[0])
            else:
                with pytest.raises(Unbatched):
                    group_cone(removed, added, c.lineage)
            spy.rebuilds.clear()
            got = replace_cone(C, c, removed, added)
            want = R.replace(r, removed, added)
            assert lists_of(C, got) == lists_of(R, want)
            C.check(got)
            if interior:
                assert "rebuild_cone" not in spy.rebuilds
                handed_on += 1
            else:
                assert spy.rebuilds == ["rebuild_cone"]
                own += 1
    assert own > 50 and handed_on > 0
    assert lists_of(C, c) == before


def _icosa_cavity(vs: list[Any]) -> tuple[list[Any], list[Any]]:
    """Two adjacent triangles of the icosahedron (no interior vertex) and their boundary cycle."""
    t0 = ICOSA[0]
    e = (t0[1], t0[0])
    t1 = next(t for t in ICOSA if any((t[i], t[(i + 1) % 3]) == e for i in range(3)))
    removed = [tuple(vs[i] for i in t) for t in (t0, t1)]
    cycle = boundary_cycle(removed)
    assert cycle is not None and len(cycle) == 4
    return removed, cycle


def _off_the_cycle(vs: list[Any], cycle: list[Any]) -> tuple[Any, ...]:
    """A triangle of the icosahedron with a vertex off ``cycle``."""
    return next(tuple(vs[i] for i in t) for t in ICOSA if any(vs[i] not in cycle for i in t))


@pytest.mark.parametrize("make", [m for _, m in TWO_COMPLEXES], ids=IDS)
def test_what_is_not_a_plain_cone_is_handed_on(make: Make) -> None:
    """Cones that group_cone refuses, and invalid changes: replace's result or error, on every 2-complex."""
    vs = fresh(N_VERTS + 3)
    removed, cycle = _icosa_cavity(vs)
    p, q = vs[N_VERTS], vs[N_VERTS + 1]
    cone = cone_over(cycle, p)
    other = fresh(2)[1]  # a vertex of another lineage
    cases = {
        "the cone": (removed, cone),
        "out of order": (removed, cone[1:2] + cone[:1] + cone[2:]),
        "two apexes": (removed, cone[:-1] + [((cone[-1][0][0], cone[-1][0][1], q), 9)]),
        "too short": (removed[:1], cone_over(cycle[:2], p)),
        "a cycle vertex twice": (removed, cone_over(cycle + cycle, p)),
        "apex present": (removed, cone_over(cycle, vs[next(i for i in range(N_VERTS) if vs[i] not in cycle)])),
        "apex on the cycle": (removed, cone_over(cycle, cycle[0])),
        "foreign vertex": (removed, cone_over(cycle[:-1] + [other], p)),
        "absent triangle": (removed + [(cycle[0], cycle[2], cycle[1])], cone),
        "a triangle twice": (removed + removed[:1], cone),
        "a vertex off the cycle": (removed + [_off_the_cycle(vs, cycle)], cone),
        "a cycle vertex that drops nothing": (removed[:1], cone),
        "lists, not tuples": ([list(t) for t in removed], [(list(t), x) for t, x in cone]),
        "no triangles": ([], []),
    }
    for name, (rem, add) in cases.items():
        C = make(2)
        R = make(2)
        c = build(C, vs, ICOSA)
        before = items_of(C, c)
        want = outcome(lambda: lists_of(R, R.replace(build(R, vs, ICOSA), rem, add)))
        got = outcome(lambda: lists_of(C, replace_cone(C, c, rem, add)))
        assert got == want, name
        if got[0] != "ok" or type(C) is TwoComplex:  # the ephemeral baseline's old version is stale
            assert items_of(C, c) == before, name
    C = make(2)
    assert outcome(lambda: items_of(C, replace_cone(C, C.new(2), [], cone))) == outcome(
        lambda: items_of(C, C.replace(C.new(2), [], cone))
    )


def test_group_cone_refuses_what_is_not_a_cone() -> None:
    vs = fresh(N_VERTS + 2)
    C = two_complex("red_black")
    c = build(C, vs, ICOSA)
    removed, cycle = _icosa_cavity(vs)
    p = vs[N_VERTS]
    cone = cone_over(cycle, p)
    assert set(normalised(group_cone(removed, cone, c.lineage))) == {int(v) for v in cycle} | {int(p)}
    for rem, add in (
        (removed, cone[::-1]),
        (removed, cone_over(cycle[:2], p)),
        (removed, cone_over(cycle + cycle, p)),
        (removed, cone_over(cycle, cycle[1])),
        (removed + [_off_the_cycle(vs, cycle)], cone),
        (removed + [(cycle[0], cycle[0], cycle[1])], cone),
        ([list(t) for t in removed], cone),
    ):
        with pytest.raises(Unbatched):
            group_cone(rem, add, c.lineage)
    with pytest.raises(Unbatched):
        group_cone(removed, cone, None)  # an empty complex
    with pytest.raises(Unbatched):
        group_cone(removed, cone, fresh(1)[0].lineage)


def test_the_grouping_is_importable_from_the_lists_module() -> None:
    # The structures import the grouping from vertex_lists, which re-exports vertex_changes' names: the same
    # objects (on the compiled twin too, where both modules are compiled in one group).
    for name in vertex_changes.__all__:
        assert name in vertex_lists.__all__
        assert getattr(vertex_lists, name) is getattr(vertex_changes, name), name


def test_rebuild_cone_is_rebuild_fresh() -> None:
    """Drops of 0 to 4 pairs, found by identity or (for equal vertex objects that are not the list's) by ==;
    Missing for a pair not there or asked twice."""
    vs = fresh(8)
    twins = fresh(8)  # equal labels, other objects
    old = tuple((vs[i], vs[(i + 1) % 7], f"d{i}") for i in range(7))
    tail = ((vs[7], vs[0], "t0"), (vs[1], vs[7], "t1"))
    for k in range(5):
        for start in range(7):
            for objs in (vs, twins):
                pairs = [(objs[(start + 2 * i) % 7], objs[(start + 2 * i + 1) % 7]) for i in range(k)]
                if len(set(map(int, (a for a, _ in pairs)))) < k:
                    continue
                flat = [x for pr in pairs for x in pr]
                want = outcome(lambda: rebuild_fresh(old, (pairs, [tail[0]], [tail[1]])))
                got = outcome(lambda: rebuild_cone(old, (flat, tail)))
                assert got == want and got[0] == "ok"
                assert all(any(e is f for f in old + tail) for e in got[1])
    with pytest.raises(Missing):
        rebuild_cone(old, ([vs[0], vs[2]], tail))
    with pytest.raises(Missing):
        rebuild_cone(old, ([vs[0], vs[1], vs[0], vs[1]], tail))
    with pytest.raises(Missing):
        rebuild_cone(old, ([vs[0], vs[1], vs[0], vs[1], vs[2], vs[3]], tail))


@pytest.mark.parametrize("backend", ["red_black", "red_black_arena", "hamt", "assoc_list"])
def test_a_history_of_cones_is_that_of_replace(backend: str) -> None:
    """Twelve cavities coned in turn: every version replace's, valid, and unchanged by the later ones."""
    n_verts, tris = random_polytope(40, seed=11)
    C = two_complex(backend)
    vs = fresh(n_verts + 12)
    c = d = build(C, vs, tris)
    history = []
    rng = np.random.default_rng(2)
    for k in range(12):
        current = [t for t, _ in C.items(c)]
        index = {tuple(int(v) for v in t): t for t in current}
        labels = list(index)
        start = int(rng.integers(len(labels)))
        cav = cavities(labels, (1 + k % 4,), range(start, start + 1))[0]
        removed = [index[labels[i]] for i in cav]
        cycle = boundary_cycle(removed)
        assert cycle is not None
        added = cone_over(cycle, vs[n_verts + k], k, tag=f"v{k}")
        c, d = replace_cone(C, c, removed, added), C.replace(d, removed, added)
        assert lists_of(C, c) == lists_of(C, d)
        C.check(c)
        history.append((c, lists_of(C, c)))
    for version, model in history:
        assert lists_of(C, version) == model


@pytest.mark.parametrize(
    "points",
    [
        np.random.default_rng(4).random((300, 2)),
        np.stack(np.meshgrid(np.arange(12.0), np.arange(12.0)), -1).reshape(-1, 2),
        np.concatenate([[[i, 0.0] for i in range(15)], np.random.default_rng(5).random((60, 2)) * [14, 3]]),
    ],
    ids=["uniform", "grid", "collinear-hull"],
)
def test_the_delaunay_checks_its_cones_against_replace(points: np.ndarray) -> None:
    """``check=True`` compares every insertion's replace_cone with replace (closed fans and open ones, whose
    cycle passes through ∞) and raises on a difference; the triangulation is the unchecked run's."""
    checked = delaunay(points, seed=1, check=True)
    plain = delaunay(points, seed=1)
    assert np.array_equal(checked.triangles, plain.triangles)


@pytest.mark.parametrize("name,angle", [("circle", 30), ("comb", 30), ("fan", 20), ("utm-tile", 33)])
def test_the_meshs_insertions_are_cones_and_their_versions_replaces(
    name: str, angle: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The mesh's insertions with no triangle beyond and no deletion before (impl/mesh/triangulation.py's
    ``build``) go to replace_cone, and each is a cone (group_cone takes it); every version of the run, list for
    list and tree for tree, is that of the same run through replace_trusted, and a checked run (replace_cone
    against replace at every step) makes the same mesh."""
    from persistri.impl.mesh import api as mesh_api
    from persistri.impl.mesh import triangulation
    from persistri.impl.mesh.gallery import gallery_domain

    pslg = gallery_domain(name).pslg
    cones: list[bool] = []
    real_cone = triangulation.replace_cone

    def spied(S: Any, c: Any, removed: list[Any], added: list[Any]) -> Any:
        try:
            group_cone(removed, added, c[2])
            cones.append(True)
        except Unbatched:
            cones.append(False)
        return real_cone(S, c, removed, added)

    monkeypatch.setattr(triangulation, "replace_cone", spied)
    mesh = mesh_api.triangulate(pslg, min_angle=angle)
    assert cones and all(cones) and len(cones) <= mesh.insertions
    monkeypatch.setattr(triangulation, "replace_cone", triangulation.replace_trusted)
    model = mesh_api.triangulate(pslg, min_angle=angle)
    S, R = mesh.history.structure, model.history.structure
    assert len(mesh.history) == len(model.history) == mesh.insertions + 1
    for c, d in zip(mesh.history, model.history):
        assert lists_of(S, c) == lists_of(R, d)
    monkeypatch.setattr(triangulation, "replace_cone", real_cone)
    checked_class = triangulation.MeshTriangulation

    def checked(pred: Any, structure: Any) -> Any:
        return checked_class(pred, structure, check=True)

    monkeypatch.setattr(mesh_api, "MeshTriangulation", checked)
    again = mesh_api.triangulate(pslg, min_angle=angle)
    assert again.history.structure is not S
    assert [lists_of(again.history.structure, c) for c in again.history] == [lists_of(S, c) for c in mesh.history]
