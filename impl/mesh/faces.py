"""The faces of a planar straight-line graph, traced exactly, and exact point location in them.

A PSLG's segments cut the plane into faces: connected open regions.  This
module finds them from the segments alone, with no triangulation (so that the
mesh checker, :mod:`~persistri.impl.mesh.verify`, does not trust the mesher it
checks):

1. **Angular order.**  At each vertex the segments leaving it are sorted
   counterclockwise by direction, exactly: by half-plane, then by the sign of a
   cross product of exact integer coordinates.
2. **Walks.**  Each segment ``s`` gives two half-edges, ``2s`` (as listed) and
   ``2s + 1`` (reversed).  The walk after half-edge ``u → v`` leaves ``v`` along
   the segment just clockwise of ``v → u``, so a walk keeps its face on its
   left.  Every half-edge is in exactly one walk; a dangling segment (a crack)
   is walked once on each side.
3. **Outer walks and faces.**  Within one connected component of the segment
   graph, every walk around a bounded face turns counterclockwise (twice its
   signed area is positive) and exactly one walk, around the outside of the
   component, does not (negative area, or zero for a component that is a tree).
   Each counterclockwise walk bounds one bounded face.
4. **Nesting.**  A component that is not the outermost lies inside a face of
   another: the innermost counterclockwise walk (least area) of another
   component whose winding number around one of its vertices is 1.  Its
   outer walk is an inner boundary of that face.

A face's region is the inside of its counterclockwise walk less the regions
enclosed by the components nested in it directly; twice its area is the sum of
twice the signed areas of its walks.  Point location (:meth:`PlanarFaces.locate`)
answers the face containing a rational point, or the vertex or segment it lies
on: the face is the least-area counterclockwise walk winding once around it.

Every decision is exact: coordinates are the input doubles times a common power
of two (:class:`~persistri.impl.geometry.exact.IntegerScale`), as Python
integers.  The input must be a *clean* PSLG (no duplicate vertices, no
duplicate or crossing segments, no vertex inside a segment), as
:func:`~persistri.impl.mesh.domain.as_pslg` makes it.

Cost: O(m log m) for the walks (m segments); nesting tests each component
against the counterclockwise walks whose bounding boxes hold it, O(c · m) in the
worst case (c components) and near O(m) for domains with a few holes; a point
location is one vectorised pass over the half-edges and exact tests on the few
that straddle the point's horizontal.  The paper (§1) needs this for Ruppert's
domains; it is not in the paper itself.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from numpy.typing import NDArray

from persistri.impl.geometry.exact import IntegerScale, binary_exponents

__all__ = ["PlanarFaces", "Location", "planar_faces", "common_scale", "UNBOUNDED"]

UNBOUNDED = -1
"""The face index of the unbounded face."""

FEW_FACES = 64
"""Up to this many bounded faces, the nesting of components tests each one's bounding boxes with a Python loop
instead of numpy's (the same faces in the same order; tests/test_mesh_faces_locate.py compares the two)."""


def common_scale(*arrays: NDArray[np.float64]) -> IntegerScale:
    """The :class:`IntegerScale` making every entry of every array an exact integer. O(size)."""
    lows = [binary_exponents(np.ascontiguousarray(a, dtype=np.float64).ravel())[0] for a in arrays if a.size]
    return IntegerScale.of(np.concatenate(lows)) if lows else IntegerScale(0)


@dataclass(frozen=True)
class Location:
    """Where a point is: in ``face`` (:data:`UNBOUNDED` for the outside), or on a ``vertex`` or a ``segment``.

    On a vertex or a segment's interior, ``face`` is :data:`UNBOUNDED` and
    means nothing.
    """

    face: int
    vertex: int | None = None
    segment: int | None = None

    @property
    def on_graph(self) -> bool:
        """Whether the point lies on a vertex or a segment (it is in no face)."""
        return self.vertex is not None or self.segment is not None


@dataclass(frozen=True, eq=False)
class PlanarFaces:
    """The walks and faces of a clean PSLG's segment graph (see the module docstring).

    * ``half_edges`` — ``(2m, 2)``: half-edge ``2s`` is segment ``s`` as listed, ``2s + 1`` reversed;
    * ``walk_of`` — ``(2m,)``: the walk of each half-edge (its face is on its left);
    * ``walks`` — each walk's half-edges in order;
    * ``walk_area2`` — twice each walk's signed area, in scaled integer units
      (``scale``: a real area is ``area2 / 2 · 4^scale.exponent``);
    * ``face_of_walk`` — the face on the left of each walk: its own face for a
      counterclockwise walk, the face it is nested in for an outer walk;
    * ``face_walk`` — the counterclockwise walk of each bounded face;
    * ``face_area2`` — twice each face's area (its walk and its nested outer walks);
    * ``component_of_segment`` and ``component_parent`` — connected components
      and the face each one lies in.
    """

    vertices: NDArray[np.float64]
    segments: NDArray[np.intp]
    scale: IntegerScale
    half_edges: NDArray[np.intp]
    walk_of: NDArray[np.intp]
    walks: tuple[tuple[int, ...], ...]
    walk_area2: tuple[int, ...]
    face_of_walk: NDArray[np.intp]
    face_walk: NDArray[np.intp]
    face_area2: tuple[int, ...]
    component_of_segment: NDArray[np.intp]
    component_parent: NDArray[np.intp]
    _x: tuple[int, ...]
    _y: tuple[int, ...]

    @property
    def n_faces(self) -> int:
        """The number of bounded faces."""
        return int(self.face_walk.size)

    def face_of_half_edge(self, h: int) -> int:
        """The face on the left of half-edge ``h`` (:data:`UNBOUNDED` for the outside). O(1)."""
        return int(self.face_of_walk[self.walk_of[h]])

    def face_area(self, f: int) -> Fraction:
        """The exact area of bounded face ``f``. O(1)."""
        return Fraction(self.face_area2[f], 2) * Fraction(2) ** (2 * self.scale.exponent)

    def face_vertices(self, f: int) -> list[int]:
        """The vertices of bounded face ``f``'s counterclockwise walk, in order. O(walk)."""
        return [int(self.half_edges[h, 0]) for h in self.walks[int(self.face_walk[f])]]

    def int_point(self, i: int) -> tuple[int, int]:
        """Vertex ``i``'s exact scaled integer coordinates. O(1)."""
        return self._x[i], self._y[i]

    # -- point location ------------------------------------------------------------------

    def locate(self, x: float | Fraction, y: float | Fraction, *, on_graph: bool = True) -> Location:
        """The face holding the real point ``(x, y)``, or the vertex or segment it lies on. Exact.

        ``x`` and ``y`` are any rationals (floats are exact rationals).  With
        ``on_graph=False`` the point is known to lie on no segment (an isolated
        vertex, say) and only its face is sought.  Cost: a vectorised pass over
        the half-edges and exact tests on those near the point.
        """
        e = self.scale.exponent
        if type(x) is float and type(y) is float:  # the usual case, without Fraction objects (the same integers)
            nx, dx = _dyadic(x, e)
            ny, dy = _dyadic(y, e)
            d = math.lcm(dx, dy)
            return self.locate_scaled(nx * (d // dx), ny * (d // dy), d, x, y, on_graph=on_graph)
        fx, fy = Fraction(x), Fraction(y)
        sx, sy = fx / Fraction(2) ** e, fy / Fraction(2) ** e
        den = math.lcm(sx.denominator, sy.denominator)
        return self.locate_scaled(int(sx * den), int(sy * den), den, float(fx), float(fy), on_graph=on_graph)

    def locate_scaled(
        self, nx: int, ny: int, d: int, approx_x: float, approx_y: float, *, on_graph: bool = True
    ) -> Location:
        """:meth:`locate` for the point ``(nx / d, ny / d)`` in scaled integer units (``d > 0``).

        ``approx_x, approx_y`` are the point's real coordinates to within a
        relative 1e-12 (they only choose which half-edges get exact tests).
        """
        pts = self.vertices
        tol = 1e-9 * (abs(approx_x) + abs(approx_y)) + 1e-300
        xs, ys = self._x, self._y
        if on_graph:
            where = self._on_graph(nx, ny, d, approx_x, approx_y, tol)
            if where is not None:
                return where
        return Location(self._face_around(nx, ny, d, approx_x, approx_y, tol))

    def _on_graph(self, nx: int, ny: int, d: int, approx_x: float, approx_y: float, tol: float) -> Location | None:
        """The vertex or segment the point lies on, or None."""
        pts = self.vertices
        xs, ys = self._x, self._y
        near = np.flatnonzero((np.abs(pts[:, 0] - approx_x) <= tol) & (np.abs(pts[:, 1] - approx_y) <= tol))
        for v in near.tolist():
            if xs[v] * d == nx and ys[v] * d == ny:
                return Location(UNBOUNDED, vertex=v)
        seg = self.segments
        if seg.shape[0] == 0:
            return None
        ax, ay = pts[seg[:, 0], 0], pts[seg[:, 0], 1]
        bx, by = pts[seg[:, 1], 0], pts[seg[:, 1], 1]
        in_box = (
            (np.minimum(ax, bx) <= approx_x + tol)
            & (np.maximum(ax, bx) >= approx_x - tol)
            & (np.minimum(ay, by) <= approx_y + tol)
            & (np.maximum(ay, by) >= approx_y - tol)
        )
        for s in np.flatnonzero(in_box).tolist():
            u, v = int(seg[s, 0]), int(seg[s, 1])
            if _orient_scaled(xs[u], ys[u], xs[v], ys[v], nx, ny, d) == 0 and _within(
                xs[u], ys[u], xs[v], ys[v], nx, ny, d
            ):
                return Location(UNBOUNDED, segment=s)
        return None

    def _face_around(self, nx: int, ny: int, d: int, approx_x: float, approx_y: float, tol: float) -> int:
        """The face of a point on no segment: the least-area ccw walk winding around it."""
        pts = self.vertices
        xs, ys = self._x, self._y
        # Winding numbers (Sunday's crossing rule) of every walk with a half-edge crossing the
        # horizontal line through the point to its right; only those half-edges are tested exactly.
        he = self.half_edges
        ux, uy = pts[he[:, 0], 0], pts[he[:, 0], 1]
        vx, vy = pts[he[:, 1], 0], pts[he[:, 1], 1]
        cand = np.flatnonzero(
            (np.minimum(uy, vy) <= approx_y + tol) & (np.maximum(uy, vy) >= approx_y - tol) & (np.maximum(ux, vx) >= approx_x - tol)
        )
        winding: dict[int, int] = {}
        for h in cand.tolist():
            u, v = int(he[h, 0]), int(he[h, 1])
            uyd, vyd = ys[u] * d, ys[v] * d
            if uyd <= ny < vyd:
                if _orient_scaled(xs[u], ys[u], xs[v], ys[v], nx, ny, d) > 0:
                    w = int(self.walk_of[h])
                    winding[w] = winding.get(w, 0) + 1
            elif vyd <= ny < uyd:
                if _orient_scaled(xs[u], ys[u], xs[v], ys[v], nx, ny, d) < 0:
                    w = int(self.walk_of[h])
                    winding[w] = winding.get(w, 0) - 1
        best, best_area = UNBOUNDED, 0
        for w, wn in winding.items():
            a = self.walk_area2[w]
            if wn != 0 and a > 0 and (best == UNBOUNDED or a < best_area):
                best, best_area = w, a
        return UNBOUNDED if best == UNBOUNDED else int(self.face_of_walk[best])


def _dyadic(x: float, e: int) -> tuple[int, int]:
    """``x / 2^e`` in lowest terms, as (numerator, denominator > 0): ``Fraction(x) / Fraction(2) ** e``'s. O(1)."""
    n, d = x.as_integer_ratio()
    if e >= 0:
        d <<= e
    else:
        n <<= -e
    g = math.gcd(n, d)
    return n // g, d // g


def _orient_scaled(ux: int, uy: int, vx: int, vy: int, nx: int, ny: int, d: int) -> int:
    """The sign of orient2d(u, v, p) for p = (nx / d, ny / d), d > 0: +1 when p is left of u → v."""
    det = (vx - ux) * (ny - uy * d) - (vy - uy) * (nx - ux * d)
    return (det > 0) - (det < 0)


def _within(ux: int, uy: int, vx: int, vy: int, nx: int, ny: int, d: int) -> bool:
    """Whether p = (nx / d, ny / d) lies in the closed bounding box of u and v."""
    return min(ux, vx) * d <= nx <= max(ux, vx) * d and min(uy, vy) * d <= ny <= max(uy, vy) * d


def planar_faces(
    vertices: NDArray[np.float64], segments: NDArray[np.intp], *, scale: IntegerScale | None = None
) -> PlanarFaces:
    """Trace the faces of a clean PSLG's segments exactly (see the module docstring).

    ``scale`` must make every vertex coordinate an integer (default: the least
    such scale, :func:`common_scale`); pass a shared one to compare areas with
    other exact quantities.  O(m log m) plus the nesting (module docstring); the
    walks are Python loops over lists (a few hundred instructions a half-edge).
    """
    pts = np.ascontiguousarray(vertices, dtype=np.float64)
    seg = np.ascontiguousarray(segments, dtype=np.intp).reshape(-1, 2)
    xs, ys, scale = _integer_coordinates(pts, scale)
    m = seg.shape[0]
    he = np.empty((2 * m, 2), dtype=np.intp)
    he[0::2] = seg
    he[1::2] = seg[:, ::-1]
    seg_list: list[list[int]] = seg.tolist()
    tails = [u for pair in seg_list for u in (pair[0], pair[1])]
    heads = [v for pair in seg_list for v in (pair[1], pair[0])]

    # 1. Counterclockwise order of the half-edges leaving each vertex.
    out: dict[int, list[int]] = {}
    for h, u in enumerate(tails):
        out.setdefault(u, []).append(h)

    def direction(h: int) -> tuple[int, int]:
        return xs[heads[h]] - xs[tails[h]], ys[heads[h]] - ys[tails[h]]

    def ccw_before(h1: int, h2: int) -> int:
        (dx1, dy1), (dx2, dy2) = direction(h1), direction(h2)
        half1 = 0 if dy1 > 0 or (dy1 == 0 and dx1 > 0) else 1
        half2 = 0 if dy2 > 0 or (dy2 == 0 and dx2 > 0) else 1
        if half1 != half2:
            return half1 - half2
        cross = dx1 * dy2 - dy1 * dx2
        return -1 if cross > 0 else (1 if cross < 0 else 0)

    position = [0] * (2 * m)
    ring: dict[int, list[int]] = {}
    for u, hs in out.items():
        if len(hs) > 2:  # one or two half-edges are in counterclockwise order as they are (a cycle of two is either)
            hs.sort(key=functools.cmp_to_key(ccw_before))
        ring[u] = hs
        for k, h in enumerate(hs):
            position[h] = k

    # 2. Walks: after u → v comes the half-edge leaving v just clockwise of v → u.
    walk_of = [-1] * (2 * m)
    walks: list[tuple[int, ...]] = []
    areas: list[int] = []
    for start in range(2 * m):
        if walk_of[start] >= 0:
            continue
        w = len(walks)
        steps: list[int] = []
        area2 = 0
        h = start
        while walk_of[h] < 0:
            walk_of[h] = w
            steps.append(h)
            u, v = tails[h], heads[h]
            area2 += xs[u] * ys[v] - xs[v] * ys[u]
            around = ring[v]
            h = around[(position[h ^ 1] - 1) % len(around)]
        walks.append(tuple(steps))
        areas.append(area2)

    # 3. Components (union-find over vertices) and their outer walks.
    parent = list(range(pts.shape[0]))

    def find(a: int) -> int:
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for u, v in seg_list:
        ru, rv = find(u), find(v)
        if ru != rv:
            parent[ru] = rv
    roots: dict[int, int] = {}
    component_list = [roots.setdefault(find(u), len(roots)) for u, _ in seg_list]
    n_comp = len(roots)
    outer = [-1] * n_comp
    for w, cycle in enumerate(walks):
        c = component_list[cycle[0] >> 1]
        if areas[w] <= 0:
            assert outer[c] < 0, "a component of a planar graph has one outer walk (is the PSLG clean?)"
            outer[c] = w
    faces_ccw = [w for w in range(len(walks)) if areas[w] > 0]
    face_of_walk = [UNBOUNDED] * len(walks)
    for f, w in enumerate(faces_ccw):
        face_of_walk[w] = f

    # 4. Nesting: each component's outer walk lies in the innermost ccw walk of another component
    # that winds once around one of its vertices (they share no point, so any vertex decides).
    # With one component there is no other: it lies in the unbounded face.
    component_parent = [UNBOUNDED] * n_comp
    if faces_ccw and n_comp > 1:
        walk_comp = [component_list[cycle[0] >> 1] for cycle in walks]
        px_all, py_all = pts[:, 0].tolist(), pts[:, 1].tolist()
        box_list = [
            [
                min(px_all[tails[h]] for h in walks[w]),
                max(px_all[tails[h]] for h in walks[w]),
                min(py_all[tails[h]] for h in walks[w]),
                max(py_all[tails[h]] for h in walks[w]),
            ]
            for w in faces_ccw
        ]
        boxes = np.array(box_list) if len(faces_ccw) > FEW_FACES else None
        for c in range(n_comp):
            p = tails[walks[outer[c]][0]]
            px, py = px_all[p], py_all[p]
            if boxes is None:  # few faces: one loop over the boxes, in order (numpy's passes cost more)
                inside = [k for k, (x0, x1, y0, y1) in enumerate(box_list) if x0 <= px <= x1 and y0 <= py <= y1]
            else:
                inside = np.flatnonzero(
                    (boxes[:, 0] <= px) & (boxes[:, 1] >= px) & (boxes[:, 2] <= py) & (boxes[:, 3] >= py)
                ).tolist()
            best, best_area = UNBOUNDED, 0
            for k in inside:
                w = faces_ccw[k]
                if walk_comp[w] == c or (best != UNBOUNDED and areas[w] >= best_area):
                    continue
                if _winding(walks[w], tails, heads, xs, ys, xs[p], ys[p]) != 0:
                    best, best_area = k, areas[w]
            component_parent[c] = best
            face_of_walk[outer[c]] = best

    face_area2 = [areas[w] for w in faces_ccw]
    for c in range(n_comp):
        f = component_parent[c]
        if f != UNBOUNDED:
            face_area2[f] += areas[outer[c]]

    return PlanarFaces(
        vertices=pts,
        segments=seg,
        scale=scale,
        half_edges=he,
        walk_of=np.array(walk_of, dtype=np.intp),
        walks=tuple(walks),
        walk_area2=tuple(areas),
        face_of_walk=np.array(face_of_walk, dtype=np.intp),
        face_walk=np.array(faces_ccw, dtype=np.intp),
        face_area2=tuple(face_area2),
        component_of_segment=np.array(component_list, dtype=np.intp),
        component_parent=np.array(component_parent, dtype=np.intp),
        _x=xs,
        _y=ys,
    )


def _integer_coordinates(
    pts: NDArray[np.float64], scale: IntegerScale | None
) -> tuple[tuple[int, ...], tuple[int, ...], IntegerScale]:
    """The vertices' exact coordinates as integers at ``scale`` (default: the least, :func:`common_scale`'s).

    One pass over the coordinates in Python: each double's ratio ``num / 2^k`` gives
    its grain and its integer. O(n).
    """
    flat: list[float] = pts.ravel().tolist()
    ratios = [x.as_integer_ratio() for x in flat]
    if scale is None:
        # common_scale(pts): the least grain (exponent of the lowest set bit) over the nonzero coordinates, else 0.
        lows = [((num & -num).bit_length() - den.bit_length()) for num, den in ratios if num]
        scale = IntegerScale(min(lows) if lows else 0)
    ints: list[int] = []
    for num, den in ratios:
        shift = scale.extra - scale.exponent - (den.bit_length() - 1)
        ints.append(num << shift if shift >= 0 else num >> -shift)  # exact: 2^-shift divides num
    return tuple(ints[0::2]), tuple(ints[1::2]), scale


def _winding(
    cycle: tuple[int, ...], tails: list[int], heads: list[int], xs: tuple[int, ...], ys: tuple[int, ...], px: int, py: int
) -> int:
    """The winding number of a walk around the integer point ``(px, py)``, not on it (Sunday's rule). O(walk)."""
    wn = 0
    for h in cycle:
        u, v = tails[h], heads[h]
        uy, vy = ys[u], ys[v]
        if uy <= py < vy:
            if (xs[v] - xs[u]) * (py - uy) - (vy - uy) * (px - xs[u]) > 0:
                wn += 1
        elif vy <= py < uy:
            if (xs[v] - xs[u]) * (py - uy) - (vy - uy) * (px - xs[u]) < 0:
                wn -= 1
    return wn
