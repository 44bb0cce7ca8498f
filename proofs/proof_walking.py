"""Proofs for the bulldozer's walking graph (paper Appendix A.1.1): its tests are signs of orient3d.

The bulldozer (:mod:`persistri.impl.hull.bulldozer`) decides everything with one
predicate, ``orient3d(a, b, c, d) = det[[a, 1], [b, 1], [c, 1], [d, 1]]``
(:mod:`persistri.impl.geometry.predicates`).  The paper states its tests
geometrically; these proofs show, as polynomial identities in the coordinates
(sympy, exact), that each geometric test is the sign of a named orient3d:

* **plane side** — for the plane through ``a, b, c`` with right-hand normal
  ``n = (b − a) × (c − a)``, ``n · (d − a) = −orient3d(a, b, c, d)``: ``d`` is on the
  normal's side ("above", "sees the face") iff ``orient3d(a, b, c, d) = −1``;
* **Definition 1** — "S(e, c) is visible to p with respect to S(B, c)": the facet
  ``(u, w, c)`` of the tetrahedron ``(u, w, c, b)`` is visible from ``p`` iff ``p`` and
  ``b`` are on opposite sides of the plane through ``u, w, c``, i.e.
  ``orient3d(u, w, c, p) = −orient3d(u, w, c, b)``.  The code compares with the
  third vertex ``f`` of the *other* face ``A`` instead, which is the same test
  because ``f`` and ``b`` are on opposite sides of that plane whenever the centre
  lies strictly inside the dihedral wedge of the edge: proved below as the
  identity ``D(f) · D(b) = −α β det[w − u, b − u, f − u]²`` for ``c − u = α(f − u) +
  β(b − u) + γ(w − u)``;
* **Theorem 3 / Lemma 4 / Definition 5** — projecting along ``d = p − c`` onto a
  plane perpendicular to it sends ``c`` and ``p`` to one point (so the rays
  ``c → q`` and ``p → q`` project to the same ray: Lemma 4); the orientation of
  projected points, measured against ``d``, is the triple product of the
  unprojected differences with ``d``; hence "which side of the projected line
  through ``c``/``p`` and ``v`` is ``q``" is (minus) the sign of ``orient3d(c, p, v, q)``
  (the code's routing test between two out-edges sharing ``v``), and "which side
  of the projected edge ``(u, w)`` is the projection of ``p``" is the sign of
  ``orient3d(u, w, c, p)`` — the very determinant of Definition 1.

What is *not* proved here but tested (``convex_hull(..., check=True)`` at every
insertion): Theorem 2 (acyclicity), Lemma 9 (reachability), Theorems 6 and 7
(the associated faces of bulldozed points) — they are geometric statements
about convex hulls, checked exactly on every run with ``check=True``.
"""

from __future__ import annotations

import sympy as sp

__all__ = [
    "proof_plane_side_is_orient3d",
    "proof_definition1_opposite_sides",
    "proof_projection_identifies_c_and_p",
    "proof_projected_orientation_is_triple_product",
    "proof_routing_test_is_orient3d",
    "proof_projected_edge_test_is_definition1",
    "proof_signs_the_bulldozer_derives",
]


def _pt(name: str) -> sp.Matrix:
    return sp.Matrix(sp.symbols(f"{name}x {name}y {name}z", real=True))


def orient3d(a: sp.Matrix, b: sp.Matrix, c: sp.Matrix, d: sp.Matrix) -> sp.Expr:
    """``det[[a, 1], [b, 1], [c, 1], [d, 1]]``: the predicate as the code defines it."""
    rows = [list(p) + [1] for p in (a, b, c, d)]
    return sp.Matrix(rows).det()


def triple(x: sp.Matrix, y: sp.Matrix, z: sp.Matrix) -> sp.Expr:
    """``det[x, y, z]`` (rows): the triple product ``(x × y) · z``."""
    return sp.Matrix.hstack(x, y, z).T.det()


def _zero(expr: sp.Expr, what: str) -> None:
    if sp.expand(expr) != 0:
        raise AssertionError(f"{what}: the identity does not hold (residue {sp.factor(expr)})")


a, b, c, d = _pt("a"), _pt("b"), _pt("c"), _pt("d")
u, w, f, q, p, v, ctr = _pt("u"), _pt("w"), _pt("f"), _pt("q"), _pt("p"), _pt("v"), _pt("k")


def proof_plane_side_is_orient3d() -> None:
    """n · (d − a) = −orient3d(a, b, c, d) for the right-hand normal n of (a, b, c): "d sees face abc" ⇔ orient3d = −1."""
    n = (b - a).cross(c - a)
    _zero(n.dot(d - a) + orient3d(a, b, c, d), "plane side")


def proof_definition1_opposite_sides() -> None:
    """With c − u = α(f − u) + β(b − u) + γ(w − u): D(f)·D(b) = −αβ·det[w−u, b−u, f−u]², D(x) = orient3d(u, w, c, x).

    So for α, β > 0 (the centre strictly inside the dihedral wedge of edge
    (u, w) between faces A = (u, w, f) and B = (w, u, b)) and a non-flat edge, f and
    b are strictly on opposite sides of the plane through u, w, c: the code's test
    ``orient3d(u, w, c, p) == orient3d(u, w, c, f)`` equals Definition 1's
    ``orient3d(u, w, c, p) == −orient3d(u, w, c, b)``.
    """
    al, be, ga = sp.symbols("alpha beta gamma", real=True)
    cc = u + al * (f - u) + be * (b - u) + ga * (w - u)
    lhs = orient3d(u, w, cc, f) * orient3d(u, w, cc, b)
    rhs = -al * be * triple(w - u, b - u, f - u) ** 2
    _zero(lhs - rhs, "Definition 1")


def _proj(x: sp.Matrix, dvec: sp.Matrix) -> sp.Matrix:
    """Orthogonal projection of x onto the plane through the origin perpendicular to dvec (scaled by d·d)."""
    dd = dvec.dot(dvec)
    return x * dd - dvec * x.dot(dvec)  # (d·d)·proj(x): keeps everything polynomial


def proof_projection_identifies_c_and_p() -> None:
    """Lemma 4: projecting along d = p − c maps c and p to the same point, so rays c→q and p→q project alike."""
    dvec = p - ctr
    _zero((_proj(p, dvec) - _proj(ctr, dvec)).dot(sp.Matrix([1, 1, 1])), "projection of c and p (sum)")
    for i in range(3):
        _zero((_proj(p, dvec) - _proj(ctr, dvec))[i], f"projection of c and p (coordinate {i})")


def proof_projected_orientation_is_triple_product() -> None:
    """Theorem 3: det[x' − a', y' − a', d] = (d·d)² det[x − a, y − a, d] for projections x' along d."""
    dvec = p - ctr
    dd = dvec.dot(dvec)
    lhs = triple(_proj(b, dvec) - _proj(a, dvec), _proj(c, dvec) - _proj(a, dvec), dvec)
    _zero(lhs - dd**2 * triple(b - a, c - a, dvec), "projected orientation")


def proof_routing_test_is_orient3d() -> None:
    """Definition 5: the side of q's projection w.r.t. the projected line through c(=p) and v is −sign orient3d(c, p, v, q).

    det[v − c, q − c, p − c] = −orient3d(c, p, v, q), and by the previous proof the
    projected 2D orientation of (c', v', q') against d has the sign of the former.
    The code compares ``orient3d(c, p, v, q)`` with ``orient3d(c, p, v, x)`` for a
    vertex x of the out-edge, so only the sign's consistency matters.
    """
    _zero(triple(v - ctr, q - ctr, p - ctr) + orient3d(ctr, p, v, q), "routing test")


def proof_projected_edge_test_is_definition1() -> None:
    """Theorem 3: the side of the projection of p (= of c) w.r.t. the projected edge (u, w) is −sign orient3d(u, w, c, p).

    det[w − u, c − u, p − c] = −orient3d(u, w, c, p): the projected test of
    Theorem 3 and the 3D test of Definition 1 are the same determinant.
    """
    _zero(triple(w - u, ctr - u, p - ctr) + orient3d(u, w, ctr, p), "projected edge test")


def proof_signs_the_bulldozer_derives() -> None:
    """The permutations behind the signs the bulldozer derives instead of testing (``check=True`` tests them).

    * ``orient3d(u, w, c, f) = −orient3d(u, w, f, c)``: the centre is strictly
      behind every outward face ``(u, w, f)`` (``orient3d(u, w, f, c) = +1``), so
      Definition 1's comparison sign is always −1 and the arc test is the one
      sign ``orient3d(u, w, c, p) = −1``;
    * ``orient3d(w, u, c, p) = −orient3d(u, w, c, p)``: the neighbour across the
      edge sees the opposite sign, so each edge is an arc in one direction only;
    * ``orient3d(c, p, x, y) = orient3d(x, y, c, p)`` and ``orient3d(c, p, y, x) =
      −orient3d(x, y, c, p)``: the routing comparisons of a face with two or three
      out-edges are out-arc signs, known from the walking graph.
    """
    _zero(orient3d(u, w, ctr, f) + orient3d(u, w, f, ctr), "centre behind the face")
    _zero(orient3d(w, u, ctr, p) + orient3d(u, w, ctr, p), "the edge seen from both faces")
    _zero(orient3d(ctr, p, u, w) - orient3d(u, w, ctr, p), "routing sign of an out-edge (x, y)")
    _zero(orient3d(ctr, p, w, u) + orient3d(u, w, ctr, p), "routing sign of an out-edge (y, x)")
