"""The region a clean PSLG describes (Triangle's domain model): its faces, which of them are kept, its area.

:func:`domain_of` traces the segments' faces (:mod:`~persistri.impl.mesh.faces`),
places each hole and region point in one, and keeps the bounded faces that hold
no hole point: Triangle's convex hull of the vertices "with concavities and holes
eaten away", as :mod:`~persistri.impl.mesh.domain` describes it.  Validation
(:func:`~persistri.impl.mesh.domain.as_pslg`) calls it to refuse holes and regions
outside every boundary and empty domains; the checker
(:mod:`~persistri.impl.mesh.verify`) calls it for the domain a mesh must cover.
Every decision is exact (integer coordinates, :class:`~persistri.impl.geometry.predicates.Predicates2`).
The paper (§1) motivates the application; the domain model is Triangle's.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from persistri.impl.geometry.exact import IntegerScale
from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.mesh.errors import DomainError
from persistri.impl.mesh.faces import UNBOUNDED, PlanarFaces, planar_faces
from persistri.impl.mesh.naming import InputNames
from persistri.impl.mesh.segments import FEW_SEGMENTS, convex_hull, point_text

if TYPE_CHECKING:
    from persistri.impl.mesh.domain import PSLG

__all__ = ["Domain", "domain_of"]



@dataclass(frozen=True, eq=False)
class Domain:
    """The region a clean PSLG describes: its segments' faces and which of them are kept.

    * ``faces`` — the :class:`~persistri.impl.mesh.faces.PlanarFaces` of the segments;
    * ``kept`` — per bounded face, whether it is in the domain (it holds no hole point);
    * ``hole_face`` / ``region_face`` — the face of each hole and region point;
    * ``vertex_inside`` — per vertex, whether it is in the closed domain (on a kept
      face's boundary or inside a kept face): the vertices a mesh must have;
    * ``area`` — the domain's exact area.
    """

    pslg: PSLG
    faces: PlanarFaces
    kept: NDArray[np.bool_]
    hole_face: NDArray[np.intp]
    region_face: NDArray[np.intp]
    vertex_inside: NDArray[np.bool_]
    area: Fraction

    @property
    def area2(self) -> int:
        """Twice the area in the faces' scaled integer units (``faces.scale``)."""
        return sum(a for a, k in zip(self.faces.face_area2, self.kept.tolist()) if k)

    def left_kept(self, h: int) -> bool:
        """Whether the face on the left of half-edge ``h`` is in the domain. O(1)."""
        f = self.faces.face_of_half_edge(h)
        return f != UNBOUNDED and bool(self.kept[f])

    def boundary_coefficient(self, s: int) -> int:
        """+1 if segment ``s`` (as listed) has the domain on its left only, -1 on its right only, else 0.

        The domain's boundary, as a chain, is the sum of these times the segments. O(1).
        """
        return int(self.left_kept(2 * s)) - int(self.left_kept(2 * s + 1))


def domain_of(pslg: PSLG, *, scale: IntegerScale | None = None, pred: Predicates2 | None = None) -> Domain:
    """The faces of a clean PSLG (as :func:`as_pslg` makes it), which are kept, and its exact area.

    Raises :class:`DomainError` for a hole or region point on the graph or
    outside every boundary, and for an empty domain.  ``scale`` (default: the
    least for the vertices) fixes the faces' integer units.  ``pred``: a
    :class:`Predicates2` over the vertices followed by the hole and region
    points, if one exists already.  Cost: :func:`~persistri.impl.mesh.faces.planar_faces`
    and one point location per hole, region point and isolated vertex.
    """
    verts, seg = pslg.vertices, pslg.segments
    n = verts.shape[0]
    faces = planar_faces(verts, seg, scale=scale)  # default: the least scale for the vertices
    kept = np.ones(faces.n_faces, dtype=bool)
    hull: list[int] | None = None

    def place(p: NDArray[np.float64], what: str, k: int, row: int) -> int:
        nonlocal hull, pred
        where = faces.locate(float(p[0]), float(p[1]))
        if where.vertex is not None:
            names = InputNames.of(pslg.segment_origin, pslg.vertex_map)  # messages name the input's rows
            raise DomainError(f"{what} {k} at {point_text(p)} is on vertex {names.vertex(where.vertex)}")
        if where.segment is not None:
            names = InputNames.of(pslg.segment_origin, pslg.vertex_map)
            a, b = (point_text(verts[v]) for v in seg[where.segment])
            raise DomainError(f"{what} {k} at {point_text(p)} lies on {names.segment(where.segment, a, b)}")
        if where.face == UNBOUNDED:
            if pred is None:
                pred = Predicates2(np.concatenate([verts, pslg.holes, pslg.regions[:, :2]]))
            if hull is None:
                hull = convex_hull(verts, pred)
            inside = all(pred.orient2d_sign(hull[i], hull[(i + 1) % len(hull)], row) > 0 for i in range(len(hull)))
            if inside:
                raise DomainError(
                    f"{what} {k} at {point_text(p)} is not enclosed by segments: its flood fill reaches the outside "
                    "of the convex hull and would eat everything (close the boundary around it)"
                )
            raise DomainError(f"{what} {k} at {point_text(p)} lies outside the domain (outside the convex hull of the vertices)")
        return where.face

    hole_face = np.array(
        [place(p, "hole", k, n + k) for k, p in enumerate(pslg.holes)], dtype=np.intp
    ).reshape(-1)
    kept[hole_face] = False
    h = pslg.holes.shape[0]
    region_face = np.array(
        [place(p[:2], "region", k, n + h + k) for k, p in enumerate(pslg.regions)], dtype=np.intp
    ).reshape(-1)
    for k, f in enumerate(region_face.tolist()):
        if not kept[f]:
            raise DomainError(f"region {k} at {point_text(pslg.regions[k, :2])} lies in a hole (the face of a hole point)")
    if faces.n_faces == 0:
        raise DomainError(
            "the segments enclose no region: the domain is empty (close the boundary, or mesh the convex hull: "
            "as_pslg(..., convex=True), --convex on the command line)"
        )
    if not kept.any():
        f = int(hole_face[0])
        ring = faces.face_vertices(f)
        only = "the only region the segments enclose" if faces.n_faces == 1 else "and the other holes eat the rest"
        raise DomainError(
            f"the domain is empty: hole 0 at {point_text(pslg.holes[0])} eats the region bounded by vertices "
            f"{'–'.join(map(str, ring[:6]))}{'…' if len(ring) > 6 else ''}, {only} (is every boundary closed?)"
        )

    keep = kept.tolist()
    inside = _inside_few(faces, keep, n) if seg.shape[0] <= FEW_SEGMENTS else _inside_many(faces, kept, n)
    area2 = sum(a for a, k in zip(faces.face_area2, keep) if k)
    area = Fraction(area2, 2) * Fraction(2) ** (2 * faces.scale.exponent)
    return Domain(pslg, faces, kept, hole_face, region_face, inside, area)


def _inside_few(faces: PlanarFaces, keep: list[bool], n: int) -> NDArray[np.bool_]:
    """:func:`_inside_many` with Python loops over lists (few segments: numpy's passes cost more there). O(n + m)."""
    in_kept = [f != UNBOUNDED and keep[f] for f in faces.face_of_walk.tolist()]  # per walk
    inside = [False] * n
    for u, w in zip(faces.half_edges[:, 0].tolist(), faces.walk_of.tolist()):
        if in_kept[w]:
            inside[u] = True
    on_segment = set(faces.segments.reshape(-1).tolist())
    pts = faces.vertices.tolist()
    for v in range(n):
        if v not in on_segment:
            f = faces.locate(pts[v][0], pts[v][1], on_graph=False).face
            inside[v] = f != UNBOUNDED and keep[f]
    return np.array(inside, dtype=bool)


def _inside_many(faces: PlanarFaces, kept: NDArray[np.bool_], n: int) -> NDArray[np.bool_]:
    """Per vertex, whether it is in the closed domain: a half-edge leaving it has a kept face on its left, or, on no
    segment, it lies in a kept face (:attr:`Domain.vertex_inside`).  Vectorised over the half-edges. O(n + m)."""
    inside = np.zeros(n, dtype=bool)
    left = faces.face_of_walk[faces.walk_of]  # the face on the left of each half-edge
    bounded = left != UNBOUNDED
    bounded[bounded] = kept[left[bounded]]
    inside[faces.half_edges[bounded, 0]] = True
    lonely = np.ones(n, dtype=bool)
    lonely[faces.segments.reshape(-1)] = False
    verts = faces.vertices
    for v in np.flatnonzero(lonely).tolist():
        f = faces.locate(float(verts[v, 0]), float(verts[v, 1]), on_graph=False).face
        inside[v] = f != UNBOUNDED and bool(kept[f])
    return inside
