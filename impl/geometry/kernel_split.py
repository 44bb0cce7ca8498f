"""The kernel's two-plane routing: :attr:`~persistri.impl.geometry.kernel.Orient3dKernel.split` (paper Appendix A.1.2).

The bulldozer routes the points of a face with two out-edges to those
edges' tents: a partition of the points by the face's plane, then of each
side by the plane of its own tent.  :func:`make_split` makes the function
that does it in one pass over a short list — each point's row read once, one
call instead of three — with the same tests, signs, lists and counts as the
three :attr:`~persistri.impl.geometry.kernel.Orient3dKernel.partition` calls
it stands for (:func:`composed_split`, used from
:data:`~persistri.impl.geometry.kernel.SCALAR_BELOW` points on and on the
checked path).  The filter expressions are written out in place, as in the
kernel's other scalar paths; ``tests/test_predicates_kernel.py`` checks that
they are the proved functions' statements, in order, so they round alike.

A module of its own only for size: it is the kernel's (made by
:class:`~persistri.impl.geometry.kernel.Orient3dKernel` from the same
prepared rows and thresholds, and compiled with it in the twin).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from persistri.impl.geometry.filter import ERRBOUND_PLANE_SIDE, FLOPS_PLANE, FLOPS_PLANE_SIDE

if TYPE_CHECKING:
    from persistri.impl.geometry.predicates import Predicates3

__all__ = ["SiftFunction", "SplitFunction", "composed_split", "make_split"]

_Indices = Sequence[int] | np.ndarray[Any, np.dtype[np.integer[Any]]]
_Plane = tuple[int, int, int]
_Partition = Callable[[int, int, int, _Indices], tuple[_Indices, _Indices]]

SplitFunction = Callable[[int, int, int, _Indices, "_Plane | None", "_Plane | None"], tuple[_Indices, _Indices, _Indices, _Indices]]
"""``split(a, b, c, qs, lo, hi) -> (mm, mp, pm, pp)``: :attr:`~persistri.impl.geometry.kernel.Orient3dKernel.split`."""

SiftFunction = Callable[
    [_Plane, _Indices, list[_Indices], int, int, int, "_Plane | None", "_Plane | None"],
    tuple[list[Any], list[Any], list[Any], list[Any], list[Any]],
]
"""``sift(f, own, incoming, a, b, c, lo, hi) -> (gone, mm, mp, pm, pp)``: the partition of the concatenated
``incoming`` lists by the plane ``f`` (``gone``: the points with ``orient3d(f, q) = +1``), then ``split(a, b, c,
own + the others, lo, hi)`` — the same tests, signs and lists (Python lists, in the same order) as those two
calls, in one pass, each point's row read once (the bulldozer's points bulldozed into a face: Appendix A.1.2).
Only for an uncounted run (``pred.stats`` None) and fewer than ``small`` points in all, where both calls
loop over the points.  O(len(own) + len(incoming))."""


def make_split(
    pred: Predicates3,
    partition: _Partition,
    exact: Callable[[int, int, int, int, bool], int],
    side_static: float,
    small: int,
) -> tuple[SplitFunction, SiftFunction]:
    """The scalar ``split`` over ``pred``'s rows (uniform point sets), ``partition``'s three calls from ``small``
    points on, and ``sift`` (:data:`SiftFunction`); ``exact`` is the exact orient3d (then SoS), ``side_static``
    the semi-static threshold of the point set's box.  O(1) to make; a call O(len(qs))."""
    rows = pred._rows
    row = pred._row  # makes a lazy row: rows[i] unpacks to ValueError until then
    side_errbound = ERRBOUND_PLANE_SIDE
    plane_flops, side_flops = FLOPS_PLANE, FLOPS_PLANE_SIDE
    nan = math.nan
    ndarray = np.ndarray
    composed = composed_split(partition)

    def settle(
        a: int, b: int, c: int, i: int, ax: float, ay: float, az: float, qx: float, qy: float, qz: float,
        det: float, yz: float, zy: float, zx: float, xz: float, xy: float, yx: float,
    ) -> int:
        """The sign of ``orient3d(a, b, c, i)`` for a point the semi-static stage left undecided (or any
        point of a counted run), from the plane's determinant ``det`` and products: ±1 when the point's
        own threshold decides it, ±2 when exact arithmetic (then SoS) does (a filter failure)."""
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
            return -1
        if det > thr:
            return 1
        return 2 * exact(a, b, c, i, True)


    def split(
        a: int, b: int, c: int, qs: _Indices, lo: _Plane | None, hi: _Plane | None
    ) -> tuple[_Indices, _Indices, _Indices, _Indices]:
        m = len(qs)
        if m == 0:
            return (), (), (), ()
        if m >= small:
            return composed(a, b, c, qs, lo, hi)
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
        # (its permanents: settle)
        # The planes lo and hi (the same statements, names suffixed _lo and _hi) are made for the first point
        # that reaches them (lo_made, hi_made): a side with no point needs none (a fifth of the short calls
        # have one), and their names are bound only then (no default values to store at every call).
        lo_made = hi_made = False
        lo_on = lo is not None
        hi_on = hi is not None
        st = pred.stats
        static = side_static if st is None else nan  # counted runs: every point against its own threshold
        below = -static
        mm: list[Any] = []
        mp: list[Any] = []
        pm: list[Any] = []
        pp: list[Any] = []
        failures = 0
        for q in qs.tolist() if type(qs) is ndarray else qs:
            i: int = q  # as in partition: appended as it is, read as an int index
            try:
                qx, qy, qz = rows[i]
            except ValueError:
                qx, qy, qz = row(i)
            # filter.plane_side_det:
            det = (ax - qx) * nx + (ay - qy) * ny + (az - qz) * nz
            # end of filter.plane_side_det
            if det < below:
                s = -1
            elif det > static:
                s = 1
            else:
                s = settle(a, b, c, i, ax, ay, az, qx, qy, qz, det, yz, zy, zx, xz, xy, yx)
                if s > 1 or s < -1:
                    failures += 1
            if s < 0:
                if lo is None:
                    mm.append(q)
                    continue
                if not lo_made:
                    lo_made = True
                    a_lo, b_lo, c_lo = lo
                    try:
                        ax_lo, ay_lo, az_lo = rows[a_lo]
                        bx_lo, by_lo, bz_lo = rows[b_lo]
                        cx_lo, cy_lo, cz_lo = rows[c_lo]
                    except ValueError:
                        (ax_lo, ay_lo, az_lo), (bx_lo, by_lo, bz_lo), (cx_lo, cy_lo, cz_lo) = row(a_lo), row(b_lo), row(c_lo)
                    # filter.plane_terms (lo):
                    bax_lo = bx_lo - ax_lo
                    bay_lo = by_lo - ay_lo
                    baz_lo = bz_lo - az_lo
                    cax_lo = cx_lo - ax_lo
                    cay_lo = cy_lo - ay_lo
                    caz_lo = cz_lo - az_lo
                    yz_lo = bay_lo * caz_lo
                    zy_lo = baz_lo * cay_lo
                    zx_lo = baz_lo * cax_lo
                    xz_lo = bax_lo * caz_lo
                    xy_lo = bax_lo * cay_lo
                    yx_lo = bay_lo * cax_lo
                    nx_lo = yz_lo - zy_lo
                    ny_lo = zx_lo - xz_lo
                    nz_lo = xy_lo - yx_lo
                # filter.plane_side_det (lo):
                det = (ax_lo - qx) * nx_lo + (ay_lo - qy) * ny_lo + (az_lo - qz) * nz_lo
                if det < below:
                    mm.append(q)
                elif det > static:
                    mp.append(q)
                else:
                    s = settle(a_lo, b_lo, c_lo, i, ax_lo, ay_lo, az_lo, qx, qy, qz, det, yz_lo, zy_lo, zx_lo, xz_lo, xy_lo, yx_lo)
                    if s > 1 or s < -1:
                        failures += 1
                    (mm if s < 0 else mp).append(q)
            else:
                if hi is None:
                    pm.append(q)
                    continue
                if not hi_made:
                    hi_made = True
                    a_hi, b_hi, c_hi = hi
                    try:
                        ax_hi, ay_hi, az_hi = rows[a_hi]
                        bx_hi, by_hi, bz_hi = rows[b_hi]
                        cx_hi, cy_hi, cz_hi = rows[c_hi]
                    except ValueError:
                        (ax_hi, ay_hi, az_hi), (bx_hi, by_hi, bz_hi), (cx_hi, cy_hi, cz_hi) = row(a_hi), row(b_hi), row(c_hi)
                    # filter.plane_terms (hi):
                    bax_hi = bx_hi - ax_hi
                    bay_hi = by_hi - ay_hi
                    baz_hi = bz_hi - az_hi
                    cax_hi = cx_hi - ax_hi
                    cay_hi = cy_hi - ay_hi
                    caz_hi = cz_hi - az_hi
                    yz_hi = bay_hi * caz_hi
                    zy_hi = baz_hi * cay_hi
                    zx_hi = baz_hi * cax_hi
                    xz_hi = bax_hi * caz_hi
                    xy_hi = bax_hi * cay_hi
                    yx_hi = bay_hi * cax_hi
                    nx_hi = yz_hi - zy_hi
                    ny_hi = zx_hi - xz_hi
                    nz_hi = xy_hi - yx_hi
                # filter.plane_side_det (hi):
                det = (ax_hi - qx) * nx_hi + (ay_hi - qy) * ny_hi + (az_hi - qz) * nz_hi
                if det < below:
                    pm.append(q)
                elif det > static:
                    pp.append(q)
                else:
                    s = settle(a_hi, b_hi, c_hi, i, ax_hi, ay_hi, az_hi, qx, qy, qz, det, yz_hi, zy_hi, zx_hi, xz_hi, xy_hi, yx_hi)
                    if s > 1 or s < -1:
                        failures += 1
                    (pm if s < 0 else pp).append(q)
        if st is not None:
            # What the three partitions count: a plane and its tests for each that got a point.
            tested = m
            planes = 1
            if lo_on and (mm or mp):
                tested += len(mm) + len(mp)
                planes += 1
            if hi_on and (pm or pp):
                tested += len(pm) + len(pp)
                planes += 1
            st.plane_side_tests += tested
            st.flops += plane_flops * planes + side_flops * tested
            st.filter_failures += failures
        return mm, mp, pm, pp

    def sift(
        f: _Plane, own: _Indices, incoming: list[_Indices], a: int, b: int, c: int, lo: _Plane | None, hi: _Plane | None
    ) -> tuple[list[Any], list[Any], list[Any], list[Any], list[Any]]:
        # The face's test of the bulldozed points first (those that do not see it go to gone), then split's routing
        # of own and the points that stay, in one pass: split's loop with a face test for the incoming points.
        fa, fb, fc = f
        try:
            ax_f, ay_f, az_f = rows[fa]
            bx_f, by_f, bz_f = rows[fb]
            cx_f, cy_f, cz_f = rows[fc]
            ax, ay, az = rows[a]
            bx, by, bz = rows[b]
            cx, cy, cz = rows[c]
        except ValueError:
            (ax_f, ay_f, az_f), (bx_f, by_f, bz_f), (cx_f, cy_f, cz_f) = row(fa), row(fb), row(fc)
            (ax, ay, az), (bx, by, bz), (cx, cy, cz) = row(a), row(b), row(c)
        # filter.plane_terms (f):
        bax_f = bx_f - ax_f
        bay_f = by_f - ay_f
        baz_f = bz_f - az_f
        cax_f = cx_f - ax_f
        cay_f = cy_f - ay_f
        caz_f = cz_f - az_f
        yz_f = bay_f * caz_f
        zy_f = baz_f * cay_f
        zx_f = baz_f * cax_f
        xz_f = bax_f * caz_f
        xy_f = bax_f * cay_f
        yx_f = bay_f * cax_f
        nx_f = yz_f - zy_f
        ny_f = zx_f - xz_f
        nz_f = xy_f - yx_f
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
        lo_made = hi_made = False
        static = side_static  # uncounted only
        below = -static
        gone: list[Any] = []
        mm: list[Any] = []
        mp: list[Any] = []
        pm: list[Any] = []
        pp: list[Any] = []
        parts: list[_Indices] = [own]
        parts.extend(incoming)
        tested = False  # whether the points of this part are tested against the face first (every part but own)
        for part in parts:
            for q in part.tolist() if type(part) is ndarray else part:
                i: int = q
                try:
                    qx, qy, qz = rows[i]
                except ValueError:
                    qx, qy, qz = row(i)
                if tested:
                    # filter.plane_side_det (f): the point stays if it sees the face (-1), as partition decides it.
                    det = (ax_f - qx) * nx_f + (ay_f - qy) * ny_f + (az_f - qz) * nz_f
                    if not det < below:
                        if det > static or settle(fa, fb, fc, i, ax_f, ay_f, az_f, qx, qy, qz, det, yz_f, zy_f, zx_f, xz_f, xy_f, yx_f) > 0:
                            gone.append(q)
                            continue
                # filter.plane_side_det:
                det = (ax - qx) * nx + (ay - qy) * ny + (az - qz) * nz
                if det < below:
                    s = -1
                elif det > static:
                    s = 1
                else:
                    s = settle(a, b, c, i, ax, ay, az, qx, qy, qz, det, yz, zy, zx, xz, xy, yx)
                if s < 0:
                    if lo is None:
                        mm.append(q)
                        continue
                    if not lo_made:
                        lo_made = True
                        a_lo, b_lo, c_lo = lo
                        try:
                            ax_lo, ay_lo, az_lo = rows[a_lo]
                            bx_lo, by_lo, bz_lo = rows[b_lo]
                            cx_lo, cy_lo, cz_lo = rows[c_lo]
                        except ValueError:
                            (ax_lo, ay_lo, az_lo), (bx_lo, by_lo, bz_lo), (cx_lo, cy_lo, cz_lo) = row(a_lo), row(b_lo), row(c_lo)
                        # filter.plane_terms (lo):
                        bax_lo = bx_lo - ax_lo
                        bay_lo = by_lo - ay_lo
                        baz_lo = bz_lo - az_lo
                        cax_lo = cx_lo - ax_lo
                        cay_lo = cy_lo - ay_lo
                        caz_lo = cz_lo - az_lo
                        yz_lo = bay_lo * caz_lo
                        zy_lo = baz_lo * cay_lo
                        zx_lo = baz_lo * cax_lo
                        xz_lo = bax_lo * caz_lo
                        xy_lo = bax_lo * cay_lo
                        yx_lo = bay_lo * cax_lo
                        nx_lo = yz_lo - zy_lo
                        ny_lo = zx_lo - xz_lo
                        nz_lo = xy_lo - yx_lo
                    # filter.plane_side_det (lo):
                    det = (ax_lo - qx) * nx_lo + (ay_lo - qy) * ny_lo + (az_lo - qz) * nz_lo
                    if det < below:
                        mm.append(q)
                    elif det > static:
                        mp.append(q)
                    else:
                        s = settle(a_lo, b_lo, c_lo, i, ax_lo, ay_lo, az_lo, qx, qy, qz, det, yz_lo, zy_lo, zx_lo, xz_lo, xy_lo, yx_lo)
                        (mm if s < 0 else mp).append(q)
                else:
                    if hi is None:
                        pm.append(q)
                        continue
                    if not hi_made:
                        hi_made = True
                        a_hi, b_hi, c_hi = hi
                        try:
                            ax_hi, ay_hi, az_hi = rows[a_hi]
                            bx_hi, by_hi, bz_hi = rows[b_hi]
                            cx_hi, cy_hi, cz_hi = rows[c_hi]
                        except ValueError:
                            (ax_hi, ay_hi, az_hi), (bx_hi, by_hi, bz_hi), (cx_hi, cy_hi, cz_hi) = row(a_hi), row(b_hi), row(c_hi)
                        # filter.plane_terms (hi):
                        bax_hi = bx_hi - ax_hi
                        bay_hi = by_hi - ay_hi
                        baz_hi = bz_hi - az_hi
                        cax_hi = cx_hi - ax_hi
                        cay_hi = cy_hi - ay_hi
                        caz_hi = cz_hi - az_hi
                        yz_hi = bay_hi * caz_hi
                        zy_hi = baz_hi * cay_hi
                        zx_hi = baz_hi * cax_hi
                        xz_hi = bax_hi * caz_hi
                        xy_hi = bax_hi * cay_hi
                        yx_hi = bay_hi * cax_hi
                        nx_hi = yz_hi - zy_hi
                        ny_hi = zx_hi - xz_hi
                        nz_hi = xy_hi - yx_hi
                    # filter.plane_side_det (hi):
                    det = (ax_hi - qx) * nx_hi + (ay_hi - qy) * ny_hi + (az_hi - qz) * nz_hi
                    if det < below:
                        pm.append(q)
                    elif det > static:
                        pp.append(q)
                    else:
                        s = settle(a_hi, b_hi, c_hi, i, ax_hi, ay_hi, az_hi, qx, qy, qz, det, yz_hi, zy_hi, zx_hi, xz_hi, xy_hi, yx_hi)
                        (pm if s < 0 else pp).append(q)
            tested = True
        return gone, mm, mp, pm, pp

    return split, sift


def composed_split(partition: _Partition) -> SplitFunction:
    """:attr:`~persistri.impl.geometry.kernel.Orient3dKernel.split` as the three ``partition`` calls it stands
    for (long lists; the checked path)."""

    def split(
        a: int, b: int, c: int, qs: _Indices, lo: _Plane | None, hi: _Plane | None
    ) -> tuple[_Indices, _Indices, _Indices, _Indices]:
        minus, plus = partition(a, b, c, qs)
        mm, mp = partition(lo[0], lo[1], lo[2], minus) if lo is not None else (minus, ())
        pm, pp = partition(hi[0], hi[1], hi[2], plus) if hi is not None else (plus, ())
        return mm, mp, pm, pp

    return split
