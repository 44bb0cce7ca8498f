"""Check 7 of :func:`~persistri.impl.mesh.verify.verify_mesh`: the quality a mesh reaches (Ruppert 1995; paper §1).

``angle`` — each triangle's smallest angle is at least ``min_angle``, decided
exactly (:mod:`~persistri.impl.mesh.angles`), except the triangles Ruppert's
algorithm must leave near small input angles (the exemption of
:mod:`~persistri.impl.mesh.verify`'s docstring, counted in ``exempt``);
``area-bound`` — each triangle's area is at most ``max_area`` and, with
``region_areas``, the bound of its region (exact rationals).  The report's
``min_angle``, ``max_area`` and ``min_angle_unexempt`` are filled in here.

Cost: O(t) vectorised floating-point angles (reports), exact tests only for the
triangles the float screen cannot clear, O(t) exact area comparisons.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import NDArray

from persistri.impl.mesh.angles import below_bound, smallest_corner, subtends_small_input_angle
from persistri.impl.mesh.domain import Domain
from persistri.impl.mesh.verify_report import ProblemLog

__all__ = ["check_quality"]


def check_quality(
    check: ProblemLog,
    dom: Domain,
    pts: NDArray[np.float64],
    tri: NDArray[np.intp],
    xl: list[int],
    yl: list[int],
    det: NDArray[Any],
    mesh_of: NDArray[np.intp],
    on_segments: dict[int, list[int]],
    tri_face: NDArray[Any],
    min_angle: float | None,
    max_area: float | None,
    region_areas: bool,
) -> None:
    """Check 7 (module docstring) on a mesh that passed the tiling checks: ``det`` twice each triangle's area in
    the faces' integer units, ``mesh_of`` the mesh row of each domain vertex, ``on_segments`` the segments each
    chain vertex is on, ``tri_face`` each triangle's face.  O(t)."""
    rep = check.rep
    t = tri.shape[0]
    P = pts[tri]  # (t, 3, 2)
    with np.errstate(all="ignore"):
        e = np.stack([P[:, 2] - P[:, 1], P[:, 0] - P[:, 2], P[:, 1] - P[:, 0]], axis=1)  # edge opposite corner i
        if t:  # each triangle scaled by a power of two (exact): near 1e-300 the products below would underflow
            e = np.ldexp(e, -np.frexp(np.abs(e).max(axis=(1, 2)))[1][:, None, None])
        cross = np.abs(e[:, 1, 0] * e[:, 2, 1] - e[:, 1, 1] * e[:, 2, 0])
        angles = np.stack(
            [np.arctan2(cross, -np.einsum("ij,ij->i", e[:, (i + 1) % 3], e[:, (i + 2) % 3])) for i in range(3)], axis=1
        )
    small = np.degrees(np.nanmin(angles, axis=1)) if t else np.zeros(0)
    rep.min_angle = float(small.min()) if t else None
    unit = Fraction(2) ** (2 * dom.faces.scale.exponent) / 2
    rep.max_area = float(max(det.tolist()) * unit) if t else None
    exempt = np.zeros(t, dtype=bool)
    if min_angle is not None and min_angle > 0:
        ends = [(int(mesh_of[u]), int(mesh_of[v])) for u, v in dom.pslg.segments.tolist()]
        for k in below_bound(pts, tri, xl, yl, min_angle):
            corner = smallest_corner(xl, yl, tri[k])
            p, q = int(tri[k, (corner + 1) % 3]), int(tri[k, (corner + 2) % 3])
            if subtends_small_input_angle(p, q, on_segments, ends, xl, yl):
                exempt[k] = True
                continue
            check.problem(
                "angle",
                f"triangle {k} {tri[k].tolist()} has a {small[k]:.6g}° angle at vertex {int(tri[k, corner])}, below {min_angle:g}°",
            )
    rep.exempt = int(exempt.sum())
    rest = small[~exempt]
    rep.min_angle_unexempt = float(rest.min()) if rest.size else None
    _area_bounds(check, dom, tri, det, tri_face, max_area, region_areas)


def _area_bounds(
    check: ProblemLog,
    dom: Domain,
    tri: NDArray[np.intp],
    det: NDArray[Any],
    tri_face: NDArray[Any],
    max_area: float | None,
    region_areas: bool,
) -> None:
    bounds: dict[int, Fraction] = {}
    for r, f in zip(dom.pslg.regions.tolist(), dom.region_face.tolist()):
        if region_areas and r[3] > 0:
            bounds[f] = min(bounds.get(f, Fraction(r[3])), Fraction(r[3]))
    if max_area is None and not bounds:
        return
    unit = Fraction(2) ** (2 * dom.faces.scale.exponent) / 2
    glob = None if max_area is None else Fraction(max_area)
    dets = det.tolist()
    faces = tri_face.tolist()
    for k in range(tri.shape[0]):
        limit = bounds.get(faces[k], glob)
        if limit is None:
            continue
        if glob is not None:
            limit = min(limit, glob)
        if dets[k] * unit > limit:
            check.problem("area-bound", f"triangle {k} {tri[k].tolist()} has area {float(dets[k] * unit):.6g}, above the bound {float(limit):g}")
