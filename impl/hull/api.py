"""``convex_hull``: the exact 3D convex hull of a point array, with every intermediate hull kept.

The public face of the bulldozer (:mod:`persistri.impl.hull.bulldozer`, paper §3
and Appendix A): validation and duplicate merging at the boundary, exact
predicates with Simulation of Simplicity, the hull as a persistent 2-complex
over any ``ORD_MAP`` backend, and the result as numpy arrays of input row
indices.

>>> import numpy as np
>>> cube = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
>>> h = convex_hull(cube)
>>> h.vertices.tolist(), len(h.simplices)
([0, 1, 2, 3, 4, 5, 6, 7], 12)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.collector import collector_paused
from persistri.impl.complex.ephemeral import EphemeralTwoComplex
from persistri.impl.complex.simpcomp import two_complex
from persistri.impl.complex.structure import Complex
from persistri.impl.complex.versions import Versions
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.geometry.points import as_points, unique_rows
from persistri.impl.geometry.zorder import morton_order, morton_order_distinct
from persistri.impl.geometry.predicates import Predicates3
from persistri.impl.hull.bulldozer import (
    Bulldozer,
    BulldozerCheckError,
    FaceDatum,
    initial_tetrahedron,
    triangle_array,
)
from persistri.impl.flags import flag
from persistri.impl.hull.errors import DegenerateInputError
from persistri.impl.hull.packed import conflict_list
from persistri.impl.hull.slivers import remove_slivers
from persistri.impl.progress import progress_callback
from persistri.impl.stats import Stats

__all__ = ["convex_hull", "Hull", "HullHistory"]

IntArray = NDArray[np.intp]


def _corners(structure: TwoComplex[FaceDatum], c: Complex[FaceDatum]) -> IntArray:
    """The triangles of hull version ``c`` as an (m, 3) array of point indices (vertex labels), outward."""
    return triangle_array([t for t, _ in structure.items(c)])


def _triangles(structure: TwoComplex[FaceDatum], c: Complex[FaceDatum], rows: IntArray) -> IntArray:
    """The triangles of hull version ``c`` as an (m, 3) array of input rows, outward, sorted for stability."""
    return _as_rows(_corners(structure, c), rows)


def _as_rows(corners: IntArray, rows: IntArray) -> IntArray:
    """Triangles of point indices as input rows, each rotated to start at its smallest row (same orientation),
    the rows sorted: one canonical array per surface.

    The rotation by comparisons (a triangle's three rows are distinct); the sort, when a row index
    fits in a third of 63 bits, of one integer key per triangle packed from its three rows (a
    triangle's rows come back from its key; the order is the lexicographic one): at 500,000
    triangles a tenth of the time of ``argmin`` / ``take_along_axis`` / ``lexsort``.  O(m lg m).
    """
    if not corners.size:
        return np.zeros((0, 3), dtype=np.intp)
    arr = rows[corners]
    a, b, c = arr[:, 0], arr[:, 1], arr[:, 2]
    b_least = (b < a) & (b < c)
    c_least = (c < a) & (c < b)
    x = np.where(b_least, b, np.where(c_least, c, a))
    y = np.where(b_least, c, np.where(c_least, a, b))
    z = np.where(b_least, a, np.where(c_least, b, c))
    bits = int(arr.max()).bit_length()
    out: IntArray
    if 3 * bits <= 63:
        key = (x.astype(np.int64) << (2 * bits)) | (y.astype(np.int64) << bits) | z.astype(np.int64)
        key.sort()
        low = (1 << bits) - 1
        out = np.empty((key.size, 3), dtype=np.intp)
        np.right_shift(key, 2 * bits, out=out[:, 0])
        np.bitwise_and(np.right_shift(key, bits), low, out=out[:, 1])
        np.bitwise_and(key, low, out=out[:, 2])
        return out
    out = np.stack([x, y, z], axis=1)[np.lexsort((z, y, x))]
    return out


def _vertex_rows(simplices: IntArray, n_rows: int) -> IntArray:
    """The sorted distinct entries of ``simplices`` (rows below ``n_rows``): ``np.unique``'s answer by a
    mask of the rows instead of a sort (O(n_rows + m); a hundredth of the sort's time at 500,000 faces)."""
    used = np.zeros(n_rows, dtype=bool)
    used[simplices.ravel()] = True
    out: IntArray = np.flatnonzero(used)
    return out


@dataclass(frozen=True)
class HullHistory(Versions[FaceDatum]):
    """Every hull version of a run, oldest first: time travel (the versions share structure).

    ``versions[0]`` is the first tetrahedron; ``versions[k]`` the hull after the
    k-th insertion, of the point ``inserted[k]`` (input rows; ``inserted[0]`` is
    the tetrahedron's first row).  Keeping them costs O(lg n) new nodes per
    changed face, not a copy per version.
    """

    structure: TwoComplex[FaceDatum]
    rows: IntArray
    versions: tuple[Complex[FaceDatum], ...]
    inserted: tuple[int, ...]


    def simplices(self, k: int) -> IntArray:
        """The outward triangles of version ``k`` as input rows (like :attr:`Hull.simplices`). O(size)."""
        return _triangles(self.structure, self[k], self.rows)

    def vertices(self, k: int) -> IntArray:
        """The sorted input rows that are vertices of version ``k``."""
        return np.unique(self.simplices(k))

    def pending(self, k: int) -> IntArray:
        """The input rows still outside version ``k`` (the union of its conflict lists), sorted."""
        lists = [np.asarray(conflict_list(x), dtype=np.intp) for _, x in self.structure.items(self[k])]
        if not lists:
            return np.zeros(0, dtype=np.intp)
        return np.sort(self.rows[np.concatenate(lists)])


@dataclass(frozen=True)
class Hull:
    """The result of :func:`convex_hull`.

    * ``points`` — the input as validated (n × 3 float64);
    * ``simplices`` — (m × 3) input row indices, each triangle outward by the
      right-hand rule;
    * ``vertices`` — the sorted input rows that are hull vertices;
    * ``complex`` — the final SIMPCOMP value (data: ``(face id, conflict list)``; with
      ``history=True`` each packed in one ``int``: :func:`~persistri.impl.hull.packed.face_id` and
      :func:`~persistri.impl.hull.packed.conflict_list` read either form)
      and ``structure`` — the structure that reads it;
    * ``history`` — every intermediate hull (``history=True``), else None; its last
      version is the bulldozer's, before zero-area triangles were flipped away
      (:mod:`persistri.impl.hull.slivers`, counted in ``slivers_flipped``);
    * ``duplicates`` — ``(row, earlier equal row)`` for every merged duplicate;
    * ``stats`` — the counts, when a :class:`Stats` was given;
    * ``rows`` — the input row of each vertex label of ``complex``;
    * ``tetra``, ``bulldozed``, ``bulldozed_faces``, ``labels`` — what continuing
      the run needs (:func:`persistri.impl.hull.extend.extend_hull`): the labels
      of the first tetrahedron (the centre is its centroid), the bulldozer's last
      version before the sliver flips and its faces, and how the points were
      labelled.
    """

    points: NDArray[np.float64]
    simplices: IntArray
    vertices: IntArray
    complex: Complex[FaceDatum]
    structure: TwoComplex[FaceDatum]
    history: HullHistory | None
    duplicates: tuple[tuple[int, int], ...]
    seed: int
    backend: str
    stats: Stats | None = field(default=None)
    insertions: int = 0
    slivers_flipped: int = 0
    rows: IntArray | None = None
    """The input row of each vertex label of ``complex`` (labels are indices into the distinct points)."""
    tetra: tuple[int, int, int, int] | None = None
    """The labels of the first tetrahedron, in the order its centroid (the centre ``c``) was computed from."""
    bulldozed: Complex[FaceDatum] | None = None
    """The bulldozer's last version: ``complex`` before zero-area triangles were flipped away (the same
    object when none was)."""
    bulldozed_faces: IntArray | None = None
    """The faces of ``bulldozed`` as rows ``(face id, a, b, c)`` of vertex labels, outward
    (:meth:`~persistri.impl.hull.bulldozer.Bulldozer.face_table`)."""
    labels: str = "spatial"
    """How the distinct points were labelled (``convex_hull``'s ``labels``)."""


def convex_hull(
    points: ArrayLike,
    *,
    backend: str = "red_black",
    seed: int = 0,
    check: bool = False,
    history: bool = False,
    stats: Stats | None = None,
    progress: bool | Any = False,
    structure: TwoComplex[FaceDatum] | None = None,
    stepwise: bool = False,
    labels: str = "spatial",
) -> Hull:
    """The exact convex hull of ``points`` (n × 3) by the bulldozer algorithm (paper §3, Appendix A).

    * ``backend`` — the ``ORD_MAP`` backend of the complex (``persistri.impl.maps.BACKENDS``),
      or ``"ephemeral"`` for the NOT persistent baseline over a ``dict``
      (:mod:`persistri.impl.complex.ephemeral`; no ``history``);
    * ``seed`` — the random insertion order; the same seed gives the same hull;
    * ``check`` — assert the theorems of Appendix A at every insertion and verify the
      final hull exactly (:func:`persistri.impl.hull.verify.verify_hull`);
    * ``history`` — keep every intermediate hull version (:class:`HullHistory`); each face's
      datum is then packed in one ``int`` (:mod:`persistri.impl.hull.packed`: a fraction of the
      memory, a little more time per insertion), read with its ``face_id`` and ``conflict_list``;
    * ``stats`` — a :class:`Stats` to count dictionary operations, key comparisons,
      plane-side tests and flops into;
    * ``progress`` — True for a progress bar on stderr, or a callable taking the
      number of points processed since the last call;
    * ``structure`` — the 2-complex structure to build the hull in, instead of the one
      ``backend`` and ``stats`` name (e.g. a :class:`~persistri.impl.complex.trace.TracingTwoComplex`
      recording the run's complex operations); ``backend`` then only labels the result;
    * ``stepwise`` — change the complex as the paper's code does, one ``rem`` per lit
      face and one ``add`` per tent face, instead of one ``replace`` per insertion (the
      same hulls and versions; more map operations: what the experiments count);
    * ``labels`` — how the distinct points are numbered, which is the vertices' order as keys
      of the complex (and the index order of Simulation of Simplicity): ``"spatial"``
      (default) in z-order (:func:`~persistri.impl.geometry.zorder.morton_order`), so that
      the vertices one insertion touches are near in key order and the red-black map updates
      them in one batched descent; ``"input"`` in input order, as the paper's experiments
      (and persistri's) do.  Either way the same seed inserts the same points in the same
      order (from the same first tetrahedron, which ties among extreme points can change),
      and :attr:`Hull.rows` maps labels back to input rows.

    Errors: ``TypeError``/``ValueError`` for input that is not an n × 3 array of
    finite reals (NaN/inf names the first bad row); :class:`DegenerateInputError`
    when the distinct points are fewer than 4 or do not span space (it names the
    affine dimension); ``UnknownBackendError`` for an unknown backend.  Exactly
    equal rows are merged (reported in :attr:`Hull.duplicates`).

    Expected O(n lg n) time (Theorem 11, §3).
    """
    check, history, stepwise = flag("check", check), flag("history", history), flag("stepwise", stepwise)
    arr = as_points(points, 3)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise TypeError(f"seed must be an integer, not {type(seed).__name__}")
    if seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed}")
    if labels not in ("spatial", "input"):
        raise ValueError(f"convex_hull: labels must be 'spatial' or 'input', got {labels!r}")
    if structure is None:
        structure = two_complex(backend, stats)
    if history and isinstance(structure, EphemeralTwoComplex):
        raise ValueError("convex_hull: the ephemeral complex keeps no old versions, so history=True is impossible")
    # Persistent nodes form no reference cycles, so the cyclic collector only costs time here — a
    # great deal of it: each full collection walks every node of every version kept so far.
    with collector_paused(promote=False):
        return _convex_hull(arr, structure, backend, seed, check, history, stats, progress, stepwise, labels)


def _convex_hull(
    arr: NDArray[np.float64],
    structure: TwoComplex[FaceDatum],
    backend: str,
    seed: int,
    check: bool,
    history: bool,
    stats: Stats | None,
    progress: bool | Any,
    stepwise: bool = False,
    labels: str = "spatial",
) -> Hull:
    """:func:`convex_hull` on validated points, in the given 2-complex structure."""
    n_rows = arr.shape[0]
    # Spatial labels: the z-order first.  When its sort finds every Morton code distinct, every row is
    # distinct (equal rows have equal codes) and unique_rows' own sort is not needed (the usual case).
    spatial: IntArray | None = None
    if labels == "spatial":
        spatial, known_distinct = morton_order_distinct(arr)
        if not known_distinct:
            spatial = None
    if spatial is not None:
        rows = np.arange(n_rows, dtype=np.intp)
        merged: tuple[tuple[int, int], ...] = ()
    else:
        uniq = unique_rows(arr)
        rows = uniq.first  # label -> input row (the first of equal rows), in input order
        merged = tuple(
            (int(i), int(rows[uniq.inverse[i]])) for i in np.flatnonzero(rows[uniq.inverse] != np.arange(n_rows))
        )
    m = rows.size
    # Every row distinct (the usual case): rows is 0 … n-1, nothing was merged, and the distinct points are arr.
    distinct = m == n_rows
    if m < 4:
        pred0 = Predicates3(arr[rows])
        dim = len(pred0.affine_basis()) - 1
        raise DegenerateInputError(
            f"no 3D convex hull: {m} distinct point{'s' if m != 1 else ''} (at least 4 not on one plane are needed; "
            f"affine dimension {max(dim, 0)})",
            affine_dimension=max(dim, 0),
            distinct=m,
        )
    # by_input[label] = the label's position among the distinct points in input order; the random
    # order is drawn over those positions, so that both labellings insert the same points in turn
    # (when they start from the same tetrahedron: ties among the extremes it is chosen from can differ).
    by_input: IntArray = np.arange(m, dtype=np.intp)
    if labels == "spatial":
        by_input = spatial if spatial is not None else morton_order(arr if distinct else np.take(arr, rows, axis=0))
        rows = by_input.copy() if spatial is not None else rows[by_input]  # rows is 0 … n-1 when spatial is known
    # np.take copies whole rows; arr[rows] gathers element by element, five times slower in this
    # permuted order (34 against 7 ms at 256K points).  The copy is validated already (as_points).
    pred = Predicates3.of_validated(np.take(arr, rows, axis=0), stats=stats)
    tetra = initial_tetrahedron(pred, m)
    pred = pred.with_centroid(*tetra)

    # A run that keeps its history packs each face's datum in one int (every version keeps its lists).
    bd = Bulldozer(pred, structure, tetra, check=check, stepwise=stepwise, pack=history)
    t0, t1, t2, t3 = (int(by_input[t]) for t in tetra)
    label_of = np.empty(m, dtype=np.intp)
    label_of[by_input] = np.arange(m, dtype=np.intp)
    # The positions other than the tetrahedron's drawn in random order, as labels: a shuffle's swaps do not
    # depend on the values, so shuffling the labels is mapping the shuffled positions to labels (the same
    # order), without a gather in random order.
    order = np.random.default_rng(seed).permutation(np.delete(label_of, [t0, t1, t2, t3]))
    versions: list[Complex[FaceDatum]] = [bd.complex]
    inserted: list[int] = [int(rows[tetra[0]])]
    tick = progress_callback(progress, "hull", order.size, batch=1024)
    count = 0
    try:
        for p, version in bd.run(order, tick):
            count += 1
            if history:
                versions.append(version)
                inserted.append(int(rows[p]))
    finally:
        if hasattr(tick, "close"):
            tick.close()
    # The last version's faces from the bulldozer's face table, which mirrors them (check=True compares the two).
    faces = bd.face_table()
    faces.setflags(write=False)  # shared by every hull that continues this one
    corners = faces[:, 1:]
    final, flips = remove_slivers(structure, bd.complex, pred, corners)
    simplices = _as_rows(corners if flips == 0 else _corners(structure, final), rows)
    hull = Hull(
        points=arr,
        simplices=simplices,
        vertices=_vertex_rows(simplices, arr.shape[0]),
        complex=final,
        structure=structure,
        history=HullHistory(structure, rows, tuple(versions), tuple(inserted)) if history else None,
        duplicates=merged,
        seed=seed,
        backend=backend,
        stats=stats,
        insertions=count,
        slivers_flipped=flips,
        rows=rows,
        tetra=tetra,
        bulldozed=bd.complex,
        bulldozed_faces=faces,
        labels=labels,
    )
    if check:
        from persistri.impl.complex.checks import check_closed_surface
        from persistri.impl.hull.verify import verify_hull

        check_closed_surface(final)
        if not np.array_equal(simplices, _triangles(structure, final, rows)):
            raise BulldozerCheckError("the bulldozer's face table and its final complex disagree")
        verify_hull(arr, simplices).raise_if_failed()
    return hull
