"""Exact 2D predicates over indexed points: :class:`Predicates2` (``orient2d`` and ``incircle``, paper §5).

The tests of the Delaunay triangulation and of the terrain; the three stages
of every test (filter, exact integers, Simulation of Simplicity), the sign
conventions and the counting are described in
:mod:`persistri.impl.geometry.predicates`, which exports this class.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.geometry.exact import incircle_det, orient2d_det
from persistri.impl.geometry.filter import (
    ERRBOUND_INCIRCLE,
    ERRBOUND_ORIENT2D,
    FLOPS_INCIRCLE,
    FLOPS_ORIENT2D,
    incircle_terms,
    orient2d_terms,
)
from persistri.impl.geometry.indexed_points import IndexedPoints, IntArray, SignArray, sign_of
from persistri.impl.geometry.kernel2d import Delaunay2Kernel
from persistri.impl.geometry.points import as_points
from persistri.impl.geometry.sos import sort_by_rank_with_parity, sort_with_parity, sos_orient2d, sos_orient3d
from persistri.impl.stats import Stats

__all__ = ["Predicates2"]


class Predicates2(IndexedPoints):
    """Exact 2D predicates over the rows of an ``(n, 2)`` array, by point index.

    ``orient2d`` and ``incircle`` with their batch and true-sign variants, for
    the Delaunay terrain (paper §5).  Validation and errors as
    :class:`~persistri.impl.geometry.predicates3.Predicates3`.  Simulation of
    Simplicity perturbs the points in index order, or, given ``sos_rank`` (``n``
    distinct integers), in the order of their ranks: the indices are then free to
    follow another order (the scattered Delaunay numbers its points along a
    Hilbert curve and ranks them by input row).
    """

    __slots__ = ("_sos_rank",)

    _sos_rank: list[int] | None

    def __init__(self, points: ArrayLike, *, stats: Stats | None = None, sos_rank: ArrayLike | None = None) -> None:
        pts = as_points(points, 2)
        # Lazy rows: a height grid has millions of points and only its vertices are ever tested one by one.
        self._setup(pts, exact_rows=pts.shape[0], extra=0, stats=stats, lazy_rows=True)
        self._sos_rank = None
        if sos_rank is not None:
            rank = np.asarray(sos_rank)
            if rank.shape != (pts.shape[0],) or rank.dtype.kind not in "iu" or np.unique(rank).size != rank.size:
                raise ValueError(f"sos_rank must be {pts.shape[0]} distinct integers, one per point")
            self._sos_rank = rank.tolist()

    def __repr__(self) -> str:
        return f"Predicates2(n={self._n})"

    def coordinates(self, q: IntArray) -> tuple[NDArray[Any], NDArray[Any]]:
        """The input coordinates ``(x, y)`` of points ``q`` (an index array), as two arrays of real numbers
        (float64 here; a grid's are small integers). O(len(q))."""
        pts = self._points[q]
        return pts[:, 0], pts[:, 1]

    def coordinate_columns(self) -> tuple[NDArray[Any], NDArray[Any]]:
        """The ``x`` and ``y`` of every point, as two columns (views of :attr:`points`; a grid's are small integers). O(1)."""
        return self._points[:, 0], self._points[:, 1]

    def xy(self, i: int) -> tuple[float, float]:
        """The input coordinates ``(x, y)`` of point ``i``. O(1)."""
        x, y = self._points[i].tolist()
        return x, y

    def kernel(self) -> Delaunay2Kernel:
        """The trusted fast path of :meth:`orient2d`, :meth:`orient2d_sign` and :meth:`incircle`: no validation.

        For the incremental Delaunay triangulation's loops; see
        :class:`~persistri.impl.geometry.kernel2d.Delaunay2Kernel`.  O(n) once (the
        point set's extents); make it once per run.
        """
        return Delaunay2Kernel(self)

    # -- orient2d ------------------------------------------------------------------------

    def orient2d(self, a: int, b: int, c: int) -> int:
        """±1: the SoS sign of ``det[[a, 1], [b, 1], [c, 1]]``; +1 when ``a, b, c`` turn counterclockwise.

        Never 0; equal indices raise :class:`ValueError`.  The perturbation is
        Λ3 of Edelsbrunner–Mücke with ``δ = 2``.  O(1).
        """
        rows = self._rows
        try:
            if (a | b | c) < 0:
                raise IndexError
            ax, ay = rows[a]
            bx, by = rows[b]
            cx, cy = rows[c]
        except (IndexError, TypeError):
            raise self._bad_index((a, b, c)) from None
        except ValueError:  # a lazy row not made yet
            (ax, ay), (bx, by), (cx, cy) = self._row(a), self._row(b), self._row(c)
        det, perm = orient2d_terms(ax, ay, bx, by, cx, cy)
        st = self.stats
        if st is not None:
            st.plane_side_tests += 1
            st.flops += FLOPS_ORIENT2D
        if self._uniform or self._grain_ok(a, b, c):
            thr = ERRBOUND_ORIENT2D * perm
            if det > thr:
                return 1
            if det < -thr:
                return -1
        if st is not None:
            st.filter_failures += 1
        return self._orient2d_exact(a, b, c, True)

    def orient2d_sign(self, a: int, b: int, c: int) -> int:
        """The true sign of the orient2d determinant: -1, 0 or +1. O(1)."""
        self._fixed(a, b, c)
        if self._uniform or self._grain_ok(a, b, c):
            row = self._row
            ax, ay = row(a)
            bx, by = row(b)
            cx, cy = row(c)
            det, perm = orient2d_terms(ax, ay, bx, by, cx, cy)
            thr = ERRBOUND_ORIENT2D * perm
            if det > thr or det < -thr:
                self._count(1, FLOPS_ORIENT2D, 0)
                return 1 if det > 0 else -1
        self._count(1, FLOPS_ORIENT2D, 1)
        return self._orient2d_exact(a, b, c, False)

    def _orient2d_exact(self, a: int, b: int, c: int, perturb: bool) -> int:
        det = orient2d_det(*self._int(a), *self._int(b), *self._int(c))
        if det or not perturb:
            return sign_of(det)
        return self._sos2(a, b, c)

    def _sos2(self, a: int, b: int, c: int) -> int:
        rank = self._sos_rank
        if rank is None:
            order, parity = sort_with_parity((int(a), int(b), int(c)))
        else:
            order, parity = sort_by_rank_with_parity((int(a), int(b), int(c)), rank)
        return parity * sos_orient2d(*(self._int(i) for i in order))

    def orient2d_batch(self, a: int, b: int, qs: ArrayLike) -> SignArray:
        """``[orient2d(a, b, q) for q in qs]`` as an int8 array of ±1. O(len(qs))."""
        self._fixed(a, b)
        return self.orient2d_many(a, b, qs)

    def orient2d_sign_batch(self, a: int, b: int, qs: ArrayLike) -> SignArray:
        """``[orient2d_sign(a, b, q) for q in qs]``: true signs, 0 included. O(len(qs))."""
        self._fixed(a, b)
        idx = self._index_arrays(a, b, qs)
        return self._many(idx, orient2d_terms, ERRBOUND_ORIENT2D, FLOPS_ORIENT2D, orient2d_det, self.orient2d_sign, None)

    def orient2d_many(self, a: ArrayLike, b: ArrayLike, c: ArrayLike) -> SignArray:
        """``[orient2d(a[k], b[k], c[k]) for k …]``, the arguments broadcast together. ±1 entries; O(length)."""
        idx = self._index_arrays(a, b, c)
        return self._many(idx, orient2d_terms, ERRBOUND_ORIENT2D, FLOPS_ORIENT2D, orient2d_det, self.orient2d, self._sos2)

    # -- incircle ------------------------------------------------------------------------

    def incircle(self, a: int, b: int, c: int, d: int) -> int:
        """±1: the SoS sign of the lifted orientation ``det[[a, |a|², 1], …, [d, |d|², 1]]``.

        +1 when ``d`` is inside the circle through ``a, b, c`` taken
        counterclockwise (Shewchuk's convention); it equals ``orient3d`` of the
        lifted points ``(x, y, x² + y²)`` (``proofs/proof_predicates.py``).

        Exact zeros (cocircular points) are broken by Λ4 on the lifted points,
        the lift perturbed as an independent third coordinate, least
        significant per point.  Why this choice: restricted to ``x, y`` the
        perturbation orders the entries exactly as :meth:`orient2d`'s (x_0,
        y_0, x_1, y_1, … from most to least significant), and SoS signs
        depend only on that order, so both predicates see *one* perturbed
        point set; perturbing the lift independently of ``x² + y²`` is giving
        each point an infinitesimal weight, so the triangulation these signs
        define is the regular triangulation of the perturbed weighted points —
        the Delaunay triangulation of the input wherever it is unique, with
        ties among cocircular points broken consistently.  Never 0; equal
        indices raise :class:`ValueError`.  O(1).
        """
        rows = self._rows
        try:
            if (a | b | c | d) < 0:
                raise IndexError
            ax, ay = rows[a]
            bx, by = rows[b]
            cx, cy = rows[c]
            dx, dy = rows[d]
        except (IndexError, TypeError):
            raise self._bad_index((a, b, c, d)) from None
        except ValueError:  # a lazy row not made yet
            (ax, ay), (bx, by), (cx, cy), (dx, dy) = self._row(a), self._row(b), self._row(c), self._row(d)
        det, perm = incircle_terms(ax, ay, bx, by, cx, cy, dx, dy)
        st = self.stats
        if st is not None:
            st.plane_side_tests += 1
            st.flops += FLOPS_INCIRCLE
        if self._uniform or self._grain_ok(a, b, c, d):
            thr = ERRBOUND_INCIRCLE * perm
            if det > thr:
                return 1
            if det < -thr:
                return -1
        if st is not None:
            st.filter_failures += 1
        return self._incircle_exact(a, b, c, d, True)

    def incircle_sign(self, a: int, b: int, c: int, d: int) -> int:
        """The true sign of the incircle determinant: -1, 0 (cocircular) or +1. O(1)."""
        self._fixed(a, b, c, d)
        if self._uniform or self._grain_ok(a, b, c, d):
            row = self._row
            ax, ay = row(a)
            bx, by = row(b)
            cx, cy = row(c)
            dx, dy = row(d)
            det, perm = incircle_terms(ax, ay, bx, by, cx, cy, dx, dy)
            thr = ERRBOUND_INCIRCLE * perm
            if det > thr or det < -thr:
                self._count(1, FLOPS_INCIRCLE, 0)
                return 1 if det > 0 else -1
        self._count(1, FLOPS_INCIRCLE, 1)
        return self._incircle_exact(a, b, c, d, False)

    def _incircle_exact(self, a: int, b: int, c: int, d: int, perturb: bool) -> int:
        det = incircle_det(*self._int(a), *self._int(b), *self._int(c), *self._int(d))
        if det or not perturb:
            return sign_of(det)
        return self._sos_incircle(a, b, c, d)

    def _lifted(self, i: int) -> tuple[int, int, int]:
        x, y = self._int(i)
        return (x, y, x * x + y * y)

    def _sos_incircle(self, a: int, b: int, c: int, d: int) -> int:
        rank = self._sos_rank
        if rank is None:
            order, parity = sort_with_parity((int(a), int(b), int(c), int(d)))
        else:
            order, parity = sort_by_rank_with_parity((int(a), int(b), int(c), int(d)), rank)
        return parity * sos_orient3d(*(self._lifted(i) for i in order))

    def incircle_batch(self, a: int, b: int, c: int, qs: ArrayLike) -> SignArray:
        """``[incircle(a, b, c, q) for q in qs]`` as an int8 array of ±1. O(len(qs))."""
        self._fixed(a, b, c)
        return self.incircle_many(a, b, c, qs)

    def incircle_sign_batch(self, a: int, b: int, c: int, qs: ArrayLike) -> SignArray:
        """``[incircle_sign(a, b, c, q) for q in qs]``: true signs, 0 included. O(len(qs))."""
        self._fixed(a, b, c)
        idx = self._index_arrays(a, b, c, qs)
        return self._many(idx, incircle_terms, ERRBOUND_INCIRCLE, FLOPS_INCIRCLE, incircle_det, self.incircle_sign, None)

    def incircle_many(self, a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike) -> SignArray:
        """``[incircle(a[k], b[k], c[k], d[k]) for k …]``, the arguments broadcast together. ±1; O(length)."""
        idx = self._index_arrays(a, b, c, d)
        return self._many(idx, incircle_terms, ERRBOUND_INCIRCLE, FLOPS_INCIRCLE, incircle_det, self.incircle, self._sos_incircle)
