"""``extend_hull``: adding points to a finished hull, as a new hull that shares structure with the old one.

A persistent complex makes this cheap to keep *both*: the bulldozer (paper §3,
Appendix A) simply continues from the old hull's last version, and every face
the new points do not touch — its triangle, its datum, the per-vertex lists and
map nodes holding it — is the same object in the old hull and the new one.
The old :class:`~persistri.impl.hull.api.Hull`, its complex and every version
of its history stay valid and unchanged (§1's "multiple futures": two
extensions of one hull are two branches).

The continuation is the bulldozer's own, with the invariants of Appendix A.1
restored for the new points:

1. **Labels.**  The distinct new points get labels after the old ones (in
   z-order among themselves, or input order, as the old run labelled its
   points); the predicates are rebuilt over old + new points.  Every old test
   is decided as before, ties included: the exact signs are of the same
   rationals (the integer scale is a power of two, which no sign depends on,
   and nothing is translated), and Simulation of Simplicity depends only on the
   *order* of the indices, which is unchanged among the old points and the
   centre — the centre keeps the largest index, after the new points too.
2. **The centre** ``c`` is the same point: the centroid of the same first
   tetrahedron, computed from the same four doubles in the same order (or the
   same exact centroid).
3. **Association.**  Each new point goes to the face through which the ray
   ``c → q`` leaves the old hull (its cone from ``c``), and joins that face's
   conflict list if it is beyond the face; otherwise it is inside the old hull,
   hence inside the new one, and is dropped.  The faces are found by a
   vectorised walk over the hull's adjacency (below), not by testing every
   face.
4. **Insertion.**  The outside points are inserted by the bulldozer in a random
   order drawn from the hull's seed (mixed with its number of distinct points,
   so each step of a chain draws afresh), and the result is post-processed by
   :func:`~persistri.impl.hull.slivers.remove_slivers` like any hull.

**Which version is continued.**  The bulldozer's own last version
(:attr:`Hull.bulldozed`), not :attr:`Hull.complex`: the sliver flips that make
``complex`` are real-geometry repairs (coplanar flips of zero-area triangles),
and the flipped surface is not the hull of the *perturbed* points the
bulldozer's invariants speak of — a flipped edge can be reflex under Simulation
of Simplicity, so the walking graph's theorems (acyclicity, Lemma 9's
reachability) would not hold on it.  The flips also give two triangles the
same datum, while the bulldozer identifies faces by the id in their datum.  So
the continuation starts from the perturbed hull, and its end is flipped again.

**Locating the new points.**  The cones from ``c`` through the faces partition
space, and crossing an edge ``(u, w)`` from its face leads out of the face's
cone exactly when ``orient3d(u, w, c, q) = +1``.  All points walk at once, one
round of three vectorised, exact ``orient3d`` batches
(:meth:`~persistri.impl.geometry.predicates.Predicates3.orient3d_many`: a float
filter, exact integers and SoS for what it leaves) per step, each crossing a
random one of the edges it lies beyond (a fixed choice can cycle for ever in a
triangulation that is not Delaunay; the random one — Devillers, Pion and
Teillaud's stochastic walk — almost surely ends in the plane, and the round
limit below makes the end certain here).  Each
starts from the face whose centroid's direction from ``c`` is nearest its own
(a k-d tree, in floating point: only a hint), so walks are a few steps long.
A point still walking after ``4·√h + 64`` rounds is located by testing every
face's cone (exact, never expected).

Cost, for a hull of ``n`` input rows and ``h`` faces and ``k`` new rows, all
of it vectorised except the bulldozer's insertions:

* O((n + k) lg(n + k)) set-up: duplicate detection, the predicates over all
  points, the concatenated points array;
* O(h lg h) on the old version's face array (:attr:`Hull.bulldozed_faces`):
  the bulldozer's face table by id, the adjacency for the walk, the k-d tree;
* O(k lg h + k · L) to locate the new points by walks of ``L`` rounds —
  measured 6 to 19 rounds for 2,000 to 20,000 new points on hulls of 4,000 to
  100,000 faces, where a point takes part in 1.4 to 1.7 rounds on average
  (most start in their own cone); never a test of every face for every point;
* the bulldozer's own cost for the outside points: O(1) complex operations of
  O(lg n) per face created or deleted, and their plane-side tests (§3).

No Python code runs per old face or per old point (``check=True`` aside, which
also reads every face of the old version): what the old run built and the new
points leave alone is neither copied nor traversed again.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.collector import collector_paused
from persistri.impl.complex.ephemeral import EphemeralTwoComplex
from persistri.impl.complex.structure import Complex
from persistri.impl.geometry.points import appended_rows, as_points
from persistri.impl.geometry.predicates import Predicates3
from persistri.impl.geometry.zorder import morton_order
from persistri.impl.hull.api import Hull, HullHistory, _as_rows, _corners, _triangles, _vertex_rows
from persistri.impl.hull.bulldozer import Bulldozer, BulldozerCheckError, FaceDatum
from persistri.impl.hull.slivers import remove_slivers
from persistri.impl.progress import progress_callback

__all__ = ["extend_hull", "locate_in_cones"]

IntArray = NDArray[np.intp]

_EDGES = ((0, 1), (1, 2), (2, 0))
"""The edges of a face ``(a, b, d)`` in the bulldozer's order: ``(a, b)``, ``(b, d)``, ``(d, a)``."""


def extend_hull(hull: Hull, new_points: ArrayLike, *, check: bool = False, progress: bool | Any = False) -> Hull:
    """The hull of ``hull.points`` and ``new_points`` together, continuing ``hull``'s run; ``hull`` is unchanged.

    * ``points`` of the result are ``hull.points`` followed by the rows of
      ``new_points``; ``simplices``, ``vertices`` and ``duplicates`` index that
      concatenation.  A new row equal to an old row or to an earlier new row is
      merged and reported in ``duplicates``, as :func:`~persistri.impl.hull.api.convex_hull`
      reports equal rows.
    * The new complex shares every face the new points do not touch with
      ``hull.complex`` (the same data objects, per-vertex lists and map nodes); if
      every new point is inside the old hull, it *is* ``hull.complex``.
    * ``history``: if ``hull`` kept one, the old versions (the same objects)
      followed by one version per insertion of a new point; else None.
    * ``seed``, ``backend``, ``labels`` and the complex structure are ``hull``'s;
      with a :class:`~persistri.impl.stats.Stats` attached to ``hull``, the
      extension's work is counted into that same object.
    * ``check`` — the bulldozer's Appendix-A checks at every insertion, each new
      point's cone verified, and the final hull verified exactly
      (:func:`~persistri.impl.hull.verify.verify_hull`).
    * ``progress`` — True for a progress bar on stderr, or a callable taking the
      number of points processed since the last call.

    Errors: ``TypeError``/``ValueError`` for ``new_points`` that are not a
    ``(k, 3)`` array of finite reals (as ``convex_hull``; NaN/inf names the
    first bad row of ``new_points``); ``ValueError`` for a hull over the
    ephemeral complex (it keeps no old versions: extending it would change the
    old hull) or one that does not record its run.

    Paper §3 and Appendix A.1 (the module docstring says which version is
    continued and why, and what each step costs: no step tests every face for
    every new point).

    >>> import numpy as np
    >>> from persistri.impl.hull.api import convex_hull
    >>> cube = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
    >>> old = convex_hull(cube)
    >>> new = extend_hull(old, [[0.5, 0.5, 2.0], [0.5, 0.5, 0.5]])  # a roof above the top face, and a point inside
    >>> new.vertices.tolist(), len(new.simplices), len(old.simplices)
    ([0, 1, 2, 3, 4, 5, 6, 7, 8], 14, 12)
    """
    new = as_points(new_points, 3, what="new points")
    if not isinstance(hull, Hull):
        raise TypeError(f"extend_hull: hull must be a Hull made by convex_hull, not {type(hull).__name__}")
    if isinstance(hull.structure, EphemeralTwoComplex):
        raise ValueError(
            "extend_hull: the ephemeral complex keeps no old versions, so extending this hull would change it "
            "(build it with a persistent backend)"
        )
    if hull.tetra is None or hull.bulldozed is None or hull.bulldozed_faces is None or hull.rows is None:
        raise ValueError("extend_hull: this hull does not record the bulldozer run it came from (made by convex_hull?)")
    with collector_paused(promote=False):  # as convex_hull: persistent nodes form no cycles
        return _extend(hull, new, check, progress)


def _extend(hull: Hull, new: NDArray[np.float64], check: bool, progress: bool | Any) -> Hull:
    """:func:`extend_hull` on validated input."""
    assert hull.tetra is not None and hull.bulldozed is not None and hull.bulldozed_faces is not None
    assert hull.rows is not None
    S = hull.structure
    n_old = hull.points.shape[0]
    points = np.concatenate([hull.points, new])
    points.setflags(write=False)

    # Distinct new points: a row's representative is its first equal row (an old one if there is one), as
    # convex_hull's; the old rows keep theirs, since the concatenation only appends.
    merged, fresh = appended_rows(points, n_old)  # fresh: input order
    m_old = hull.rows.size
    by_input: IntArray = np.arange(fresh.size, dtype=np.intp)
    if hull.labels == "spatial" and fresh.size:
        by_input = morton_order(np.take(points, fresh, axis=0))
    rows = np.concatenate([hull.rows, fresh[by_input]])
    m = rows.size
    labels = np.arange(m_old, m, dtype=np.intp)

    tetra = (int(hull.tetra[0]), int(hull.tetra[1]), int(hull.tetra[2]), int(hull.tetra[3]))
    pred = Predicates3(np.take(points, rows, axis=0), stats=hull.stats).with_centroid(*tetra)
    table = hull.bulldozed_faces
    # Packed when the hull keeps its history: its versions, the one resumed included, hold packed data.
    bd = Bulldozer(pred, S, tetra, check=check, resume=(hull.bulldozed, table), pack=hull.history is not None)

    # Associate each new point with its face (Appendix A.1): locate its cone by a walk, then attach.
    where = locate_in_cones(pred, table[:, 1:], labels, seed=hull.seed)
    bd.attach(labels, table[where, 0])

    # Insert the outside ones in a random order over their input positions (so that the labelling does
    # not change it, as in convex_hull), drawn from the hull's seed and its size.
    drawn = np.random.default_rng((hull.seed, m_old)).permutation(fresh.size)
    label_of = np.empty(fresh.size, dtype=np.intp)
    label_of[by_input] = labels
    order = label_of[drawn]
    versions: list[Complex[FaceDatum]] = []
    inserted: list[int] = []
    keep = hull.history is not None
    tick = progress_callback(progress, "hull", order.size, batch=1024)
    count = 0
    try:
        for p, version in bd.run(order, tick):
            count += 1
            if keep:
                versions.append(version)
                inserted.append(int(rows[p]))
    finally:
        if hasattr(tick, "close"):
            tick.close()

    if count == 0:
        # Every new point is inside: no face changed (attach made no version), and the flipped hull is the old one.
        assert bd.complex is hull.bulldozed
        final, flips, simplices = hull.complex, hull.slivers_flipped, hull.simplices.copy()
        faces = table
    else:
        faces = bd.face_table()
        faces.setflags(write=False)
        tri_labels = faces[:, 1:]
        final, flips = remove_slivers(S, bd.complex, pred, tri_labels)
        simplices = _as_rows(tri_labels if flips == 0 else _corners(S, final), rows)
    history = None
    if hull.history is not None:
        history = HullHistory(S, rows, hull.history.versions + tuple(versions), hull.history.inserted + tuple(inserted))
    out = Hull(
        points=points,
        simplices=simplices,
        vertices=_vertex_rows(simplices, points.shape[0]),
        complex=final,
        structure=S,
        history=history,
        duplicates=hull.duplicates + merged,
        seed=hull.seed,
        backend=hull.backend,
        stats=hull.stats,
        insertions=hull.insertions + count,
        slivers_flipped=flips,
        rows=rows,
        tetra=tetra,
        bulldozed=bd.complex,
        bulldozed_faces=faces,
        labels=hull.labels,
    )
    if check:
        from persistri.impl.complex.checks import check_closed_surface
        from persistri.impl.hull.verify import verify_hull

        check_closed_surface(final)
        if not np.array_equal(simplices, _triangles(S, final, rows)):
            raise BulldozerCheckError("the extended hull's face table and its final complex disagree")
        verify_hull(points, simplices).raise_if_failed()
    return out


def _across(corners: IntArray) -> IntArray:
    """``across[j, e]``: the face holding edge ``e`` of face ``j`` reversed (edges in :data:`_EDGES` order).

    On a closed, consistently oriented surface each edge is in two faces, once
    in each direction: sorting the 3h directed edges by their undirected key
    puts the two next to each other.  O(h lg h) vectorised for ``h`` faces.
    Raises :class:`BulldozerCheckError` if the faces are not such a surface.
    """
    h = corners.shape[0]
    src = np.concatenate([corners[:, i] for i, _ in _EDGES]).astype(np.int64)
    dst = np.concatenate([corners[:, j] for _, j in _EDGES]).astype(np.int64)
    base = int(corners.max()) + 1 if h else 1
    key = np.minimum(src, dst) * base + np.maximum(src, dst)
    order = np.argsort(key)
    first, second = order[0::2], order[1::2]
    paired = (
        first.size == second.size
        and bool(np.all(key[first] == key[second]))
        and bool(np.all(src[first] == dst[second]))
        and bool(np.all(key[second[:-1]] != key[first[1:]]))
    )
    if not paired:
        raise BulldozerCheckError("the hull is not a closed, oriented surface: an edge is not in exactly two faces")
    out = np.empty(3 * h, dtype=np.intp)
    out[first] = second % h
    out[second] = first % h
    return out.reshape(3, h).T.copy()


def _start_faces(pred: Predicates3, corners: IntArray, queries: IntArray) -> IntArray:
    """For each query point, the face whose centroid's direction from the centre is nearest its own (a hint).

    Floating point on copies scaled by the largest coordinate (nothing
    overflows); a direction that is not finite (a point at the centre, or an
    underflow) is left at 0, and its walk is merely longer.  O((h + k) lg h).
    """
    from scipy.spatial import cKDTree

    pts = pred.points
    c = pred.centre
    assert c is not None
    with np.errstate(all="ignore"):
        scale = float(np.max(np.abs(pts[np.isfinite(pts).all(axis=1)]))) or 1.0
        origin = pts[c] / scale
        dirs = (pts[corners[:, 0]] / scale + pts[corners[:, 1]] / scale + pts[corners[:, 2]] / scale) / 3 - origin
        dirs /= np.linalg.norm(dirs, axis=1)[:, None]
        qdirs = pts[queries] / scale - origin
        qdirs /= np.linalg.norm(qdirs, axis=1)[:, None]
    dirs[~np.isfinite(dirs).all(axis=1)] = 0.0
    qdirs[~np.isfinite(qdirs).all(axis=1)] = 0.0
    found = cKDTree(dirs).query(qdirs)[1]
    return np.asarray(found, dtype=np.intp)


def _walk_rounds(h: int) -> int:
    """How many rounds the walks get on a surface of ``h`` faces before the stragglers are decided by every cone."""
    return 4 * math.isqrt(h) + 64


def locate_in_cones(pred: Predicates3, corners: IntArray, queries: IntArray, *, seed: int = 0) -> IntArray:
    """For each point of ``queries``, the row of ``corners`` whose cone from the centre holds it (exact).

    ``corners`` (h × 3 point indices of ``pred``) are the faces of a closed,
    outward surface around ``pred``'s centre ``c`` in which ``c`` is strictly
    behind every face — a bulldozer hull, with Simulation of Simplicity — so
    the cones from ``c`` through the faces partition space, and ``q`` is in the
    cone of face ``(a, b, d)`` iff ``orient3d(u, w, c, q) = -1`` on each of its
    edges ``(u, w)`` (Appendix A.1's association; the bulldozer's arc test).
    The queries must be points of ``pred`` other than the faces' vertices
    and ``c``.

    All queries walk together from the faces :func:`_start_faces` suggests: each
    round tests the current face's three edges of every walking point in three
    vectorised batches, and a point outside its face's cone crosses one of the
    edges it lies beyond, chosen at random (``seed``; the answer does not
    depend on it).  Points still walking after ``4·√h + 64`` rounds are located
    by testing every cone.  O(k · L) tests for walks of ``L`` rounds, plus
    O(h lg h) set-up.
    """
    centre = pred.centre
    if centre is None:
        raise ValueError("locate_in_cones: the predicates need their centre (with_centroid)")
    h, k = corners.shape[0], queries.size
    if k == 0:
        return np.zeros(0, dtype=np.intp)
    across = _across(corners)
    cur = _start_faces(pred, corners, queries)
    rng = np.random.default_rng(seed)
    active = np.arange(k, dtype=np.intp)
    for _ in range(_walk_rounds(h)):
        f = cur[active]
        q = queries[active]
        exits = np.empty((active.size, 3), dtype=bool)
        for e, (i, j) in enumerate(_EDGES):
            exits[:, e] = pred.orient3d_many(corners[f, i], corners[f, j], centre, q) > 0
        n_exits = exits.sum(axis=1)
        moving = n_exits > 0
        if not moving.any():
            active = active[:0]
            break
        # The r-th exit edge of each walking point, r uniform among its exits.
        r = (rng.random(active.size) * n_exits).astype(np.intp)
        choice = np.argmax(np.cumsum(exits, axis=1) > r[:, None], axis=1)
        cur[active[moving]] = across[f[moving], choice[moving]]
        active = active[moving]
    for j in active.tolist():
        # Never expected: decide by every face's cone.
        point = int(queries[j])
        inside = np.ones(h, dtype=bool)
        for i, i2 in _EDGES:
            inside &= pred.orient3d_many(corners[:, i], corners[:, i2], centre, point) < 0
        hits = np.flatnonzero(inside)
        if hits.size != 1:
            raise BulldozerCheckError(
                f"point {point} lies in {hits.size} cones of the hull's faces: not a closed surface around the centre"
            )
        cur[j] = hits[0]
    return cur
