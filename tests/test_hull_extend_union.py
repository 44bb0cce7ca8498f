"""extend_hull (:mod:`persistri.impl.hull.extend`): the hull of the union, as a rebuild makes it.

Extending the hull of A by B gives the faces (as row triples, outward) and the
vertices of the hull of A ∪ B, on every distribution, label order and backend,
with the Appendix A checks on the continuation; a chain of extensions gives the
hull of everything, extending one hull twice gives the same result twice, and
the continuation is the same run: its insertions and its counts go on from the
old hull's.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from persistri.impl.hull.api import convex_hull
from persistri.impl.hull.distributions import generate
from persistri.impl.hull.extend import extend_hull
from persistri.impl.hull.verify import verify_hull

from hull_extend_helpers import facets, oriented


# -- the same hull as a rebuild -------------------------------------------------------------------


@pytest.mark.parametrize("dist", ["InBall", "OnSphere", "BordHeavy", "PolHeavy"])
def test_extending_gives_the_hull_of_the_union(dist: str) -> None:
    """General position: the same faces (as row triples, outward) and vertices as the hull of A ∪ B."""
    A = generate(dist, 1500, seed=1)
    B = generate(dist, 700, seed=2) * 1.02
    old = convex_hull(A, seed=3)
    new = extend_hull(old, B)
    union = np.vstack([A, B])
    ref = convex_hull(union, seed=5)
    assert np.array_equal(new.points, union)
    assert oriented(new.simplices) == oriented(ref.simplices)
    assert new.vertices.tolist() == ref.vertices.tolist()
    assert facets(new.simplices) == facets(ConvexHull(union).simplices)
    assert verify_hull(union, new.simplices).ok
    assert new.insertions > old.insertions and new.seed == old.seed and new.backend == old.backend


@pytest.mark.parametrize("labels", ["spatial", "input"])
def test_check_mode_runs_the_appendix_checks_on_the_continuation(labels: str) -> None:
    A = generate("InBall", 300, seed=4)
    B = np.vstack([generate("OnSphere", 150, seed=5) * 1.1, generate("InBall", 100, seed=6) * 0.5])
    old = convex_hull(A, seed=1, labels=labels, check=True)
    new = extend_hull(old, B, check=True)
    assert new.labels == labels
    assert facets(new.simplices) == facets(ConvexHull(np.vstack([A, B])).simplices)


def test_a_chain_of_extensions_is_the_hull_of_everything() -> None:
    parts = [generate("InBall", 400, seed=s) * (1 + 0.05 * s) for s in range(5)]
    hull = convex_hull(parts[0], seed=2)
    for part in parts[1:]:
        hull = extend_hull(hull, part)
    union = np.vstack(parts)
    assert oriented(hull.simplices) == oriented(convex_hull(union).simplices)


def test_every_backend_extends_to_the_same_hull() -> None:
    A, B = generate("OnSphere", 300, seed=1), generate("OnSphere", 200, seed=2) * 1.01
    ref = extend_hull(convex_hull(A, seed=1), B).simplices
    for backend in ["hamt", "assoc_list", "immutables", "pyrsistent"]:
        got = extend_hull(convex_hull(A, seed=1, backend=backend), B)
        assert np.array_equal(got.simplices, ref), backend


def test_the_same_hull_extended_twice_gives_the_same_result() -> None:
    A, B = generate("InBall", 800, seed=1), generate("InBall", 300, seed=2) * 1.1
    old = convex_hull(A, seed=7, history=True)
    a, b = extend_hull(old, B), extend_hull(old, B)
    assert np.array_equal(a.simplices, b.simplices)
    assert a.history is not None and b.history is not None and a.history.inserted == b.history.inserted


# -- the counts go on -----------------------------------------------------------------------------


def test_counts_go_on_into_the_old_hulls_stats() -> None:
    from persistri.impl.stats import Stats

    stats = Stats()
    old = convex_hull(generate("InBall", 500, seed=1), stats=stats)
    tests, created = stats.plane_side_tests, stats.faces_created
    new = extend_hull(old, generate("OnSphere", 100, seed=2) * 1.2)
    assert new.stats is stats and stats.plane_side_tests > tests and stats.faces_created > created
