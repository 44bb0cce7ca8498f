"""A segment with the outside on both sides (a hole against the domain's boundary) needs no mesh edges.

The 4 × 4 square with a 2 × 2 hole whose left side lies on the square's: segment (0, 3)-(0, 1) separates
the hole from the exterior, no triangle touches it, and the exact checker must accept the mesh (it said
"not a union of mesh edges", so ``persistri mesh --check`` refused a right mesh).
"""

from __future__ import annotations

import numpy as np
import pytest

import persistri

NOTCH = {
    "vertices": [[0, 0], [4, 0], [4, 4], [0, 4], [0, 1], [2, 1], [2, 3], [0, 3]],
    "segments": [[0, 1], [1, 2], [2, 3], [3, 7], [7, 4], [4, 0], [4, 5], [5, 6], [6, 7]],
    "holes": [[1, 2]],
}


@pytest.mark.parametrize("min_angle", [0.0, 20.0, 30.0])
def test_a_hole_against_the_boundary_is_verified(min_angle: float) -> None:
    mesh = persistri.triangulate(NOTCH, min_angle=min_angle)
    report = persistri.verify_mesh(mesh.domain, mesh.vertices, mesh.triangles, min_angle=min_angle or None)
    assert report.ok, report
    v, t = np.asarray(mesh.vertices), np.asarray(mesh.triangles)
    a, b = v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]
    assert float(np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])) / 2 == 12.0  # 16 less the hole's 4


def test_a_mesh_over_the_hole_is_still_refused() -> None:
    square = persistri.triangulate({"vertices": [[0, 0], [4, 0], [4, 4], [0, 4]], "segments": [[0, 1], [1, 2], [2, 3], [3, 0]]})
    mesh = persistri.triangulate(NOTCH)
    assert not persistri.verify_mesh(mesh.domain, square.vertices, square.triangles).ok
