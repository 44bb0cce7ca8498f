"""The error measure of greedy insertion (paper §5): vertical distances of grid samples to triangles' planes.

A *measurement*, not a predicate (:mod:`persistri.impl.terrain.greedy` says why
floats suffice): the vertical distance ``|z − plane(x, y)|`` in float64,
vectorised with numpy.  :func:`plane_errors` measures samples grouped by
triangle (a level of detail, the first triangles); :func:`fan_errors` and
:func:`fan_plane_errors` the fan of one insertion, with the same IEEE
operations in the same order, so that the queue's errors and a mesh's reported
errors agree bit for bit.  The plane of a triangle is written around its
*apex*, the vertex whose insertion made it (:func:`apex_first`, :func:`ranks`).
Grid convention: sample ``i`` of a grid with ``cols`` columns is the point
``(x, y) = (i mod cols, i div cols)`` (:func:`grid_xy`, :func:`grid_points`).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "apex_first", "ranks", "grid_points", "grid_xy", "plane_errors", "fan_errors", "fan_plane_errors", "level_errors",
    "level_error_blocks", "Coordinates", "CHUNK",
]

IntArray = NDArray[np.intp]
Samples = NDArray[np.signedinteger[Any]]
"""Sample indices of any signed integer dtype (a triangulator's sample lists are ``int32`` or ``intp``)."""
FloatArray = NDArray[np.float64]


def apex_first(tri: IntArray, rank: IntArray) -> IntArray:
    """Each triangle rotated (orientation kept) to start at its *apex*, the vertex of largest rank.

    ``rank`` is ``(k, 3)``: the insertion order of each vertex of ``tri`` (:func:`ranks`); the apex is the
    vertex whose insertion made the triangle (every new triangle is in the fan of the new point).  O(m).
    """
    t = np.asarray(tri, dtype=np.intp).reshape(-1, 3)
    k = np.argmax(np.asarray(rank).reshape(-1, 3), axis=1)
    out: IntArray = np.take_along_axis(t, (k[:, None] + np.arange(3)[None, :]) % 3, axis=1)
    return out


def ranks(labels: IntArray, inserted: IntArray) -> IntArray:
    """The position in ``inserted`` (the insertion order) of each of ``labels`` (all of them inserted).

    By binary search over the sorted insertion order: O((k + len(labels)) log k), no array of the grid's size.
    """
    order = np.argsort(inserted, kind="stable")
    out: IntArray = order[np.searchsorted(inserted[order], labels)]
    return out


def grid_points(shape: tuple[int, int]) -> FloatArray:
    """The ``(rows·cols, 2)`` array of grid coordinates ``(x, y) = (col, row)`` in row-major order (float64)."""
    rows, cols = shape
    xy = np.empty((rows * cols, 2), dtype=np.float64)
    xy[:, 0] = np.tile(np.arange(cols, dtype=np.float64), rows)
    xy[:, 1] = np.repeat(np.arange(rows, dtype=np.float64), cols)
    return xy


def grid_xy(q: Samples, cols: int) -> tuple[FloatArray, FloatArray]:
    """The grid coordinates ``(x, y) = (q mod cols, q div cols)`` of samples ``q``, as float64 (exact). O(len(q))."""
    y, x = np.divmod(q, cols)
    return x.astype(np.float64), y.astype(np.float64)


CHUNK: Final = 1 << 16
"""Samples per block where a whole grid's samples are measured at once (the first triangles, a level's
errors): the temporaries stay about half a megabyte each whatever the grid (2^18 made a level's errors
take 25 MB of temporaries on a 2,048² grid, measured; smaller blocks cost nothing measurable)."""


def plane_errors(cols: int, z: FloatArray, tri: IntArray, counts: IntArray, samples: Samples) -> FloatArray:
    """Vertical errors ``|z[s] − plane(t)(x[s], y[s])|`` of samples grouped by triangle (float64).

    Points are samples of a grid with ``cols`` columns (``x = s mod cols``,
    ``y = s div cols``).  ``tri`` is ``(k, 3)`` vertex indices (nonzero area); the
    first ``counts[0]`` entries of ``samples`` lie in ``tri[0]``, the next
    ``counts[1]`` in ``tri[1]``, and so on.  Each row must start at the
    triangle's apex (:func:`apex_first`), and the plane of ``(a, b, c)`` is
    written around ``a``: ``z_a + g_x (x − x_a) + g_y (y − y_a)``, its gradient
    ``g`` by Cramer's rule, computed once per triangle.  :func:`fan_errors`
    performs the same operations in the same order for the fan of one
    insertion, so the queue's errors and a mesh's reported errors agree bit for
    bit (``check=True`` asserts it).  O(k + len(samples)), vectorised, in blocks
    of :data:`CHUNK` samples.
    """
    x, y = grid_xy(tri.ravel(), cols)
    x, y = x.reshape(-1, 3), y.reshape(-1, 3)
    zt = z[tri]
    xa, ya, za = x[:, 0], y[:, 0], zt[:, 0]
    dx1, dy1, dz1 = x[:, 1] - xa, y[:, 1] - ya, zt[:, 1] - za
    dx2, dy2, dz2 = x[:, 2] - xa, y[:, 2] - ya, zt[:, 2] - za
    det = dx1 * dy2 - dx2 * dy1
    gx = (dz1 * dy2 - dz2 * dy1) / det
    gy = (dx1 * dz2 - dx2 * dz1) / det
    m = samples.size
    err: FloatArray = np.empty(m, dtype=np.float64)
    ends = np.cumsum(counts)
    for lo in range(0, m, CHUNK):
        hi = min(m, lo + CHUNK)
        s = samples[lo:hi]
        xs, ys = grid_xy(s, cols)
        rep = _owners(ends, counts, lo, hi) if tri.shape[0] > 1 else np.zeros(hi - lo, dtype=np.intp)
        np.abs(z[s] - (za[rep] + gx[rep] * (xs - xa[rep]) + gy[rep] * (ys - ya[rep])), out=err[lo:hi])
    return err


def _owners(ends: IntArray, counts: IntArray, lo: int, hi: int) -> IntArray:
    """The triangle of each of the samples ``lo … hi − 1`` (``hi > lo``), for triangles holding ``counts`` samples
    one after the other (``ends`` their running sums): ``searchsorted(ends, arange(lo, hi), side="right")``,
    the same integers, made by two binary searches and one ``repeat`` of the triangles the samples span
    (a binary search per sample cost a fifth of a 2,048² mesh's error measurement).  O(hi − lo + triangles)."""
    first = int(np.searchsorted(ends, lo, side="right"))
    last = int(np.searchsorted(ends, hi - 1, side="right"))
    held = np.array(counts[first : last + 1], dtype=np.intp)
    if last == first:
        held[0] = hi - lo
    else:
        held[0] = int(ends[first]) - lo
        held[-1] = hi - int(ends[last - 1])
    out: IntArray = np.repeat(np.arange(first, last + 1, dtype=np.intp), held)
    return out


def fan_errors(cols: int, z: FloatArray, p: int, ring: IntArray, fan_index: IntArray, samples: Samples) -> FloatArray:
    """:func:`plane_errors` for the fan of one insertion: triangles ``(p, ring[i], ring[i+1])``, apex ``p``.

    ``ring`` holds the ``k + 1`` boundary vertices in fan order (the last repeats
    the first when the fan closes around ``p``); ``samples[j]`` lies in fan
    triangle ``fan_index[j]``; the grid has ``cols`` columns.  The fan has a
    handful of triangles, so their gradients are computed on Python floats — the
    same IEEE operations in the same order as :func:`plane_errors`, so the same
    floats — and only the per-sample work is vectorised (numpy calls on small
    arrays cost more than the arithmetic).  O(k + len(samples)).
    """
    xy = [(float(v % cols), float(v // cols), z.item(v)) for v in (int(p), *map(int, ring))]
    (xp, yp, zp), (x1, y1, z1) = xy[0], xy[1]
    gxs: list[float] = []
    gys: list[float] = []
    for x2, y2, z2 in xy[2:]:
        dx1, dy1, dz1 = x1 - xp, y1 - yp, z1 - zp
        dx2, dy2, dz2 = x2 - xp, y2 - yp, z2 - zp
        det = dx1 * dy2 - dx2 * dy1
        gxs.append((dz1 * dy2 - dz2 * dy1) / det)
        gys.append((dx1 * dz2 - dx2 * dz1) / det)
        x1, y1, z1 = x2, y2, z2
    return fan_plane_errors(lambda q: grid_xy(q, cols), z, xp, yp, zp, gxs, gys, fan_index, samples)


Coordinates = Callable[[Samples], tuple[NDArray[Any], NDArray[Any]]]
"""Samples to their ``(x, y)`` grid coordinates (:meth:`GridPredicates2.coordinates`, or :func:`grid_xy`)."""


def fan_plane_errors(
    coordinates: Coordinates,
    z: FloatArray,
    xp: float,
    yp: float,
    zp: float,
    gxs: list[float],
    gys: list[float],
    fan_index: IntArray | None,
    samples: Samples,
) -> FloatArray:
    """The per-sample half of :func:`fan_errors`: ``|z − (zp + gx (x − xp) + gy (y − yp))|`` by fan triangle.

    ``fan_index`` may be None for one triangle.  In blocks of :data:`CHUNK` samples (the first
    insertions move millions): O(len(samples)).
    """
    m = samples.size
    if m > CHUNK:
        err: FloatArray = np.empty(m, dtype=np.float64)
        for lo in range(0, m, CHUNK):
            hi = min(m, lo + CHUNK)
            part = None if fan_index is None else fan_index[lo:hi]
            err[lo:hi] = fan_plane_errors(coordinates, z, xp, yp, zp, gxs, gys, part, samples[lo:hi])
        return err
    xs, ys = coordinates(samples)
    if len(gxs) == 1:
        # One triangle: its gradient is a scalar (no gather).
        plane = xs - xp
        plane *= gxs[0]
        plane += zp
        slope = ys - yp
        slope *= gys[0]
    else:
        assert fan_index is not None, "several triangles need their samples' fan_index"
        plane = np.array(gxs)[fan_index]
        plane *= xs - xp
        plane += zp
        slope = np.array(gys)[fan_index]
        slope *= ys - yp
    plane += slope
    out: FloatArray = np.abs(z[samples] - plane)
    return out


def level_error_blocks(cols: int, z: FloatArray, apex: IntArray, counts: IntArray, lists: list[Samples]) -> Iterator[FloatArray]:
    """The errors of every listed sample (:func:`plane_errors`), in order, as consecutive blocks: triangles
    taken together until they hold at least :data:`CHUNK` samples, so that no list or error array of the
    whole grid's samples is made.

    A block ends at the first triangle that brings it to :data:`CHUNK` samples, and the last block is the
    rest if it holds any: found by binary search in the running sums of ``counts`` (one search a block;
    a Python step per triangle, reading ``counts[t]`` as a numpy scalar, took a quarter of reading the
    final Jacksboro mesh's errors).  O(total + k)."""
    k = len(lists)
    if not k:
        return
    ends = np.cumsum(counts)
    total = int(ends[-1])
    first = 0
    base = 0  # samples in the triangles before ``first``
    while base < total:
        if total - base >= CHUNK:
            # The first t with ends[t] >= base + CHUNK: the block is first … t.
            t = int(np.searchsorted(ends, base + CHUNK, side="left")) + 1
        else:
            t = k
        block = np.concatenate(lists[first:t]) if t - first > 1 else lists[first]
        yield plane_errors(cols, z, apex[first:t], counts[first:t], block)
        first, base = t, int(ends[t - 1])


def level_errors(cols: int, z: FloatArray, apex: IntArray, counts: IntArray, lists: list[Samples], total: int) -> FloatArray:
    """The errors of every listed sample (:func:`level_error_blocks`, ``total`` of them) as one array. O(total)."""
    err: FloatArray = np.empty(total, dtype=np.float64)
    pos = 0
    for block in level_error_blocks(cols, z, apex, counts, lists):
        err[pos : pos + block.size] = block
        pos += block.size
    return err
