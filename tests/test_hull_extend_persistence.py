"""extend_hull and persistence (:mod:`persistri.impl.hull.extend`): structure shared, the old hull intact.

A few points beyond one spot of a big hull leave every face they do not touch
the same object (its datum, the per-vertex lists, the map nodes); chains and
branches of extensions leave the old hull and every version of its history as
they were, recomputed from the complexes; the history goes on with one version
per new insertion, each the hull of the one before and the point inserted.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np
from scipy.spatial import ConvexHull

from persistri.impl.hull.api import convex_hull
from persistri.impl.hull.distributions import generate
from persistri.impl.hull.extend import extend_hull
from persistri.impl.hull.verify import verify_hull

from hull_extend_helpers import assert_unchanged, facets, oriented, snapshot


# -- structure sharing and persistence -------------------------------------------------------------


def tree_nodes(tree: Any) -> Iterator[Any]:
    """The nodes of one red-black tree ``(colour, left, key, value, right)``."""
    stack = [tree]
    while stack:
        node = stack.pop()
        if node is not None:
            yield node
            stack += [node[1], node[4]]


def test_faces_the_new_points_do_not_touch_are_shared() -> None:
    """A few points beyond one spot of a big hull: every face they leave alone is the same object (its
    datum, the per-vertex lists holding it, the map nodes), and the new version is a few dozen new tree
    nodes, where a rebuild makes every node anew."""
    A = generate("OnSphere", 4000, seed=1)
    old = convex_hull(A, seed=2)
    spot = A[0] / np.linalg.norm(A[0])
    B = spot * 1.02 + generate("InBall", 10, seed=3) * 0.02
    new = extend_hull(old, B)
    S = old.structure
    old_faces = {t: x for t, x in S.items(old.complex)}
    new_faces = {t: x for t, x in S.items(new.complex)}
    common = old_faces.keys() & new_faces.keys()
    assert len(common) > 0.95 * len(old_faces)
    assert all(new_faces[t] is old_faces[t] for t in common)
    old_nodes = {id(node): node for node in tree_nodes(old.complex.rep[1])}
    new_nodes = list(tree_nodes(new.complex.rep[1]))
    made = [node for node in new_nodes if id(node) not in old_nodes]
    assert 0 < len(made) < 0.1 * len(new_nodes)
    # Each vertex's list is the old tuple unless a triangle at that vertex changed.
    changed = {v for t in old_faces.keys() ^ new_faces.keys() for v in t}
    lists_old = {node[2]: node[3] for node in old_nodes.values()}
    for node in new_nodes:
        if node[2] not in changed:
            assert node[3] is lists_old[node[2]]
    rebuilt = convex_hull(np.vstack([A, B]), seed=2)
    assert not {id(n) for n in tree_nodes(rebuilt.complex.rep[1])} & old_nodes.keys()
    assert oriented(new.simplices) == oriented(rebuilt.simplices)


def test_the_old_hull_and_its_history_are_unchanged_by_chains_and_branches() -> None:
    """Thousands of points, extended three times in a chain and twice from the same hull: every array
    recomputed from every kept complex (the old hull's, its bulldozer version, all its history) is as before."""
    A = generate("InBall", 4000, seed=1)
    base = convex_hull(A, seed=4, history=True)
    kept = [(base, snapshot(base))]
    hull = base
    for s in range(3):
        hull = extend_hull(hull, generate("OnSphere", 1500, seed=10 + s) * (1.0 + 0.01 * s))
        kept.append((hull, snapshot(hull)))
    left = extend_hull(base, generate("BordHeavy", 3000, seed=20) * 1.05)
    right = extend_hull(base, generate("OnSphere", 3000, seed=21) * 1.03)
    chained = extend_hull(kept[1][0], generate("InBall", 2000, seed=22) * 1.2)
    for h, snap in kept:
        assert_unchanged(h, snap)
    for h in (left, right, chained):
        assert verify_hull(h.points, h.simplices).ok
        assert h.history is not None and base.history is not None
        assert all(x is y for x, y in zip(h.history.versions, base.history.versions))
    assert snapshot(left)["complex"] != kept[0][1]["complex"]  # the comparison above can see a difference
    # The branches differ from each other and share the old versions.
    assert oriented(left.simplices) != oriented(right.simplices)
    assert facets(left.simplices) == facets(ConvexHull(left.points).simplices)
    assert facets(right.simplices) == facets(ConvexHull(right.points).simplices)


def test_the_history_continues_with_one_version_per_new_insertion() -> None:
    A, B = generate("BordHeavy", 200, seed=2), generate("OnSphere", 100, seed=3) * 1.3
    old = convex_hull(A, seed=3, history=True)
    new = extend_hull(old, B)
    H, O = new.history, old.history
    assert H is not None and O is not None
    assert len(H) == new.insertions + 1 == len(O) + (new.insertions - old.insertions)
    assert H.inserted[: len(O)] == O.inserted and all(r >= len(A) for r in H.inserted[len(O) :])
    # Each new version is the hull of the one before and the point inserted; the old ones read as before.
    for k in range(len(O), len(H)):
        sub = np.array(sorted(set(H.vertices(k - 1).tolist()) | {H.inserted[k]}))
        local = {row: i for i, row in enumerate(sub.tolist())}
        tri = np.vectorize(local.__getitem__)(H.simplices(k))
        assert verify_hull(new.points[sub], tri).ok
    for k in range(len(O)):
        assert np.array_equal(H.simplices(k), O.simplices(k))
    assert H.pending(len(H) - 1).size == 0
    without = extend_hull(convex_hull(A, seed=3), B)
    assert without.history is None and np.array_equal(without.simplices, new.simplices)
