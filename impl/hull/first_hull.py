"""The first hull: the initial tetrahedron, the cones that give every other point its first face, the first version.

The bulldozer starts from a tetrahedron of nonzero volume (chosen exactly by
:func:`initial_tetrahedron`) whose centroid is the fixed centre ``c``; each
other point is associated with the face through which the ray ``c → q``
leaves the tetrahedron (Appendix A.1): the face's **cone**.
:func:`cones_by_planes` computes the cones by their definition (the counted
and checked runs), :func:`cones_by_tree` by a decision tree of three tests per
point, and :func:`seen_in_cones` the points of each cone that see its face by
that tree's planes over whole columns (uncounted runs); :func:`first_hull` — the
first version of a run of :class:`~persistri.impl.hull.bulldozer.Bulldozer` —
uses one of them.  Each is O(n) plane-side tests, vectorised.  Once per run, so interpreted, beside
the compiled insertion loop.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from persistri.impl.complex.structure import Complex
from persistri.impl.geometry.filter import plane_side_box_threshold, plane_terms
from persistri.impl.geometry.kernel import Indices, _finite_range
from persistri.impl.geometry.predicates import Predicates3
from persistri.impl.hull.conflicts import (
    ON_HULL,
    PENDING,
    Entry,
    FaceDatum,
    IntArray,
    Triangle,
    _assign,
    _freeze,
    all_but,
)
from persistri.impl.hull.errors import BulldozerCheckError, DegenerateInputError
from persistri.impl.hull.packed import pack_face

if TYPE_CHECKING:
    from persistri.impl.hull.bulldozer import Bulldozer

__all__ = ["initial_tetrahedron", "cones_by_planes", "cones_by_tree", "seen_in_cones", "first_hull"]


def initial_tetrahedron(pred: Predicates3, n: int) -> tuple[int, int, int, int]:
    """Four points among the first ``n`` of ``pred`` spanning a tetrahedron of nonzero volume (exact).

    A fat tetrahedron is chosen from extremes (least x, farthest from it,
    farthest from their line, farthest from their plane, in floating point) and
    verified exactly; if that fails, the exact greedy
    :meth:`~persistri.impl.geometry.predicates.Predicates3.affine_basis` decides.
    Raises :class:`DegenerateInputError` naming the affine dimension when the
    points are identical, collinear or coplanar.  O(n).
    """
    pts = pred.points[:n]
    if n >= 4:
        with np.errstate(all="ignore"):
            # Scaled so that squares cannot overflow; a float heuristic, verified exactly below.  Dot
            # products column by column (no BLAS: a threaded BLAS call leaves its worker threads spinning,
            # which costs CPU time long after the call, 0.1 s at 256K points; no einsum: about 65
            # instructions a row here against about 15), summed as (x + z) + y: the values that this
            # machine's numpy einsum gives (it sums three products in two SSE lanes), so the same
            # tetrahedron as before, now on any numpy build.
            scale = max(float(pts.max()), -float(pts.min())) or 1.0
            i0 = int(np.argmin(pts[:, 0]))
            # The points less point i0, scaled before subtracting (1e308 - (-1e308) would overflow), one contiguous
            # array per axis (the passes below read contiguous memory).
            x, y, z = (pts[:, j] / scale for j in range(3))
            for col in (x, y, z):
                col -= col[i0]
            d0 = _dots(x, y, z, x, y, z)  # squared distances to point i0
            i1 = int(np.argmax(d0))
            ux, uy, uz = float(x[i1]), float(y[i1]), float(z[i1])
            along = _dots(x, y, z, ux, uy, uz)
            # Squared distances to the line (i0, i1), by Pythagoras: |dq|² - (dq·u)²/|u|².
            along *= along
            along /= (ux * ux + uz * uz) + uy * uy
            d0 -= along
            i2 = int(np.argmax(d0))
            nx, ny, nz = (float(v) for v in np.cross(np.array([ux, uy, uz]), np.array([x[i2], y[i2], z[i2]])))
            i3 = int(np.argmax(np.abs(_dots(x, y, z, nx, ny, nz))))
        cand = (i0, i1, i2, i3)
        if len(set(cand)) == 4 and pred.orient3d_sign(*cand) != 0:
            return cand
    basis = pred.affine_basis(np.arange(n, dtype=np.intp))
    if len(basis) < 4:
        dim = len(basis) - 1
        what = {-1: "there are no points", 0: "all points are identical", 1: "all points are collinear",
                2: "all points are coplanar"}[dim]
        raise DegenerateInputError(
            f"no 3D convex hull: {what} (affine dimension {max(dim, 0)}, {n} distinct points)",
            affine_dimension=max(dim, 0),
            distinct=n,
        )
    a, b, c, d = basis
    return (a, b, c, d)


def _dots(
    x: NDArray[np.float64], y: NDArray[np.float64], z: NDArray[np.float64],
    u: float | NDArray[np.float64], v: float | NDArray[np.float64], w: float | NDArray[np.float64],
) -> NDArray[np.float64]:
    """``(x·u + z·w) + y·v`` entry by entry, in a new array: :func:`initial_tetrahedron`'s dot products. O(len(x))."""
    out = x * u
    out += z * w
    out += y * v
    return out


def cones_by_planes(bd: Bulldozer, faces: list[Triangle], others: IntArray) -> dict[frozenset[int], IntArray]:
    """The points of ``others`` in the cone from the centre through each face, by the cone's definition.

    ``q`` is in the cone of face ``(x, y, z)`` iff it is on the inner side of the
    three planes ``(c, x, y)``, ``(c, y, z)``, ``(c, z, x)``: six planes in all,
    each tested on every point (counted runs, and ``check=True``, which also
    verifies that the cones partition the points).  O(n) tests.
    """
    P, C = bd.pred, bd.C
    side: dict[tuple[int, int], NDArray[np.int8]] = {}

    def plane_side(x: int, y: int) -> NDArray[np.int8]:
        if (x, y) in side:
            return side[(x, y)]
        if (y, x) in side:
            return -side[(y, x)]
        s = bd._signs(C, x, y, others)
        side[(x, y)] = s
        return s

    cones: dict[frozenset[int], IntArray] = {}
    claimed = np.zeros(others.size, dtype=bool)
    for tri in faces:
        x, y, z = tri
        inside = (
            (plane_side(x, y) == P.orient3d(C, x, y, z))
            & (plane_side(y, z) == P.orient3d(C, y, z, x))
            & (plane_side(z, x) == P.orient3d(C, z, x, y))
        )
        if bd.check and bool(np.any(inside & claimed)):
            raise BulldozerCheckError("the cones of the first tetrahedron's faces overlap")
        claimed |= inside
        cones[frozenset(tri)] = others[inside]
    if bd.check and others.size and not bool(claimed.all()):
        raise BulldozerCheckError("some point lies in no cone of the first tetrahedron's faces")
    return cones


def cones_by_tree(bd: Bulldozer, tetra: tuple[int, int, int, int], others: IntArray) -> dict[frozenset[int], IntArray]:
    """:func:`cones_by_planes` in three tests per point: a decision tree over the same planes.

    The plane ``(c, a, b)`` has ``c`` and ``d`` on opposite sides (the centre is
    inside), and the cone of ``abc`` lies on ``c``'s side, that of ``abd`` on
    ``d``'s.  On ``c``'s side the cones met are those of the three faces at
    ``c``; there, a point is in the cone of the face ``c x y`` iff it lies in
    the wedge between the half-planes that the axis from the centre through
    the apex ``c`` spans with ``x`` and with ``y`` — the routing question of
    the associated face (two tests of planes through the axis).  Likewise on
    ``d``'s side around the apex ``d``.  The same cones as the definition (a perturbed point set is
    in general position, where both are exact), each list in increasing
    order as there (``others`` must be increasing, as :func:`all_but` makes it: each partition keeps
    its order); ``tests/test_hull.py`` compares the two.  O(n) tests.
    """
    C, partition, o3 = bd.C, bd._partition, bd._o3

    def split(x: int, y: int, ref: int, pts: Indices) -> tuple[Indices, Indices]:
        """``pts`` on ``ref``'s side of the plane ``(c, x, y)``, and on the other side."""
        minus, plus = partition(C, x, y, pts)
        return (plus, minus) if o3(C, x, y, ref) > 0 else (minus, plus)

    a, b, c, d = tetra
    found: dict[frozenset[int], list[Indices]] = {}
    for apex, half, (x, y, z) in zip((c, d), split(a, b, c, others), ((a, b, d), (a, b, c))):
        # Around the axis from the centre through apex, the wedges between x, y and z.
        y_side, z_side = split(apex, x, y, half)
        in_xy, in_yz = split(apex, y, x, y_side)
        in_zx, in_zy = split(apex, z, x, z_side)
        for corners, pts in (((apex, x, y), in_xy), ((apex, y, z), in_yz), ((apex, y, z), in_zy), ((apex, z, x), in_zx)):
            found.setdefault(frozenset(corners), []).append(pts)
    return {key: _union(parts, bd.n) for key, parts in found.items()}


def _union(parts: list[Indices], n: int) -> IntArray:
    """The points of ``parts`` — disjoint lists of points below ``n``, each increasing — in increasing order.

    One part is its own order (a partition keeps the order of the points it splits); several are
    merged through a mask of the ``n`` points, not sorted (at 256K points a sort of 64K costs about
    70 instructions a point, the mask about 10).  O(n) for several parts, O(len) for one.
    """
    if len(parts) == 1:
        return np.asarray(parts[0], dtype=np.intp)
    mark = np.zeros(n, dtype=bool)
    for part in parts:
        mark[np.asarray(part, dtype=np.intp)] = True
    return np.flatnonzero(mark)


def seen_in_cones(bd: Bulldozer, tetra: tuple[int, int, int, int], faces: list[Triangle]) -> list[IntArray] | None:
    """For each face of ``faces`` (the first tetrahedron's, outward), the other points in its cone that see it, increasing:
    what :func:`cones_by_tree` and a partition of each cone by its face give, over whole columns.

    Each of the decision tree's six planes through the centre and the four faces is tested on every point at
    once by the kernel's semi-static stage (its threshold, from the same box; the determinant as the vectorised
    partition computes it, in three buffers), with no gathering of the points a plane is asked about (at 256K
    points a gathered partition costs about 75 instructions a point, most of them numpy's ``take``; a plane
    over every point about 15).  The few tests it leaves undecided are settled by the kernel's ``orient3d``
    (exactly, then by SoS) where the tree asks them.  The same signs, so the same lists.  None when the point
    set has no semi-static stage (an extreme dynamic range: the kernel tests through the checked methods).
    Appendix A.1 (the association of points to faces).  O(n).
    """
    pred = bd.pred
    if not pred._uniform:
        return None
    n, C, o3 = bd.n, bd.C, bd._o3
    (xlo, xhi), (ylo, yhi), (zlo, zhi) = (_finite_range(col) for col in pred._cols)
    static = plane_side_box_threshold(xhi - xlo, yhi - ylo, zhi - zlo)  # the kernel's threshold
    xs, ys, zs = (col[:n] for col in pred._cols)
    buffers = np.empty((3, n))

    def signs(a: int, b: int, c: int, need: NDArray[np.bool_]) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
        """The points with orient3d(a, b, c, q) = -1 and those with +1, each as a mask, exact where ``need``."""
        ax, ay, az = pred._row(a)
        nx, ny, nz, _, _, _ = plane_terms(ax, ay, az, *pred._row(b), *pred._row(c))
        # kernel.negated_plane_side_dets into the buffers: minus filter.plane_side_det_into's determinants
        gx, gy, gz = buffers
        np.subtract(xs, ax, out=gx)
        gx *= nx
        np.subtract(ys, ay, out=gy)
        gy *= ny
        gx += gy
        np.subtract(zs, az, out=gz)
        gz *= nz
        gx += gz
        neg = gx > static
        pos = gx < -static
        open_ = neg | pos
        np.logical_not(open_, out=open_)
        open_ &= need
        if open_.any():
            for q in np.flatnonzero(open_).tolist():
                if o3(a, b, c, q) < 0:
                    neg[q] = True
                else:
                    pos[q] = True
        return neg, pos

    def split(x: int, y: int, ref: int, pts: NDArray[np.bool_]) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
        """:func:`cones_by_tree`'s split, as masks: ``pts`` on ``ref``'s side of the plane ``(c, x, y)``, and on the other."""
        minus, plus = signs(C, x, y, pts)
        minus &= pts
        plus &= pts
        return (plus, minus) if o3(C, x, y, ref) > 0 else (minus, plus)

    a, b, c, d = tetra
    others = np.ones(n, dtype=bool)
    others[list(tetra)] = False
    cones: dict[frozenset[int], NDArray[np.bool_]] = {}
    for apex, half, (x, y, z) in zip((c, d), split(a, b, c, others), ((a, b, d), (a, b, c))):
        y_side, z_side = split(apex, x, y, half)
        in_xy, in_yz = split(apex, y, x, y_side)
        in_zx, in_zy = split(apex, z, x, z_side)
        for corners, pts in (((apex, x, y), in_xy), ((apex, y, z), in_yz), ((apex, y, z), in_zy), ((apex, z, x), in_zx)):
            key = frozenset(corners)
            if key in cones:
                cones[key] |= pts
            else:
                cones[key] = pts
    seen: list[IntArray] = []
    for tri in faces:
        cone = cones[frozenset(tri)]
        sees, _ = signs(tri[0], tri[1], tri[2], cone)
        sees &= cone
        seen.append(np.flatnonzero(sees))
    return seen


def new_face(bd: Bulldozer, tri: Triangle, kept: Indices) -> Entry:
    """A new face ``tri`` of ``bd`` with the conflict list ``kept``: its id, its table entry, its points' association.

    What :meth:`Bulldozer.insert <persistri.impl.hull.bulldozer.Bulldozer.insert>` does for each
    tent face, written out there.  O(len(kept)).
    """
    fid = bd._next_fid
    bd._next_fid += 1
    conflict = _freeze(kept)
    _assign(bd._assoc, bd.assoc, conflict, fid)
    entry: Entry = (tri, pack_face(fid, conflict) if bd.packed else (fid, conflict))
    bd.faces[fid] = entry
    if bd._table is not None:
        bd._table.add(fid, tri)
    return entry


def first_hull(bd: Bulldozer, tetra: tuple[int, int, int, int]) -> Complex[FaceDatum]:
    """The first version of ``bd``'s run: the tetrahedron ``tetra``, outward, each face with its conflict list.

    Every other point is associated with the face whose cone holds it
    (:func:`cones_by_planes` in counted and checked runs, whose counts are the
    paper's; :func:`seen_in_cones` otherwise, or :func:`cones_by_tree` for a point
    set without the kernel's semi-static stage) and joins its list if it sees the
    face; the four corners are on the hull, the points that see no face are
    interior.  O(n) plane-side tests, vectorised; four ``add`` of the complex.
    """
    P = bd.pred
    V = {i: bd._vertex(i) for i in tetra}
    a, b, c, d = tetra
    faces: list[Triangle] = []
    for (i, j, k), opp in (((a, b, c), d), ((a, d, b), c), ((b, d, c), a), ((c, d, a), b)):
        # Outward: the opposite vertex (inside) is below the face (+1).
        tri = (V[i], V[j], V[k]) if P.orient3d(i, j, k, opp) > 0 else (V[i], V[k], V[j])
        faces.append(tri)
    bd.status[list(tetra)] = ON_HULL
    # Each other point goes to the face its ray from the centre leaves through: the face's cone.
    counted = bd.check or P.stats is not None
    found = None if counted else seen_in_cones(bd, tetra, faces)
    seen: list[Indices] = [] if found is None else list(found)
    if found is None:
        others = all_but(bd.n, tetra)
        if counted:
            cones = cones_by_planes(bd, faces, others)  # by definition: checked, and the counts of the paper
        else:
            cones = cones_by_tree(bd, tetra, others)
        for tri in faces:
            x, y, z = tri
            out, _ = bd._partition(x, y, z, cones[frozenset(tri)])
            seen.append(out)
    cx = bd.S.new(2)
    for tri, out in zip(faces, seen):
        _assign(bd._status, bd.status, out, PENDING)
        cx = bd.S.add(cx, *new_face(bd, tri, out))
    return cx
