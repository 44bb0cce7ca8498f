"""triangulate / refine (impl/mesh/api.py): every step a version, two futures of one CDT, errors."""

from __future__ import annotations

import numpy as np
import pytest

from mesh_helpers import check_mesh, check_quality, l_shape, square_with_hole
from persistri.impl.mesh.api import QualityMesh, refine, triangulate
from persistri.impl.mesh.domain import PSLG


def _snapshot(m: QualityMesh) -> list[tuple[bytes, bytes, bytes]]:
    out = []
    for k in range(len(m.history)):
        a = m.history.mesh(k)
        out.append((a.vertices.tobytes(), np.sort(np.sort(a.triangles, axis=1), axis=0).tobytes(), a.segments.tobytes()))
    return out


def _check_all_versions(d: PSLG, m: QualityMesh) -> None:
    for k in range(len(m.history)):
        a = m.history.mesh(k)
        check_mesh(d, a.vertices, a.triangles, a.segments, a.segment_of)


def test_history_has_every_version_and_each_is_a_cdt() -> None:
    d = square_with_hole()
    m = triangulate(d, min_angle=30, max_area=0.5)
    assert len(m.history) == m.insertions + 1 == len(m.history.inserted) + 1
    _check_all_versions(d, m)
    sizes = [m.history.mesh(k).vertices.shape[0] for k in range(len(m.history))]
    # One vertex per step, less the free vertices Chew's rule deleted in it (before a segment split).
    assert len(m.history.deleted) == len(m.history.inserted)
    assert all(sizes[k + 1] == sizes[k] + 1 - len(m.history.deleted[k]) for k in range(len(sizes) - 1))
    assert sum(map(len, m.history.deleted)) == m.deletions
    last = m.history.mesh(len(m.history) - 1)
    assert np.array_equal(last.triangles, m.triangles) and np.array_equal(last.vertices, m.vertices)


def test_two_futures_of_one_cdt_both_stay_valid() -> None:
    d = l_shape()
    cdt = triangulate(d)
    before = _snapshot(cdt)
    fine = refine(cdt, min_angle=30, max_area=0.1)
    snap_fine = _snapshot(fine)
    coarse_small = refine(cdt, min_angle=20, max_area=0.01)
    # Both futures start at the CDT's version; the runs share the complex's structure and point set.
    assert fine.history[0] is cdt.complex and coarse_small.history[0] is cdt.complex
    assert fine.min_angle_reached and coarse_small.min_angle_reached and coarse_small.max_area_reached
    # Every version of both, rechecked after both runs: unchanged and valid.
    assert _snapshot(cdt) == before and _snapshot(fine) == snap_fine
    _check_all_versions(d, fine)
    _check_all_versions(d, coarse_small)
    check_quality(fine.vertices, fine.triangles, 30, 0.1, exempt=fine.exempt)
    check_quality(coarse_small.vertices, coarse_small.triangles, 20, 0.01, exempt=coarse_small.exempt)
    # The second future's Steiner points come after the first's in the shared, append-only point set.
    assert min(coarse_small.history.inserted) > max(fine.history.inserted)


def test_refine_continues_a_refined_mesh() -> None:
    d = square_with_hole()
    m20 = triangulate(d, min_angle=20)
    m33 = refine(m20, min_angle=33, max_area=0.2)
    assert m33.history[0] is m20.complex and m33.triangles.shape[0] > m20.triangles.shape[0]
    check_quality(m33.vertices, m33.triangles, 33, 0.2, exempt=m33.exempt)


@pytest.mark.parametrize("backend", ["int_trie", "red_black"])  # the default, and the paper's tree
def test_versions_share_structure(backend: str) -> None:
    m = triangulate(l_shape(), min_angle=30, max_area=0.01, backend=backend)

    def nodes(root):  # type: ignore[no-untyped-def]
        """Every tuple reachable from a version: its map's nodes and the vertices' entry lists."""
        stack = [root]
        while stack:
            node = stack.pop()
            if isinstance(node, tuple):
                yield node
                stack += node

    per_version = [list(nodes(v.rep)) for v in m.history]
    assert min(map(len, per_version[1:])) > 100
    distinct = {id(node) for found in per_version for node in found}
    assert len(distinct) < sum(map(len, per_version)) / 5


@pytest.mark.parametrize(
    "kwargs, error, match",
    [
        ({"min_angle": -1}, ValueError, "min_angle"),
        ({"min_angle": 60}, ValueError, "min_angle"),
        ({"min_angle": "30"}, TypeError, "min_angle"),
        ({"max_area": 0.0}, ValueError, "max_area"),
        ({"max_area": float("nan")}, ValueError, "max_area"),
        ({"backend": "nope"}, Exception, "backend"),
        ({"encroachment": "bad"}, ValueError, "encroachment must be 'lens'"),  # no refinement runs: still refused
        ({"encroachment": "bad", "min_angle": 20}, ValueError, "encroachment must be 'lens'"),
        ({"max_steiner": -1}, ValueError, "max_steiner must be a nonnegative integer"),
        ({"check": "yes"}, TypeError, "check must be True or False, not str 'yes'"),
        ({"offcenters": "no", "min_angle": 20}, TypeError, "offcenters must be True or False"),
        ({"exact_segments": 1}, TypeError, "exact_segments must be True or False, not int 1"),
    ],
)
def test_bad_arguments_are_one_line_errors(kwargs: dict[str, object], error: type[Exception], match: str) -> None:
    with pytest.raises(error, match=match) as info:
        triangulate(square_with_hole(), **kwargs)  # type: ignore[arg-type]
    assert "\n" not in str(info.value)


def test_refine_takes_a_mesh() -> None:
    with pytest.raises(TypeError, match="QualityMesh"):
        refine(square_with_hole(), min_angle=20)  # type: ignore[arg-type]


def test_unvalidated_pslg_is_validated() -> None:
    raw = PSLG(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), np.array([[0, 1], [1, 3], [3, 0]]))
    m = triangulate(raw)
    assert m.triangles.shape == (1, 3)


def test_check_runs_the_exact_checker() -> None:
    m = triangulate(square_with_hole(), min_angle=33, max_area=0.2, check=True)
    assert m.min_angle_reached and m.max_area_reached


@pytest.mark.parametrize("scale", [1.0, 2.0**-60, 2.0**-996, 2.0**-1000])  # 2^-996 ≈ 1.5e-300: exact scalings
def test_angles_are_measured_alike_at_every_scale(scale: float) -> None:
    """Angles do not depend on scale: near 1e-300 the products of the edge vectors underflow unless each
    triangle is first scaled by a power of two (exactly) — it read 0° or 180° before."""
    from persistri.impl.mesh.api import smallest_angle
    from persistri.impl.mesh.plot import smallest_angles
    from persistri.impl.mesh.verify import verify_mesh

    outline = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 1.0], [0.0, 1.0]]) * scale
    domain = {"vertices": outline, "segments": [[0, 1], [1, 2], [2, 3], [3, 0]]}
    mesh = triangulate(domain, min_angle=30)
    unit = triangulate({"vertices": outline / scale, "segments": domain["segments"]}, min_angle=30)
    assert mesh.triangles.tolist() == unit.triangles.tolist()
    assert smallest_angle(mesh.vertices, mesh.triangles) == smallest_angle(unit.vertices, unit.triangles) > 30
    assert smallest_angles(mesh.vertices, mesh.triangles).tolist() == smallest_angles(unit.vertices, unit.triangles).tolist()
    report = verify_mesh(domain, mesh.vertices, mesh.triangles, min_angle=30)
    assert report.ok and report.min_angle_unexempt == verify_mesh(
        {"vertices": outline / scale, "segments": domain["segments"]}, unit.vertices, unit.triangles, min_angle=30
    ).min_angle_unexempt
