"""Barycentric transforms and the paraboloid lifting of triangles, as scipy.spatial.Delaunay gives them.

These are *measurements* of a triangulation in float64, not decisions: the
triangulation itself is decided exactly (paper §5, :mod:`persistri.impl.geometry.predicates2`).
They exist so that code written against :class:`scipy.spatial.Delaunay`
(barycentric interpolation through ``transform``, the lifted hyperplanes
``equations`` / ``plane_distance``) runs unchanged on :class:`persistri.Delaunay`.

* :func:`barycentric_transforms` — for each triangle ``(a, b, c)`` the matrix
  ``T⁻¹`` with ``T = [a − c, b − c]`` (columns) and the vector ``r = c``, so that the
  barycentric coordinates of ``x`` are ``T⁻¹ (x − r)`` for ``a`` and ``b`` and one
  minus their sum for ``c``.  Every entry is within a relative 2⁻⁴⁰ of the exact
  value of the entry for the float64 input: computed in float64 where a forward
  error bound guarantees that, and in exact rational arithmetic (rounded once)
  where it does not: a thin triangle gets its true transform, never the NaN that
  scipy documents for nearly degenerate simplices.
* :func:`paraboloid_lift` / :func:`lifted_equations` — the lift
  ``x ↦ (x, scale·|x|² + shift)`` with scipy's constants (Qhull's ``Qbb`` under
  ``Qz``, scipy's default options: the squared norms spread over ``[0, M]``, ``M``
  the largest absolute coordinate, with room for Qhull's point at infinity at
  ``1.1·max|x|²``), so that ``lift_points``, ``equations`` and ``plane_distance``
  are scipy's numbers up to rounding, and each
  triangle's plane through its lifted vertices as a unit normal pointing down
  (out of the lower hull) and an offset.  Plain float64, like scipy's: a point lifted
  below a triangle's plane (inside its circumcircle) has a positive distance, up to
  rounding; exact answers to that question are :func:`persistri.impl.geometry.predicates2`'s
  ``incircle``.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
from numpy.typing import NDArray

__all__ = ["barycentric_transforms", "paraboloid_scaling", "paraboloid_lift", "lifted_equations"]

FloatArray = NDArray[np.float64]
IndexArray = NDArray[np.integer]

_FILTER = 2.0**-9
"""A float64 determinant is kept when ``|det| ≥ 2⁻⁹ · (|d₀₀d₁₁| + |d₀₁d₁₀|)``: its rounding error,
at most ``2ε`` times that sum for exact differences, is then below ``2⁻⁴³|det|``, and each entry of
``T⁻¹`` (an exact difference over ``det``, one more rounding) is within ``2⁻⁴⁰`` relative."""

_TINY = 2.0**-1000
"""Below this a float64 may be subnormal (or have rounded to one): the relative bounds no longer hold."""


def _exact_difference(a: FloatArray, b: FloatArray) -> tuple[FloatArray, NDArray[np.bool_]]:
    """``a − b`` in float64 and whether it is exact, elementwise (Knuth's TwoSum error term is zero). O(n)."""
    with np.errstate(over="ignore", invalid="ignore"):
        s = a - b
        bb = s - a
        err = (a - (s - bb)) + (-b - bb)
    return s, np.isfinite(s) & (err == 0.0)


def _exact_transform(a: FloatArray, b: FloatArray, c: FloatArray) -> FloatArray:
    """The 2 × 2 inverse of ``[a − c, b − c]`` in rationals, each entry rounded once to float64 (±inf past its range)."""
    ax, ay, bx, by, cx, cy = (Fraction(float(v)) for v in (*a, *b, *c))
    t00, t01, t10, t11 = ax - cx, bx - cx, ay - cy, by - cy
    det = t00 * t11 - t01 * t10
    out = np.empty((2, 2))
    for (i, j), num in zip(((0, 0), (0, 1), (1, 0), (1, 1)), (t11, -t01, -t10, t00)):
        q = num / det
        try:
            out[i, j] = float(q)
        except OverflowError:
            out[i, j] = np.inf if q > 0 else -np.inf
    return out


def barycentric_transforms(points: FloatArray, triangles: IndexArray) -> FloatArray:
    """``(m, 3, 2)``: scipy's ``Delaunay.transform`` for nondegenerate ``triangles`` of ``points`` (module docstring).

    ``out[i, :2, :2]`` is ``T⁻¹`` and ``out[i, 2]`` is ``r`` (the third vertex).
    Each entry within a relative 2⁻⁴⁰ of its exact value; the triangles must have
    nonzero area (every triangle of a triangulation has, exactly). O(m), plus
    O(1) rational arithmetic per triangle too thin for the float bound.
    """
    a = points[triangles[:, 0]]
    b = points[triangles[:, 1]]
    c = points[triangles[:, 2]]
    t00, e00 = _exact_difference(a[:, 0], c[:, 0])
    t01, e01 = _exact_difference(b[:, 0], c[:, 0])
    t10, e10 = _exact_difference(a[:, 1], c[:, 1])
    t11, e11 = _exact_difference(b[:, 1], c[:, 1])
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        p, q = t00 * t11, t01 * t10
        det = p - q
        size = np.abs(p) + np.abs(q)
        good = e00 & e01 & e10 & e11 & np.isfinite(size) & (np.abs(det) >= _FILTER * size) & (det != 0.0)
        out = np.empty((triangles.shape[0], 3, 2))
        out[:, 0, 0] = t11 / det
        out[:, 0, 1] = -t01 / det
        out[:, 1, 0] = -t10 / det
        out[:, 1, 1] = t00 / det
        # The bounds are relative: products, determinants and entries must be normal floats (or exact zeros).
        entries = out[:, :2, :2].reshape(-1, 4)
        numerators = np.stack([t11, t01, t10, t00], axis=1)
        normal = (np.abs(entries) >= _TINY) | ((entries == 0.0) & (numerators == 0.0))
        good &= (size >= _TINY) & np.isfinite(entries).all(axis=1) & normal.all(axis=1)
    out[:, 2, :] = c
    for i in np.flatnonzero(~good).tolist():
        out[i, :2, :2] = _exact_transform(a[i], b[i], c[i])
    return out


def paraboloid_scaling(points: FloatArray) -> tuple[float, float]:
    """``(scale, shift)`` of the lifting, as scipy's ``paraboloid_scale`` and ``paraboloid_shift``.

    Qhull's ``Qbb`` with ``Qz`` (scipy's default options for 2D points): with
    ``lo``/``hi`` the least/greatest ``|x|²`` over the rows of ``points`` and ``M`` their
    largest absolute coordinate, ``scale = M / (1.1·hi − lo)`` (1.1·hi is the height of
    Qhull's point at infinity) and ``shift = −lo·scale``, so ``scale·|x|² + shift``
    spans ``[0, M·(hi − lo)/(1.1·hi − lo)]`` over the points.  ``(1.0, 0.0)`` when the
    norms overflow or every row is the origin. O(n).
    """
    with np.errstate(over="ignore", invalid="ignore"):
        sq = (points * points).sum(axis=1)
        low, high = float(sq.min()), float(sq.max())
        reach = float(np.abs(points).max())
        room = 1.1 * high - low
        if not (np.isfinite(room) and np.isfinite(reach)) or room <= 0.0 or reach == 0.0:
            return 1.0, 0.0
        scale = reach / room
        return scale, -low * scale


def paraboloid_lift(x: FloatArray, scale: float, shift: float) -> FloatArray:
    """``(..., 3)``: ``x`` (shape ``(..., 2)``) with ``scale·|x|² + shift`` appended, in float64. O(size)."""
    z = np.empty(x.shape[:-1] + (3,))
    z[..., :2] = x
    z[..., 2] = (x * x).sum(axis=-1) * scale + shift
    return z


def lifted_equations(points: FloatArray, triangles: IndexArray, scale: float, shift: float) -> FloatArray:
    """``(m, 4)``: each triangle's plane through its lifted vertices, ``[unit normal, offset]``, normal pointing down.

    ``normal · lift(x) + offset`` is the signed distance of ``lift(x)`` from the
    plane, positive below it (inside the circumcircle, in exact arithmetic). Float64,
    like scipy's.  Each triangle's two edge vectors are first scaled by a power of
    two near their size (the direction is unchanged), so that the cross product and
    its norm neither underflow nor overflow: tiny inputs (coordinates of 1e-80 and
    below, where the plain cross product's squares underflow to 0 and the normal
    came out NaN) get their planes as scipy's do. O(m).
    """
    lifted = paraboloid_lift(points, scale, shift)
    la, lb, lc = (lifted[triangles[:, k]] for k in range(3))
    u, v = lb - la, lc - la
    size = np.maximum(np.abs(u).max(axis=1), np.abs(v).max(axis=1))
    exponent = np.frexp(np.where(size > 0, size, 1.0))[1][:, None]
    normal = np.cross(np.ldexp(u, -exponent), np.ldexp(v, -exponent))
    # And the cross product by a power of two near its size: a plane steep beyond 2^500 (a lifting far out without
    # Qbb) has a normal whose squares underflow, whose norm would be 0.
    largest = np.abs(normal).max(axis=1)
    normal = np.ldexp(normal, -np.frexp(np.where(largest > 0, largest, 1.0))[1][:, None])
    # Counterclockwise triangles give an upward cross product: flip it out of the lower hull.
    normal = -normal / np.linalg.norm(normal, axis=1, keepdims=True)
    offset = -(normal * la).sum(axis=1)
    out: FloatArray = np.concatenate([normal, offset[:, None]], axis=1)
    return out
