"""``verify_hull``: an exact, independent check of a 3D convex hull, from any source.

Given input points and triangles (row indices), :func:`verify_hull` decides
exactly — with the predicates' true signs, no perturbation and no epsilon —
whether the triangles are the boundary of the convex hull of the points, and
says precisely what fails.  It does not trust the algorithm that produced the
hull: persistri's bulldozer, scipy's Qhull or anything else.

The checks, in order:

1. **combinatorial** — indices in range, three distinct per triangle; every
   oriented edge once and its reverse once (a closed, consistently oriented
   surface); every vertex link a single cycle; Euler characteristic 2 (a sphere);
2. **star-shaped and outward** — a point ``g`` strictly inside (the centroid of a
   tetrahedron of hull vertices) is strictly below every face plane;
3. **locally convex** — at every edge the neighbour's far vertex is on or below
   the face's plane;
4. **containment** — every input point is on or below the face whose cone from
   ``g`` contains it (located by an exact walk).

Why 1–4 suffice: by 1 and 2 the radial projection from ``g`` maps the surface
one-to-one onto a sphere, so it bounds a star-shaped polyhedron; by 3 that
polyhedron is locally convex at every edge, hence convex (Tietze–Nakajima).
Its vertices are input points, so it is inside the hull; by 4 every input point
is inside it, so it is the hull — and every extreme point is one of its vertices.
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.geometry.points import as_points
from persistri.impl.geometry.predicates import Predicates3

__all__ = ["verify_hull", "HullReport", "HullVerificationError"]


class HullVerificationError(AssertionError):
    """A hull failed :func:`verify_hull`; the message lists what is wrong."""


@dataclass
class HullReport:
    """What :func:`verify_hull` found: ``ok`` when ``problems`` is empty."""

    faces: int = 0
    vertices: int = 0
    problems: list[str] = field(default_factory=list)
    outside: list[int] = field(default_factory=list)
    """Input rows found strictly outside the hull (at most ``max_problems`` of them)."""

    @property
    def ok(self) -> bool:
        return not self.problems

    def raise_if_failed(self) -> None:
        """Raise :class:`HullVerificationError` listing the problems, if any."""
        if self.problems:
            raise HullVerificationError("not a valid convex hull:\n  " + "\n  ".join(self.problems))

    def __str__(self) -> str:
        if self.ok:
            return f"valid convex hull: {self.faces} faces, {self.vertices} vertices"
        return "not a valid convex hull:\n  " + "\n  ".join(self.problems)


def verify_hull(
    points: ArrayLike,
    simplices: ArrayLike,
    *,
    require_outward: bool = True,
    max_problems: int = 10,
) -> HullReport:
    """Check exactly that ``simplices`` (m × 3 row indices) bound the convex hull of ``points``.

    ``require_outward=False`` first orients each triangle away from an interior
    point (for hulls, like scipy's, whose triangles are not consistently
    oriented).  Returns a :class:`HullReport`; ``report.raise_if_failed()``
    raises with every problem found.  Cost: O(m) combinatorics, O(m) exact
    orientation tests, and a walk per input point (short when points are
    spatially coherent).
    """
    if isinstance(max_problems, bool) or not isinstance(max_problems, (int, np.integer)) or max_problems < 1:
        raise ValueError(f"max_problems must be a positive integer, got {max_problems!r}")
    pts = as_points(points, 3)
    tri = np.asarray(simplices)
    rep = HullReport()

    def problem(msg: str) -> bool:
        rep.problems.append(msg)
        return len(rep.problems) >= max_problems

    if tri.ndim != 2 or tri.shape[1] != 3 or tri.dtype.kind not in "iu":
        problem(f"simplices must be an (m, 3) integer array, got shape {tri.shape} of {tri.dtype}")
        return rep
    n = pts.shape[0]
    tri = tri.astype(np.intp)
    rep.faces = tri.shape[0]
    if rep.faces < 4:
        problem(f"a closed surface needs at least 4 triangles, got {rep.faces}")
        return rep
    if tri.min() < 0 or tri.max() >= n:
        problem(f"simplices index rows outside 0..{n - 1}")
        return rep
    bad = (tri[:, 0] == tri[:, 1]) | (tri[:, 1] == tri[:, 2]) | (tri[:, 0] == tri[:, 2])
    if bad.any():
        k = int(np.argmax(bad))
        problem(f"triangle {k} {tri[k].tolist()} repeats a vertex")
        return rep
    verts = np.unique(tri)
    rep.vertices = verts.size
    pred = Predicates3(pts)

    # An interior reference point g: the centroid of a tetrahedron of hull vertices.
    a, b, c = (int(x) for x in tri[0])
    d = next((int(v) for v in verts if pred.orient3d_sign(a, b, c, int(v)) != 0), None)
    if d is None:
        problem("all hull vertices are coplanar: the surface encloses no volume")
        return rep
    pg = pred.with_centroid(a, b, c, d)
    g = n
    below = np.array([pg.orient3d_sign(int(x), int(y), int(z), g) for x, y, z in tri], dtype=np.int8)
    if not require_outward:
        tri = np.where((below < 0)[:, None], tri[:, [0, 2, 1]], tri)
        below = np.abs(below)
    for k in np.flatnonzero(below <= 0)[:max_problems].tolist():
        if below[k] != 0:
            what = "faces inward"
        elif pred.collinear(*(int(v) for v in tri[k])):
            what = "has zero area (its vertices are collinear)"
        else:
            what = "contains the interior point in its plane"
        if problem(f"triangle {k} {tri[k].tolist()} {what}"):
            return rep
    if rep.problems:
        return rep

    # 1. Combinatorics: edges pair up, links are cycles, Euler characteristic 2.
    nxt: dict[tuple[int, int], int] = {}
    for x, y, z in tri.tolist():
        for u, w, f in ((x, y, z), (y, z, x), (z, x, y)):
            if (u, w) in nxt:
                if problem(f"oriented edge ({u}, {w}) is in two triangles"):
                    return rep
            nxt[(u, w)] = f
    for u, w in nxt:
        if (w, u) not in nxt and problem(f"edge ({u}, {w}) has no triangle on its other side (a hole)"):
            return rep
    if rep.problems:
        return rep
    link: dict[int, dict[int, int]] = {}
    for x, y, z in tri.tolist():
        for v, p, q in ((x, y, z), (y, z, x), (z, x, y)):
            link.setdefault(v, {})[p] = q
    for v, succ in link.items():
        start = next(iter(succ))
        cur, steps = succ[start], 1
        while cur != start and steps <= len(succ):
            cur = succ.get(cur, start)
            steps += 1
        if steps != len(succ) and problem(f"the link of vertex {v} is not a single cycle"):
            return rep
    euler = verts.size - len(nxt) // 2 + rep.faces
    if euler != 2 and problem(f"Euler characteristic {euler}, not 2: the surface is not a sphere"):
        return rep
    if rep.problems:
        return rep

    # 3. Local convexity at every edge.
    for (u, w), f in nxt.items():
        if u < w:
            h = nxt[(w, u)]
            if pg.orient3d_sign(u, w, f, h) < 0 and problem(
                f"edge ({u}, {w}) is reflex: vertex {h} is above triangle ({u}, {w}, {f})"
            ):
                return rep
    if rep.problems:
        return rep

    # 4. Every input point on or below the face whose cone from g holds it.
    faces = [tuple(t) for t in tri.tolist()]
    across = {(u, w): i for i, t in enumerate(faces) for u, w in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
    side_cache: dict[tuple[int, int], int] = {}

    def inner(u: int, w: int, f: int) -> int:
        key = (u, w)
        s = side_cache.get(key)
        if s is None:
            s = pg.orient3d_sign(g, u, w, f)
            side_cache[key] = s
        return s

    with np.errstate(all="ignore"):  # a heuristic: overflow near ±1e308 only disables it (isfinite below)
        cen = pts[tri].mean(axis=1)
        gf = pts[[a, b, c, d]].mean(axis=0)
        dirs = cen - gf
        dirs /= np.linalg.norm(dirs, axis=1)[:, None]
        qdirs = pts - gf
        qdirs /= np.linalg.norm(qdirs, axis=1)[:, None]
    first_face: NDArray[np.intp] = np.zeros(n, dtype=np.intp)
    if np.isfinite(dirs).all() and np.isfinite(qdirs).all():
        from scipy.spatial import cKDTree

        first_face = np.asarray(cKDTree(dirs).query(qdirs)[1], dtype=np.intp)
    rng = random.Random(0)
    limit = 4 * len(faces) + 16
    on_hull = np.zeros(n, dtype=bool)
    on_hull[verts] = True
    for q in range(n):
        if on_hull[q]:
            continue
        fi = int(first_face[q])
        for _ in range(limit):
            x, y, z = faces[fi]
            exits = [
                (u, w)
                for u, w, f in ((x, y, z), (y, z, x), (z, x, y))
                if pg.orient3d_sign(g, u, w, q) == -inner(u, w, f) != 0
            ]
            if not exits:
                break
            u, w = exits[rng.randrange(len(exits))]
            fi = across[(w, u)]
        else:  # the walk did not settle: decide by every face (exact, slow, never expected)
            fi = -1
        if fi < 0:
            above = [i for i, (x, y, z) in enumerate(faces) if pg.orient3d_sign(x, y, z, q) < 0]
            outside = bool(above)
            where = faces[above[0]] if above else None
        else:
            x, y, z = faces[fi]
            outside = pg.orient3d_sign(x, y, z, q) < 0
            where = faces[fi]
        if outside:
            rep.outside.append(q)
            if problem(f"point {q} {pts[q].tolist()} is outside the hull, beyond triangle {list(where or ())}"):
                return rep
    return rep
