"""``verify_mesh``: an exact, independent check of a triangle mesh of a planar domain, from any source.

Given a :class:`~persistri.impl.mesh.domain.PSLG` and a mesh (vertices, and
triangles as rows of vertex indices), :func:`verify_mesh` decides exactly —
integer arithmetic on the input doubles times a common power of two, no
epsilon — whether the mesh is a constrained Delaunay triangulation of exactly
the domain, and what quality it reaches.  It does not trust the mesher:
persistri's Ruppert refinement, Shewchuk's Triangle or anything else.  The
domain's faces are traced from the segments alone
(:mod:`~persistri.impl.mesh.faces`).

The checks (each failure is a :class:`MeshProblem` of the kind named):

1. ``orientation`` — every triangle strictly counterclockwise;
2. ``missing-vertex`` — every input vertex of the closed domain is a mesh vertex
   (``coincident``: no two used mesh vertices at one point);
3. ``segment`` — every input segment ``u → v`` is a chain of mesh edges from ``u`` to
   ``v`` whose vertices advance along it and lie on it.  Triangle computes its split
   points in floating point (``a + s(b − a)``, from earlier split points), so they
   lie off the segment by about an ulp: with ``exact_segments=False`` a vertex also
   counts as on the segment when the segment meets its *tolerance box* — the closed
   box of half-width ``rounding_ulps`` units in the last place of the largest
   magnitude among the vertex's and the segment's coordinates, axis by axis —
   decided exactly.  ``rounding_ulps=0.5`` is the vertex's closed rounding cell (the
   reals that round to it); the default 2 covers the drift measured on Triangle's
   outputs (at most 1.11 ulps over circles, stars and offset tiles at q20–q33).
   Such vertices are counted apart (``rounded_split_vertices``); with
   ``exact_segments=True`` they are problems of kind ``segment-rounding``.
   persistri's own meshes pass with ``exact_segments=True``;
4. ``edge`` and ``boundary`` — each oriented edge is in at most one triangle; an edge
   on no segment chain has its reverse in another triangle; and along the chain of
   a segment ``s`` each edge ``p → q`` (in the direction of ``s``) satisfies
   ``n(p → q) − n(q → p) = c(s)``, where ``n`` counts triangles having that oriented
   edge and ``c(s)`` is +1, −1 or 0 as the domain lies on the left of ``s`` only, on
   its right only, or on both sides or neither (``outside`` when a triangle lies on
   the wrong side);
5. ``outside`` and ``area`` — triangles joined across non-segment edges are located
   (one exact point location per group) in a face of the domain; per face and in
   total, twice the triangles' areas add up to twice the face's area, exactly;
6. ``delaunay`` — every edge on no segment is locally Delaunay: the far vertex of
   the neighbouring triangle is not strictly inside the circumcircle (exact
   incircle determinant; cocircular is fine);
7. ``angle`` and ``area-bound`` (:mod:`~persistri.impl.mesh.verify_quality`) — quality: each triangle's smallest angle is at least
   ``min_angle`` (exact, :mod:`~persistri.impl.mesh.angles`), except the triangles
   Ruppert's algorithm must leave (below), and its area is at most ``max_area`` and,
   with ``region_areas``, the bound of its region (exact rationals).

**Why 1 and 4 make a triangulation of exactly the domain.**  For a point ``x`` on
no edge, the number of triangles containing ``x`` is the winding number around
``x`` of the 1-chain ``Σ ∂t`` (each counterclockwise triangle's boundary winds once
around its interior points and not around others).  Edges on no segment pair up
with their reverses, so they cancel in ``Σ ∂t``; by 4 what remains is, segment by
segment, ``c(s)`` times the chain along ``s``, which as a geometric chain is
``c(s) · (u → v)`` — and ``Σ c(s) s`` is exactly the boundary of the domain ``D``
(each kept face's boundary walks keep the face on their left; a segment between
two kept faces or two eaten ones cancels).  The winding number of ``∂D`` around
``x`` is 1 in ``D`` and 0 outside.  So every point of ``D`` off the edges is
covered exactly once and no point outside ``D`` is covered: the triangles tile
``D``, a covering of degree 1.  Non-degenerate triangles tiling ``D`` whose shared
edges pair up are a triangulation (a vertex inside another triangle's edge would
be covered twice on one side).  Check 5 is then implied — the area ratio equals
the degree, 1, and every triangle lies in a kept face — and is kept as an
independent cross-check of the face tracing and of the pairing.  With
``exact_segments=False`` the tiled region is ``D`` with each boundary segment
replaced by its chain through the rounded split points; check 5 compares with
that region's exact area, and ``area_rounding`` reports how far it is from ``D``'s.

**Ruppert's exemption.**  Small angles between input segments cannot be removed,
and near them Delaunay refinement must leave some skinny triangles.  Following
Miller, Pav and Walkington ("When and why Ruppert's algorithm works", 2003) as
implemented in Triangle (``testtriangle``: "a skinny triangle is not split if its
shortest edge subtends a small input angle") and Shewchuk's treatment of small
input angles ("Delaunay refinement algorithms for triangular mesh generation",
CGTA 22, 2002, §4), a triangle below ``min_angle`` is *exempt* when its shortest
edge joins two points on two distinct input segments that share an endpoint
``o`` (neither point being ``o``) and meet there at an angle below 60°.  Triangle
additionally asks that the two points be about equidistant from ``o`` (concentric
shells); this checker does not, so it accepts every mesh Triangle's rule accepts.
Exempt triangles are counted (``exempt``), not reported as problems.

Cost: O(t) vectorised integer work for orientation, pairing, areas and incircle
(t triangles), a walk per segment, one point location per group of triangles,
and the domain's faces (:func:`~persistri.impl.mesh.domain.domain_of`).

The report and its problems (:class:`MeshReport`, :class:`MeshProblem`,
:data:`PROBLEM_KINDS`) are defined in :mod:`~persistri.impl.mesh.verify_report`.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.geometry.exact import incircle_det, orient2d_det
from persistri.impl.geometry.points import as_points, unique_rows
from persistri.impl.mesh.chains import segment_chains
from persistri.impl.mesh.domain import PSLG, Domain, DomainError, as_pslg, domain_of
from persistri.impl.mesh.faces import UNBOUNDED, common_scale
from persistri.impl.mesh.naming import InputNames
from persistri.impl.mesh.segments import point_text
from persistri.impl.mesh.verify_quality import check_quality
from persistri.impl.mesh.verify_report import (
    PROBLEM_KINDS,
    MeshProblem,
    MeshReport,
    MeshVerificationError,
    ProblemLog,
)

__all__ = ["verify_mesh", "MeshReport", "MeshProblem", "MeshVerificationError", "PROBLEM_KINDS"]

_TILING = ("input", "domain", "orientation", "missing-vertex", "coincident", "segment", "edge", "boundary", "outside")


def verify_mesh(
    domain: PSLG | Mapping[str, Any],
    vertices: ArrayLike,
    triangles: ArrayLike,
    *,
    min_angle: float | None = None,
    max_area: float | None = None,
    exact_segments: bool = True,
    rounding_ulps: float = 2.0,
    region_areas: bool = False,
    max_problems: int = 10,
) -> MeshReport:
    """Check exactly that ``triangles`` (t × 3 rows of ``vertices``) are a constrained Delaunay mesh of ``domain``.

    ``domain`` is a :class:`PSLG` or ``triangle.triangulate``'s dictionary (as
    :func:`~persistri.impl.mesh.api.triangulate` takes it).

    ``min_angle`` (degrees, in ``[0, 60]``) and ``max_area`` add the quality checks;
    ``region_areas=True`` adds the area bounds of ``domain``'s regions (Triangle's ``-a``
    without a number).  ``exact_segments=False``
    accepts split vertices off their segments by up to ``rounding_ulps`` ulps
    (Triangle's; module docstring).  Returns a
    :class:`MeshReport`; ``report.raise_if_failed()`` raises with every problem
    kept.  The module docstring lists the checks and proves them sufficient.
    Raises :class:`ValueError` (a value) or :class:`TypeError` (not a real number) only for a bad
    ``min_angle``, ``max_area`` or ``rounding_ulps``.
    """
    bounds: tuple[tuple[str, object], ...] = (("min_angle", min_angle), ("max_area", max_area), ("rounding_ulps", rounding_ulps))
    for name, bound in bounds:  # typed float, but called from untyped code too
        if (bound is not None or name == "rounding_ulps") and (isinstance(bound, bool) or not isinstance(bound, numbers.Real)):
            raise TypeError(f"{name} must be a real number, not {type(bound).__name__}")
    if min_angle is not None and not (math.isfinite(min_angle) and 0.0 <= min_angle <= 60.0):
        raise ValueError(f"min_angle must be between 0 and 60 degrees, got {min_angle}")
    if max_area is not None and not (math.isfinite(max_area) and max_area > 0):
        raise ValueError(f"max_area must be a positive number, got {max_area}")
    if not (math.isfinite(rounding_ulps) and rounding_ulps >= 0):
        raise ValueError(f"rounding_ulps must be a non-negative number, got {rounding_ulps}")
    rep = MeshReport()
    check = ProblemLog(rep, max_problems)
    try:
        pts = as_points(vertices, 2, what="vertices")
    except (TypeError, ValueError) as exc:
        check.problem("input", str(exc))
        return rep
    tri = np.asarray(triangles)
    if tri.ndim != 2 or tri.shape[1] != 3 or (tri.size and tri.dtype.kind not in "iu"):
        check.problem("input", f"triangles must be a (t, 3) integer array, got shape {tri.shape} of {tri.dtype}")
        return rep
    tri = tri.astype(np.intp)
    n = pts.shape[0]
    rep.triangles = tri.shape[0]
    if tri.size and (tri.min() < 0 or tri.max() >= n):
        k = int(np.argmax(((tri < 0) | (tri >= n)).any(axis=1)))
        check.problem("input", f"triangle {k} {tri[k].tolist()} indexes a vertex outside 0..{n - 1}")
        return rep
    repeat = (tri[:, 0] == tri[:, 1]) | (tri[:, 1] == tri[:, 2]) | (tri[:, 0] == tri[:, 2])
    for k in np.flatnonzero(repeat).tolist():
        check.problem("input", f"triangle {k} {tri[k].tolist()} repeats a vertex")
    if rep.problems:
        return rep
    try:
        if isinstance(domain, Mapping):
            domain = PSLG.from_dict(domain, repair=False)
        clean = as_pslg(domain.vertices, domain.segments, domain.holes, domain.regions, repair=False)
        names = InputNames.through((domain.segment_origin, domain.vertex_map), (clean.segment_origin, clean.vertex_map))
        scale = common_scale(pts, clean.vertices, clean.holes, clean.regions[:, :2])
        dom = domain_of(clean, scale=scale)
    except DomainError as exc:
        check.problem("domain", f"{exc} (validate the domain with as_pslg first)")
        return rep
    rep.domain_area = dom.area
    _Mesh(check, dom, pts, tri, scale.to_ints(pts[:, 0]), scale.to_ints(pts[:, 1]), rounding_ulps, names).run(
        min_angle, max_area, exact_segments, region_areas
    )
    return rep


def _sign(values: NDArray[np.object_]) -> NDArray[np.int8]:
    return (np.greater(values, 0).astype(np.int8) - np.less(values, 0).astype(np.int8)).astype(np.int8)


class _Mesh:
    """The state of one check: exact integer coordinates, edges, chains."""

    def __init__(
        self,
        check: ProblemLog,
        dom: Domain,
        pts: NDArray[np.float64],
        tri: NDArray[np.intp],
        xs: NDArray[Any],
        ys: NDArray[Any],
        rounding_ulps: float,
        names: InputNames,
    ) -> None:
        self.check, self.dom, self.pts, self.tri, self.names = check, dom, pts, tri, names
        self.rounding_ulps = rounding_ulps
        self.X, self.Y = xs, ys
        self.xl: list[int] = xs.tolist()
        self.yl: list[int] = ys.tolist()
        self.n = pts.shape[0]

    def run(self, min_angle: float | None, max_area: float | None, exact_segments: bool, region_areas: bool) -> None:
        rep, tri = self.check.rep, self.tri
        used = np.unique(tri)
        rep.vertices = int(used.size)
        if tri.shape[0] == 0:
            self.check.problem("outside", "the mesh has no triangles, the domain is not empty")
            return
        self.det = self._orientation()
        self._input_vertices(used)
        self._edges()
        self._chains(exact_segments)
        self._pairing()
        self._faces_and_areas()
        self._delaunay()
        # 7. Quality (verify_quality).
        check_quality(
            self.check, self.dom, self.pts, self.tri, self.xl, self.yl, self.det, self.mesh_of, self.on_segments,
            self.tri_face, min_angle, max_area, region_areas,
        )

    # 1. Orientation.
    def _orientation(self) -> NDArray[np.object_]:
        t, X, Y = self.tri, self.X, self.Y
        a, b, c = t[:, 0], t[:, 1], t[:, 2]
        det: NDArray[np.object_] = orient2d_det(X[a], Y[a], X[b], Y[b], X[c], Y[c])
        sign = _sign(det)
        for k in np.flatnonzero(sign <= 0).tolist():
            what = "is clockwise" if sign[k] < 0 else "has zero area (its vertices are collinear)"
            self.check.problem("orientation", f"triangle {k} {t[k].tolist()} {what}")
        return det

    # 2. Input vertices and coincident vertices.
    def _input_vertices(self, used: NDArray[np.intp]) -> None:
        pts = self.pts
        uniq = unique_rows(pts[used])
        if uniq.first.size < used.size:
            dup = np.flatnonzero(uniq.first[uniq.inverse] != np.arange(used.size))
            for i in dup.tolist():
                j = int(used[uniq.first[uniq.inverse[i]]])
                self.check.problem("coincident", f"mesh vertices {j} and {int(used[i])} are the same point {tuple(pts[j].tolist())}")
        at = {(float(pts[v, 0]), float(pts[v, 1])): int(v) for v in used[::-1].tolist()}
        verts = self.dom.pslg.vertices
        self.mesh_of = np.full(verts.shape[0], -1, dtype=np.intp)
        for i in range(verts.shape[0]):
            m = at.get((float(verts[i, 0]), float(verts[i, 1])))
            if m is not None:
                self.mesh_of[i] = m
            elif self.dom.vertex_inside[i]:
                self.check.problem("missing-vertex", f"input vertex {i} at {tuple(verts[i].tolist())} is not a vertex of the mesh")

    # Edges: oriented edge codes a·n + b, the triangle of each, and undirected adjacency.
    def _edges(self) -> None:
        t, n = self.tri, self.n
        a = t.reshape(-1)
        b = t[:, [1, 2, 0]].reshape(-1)
        codes = a.astype(np.int64) * n + b
        order = np.argsort(codes, kind="stable")
        sc = codes[order]
        repeated = np.flatnonzero(sc[1:] == sc[:-1])
        for k in repeated.tolist():
            i, j = int(order[k]) // 3, int(order[k + 1]) // 3
            u, v = divmod(int(sc[k]), n)
            self.check.problem("edge", f"oriented edge ({u}, {v}) is in triangles {i} and {j}: they overlap")
        self.codes, self.sorted_codes, self.code_order = codes, sc, order
        self.twin = codes % n * n + codes // n
        pos = np.searchsorted(sc, self.twin)
        pos = np.minimum(pos, sc.size - 1)
        self.has_twin = sc[pos] == self.twin
        self.twin_slot = np.where(self.has_twin, order[pos], -1)  # a triangle slot (3·triangle + edge) across
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        und = np.unique(lo.astype(np.int64) * n + hi)
        ends = np.concatenate([np.stack([und // n, und % n], axis=1), np.stack([und % n, und // n], axis=1)])
        ends = ends[np.argsort(ends[:, 0], kind="stable")]
        self.nbr = ends[:, 1].astype(np.intp)
        self.nbr_ptr = np.searchsorted(ends[:, 0], np.arange(n + 1))

    def _count(self, u: int, v: int) -> int:
        code = u * self.n + v
        k = int(np.searchsorted(self.sorted_codes, code))
        return int(k < self.sorted_codes.size and self.sorted_codes[k] == code)

    # 3. Segment chains.
    def _segment(self, s: int) -> str:
        """Segment ``s`` named as the caller wrote it (:class:`~persistri.impl.mesh.naming.InputNames`)."""
        a, b = (point_text(self.dom.pslg.vertices[v]) for v in self.dom.pslg.segments[s])
        return self.names.segment(s, a, b)

    def _chains(self, exact_segments: bool) -> None:
        seg = self.dom.pslg.segments
        found = segment_chains(self.pts, self.xl, self.yl, self.nbr, self.nbr_ptr, seg, self.mesh_of, self.rounding_ulps)
        self.chain, self.on_segments = found.paths, found.on_segments
        for s, cur, edges in found.stuck:
            if not (self.dom.left_kept(2 * s) or self.dom.left_kept(2 * s + 1)):
                continue  # outside the domain on both sides (a hole against the boundary): no triangle needs its edges
            self.check.problem(
                "segment",
                f"{self._segment(s)} is not a union of mesh edges: "
                f"the chain along it stops at mesh vertex {cur} {tuple(self.pts[cur].tolist())} after {edges} edges",
            )
        if exact_segments:
            for s, rounded in found.rounded:
                w = rounded[0]
                self.check.problem(
                    "segment-rounding",
                    f"{self._segment(s)}: {len(rounded)} split vertices lie off it within their tolerance boxes "
                    f"(first: mesh vertex {w} {tuple(self.pts[w].tolist())}); exact_segments=False accepts them",
                )
        self.check.rep.split_vertices = found.split_vertices
        self.check.rep.rounded_split_vertices = found.rounded_split_vertices

    # 4. Pairing and the boundary chain.
    def _pairing(self) -> None:
        n = self.n
        self.constrained: set[int] = set()  # undirected codes lo·n + hi of chain edges
        for s, path in enumerate(self.chain):
            if path is None:
                continue
            c = self.dom.boundary_coefficient(s)
            for p, q in zip(path[:-1], path[1:]):
                self.constrained.add(min(p, q) * n + max(p, q))
                fwd, back = self._count(p, q), self._count(q, p)
                if fwd - back == c:
                    continue
                name = self._segment(s)
                if c != 0 and fwd + back == 2:
                    self.check.problem("outside", f"triangles lie on both sides of edge ({p}, {q}) of {name}, which bounds the domain")
                elif c != 0 and fwd - back == -c:
                    self.check.problem("outside", f"the triangle on edge ({p}, {q}) of {name} lies on the side outside the domain")
                elif c != 0:
                    self.check.problem("boundary", f"edge ({p}, {q}) of {name} has no triangle on the domain's side")
                else:
                    inside = self.dom.left_kept(2 * s)
                    where = "inside the domain" if inside else "outside the domain"
                    self.check.problem("boundary" if inside else "outside", f"edge ({p}, {q}) of {name}, which lies {where}, has a triangle on one side only")
        self.rep_constrained = len(self.constrained)
        self.check.rep.constrained_edges = len(self.constrained)
        codes = self.codes
        und = np.minimum(codes // n, codes % n) * n + np.maximum(codes // n, codes % n)
        self.is_constrained = np.isin(und, np.fromiter(self.constrained, dtype=np.int64, count=len(self.constrained)))
        lone = np.flatnonzero(~self.has_twin & ~self.is_constrained)
        for k in lone.tolist():
            u, v = divmod(int(codes[k]), n)
            self.check.problem(
                "boundary",
                f"edge ({u}, {v}) of triangle {k // 3} has no triangle on its other side and lies on no input segment",
            )

    # 5. Faces and areas.
    def _faces_and_areas(self) -> None:
        rep, dom, t = self.check.rep, self.dom, self.tri.shape[0]
        faces = dom.faces
        parent = np.arange(t)

        def find(a: int) -> int:
            while parent[a] != a:
                parent[a] = parent[parent[a]]
                a = int(parent[a])
            return a

        across = np.flatnonzero(self.has_twin & ~self.is_constrained)
        for k in across.tolist():
            ra, rb = find(k // 3), find(int(self.twin_slot[k]) // 3)
            if ra != rb:
                parent[ra] = rb
        roots = np.array([find(i) for i in range(t)])
        groups, group_of = np.unique(roots, return_inverse=True)
        sizes = np.bincount(group_of.reshape(-1), minlength=groups.size)
        group_face = np.full(groups.size, UNBOUNDED, dtype=np.intp)
        tri, xl, yl = self.tri, self.xl, self.yl
        for g, r in enumerate(groups.tolist()):
            a, b, c = (int(v) for v in tri[r])
            nx, ny = xl[a] + xl[b] + xl[c], yl[a] + yl[b] + yl[c]
            cx, cy = (float(self.pts[[a, b, c], 0].sum()) / 3, float(self.pts[[a, b, c], 1].sum()) / 3)
            where = faces.locate_scaled(nx, ny, 3, cx, cy)
            size = int(sizes[g])
            if where.on_graph:
                self.check.problem("outside", f"triangle {r}'s centroid lies on the domain's segments or vertices (with {size - 1} triangles joined to it)")
                continue
            group_face[g] = where.face
            if where.face == UNBOUNDED or not dom.kept[where.face]:
                hole = f"hole {int(np.flatnonzero(dom.hole_face == where.face)[0])}" if where.face != UNBOUNDED else "the unbounded outside"
                self.check.problem("outside", f"triangle {r} (and {size - 1} triangles joined to it) lies in {hole}, outside the domain")
        self.tri_face = group_face[group_of]
        det = self.det
        total = sum(det.tolist())
        e = faces.scale.exponent
        unit = Fraction(2) ** (2 * e) / 2
        rep.mesh_area = total * unit
        # Twice each face's area as bounded by the segment chains (exact_segments: the face's own area).
        chain2 = self._chain_area2()
        face_mesh: dict[int, int] = {}
        for f, d in zip(self.tri_face.tolist(), det.tolist()):
            face_mesh[f] = face_mesh.get(f, 0) + d
        domain_chain = 0
        for f in range(faces.n_faces):
            if not dom.kept[f]:
                continue
            walks = [w for w in range(len(faces.walks)) if int(faces.face_of_walk[w]) == f]
            expect = sum(chain2[h] for w in walks for h in faces.walks[w])
            domain_chain += expect
            got = face_mesh.get(f, 0)
            if got != expect and not self.check.any(_TILING):
                ring = "–".join(str(v) for v in faces.face_vertices(f)[:5])
                self.check.problem("area", f"the triangles in the face bounded by vertices {ring}… cover {float(got * unit):.17g}, the face's area is {float(expect * unit):.17g}")
        rep.area_rounding = abs(domain_chain - dom.area2) * unit
        if total != domain_chain and not self.check.any(_TILING + ("area",)):
            self.check.problem("area", f"the triangles' areas add up to {float(total * unit):.17g}, the domain's area is {float(domain_chain * unit):.17g}")

    def _chain_area2(self) -> list[int]:
        """Twice the signed area contribution (Σ x_i y_{i+1} − x_{i+1} y_i) of each half-edge's chain."""
        faces, xl, yl = self.dom.faces, self.xl, self.yl
        fx, fy = faces._x, faces._y
        out = [0] * faces.half_edges.shape[0]
        for s in range(faces.segments.shape[0]):
            path = self.chain[s] if s < len(self.chain) else None
            if path is None:
                u, v = (int(w) for w in faces.segments[s])
                c = fx[u] * fy[v] - fx[v] * fy[u]
            else:
                c = sum(xl[p] * yl[q] - xl[q] * yl[p] for p, q in zip(path[:-1], path[1:]))
            out[2 * s], out[2 * s + 1] = c, -c
        return out

    # 6. Constrained Delaunay.
    def _delaunay(self) -> None:
        slots = np.flatnonzero(self.has_twin & ~self.is_constrained)
        if not slots.size:
            return
        slots = slots[self.codes[slots] // self.n < self.codes[slots] % self.n]  # each edge once
        tri, X, Y = self.tri, self.X, self.Y
        k, j = slots // 3, slots % 3
        a, b, c = tri[k, j], tri[k, (j + 1) % 3], tri[k, (j + 2) % 3]
        other = self.twin_slot[slots]
        d = tri[other // 3, (other % 3 + 2) % 3]
        det = incircle_det(X[a], Y[a], X[b], Y[b], X[c], Y[c], X[d], Y[d])
        for i in np.flatnonzero(_sign(det) > 0).tolist():
            self.check.problem(
                "delaunay",
                f"edge ({int(a[i])}, {int(b[i])}) is not locally Delaunay: vertex {int(d[i])} is strictly inside "
                f"the circumcircle of triangle {int(k[i])} {tri[int(k[i])].tolist()}",
            )
