"""Simulation of Simplicity (Edelsbrunner & Mücke 1990): exact zeros broken by a symbolic perturbation.

Every point ``p_i`` (``i`` its index) is moved symbolically to

    p_i(ε) = (x_i + ε^(2^(iδ-1)), y_i + ε^(2^(iδ-2)), …)        (δ = the dimension)

for an infinitesimal ``ε > 0``.  The perturbed orientation determinant is a
polynomial in ``ε``; each perturbation is a distinct power of two, so every
product of perturbations has its own exponent and the terms are totally
ordered.  The sign of the perturbed determinant is the sign of its first
nonzero coefficient, and each coefficient is ± a minor of the unperturbed
matrix.  A term whose minor is the constant 1 comes before the sequence can run
out, so the perturbed sign is never 0.

The sequence depends only on the *order* of the indices (the exponents compare
by their largest differing power of two), so the tables below are written for
rows sorted by increasing index: row 0 is the point of smallest index, the most
strongly perturbed.  The caller sorts the indices and multiplies by the parity
of the sorting permutation (:func:`sort_with_parity`), which makes the result
antisymmetric in its arguments exactly as the determinant is.

The tables were derived with sympy, and ``proofs/proof_predicates.py`` derives
them again and checks these ones against the expansion, signs included.  A
minor that already occurred earlier in the expansion (up to sign) is dropped:
it is reached only if that earlier occurrence was zero.  What remains is
Edelsbrunner and Mücke's sequence: 4 terms after the determinant for Λ3
(orient2d), 14 for Λ4 (orient3d).

The same Λ4 sequence decides the *lifted* orientation (incircle): the lift
``x² + y²`` is perturbed as an independent third coordinate, which keeps the
2D perturbation of ``x, y`` (hence consistency with orient2d) and amounts to
infinitesimal weights of a regular triangulation (see
:meth:`persistri.impl.geometry.predicates.Predicates2.incircle`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Final, Protocol, Self, TypeVar

__all__ = [
    "Minor",
    "ORIENT2D_SOS",
    "ORIENT3D_SOS",
    "sort_with_parity",
    "sort_by_rank_with_parity",
    "minor",
    "perturbed_sign",
    "sos_orient2d",
    "sos_orient3d",
]

class _Ring(Protocol):
    def __add__(self, other: Self, /) -> Self: ...

    def __sub__(self, other: Self, /) -> Self: ...

    def __mul__(self, other: Self, /) -> Self: ...


R = TypeVar("R", bound=_Ring)

Minor = tuple[int, tuple[int, ...], tuple[int, ...]]
"""A term of the expansion: ``(sign, rows, columns)`` — the coefficient is
``sign · det(M[rows, columns])`` of the unperturbed matrix ``M``."""

ORIENT2D_SOS: Final[tuple[Minor, ...]] = (
    # Rows are the three points sorted by index; columns are (x, y, 1).
    (1, (0, 1, 2), (0, 1, 2)),  # the determinant itself
    (-1, (1, 2), (0, 2)),  # ε^1:  -(x_1 - x_2)
    (1, (1, 2), (1, 2)),  # ε^2:  y_1 - y_2
    (1, (0, 2), (0, 2)),  # ε^4:  x_0 - x_2
    (1, (2,), (2,)),  # ε^5:  1
)
"""Λ3: the SoS sequence of the 2D orientation determinant (rows ``(x, y, 1)``)."""

ORIENT3D_SOS: Final[tuple[Minor, ...]] = (
    # Rows are the four points sorted by index; columns are (x, y, z, 1).
    (1, (0, 1, 2, 3), (0, 1, 2, 3)),  # the determinant itself
    (1, (1, 2, 3), (0, 1, 3)),
    (-1, (1, 2, 3), (0, 2, 3)),
    (1, (1, 2, 3), (1, 2, 3)),
    (-1, (0, 2, 3), (0, 1, 3)),
    (1, (2, 3), (0, 3)),
    (-1, (2, 3), (1, 3)),
    (1, (0, 2, 3), (0, 2, 3)),
    (1, (2, 3), (2, 3)),
    (-1, (0, 2, 3), (1, 2, 3)),
    (1, (0, 1, 3), (0, 1, 3)),
    (-1, (1, 3), (0, 3)),
    (1, (1, 3), (1, 3)),
    (1, (0, 3), (0, 3)),
    (1, (3,), (3,)),
)
"""Λ4: the SoS sequence of the 3D orientation determinant (rows ``(x, y, z, 1)``)."""


def sort_with_parity(indices: Sequence[int]) -> tuple[list[int], int]:
    """``(sorted indices, parity)`` of a few point indices.

    ``parity`` is +1 for an even sorting permutation, -1 for an odd one; equal
    indices raise :class:`ValueError` (a repeated point is a genuine zero that
    no perturbation can break).  O(k²) for k indices (k <= 4).
    """
    k = len(indices)
    inversions = 0
    for p in range(k):
        for q in range(p + 1, k):
            if indices[p] > indices[q]:
                inversions += 1
            elif indices[p] == indices[q]:
                raise ValueError(f"point indices must be distinct, got {tuple(indices)}")
    return sorted(indices), -1 if inversions & 1 else 1


def sort_by_rank_with_parity(indices: Sequence[int], rank: Sequence[int]) -> tuple[list[int], int]:
    """``(indices sorted by rank, parity)``: :func:`sort_with_parity` with the perturbation order ``rank[i]``
    in place of the index ``i`` (distinct ranks; equal indices raise :class:`ValueError`).  O(k²) for k <= 4.

    A point's infinitesimal perturbation depends only on its place in this order
    (Edelsbrunner and Mücke): ranking points by anything other than their indices
    — their input rows, say, while the indices follow a space-filling curve — breaks
    every tie as an index order equal to the ranks would.
    """
    keys = [rank[i] for i in indices]
    _, parity = sort_with_parity(keys)
    return [i for _, i in sorted(zip(keys, indices))], parity


def minor(matrix: Sequence[Sequence[R]], rows: Sequence[int], cols: Sequence[int]) -> R:
    """``det(matrix[rows, cols])``: exact on ints (or any ring). O(k!) for k <= 4.

    Sizes 1 to 3 are written out (the SoS minors); larger ones expand along the first row.
    """
    k = len(rows)
    if k == 1:
        return matrix[rows[0]][cols[0]]
    if k == 2:
        r0, r1 = matrix[rows[0]], matrix[rows[1]]
        c0, c1 = cols
        return r0[c0] * r1[c1] - r0[c1] * r1[c0]
    if k == 3:
        r0, r1, r2 = matrix[rows[0]], matrix[rows[1]], matrix[rows[2]]
        c0, c1, c2 = cols
        return (
            r0[c0] * (r1[c1] * r2[c2] - r1[c2] * r2[c1])
            - r0[c1] * (r1[c0] * r2[c2] - r1[c2] * r2[c0])
            + r0[c2] * (r1[c0] * r2[c1] - r1[c1] * r2[c0])
        )
    first = matrix[rows[0]]
    rest = rows[1:]
    total = first[cols[0]] * minor(matrix, rest, cols[1:])
    for j in range(1, k):
        term = first[cols[j]] * minor(matrix, rest, [*cols[:j], *cols[j + 1 :]])
        total = total - term if j % 2 else total + term
    return total


def perturbed_sign(matrix: Sequence[Sequence[int]], table: Sequence[Minor], start: int = 0) -> int:
    """The sign of the first nonzero term of ``table`` from ``start`` on: the SoS sign of ``matrix``.

    ``matrix`` has its rows sorted by point index and its last column all ones.
    Raises :class:`AssertionError` only if the table does not end in a constant
    term (it does, by construction). O(len(table)) minors.
    """
    for sign, rows, cols in table[start:]:
        value = minor(matrix, rows, cols)
        if value:
            return sign if value > 0 else -sign
    raise AssertionError("an SoS table must end in a nonzero constant term")


def sos_orient2d(p0: Sequence[int], p1: Sequence[int], p2: Sequence[int]) -> int:
    """The SoS sign of an orient2d determinant known to be exactly 0.

    ``p0, p1, p2`` are integer ``(x, y)`` points in increasing index order.
    Returns ±1, never 0. O(1).
    """
    matrix = [(p0[0], p0[1], 1), (p1[0], p1[1], 1), (p2[0], p2[1], 1)]
    return perturbed_sign(matrix, ORIENT2D_SOS, start=1)


def sos_orient3d(p0: Sequence[int], p1: Sequence[int], p2: Sequence[int], p3: Sequence[int]) -> int:
    """The SoS sign of an orient3d determinant known to be exactly 0.

    ``p0 … p3`` are integer ``(x, y, z)`` points in increasing index order (for
    incircle: the lifted points ``(x, y, x² + y²)``).  Returns ±1, never 0. O(1).
    """
    matrix = [(p[0], p[1], p[2], 1) for p in (p0, p1, p2, p3)]
    return perturbed_sign(matrix, ORIENT3D_SOS, start=1)
