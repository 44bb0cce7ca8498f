"""Proofs for quality meshing (Ruppert's refinement, the paper's §1; :mod:`persistri.impl.mesh`).

The refinement decides with a few predicates beyond orient2d and incircle;
these sympy identities (exact, polynomial) and exhaustive checks justify them:

* **encroachment is Thales' theorem** — ``(a − p)·(b − p) = |p − m|² − |b − a|²/4``
  with ``m`` the midpoint of ``ab``: the sign of the dot product is negative
  exactly when ``p`` is strictly inside the circle with diameter ``ab``
  (:meth:`~persistri.impl.geometry.growing.GrowingPredicates2.dot_sign`);
* **its filter** — :func:`~persistri.impl.geometry.growing.dot_terms`, run on the
  tracking numbers of ``proofs/proof_predicates.py`` (every float operation
  ``exact · (1 + δ)``), has the dot product as its exact value and
  :data:`~persistri.impl.geometry.growing.ERRBOUND_DOT` as a sufficient constant;
* **the angle test by squared cosines** — Lagrange's identity
  ``|d|²|e|² = (d·e)² + (d × e)²`` makes ``cos²A = (d·e)² / (|d|²|e|²)`` a
  number in ``[0, 1]``, and for a bound ``0 < θ < 90°`` (``cos θ > 0``, cosine
  decreasing on ``[0°, 180°]``): ``A >= θ ⇔ d·e <= 0 or (d·e)² <= cos²θ |d|²|e|²``
  (checked on a grid of exact rational cases against the angle itself);
* **the diametral lens** — the apex angle ``∠uxw >= 180° − 2θ`` iff the
  supplementary angle is ``<= 2θ``, whose cosine is ``−(u − x)·(w − x) / (|u − x| |w − x|)``;
  on the lens's boundary the triangle ``u w x`` is isosceles with base angles ``θ``;
* **the circumcentre** — the formula of :func:`~persistri.impl.mesh.steiner.circumcenter`
  is equidistant from the three vertices (and its denominator is twice the
  orient2d determinant, nonzero for a proper triangle);
* **the off-centre** — the point at height ``k |pq|`` over the midpoint of ``pq``
  sees ``pq`` under the angle ``2 atan(1 / (2k))``: ``θ`` for ``k = cot(θ/2) / 2``,
  a little more for Triangle's ``0.475 cot(θ/2)``;
* **the float stage of the quality tests** — the constants of
  :class:`~persistri.impl.mesh.quality_filter.QualityTests`' error argument, in exact
  rationals: squared lengths within ``4.01u``; ``1 − 2^-40`` separates them; an angle
  opposite a near-shortest edge has cosine at least ``0.49``; the squared-cosine
  ratio within ``31u`` — far inside the ``1e-9`` margin; the area slack ``2^-40``
  covers the last roundings;
* **split points on the lattice** — :func:`~persistri.impl.mesh.steiner._congruence`
  solves ``c + k d ≡ 0 (mod 2^b)`` exactly (exhaustively checked against brute
  force for small moduli), and the integer points of a segment between integer
  points ``u`` and ``w`` are ``u + j (w − u) / gcd`` (checked exhaustively on a box).
"""

from __future__ import annotations

import itertools
import math
from fractions import Fraction

import sympy as sp

from persistri.impl.geometry import growing
from persistri.impl.mesh import steiner
from proofs.proof_predicates import _check_filter

__all__ = [
    "proof_encroachment_is_thales",
    "proof_dot_filter_bound",
    "proof_lagrange_identity",
    "proof_angle_test_by_squared_cosines",
    "proof_lens_boundary_is_isosceles",
    "proof_circumcenter_is_equidistant",
    "proof_offcenter_angle",
    "proof_quality_float_stage",
    "proof_congruence_solver",
    "proof_segment_lattice_points",
]

ax, ay, bx, by, px, py, cx, cy = sp.symbols("ax ay bx by px py cx cy", real=True)


def _zero(expr: sp.Expr, what: str) -> None:
    if sp.expand(expr) != 0:
        raise AssertionError(f"{what}: the identity does not hold (residue {sp.factor(expr)})")


def proof_encroachment_is_thales() -> None:
    """(a − p)·(b − p) = |p − m|² − |b − a|²/4 (m the midpoint): negative iff p is strictly inside the diametral circle."""
    dot = (ax - px) * (bx - px) + (ay - py) * (by - py)
    mx, my = (ax + bx) / 2, (ay + by) / 2
    radius2 = ((bx - ax) ** 2 + (by - ay) ** 2) / 4
    _zero(dot - ((px - mx) ** 2 + (py - my) ** 2 - radius2), "Thales")


def proof_dot_filter_bound() -> None:
    """ERRBOUND_DOT is a sufficient filter constant for dot_terms, whose exact value is (a − p)·(b − p)."""
    names = ["ax", "ay", "bx", "by", "px", "py"]
    s = {n: sp.Symbol(n) for n in names}
    expected = (s["ax"] - s["px"]) * (s["bx"] - s["px"]) + (s["ay"] - s["py"]) * (s["by"] - s["py"])
    margin = _check_filter(growing.dot_terms, names, expected, growing.ERRBOUND_DOT)
    assert margin >= 0


def proof_lagrange_identity() -> None:
    """|d|²|e|² = (d·e)² + (d × e)²: cos²A = (d·e)²/(|d|²|e|²) lies in [0, 1], equal to 1 only for collinear d, e."""
    dx, dy, ex, ey = sp.symbols("dx dy ex ey", real=True)
    _zero((dx**2 + dy**2) * (ex**2 + ey**2) - (dx * ex + dy * ey) ** 2 - (dx * ey - dy * ex) ** 2, "Lagrange")


def proof_angle_test_by_squared_cosines() -> None:
    """A >= θ ⇔ d·e <= 0 or (d·e)² <= cos²θ |d|²|e|², on exact cases around rational-cosine bounds (30°, 45°, 60°)."""
    # Bounds with rational cos²: 30° (3/4), 45° (1/2), 60° (1/4); vectors on a small grid, compared with sympy's angle.
    for theta, cos2 in ((30, Fraction(3, 4)), (45, Fraction(1, 2)), (60, Fraction(1, 4))):
        for dx, dy, ex, ey in itertools.product(range(-2, 3), repeat=4):
            if (dx, dy) == (0, 0) or (ex, ey) == (0, 0):
                continue
            dot = dx * ex + dy * ey
            n = (dx * dx + dy * dy) * (ex * ex + ey * ey)
            test = dot <= 0 or dot * dot * cos2.denominator <= cos2.numerator * n
            diff = sp.acos(sp.Rational(dot) / sp.sqrt(n)) - sp.pi * theta / 180
            approx = sp.N(diff, 60)
            truth = bool(approx > 0) if abs(approx) > 1e-40 else sp.simplify(diff) == 0
            assert test == truth, f"the test disagrees with the angle for d = {(dx, dy)}, e = {(ex, ey)}, θ = {theta}"


def proof_lens_boundary_is_isosceles() -> None:
    """On the lens boundary (apex angle 180° − 2θ, x on the bisector of uw) the base angles are θ: the lens is where
    a vertex would make two base angles below θ."""
    h, t = sp.symbols("h t", positive=True)
    # u = (-1, 0), w = (1, 0), x = (0, h): base angle atan(h), apex angle π − 2 atan(h).
    apex = sp.pi - 2 * sp.atan(h)
    base = sp.atan(h)
    _zero(sp.simplify(apex - (sp.pi - 2 * base)), "isosceles angles")
    # The supplementary cosine the code tests: −(u − x)·(w − x)/(|u − x||w − x|) = cos(2 · base angle).
    dot = (-1 - 0) * (1 - 0) + (0 - h) * (0 - h)
    sup_cos = -dot / (1 + h**2)
    _zero(sp.simplify(sup_cos - sp.cos(2 * sp.atan(h))), "supplementary cosine")
    del t


def proof_circumcenter_is_equidistant() -> None:
    """steiner.circumcenter's formula a + (e_y|d|² − d_y|e|², d_x|e|² − e_x|d|²)/D, D = 2 d × e, is equidistant from a, b, c."""
    dx, dy = bx - ax, by - ay
    ex, ey = cx - ax, cy - ay
    den = 2 * (dx * ey - dy * ex)
    d2, e2 = dx * dx + dy * dy, ex * ex + ey * ey
    ox = ax + (ey * d2 - dy * e2) / den
    oy = ay + (dx * e2 - ex * d2) / den
    ra = (ox - ax) ** 2 + (oy - ay) ** 2
    rb = (ox - bx) ** 2 + (oy - by) ** 2
    rc = (ox - cx) ** 2 + (oy - cy) ** 2
    _zero(sp.together(ra - rb).as_numer_denom()[0], "|o − a| = |o − b|")
    _zero(sp.together(ra - rc).as_numer_denom()[0], "|o − a| = |o − c|")
    orient = sp.Matrix([[ax, ay, 1], [bx, by, 1], [cx, cy, 1]]).det()
    _zero(den - 2 * orient, "D = 2 orient2d")


def proof_offcenter_angle() -> None:
    """At height k|pq| over pq's midpoint, pq subtends 2 atan(1/(2k)): θ for k = cot(θ/2)/2; 0.475 cot(θ/2) gives more."""
    theta = sp.symbols("theta", positive=True)
    k = sp.cot(theta / 2) / 2
    # tan(apex / 2) = (|pq| / 2) / (k |pq|) = 1 / (2k) = tan(θ / 2), and atan is the inverse of tan on (0, π/2).
    _zero(sp.simplify(1 / (2 * k) - sp.tan(theta / 2)), "1/(2k) = tan(θ/2)")
    for degrees in (20, 30, 33):
        value = sp.pi * degrees / 180
        triangle_k = sp.Rational(475, 1000) * sp.cot(value / 2)
        assert sp.N(2 * sp.atan(1 / (2 * triangle_k)) - value, 30) > 0, "Triangle's constant must give an angle above θ"
        assert math.isclose(steiner.offcenter_constant(float(degrees)), float(sp.N(triangle_k, 30)), rel_tol=1e-14)


def proof_quality_float_stage() -> None:
    """QualityTests' float stage: its error constants hold, in exact rationals (u = 2^-53), so its verdicts are exact."""
    from persistri.impl.mesh import quality

    u = Fraction(1, 2**53)
    # A squared length fl(fl(dx²) + fl(dy²)) of rounded differences dx, dy: four roundings on a sum of squares.
    e_len = (1 + u) ** 4 - 1
    assert e_len <= Fraction(401, 100) * u, "squared lengths are within 4.01u"
    # l' < m' · (1 − 2^-40) proves l < m: l <= l'/(1 − e) < m'(1 − 2^-40)/(1 − e) <= m (1 + e)(1 − 2^-40)/(1 − e).
    sep = Fraction(quality._SEPARATE)
    assert sep == 1 - Fraction(1, 2**40)
    assert (1 + e_len) * sep * (1 + u) / (1 - e_len) < 1, "the separation decides which edge is shorter"
    # A candidate edge is within (1 + e)/(1 − e)/sep of the shortest, squared; the angle A opposite it is acute (an
    # obtuse one faces an edge longer than sqrt(2) times the others) with sin²A <= factor · sin²60° = factor · 3/4.
    factor = (1 + e_len) / ((1 - e_len) * sep)
    assert factor < 2
    cos2_min = 1 - factor * Fraction(3, 4)
    assert cos2_min >= Fraction(49, 100) ** 2, "an angle opposite a candidate has cosine at least 0.49"
    # The dot product of rounded differences: within e_len (|dx ex| + |dy ey|) <= e_len |d||e| <= e_len / 0.49 · d·e.
    e_dot = e_len / Fraction(49, 100)
    assert e_dot <= Fraction(82, 10) * u
    # ratio' = fl(fl(dot²) / fl(n1 · n2)) = ratio · f with n1, n2 the computed squared lengths, f in [lo, hi].
    hi = (1 + e_dot) ** 2 * (1 + u) * (1 + u) / ((1 - e_len) ** 2 * (1 - u))
    lo = (1 - e_dot) ** 2 * (1 - u) * (1 - u) / ((1 + e_len) ** 2 * (1 + u))
    assert hi - 1 <= 31 * u and 1 - lo <= 31 * u, "the squared-cosine ratio is within 31u"
    # The margin: ratio' below fl(c_lo · (1 − M)) <= cos²θ (1 − M)(1 + u) gives ratio <= ratio' / lo < cos²θ, and
    # ratio' above fl(c_hi · (1 + M)) >= cos²θ (1 + M)(1 − u) gives ratio >= ratio' / hi > cos²θ.
    margin = Fraction(quality._MARGIN)
    assert (1 - margin) * (1 + u) / lo < 1 and (1 + margin) * (1 - u) / hi > 1, "the margin covers the ratio's error"
    # The area: det > (T + thr)(1 + s) computed proves v > T + thr (v the value before the last rounding, within
    # thr of det), since fl((T + thr)(1 + s)) >= (T + thr)(1 + s)(1 − u)^2 and v >= det_computed / (1 + u).
    slack = Fraction(quality._SLACK)
    assert (1 + slack) * (1 - u) ** 2 / (1 + u) > 1 and (1 - slack) * (1 + u) ** 2 / (1 - u) < 1, "the area slack"
    # The lens: cos B = −dot / sqrt(fl(n1 n2)): the dot within e_len |a||b| (Cauchy–Schwarz), the root within
    # e_len + u of |a||b| (half the product's error, plus its own rounding), the quotient rounded once.
    e_root = e_len + u
    e_cos = (e_len + e_root + u) / (1 - e_root)
    assert e_cos < Fraction(2, 10**15) < Fraction(quality._LENS_MARGIN), "the lens test's margin"


def proof_congruence_solver() -> None:
    """_congruence(c, d, b) returns (r, M) with {k : c + k d ≡ 0 mod 2^b} = r + M Z, or None when empty (exhaustive, b <= 4)."""
    for bits in range(0, 5):
        mod = 1 << bits
        for c in range(-mod, 2 * mod):
            for d in range(-mod, 2 * mod):
                want = {k for k in range(4 * mod) if (c + k * d) % mod == 0}
                got = steiner._congruence(c, d, bits)
                if got is None:
                    assert not want, f"_congruence({c}, {d}, {bits}) found no solution, but {sorted(want)[:3]} solve it"
                    continue
                r, m = got
                assert want == {k for k in range(4 * mod) if (k - r) % m == 0}, f"_congruence({c}, {d}, {bits}) = {got}"


def proof_segment_lattice_points() -> None:
    """The integer points of the segment from u to w (integers) are u + j (w − u)/G, j = 0..G, G = gcd (exhaustive on a box)."""
    for wx, wy in itertools.product(range(-6, 7), repeat=2):
        if (wx, wy) == (0, 0):
            continue
        g = math.gcd(wx, wy)
        on = {(x, y) for x in range(-6, 7) for y in range(-6, 7) if x * wy == y * wx and 0 <= x * wx + y * wy <= wx * wx + wy * wy}
        assert on == {(j * wx // g, j * wy // g) for j in range(g + 1)}, f"lattice points of (0, 0)–{(wx, wy)}"
