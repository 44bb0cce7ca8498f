"""Deleting a free vertex (impl/mesh/deletion.py): the link's triangulation with the filters inlined and without.

``link_polygon`` decides its orientations and incircle tests by the predicates' float filters written out in the
loop, exactly whenever a filter cannot tell; a counted run (predicates with a ``Stats``) goes through the predicates'
own methods instead.  Both must triangulate every link alike — or refuse it alike — on random, cocircular and
UTM-offset polygons.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from persistri.impl.complex.vertex import VertexState, Vertex
from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.datum import MeshError, Tri
from persistri.impl.mesh.deletion import link_polygon
from persistri.impl.stats import Stats


def triangulated(P: GrowingPredicates2, n: int) -> list[tuple[int, int, int]] | str:
    lineage = VertexState.initial().lineage
    vs = [Vertex(i, None, lineage) for i in range(n)]
    out: list[Tri] = []
    try:
        link_polygon(P, vs[0], vs[1], vs[:1:-1], out)
    except MeshError as exc:
        return str(exc)
    return [(int(a), int(b), int(c)) for a, b, c in out]


@settings(max_examples=150)
@given(
    st.lists(st.floats(0.0, 2 * math.pi, exclude_max=True), min_size=3, max_size=12, unique=True),
    st.lists(st.floats(0.5, 2.0), min_size=12, max_size=12),
    st.sampled_from([0.0, 5.0e5, 4.0e6]),
    st.booleans(),
)
def test_inlined_filters_triangulate_every_link_as_the_predicates_do(
    angles: list[float], radii: list[float], offset: float, cocircular: bool
) -> None:
    angles = sorted(angles)
    r = [1.0] * len(angles) if cocircular else radii[: len(angles)]
    pts = np.array([[offset + ri * math.cos(t), offset + ri * math.sin(t)] for ri, t in zip(r, angles)])
    fast = triangulated(GrowingPredicates2(pts), len(angles))
    counted = triangulated(GrowingPredicates2(pts, stats=Stats()), len(angles))
    assert fast == counted


def test_a_square_link_is_split_by_symbolic_perturbation_alike() -> None:
    pts = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [0.6, -0.8]])  # five points on one circle
    stats = Stats()
    assert triangulated(GrowingPredicates2(pts), 5) == triangulated(GrowingPredicates2(pts, stats=stats), 5)
    assert stats.filter_failures > 0  # the ties went to the exact path
