"""Independent exact references for the predicate tests: Fractions and explicit ε.

Nothing here uses persistri: determinants are computed by the Leibniz formula on
:class:`fractions.Fraction` values of the input doubles, and Simulation of
Simplicity by evaluating the perturbed determinant at an explicit, tiny enough
ε (exactly, on big integers) instead of by any table of minors.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from fractions import Fraction

import numpy as np
from numpy.typing import NDArray


def _parity(perm: Sequence[int]) -> int:
    inversions = sum(1 for i in range(len(perm)) for j in range(i + 1, len(perm)) if perm[i] > perm[j])
    return -1 if inversions % 2 else 1


def det(matrix: Sequence[Sequence[Fraction | int]]) -> Fraction | int:
    """The determinant: written out up to 3×3, Laplace expansion along the first row above."""
    k = len(matrix)
    if k == 1:
        return matrix[0][0]
    if k == 2:
        return matrix[0][0] * matrix[1][1] - matrix[0][1] * matrix[1][0]
    if k == 3:
        (a, b, c), (d, e, f), (g, h, i) = matrix
        return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    total: Fraction | int = 0
    for j in range(k):
        sub = [[*row[:j], *row[j + 1 :]] for row in matrix[1:]]
        term = matrix[0][j] * det(sub)
        total = total - term if j % 2 else total + term
    return total


def leibniz(matrix: Sequence[Sequence[Fraction | int]]) -> Fraction | int:
    """The determinant by the Leibniz formula (a second, independent evaluation)."""
    k = len(matrix)
    total: Fraction | int = 0
    for perm in itertools.permutations(range(k)):
        term: Fraction | int = _parity(perm)
        for i, j in enumerate(perm):
            term *= matrix[i][j]
        total += term
    return total


def sign(v: Fraction | int) -> int:
    return (v > 0) - (v < 0)


def rows(points: NDArray[np.float64], idx: Sequence[int]) -> list[list[Fraction]]:
    return [[Fraction(float(v)) for v in points[i]] for i in idx]


def orient(points: NDArray[np.float64], *idx: int) -> int:
    """Sign of det[[p, 1] for p in points[idx]] (orient2d for 3 2D points, orient3d for 4 3D points).

    Computed as the determinant of the differences to the last point (the same value).
    """
    r = rows(points, idx)
    last = r[-1]
    return sign(det([[v - w for v, w in zip(p, last)] for p in r[:-1]]))


def lifted(points: NDArray[np.float64], idx: Sequence[int]) -> list[list[Fraction]]:
    return [[x, y, x * x + y * y] for x, y in rows(points, idx)]


def incircle(points: NDArray[np.float64], *idx: int) -> int:
    """Sign of det[[x, y, x² + y², 1]] over points[idx] (4 2D points)."""
    return sign(det([r + [Fraction(1)] for r in lifted(points, idx)]))


def small(coords: Sequence[Sequence[Fraction]], bits: int = 64) -> bool:
    """Whether :func:`sos_sign` is cheap here: the points are integers of at most ``bits`` bits at a common scale."""
    scale = math.lcm(*[v.denominator for p in coords for v in p])
    return all(abs(int(v * scale)).bit_length() <= bits for p in coords for v in p)


def sos_sign(coords: Sequence[Sequence[Fraction]], indices: Sequence[int]) -> int:
    """The SoS sign of det[[p_i(ε), 1]] by explicit evaluation at a tiny ε.

    ``coords[k]`` are the δ coordinates of the point with index ``indices[k]``
    (distinct).  Point of rank r (1 = smallest index) coordinate j (1-based) is
    perturbed by ε^(2^(rδ - j)) — only the order of the indices matters.  ε is
    2^-K with K large enough that the first nonzero term dominates the rest, and
    everything is scaled to integers, so the evaluation is exact.
    """
    k = len(coords)
    delta = len(coords[0])
    rank = {i: r + 1 for r, i in enumerate(sorted(indices))}
    denominators = [v.denominator for p in coords for v in p]
    scale = math.lcm(*denominators)
    ints = [[int(v * scale) for v in p] for p in coords]
    bound = max([1] + [abs(v) for p in ints for v in p]) + 1
    minor_bound = math.factorial(k) * bound ** (k - 1)
    terms = 2 ** (k * delta)
    big_k = (2 * minor_bound * terms).bit_length() + 2
    top = 2 ** (k * delta - 1)  # the largest ε exponent
    matrix = []
    for p, i in zip(ints, indices):
        r = rank[i]
        row = [v * 2 ** (big_k * top) + 2 ** (big_k * (top - 2 ** (r * delta - (j + 1)))) for j, v in enumerate(p)]
        row.append(2 ** (big_k * top))
        matrix.append(row)
    value = leibniz(matrix)
    assert value != 0
    return sign(value)
