"""The bulldozer's edge index: the walk's answer to "which face is across this edge", kept beside the complex.

``Bulldozer._edges[u][w]`` is the entry of the face holding the directed edge
``(u, w)`` in the current version (:mod:`persistri.impl.hull.bulldozer`).  It
must mirror the complex after every insertion (the same faces, the same datum
objects), give the very versions that reading the complex gives, be off where
the walk has to ask the complex (stepwise, counted and recording structures,
resumed runs) and beside the ephemeral complex (a dict already), and ``check=True`` must catch an index that disagrees.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from persistri.impl.complex.simpcomp import two_complex
from persistri.impl.complex.trace import TracingTwoComplex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.geometry.predicates import Predicates3
from persistri.impl.hull.bulldozer import Bulldozer, BulldozerCheckError, initial_tetrahedron
from persistri.impl.hull.conflicts import all_but
from persistri.impl.hull.distributions import generate
from persistri.impl.hull.packed import conflict_list, face_id
from persistri.impl.stats import Stats


def _bulldozer(points: np.ndarray[Any, Any], S: TwoComplex[Any], **kw: Any) -> tuple[Bulldozer, np.ndarray[Any, Any]]:
    """A bulldozer over ``points`` (distinct rows) in ``S`` and its insertion order (seed 3)."""
    pred = Predicates3(points)
    n = len(points)
    tetra = initial_tetrahedron(pred, n)
    pred = pred.with_centroid(*tetra)
    bd = Bulldozer(pred, S, tetra, **kw)
    order = np.random.default_rng(3).permutation(all_but(n, tetra))
    return bd, order


def _index_mirrors(bd: Bulldozer) -> None:
    """Every directed edge of the current version is in the index under the face's own entry, and nothing else is."""
    index = bd._edges
    assert index is not None
    items = bd.S.items(bd.complex)
    for tri, datum in items:
        a, b, d = tri
        for u, w in ((a, b), (b, d), (d, a)):
            entry = index[u][w]
            assert entry[1] is datum  # the complex's own datum object
            t = entry[0]
            assert {(t[0], t[1]), (t[1], t[2]), (t[2], t[0])} == {(a, b), (b, d), (d, a)}
    assert sum(len(at) for at in index.values()) == 3 * len(items)


@pytest.mark.parametrize("dist", ["InBall", "OnSphere", "BordHeavy"])
@pytest.mark.parametrize(("backend", "pack"), [("red_black", False), ("red_black", True), ("hamt", False)])
def test_the_index_mirrors_every_version(dist: str, backend: str, pack: bool) -> None:
    bd, order = _bulldozer(generate(dist, 400, seed=5), two_complex(backend), pack=pack)
    _index_mirrors(bd)
    for _, _ in bd.run(order):
        _index_mirrors(bd)


def _listing(S: TwoComplex[Any], c: Any) -> list[tuple[tuple[int, ...], int, tuple[int, ...]]]:
    """A version as the complex stores it: every face in the stored order, with its id and conflict list."""
    return [
        (tuple(int(v) for v in t), face_id(x), tuple(int(q) for q in np.asarray(conflict_list(x)).tolist()))
        for t, x in S.items(c)
    ]


@pytest.mark.parametrize("dist", ["InBall", "OnSphere"])
def test_the_index_gives_the_versions_the_complex_gives(dist: str) -> None:
    """The walk reading the index and the walk reading the complex make the same versions, face for face in
    the complex's own order (the same rotations reach ``replace``, so every vertex list is the same)."""
    points = generate(dist, 800, seed=9)
    indexed, order = _bulldozer(points, two_complex("red_black"))
    plain, _ = _bulldozer(points, two_complex("red_black"))
    plain._edges = None  # the walk asks the complex
    S = indexed.S
    for (p, a), (q, b) in zip(indexed.run(order), plain.run(order)):
        assert p == q
        assert _listing(S, a) == _listing(S, b)
    assert indexed.pending() == plain.pending() == 0


def test_the_index_is_off_where_the_walk_asks_the_complex() -> None:
    points = generate("InBall", 200, seed=1)
    assert _bulldozer(points, two_complex("red_black"))[0]._edges is not None
    # The ephemeral complex's neighbour is a dict read already: no index beside it.
    assert _bulldozer(points, two_complex("ephemeral"))[0]._edges is None
    # stepwise: findi, as the paper's code; counted: the paper's look-ups; recording: every call recorded.
    assert _bulldozer(points, two_complex("red_black"), stepwise=True)[0]._edges is None
    assert _bulldozer(points, two_complex("red_black", Stats()))[0]._edges is None
    assert _bulldozer(points, two_complex("ephemeral", Stats()))[0]._edges is None
    assert _bulldozer(points, TracingTwoComplex(two_complex("red_black")))[0]._edges is None


def test_check_catches_an_index_that_disagrees_with_the_complex() -> None:
    bd, order = _bulldozer(generate("OnSphere", 300, seed=4), two_complex("red_black"), check=True)
    run = bd.run(order)
    for _ in range(20):
        next(run)
    index = bd._edges
    assert index is not None
    for at in index.values():
        for w, (tri, datum) in list(at.items()):
            at[w] = (tri, (datum[0], datum[1]))  # an equal datum, but not the complex's object
    with pytest.raises(BulldozerCheckError, match="edge index"):
        next(run)


def test_an_index_missing_an_edge_is_a_check_error() -> None:
    bd, order = _bulldozer(generate("InBall", 300, seed=6), two_complex("red_black"))
    run = bd.run(order)
    next(run)
    index = bd._edges
    assert index is not None
    for at in index.values():
        at.clear()
    with pytest.raises(BulldozerCheckError, match="not a closed surface"):
        next(run)
