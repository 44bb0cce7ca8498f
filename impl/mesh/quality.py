"""Triangle quality, decided exactly: the smallest angle against a bound, and the area against a bound.

Delaunay refinement (:mod:`persistri.impl.mesh.ruppert`) splits a triangle whose
smallest angle is below ``min_angle`` or whose area exceeds ``max_area``.  Both
tests are exact here, on the integer coordinates of the predicates
(:meth:`~persistri.impl.geometry.growing.GrowingPredicates2.integers`), so a mesh
reported as meeting its bounds meets them — no epsilon.

**The angle.**  The smallest angle of a triangle is the one opposite its
shortest edge (law of sines).  At vertex ``r`` opposite the edge ``pq``, with
``d = p − r`` and ``e = q − r``, ``cos A = d·e / (|d| |e|)``; for a bound
``θ < 90°`` (where ``cos θ > 0``)::

    A >= θ   ⇔   d·e <= 0   or   (d·e)² <= cos²θ · |d|² |e|²

(``proofs/proof_mesh.py``): squared cosines, so no square root.  ``cos²θ`` is
irrational for almost every ``θ``; :func:`cos2_bracket` encloses it between two
rationals, ``L <= cos²θ <= H``, from a rational enclosure of π and the Taylor
series of cosine with its Lagrange remainder (every step exact in
:class:`fractions.Fraction`).  A triangle is **good** only when
``(d·e)² <= L |d|² |e|²`` (or ``d·e <= 0``), which implies ``A >= θ``: the
guarantee is sound; a triangle within ``2^-120`` of the bound in ``cos²`` may be
called bad though its angle is ``θ`` to 36 digits, which costs at most one
needless split.

**The area.**  Twice the area is the orient2d determinant: ``area > max_area``
is decided on integers, ``max_area`` being a double (an exact rational).

Costs: O(1) big-integer operations per triangle; :func:`cos2_bracket` once per
refinement (a few hundred rational operations).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Final

from persistri.impl.geometry.growing import GrowingPredicates2

__all__ = ["AngleBound", "cos2_bracket", "Shape", "shape", "area_exceeds", "twice_area"]

_PI_LO: Final[Fraction] = Fraction("3.14159265358979323846264338327950288")
"""π truncated to 35 decimals: ``_PI_LO < π < _PI_LO + 10^-35`` (the next digits of π are 419…)."""
_PI_HI: Final[Fraction] = _PI_LO + Fraction(1, 10**35)
_BITS: Final[int] = 128
"""The enclosure is rounded outward to multiples of ``2^-_BITS`` (keeps the comparisons' integers small)."""
_TERMS: Final[int] = 30
"""Taylor terms of cosine: the remainder ``x^62 / 62!`` is below ``10^-70`` for ``|x| <= π/2``."""


def _cos_enclosure(x: Fraction) -> tuple[Fraction, Fraction]:
    """``(lo, hi)`` with ``lo <= cos x <= hi``: the Taylor sum and its Lagrange remainder bound ``|x|^(2N) / (2N)!``."""
    total = Fraction(0)
    term = Fraction(1)
    x2 = x * x
    for k in range(_TERMS):
        total += term
        term = -term * x2 / ((2 * k + 1) * (2 * k + 2))
    remainder = abs(term)  # |x|^(2N) / (2N)!, bounding every derivative of cos by 1
    return total - remainder, total + remainder


def cos2_bracket(min_angle: float) -> tuple[Fraction, Fraction]:
    """Rationals ``(L, H)`` with ``L <= cos²(min_angle°) <= H`` and ``H − L < 2^-120``, for ``0 <= min_angle <= 90``.

    Cosine decreases on ``[0, π/2]``, so ``cos θ`` lies between the enclosures at
    the two ends of ``θ · [π_lo, π_hi] / 180``.  Exact rational arithmetic. O(1).
    """
    if not 0.0 <= min_angle <= 90.0:
        raise ValueError(f"min_angle must be within [0, 90] degrees, got {min_angle!r}")
    theta = Fraction(min_angle)
    lo, _ = _cos_enclosure(theta * _PI_HI / 180)
    _, hi = _cos_enclosure(theta * _PI_LO / 180)
    lo = max(lo, Fraction(0))
    hi = min(hi, Fraction(1))
    scale = 1 << _BITS
    low = Fraction((lo * lo * scale).__floor__(), scale)
    high = Fraction(-((-(hi * hi) * scale).__floor__()), scale)
    return low, high


@dataclass(frozen=True, slots=True)
class AngleBound:
    """A minimum-angle bound in degrees and the rational lower bound ``L`` of its squared cosine that decides it.

    ``AngleBound.of(θ)`` for ``0 <= θ < 60`` (no triangle has a smallest angle
    above 60°); ``θ = 0`` means no bound.
    """

    degrees: float
    cos2_num: int
    cos2_den: int

    @staticmethod
    def of(degrees: float) -> AngleBound:
        """The bound for ``degrees`` (validated: a real in ``[0, 60)``). O(1)."""
        if isinstance(degrees, bool) or not isinstance(degrees, (int, float)):
            raise TypeError(f"min_angle must be a real number of degrees, not {type(degrees).__name__}")
        d = float(degrees)
        if not 0.0 <= d < 60.0:
            raise ValueError(
                f"min_angle must be within [0, 60) degrees (no triangle has a smallest angle above 60), got {degrees!r}"
            )
        low, _ = cos2_bracket(d)
        return AngleBound(d, low.numerator, low.denominator)


@dataclass(frozen=True, slots=True)
class Shape:
    """A triangle's shortest edge and smallest angle, exactly.

    ``(p, q, r)`` is the triangle rotated (orientation kept) so that ``pq`` is its
    shortest edge and ``r`` the vertex of its smallest angle; ``edge2`` is
    ``|pq|²`` as a float (the queue key); ``good_angle`` whether that angle is at
    least the bound.
    """

    p: int
    q: int
    r: int
    edge2: float
    good_angle: bool


def shape(P: GrowingPredicates2, a: int, b: int, c: int, bound: AngleBound) -> Shape:
    """The :class:`Shape` of triangle ``(a, b, c)`` against ``bound`` (module docstring). O(1) exact."""
    (pa, pb, pc), e = P.integers(a, b, c)
    lab = (pa[0] - pb[0]) ** 2 + (pa[1] - pb[1]) ** 2
    lbc = (pb[0] - pc[0]) ** 2 + (pb[1] - pc[1]) ** 2
    lca = (pc[0] - pa[0]) ** 2 + (pc[1] - pa[1]) ** 2
    if lab <= lbc and lab <= lca:
        p, q, r, pp, pq, pr, short, d2, e2 = a, b, c, pa, pb, pc, lab, lca, lbc
    elif lbc <= lca:
        p, q, r, pp, pq, pr, short, d2, e2 = b, c, a, pb, pc, pa, lbc, lab, lca
    else:
        p, q, r, pp, pq, pr, short, d2, e2 = c, a, b, pc, pa, pb, lca, lbc, lab
    if bound.cos2_num == bound.cos2_den:  # θ = 0: every angle is good
        good = True
    else:
        dot = (pp[0] - pr[0]) * (pq[0] - pr[0]) + (pp[1] - pr[1]) * (pq[1] - pr[1])
        good = dot <= 0 or dot * dot * bound.cos2_den <= bound.cos2_num * d2 * e2
    return Shape(p, q, r, _scaled_float(short, 2 * e), good)


def _scaled_float(v: int, e: int) -> float:
    """``v · 2^e`` as a float (inf on overflow, for a queue key only)."""
    try:
        return float(Fraction(v) * Fraction(2) ** e)
    except OverflowError:
        return float("inf")


def twice_area(P: GrowingPredicates2, a: int, b: int, c: int) -> Fraction:
    """Twice the signed area of ``(a, b, c)``, exactly (positive when counterclockwise). O(1)."""
    (pa, pb, pc), e = P.integers(a, b, c)
    det = (pa[0] - pc[0]) * (pb[1] - pc[1]) - (pa[1] - pc[1]) * (pb[0] - pc[0])
    return Fraction(det) * Fraction(2) ** (2 * e)


def area_exceeds(P: GrowingPredicates2, a: int, b: int, c: int, max_area: Fraction) -> bool:
    """Whether the area of counterclockwise ``(a, b, c)`` is strictly above ``max_area`` (exact). O(1)."""
    (pa, pb, pc), e = P.integers(a, b, c)
    det = (pa[0] - pc[0]) * (pb[1] - pc[1]) - (pa[1] - pc[1]) * (pb[0] - pc[0])
    # area = det · 2^(2e) / 2 > max_area  ⇔  det · 2^(2e) > 2 · max_area
    lhs_num, lhs_den = (det << (2 * e), 1) if e >= 0 else (det, 1 << (-2 * e))
    bound = 2 * max_area
    return lhs_num * bound.denominator > bound.numerator * lhs_den
