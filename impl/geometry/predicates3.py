"""Exact 3D predicates over indexed points: :class:`Predicates3` (``orient3d``, paper §3 and Appendix A).

The bulldozer's plane-side test, its centre point (:meth:`Predicates3.with_centroid`)
and the affine basis of a point set; the three stages of every test (filter,
exact integers, Simulation of Simplicity), the sign conventions and the
counting are described in :mod:`persistri.impl.geometry.predicates`, which
exports this class.
"""

from __future__ import annotations

from collections.abc import Callable
from fractions import Fraction

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.geometry.exact import ZERO_LOW, IntegerScale, binary_exponents, orient2d_det, orient3d_det
from persistri.impl.geometry.filter import (
    ERRBOUND_ORIENT2D,
    ERRBOUND_ORIENT3D,
    FLOPS_ORIENT2D,
    FLOPS_ORIENT3D,
    GRAIN_MIN,
    choose_scaling,
    orient2d_terms,
    orient3d_terms,
)
from persistri.impl.geometry.indexed_points import IndexedPoints, IntArray, SignArray, sign_of
from persistri.impl.geometry.kernel import Orient3dKernel
from persistri.impl.geometry.points import as_points
from persistri.impl.geometry.sos import sort_with_parity, sos_orient3d
from persistri.impl.stats import Stats

__all__ = ["Predicates3", "affine_dimension"]


class Predicates3(IndexedPoints):
    """Exact 3D predicates over the rows of an ``(n, 3)`` array, by point index.

    Build once (O(n)): ``Predicates3(points, stats=None)``.  ``points`` must be
    an ``(n, 3)`` array of real numbers; NaN or inf raises :class:`ValueError`
    naming the first bad row, non-numeric input :class:`TypeError`, a wrong
    shape :class:`ValueError`.  Tests take point indices ``0 <= i < len(self)``;
    a bad index raises :class:`IndexError` or :class:`TypeError`.

    The bulldozer's centre point is added by :meth:`with_centroid`, which returns
    a new object in which the centre has index ``len(points)``.
    """

    __slots__ = ("_centre", "_centre_exact")

    _rows: list[tuple[float, ...]]
    """Always :meth:`_setup`'s list here (or :meth:`_with_row`'s copy of it): the compiled
    :class:`~persistri.impl.geometry.kernel.Orient3dKernel` indexes it as a list."""
    _centre: int | None
    _centre_exact: tuple[int, ...] | None

    def __init__(self, points: ArrayLike, *, stats: Stats | None = None) -> None:
        pts = as_points(points, 3)
        self._centre = None
        self._centre_exact = None
        self._setup(pts, exact_rows=pts.shape[0], extra=0, stats=stats, lazy_rows=True)

    @classmethod
    def of_validated(cls, points: NDArray[np.float64], *, stats: Stats | None = None) -> Predicates3:
        """``Predicates3(points, stats=stats)`` for an array that :func:`~persistri.impl.geometry.points.as_points`
        returned (or a row selection of one): C-contiguous ``(n, 3)`` float64, finite, no ``-0.0``.

        Skips the validation's passes over the points (a copy and a finiteness test: about 1 ms at
        256K points).  The array becomes read-only and is kept (not copied): pass one that nothing
        else writes to.  O(n).
        """
        out = cls.__new__(cls)
        out._centre = None
        out._centre_exact = None
        out._setup(points, exact_rows=points.shape[0], extra=0, stats=stats, lazy_rows=True)
        return out

    def __repr__(self) -> str:
        centre = "" if self._centre is None else f", centre={self._centre}"
        return f"Predicates3(n={self._n}{centre})"

    # -- the centre --------------------------------------------------------------------

    @property
    def centre(self) -> int | None:
        """The index of the constructed centre point, or None before :meth:`with_centroid`."""
        return self._centre

    @property
    def centre_is_float(self) -> bool:
        """Whether the centre is a double (filtered like any point) rather than the exact centroid."""
        return self._centre is not None and self._centre_exact is None

    def with_centroid(self, a: int, b: int, c: int, d: int) -> Predicates3:
        """A new ``Predicates3`` with a point strictly inside tetrahedron ``a, b, c, d`` at index ``len(self)``.

        The centre is the float centroid ``fl((p_a + p_b + p_c + p_d) / 4)``
        when it is *exactly* verified to lie strictly inside (four exact
        orientation signs, all equal to the tetrahedron's).  It is then an
        ordinary input double: it takes part in the integer scale and the
        filter like any point, so tests involving it stay fast.  When the float
        centroid is not strictly inside (a needle-thin tetrahedron, or
        overflow), the centre is the exact centroid: every integer coordinate
        is multiplied by 4 and the centre is the exact sum of the four points;
        tests involving it are then always decided exactly (its float copy is
        NaN, which the filter never accepts), and row ``len(self)`` of
        :attr:`points` holds only the nearest doubles.  Either way the centre
        is indexed for SoS like any point (the largest index: the least
        perturbed).  Stats and everything else carry over.

        Raises :class:`ValueError` if the tetrahedron is flat (exact sign 0),
        the indices repeat, or a centre was already added. O(n) (copies the arrays).
        """
        if self._centre is not None:
            raise ValueError("this point set already has a centre")
        self._fixed(a, b, c, d)
        tetra = (int(a), int(b), int(c), int(d))
        if len(set(tetra)) != 4:
            raise ValueError(f"a tetrahedron needs four distinct points, got {tetra}")
        s = self.orient3d_sign(*tetra)
        if s == 0:
            raise ValueError(f"points {tetra} are coplanar: no interior centre")
        p = self._points[list(tetra)]
        with np.errstate(all="ignore"):
            guess = ((p[0] + p[1]) + (p[2] + p[3])) * 0.25
        n = self._n
        if np.all(np.isfinite(guess)):
            guess = guess + 0.0
            cand = self._with_row(guess)
            if cand is None:
                cand = Predicates3.__new__(Predicates3)
                cand._setup(np.vstack([self._points, guess[None, :]]), exact_rows=n + 1, extra=0, stats=self.stats, lazy_rows=True)
            cand._centre = n
            cand._centre_exact = None
            if cand._strictly_inside(tetra, n, s):
                return cand
        # The exact centroid: at the integer scale ×4 it is the sum of the four points.
        ints = [self._int(i) for i in tetra]
        exact = tuple(ints[0][j] + ints[1][j] + ints[2][j] + ints[3][j] for j in range(3))
        unit = Fraction(2) ** (self._scale.exponent - 2)  # the value of 1 at the scale ×4
        nearest = np.array([[float(v * unit) for v in exact]])
        out = Predicates3.__new__(Predicates3)
        out._centre = n
        out._centre_exact = None
        out._setup(np.vstack([self._points, nearest]), exact_rows=n, extra=2, stats=self.stats, lazy_rows=True)
        out._centre_exact = exact
        out._ints[n] = exact  # the memo of exact integers serves the centre's from the start
        assert out._strictly_inside(tetra, n, s), "the exact centroid of a tetrahedron is interior"
        return out

    def _with_row(self, row: NDArray[np.float64]) -> Predicates3 | None:
        """A copy with ``row`` appended as an ordinary exact point, or None if that changes the filter scaling.

        What :meth:`_setup` would build for the ``n + 1`` rows, without redoing it
        for the first ``n``: when the power-of-two scale of the filter copy stays
        the same (the usual case: a centroid's exponents lie within the data's),
        the filter rows and columns are the parent's plus one.  O(n) copying, no
        per-point Python work.
        """
        if self._span is None or not self._uniform:
            return None
        low, high = binary_exponents(row[None, :])
        nonzero = low < ZERO_LOW
        g, h = self._span
        if nonzero.any():
            g, h = min(g, int(low[nonzero].min())), max(h, int(high[nonzero].max()))
        scaling = choose_scaling(np.array([g], dtype=np.int64), np.array([h], dtype=np.int64))
        if not scaling.uniform or scaling.shift != self._shift:
            return None
        shift = self._shift
        scaled = np.ldexp(row, shift)
        out = Predicates3.__new__(Predicates3)
        pts = np.vstack([self._points, row[None, :]])
        pts.setflags(write=False)
        out._points = pts
        out._n = self._n + 1
        out._dim = self._dim
        out.stats = self.stats
        out._shift = shift
        out._span = (g, h)
        out._scale = IntegerScale(min(self._scale.exponent, g), 0)
        out._grain = None  # the scaling is uniform: every grain, the new one's included, is >= GRAIN_MIN
        out._uniform = True
        out._cols = tuple(np.append(col, x) for col, x in zip(self._cols, scaled.tolist()))
        out._rows = self._rows + [tuple(scaled.tolist())]
        out._ints = dict(self._ints) if out._scale == self._scale else {}
        return out

    def _strictly_inside(self, tetra: tuple[int, int, int, int], c: int, s: int) -> bool:
        """Whether ``c`` has positive barycentric coordinates in ``tetra`` (orientation ``s``), exactly."""
        for k in range(4):
            replaced = list(tetra)
            replaced[k] = c
            if self.orient3d_sign(*replaced) != s:
                return False
        return True

    def _int_columns(self, q: IntArray) -> list[NDArray[np.object_]]:
        cols = super()._int_columns(q)
        if self._centre_exact is not None:
            at = np.flatnonzero(q == self._centre)
            for j in range(3):
                cols[j][at] = self._centre_exact[j]
        return cols

    # -- orient3d ------------------------------------------------------------------------

    def orient3d(self, a: int, b: int, c: int, d: int) -> int:
        """±1: the SoS sign of ``det[[a, 1], [b, 1], [c, 1], [d, 1]]`` (see the module docstring).

        Never 0; ``d`` below the plane of ``a, b, c`` gives +1.  Raises
        :class:`ValueError` if two indices are equal.  O(1): one float filter
        (:data:`~persistri.impl.geometry.filter.FLOPS_ORIENT3D` flops), exact
        integers when it cannot decide.
        """
        row = self._row
        try:
            if (a | b | c | d) < 0:
                raise IndexError
            ax, ay, az = row(a)
            bx, by, bz = row(b)
            cx, cy, cz = row(c)
            dx, dy, dz = row(d)
        except (IndexError, TypeError):
            raise self._bad_index((a, b, c, d)) from None
        det, perm = orient3d_terms(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz)
        st = self.stats
        if st is not None:
            st.plane_side_tests += 1
            st.flops += FLOPS_ORIENT3D
        if self._uniform or self._grain_ok(a, b, c, d):
            thr = ERRBOUND_ORIENT3D * perm
            if det > thr:
                return 1
            if det < -thr:
                return -1
        if st is not None:
            st.filter_failures += 1
        return self._orient3d_exact(a, b, c, d, True)

    def orient3d_sign(self, a: int, b: int, c: int, d: int) -> int:
        """The true sign of the orient3d determinant: -1, 0 or +1 (no perturbation). O(1)."""
        self._fixed(a, b, c, d)
        if self._uniform or self._grain_ok(a, b, c, d):
            row = self._row
            ax, ay, az = row(a)
            bx, by, bz = row(b)
            cx, cy, cz = row(c)
            dx, dy, dz = row(d)
            det, perm = orient3d_terms(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz)
            thr = ERRBOUND_ORIENT3D * perm
            if det > thr or det < -thr:
                self._count(1, FLOPS_ORIENT3D, 0)
                return 1 if det > 0 else -1
        self._count(1, FLOPS_ORIENT3D, 1)
        return self._orient3d_exact(a, b, c, d, False)

    def _orient3d_exact(self, a: int, b: int, c: int, d: int, perturb: bool) -> int:
        det = orient3d_det(*self._int(a), *self._int(b), *self._int(c), *self._int(d))
        if det or not perturb:
            return sign_of(det)
        return self._sos3(a, b, c, d)

    def _sos3(self, a: int, b: int, c: int, d: int) -> int:
        order, parity = sort_with_parity((int(a), int(b), int(c), int(d)))
        return parity * sos_orient3d(*(self._int(i) for i in order))

    def orient3d_batch(self, a: int, b: int, c: int, qs: ArrayLike) -> SignArray:
        """``[orient3d(a, b, c, q) for q in qs]`` as an int8 array of ±1.

        For conflict lists: the plane-side test of every pending point ``q``
        against one plane.  The filter runs vectorised; the entries it cannot
        decide go to exact integer arithmetic (vectorised on object arrays), and
        their exact zeros to SoS.  ``q`` equal to ``a``, ``b`` or ``c`` raises
        :class:`ValueError`.  O(len(qs)).
        """
        self._fixed(a, b, c)
        return self.orient3d_many(a, b, c, qs)

    def orient3d_sign_batch(self, a: int, b: int, c: int, qs: ArrayLike) -> SignArray:
        """``[orient3d_sign(a, b, c, q) for q in qs]``: true signs, 0 included. O(len(qs))."""
        self._fixed(a, b, c)
        idx = self._index_arrays(a, b, c, qs)
        return self._many(idx, orient3d_terms, ERRBOUND_ORIENT3D, FLOPS_ORIENT3D, orient3d_det, self.orient3d_sign, None)

    def orient3d_many(self, a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike) -> SignArray:
        """``[orient3d(a[k], b[k], c[k], d[k]) for k …]``: each argument an index or a 1-D index array.

        The arrays are broadcast together, so any mix of fixed points and
        per-entry points works — e.g. every (face, pending point) pair of a
        whole visible region in one call.  ±1 entries; O(length).
        """
        idx = self._index_arrays(a, b, c, d)
        return self._many(idx, orient3d_terms, ERRBOUND_ORIENT3D, FLOPS_ORIENT3D, orient3d_det, self.orient3d, self._sos3)

    def kernel(self) -> Orient3dKernel:
        """The trusted fast path of :meth:`orient3d` for internal algorithms (the bulldozer): no validation.

        See :class:`Orient3dKernel`.  O(1); make it once per run.
        """
        return Orient3dKernel(self)

    # -- affine structure -----------------------------------------------------------------

    def collinear(self, a: int, b: int, c: int) -> bool:
        """Whether points ``a, b, c`` lie on one line (exact; repeated points count as collinear). O(1)."""
        self._fixed(a, b, c)
        return bool(self._collinear_batch(int(a), int(b), np.array([c], dtype=np.intp))[0])

    def _collinear_batch(self, a: int, b: int, q: IntArray) -> NDArray[np.bool_]:
        """Exact collinearity of ``a, b, q`` for each ``q``: the three projected orient2d vanish."""
        m = q.size
        undecided = np.ones(m, dtype=bool)
        cols = self._cols
        grain_ok = np.ones(m, dtype=bool)
        if not self._uniform:
            grains = self._grain
            assert grains is not None, "a non-uniform set keeps its per-point grains"
            grain_ok = np.minimum(grains[q], min(int(grains[a]), int(grains[b]))) >= GRAIN_MIN
        for u, v in ((0, 1), (1, 2), (2, 0)):
            au, av = np.full(m, cols[u][a]), np.full(m, cols[v][a])
            bu, bv = np.full(m, cols[u][b]), np.full(m, cols[v][b])
            with np.errstate(all="ignore"):
                det, perm = orient2d_terms(au, av, bu, bv, cols[u][q], cols[v][q])
                thr = ERRBOUND_ORIENT2D * perm
                undecided &= ~(((det > thr) | (det < -thr)) & grain_ok)
        self._count(3 * m, FLOPS_ORIENT2D, 0)
        out = np.zeros(m, dtype=bool)
        todo = np.flatnonzero(undecided)
        if todo.size:
            self._count(0, 0, int(todo.size))
            pa, pb = self._int(a), self._int(b)
            iq = self._int_columns(q[todo])
            zero = np.ones(todo.size, dtype=bool)
            for u, v in ((0, 1), (1, 2), (2, 0)):
                fau, fav, fbu, fbv = (np.full(todo.size, x, dtype=object) for x in (pa[u], pa[v], pb[u], pb[v]))
                zero &= orient2d_det(fau, fav, fbu, fbv, iq[u], iq[v]) == 0
            out[todo] = zero
        return out

    def affine_basis(self, order: ArrayLike | None = None) -> tuple[int, ...]:
        """A maximal affinely independent subset, as indices, chosen greedily in ``order``.

        Scanning ``order`` (default: every input row in index order, the centre
        excluded), the result is ``(p0,)`` plus the first point different from
        ``p0``, then the first not on their line, then the first not on their
        plane — as far as such points exist.  Its length minus one is the
        affine dimension of the scanned points (exact): 0 all identical,
        1 collinear, 2 coplanar, 3 spanning space; ``()`` for no points.  The
        hull's first tetrahedron can be the 4-point result.  O(n) filtered
        tests, done in growing chunks so that typical inputs stop after a few points.
        """
        if order is None:
            n_input = self._n if self._centre is None else self._centre
            idx = np.arange(n_input, dtype=np.intp)
        else:
            (first,), _ = self._index_arrays(order)
            idx = np.array([first], dtype=np.intp) if isinstance(first, int) else first
            if self._centre is not None and bool(np.any(idx == self._centre)):
                raise ValueError("the affine basis is taken over input points, not the centre")
        if idx.size == 0:
            return ()
        p0 = int(idx[0])
        rows = self._points
        p1 = self._first(idx, lambda q: np.any(rows[q] != rows[p0], axis=1))
        if p1 is None:
            return (p0,)
        p2 = self._first(idx, lambda q: ~self._collinear_batch(p0, p1, q))
        if p2 is None:
            return (p0, p1)
        p3 = self._first(idx, lambda q: self.orient3d_sign_batch(p0, p1, p2, q) != 0)
        if p3 is None:
            return (p0, p1, p2)
        return (p0, p1, p2, p3)

    @staticmethod
    def _first(idx: IntArray, hit: Callable[[IntArray], NDArray[np.bool_]]) -> int | None:
        """The first index in ``idx`` where ``hit`` is True, testing chunks of growing size."""
        start = 0
        size = 16
        while start < idx.size:
            chunk = idx[start : start + size]
            found = np.flatnonzero(hit(chunk))
            if found.size:
                return int(chunk[found[0]])
            start += size
            size *= 8
        return None


def affine_dimension(points: ArrayLike | Predicates3) -> int:
    """The exact dimension of the affine hull of 3D points: 0, 1, 2 or 3 (-1 for no points).

    0: all points identical; 1: collinear; 2: coplanar; 3: spanning space.
    Accepts an ``(n, 3)`` array (validated as by :class:`Predicates3`) or a
    :class:`Predicates3` (its input points, the centre excluded). O(n).
    """
    preds = points if isinstance(points, Predicates3) else Predicates3(points)
    return len(preds.affine_basis()) - 1
