"""The constrained Delaunay triangulation of PSLGs (impl/mesh/cdt.py, triangulation.py): exact, on the persistent complex."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
import triangle as tr
from hypothesis import given, settings

from mesh_helpers import check_mesh, circle, hole_square_area2, l_shape, pslgs, ring, square_with_hole, twice_area
from persistri.impl.complex.replace import same_replace
from persistri.impl.mesh.api import MeshHistory, triangulate
from persistri.impl.mesh.domain import as_pslg
from persistri.impl.mesh.triangulation import EXTERIOR, MeshError


def _check(m, area2=None):  # type: ignore[no-untyped-def]
    check_mesh(m.domain, m.vertices, m.triangles, m.segments, m.segment_of, area2=area2)


def test_square_with_hole_is_a_cdt_with_the_hole_empty() -> None:
    m = triangulate(square_with_hole())
    _check(m, area2=Fraction(2 * 15))  # 16 - 1, twice
    centroids = m.vertices[m.triangles].mean(axis=1)
    inside_hole = np.all((centroids > 1) & (centroids < 2), axis=1)
    assert not inside_hole.any()
    assert m.vertices.shape == (8, 2) and len(m.history) == 1 and m.insertions == 0


def test_concavity_is_eaten() -> None:
    # A U shape: the notch between its arms is inside the hull but not in the domain.
    u = as_pslg([[0, 0], [3, 0], [3, 3], [2, 3], [2, 1], [1, 1], [1, 3], [0, 3]], ring(8))
    m = triangulate(u)
    _check(m, area2=Fraction(2 * 7))


def test_segments_are_recorded_on_both_sides_in_the_version() -> None:
    m = triangulate(square_with_hole())
    S, c = m.history.structure, m.complex
    sides: dict[tuple[int, int], int] = {}
    for t, (_, region, cons) in S.items(c):
        for lo, hi, s in cons:
            sides[(lo, hi)] = sides.get((lo, hi), 0) + 1
    assert len(sides) == 8 and set(sides.values()) == {2}
    regions = {d[1] for _, d in S.items(c)}
    assert regions == {0, EXTERIOR}


def test_cocircular_grid_with_constraints() -> None:
    # Every 4 neighbours of an integer grid are cocircular: SoS decides, the CDT stays exact.
    g = np.array([[x, y] for y in range(6) for x in range(6)], dtype=np.float64)
    idx = lambda x, y: 6 * y + x  # noqa: E731
    boundary = [[idx(x, 0), idx(x + 1, 0)] for x in range(5)] + [[idx(5, y), idx(5, y + 1)] for y in range(5)]
    boundary += [[idx(x + 1, 5), idx(x, 5)] for x in range(5)] + [[idx(0, y + 1), idx(0, y)] for y in range(5)]
    diagonal = [[idx(1, 1), idx(4, 4)]]  # passes through (2, 2) and (3, 3): split there
    m = triangulate(as_pslg(g, boundary + diagonal))
    _check(m, area2=Fraction(50))
    assert m.triangles.shape[0] == 50


def test_collinear_boundary_vertices_make_no_flat_triangle() -> None:
    pts = [[0, 0], [1, 0], [2, 0], [3, 0], [3, 1], [0, 1]]
    m = triangulate(as_pslg(pts, ring(6)))
    _check(m, area2=Fraction(6))


@pytest.mark.parametrize("offset", [(5e5, 4e6), (6.5e6, 1.25e7)])
def test_utm_offsets_are_exact(offset: tuple[float, float]) -> None:
    # Centimetre features at UTM magnitudes: every decision exact, the area exact.
    d = square_with_hole(offset=offset, size=0.04)
    cdt = triangulate(d)
    _check(cdt, area2=hole_square_area2(d))
    m = triangulate(d, min_angle=30)
    _check(m, area2=hole_square_area2(d))
    assert m.min_angle_reached and m.segment_splits > 0


def test_dictionary_input_as_triangle_takes_it() -> None:
    m = triangulate({"vertices": [[0, 0], [2, 0], [2, 2], [0, 2]], "segments": ring(4)})
    assert m.triangles.shape == (2, 3)


@settings(max_examples=40)
@given(pslgs())
def test_random_pslgs_give_exact_cdts(data: tuple[np.ndarray, np.ndarray]) -> None:
    verts, segs = data
    d = as_pslg(verts, segs, convex=True)
    m = triangulate(d)
    # Triangle's CDT of the same domain covers the same area (its vertices are the input's: exact).
    ref = tr.triangulate(d.to_dict(), "p")
    _check(m, area2=twice_area(ref["vertices"], ref["triangles"]))
    assert m.triangles.shape[0] == ref["triangles"].shape[0]


def _free_vertices(m):  # type: ignore[no-untyped-def]
    """The circumcentres and off-centres of a refined mesh's last version: on no segment, not input."""
    geo = m._run.geo
    return [int(v) for v in m.history.mesh(len(m.history) - 1).points if v >= geo.n_input and v not in geo.on_segment]


@pytest.mark.parametrize("make, angle, area", [(square_with_hole, 30.0, 0.3), (l_shape, 33.0, 0.02), (circle, 20.0, 0.05)])
def test_removing_a_free_vertex_leaves_the_cdt_of_the_rest(make, angle, area) -> None:  # type: ignore[no-untyped-def]
    # Chew's deletion: the star of a free vertex replaced by the Delaunay triangulation of its link, a new version.
    d = make()
    m = triangulate(d, min_angle=angle, max_area=area)
    T, S, last = m._run.T, m.history.structure, m.complex
    free = _free_vertices(m)
    assert len(free) >= 5
    before = m.history.mesh(len(m.history) - 1)
    for v in free[:: max(1, len(free) // 8)]:
        start = next((t, x) for t, x in S.items(last) if v in t)
        step = T.remove(last, v, start)
        after = MeshHistory(m._run, [step.version], []).mesh(0)
        check_mesh(d, after.vertices, after.triangles, after.segments, after.segment_of, area2=twice_area(before.vertices, before.triangles))
        assert v not in after.points.tolist() and after.points.size == before.points.size - 1
        assert len(step.created) == len(step.removed) - 2  # a star of k triangles, a polygon of k vertices
        # Through the trusted entry: the same version the public replace makes.
        public = S.replace(last, [t for t, _ in step.removed], list(step.created))
        assert same_replace(S, step.version, public, [t for t, _ in step.removed], list(step.created))
    # The version removed from is untouched.
    again = m.history.mesh(len(m.history) - 1)
    assert np.array_equal(again.triangles, before.triangles) and np.array_equal(again.vertices, before.vertices)


def test_removing_a_segment_vertex_is_refused() -> None:
    m = triangulate(square_with_hole(), min_angle=30, max_area=0.3)
    T, S, last = m._run.T, m.history.structure, m.complex
    v = next(iter(m._run.geo.on_segment))
    start = next((t, x) for t, x in S.items(last) if v in t)
    with pytest.raises(MeshError, match="only free vertices"):
        T.remove(last, v, start)
