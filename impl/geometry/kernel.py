"""The trusted fast path of ``orient3d`` for the bulldozer: :class:`Orient3dKernel` (paper §3, Appendix A).

:meth:`Predicates3.kernel <persistri.impl.geometry.predicates.Predicates3.kernel>`
makes it.  It answers the same signs as the checked
:class:`~persistri.impl.geometry.predicates.Predicates3`, through the same proven
filter, exact fallback and Simulation of Simplicity, without the checked API's
validation; its ``partition`` splits a conflict list by a plane prepared once.
It is a module of its own because it is the bulldozer's innermost loop: the
compiled twin (``make compiled``, docs/performance.md) compiles it with mypyc.
"""

from __future__ import annotations

import math
import types
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import NDArray

from persistri.impl.geometry.filter import (
    ERRBOUND_ORIENT3D,
    ERRBOUND_PLANE_SIDE,
    FLOPS_ORIENT3D,
    FLOPS_PLANE,
    FLOPS_PLANE_SIDE,
    orient3d_box_threshold,
    plane_side_box_threshold,
)
from persistri.impl.geometry.kernel_split import SiftFunction, composed_split, make_split
from persistri.impl.geometry.kernel_vector import MASK_BELOW, make_vectorised, negated_plane_side_dets

if TYPE_CHECKING:
    from persistri.impl.geometry.predicates import Predicates3

__all__ = [
    "Orient3dKernel", "Indices", "Plane", "PointArray", "KERNEL_BATCH", "COMPILED_BATCH", "SCALAR_BELOW", "MASK_BELOW", "COMPILED",
    "negated_plane_side_dets",
]

KERNEL_BATCH: Final[int] = 64
"""Below this many points the interpreted :attr:`Orient3dKernel.partition` loops over the points
instead of running vectorised (and the bulldozer keeps a conflict list this long or longer as an
int32 array).  Higher than the checked batches'
:data:`~persistri.impl.geometry.predicates.SMALL_BATCH` because the kernel's loop is cheaper than
the checked scalar test: with the semi-static threshold a point costs about 0.1 µs in it,
against the vectorised path's 5–6 µs for a call of up to a hundred points (measured on
2026-11-28 at 8 to 512 points of a 256K-point InBall set: the two meet near 60)."""

COMPILED_BATCH: Final[int] = 128
""":data:`KERNEL_BATCH` of the compiled twin (``tools/compiled_twin.py``): compiled, the loop costs
about 20 ns a point and 0.15 µs a call, the vectorised path 5.2 µs a call and 4.5 ns a point
(measured on 2026-11-28, 256K-point InBall set), so they meet near 320 points; the scalar loop's
lists then cost a conversion when they become stored conflict lists, hence a little lower."""


def _probe() -> None:
    """A function whose type tells whether this module runs compiled (mypyc makes it a built-in)."""


COMPILED: Final[bool] = not isinstance(_probe, types.FunctionType)
"""Whether this module is the compiled twin's extension (a mypyc function is not a Python function)."""

SCALAR_BELOW: Final[int] = COMPILED_BATCH if COMPILED else KERNEL_BATCH
"""Below this many points :attr:`Orient3dKernel.partition` loops over the points: :data:`KERNEL_BATCH`
interpreted, :data:`COMPILED_BATCH` compiled.  The signs are the same either way (exact); only the
type of the two lists returned (Python lists, or int arrays) follows this threshold."""

IntArray = NDArray[np.intp]
SignArray = NDArray[np.int8]

PointArray = NDArray[np.integer[Any]]
"""Point indices as an array of any integer type (the bulldozer keeps its long conflict lists in int32)."""

Indices = Sequence[int] | PointArray
"""Point indices as the kernel takes and returns them: a tuple or list of ints, or an integer array
(``partition`` returns arrays of the type it was given)."""

Plane = tuple[int, int, int]
"""A plane by three point indices ``(a, b, c)``: :attr:`Orient3dKernel.split`'s second-level planes."""


class Orient3dKernel:
    """``orient3d`` without validation, for algorithms that only ever pass valid, distinct indices.

    Made by :meth:`~persistri.impl.geometry.predicates.Predicates3.kernel`.  The signs are those of
    :meth:`~persistri.impl.geometry.predicates.Predicates3.orient3d` — the same proven filter
    (:func:`~persistri.impl.geometry.filter.orient3d_terms`), the same exact
    fallback and Simulation of Simplicity — and so is the counting
    (``plane_side_tests``, ``flops``, ``filter_failures`` of the predicates'
    ``stats``, read at every call).  What is left out is the work of the
    checked API on every call: index validation, per-call type tests,
    attribute lookups, and for batches ``np.asarray``/``min``/``max`` of the
    indices and broadcasting.  Indices out of range or repeated are the
    caller's error and are not diagnosed (a repeated index reaches SoS, which
    raises ``ValueError``).  The scalar paths also write the filter expressions
    out in place instead of calling :mod:`.filter` (a call per test costs about
    a sixth of the test); ``tests/test_predicates_kernel.py`` checks that they
    are the proved functions' statements, in order, so they round alike.

    **Semi-static stage.**  When nothing is counted (``stats`` is None) each
    determinant is first compared with one threshold for the whole point set,
    computed once from the bounding box of its points
    (:func:`~persistri.impl.geometry.filter.orient3d_box_threshold`,
    :func:`~persistri.impl.geometry.filter.plane_side_box_threshold`): it is at
    least every test's own threshold (rounding is monotone), so it decides
    only what the proved filter would decide.  A test's own permanent and
    threshold are computed only when it does not decide — almost never on
    real data, but always on exact zeros.  Counted runs skip the stage, so
    that every test costs the ``FLOPS_*`` that :class:`~persistri.impl.stats.Stats`
    adds.

    * :attr:`orient3d` ``(a, b, c, d) -> ±1`` — one test (about a microsecond);
    * :attr:`partition` ``(a, b, c, qs) -> (minus, plus)`` — the ``qs`` with
      ``orient3d(a, b, c, q) = -1`` (beyond the plane of the outward face
      ``(a, b, c)``: they see it) and those with ``+1``, each in the order of
      ``qs``.  The plane is prepared once
      (:func:`~persistri.impl.geometry.filter.plane_terms`: its normal and
      the normal's permanents), so each point costs the 17 flops of
      :func:`~persistri.impl.geometry.filter.plane_side_terms` instead of
      orient3d's 41, under a filter constant proved for that composition
      (``proofs/proof_predicates.py``) — 8 of them when the semi-static stage
      decides (the determinant, :func:`~persistri.impl.geometry.filter.plane_side_det`).
      Below :data:`SCALAR_BELOW` points it loops over the points and returns
      lists (an empty ``qs`` gives two empty tuples); from there on the same
      expression runs vectorised over numpy, negated
      (:mod:`.kernel_vector`, :func:`~persistri.impl.geometry.kernel_vector.negated_plane_side_dets`: the plane's terms written into one buffer
      that 0-d arrays view; about fifteen numpy calls whatever the length, each side
      gathered by its boolean mask below :data:`~persistri.impl.geometry.kernel_vector.MASK_BELOW` points, through an index
      list from there on) and it returns int arrays.  Entries the filter leaves
      undecided are settled one by one, exactly (then by SoS).  Counted as
      ``len(qs)`` plane-side tests and ``FLOPS_PLANE + len(qs) ·
      FLOPS_PLANE_SIDE`` flops.  O(len(qs)).
    * :attr:`split` ``(a, b, c, qs, lo, hi) -> (mm, mp, pm, pp)`` — a partition of ``qs`` by
      the plane ``(a, b, c)`` into ``minus`` and ``plus``, then of ``minus`` by the plane
      ``lo = (a', b', c')`` into ``mm`` and ``mp`` and of ``plus`` by ``hi`` into ``pm`` and
      ``pp`` (a side whose plane is None is returned whole, as ``mm`` or ``pm``, with an empty
      ``mp`` or ``pp``): the same tests, signs, lists and counts as those three
      :attr:`partition` calls, in one pass over a short ``qs`` (each point's row read once,
      one call instead of three: the bulldozer's routing of a face's points to its out-edges
      and their tents, paper Appendix A.1.2).  From :data:`SCALAR_BELOW` points on it is those
      three calls.  O(len(qs)).
    * :attr:`sift` ``(f, own, incoming, a, b, c, lo, hi) -> (gone, mm, mp, pm, pp)`` — the partition of the
      ``incoming`` lists by the plane ``f`` (``gone`` the points that do not see it), then :attr:`split` of ``own``
      and the points that see it, in one pass below :data:`SCALAR_BELOW` points in all, for uncounted runs only
      (:data:`~persistri.impl.geometry.kernel_split.SiftFunction`); None when the point set needs the checked
      methods.  O(len(own) + len(incoming)).
    * :attr:`signs` ``(a, b, c, qs) -> int8 array`` — ``orient3d(a, b, c, q)``
      for each ``q`` of an int array, vectorised through the prepared plane at
      any size (for whole point sets, e.g. the bulldozer's first cones), counted
      alike.  O(len(qs)).

    When the point set needs per-test grain checks (``filter_scale[1]`` is
    False: an extreme dynamic range) both fall back to the checked methods.
    """

    __slots__ = ("orient3d", "partition", "split", "sift", "signs")

    orient3d: Callable[[int, int, int, int], int]
    partition: Callable[[int, int, int, Indices], tuple[Indices, Indices]]
    split: Callable[[int, int, int, Indices, Plane | None, Plane | None], tuple[Indices, Indices, Indices, Indices]]
    sift: SiftFunction | None
    signs: Callable[[int, int, int, IntArray], SignArray]

    def __init__(self, pred: Predicates3) -> None:
        if not pred._uniform:
            self.orient3d = pred.orient3d
            self.partition = _checked_partition(pred)
            self.split = composed_split(self.partition)
            self.sift = None
            self.signs = pred.orient3d_batch
            return
        rows = pred._rows
        row = pred._row  # makes a lazy row: rows[i] unpacks to ValueError until then
        errbound = ERRBOUND_ORIENT3D
        flops = FLOPS_ORIENT3D
        exact = pred._orient3d_exact
        nan = math.nan
        # The semi-static stage: thresholds for the box of every point with a float copy (the exact
        # centroid's is NaN, and tests with it go on to exact arithmetic), each at least any test's own.
        (xlo, xhi), (ylo, yhi), (zlo, zhi) = (_finite_range(col) for col in pred._cols)
        o3_static = orient3d_box_threshold(xhi - xlo, yhi - ylo, zhi - zlo)
        side_static = plane_side_box_threshold(xhi - xlo, yhi - ylo, zhi - zlo)
        side_errbound = ERRBOUND_PLANE_SIDE
        plane_flops, side_flops = FLOPS_PLANE, FLOPS_PLANE_SIDE
        small = SCALAR_BELOW
        ndarray = np.ndarray
        # The scalar paths below run the filter expressions of :mod:`.filter` written out in place
        # (orient3d_terms; plane_terms, then plane_side_terms per point): a call per test costs as much
        # as a third of its arithmetic.  They are the same statements in the same order, so they round
        # exactly as the proved functions do; tests/test_predicates_kernel.py compares them, statement
        # by statement, with the functions' bodies.

        def orient3d(a: int, b: int, c: int, d: int) -> int:
            try:
                ax, ay, az = rows[a]
                bx, by, bz = rows[b]
                cx, cy, cz = rows[c]
                dx, dy, dz = rows[d]
            except ValueError:
                (ax, ay, az), (bx, by, bz), (cx, cy, cz), (dx, dy, dz) = row(a), row(b), row(c), row(d)
            # filter.orient3d_terms:
            adx = ax - dx
            bdx = bx - dx
            cdx = cx - dx
            ady = ay - dy
            bdy = by - dy
            cdy = cy - dy
            adz = az - dz
            bdz = bz - dz
            cdz = cz - dz
            bdxcdy = bdx * cdy
            cdxbdy = cdx * bdy
            cdxady = cdx * ady
            adxcdy = adx * cdy
            adxbdy = adx * bdy
            bdxady = bdx * ady
            det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady)
            st = pred.stats
            if st is None:
                # The semi-static stage (filter.orient3d_box_threshold): most tests stop here.
                if det > o3_static:
                    return 1
                if det < -o3_static:
                    return -1
            else:
                st.plane_side_tests += 1
                st.flops += flops
            # The test's own threshold:
            permanent = (
                (abs(bdxcdy) + abs(cdxbdy)) * abs(adz)
                + (abs(cdxady) + abs(adxcdy)) * abs(bdz)
                + (abs(adxbdy) + abs(bdxady)) * abs(cdz)
            )
            # end of filter.orient3d_terms
            thr = errbound * permanent
            if det > thr:
                return 1
            if det < -thr:
                return -1
            if st is not None:
                st.filter_failures += 1
            return exact(a, b, c, d, True)

        # The vectorised paths (kernel_vector), over the same columns and threshold:
        wide, signs = make_vectorised(pred, orient3d, exact, side_static)

        def partition(a: int, b: int, c: int, qs: Indices) -> tuple[Indices, Indices]:
            m = len(qs)
            if m == 0:
                return (), ()
            try:
                ax, ay, az = rows[a]
                bx, by, bz = rows[b]
                cx, cy, cz = rows[c]
            except ValueError:
                (ax, ay, az), (bx, by, bz), (cx, cy, cz) = row(a), row(b), row(c)
            # filter.plane_terms:
            bax = bx - ax
            bay = by - ay
            baz = bz - az
            cax = cx - ax
            cay = cy - ay
            caz = cz - az
            yz = bay * caz
            zy = baz * cay
            zx = baz * cax
            xz = bax * caz
            xy = bax * cay
            yx = bay * cax
            nx = yz - zy
            ny = zx - xz
            nz = xy - yx
            st = pred.stats
            # The semi-static stage first (one threshold for the whole point set), so most points need no
            # permanent of their own.  Counted runs skip it (NaN decides nothing): each point is then
            # tested against its own threshold, the FLOPS_PLANE_SIDE that Stats counts.
            static = side_static if st is None else nan
            if m >= small:
                return wide(a, b, c, ax, ay, az, nx, ny, nz, static, qs, m)
            minus: list[Any] = []
            plus: list[Any] = []
            failures = 0
            below = -static
            px = py = pz = nan  # the plane's permanents: made for the first point the static stage leaves undecided
            for q in qs.tolist() if type(qs) is ndarray else qs:
                # q is appended as it is (never re-made) and read as an int index: compiled, rows[i] is then a
                # direct list access, where q (an object: an int or numpy's Any) would cost a generic lookup.
                i: int = q
                try:
                    qx, qy, qz = rows[i]
                except ValueError:
                    qx, qy, qz = row(i)
                # filter.plane_side_det:
                det = (ax - qx) * nx + (ay - qy) * ny + (az - qz) * nz
                # end of filter.plane_side_det
                if det < below:
                    minus.append(q)
                elif det > static:
                    plus.append(q)
                else:
                    if px != px:
                        px = abs(yz) + abs(zy)
                        py = abs(zx) + abs(xz)
                        pz = abs(xy) + abs(yx)
                        # end of filter.plane_terms
                    # The point's own threshold: filter.plane_side_terms' permanent.
                    aqx = ax - qx
                    aqy = ay - qy
                    aqz = az - qz
                    permanent = abs(aqx) * px + abs(aqy) * py + abs(aqz) * pz
                    thr = side_errbound * permanent
                    if det < -thr:
                        minus.append(q)
                    elif det > thr:
                        plus.append(q)
                    else:
                        failures += 1
                        (minus if exact(a, b, c, i, True) < 0 else plus).append(q)
            if st is not None:
                st.plane_side_tests += m
                st.flops += plane_flops + side_flops * m
                st.filter_failures += failures
            return minus, plus

        self.orient3d = orient3d
        self.partition = partition
        self.split, self.sift = make_split(pred, partition, exact, side_static, small)
        self.signs = signs


def _finite_range(col: NDArray[np.float64]) -> tuple[float, float]:
    """The least and greatest non-NaN entries of ``col``, or NaN twice when there are none. O(len(col))."""
    if col.size == 0:
        return math.nan, math.nan
    lo, hi = float(col.min()), float(col.max())
    if lo == lo and hi == hi:
        return lo, hi  # no NaN: numpy's min and max return NaN when there is one
    missing = np.isnan(col)
    finite = col[~missing] if missing.any() else col
    if finite.size == 0:
        return math.nan, math.nan
    return float(finite.min()), float(finite.max())


def _checked_partition(pred: Predicates3) -> Callable[[int, int, int, Indices], tuple[Indices, Indices]]:
    """:attr:`Orient3dKernel.partition` through the checked batch (per-test grain checks)."""

    def partition(a: int, b: int, c: int, qs: Indices) -> tuple[Indices, Indices]:
        q_arr = np.asarray(qs, dtype=np.intp)
        if q_arr.size == 0:
            return [], []
        signs = pred.orient3d_batch(a, b, c, q_arr)
        return q_arr[signs < 0], q_arr[signs > 0]

    return partition
