"""Floating-point filters with proven error bounds (Shewchuk 1997, stage A).

A *filter* evaluates a predicate's determinant in float64 together with its
*permanent* (the same expression with every product of differences replaced by
its absolute value, so ``|det| <= permanent`` term by term).  If

    |det_computed| > fl(ERRBOUND · permanent_computed)

the sign of the computed determinant is the sign of the exact one; otherwise the
caller decides the test exactly (:mod:`persistri.impl.geometry.exact`).  The
constants are proved sufficient in ``proofs/proof_predicates.py`` by a symbolic
forward error analysis of *these very functions*: the proof runs them on
tracking numbers that model every operation as ``exact · (1 + δ)`` with
``|δ| <= u = 2^-53``.

The expressions are written once, generically, so that the scalar path (Python
floats), the batch path (numpy arrays, one element per query point) and the
proof all evaluate the same operations in the same order: numpy's float64
arithmetic rounds exactly like Python's, so scalar and batch agree bit for bit.

When the model holds
--------------------
The model ``fl(x ∘ y) = (x ∘ y)(1 + δ)`` fails on overflow and, for products,
on underflow.

* *Overflow* is detected at run time: the permanent dominates the determinant
  operation by operation (rounding is monotone and ``|x ± y| <= |x| + |y|``), so
  a finite permanent means no intermediate value overflowed; an infinite or NaN
  permanent makes the threshold ``inf``/``NaN``, which no comparison accepts.
* *Underflow* is excluded by the **grain** argument.  If every coordinate of
  the points of a test is an integer multiple of ``2^G`` (``G`` the smallest
  *grain*, the exponent of the lowest set bit, over those coordinates), then
  every computed value of degree ``j`` (a rounded polynomial of degree ``j`` in
  the coordinate differences) is a multiple of ``2^(jG)``: round-to-nearest
  maps a multiple of ``2^m`` to a multiple of ``2^m`` whenever
  ``2^m >= 2^-1074``.  A nonzero product of degree ``j <= 4`` therefore has
  magnitude at least ``2^(4G) >= 2^-960`` when ``G >= GRAIN_MIN = -240``: it is
  a normal number and the relative-error model holds (sums obey it even in the
  subnormal range, where they are exact).  The threshold ``ERRBOUND ·
  permanent`` is then at least ``2^-1012``, also normal.  The filters are fed
  a copy of the points scaled by a power of two (exact) chosen by
  :func:`choose_scaling` so that every grain satisfies the bound when the
  data's dynamic range allows it; otherwise each test checks the grains of its
  own points (:attr:`FilterScaling.uniform` is False).

Operation counts
----------------
``FLOPS_*`` is the number of floating-point operations (``+``, ``-``, ``×``,
``|·|``) one filtered test performs: the expression below plus the threshold
product.  They are what :class:`~persistri.impl.stats.Stats` ``flops`` counts.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Final, Protocol, Self, TypeVar

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "Arith",
    "U",
    "ERRBOUND_ORIENT2D",
    "ERRBOUND_ORIENT3D",
    "ERRBOUND_INCIRCLE",
    "FLOPS_ORIENT2D",
    "FLOPS_ORIENT3D",
    "FLOPS_INCIRCLE",
    "FLOPS_PLANE",
    "FLOPS_PLANE_SIDE",
    "ERRBOUND_PLANE_SIDE",
    "GRAIN_MIN",
    "TOP_MAX",
    "orient2d_terms",
    "orient2d_box_threshold",
    "incircle_box_threshold",
    "orient3d_terms",
    "incircle_terms",
    "plane_terms",
    "plane_side_terms",
    "plane_side_terms_into",
    "plane_side_det",
    "plane_side_det_into",
    "orient3d_box_threshold",
    "plane_side_box_threshold",
    "orient3d_plane_terms",
    "FilterScaling",
    "choose_scaling",
]


class Arith(Protocol):
    """Numbers the filter expressions run on: floats, float64 arrays, the proof's tracking numbers."""

    def __add__(self, other: Self, /) -> Self: ...

    def __sub__(self, other: Self, /) -> Self: ...

    def __mul__(self, other: Self, /) -> Self: ...

    def __abs__(self) -> Self: ...


T = TypeVar("T", bound=Arith)

if TYPE_CHECKING:

    def _abs(x: T, /) -> T:
        """``abs``, typed so that it keeps the argument's type."""
        ...

else:
    # The builtin itself: a generic wrapper would cost a call per use on the hot path.
    _abs = abs


U: Final[float] = 2.0**-53
"""The unit roundoff of float64 under round-to-nearest: ``|δ| <= U``."""

ERRBOUND_ORIENT2D: Final[float] = (3.0 + 2.0**-40) * U
"""Filter constant of :func:`orient2d_terms`: 3u plus slack for the second-order terms (proved)."""

ERRBOUND_ORIENT3D: Final[float] = (7.0 + 2.0**-40) * U
"""Filter constant of :func:`orient3d_terms`: 7u plus slack for the second-order terms (proved)."""

ERRBOUND_INCIRCLE: Final[float] = (10.0 + 2.0**-40) * U
"""Filter constant of :func:`incircle_terms`: 10u plus slack for the second-order terms (proved)."""

ERRBOUND_PLANE_SIDE: Final[float] = (7.0 + 2.0**-40) * U
"""Filter constant of :func:`orient3d_plane_terms` (a plane-side test through :func:`plane_terms`
and :func:`plane_side_terms`): 7u plus slack for the second-order terms (proved), as for
:func:`orient3d_terms` — the same depth of rounding, in another order."""

FLOPS_ORIENT2D: Final[int] = 11
"""Floating-point operations of one filtered orient2d: 4 differences, 2 products, 1 difference,
2 absolute values, 1 sum (the permanent), 1 threshold product."""

FLOPS_ORIENT3D: Final[int] = 41
"""Floating-point operations of one filtered orient3d: 9 differences, 6 products,
3 differences, 3 products, 2 sums (the determinant: 23); 9 absolute values, 3 sums,
3 products, 2 sums (the permanent: 17); 1 threshold product."""

FLOPS_INCIRCLE: Final[int] = 44
"""Floating-point operations of one filtered incircle: 6 differences, 6 products and
3 sums (the lifts), 6 products, 3 differences, 3 products, 2 sums (the determinant: 29);
6 absolute values, 3 sums, 3 products, 2 sums (the permanent: 14); 1 threshold product."""

FLOPS_PLANE: Final[int] = 24
"""Floating-point operations of :func:`plane_terms`, done once per plane: 6 differences,
6 products, 3 differences (the normal); 6 absolute values, 3 sums (its permanents)."""

FLOPS_PLANE_SIDE: Final[int] = 17
"""Floating-point operations of one filtered plane-side test against a prepared plane
(:func:`plane_side_terms`): 3 differences, 3 products, 2 sums (the determinant: 8);
3 absolute values, 3 products, 2 sums (the permanent: 8); 1 threshold product."""

GRAIN_MIN: Final[int] = -240
"""The smallest grain (exponent of the lowest set bit of a scaled coordinate) for which
the filters' error model provably holds: degree-4 products stay ``>= 2^-960``."""

TOP_MAX: Final[int] = 250
"""Largest exponent ``e`` with ``|x| < 2^e`` that :func:`choose_scaling` allows for the scaled
coordinates, so that degree-4 expressions of coordinate differences stay below ``2^1016``."""


def orient2d_terms(ax: T, ay: T, bx: T, by: T, cx: T, cy: T) -> tuple[T, T]:
    """``(det, permanent)`` of orient2d in floating point, translated to ``c``.

    ``det = (a - c) × (b - c)`` is the 3×3 determinant with rows ``(x, y, 1)``:
    positive when ``a, b, c`` turn counterclockwise.  O(1).
    """
    acx = ax - cx
    bcx = bx - cx
    acy = ay - cy
    bcy = by - cy
    detleft = acx * bcy
    detright = acy * bcx
    det = detleft - detright
    permanent = _abs(detleft) + _abs(detright)
    return det, permanent


def orient3d_terms(
    ax: T, ay: T, az: T, bx: T, by: T, bz: T, cx: T, cy: T, cz: T, dx: T, dy: T, dz: T
) -> tuple[T, T]:
    """``(det, permanent)`` of orient3d in floating point, translated to ``d``.

    ``det = det[a - d; b - d; c - d]`` equals the 4×4 determinant with rows
    ``(x, y, z, 1)``: positive when ``d`` lies below the plane of ``a, b, c``
    (``a, b, c`` counterclockwise seen from above).  O(1).
    """
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
    permanent = (
        (_abs(bdxcdy) + _abs(cdxbdy)) * _abs(adz)
        + (_abs(cdxady) + _abs(adxcdy)) * _abs(bdz)
        + (_abs(adxbdy) + _abs(bdxady)) * _abs(cdz)
    )
    return det, permanent


def plane_terms(ax: T, ay: T, az: T, bx: T, by: T, bz: T, cx: T, cy: T, cz: T) -> tuple[T, T, T, T, T, T]:
    """The plane through ``a, b, c``, prepared for many plane-side tests: ``(nx, ny, nz, px, py, pz)``.

    ``n = (b - a) × (c - a)`` is the right-hand normal in floating point and
    ``p`` its permanents (``px = |(b - a)_y (c - a)_z| + |(b - a)_z (c - a)_y|``
    and so on: each component's two products, without their signs).
    :func:`plane_side_terms` finishes one test per query point.  Done once per
    plane (:data:`FLOPS_PLANE`), so that a conflict list tested against one
    face costs :data:`FLOPS_PLANE_SIDE` per point instead of
    :data:`FLOPS_ORIENT3D`.  O(1).
    """
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
    px = _abs(yz) + _abs(zy)
    py = _abs(zx) + _abs(xz)
    pz = _abs(xy) + _abs(yx)
    return nx, ny, nz, px, py, pz


def plane_side_terms(nx: T, ny: T, nz: T, px: T, py: T, pz: T, ax: T, ay: T, az: T, qx: T, qy: T, qz: T) -> tuple[T, T]:
    """``(det, permanent)`` of ``orient3d(a, b, c, q)`` from the plane of ``a, b, c`` (:func:`plane_terms`).

    ``det = (a - q) · n``, which equals the 4×4 determinant with rows ``(x, y, z, 1)``
    of ``a, b, c, q`` (``det[a - q; b - q; c - q]``, subtracting the first row from
    the others); ``permanent = Σ |a - q|_j p_j``.  The filter constant is
    :data:`ERRBOUND_PLANE_SIDE` (proved for :func:`orient3d_plane_terms`, the
    two functions composed).  O(1).
    """
    aqx = ax - qx
    aqy = ay - qy
    aqz = az - qz
    det = aqx * nx + aqy * ny + aqz * nz
    permanent = _abs(aqx) * px + _abs(aqy) * py + _abs(aqz) * pz
    return det, permanent


def plane_side_terms_into(
    nx: float, ny: float, nz: float, px: float, py: float, pz: float, ax: float, ay: float, az: float,
    qx: NDArray[np.float64], qy: NDArray[np.float64], qz: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """:func:`plane_side_terms` over float64 arrays, computed in the arrays ``qx``, ``qy``, ``qz`` (overwritten).

    The same IEEE operations on the same operands in the same order — only the
    buffers differ (an operation's result written over an operand it no longer
    needs) — so the results are bitwise those of :func:`plane_side_terms` and
    its filter constant applies unchanged (``tests/test_filter.py`` compares
    the two bit for bit).  Returns ``(det, permanent)``; ``permanent`` is
    ``qx``'s buffer.  Five arrays' worth of memory traffic fewer than the
    expression form (no temporaries), for the bulldozer's long conflict lists.  O(len(qx)).
    """
    np.subtract(ax, qx, out=qx)  # aqx = ax - qx
    np.subtract(ay, qy, out=qy)  # aqy = ay - qy
    np.subtract(az, qz, out=qz)  # aqz = az - qz
    det = qx * nx
    t = qy * ny
    det += t  # aqx * nx + aqy * ny
    np.multiply(qz, nz, out=t)
    det += t  # ... + aqz * nz
    np.abs(qx, out=qx)
    qx *= px  # abs(aqx) * px
    np.abs(qy, out=qy)
    qy *= py
    qx += qy  # ... + abs(aqy) * py
    np.abs(qz, out=qz)
    qz *= pz
    qx += qz  # ... + abs(aqz) * pz
    return det, qx


def plane_side_det(nx: T, ny: T, nz: T, ax: T, ay: T, az: T, qx: T, qy: T, qz: T) -> T:
    """The determinant of :func:`plane_side_terms` alone, in one expression: the same operations on the
    same operands in the same order (``ax - qx``, its product with ``nx``, …), so bitwise the same value.

    For the semi-static stage of a plane-side test (:func:`plane_side_box_threshold`),
    which compares this determinant with a threshold shared by all query points
    and computes a point's own permanent only when that does not decide.  O(1).
    """
    det = (ax - qx) * nx + (ay - qy) * ny + (az - qz) * nz
    return det


def plane_side_det_into(
    nx: float | NDArray[np.float64], ny: float | NDArray[np.float64], nz: float | NDArray[np.float64],
    ax: float | NDArray[np.float64], ay: float | NDArray[np.float64], az: float | NDArray[np.float64],
    qx: NDArray[np.float64], qy: NDArray[np.float64], qz: NDArray[np.float64],
) -> NDArray[np.float64]:
    """:func:`plane_side_det` over float64 arrays, computed in ``qx``, ``qy``, ``qz`` (overwritten; ``qx`` returned).

    Bitwise the determinant of :func:`plane_side_terms` and :func:`plane_side_terms_into`:
    the same operations on the same operands in the same order.  The plane's numbers are floats
    or 0-d float64 arrays of the same values (numpy converts a float operand anew at each of
    the eight calls; the kernel passes 0-d arrays).  O(len(qx)).
    """
    np.subtract(ax, qx, out=qx)  # aqx = ax - qx
    np.subtract(ay, qy, out=qy)  # aqy = ay - qy
    np.subtract(az, qz, out=qz)  # aqz = az - qz
    qx *= nx  # aqx * nx
    qy *= ny
    qx += qy  # ... + aqy * ny
    qz *= nz
    qx += qz  # ... + aqz * nz
    return qx


def orient3d_box_threshold(dx: float, dy: float, dz: float) -> float:
    """A threshold at least the filter threshold of :func:`orient3d_terms` for any four points of a box.

    ``dx, dy, dz`` are the box's sides as computed, ``fl(hi - lo)`` per axis.
    Every computed difference of two coordinates in the box is bounded by the
    side: ``a_x - d_x`` lies in ``[lo - hi, hi - lo]`` and IEEE rounding is
    monotone (``x <= y`` implies ``fl(x) <= fl(y)``), so ``|fl(a_x - d_x)| <=
    fl(hi - lo)``.  The result is ``fl(ERRBOUND_ORIENT3D · permanent)`` with
    the permanent's expression evaluated on the sides in place of the
    differences' absolute values.  All factors are nonnegative and each
    rounded operation is monotone in its operands, so each operation of a
    test's permanent, and then the threshold product, is bounded by the same
    operation here: a test's own computed threshold never exceeds this one.
    Hence ``|det| >`` this threshold implies ``|det| >`` the test's own, and the
    proved filter's conclusion holds — no new error analysis is needed;
    ``tests/test_predicates_kernel.py`` checks the inequality on adversarial
    floats.  One constant per point set: a *semi-static* filter (Shewchuk's
    static filter, with the box of the data; Devillers and Pion, "Efficient
    exact geometric predicates for Delaunay triangulations", 2003).  A test
    it leaves undecided goes on to its own threshold, then to exact
    arithmetic.  Overflow gives ``inf`` and NaN gives NaN, which no comparison
    accepts.  O(1).
    """
    dxdy = dx * dy
    sum2 = dxdy + dxdy  # bounds |bdx·cdy| + |cdx·bdy|, and each of the three such sums
    permanent = sum2 * dz + sum2 * dz + sum2 * dz
    return ERRBOUND_ORIENT3D * permanent


def plane_side_box_threshold(dx: float, dy: float, dz: float) -> float:
    """A threshold at least the filter threshold of :func:`plane_side_terms` (after :func:`plane_terms`)
    for any plane through three points of a box and any query point in it.

    As :func:`orient3d_box_threshold`, for the prepared-plane form: each
    difference is bounded by the box's side, so the plane's permanents by
    ``fl(dy·dz + dz·dy)`` and so on, and the point's permanent by the same
    expression on those bounds.  O(1).
    """
    px = dy * dz + dz * dy
    py = dz * dx + dx * dz
    pz = dx * dy + dy * dx
    return ERRBOUND_PLANE_SIDE * (dx * px + dy * py + dz * pz)


def orient2d_box_threshold(dx: float, dy: float) -> float:
    """A threshold at least the filter threshold of :func:`orient2d_terms` for any three points of a box.

    As :func:`orient3d_box_threshold`: ``dx, dy`` are the box's sides as
    computed, each computed difference is bounded by its side (rounding is
    monotone), so ``|detleft|`` and ``|detright|`` by ``fl(dx · dy)``, the
    permanent by their sum, and the threshold by ``fl(ERRBOUND_ORIENT2D ·
    permanent)`` of those bounds.  O(1).
    """
    dxdy = dx * dy
    return ERRBOUND_ORIENT2D * (dxdy + dxdy)


def incircle_box_threshold(dx: float, dy: float) -> float:
    """A threshold at least the filter threshold of :func:`incircle_terms` for any four points of a box.

    As :func:`orient3d_box_threshold`: each product of two differences is bounded
    by ``fl(dx · dy)`` (or, for the lifts, ``fl(dx · dx)`` and ``fl(dy · dy)``),
    so each pair sum by ``fl(dxdy + dxdy)``, each lift by ``fl(dx·dx + dy·dy)``,
    and the permanent — evaluated in the same order as :func:`incircle_terms`'
    — by the same expression on those bounds; every operation is monotone in
    nonnegative operands.  O(1).
    """
    dxdy = dx * dy
    sum2 = dxdy + dxdy
    lift = dx * dx + dy * dy
    permanent = sum2 * lift + sum2 * lift + sum2 * lift
    return ERRBOUND_INCIRCLE * permanent


def orient3d_plane_terms(
    ax: T, ay: T, az: T, bx: T, by: T, bz: T, cx: T, cy: T, cz: T, qx: T, qy: T, qz: T
) -> tuple[T, T]:
    """``(det, permanent)`` of orient3d through the prepared plane: :func:`plane_side_terms` ∘ :func:`plane_terms`.

    The same determinant as :func:`orient3d_terms`, expanded along the query
    point's row instead of translated to it; this composition is what the
    proof analyses.  O(1).
    """
    nx, ny, nz, px, py, pz = plane_terms(ax, ay, az, bx, by, bz, cx, cy, cz)
    return plane_side_terms(nx, ny, nz, px, py, pz, ax, ay, az, qx, qy, qz)


def incircle_terms(ax: T, ay: T, bx: T, by: T, cx: T, cy: T, dx: T, dy: T) -> tuple[T, T]:
    """``(det, permanent)`` of incircle in floating point, translated to ``d``.

    ``det`` is the 3×3 determinant with rows ``(p - d, |p - d|²)`` for ``p = a, b, c``,
    which equals the 4×4 determinant with rows ``(x, y, x² + y², 1)`` — the
    orient3d determinant of the lifted points: positive when ``d`` is inside the
    circle through ``a, b, c`` (counterclockwise).  The lifts are sums of squares,
    nonnegative as computed, so they enter the permanent as they are.  O(1).
    """
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
    permanent = (
        (_abs(bdxcdy) + _abs(cdxbdy)) * alift
        + (_abs(cdxady) + _abs(adxcdy)) * blift
        + (_abs(adxbdy) + _abs(bdxady)) * clift
    )
    return det, permanent


@dataclass(frozen=True, slots=True)
class FilterScaling:
    """How the filters' copy of the points is scaled: ``copy = points · 2^shift`` (exact).

    ``uniform`` is True when every coordinate's scaled grain is at least
    :data:`GRAIN_MIN`, so no test needs a grain check; otherwise each test
    checks ``min(grain of its points) >= GRAIN_MIN`` and leaves the others to
    exact arithmetic.
    """

    shift: int
    uniform: bool


def choose_scaling(low: NDArray[np.int64], high: NDArray[np.int64]) -> FilterScaling:
    """The power-of-two scale for the filters' copy of the points.

    ``low`` and ``high`` hold, for the *nonzero* coordinates only, the grain
    (``x = odd · 2^low``) and the magnitude exponent (``2^(high-1) <= |x| <
    2^high``).  The scale wants every grain ``>= GRAIN_MIN`` (validity) and
    every magnitude ``<= TOP_MAX`` (no overflow in degree-4 expressions).  When
    both are possible the data is centred in the allowed window; when the
    dynamic range is too wide for both, overflow is avoided and the points with
    too fine a grain are left to per-test checks (the bulk of typical data is
    then still filtered; only tests touching the extreme points go exact).
    O(n) on the arrays.
    """
    if low.size == 0:
        return FilterScaling(0, True)
    g = int(low.min())
    h = int(high.max())
    lo = GRAIN_MIN - g  # the smallest shift giving every grain >= GRAIN_MIN
    hi = TOP_MAX - h  # the largest shift keeping every magnitude <= TOP_MAX
    if lo <= hi:
        centre = -((h + g) // 2)
        return FilterScaling(min(max(centre, lo), hi), True)
    return FilterScaling(hi, False)
