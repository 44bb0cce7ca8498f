"""A bad triangle's Steiner point: the off-centre chosen by the same exact decision as the squared distances give.

``steiner_point`` decides whether the off-centre is nearer to the shortest edge than the circumcentre by
``kn · den < kd · |(p − r) · (q − r)|`` (the cotangent of the angle at ``r``); before, by comparing the squared
distances ``|o − m|²`` and ``|c − m|²`` over a common denominator.  Both are exact on integers and equivalent; here
the new decision and point are compared with that reference on random, UTM-offset, thin and tied triangles.
"""

from __future__ import annotations

import math
import random

import numpy as np
import pytest

from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.steiner import offcenter_constant, steiner_point


def _reference_offcentre_nearer(P: GrowingPredicates2, p: int, q: int, r: int, offconstant: float) -> bool:
    """The decision as ``steiner_point`` made it before: ``|o − m|² < |c − m|²``, everything over ``(2 den kd)²``."""
    (pp, pq, pr), _ = P.integers(p, q, r)
    dx, dy = pq[0] - pp[0], pq[1] - pp[1]
    gx, gy = pr[0] - pp[0], pr[1] - pp[1]
    den = 2 * (dx * gy - dy * gx)
    d2, g2 = dx * dx + dy * dy, gx * gx + gy * gy
    cx = pp[0] * den + gy * d2 - dy * g2
    cy = pp[1] * den + dx * g2 - gx * d2
    kn, kd = offconstant.as_integer_ratio()
    sx, sy = pp[0] + pq[0], pp[1] + pq[1]
    lhs = 4 * kn * kn * d2 * den * den
    rhs = kd * kd * ((2 * cx - sx * den) ** 2 + (2 * cy - sy * den) ** 2)
    return lhs < rhs


def _check(points: list[tuple[float, float]], offconstants: list[float]) -> int:
    """Compare the decision on every counterclockwise triangle of ``points`` (in threes); the number of ties met."""
    P = GrowingPredicates2(np.array(points, dtype=np.float64))
    ties = 0
    for i in range(0, len(points) - 2, 3):
        p, q, r = i, i + 1, i + 2
        sign = P.orient2d_sign(p, q, r)
        if sign == 0:
            continue
        if sign < 0:
            p, q = q, p
        for k in offconstants:
            x, y, off = steiner_point(P, p, q, r, k)
            assert off == (k > 0.0 and _reference_offcentre_nearer(P, p, q, r, k)), (points[i : i + 3], k)
            if not off:
                cx, cy, _ = steiner_point(P, p, q, r, 0.0)
                assert (x, y) == (cx, cy)
            (pp, pq, pr), _ = P.integers(p, q, r)
            dx, dy = pq[0] - pp[0], pq[1] - pp[1]
            gx, gy = pr[0] - pp[0], pr[1] - pp[1]
            kn, kd = k.as_integer_ratio()
            dot_r = gx * gx + gy * gy - dx * gx - dy * gy
            ties += kn * 2 * (dx * gy - dy * gx) == kd * abs(dot_r)
    return ties


KS = [offcenter_constant(a) for a in (20.0, 25.0, 30.0, 33.0, 34.0)] + [0.25, 0.5, 1.0, 0.0]


@pytest.mark.parametrize("offset", [0.0, 5.0e5, 4.0e6])
def test_offcentre_decision_matches_the_squared_distances_on_random_triangles(offset: float) -> None:
    rng = random.Random(16)
    pts: list[tuple[float, float]] = []
    for _ in range(600):
        scale = 2.0 ** rng.randint(-30 if offset == 0.0 else -6, 10)  # a Steiner point of doubles near the offset
        pts.extend((offset + rng.uniform(-1, 1) * scale, offset + rng.uniform(-1, 1) * scale) for _ in range(3))
    _check(pts, KS)


def test_offcentre_decision_matches_on_thin_and_obtuse_triangles() -> None:
    # The apex far from, near to and beyond the base's ends: acute, right and obtuse angles at r, both signs of
    # (p − r)·(q − r), and apexes a few units in the last place above the base.
    pts: list[tuple[float, float]] = []
    for apex_x in (-3.0, -1.0, 0.0, 0.25, 0.5, 0.75, 1.0, 2.0):
        for h in (1e-12, 1e-3, 0.1, 0.5, 0.8660254037844386, 1.0, 5.0):
            pts.extend([(0.0, 0.0), (1.0, 0.0), (apex_x, h)])
    pts.extend([(0.0, 0.0), (1.0, 0.0), (0.5, math.ulp(1.0) * 4)])
    _check(pts, KS)


def test_offcentre_decision_matches_at_exact_ties() -> None:
    # Integer triangles with kn · den == kd · |(p − r)·(q − r)| for k = 1/4, 1/2, 1: the two sides equal, so neither
    # decision takes the off-centre (a strict comparison both ways).
    found: list[tuple[float, float]] = []
    for k in (0.25, 0.5, 1.0):
        kn, kd = k.as_integer_ratio()
        for D in range(1, 9):
            for gx in range(-8, 9):
                for gy in range(1, 9):
                    dot_r = gx * gx + gy * gy - D * gx
                    if kn * 2 * D * gy == kd * abs(dot_r):
                        found.extend([(0.0, 0.0), (float(D), 0.0), (float(gx), float(gy))])
    assert len(found) >= 30
    assert _check(found, [0.25, 0.5, 1.0]) >= 10
