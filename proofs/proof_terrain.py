"""Proofs for the terrain's incremental Delaunay triangulation (paper §5; :mod:`persistri.impl.terrain`).

The triangulation (:mod:`persistri.impl.terrain.delaunay`) decides with two
predicates, ``orient2d(a, b, c) = det[[a, 1], [b, 1], [c, 1]]`` and
``incircle(a, b, c, d) = det[[a, |a|², 1], …, [d, |d|², 1]]`` (+1: ``d`` inside the
circle through counterclockwise ``a, b, c``).  These sympy identities (exact,
polynomial in the coordinates) justify the rules it builds on them:

* **the ghost's circle** — a ghost triangle ``(u, w, ∞)`` is the limit of ``(u, w, c)``
  with ``c`` going to infinity on the left of ``u → w`` along the edge's normal:
  ``incircle(u, w, c, p) = |w − u|² · orient2d(u, w, p) · t² + O(t)``, so the
  limit "circle" is the open half-plane left of ``u → w``; and for ``p`` on the
  line, ``p = u + s (w − u)``, the whole determinant is ``s (1 − s) |w − u|⁴ t``:
  positive exactly on the open segment.  That is the ghost conflict rule;
* **the chord** — for ``p = u + s (w − u)``,
  ``incircle(u, w, c, p) = s (1 − s) |w − u|² · orient2d(u, w, c)``: a point of the
  open segment ``uw`` is strictly inside every circle through ``u`` and ``w``, a
  point of the line outside the segment strictly outside.  This is why no fan
  triangle is ever flat (``Triangulator.insert``'s docstring);
* **the sector test** — ``(r − p) × (q − p)``, the expression the fast path of
  :mod:`persistri.impl.terrain.sectors` evaluates, *is* ``orient2d(p, r, q)``, and
  its float64 evaluation is exact on integer coordinates of magnitude ≤ 2^25;
* **the plane of a triangle** — the plane ``z_a + g · (x − a)`` with the gradient
  by Cramer's rule, as :func:`persistri.impl.terrain.greedy.plane_errors` writes
  it, passes through all three vertices.
"""

from __future__ import annotations

import sympy as sp

__all__ = [
    "proof_ghost_circle_is_the_outer_half_plane",
    "proof_ghost_segment_rule",
    "proof_chord_is_inside_every_circle",
    "proof_sector_test_is_orient2d",
    "proof_sector_float_path_is_exact",
    "proof_plane_passes_through_the_vertices",
]

ux, uy, wx, wy, px, py, cx, cy, s, t = sp.symbols("ux uy wx wy px py cx cy s t", real=True)


def _zero(expr: sp.Expr, what: str) -> None:
    if sp.expand(expr) != 0:
        raise AssertionError(f"{what}: the identity does not hold (residue {sp.factor(expr)})")


def orient2d(a: tuple[sp.Expr, sp.Expr], b: tuple[sp.Expr, sp.Expr], c: tuple[sp.Expr, sp.Expr]) -> sp.Expr:
    """``det[[a, 1], [b, 1], [c, 1]]``: the predicate as the code defines it."""
    return sp.Matrix([[a[0], a[1], 1], [b[0], b[1], 1], [c[0], c[1], 1]]).det()


def incircle(
    a: tuple[sp.Expr, sp.Expr], b: tuple[sp.Expr, sp.Expr], c: tuple[sp.Expr, sp.Expr], d: tuple[sp.Expr, sp.Expr]
) -> sp.Expr:
    """``det[[x, y, x² + y², 1]]`` over ``a, b, c, d``: the lifted orientation, as the code defines it."""
    return sp.Matrix([[x, y, x * x + y * y, 1] for x, y in (a, b, c, d)]).det()


U, W, P = (ux, uy), (wx, wy), (px, py)
L2 = (wx - ux) ** 2 + (wy - uy) ** 2


def _far(tt: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """The point ``t`` edge-lengths out from the midpoint of ``uw``, on the left of ``u → w``."""
    return ((ux + wx) / 2 - tt * (wy - uy), (uy + wy) / 2 + tt * (wx - ux))


def proof_ghost_circle_is_the_outer_half_plane() -> None:
    """incircle(u, w, c(t), p) = |w−u|² orient2d(u, w, p) t² + O(t), with (u, w, c(t)) counterclockwise for t > 0."""
    _zero(orient2d(U, W, _far(t)) - t * L2, "the far point is on the left of u → w")
    poly = sp.Poly(sp.expand(incircle(U, W, _far(t), P)), t)
    if poly.degree() != 2:
        raise AssertionError(f"ghost circle: expected degree 2 in t, got {poly.degree()}")
    _zero(poly.coeff_monomial(t**2) - L2 * orient2d(U, W, P), "ghost circle (leading coefficient)")


def proof_ghost_segment_rule() -> None:
    """For p = u + s(w − u) on the edge's line: incircle(u, w, c(t), p) = s(1 − s)|w − u|⁴ t (inside iff 0 < s < 1)."""
    on_line = (ux + s * (wx - ux), uy + s * (wy - uy))
    _zero(incircle(U, W, _far(t), on_line) - s * (1 - s) * L2**2 * t, "ghost segment rule")


def proof_chord_is_inside_every_circle() -> None:
    """For p = u + s(w − u): incircle(u, w, c, p) = s(1 − s)|w − u|² orient2d(u, w, c), for every c."""
    on_line = (ux + s * (wx - ux), uy + s * (wy - uy))
    _zero(incircle(U, W, (cx, cy), on_line) - s * (1 - s) * L2 * orient2d(U, W, (cx, cy)), "chord")


def proof_sector_test_is_orient2d() -> None:
    """(r − p) × (q − p) = rx·qy − ry·qx (differences to p) equals orient2d(p, r, q)."""
    rx, ry, qx, qy = sp.symbols("rx ry qx qy", real=True)
    fast = (rx - px) * (qy - py) - (ry - py) * (qx - px)
    _zero(fast - orient2d(P, (rx, ry), (qx, qy)), "sector test")


def proof_sector_float_path_is_exact() -> None:
    """On integers |x| ≤ 2^25 every operation of the fast sector test has an exact result of magnitude ≤ 2^53.

    IEEE 754 double arithmetic returns the exact result whenever it is
    representable, and every integer of magnitude ≤ 2^53 is: differences are at
    most 2^26, products at most 2^52, the final difference at most 2^53.
    """
    limit = 2**25
    diff = 2 * limit
    prod = diff * diff
    det = 2 * prod
    if not (diff <= 2**26 and prod <= 2**52 and det <= 2**53):
        raise AssertionError("sector float path: a bound is exceeded")
    for v in (diff, prod, det, det - 1, prod - 1):
        if int(float(v)) != v:
            raise AssertionError(f"sector float path: {v} is not a float64")
    from persistri.impl.terrain.sectors import EXACT_LIMIT

    if EXACT_LIMIT != float(limit):
        raise AssertionError(f"sector float path: the code's EXACT_LIMIT is {EXACT_LIMIT}, the proof's {limit}")


def proof_plane_passes_through_the_vertices() -> None:
    """z_a + gx (x − x_a) + gy (y − y_a), g by Cramer's rule as in plane_errors, equals z at a, b and c."""
    ax, ay, az, bx, by, bz, qx, qy, qz = sp.symbols("ax ay az bx by bz qx qy qz", real=True)
    dx1, dy1, dz1 = bx - ax, by - ay, bz - az
    dx2, dy2, dz2 = qx - ax, qy - ay, qz - az
    det = dx1 * dy2 - dx2 * dy1
    gx = (dz1 * dy2 - dz2 * dy1) / det
    gy = (dx1 * dz2 - dx2 * dz1) / det

    def plane(x: sp.Expr, y: sp.Expr) -> sp.Expr:
        return az + gx * (x - ax) + gy * (y - ay)

    for (x, y, z), name in (((ax, ay, az), "a"), ((bx, by, bz), "b"), ((qx, qy, qz), "c")):
        if sp.simplify(plane(x, y) - z) != 0:
            raise AssertionError(f"plane: does not pass through vertex {name}")
