"""Removing zero-area triangles from a finished hull by coplanar edge flips.

Simulation of Simplicity makes every input look like it is in general position,
so the bulldozer's hull is exact — but when three or more input points lie on
one hull *edge*, the perturbed hull may use the middle ones as vertices and
contain triangles ``(a, m, b)`` whose vertices are collinear: zero area in the
real geometry.  Such a sliver lies along the long edge ``(a, b)`` of its
neighbour ``(b, a, x)``, so flipping that edge — replacing the two triangles by
``(a, m, x)`` and ``(m, b, x)`` — covers exactly the same part of the surface
(``m`` is on the segment ``ab``, inside the neighbour's plane) with triangles of
positive area, keeps the orientation, and changes nothing else.

:func:`remove_slivers` repeats this on the final complex (as ``rem``/``add``
operations, so the result is one more persistent version) until no sliver is
left.  Each flip removes one zero-area triangle and, unless the neighbour's third
vertex is on the same line, adds none; the loop is bounded.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.geometry.predicates import Predicates3

__all__ = ["remove_slivers"]


def _middle(pts: Any, a: int, b: int, c: int) -> tuple[int, int, int] | None:
    """For collinear a, b, c: (start, middle, end) in the triangle's cyclic order, the middle between the others."""
    for s, m, e in ((a, b, c), (b, c, a), (c, a, b)):
        lo = np.minimum(pts[s], pts[e])
        hi = np.maximum(pts[s], pts[e])
        if bool(np.all(lo <= pts[m])) and bool(np.all(pts[m] <= hi)):
            return (s, m, e)
    return None


_U = 2.0**-53
_CCW_BOUND = (3.0 + 16.0 * _U) * _U
"""Shewchuk's bound for a 2D orientation determinant evaluated in doubles (error < bound × permanent)."""


def _maybe_collinear(pts: NDArray[np.float64], tri: NDArray[np.intp]) -> NDArray[np.bool_]:
    """False where triangle ``tri[k]`` is certainly not collinear (a float filter, proven bound); True = ask exactly.

    A triangle is collinear iff all three axis-parallel projections of it are
    degenerate; one projection whose filtered determinant is provably nonzero
    settles it.  Overflow or NaN leaves the answer to exact arithmetic.
    """
    # np.take copies whole rows: half the time of pts[tri[:, k]] at 500,000 triangles.
    a, b, c = (np.take(pts, tri[:, k], axis=0) for k in range(3))
    maybe = np.ones(tri.shape[0], dtype=bool)
    with np.errstate(all="ignore"):  # coordinates near ±1e308: the differences overflow, the filter then abstains
        u, v = b - a, c - a
        for i, j in ((0, 1), (1, 2), (2, 0)):
            left, right = u[:, i] * v[:, j], u[:, j] * v[:, i]
            det = left - right
            perm = np.abs(left) + np.abs(right)
            sure = np.isfinite(perm) & (np.abs(det) > _CCW_BOUND * perm)
            maybe &= ~sure
    return maybe


def remove_slivers(
    structure: TwoComplex[Any], c: Complex[Any], pred: Predicates3, triangles: NDArray[np.intp] | None = None
) -> tuple[Complex[Any], int]:
    """``c`` with every zero-area triangle flipped away; also the number of flips made.

    ``triangles`` — the faces of ``c`` as an (m, 3) array of vertex labels, when the
    caller has them (else they are read from ``c``).
    Exact: collinearity by :meth:`Predicates3.collinear`, betweenness by
    comparing the input doubles.  The data of the flipped triangles are replaced
    by the data of the neighbour (conflict lists are empty on a finished hull).
    O(#slivers) complex operations after an O(N) scan.
    """
    pts = pred.points
    tri_arr = triangles
    if tri_arr is None:
        tri_arr = np.array([t for t, _ in structure.items(c)], dtype=np.intp).reshape(-1, 3)
    if not tri_arr.size:
        return c, 0
    maybe = np.flatnonzero(_maybe_collinear(pts, tri_arr))
    if maybe.size:
        # The few candidates, as the complex's own triangles (vertices, in its rotation).
        lookup = {frozenset(t): t for t, _ in structure.items(c)}
        candidates = [lookup[frozenset(row)] for row in tri_arr[maybe].tolist()]
    else:
        candidates = []
    # In an order fixed by the labels alone (not by the face table's, which follows the insertion path):
    # the bulldozer's hull of the perturbed points is unique, so the flipped surface is too, whatever
    # the seed or the insertion order (the parallel hull's equality with the one-process hull needs it).
    work = sorted((t for t in candidates if pred.collinear(t[0], t[1], t[2])), key=lambda t: sorted(int(v) for v in t), reverse=True)
    flips = 0
    budget = 4 * len(work) + 8
    while work and budget > 0:
        budget -= 1
        t = work.pop()
        if structure.data(c, t) is None:
            continue  # already flipped away
        order = _middle(pts, int(t[0]), int(t[1]), int(t[2]))
        if order is None:
            continue
        # Rotate the triangle so that it reads (a, m, b) with m between a and b.
        ia, im, ib = order
        k = [int(v) for v in t].index(ia)
        a, m, b = t[k], t[(k + 1) % 3], t[(k + 2) % 3]
        assert int(m) == im and int(b) == ib
        nb = structure.findi(c, (a, b))
        if len(nb) != 1:
            continue
        (n_tri, datum), = nb
        x = n_tri[2]
        pair = False
        if pred.collinear(int(a), int(b), int(x)):
            # The neighbour (b, a, x) is a sliver on the same line.  If x lies between a and b, the two
            # share their long edge and each waits for the other: flip that edge between them, which
            # leaves two slivers whose long edges are shorter (both ends within [a, b]), and go on with
            # them.  Otherwise the neighbour's long edge is another one: flip the neighbour first.
            nb_order = _middle(pts, int(n_tri[0]), int(n_tri[1]), int(n_tri[2]))
            if nb_order is None or nb_order[1] != int(x):
                work.insert(0, t)
                continue
            pair = True
        c = structure.rem(c, t)
        c = structure.rem(c, n_tri)
        c = structure.add(c, (a, m, x), datum)
        c = structure.add(c, (m, b, x), datum)
        flips += 1
        if pair:
            work += [(a, m, x), (m, b, x)]
            budget += 2
    return c, flips
