"""The trusted fast path of ``orient2d`` and ``incircle`` for the incremental Delaunay triangulation (paper §5).

:meth:`Predicates2.kernel <persistri.impl.geometry.predicates.Predicates2.kernel>`
makes a :class:`Delaunay2Kernel`.  It answers the same signs as the checked
:class:`~persistri.impl.geometry.predicates.Predicates2` — the same Simulation of
Simplicity for exact zeros — without the checked API's validation, and it is a
module of its own because it is the triangulator's innermost loop (every cavity
test of :mod:`persistri.impl.terrain.delaunay`): the compiled twin
(docs/performance.md) compiles it with mypyc.

Two ways to decide a sign, chosen once per point set:

* **Exact floats** (:attr:`Delaunay2Kernel.exact_floats`).  When every coordinate
  is an integer multiple of one power of two ``2^g`` — the point set's least
  grain (:func:`~persistri.impl.geometry.exact.grain_span`) — and the points
  span at most :data:`INCIRCLE_EXACT_SPAN` ``= 2^12`` grains along each axis,
  every operation of :func:`~persistri.impl.geometry.filter.incircle_terms`'
  determinant is exact in float64: in units of the grain, coordinate
  differences are integers of magnitude at most ``S = 2^12``, their products at
  most ``S²``, the differences of products and the lifts at most ``2S²``, the
  three terms at most ``4S⁴`` each and their sum at most ``12 S⁴ = 3 · 2^50``:
  all integers below ``2^53``, so nothing rounds (the filter's copy is the input
  times a power of two, which changes no significand; ``choose_scaling`` keeps
  every product a normal number).  The computed determinant *is* the exact one:
  its sign decides, and an exact zero goes straight to Simulation of Simplicity.
  The same argument with ``2S² <= 2^53`` makes orient2d exact up to
  :data:`ORIENT2D_EXACT_SPAN` ``= 2^26`` grains.  Every height grid (``x`` =
  column, ``y`` = row, fewer than 4,097 samples a side) is such a set, and on it
  cocircular quadruples are common (every grid square): the checked predicates
  would prove each of those zeros with Python integers first.
* **Semi-static filter** otherwise: each determinant is compared with one
  threshold for the whole point set, from its bounding box
  (:func:`~persistri.impl.geometry.filter.incircle_box_threshold`), at least every
  test's own; then with the test's own threshold; then exact integers and SoS,
  exactly as the checked predicates do.

For the SoS of an incircle zero the first term of the Λ4 sequence
(:data:`~persistri.impl.geometry.sos.ORIENT3D_SOS`, rows sorted by index) is the
orient2d determinant of the three points of largest index; it is computed
here (exactly, on the exact-float path) and the full sequence runs only when it
is zero too.

Counting: while the predicates' ``stats`` is set, every call goes through the
checked method, so counted runs count exactly what the checked predicates count.
A caller that knows its whole run is uncounted calls ``incircle_uncounted`` and
``orient2d_uncounted``, which do not read ``stats`` (the triangulator's cavity
and walks: ``Triangulator.counted``).
Indices are not validated: out of range or repeated indices are the caller's
error (a repeated index reaches SoS, which raises :class:`ValueError`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Final

from persistri.impl.geometry.filter import (
    ERRBOUND_INCIRCLE,
    ERRBOUND_ORIENT2D,
    incircle_box_threshold,
    orient2d_box_threshold,
)

if TYPE_CHECKING:
    from persistri.impl.geometry.indexed_points import RowTable
    from persistri.impl.geometry.predicates import Predicates2

__all__ = ["Delaunay2Kernel", "INCIRCLE_EXACT_SPAN", "ORIENT2D_EXACT_SPAN", "exact_float_spans"]

INCIRCLE_EXACT_SPAN: Final[int] = 2**12
"""Largest extent, in grains along each axis, for which the incircle determinant is exact in float64."""

ORIENT2D_EXACT_SPAN: Final[int] = 2**26
"""Largest extent, in grains along each axis, for which the orient2d determinant is exact in float64."""


def exact_float_spans(pred: Predicates2) -> tuple[bool, bool]:
    """``(orient2d exact, incircle exact)``: whether the float determinants of ``pred``'s points are exact.

    The points must span at most :data:`ORIENT2D_EXACT_SPAN` (resp.
    :data:`INCIRCLE_EXACT_SPAN`) multiples of their least grain along each axis
    (module docstring); the extents ``hi − lo`` must be strictly below
    ``span · 2^grain``, decided soundly in floats (rounding is monotone and the
    bound is a double).  O(n) once.
    """
    span = pred._span
    if not pred._uniform:
        return False, False
    if span is None or len(pred) == 0:  # every coordinate is 0 (one point), or none: no test to make
        return True, True
    grain = span[0]
    extents = [hi - lo for lo, hi in pred._extents()]
    # Rounding is monotone and the bounds are doubles, so fl(hi - lo) < bound implies hi - lo < bound.
    fits_o = all(e < math.ldexp(float(ORIENT2D_EXACT_SPAN), grain) for e in extents)
    fits_i = fits_o and all(e < math.ldexp(float(INCIRCLE_EXACT_SPAN), grain) for e in extents)
    return fits_o, fits_i


class Delaunay2Kernel:
    """``orient2d``, ``orient2d_sign`` and ``incircle`` without validation, for the triangulator's loops.

    Made by :meth:`~persistri.impl.geometry.predicates.Predicates2.kernel`; the same
    signs as the checked methods of the same names (module docstring):

    * :meth:`orient2d` ``(a, b, c) -> ±1`` — SoS for exact zeros;
    * :meth:`orient2d_sign` ``(a, b, c) -> -1, 0, +1`` — the true sign;
    * :meth:`incircle` ``(a, b, c, d) -> ±1`` — +1 when ``d`` is inside the circle
      through ``a, b, c`` (counterclockwise); SoS for cocircular points, or, when
      :attr:`strict` is set, −1 (``d`` on the circle counts as outside it: the strict
      conflict rule of greedy insertion, :mod:`persistri.impl.terrain.delaunay`).

    Each is O(1): about half a microsecond interpreted.  A point set that needs
    per-test grain checks (``filter_scale[1]`` False) gets the checked methods.

    Methods of one object, called as ``kernel.incircle(…)``: compiled by mypyc (the twin), a
    compiled caller calls them directly, where a function held in an attribute is called
    through Python's call protocol (its arguments parsed and its result boxed at every test);
    interpreted, a method call costs what a closure's does (0.6 % more a test, measured).
    """

    __slots__ = ("exact_floats", "exact_orient2d", "strict", "_pred", "_rows", "_checked", "_o2_static", "_ic_static")

    exact_floats: bool
    strict: bool
    exact_orient2d: bool
    _pred: Predicates2
    _rows: RowTable
    _checked: bool
    _o2_static: float
    _ic_static: float

    def __init__(self, pred: Predicates2) -> None:
        exact_o, exact_i = exact_float_spans(pred)
        self.exact_floats = exact_i
        self.strict = False
        self.exact_orient2d = exact_o
        self._pred = pred
        self._rows = pred._rows
        self._checked = not pred._uniform
        # The semi-static thresholds (a test whose determinant exceeds one in magnitude is decided by its sign):
        # the box's, or 0 where the float determinant is exact (only an exact zero is left: SoS), or +inf where
        # the filters need per-test grain checks (no float decides: the checked method does).
        if self._checked:
            self._o2_static = self._ic_static = math.inf
            return
        # The box of the filter copy: the input's, times 2^shift (exact: a power of two).
        shift = pred.filter_scale[0]
        (xlo, xhi), (ylo, yhi) = pred._extents() if len(pred) else [(0.0, 0.0), (0.0, 0.0)]
        xspan, yspan = math.ldexp(xhi - xlo, shift), math.ldexp(yhi - ylo, shift)
        self._o2_static = 0.0 if exact_o else orient2d_box_threshold(xspan, yspan)
        self._ic_static = 0.0 if exact_i else incircle_box_threshold(xspan, yspan)

    # The filter expressions of :mod:`.filter` are written out in place (a call per test costs a
    # sixth of the test); they are the same statements in the same order, so they round alike
    # (tests/test_terrain_kernel.py compares them with the functions' bodies).
    # The three tests take their indices as objects (Any, not int): compiled by mypyc, an int parameter
    # is unboxed on entry and boxed again for every ``rows[i]``; the callers pass the vertices (int
    # objects) they hold.  Interpreted, nothing changes.

    def _incircle_zero(self, a: Any, b: Any, c: Any, d: Any) -> int:
        """SoS of an exact-float zero: the first term of Λ4 (orient2d of the three largest indices), then the rest.
        Points ranked otherwise than by index (``Predicates2(sos_rank=…)``) go to the predicates' own SoS.
        Under :attr:`strict`, −1: ``d`` on the circle is not inside it."""
        if self.strict:
            return -1
        if self._pred._sos_rank is not None:
            return self._pred._sos_incircle(a, b, c, d)
        i0, i1, i2, i3 = sorted((a, b, c, d))
        inversions = (a > b) + (a > c) + (a > d) + (b > c) + (b > d) + (c > d)
        rows = self._rows
        try:
            px, py = rows[i1]
            qx, qy = rows[i2]
            rx, ry = rows[i3]
        except ValueError:
            row = self._pred._row
            (px, py), (qx, qy), (rx, ry) = row(i1), row(i2), row(i3)
        first = (px - rx) * (qy - ry) - (py - ry) * (qx - rx)  # exact: orient2d on the exact-float path
        if first == 0.0:
            return self._pred._sos_incircle(a, b, c, d)
        return (1 if first > 0.0 else -1) * (-1 if inversions & 1 else 1)

    def incircle(self, a: Any, b: Any, c: Any, d: Any) -> int:
        """±1: +1 when ``d`` is inside the circle through ``a, b, c`` (counterclockwise); SoS for cocircular points
        (−1 under :attr:`strict`). O(1)."""
        pred = self._pred
        if pred.stats is not None:
            if self.strict:
                return 1 if pred.incircle_sign(a, b, c, d) > 0 else -1
            return pred.incircle(a, b, c, d)
        return self.incircle_uncounted(a, b, c, d)

    def incircle_uncounted(self, a: Any, b: Any, c: Any, d: Any) -> int:
        """:meth:`incircle` for a caller that knows nothing is counted — the predicates' ``stats`` is None and stays
        so for its whole run (the triangulator decides it once: ``Triangulator.counted``): the same sign, without
        reading ``stats`` (compiled, a generic attribute read of the interpreted predicates, a sixth of a test). O(1)."""
        # (The predicates are read only off the fast path: the filter decides nearly every test.)
        rows = self._rows
        try:
            ax, ay = rows[a]
            bx, by = rows[b]
            cx, cy = rows[c]
            dx, dy = rows[d]
        except ValueError:
            row = self._pred._row
            (ax, ay), (bx, by), (cx, cy), (dx, dy) = row(a), row(b), row(c), row(d)
        # filter.incircle_terms:
        adx = ax - dx
        bdx = bx - dx
        cdx = cx - dx
        ady = ay - dy
        bdy = by - dy
        cdy = cy - dy
        bdxcdy = bdx * cdy
        cdxbdy = cdx * bdy
        alift = adx * adx + ady * ady
        cdxady = cdx * ady
        adxcdy = adx * cdy
        blift = bdx * bdx + bdy * bdy
        adxbdy = adx * bdy
        bdxady = bdx * ady
        clift = cdx * cdx + cdy * cdy
        det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady)
        ic_static = self._ic_static
        if det > ic_static:
            return 1
        if det < -ic_static:
            return -1
        if self.exact_floats:
            return self._incircle_zero(a, b, c, d)  # the exact determinant is 0
        pred = self._pred
        if self._checked:
            if self.strict:
                return 1 if pred.incircle_sign(a, b, c, d) > 0 else -1
            return pred.incircle(a, b, c, d)
        permanent = (
            (abs(bdxcdy) + abs(cdxbdy)) * alift
            + (abs(cdxady) + abs(adxcdy)) * blift
            + (abs(adxbdy) + abs(bdxady)) * clift
        )
        # end of filter.incircle_terms
        thr = ERRBOUND_INCIRCLE * permanent
        if det > thr:
            return 1
        if det < -thr:
            return -1
        if self.strict:
            return 1 if pred._incircle_exact(a, b, c, d, False) > 0 else -1
        return pred._incircle_exact(a, b, c, d, True)

    # orient2d and orient2d_sign each write the determinant out (a helper returning it would box a
    # tuple of three floats per test when compiled).

    def orient2d(self, a: Any, b: Any, c: Any) -> int:
        """±1: the SoS sign of ``det[[a, 1], [b, 1], [c, 1]]``; +1 when ``a, b, c`` turn counterclockwise. O(1)."""
        pred = self._pred
        if pred.stats is not None:
            return pred.orient2d(a, b, c)
        return self.orient2d_uncounted(a, b, c)

    def orient2d_uncounted(self, a: Any, b: Any, c: Any) -> int:
        """:meth:`orient2d` for a caller that knows nothing is counted (as :meth:`incircle_uncounted`). O(1)."""
        rows = self._rows
        try:
            ax, ay = rows[a]
            bx, by = rows[b]
            cx, cy = rows[c]
        except ValueError:
            row = self._pred._row
            (ax, ay), (bx, by), (cx, cy) = row(a), row(b), row(c)
        # filter.orient2d_terms (the permanent is computed below when needed):
        acx = ax - cx
        bcx = bx - cx
        acy = ay - cy
        bcy = by - cy
        detleft = acx * bcy
        detright = acy * bcx
        det = detleft - detright
        # end of filter.orient2d_terms
        o2_static = self._o2_static
        if det > o2_static:
            return 1
        if det < -o2_static:
            return -1
        pred = self._pred
        if self.exact_orient2d:
            return pred._sos2(a, b, c)  # the exact determinant is 0
        if self._checked:
            return pred.orient2d(a, b, c)
        o2_errbound = ERRBOUND_ORIENT2D
        thr = o2_errbound * (abs(detleft) + abs(detright))
        if det > thr:
            return 1
        if det < -thr:
            return -1
        return pred._orient2d_exact(a, b, c, True)

    def orient2d_sign(self, a: Any, b: Any, c: Any) -> int:
        """-1, 0 or +1: the true sign of ``det[[a, 1], [b, 1], [c, 1]]`` (no perturbation). O(1)."""
        pred = self._pred
        if pred.stats is not None:
            return pred.orient2d_sign(a, b, c)
        rows = self._rows
        try:
            ax, ay = rows[a]
            bx, by = rows[b]
            cx, cy = rows[c]
        except ValueError:
            row = pred._row
            (ax, ay), (bx, by), (cx, cy) = row(a), row(b), row(c)
        # filter.orient2d_terms (the permanent is computed below when needed):
        acx = ax - cx
        bcx = bx - cx
        acy = ay - cy
        bcy = by - cy
        detleft = acx * bcy
        detright = acy * bcx
        det = detleft - detright
        # end of filter.orient2d_terms
        o2_static = self._o2_static
        if det > o2_static:
            return 1
        if det < -o2_static:
            return -1
        if self.exact_orient2d:
            return 0  # the exact determinant
        if self._checked:
            return pred.orient2d_sign(a, b, c)
        o2_errbound = ERRBOUND_ORIENT2D
        thr = o2_errbound * (abs(detleft) + abs(detright))
        if det > thr:
            return 1
        if det < -thr:
            return -1
        return pred._orient2d_exact(a, b, c, False)
