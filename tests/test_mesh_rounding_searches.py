"""The exact searches behind rounded split points, each against a plain rational reference.

:func:`~persistri.impl.mesh.splitting.near_segment` (the tolerance box, on
integers), the dyadic fallback of the split parameter, the band filter before
the exact tolerance-band test and the order of
:func:`~persistri.impl.mesh.splitting.rounded_candidates` are each computed on
integers for speed; here each agrees with the same search written plainly in
rationals, on UTM, subnormal and huge coordinates.  The meshes these searches
make are tested in ``test_mesh_rounding.py``.
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Any

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.api import triangulate
from persistri.impl.mesh.chains import in_tolerance_box
from persistri.impl.mesh.precision import BAND_ULPS, clear_of_band
from persistri.impl.mesh.splitting import _candidate_parameters, near_segment, rounded_candidates
from persistri.impl.mesh.steiner import PrecisionLimitError, _dyadic_double, _dyadic_split, _last_reducing_level
from rounding_helpers import A, B, X0, Y0, exact_on


def _near_segment_rational(ax: float, ay: float, bx: float, by: float, x: float, y: float, ulps: float) -> bool:
    """The tolerance-box clipping of :func:`near_segment`, in rationals: the checker's reference, ``in_tolerance_box``."""
    return in_tolerance_box(np.array([x, y]), np.array([ax, ay]), np.array([bx, by]), ulps)


_any_double = st.one_of(
    st.floats(-1e7, 1e7, allow_nan=False),
    st.floats(allow_nan=False, allow_infinity=False),
    st.sampled_from([0.0, -0.0, 5e-324, -5e-324, 2.2250738585072014e-308, 1.7976931348623157e308]),
)


@settings(max_examples=400, deadline=None)
@given(
    _any_double, _any_double, _any_double, _any_double, st.floats(0, 1), st.integers(-3, 3), st.integers(-3, 3),
    st.sampled_from([0.3, 0.5, 1.0, 1.5, 2.0]), st.booleans(),
)
def test_near_segment_on_integers_agrees_with_rationals(
    ax: float, ay: float, bx: float, by: float, t: float, sx: int, sy: int, ulps: float, vertical: bool
) -> None:
    """The integer clipping decides exactly as the rational one, near the segment (a few ulps off a point on it),
    on degenerate axes and on subnormal and huge coordinates, where ``ulps · ulp`` underflows a double."""
    if vertical:
        bx = ax
    x, y = ax + t * (bx - ax), ay + t * (by - ay)
    assume(math.isfinite(x) and math.isfinite(y))
    for _ in range(abs(sx)):
        x = math.nextafter(x, math.copysign(math.inf, sx))
    for _ in range(abs(sy)):
        y = math.nextafter(y, math.copysign(math.inf, sy))
    assume(math.isfinite(x) and math.isfinite(y))
    assert near_segment(ax, ay, bx, by, x, y, ulps) == _near_segment_rational(ax, ay, bx, by, x, y, ulps)
    assert near_segment(ax, ay, bx, by, bx, ay, ulps) == _near_segment_rational(ax, ay, bx, by, bx, ay, ulps)


@settings(max_examples=400, deadline=None)
@given(_any_double, _any_double, _any_double, _any_double, st.integers(0, 1 << 62), st.integers(0, 62))
@example(5e-324, -5e-324, 2.2250738585072014e-308, 1e-310, 1, 1)
@example(X0, Y0, X0 + 40.01, Y0 + 10.03, 1, 1)
@example(1.0, 1.0, 2.0, 2.0, (1 << 62) - 1, 62)  # rounds up onto the power of two 2.0: its ulp is twice as wide
def test_the_nearest_doubles_to_a_point_on_a_segment_pass_the_box_test(
    ax: float, ay: float, bx: float, by: float, num: int, bits: int
) -> None:
    """``rounded_candidates`` yields the rounding to nearest of a point of the closed segment without the box test:
    each coordinate's rounding error is at most ``ulp`` of the rounded value, the box's half-width at least that
    (subnormal, huge and UTM coordinates; a rounding onto a power of two)."""
    t = Fraction(min(num, 1 << bits), 1 << bits)  # in [0, 1]
    px, py = Fraction(ax) + t * (Fraction(bx) - Fraction(ax)), Fraction(ay) + t * (Fraction(by) - Fraction(ay))
    try:
        x, y = float(px), float(py)  # Fraction -> float rounds to nearest
    except OverflowError:
        return
    assume(math.isfinite(x) and math.isfinite(y))
    assert near_segment(ax, ay, bx, by, x, y)
    assert _near_segment_rational(ax, ay, bx, by, x, y, 1.0)


def test_dyadic_double_is_exact() -> None:
    """``n · 2^e`` is returned exactly when it is a double: 53-bit odd parts, subnormals down to 2^-1074, no overflow."""
    assert _dyadic_double(0, 5) == 0.0
    assert _dyadic_double(3, -1) == 1.5 and _dyadic_double(-12, -3) == -1.5
    assert _dyadic_double((1 << 53) - 1, 0) == float((1 << 53) - 1)
    assert _dyadic_double((1 << 53) + 1, 0) is None  # 54 significant bits
    assert _dyadic_double(1, -1074) == 5e-324 and _dyadic_double(1, -1075) is None
    assert _dyadic_double(3, -1075) is None and _dyadic_double(6, -1075) == 1.5e-323
    assert _dyadic_double(1, 1023) == 2.0**1023 and _dyadic_double(1, 1024) is None
    for n, e in ((5, 7), (-(2**52) - 1, -1100), (2**60, -2000)):
        got = _dyadic_double(n, e)
        exact = Fraction(n) * Fraction(2) ** e
        assert (got is not None) == (Fraction(float(exact)) == exact if abs(exact) < 2**1024 else False)
        if got is not None:
            assert Fraction(got) == exact


def _dyadic_split_rational(
    P: GrowingPredicates2, a: int, b: int, t_lo: Fraction, t_hi: Fraction, wanted: Fraction
) -> tuple[Fraction, float, float] | None:
    """The dyadic fallback of ``split_parameter`` written plainly in rationals, every candidate tried (the reference)."""
    delta = t_hi - t_lo
    lo_ok, hi_ok = t_lo + delta / 4, t_hi - delta / 4
    target = min(max(wanted, lo_ok), hi_ok)
    k0 = 0
    while Fraction(1, 1 << k0) > delta / 8:
        k0 += 1
    fine = min(k0 + 64, max(k0, target.denominator.bit_length() - 1))
    (xa, ya), (xb, yb) = (Fraction(v) for v in P.xy(a)), (Fraction(v) for v in P.xy(b))
    tried: set[Fraction] = set()
    for k in range(fine, k0 - 1, -1):
        unit = 1 << k
        base = math.floor(target * unit)
        for j in (base, base + 1) if target * unit - base <= Fraction(1, 2) else (base + 1, base):
            t = Fraction(j, unit)
            if t in tried or not lo_ok <= t <= hi_ok:
                continue
            tried.add(t)
            x, y = xa + t * (xb - xa), ya + t * (yb - ya)
            try:
                fx, fy = float(x), float(y)
            except OverflowError:
                continue
            if fx == x and fy == y:
                return t, fx, fy
    return None


@settings(max_examples=300, deadline=None)
@given(
    st.floats(-1e6, 1e6), st.floats(-1e6, 1e6), st.floats(-1e6, 1e6), st.floats(-1e6, 1e6),
    st.integers(0, 2**20), st.integers(1, 2**20), st.integers(0, 60), st.integers(0, 1000),
)
def test_dyadic_split_agrees_with_the_plain_search(
    xa: float, ya: float, xb: float, yb: float, lo_num: int, width: int, shift: int, at: int
) -> None:
    """The dyadic fallback on integers, with its levels skipped where a coordinate cannot be a double, returns the
    candidate the plain rational search returns (the first that is a pair of doubles), or fails where it fails."""
    assume((xa, ya) != (xb, yb))
    P = GrowingPredicates2(np.array([[xa, ya], [xb, yb]]))
    denominator = 2**21 << shift
    t_lo = Fraction(lo_num, denominator)
    t_hi = t_lo + Fraction(width, denominator)
    assume(t_hi <= 1)
    wanted = t_lo + (t_hi - t_lo) * Fraction(at, 1000)
    expected = _dyadic_split_rational(P, 0, 1, t_lo, t_hi, wanted)
    if expected is None:
        with pytest.raises(PrecisionLimitError):
            _dyadic_split(P, 0, 1, t_lo, t_hi, wanted)
    else:
        assert _dyadic_split(P, 0, 1, t_lo, t_hi, wanted) == expected


@settings(max_examples=300)
@given(st.integers(0, 2**70), st.integers(1, 2**70), st.integers(0, 40))
@example(1, 4, 0)  # 2^-k at exactly the distance below the target: the strict side
@example(3, 4, 0)  # and above it: the side that counts equality
@example(5, 16, 1)
@example(0, 7, 3)  # on the grid: every level
def test_last_reducing_level_is_the_highest_level_with_a_reducing_candidate(tn: int, td: int, bound: int) -> None:
    """Above the returned level no candidate (floor(target · 2^k) or one more) reduces to a level at most ``bound``;
    at every level from ``bound`` up to it one does: checked level by level against the definition."""
    assume(tn <= td)
    top = _last_reducing_level(tn, td, bound)

    def reduces(k: int) -> bool:
        j = (tn << k) // td
        return any(c % (1 << (k - bound)) == 0 for c in (j, j + 1))

    for k in range(bound + 1, bound + 90):
        assert reduces(k) == (k <= top), (k, top)


def test_dyadic_split_on_the_needle_agrees_with_the_plain_search(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every call the needle's refinement makes (coordinates not snapped, sides 1e-6 rad apart: the lattice of
    doubles on a side is sparse, and the fallback runs), and the same intervals shifted along the sides."""
    import persistri.impl.mesh.steiner as steiner
    from persistri.impl.mesh.gallery import gallery_domain

    calls: list[tuple[GrowingPredicates2, int, int, Fraction, Fraction, Fraction]] = []
    real = steiner._dyadic_split

    def spy(
        P: GrowingPredicates2, a: int, b: int, t_lo: Fraction, t_hi: Fraction, wanted: Fraction, reach: Any = None
    ) -> tuple[Fraction, float, float] | None:
        calls.append((P, a, b, t_lo, t_hi, wanted))  # the search itself is checked below without a reach
        return real(P, a, b, t_lo, t_hi, wanted, reach)

    monkeypatch.setattr(steiner, "_dyadic_split", spy)
    triangulate(gallery_domain("needle").pslg, min_angle=30)
    assert len(calls) > 10
    found = failed = 0
    for P, a, b, t_lo, t_hi, wanted in calls:
        for shift in (Fraction(0), (t_hi - t_lo) / 3, -(t_hi - t_lo) / 7):
            lo, hi, w = t_lo + shift, t_hi + shift, wanted + shift
            if not 0 <= lo < hi <= 1:
                continue
            expected = _dyadic_split_rational(P, a, b, lo, hi, w)
            if expected is None:
                with pytest.raises(PrecisionLimitError):
                    real(P, a, b, lo, hi, w)
                failed += 1
            else:
                assert real(P, a, b, lo, hi, w) == expected
                found += 1
    assert found >= 1 and failed > 10  # on the needle the search mostly fails: the split point is then rounded


@settings(max_examples=300, deadline=None)
@given(
    st.floats(-1e7, 1e7), st.floats(-1e7, 1e7), st.floats(-1e7, 1e7), st.floats(-1e7, 1e7), st.floats(-0.5, 1.5),
    st.integers(-6, 6), st.integers(-6, 6), st.sampled_from([0.0, 1e-12, 1e-9, 1e-3, 1.0]),
)
def test_band_filter_never_clears_a_point_in_the_band(
    xa: float, ya: float, xb: float, yb: float, t: float, sx: int, sy: int, away: float
) -> None:
    """``clear_of_band`` (the float filter before the exact tolerance-band test) says "outside" only where
    ``near_segment`` says so too: points a few ulps off the segment, and farther off its line."""
    assume((xa, ya) != (xb, yb))
    x, y = xa + t * (xb - xa) - away * (yb - ya), ya + t * (yb - ya) + away * (xb - xa)
    for _ in range(abs(sx)):
        x = math.nextafter(x, math.copysign(math.inf, sx))
    for _ in range(abs(sy)):
        y = math.nextafter(y, math.copysign(math.inf, sy))
    P = GrowingPredicates2(np.array([[xa, ya], [xb, yb], [x, y]]))
    if clear_of_band(P, 0, 1, 2, xa, ya, xb, yb, x, y):
        assert not near_segment(xa, ya, xb, yb, x, y, BAND_ULPS)


def test_band_filter_decides_the_far_points() -> None:
    """The filter is what the refiner meets first for every apex beside a subsegment: far apexes are cleared
    without exact arithmetic, and an apex an ulp off a UTM segment is left to the exact test."""
    P = GrowingPredicates2(np.array([A, B, (X0 + 20.0, Y0 + 9.0), (X0 + 20.005, Y0 + 5.015)]))
    (xa, ya), (xb, yb) = A, B
    assert clear_of_band(P, 0, 1, 2, xa, ya, xb, yb, *P.xy(2))
    ex, ey = exact_on(Fraction(1, 2))
    near = GrowingPredicates2(np.array([A, B, (float(ex), float(ey))]))
    assert not clear_of_band(near, 0, 1, 2, xa, ya, xb, yb, float(ex), float(ey))


@settings(max_examples=200, deadline=None)
@given(st.fractions(0, 1), st.fractions(Fraction(1, 10**30), 1), st.fractions(0, 1))
def test_candidate_parameters_in_the_order_of_their_distance(tu: Fraction, delta: Fraction, at: Fraction) -> None:
    """The parameters after the first come nearest it first (ties: the smaller), as a plain sort of the rationals
    orders them — the order is computed on integers, the parameters' denominators can be long."""
    first = min(max(tu + delta * at, tu + delta / 4), tu + delta - delta / 4)
    plain = [t for t in sorted((tu + delta * k / 16 for k in range(4, 13)), key=lambda t: (abs(t - first), t)) if t != first]
    assert list(_candidate_parameters(first, tu, delta)) == [first, *plain]


def _reference_candidates(
    P: GrowingPredicates2, a: int, b: int, u: int, w: int, tu: Fraction, tw: Fraction, wanted: Fraction
) -> list[tuple[Fraction, float, float]]:
    """``rounded_candidates`` written plainly in rationals: for each parameter, the window of doubles around the
    exact point, those strictly between u and w, nearest first, that pass the box test."""
    delta = tw - tu
    first = min(max(wanted, tu + delta / 4), tw - delta / 4)
    (ax, ay), (bx, by), (ux, uy), (wx, wy) = ([Fraction(v) for v in P.xy(i)] for i in (a, b, u, w))
    seen: set[tuple[float, float]] = set()
    out: list[tuple[Fraction, float, float]] = []
    for t in _candidate_parameters(first, tu, delta):
        px, py = ax + t * (bx - ax), ay + t * (by - ay)
        xs, ys = [float(px)], [float(py)]  # Fraction -> float rounds to nearest
        for v in (xs, ys):
            for step in (-math.inf, math.inf):
                f = v[0]
                for _ in range(3):
                    f = math.nextafter(f, step)
                    v.append(f)
        near = []
        for x in sorted(xs):
            for y in sorted(ys):
                if (x, y) in seen:
                    continue
                seen.add((x, y))
                along = (Fraction(x) - ux) * (wx - ux) + (Fraction(y) - uy) * (wy - uy)
                if 0 < along < (wx - ux) ** 2 + (wy - uy) ** 2:
                    near.append(((Fraction(x) - px) ** 2 + (Fraction(y) - py) ** 2, x, y))
        near.sort()
        fa, fb = P.xy(a), P.xy(b)
        out += [(t, x, y) for _, x, y in near if near_segment(fa[0], fa[1], fb[0], fb[1], x, y)]
    return out


@settings(max_examples=150, deadline=None)
@given(
    st.integers(-50, 50), st.integers(-50, 50), st.integers(-50, 50), st.integers(-50, 50),
    st.sampled_from([1.0, 3.0, 1e5, 4e6]), st.integers(1, 15), st.integers(1, 15),
)
def test_rounded_candidates_agree_with_the_plain_search(
    i: int, j: int, k: int, m: int, base: float, num: int, den_bits: int
) -> None:
    # Ends a few ulps apart at several magnitudes, and dyadic parameters: exact points that are doubles, midpoints
    # between two doubles (ties of the nearest) and neither.  The whole sequence must agree, not only the first.
    ulp = math.ulp(base)
    A_, B_ = (base + i * ulp, base + j * ulp), (base + (k + 400) * ulp, base + (m + 900) * ulp)
    P = GrowingPredicates2(np.array([A_, B_]))
    wanted = Fraction(num % (1 << den_bits) or 1, 1 << den_bits)
    assert list(rounded_candidates(P, 0, 1, 0, 1, Fraction(0), Fraction(1), wanted)) == _reference_candidates(
        P, 0, 1, 0, 1, Fraction(0), Fraction(1), wanted
    )


def test_rounded_candidates_agree_on_the_gallery_utm_edge() -> None:
    P = GrowingPredicates2(np.array([A, B]))
    for wanted in (Fraction(1, 2), Fraction(1, 3), Fraction(5, 8), Fraction(1, 2) + Fraction(1, 1 << 60)):
        assert list(rounded_candidates(P, 0, 1, 0, 1, Fraction(0), Fraction(1), wanted)) == _reference_candidates(
            P, 0, 1, 0, 1, Fraction(0), Fraction(1), wanted
        )
