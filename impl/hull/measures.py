"""The measures of a finished hull: facet planes, surface area, enclosed volume.

The hull itself is decided exactly (paper §3; :mod:`persistri.impl.hull.api`);
what is measured from it here are real numbers that a double cannot always hold,
so each is computed as close to the exact value as a double allows, and says how
close:

* :func:`facet_equations` — each triangle's outward unit normal ``n`` and offset
  ``d``, scipy.spatial's convention (``n·x + d <= 0`` inside).  The cross
  product of two edge vectors is computed in floating point on power-of-two
  scaled copies (no overflow, no underflow that matters), with a bound on its
  rounding error; a facet whose bound exceeds ``2^-46`` of the vector's length
  (a needle or sliver triangle, where the subtraction cancels) is computed again
  from the exact rational coordinates.  Every unit normal is therefore within
  about ``2^-44`` of the exact one, component by component.  The offset is
  ``-n·a`` at the first vertex, one float dot product (its error is a few units
  in the last place of ``|a|``, as for any float plane).
* :func:`surface_area` — half the lengths of the same cross products, summed
  with :func:`math.fsum`.
* :func:`enclosed_volume` — exact: ``Σ a·(b × c) / 6`` over the outward
  triangles on the input's exact integer coordinates
  (:class:`~persistri.impl.geometry.exact.IntegerScale`), rounded once to the
  nearest double.

>>> import numpy as np
>>> cube = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float) * 3
>>> from persistri.impl.hull.api import convex_hull
>>> tri = convex_hull(cube).simplices
>>> enclosed_volume(cube, tri), surface_area(cube, tri)
(27.0, 54.0)
>>> eq = facet_equations(cube, tri)
>>> bool(np.all(eq[:, :3] @ cube.T + eq[:, 3:] <= 0))      # every point on or inside every plane
True
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.geometry.exact import IntegerScale, grain_span
from persistri.impl.geometry.points import as_points

__all__ = ["facet_normals", "facet_equations", "equations_of", "surface_area", "half_sum", "enclosed_volume"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]

_U: Final[float] = 2.0**-53
"""The unit roundoff of float64."""

_TOLERANCE: Final[float] = 2.0**-46
"""A facet's float cross product is kept when its error bound is at most this fraction of its length."""

_TINY: Final[float] = 2.0**-1000
"""Covers every absolute (underflow) error of the scaled computation; negligible beside any length kept."""


def _checked(points: ArrayLike, simplices: ArrayLike) -> tuple[FloatArray, IntArray]:
    pts = as_points(points, 3)
    tri = np.asarray(simplices)
    if tri.ndim != 2 or tri.shape[1] != 3 or (tri.size and tri.dtype.kind not in "iu"):
        raise ValueError(f"simplices must be an (m, 3) integer array, got shape {tri.shape} of {tri.dtype}")
    if tri.size and (int(tri.min()) < 0 or int(tri.max()) >= pts.shape[0]):
        raise ValueError(f"simplices refer to points outside 0..{pts.shape[0] - 1}")
    return pts, tri.astype(np.intp, copy=False)


def _exact_normal(a: FloatArray, b: FloatArray, c: FloatArray) -> tuple[tuple[float, float, float], float]:
    """The unit normal of ``(a, b, c)`` from the exact cross product, and the cross product's length (a double).

    Every double is an integer over a power of two, so the coordinates times their
    largest denominator are integers and the cross product is exact; it is then
    rounded to 64 leading bits and normalised in floating point.  A zero-area
    triangle has no normal: NaN, length 0.
    """
    ratios = [float(x).as_integer_ratio() for x in (*a, *b, *c)]
    den = max(d for _, d in ratios)
    ax, ay, az, bx, by, bz, cx, cy, cz = (n * (den // d) for n, d in ratios)
    ux, uy, uz = bx - ax, by - ay, bz - az
    vx, vy, vz = cx - ax, cy - ay, cz - az
    n = (uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx)
    big = max(abs(v) for v in n)
    if big == 0:
        return (math.nan, math.nan, math.nan), 0.0
    shift = max(big.bit_length() - 64, 0)
    fx, fy, fz = (float(v >> shift) for v in n)
    norm = math.hypot(fx, fy, fz)
    # |n| = norm · 2^shift / den², den a power of two.
    try:
        length = math.ldexp(norm, shift - 2 * (den.bit_length() - 1))
    except OverflowError:
        length = math.inf
    return (fx / norm, fy / norm, fz / norm), length


def facet_normals(points: ArrayLike, simplices: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """``(normals, lengths)``: each triangle's unit normal by the right-hand rule, and ``|(b − a) × (c − a)|``.

    The normals are within about ``2^-44`` of the exact ones (module docstring);
    a zero-area triangle gets NaN and length 0.  A length beyond the largest
    double is ``inf``.  O(m), vectorised; exact arithmetic only for the facets
    the error bound rejects.
    """
    pts, tri = _checked(points, simplices)
    m = tri.shape[0]
    a, b, c = (np.take(pts, tri[:, k], axis=0) for k in range(3))
    with np.errstate(all="ignore"):
        d1 = b - a
        d2 = c - a
        # Scale each edge vector by a power of two (exact) to a largest magnitude in [0.5, 1).
        _, e1 = np.frexp(np.abs(d1).max(axis=1))
        _, e2 = np.frexp(np.abs(d2).max(axis=1))
        s1 = np.ldexp(d1, -e1[:, None])
        s2 = np.ldexp(d2, -e2[:, None])
        y1, z1, x1 = s1[:, 1], s1[:, 2], s1[:, 0]
        x2, y2, z2 = s2[:, 0], s2[:, 1], s2[:, 2]
        cross = np.stack([y1 * z2 - z1 * y2, z1 * x2 - x1 * z2, x1 * y2 - y1 * x2], axis=1)
        perm = np.stack(
            [np.abs(y1 * z2) + np.abs(z1 * y2), np.abs(z1 * x2) + np.abs(x1 * z2), np.abs(x1 * y2) + np.abs(y1 * x2)],
            axis=1,
        )
        norm = np.sqrt(np.einsum("ij,ij->i", cross, cross))
        bound = 4 * _U * np.sqrt(np.einsum("ij,ij->i", perm, perm)) + 2 * _U * norm + _TINY
        ok = np.isfinite(d1).all(axis=1) & np.isfinite(d2).all(axis=1) & (bound <= _TOLERANCE * norm)
        normals = np.full((m, 3), np.nan)
        normals[ok] = cross[ok] / norm[ok, None]
        lengths = np.zeros(m)
        lengths[ok] = np.ldexp(norm[ok], e1[ok] + e2[ok])
    for i in np.flatnonzero(~ok).tolist():
        unit, length = _exact_normal(a[i], b[i], c[i])
        normals[i] = unit
        lengths[i] = length
    return normals, lengths


def facet_equations(points: ArrayLike, simplices: ArrayLike) -> FloatArray:
    """``(m, 4)``: ``[n_x, n_y, n_z, d]`` per triangle, ``n`` the outward unit normal and ``d = −n·a``.

    scipy.spatial's ``equations``: for an outward hull, ``n·x + d <= 0`` for every
    point inside (up to the rounding of ``d``; module docstring).  O(m).
    """
    pts, tri = _checked(points, simplices)
    normals, _ = facet_normals(pts, tri)
    return equations_of(pts, tri, normals)


def equations_of(points: FloatArray, simplices: IntArray, normals: FloatArray) -> FloatArray:
    """:func:`facet_equations` from normals already computed by :func:`facet_normals` (validated arrays). O(m)."""
    out = np.empty((simplices.shape[0], 4))
    out[:, :3] = normals
    with np.errstate(all="ignore"):
        out[:, 3] = -np.einsum("ij,ij->i", normals, np.take(points, simplices[:, 0], axis=0))
    return out


def surface_area(points: ArrayLike, simplices: ArrayLike) -> float:
    """The total area of the triangles: half their cross products' lengths, summed exactly rounded. O(m)."""
    _, lengths = facet_normals(points, simplices)
    return half_sum(lengths)


def half_sum(lengths: FloatArray) -> float:
    """Half the sum of ``lengths`` (non-negative), exactly rounded: ``inf`` when it exceeds the largest double.

    :func:`math.fsum` raises ``OverflowError`` when a partial sum of finite terms
    overflows (a hull of coordinates near 1e154); the halves are summed then, and
    a total beyond the largest double is ``inf``, as :func:`enclosed_volume`'s. O(m).
    """
    try:
        return math.fsum(lengths.tolist()) / 2
    except OverflowError:
        try:
            return math.fsum((lengths / 2).tolist())
        except OverflowError:
            return math.inf


def enclosed_volume(points: ArrayLike, simplices: ArrayLike) -> float:
    """The volume bounded by the outward triangles ``simplices``, exactly, rounded once to a double.

    ``Σ a·(b × c) / 6`` over the triangles (the divergence theorem) on exact
    integer coordinates; for a closed outward surface it is the enclosed volume.
    O(m) big-integer operations on object arrays: some 7 µs per triangle (1.4 s for a
    200,000-triangle hull, whose construction takes twenty times longer).
    """
    pts, tri = _checked(points, simplices)
    if tri.shape[0] == 0:
        return 0.0
    used, local = np.unique(tri, return_inverse=True)
    coords = np.take(pts, used, axis=0)
    span = grain_span(coords)
    if span is None:
        return 0.0
    ints = IntegerScale(span[0]).to_ints(coords)  # coords · 2^-grain, exact
    a, b, c = (ints[local.reshape(tri.shape)[:, k]] for k in range(3))
    det = (
        a[:, 0] * (b[:, 1] * c[:, 2] - b[:, 2] * c[:, 1])
        + a[:, 1] * (b[:, 2] * c[:, 0] - b[:, 0] * c[:, 2])
        + a[:, 2] * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0])
    )
    six_volume = int(det.sum())
    grain = 3 * span[0]  # the volume's scale: (2^grain)^3
    exact = Fraction(six_volume << grain, 6) if grain >= 0 else Fraction(six_volume, 6 << -grain)
    try:
        return float(exact)
    except OverflowError:
        return math.inf if exact > 0 else -math.inf
