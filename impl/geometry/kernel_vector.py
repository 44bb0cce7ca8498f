"""The kernel's vectorised paths: :attr:`~persistri.impl.geometry.kernel.Orient3dKernel.partition` of long lists, and ``signs`` (paper §3, Appendix A).

From :data:`~persistri.impl.geometry.kernel.SCALAR_BELOW` points on, the
kernel tests a list of points against a prepared plane over numpy instead of
point by point: the semi-static stage as :func:`negated_plane_side_dets` over
the gathered columns (about fifteen numpy calls whatever the length), each side
gathered by its boolean mask below :data:`MASK_BELOW` points and through index
lists from there on, the few entries the filter leaves undecided settled one by
one, exactly (then by Simulation of Simplicity); counted runs test each entry
against its own threshold (:func:`~persistri.impl.geometry.filter.plane_side_terms_into`).
:func:`make_vectorised` makes these functions over a uniform point set's
columns.  The signs are those of the scalar path; only the type of the lists
returned differs (int arrays).

A module of its own for size: it is the kernel's (made by
:class:`~persistri.impl.geometry.kernel.Orient3dKernel` from the same
prepared columns and thresholds, and compiled with it in the twin).
"""

from __future__ import annotations

import struct
from array import array
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import NDArray

from persistri.impl.geometry.filter import ERRBOUND_PLANE_SIDE, FLOPS_PLANE, FLOPS_PLANE_SIDE, plane_side_terms_into, plane_terms
from persistri.impl.stats import Stats

if TYPE_CHECKING:
    from persistri.impl.geometry.predicates import Predicates3

__all__ = ["MASK_BELOW", "WidePartition", "SignsFunction", "make_vectorised", "negated_plane_side_dets"]

MASK_BELOW: Final[int] = 512
"""Below this many points (and from :data:`SCALAR_BELOW` on) the vectorised :attr:`Orient3dKernel.partition` gathers
each side by its boolean mask (one numpy call a side) instead of through index lists (``nonzero``, then
``take``: two): about 6,400 instructions fewer a call (interpreted, 64 points).  A mask of mixed signs costs a
mispredicted branch an entry, so from here on the index lists are faster (measured on 2026-11-28, 256K-point
InBall set, a fifth of the points on one side: masks 0.92× the time at 64 points, 1.0× at 512–1,024, 1.36×
at 2,048).  The same lists in the same order and type either way."""

_IntArray = NDArray[np.intp]
_SignArray = NDArray[np.int8]
_PointArray = NDArray[np.integer[Any]]
_Indices = Sequence[int] | _PointArray

WidePartition = Callable[[int, int, int, float, float, float, float, float, float, float, _Indices, int], tuple[_Indices, _Indices]]
"""``wide(a, b, c, ax, ay, az, nx, ny, nz, static, qs, m) -> (minus, plus)``: :attr:`~persistri.impl.geometry.kernel.Orient3dKernel.partition`
of the ``m = len(qs)`` points ``qs`` (from :data:`~persistri.impl.geometry.kernel.SCALAR_BELOW` on) by the plane
through ``a = (ax, ay, az)`` with normal ``(nx, ny, nz)`` (:func:`~persistri.impl.geometry.filter.plane_terms`'
of ``a, b, c``), as int arrays; ``static`` is the semi-static threshold, NaN in a counted run.  Not counted here
but for the entries :func:`make_vectorised`'s ``where`` settles in a counted run.  O(len(qs))."""

SignsFunction = Callable[[int, int, int, _IntArray], _SignArray]
"""``signs(a, b, c, qs) -> int8 array``: :attr:`~persistri.impl.geometry.kernel.Orient3dKernel.signs`."""


def make_vectorised(
    pred: Predicates3,
    orient3d: Callable[[int, int, int, int], int],
    exact: Callable[[int, int, int, int, bool], int],
    side_static: float,
) -> tuple[WidePartition, SignsFunction]:
    """The vectorised ``partition`` (:data:`WidePartition`) and ``signs`` over ``pred``'s columns (uniform point
    sets); ``orient3d`` is the kernel's scalar test, ``exact`` the exact orient3d (then SoS), ``side_static`` the
    semi-static threshold of the point set's box.  O(1) to make; a call O(len(qs))."""
    row = pred._row
    xs, ys, zs = pred._cols
    side = plane_side_terms_into
    nan = float("nan")
    side_errbound = ERRBOUND_PLANE_SIDE
    plane_flops, side_flops = FLOPS_PLANE, FLOPS_PLANE_SIDE
    mask_below = MASK_BELOW
    ndarray = np.ndarray
    intp = np.dtype(np.intp)
    asarray = np.asarray
    # The semi-static threshold and its negative as 0-d float64 arrays, made once (numpy converts a
    # Python float operand anew at each call; the vectorised stage compares with these).
    side_static_arr = asarray(side_static)
    side_static_neg = asarray(-side_static)
    # The plane of a vectorised call, (ax, ay, az, nx, ny, nz), written into one buffer (one call, against six
    # asarray) that six fixed 0-d float64 views read: the same values as operands.  Scratch of one call at a time
    # (a call writes it and reads it back before it returns; no kernel call runs in between).
    plane_buf = array("d", bytes(48))
    put_plane = struct.Struct("6d").pack_into
    ax_0d, ay_0d, az_0d, nx_0d, ny_0d, nz_0d = (np.frombuffer(plane_buf)[k, ...] for k in range(6))

    def wide(
        a: int, b: int, c: int, ax: float, ay: float, az: float, nx: float, ny: float, nz: float,
        static: float, qs: _Indices, m: int,
    ) -> tuple[_Indices, _Indices]:
        q_arr: _PointArray = qs if isinstance(qs, ndarray) else np.array(qs, dtype=np.intp)
        if m < mask_below and pred.stats is None:
            # The semi-static stage on the gathered columns, each side gathered by its boolean mask:
            # two numpy calls fewer than nonzero and take (where) make.
            q_idx = q_arr if q_arr.dtype == intp else q_arr.astype(intp)
            put_plane(plane_buf, 0, ax, ay, az, nx, ny, nz)
            gx = xs.take(q_idx)
            gy = ys.take(q_idx)
            gz = zs.take(q_idx)
            # negated_plane_side_dets (minus filter.plane_side_det_into's determinants, bitwise):
            gx -= ax_0d
            gx *= nx_0d
            gy -= ay_0d
            gy *= ny_0d
            gx += gy
            gz -= az_0d
            gz *= nz_0d
            gx += gz
            # end of negated_plane_side_dets
            minus_arr = q_arr[gx > side_static_arr]
            plus_arr = q_arr[gx < side_static_neg]
            if minus_arr.size + plus_arr.size == m:
                return minus_arr, plus_arr
            # Some point undecided (rare: near the plane): where settles it, exactly.
        neg, pos = where(a, b, c, (ax, ay, az), (nx, ny, nz), static, q_arr)
        # Gathering through index lists: a boolean mask of mixed signs costs a mispredicted branch per entry
        # (and take costs a fifth less than indexing with the same list).
        return q_arr.take(neg), q_arr.take(pos)

    def where(
        a: int,
        b: int,
        c: int,
        at: tuple[float, float, float],
        normal: tuple[float, float, float],
        static: float,
        q_arr: _PointArray,
    ) -> tuple[_IntArray, _IntArray]:
        """The positions in ``q_arr`` where orient3d(a, b, c, q) = -1 and where it is +1, increasing.

        Vectorised through the prepared plane.  With a ``static`` threshold (not NaN):
        :func:`negated_plane_side_dets` on the gathered columns and
        one comparison per side (a dozen numpy calls whatever the length), the few undecided
        entries then by the scalar kernel (their own filter, then exact).  Without (counted
        runs): :func:`~persistri.impl.geometry.filter.plane_side_terms_into`, each entry
        against its own threshold, the undecided ones exactly.
        """
        nx, ny, nz = normal
        ax, ay, az = at
        if q_arr.dtype != intp:
            # numpy gathers through intp indices only: converted once here, not once per column.
            q_arr = q_arr.astype(intp)
        # Gathered copies (the filter functions compute in them); take costs a fifth less than indexing.
        qy = ys.take(q_arr)
        counted = static != static
        if counted:
            # The plane's permanents (a counted run: each point against its own threshold), by the proved
            # function from the same corners, so bitwise the scalar path's.
            ra, rb, rc = row(a), row(b), row(c)
            px, py, pz = plane_terms(*ra, *rb, *rc)[3:]
            det, thr = side(nx, ny, nz, px, py, pz, ax, ay, az, xs.take(q_arr), qy, zs.take(q_arr))
            thr *= side_errbound  # the threshold side_errbound * permanent, in place
            neg_mask = det < np.negative(thr, out=qy)  # qy is free again
            pos_mask = det > thr
        else:
            # The plane's numbers enter as 0-d float64 arrays, the same values: numpy converts a Python
            # float operand anew at each call, a 0-d array not (measured on 2026-11-28: a call of 64 to 256
            # points 6.3-7.6 -> 5.6-6.8 µs); they view one buffer, written by one call.
            put_plane(plane_buf, 0, ax, ay, az, nx, ny, nz)
            neg_det = negated_plane_side_dets(xs.take(q_arr), qy, zs.take(q_arr), ax_0d, ay_0d, az_0d, nx_0d, ny_0d, nz_0d)
            neg_mask = neg_det > side_static_arr  # static is side_static here (uncounted)
            pos_mask = neg_det < side_static_neg
        neg: _IntArray = neg_mask.nonzero()[0]
        pos: _IntArray = pos_mask.nonzero()[0]
        m = q_arr.size
        undecided = m - neg.size - pos.size
        if undecided:
            for i in (~(neg_mask | pos_mask)).nonzero()[0].tolist():
                q = int(q_arr[i])
                if (exact(a, b, c, q, True) if counted else orient3d(a, b, c, q)) < 0:
                    neg_mask[i] = True
                else:
                    pos_mask[i] = True
            neg, pos = neg_mask.nonzero()[0], pos_mask.nonzero()[0]
        if counted:
            _count(pred.stats, m, undecided)
        return neg, pos

    def signs(a: int, b: int, c: int, qs: _IntArray) -> _SignArray:
        if qs.size == 0:
            return np.zeros(0, dtype=np.int8)
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = row(a), row(b), row(c)  # once per call: no fast path
        nx, ny, nz, _, _, _ = plane_terms(ax, ay, az, bx, by, bz, cx, cy, cz)
        static = side_static if pred.stats is None else nan
        neg, pos = where(a, b, c, (ax, ay, az), (nx, ny, nz), static, qs)
        out: _SignArray = np.zeros(qs.size, dtype=np.int8)
        out[neg] = -1
        out[pos] = 1
        return out

    def _count(st: Stats | None, m: int, failures: int) -> None:
        if st is not None:
            st.plane_side_tests += m
            st.flops += plane_flops + side_flops * m
            st.filter_failures += failures

    return wide, signs


def negated_plane_side_dets(
    qx: NDArray[np.float64], qy: NDArray[np.float64], qz: NDArray[np.float64],
    ax: float | NDArray[np.float64], ay: float | NDArray[np.float64], az: float | NDArray[np.float64],
    nx: float | NDArray[np.float64], ny: float | NDArray[np.float64], nz: float | NDArray[np.float64],
) -> NDArray[np.float64]:
    """Minus :func:`~persistri.impl.geometry.filter.plane_side_det_into`'s determinants, computed in ``qx``, ``qy``,
    ``qz`` (overwritten; ``qx`` returned) by numpy's in-place operators (its ``np.subtract(ax, qx, out=qx)``
    takes a keyword: about a tenth more a call).

    Bitwise the negated determinant, up to the sign of a zero: round-to-nearest is symmetric, so
    ``fl(q - a) = -fl(a - q)``, ``fl(-u · n) = -fl(u · n)`` and ``fl(-s + -t) = -fl(s + t)``, each step
    the proved one's negation (``tests/test_hull_kernel_dets.py`` compares them); a comparison with a
    threshold ``t >= 0`` reads either zero alike, so ``-det > t`` is ``det < -t``.  The vectorised
    :attr:`Orient3dKernel.partition` runs these statements in place.  O(len(qx)).
    """
    qx -= ax
    qx *= nx
    qy -= ay
    qy *= ny
    qx += qy
    qz -= az
    qz *= nz
    qx += qz
    return qx
