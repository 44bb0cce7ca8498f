"""The UTM edge the rounding tests split: given to the centimetre, so few doubles lie on it."""

from __future__ import annotations

from fractions import Fraction

X0, Y0 = 512_345.0, 4_123_456.0
A, B = (X0, Y0), (X0 + 40.01, Y0 + 10.03)  # given to the centimetre: few doubles lie on A–B


def exact_on(t: Fraction) -> tuple[Fraction, Fraction]:
    """The point of A–B at parameter ``t``, exactly."""
    return Fraction(A[0]) + t * (Fraction(B[0]) - Fraction(A[0])), Fraction(A[1]) + t * (Fraction(B[1]) - Fraction(A[1]))
