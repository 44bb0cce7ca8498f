"""The CDT's scratch triangulation (impl/mesh/scratch.py): the builder's steps on it give the triangulation they give
on the persistent complex, which then holds the CDT as one version."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mesh_helpers import circle, l_shape, pslgs, square_with_hole
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.maps import backend
from persistri.impl.mesh.cdt import _Builder, constrained_delaunay
from persistri.impl.mesh.domain import PSLG, as_pslg
from persistri.impl.mesh.gallery import gallery_domain
from persistri.impl.mesh.scratch import ScratchComplex
from persistri.impl.mesh.triangulation import MeshError, MeshTriangulation


def _steps(T: MeshTriangulation, domain: PSLG) -> tuple[set[tuple[int, ...]], set[tuple[int, int, int]]]:
    """The builder's vertices and segments on ``T``: its triangles (from their smallest vertex) and constraints."""
    builder = _Builder(T)
    cx = builder.vertices(domain.vertices.shape[0])
    for s, (a, b) in enumerate(np.asarray(domain.segments).tolist()):
        if a != b:
            cx = builder.segment(cx, a, b, s)
    tris = {tuple(int(v) for v in t) for t, _ in T.S.items(cx)}
    cons = {c for _, d in T.S.items(cx) for c in d[2]} | {(int(lo), int(hi), s) for (lo, hi), (s, _) in builder.marked.items()}
    return tris, cons


def _both(domain: PSLG) -> None:
    persistent = MeshTriangulation(GrowingPredicates2(domain.vertices), TwoComplex(backend("red_black")))
    scratch_of = MeshTriangulation(GrowingPredicates2(domain.vertices), TwoComplex(backend("red_black")))
    scratch = scratch_of.with_structure(ScratchComplex())
    assert _steps(persistent, domain) == _steps(scratch, domain)


@pytest.mark.parametrize("make", [square_with_hole, l_shape, lambda: circle(40)])
def test_the_builder_makes_the_same_triangulation_on_scratch(make: Any) -> None:
    _both(make())


@pytest.mark.parametrize("name", ["comb", "crack", "utm-tile", "needle", "fan", "star"])
def test_the_gallery_cdts_agree(name: str) -> None:
    _both(gallery_domain(name).pslg)


@settings(max_examples=25, deadline=None)
@given(pslgs())
def test_random_pslgs_agree(data: tuple[np.ndarray, np.ndarray]) -> None:
    verts, segs = data
    _both(as_pslg(verts, segs, convex=True))


def test_the_cdt_is_one_version_with_ids_after_the_scratch_ones() -> None:
    domain = square_with_hole()
    T = MeshTriangulation(GrowingPredicates2(domain.vertices), TwoComplex(backend("red_black")))
    cx, _ = constrained_delaunay(T, domain)
    ids = [d[0] for _, d in T.S.items(cx)]
    assert len(set(ids)) == len(ids)
    assert T.new_datum(0)[0] > max(ids)  # the refinement's ids never meet the CDT's


def test_scratch_operations() -> None:
    T = MeshTriangulation(GrowingPredicates2(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])), TwoComplex(backend("red_black")))
    S = ScratchComplex()
    v0, v1, v2, v3 = (T.vertex(i) for i in range(4))
    c = S.new(2)
    c = S.add(c, (v0, v1, v2), T.new_datum(0))
    c = S.add(c, (v1, v3, v2), T.new_datum(0))
    assert S.data(c, (v1, v2, v0)) is not None and S.data(c, (v0, v2, v1)) is None
    found = S.neighbour(c, (v2, v1))
    assert found is not None and found[0] == (v2, v1, v3)
    assert S.neighbours(c)((v1, v0)) is None
    assert {tuple(sorted(int(v) for v in t)) for t in S.grep(c, 2, (v1,))} == {(0, 1, 2), (1, 2, 3)}
    assert sorted(tuple(int(v) for v in t) for t, _ in S.items(c)) == [(0, 1, 2), (1, 3, 2)]
    with pytest.raises(MeshError):
        S.add(c, (v0, v1, v3), T.new_datum(0))  # the edge (v0, v1) is in a triangle already
    with pytest.raises(MeshError):
        S.replace(c, [(v0, v3, v2)], [])
    fresh = T.new_datum(5)
    c = S.replace(c, [(v2, v0, v1)], [((v1, v2, v0), fresh)])
    assert S.data(c, (v0, v1, v2)) == (fresh,)
    c = S.replace(c, [(v0, v1, v2)], [])
    assert S.data(c, (v0, v1, v2)) is None and S.neighbour(c, (v1, v2)) is None


def _scratch_state(points: np.ndarray, on_scratch: bool) -> tuple[Any, ...]:
    """The scratch dictionary after the builder's vertex insertions (its entries in order, the edge out of each
    vertex, the next datum id), inserted by ``scratch.insert_vertex`` or by ``T.locate`` and ``T.insert``."""
    T = MeshTriangulation(GrowingPredicates2(points), TwoComplex(backend("red_black")))
    S = T.with_structure(ScratchComplex())
    cx = _Builder(S, on_scratch=on_scratch).vertices(points.shape[0])
    edges = [(int(u), int(w), int(x), d) for (u, w), (x, d) in cx.edges.items()]
    out = [(int(v), int(e[0]), int(e[1])) for v, e in cx.out.items()]
    return edges, out, S.new_datum(0)[0]


@pytest.mark.parametrize("name", ["circle", "comb", "star", "utm-tile", "needle", "fan", "square-hole"])
def test_insert_vertex_is_locate_and_insert_step_for_step(name: str) -> None:
    # The same dictionary, entry for entry and in the same order: the CDT built on it cannot differ.
    pts = np.asarray(gallery_domain(name).pslg.vertices)
    assert _scratch_state(pts, True) == _scratch_state(pts, False)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 9), st.integers(0, 9)), min_size=3, max_size=90, unique=True))
def test_insert_vertex_agrees_on_grids(pts: list[tuple[int, int]]) -> None:
    # Integer grids: collinear points on the hull (the ghost rule) and cocircular ones (exact incircle and SoS); past
    # 64 points the builder's Hilbert order.
    arr = np.array(pts, dtype=np.float64)
    if np.linalg.matrix_rank(arr[1:] - arr[0]) < 2:
        arr = np.vstack([arr, [[10.0, 0.3]]])  # on no line through two grid points
    assert _scratch_state(arr, True) == _scratch_state(arr, False)
