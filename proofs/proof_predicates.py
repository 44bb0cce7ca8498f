"""Proofs for the exact predicates (:mod:`persistri.impl.geometry`).

* **SoS order** — sympy expands the perturbed orientation determinants Λ3
  (orient2d) and Λ4 (orient3d) of Edelsbrunner and Mücke, with
  ``π(i, j) = ε^(2^(iδ - j))``, orders the terms by their power of ε, and checks
  the implementation's tables :data:`~persistri.impl.geometry.sos.ORIENT2D_SOS`
  and :data:`~persistri.impl.geometry.sos.ORIENT3D_SOS` against it, signs
  included (each coefficient is ``sign · minor`` as the implementation's
  :func:`~persistri.impl.geometry.sos.minor` computes it).
* **Filter bounds** — a forward error analysis of the filter functions *as
  implemented*: :mod:`persistri.impl.geometry.filter`'s ``*_terms`` run on
  tracking numbers that model each float operation as ``exact · (1 + δ_i)``,
  ``|δ_i| <= u = 2^-53``; the resulting polynomials bound the error by the
  permanent, and the proof checks, in exact rational arithmetic, that each
  ``ERRBOUND_*`` constant is sufficient.
* **Lifting** — incircle is orient3d of the lifted points ``(x, y, x² + y²)``,
  with the sign convention documented in
  :mod:`persistri.impl.geometry.predicates`.
* **Operation counts** — the ``FLOPS_*`` constants count the operations of the
  filter functions.

The argument of the filter proof
--------------------------------
Let the filter compute ``det^`` and ``perm^`` from float inputs.  In the model,
``det^ = v^ (1 + δ_f)`` where ``v^`` is the exact result of the last operation
on its computed operands; ``sign(det^) = sign(v^)`` because rounding is
monotone and a nonzero sum never rounds to 0.  Expanding, ``v^ = Σ_T T ·
C_T(δ)`` over monomials ``T`` in the exact coordinate differences, and the
exact determinant is ``det = Σ_T T · C_T(0)``.  So

    |v^ - det| <= Σ_T |T| · R_T,   R_T = Σ_{α≠0} |c_α| u^|α|   (c_α the coefficients of C_T)
              <= ρ · P,            ρ = max_T R_T / |C_T(0)|,   P = Σ_T |T| |C_T(0)|.

The computed permanent is ``perm^ = Σ_T |T| · Q_T(δ)`` with ``Q_T(0) = |C_T(0)|``
(checked), so ``perm^ >= κ · P`` with ``κ = min_T q_T / Q_T(0)``, ``q_T = Q_T(0)
- Σ_{α≠0} |q_α| u^|α|``.  The threshold ``fl(B · perm^) >= (1 - u) B perm^``.
Hence ``|det^| > fl(B · perm^)`` gives ``|v^| >= |det^| / (1 + u) > (1 - u) B κ P
/ (1 + u) >= ρ P >= |v^ - det|`` — so ``sign(det) = sign(v^) = sign(det^)`` —
whenever ``B (1 - u) κ >= (1 + u) ρ``, which is what is checked.  The model's
validity (no overflow, no harmful underflow) is the grain argument of
:mod:`persistri.impl.geometry.filter`.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any

import sympy as sp
from sympy.combinatorics import Permutation
from sympy.polys.rings import PolyElement, PolyRing, ring

from persistri.impl.geometry import exact, sos
from persistri.impl.geometry import filter as fp

__all__ = [
    "proof_sos_orient2d_order",
    "proof_sos_orient3d_order",
    "proof_filter_bound_orient2d",
    "proof_filter_bound_orient3d",
    "proof_filter_bound_orient3d_plane",
    "proof_filter_bound_incircle",
    "proof_filter_flop_counts",
    "proof_lifting_identity",
]

U = Fraction(1, 2**53)


# -- Simulation of Simplicity -------------------------------------------------------------


def _leibniz(matrix: Sequence[Sequence[PolyElement]], rows: Sequence[int], cols: Sequence[int]) -> PolyElement:
    """``det(matrix[rows, cols])`` by the Leibniz formula (sympy's permutation signatures)."""
    total = matrix[0][0].ring.zero
    for perm in itertools.permutations(range(len(rows))):
        term = matrix[0][0].ring.one * Permutation(list(perm)).signature()
        for i, j in enumerate(perm):
            term *= matrix[rows[i]][cols[j]]
        total += term
    return total


def _sos_expansion(npoints: int, delta: int) -> list[tuple[int, tuple[int, ...], tuple[int, ...]]]:
    """The SoS sequence of the ``npoints × (delta + 1)`` orientation determinant, derived.

    Entry ``(i, j)`` (point ``i``, coordinate ``j``, both from 0) is perturbed by
    ``ε^(2^((i+1)δ - (j+1)))``; the last column (ones) is not perturbed.  The
    determinant is expanded with an independent symbol per perturbation; each
    monomial's ε-power is the sum of its entries' powers (distinct powers of two,
    so distinct sums).  Terms are sorted by increasing power (most significant
    first) up to the first constant one; each coefficient is matched to
    ``± det`` of the minor left after deleting the monomial's rows and columns.
    """
    coord_names = [f"p{i}_{j}" for i in range(npoints) for j in range(delta)]
    eps_names = [f"e{i}_{j}" for i in range(npoints) for j in range(delta)]
    r, *gens = ring(coord_names + eps_names, sp.ZZ)
    ncoords = len(coord_names)
    coords = [[gens[i * delta + j] for j in range(delta)] for i in range(npoints)]
    eps = [[gens[ncoords + i * delta + j] for j in range(delta)] for i in range(npoints)]
    perturbed = [[coords[i][j] + eps[i][j] for j in range(delta)] + [r.one] for i in range(npoints)]
    plain = [[coords[i][j] for j in range(delta)] + [r.one] for i in range(npoints)]
    everything = list(range(npoints))
    expansion = _leibniz(perturbed, everything, list(range(delta + 1)))
    # Group by the ε part: each ε-monomial's coefficient is a polynomial in the coordinates.
    by_eps: dict[tuple[int, ...], dict[tuple[int, ...], int]] = {}
    for mon, c in expansion.items():
        by_eps.setdefault(mon[ncoords:], {})[mon[:ncoords] + (0,) * ncoords] = c
    terms: list[tuple[int, tuple[int, ...], tuple[int, ...], PolyElement]] = []
    for powers, coeffs in by_eps.items():
        assert all(p <= 1 for p in powers), "a determinant is linear in each entry"
        entries = [divmod(k, delta) for k, p in enumerate(powers) if p]
        exponent = sum(2 ** ((i + 1) * delta - (j + 1)) for i, j in entries)
        rows = tuple(x for x in range(npoints) if x not in {i for i, _ in entries})
        cols = tuple(x for x in range(delta + 1) if x not in {j for _, j in entries})
        terms.append((exponent, rows, cols, r.from_dict(coeffs)))
    exponents = [t[0] for t in terms]
    assert len(set(exponents)) == len(exponents), "ε-powers of distinct terms must differ"
    terms.sort(key=lambda t: t[0])
    out: list[tuple[int, tuple[int, ...], tuple[int, ...]]] = []
    for _, rows, cols, coeff in terms:
        value = _leibniz(plain, rows, cols)
        assert sos.minor(plain, rows, cols) == value, "the implementation's minor is the determinant"
        if coeff == value:
            sign = 1
        elif coeff == -value:
            sign = -1
        else:
            raise AssertionError(f"coefficient {coeff} is not ± the minor rows={rows} cols={cols}")
        out.append((sign, rows, cols))
        if coeff.is_ground:
            assert coeff != 0
            return out
    raise AssertionError("the expansion has no constant term")


def _without_repeats(
    sequence: Sequence[tuple[int, tuple[int, ...], tuple[int, ...]]],
) -> list[tuple[int, tuple[int, ...], tuple[int, ...]]]:
    """Drop a term whose minor already occurred: it is reached only after that minor was 0."""
    seen: set[tuple[tuple[int, ...], tuple[int, ...]]] = set()
    out = []
    for sign, rows, cols in sequence:
        if (rows, cols) not in seen:
            seen.add((rows, cols))
            out.append((sign, rows, cols))
    return out


def proof_sos_orient2d_order() -> None:
    """Λ3 (orient2d, δ = 2): the implementation's SoS sequence is the sympy-derived expansion order, signs included."""
    derived = _sos_expansion(3, 2)
    assert len(derived) == 5
    assert _without_repeats(derived) == list(sos.ORIENT2D_SOS), (derived, sos.ORIENT2D_SOS)


def proof_sos_orient3d_order() -> None:
    """Λ4 (orient3d, δ = 3): the implementation's SoS sequence is the sympy-derived expansion order, signs included.

    The full expansion up to its first constant term has 18 terms; 3 repeat an
    earlier minor and are dropped, leaving Edelsbrunner–Mücke's 15.
    """
    derived = _sos_expansion(4, 3)
    assert len(derived) == 18
    reduced = _without_repeats(derived)
    assert len(reduced) == 15
    assert reduced == list(sos.ORIENT3D_SOS), (reduced, sos.ORIENT3D_SOS)


# -- the floating-point filters -----------------------------------------------------------

_ATOMS = 12  # exact coordinate differences (at most 9 in orient3d)
_DELTAS = 64  # rounding errors (orient3d's filter has 40 operations, the prepared plane's 34 roundings)


class _Model:
    """The standard model of float arithmetic as polynomials over exact atoms and δ's.

    Generators: ``D0..`` exact coordinate differences, ``A0..`` their absolute
    values, ``d0..`` the relative rounding errors.
    """

    def __init__(self) -> None:
        names = (
            [f"D{k}" for k in range(_ATOMS)] + [f"A{k}" for k in range(_ATOMS)] + [f"d{k}" for k in range(_DELTAS)]
        )
        self.ring: PolyRing = ring(names, sp.ZZ)[0]
        self.atoms: list[tuple[str, str]] = []  # D_k = first - second (coordinate names)
        self.deltas = 0

    def one_plus_delta(self) -> tuple[PolyElement, int]:
        k = self.deltas
        assert k < _DELTAS
        self.deltas += 1
        return self.ring.one + self.ring.gens[2 * _ATOMS + k], 2 * _ATOMS + k

    def atom(self, first: str, second: str) -> PolyElement:
        k = len(self.atoms)
        assert k < _ATOMS
        self.atoms.append((first, second))
        gen: PolyElement = self.ring.gens[k]
        return gen


class _Rounded:
    """A float value in the model: ``poly`` (for an input, ``name``); ``product`` if no sum is inside."""

    __slots__ = ("model", "poly", "name", "product", "root")

    def __init__(
        self, model: _Model, poly: PolyElement | None, *, name: str | None = None, product: bool, root: int | None
    ) -> None:
        self.model = model
        self.poly = poly
        self.name = name
        self.product = product
        self.root = root  # the generator index of the δ of the operation that made this value

    def _op(self, other: _Rounded, op: str) -> _Rounded:
        m = self.model
        factor, root = m.one_plus_delta()
        if self.poly is None and other.poly is None:
            assert op == "-", "the filters only subtract input coordinates"
            assert self.name is not None and other.name is not None
            return _Rounded(m, m.atom(self.name, other.name) * factor, product=True, root=root)
        assert self.poly is not None and other.poly is not None, "inputs are only ever subtracted"
        if op == "+":
            return _Rounded(m, (self.poly + other.poly) * factor, product=False, root=root)
        if op == "-":
            return _Rounded(m, (self.poly - other.poly) * factor, product=False, root=root)
        return _Rounded(m, self.poly * other.poly * factor, product=self.product and other.product, root=root)

    def __add__(self, other: _Rounded) -> _Rounded:
        return self._op(other, "+")

    def __sub__(self, other: _Rounded) -> _Rounded:
        return self._op(other, "-")

    def __mul__(self, other: _Rounded) -> _Rounded:
        return self._op(other, "*")

    def __abs__(self) -> _Rounded:
        """``|x|`` is exact; for a product ``c · T · Π(1 + δ)`` it is ``|c| · |T| · Π(1 + δ)``."""
        assert self.poly is not None and self.product, "the filters take |·| of products only"
        d_parts = {mon[:_ATOMS] for mon in self.poly.keys()}
        assert len(d_parts) == 1, "a product has one monomial in the differences"
        const = self.poly.get(next(iter(d_parts)) + (0,) * (_ATOMS + _DELTAS), 0)
        assert const != 0, "a product's exact part is nonzero"
        sign = 1 if const > 0 else -1
        flipped: dict[tuple[int, ...], Fraction] = {}
        for mon, c in self.poly.items():
            d, a, e = mon[:_ATOMS], mon[_ATOMS : 2 * _ATOMS], mon[2 * _ATOMS :]
            assert not any(a)
            flipped[(0,) * _ATOMS + d + e] = sign * c
        return _Rounded(self.model, self.poly.ring.from_dict(flipped), product=True, root=self.root)


def _group(poly: PolyElement, part: slice) -> dict[tuple[int, ...], dict[tuple[int, ...], int]]:
    """Terms of ``poly`` grouped by their exponents in ``part`` (the atoms), the rest keyed by δ exponents."""
    out: dict[tuple[int, ...], dict[tuple[int, ...], int]] = {}
    for mon, c in poly.items():
        assert not any(mon[: part.start]) and not any(mon[part.stop : 2 * _ATOMS])
        out.setdefault(mon[part], {})[mon[2 * _ATOMS :]] = int(c)
    return out


def _deviation(coeffs: dict[tuple[int, ...], int]) -> tuple[int, Fraction]:
    """``(C(0), Σ_{α≠0} |c_α| u^|α|)`` of a polynomial in the δ's."""
    zero = (0,) * _DELTAS
    rest = sum((abs(c) * U ** sum(a) for a, c in coeffs.items() if a != zero), Fraction(0))
    return coeffs.get(zero, 0), rest


def _check_filter(
    terms: Callable[..., tuple[Any, Any]],
    inputs: Sequence[str],
    expected: sp.Expr,
    errbound: float,
) -> Fraction:
    """Run ``terms`` in the model; check ``det|δ=0 == expected`` and ``errbound`` sufficient. Returns the margin."""
    model = _Model()
    args = [_Rounded(model, None, name=n, product=True, root=None) for n in inputs]
    det, perm = terms(*args)
    assert det.root is not None
    symbols = {n: sp.Symbol(n) for n in inputs}
    r = model.ring
    ngens = r.ngens
    # v^: the determinant before its last rounding (drop the terms carrying the root δ).
    vhat = {mon: c for mon, c in det.poly.items() if mon[det.root] == 0}
    by_t = _group(r.from_dict(vhat), slice(0, _ATOMS))
    # δ = 0: the exact determinant, as a polynomial in the differences, is the expected one.
    zero = (0,) * _DELTAS
    d_syms = [sp.Symbol(f"D{k}") for k in range(len(model.atoms))]
    exact_det = sum(
        (c[zero] * sp.Mul(*[d_syms[k] ** e for k, e in enumerate(t) if e]) for t, c in by_t.items() if zero in c),
        sp.Integer(0),
    )
    substituted = exact_det.subs(
        {d_syms[k]: symbols[a] - symbols[b] for k, (a, b) in enumerate(model.atoms)}, simultaneous=True
    )
    assert sp.expand(substituted - expected) == 0, "the filter's exact value is not the determinant"
    # The error bound ρ.
    rho = Fraction(0)
    c0: dict[tuple[int, ...], int] = {}
    for t, coeffs in by_t.items():
        const, dev = _deviation(coeffs)
        assert const != 0, f"monomial {t} has no exact part"
        c0[t] = abs(const)
        rho = max(rho, dev / abs(const))
    # The permanent: differences appear only as |D| or squared (the lifts).
    flipped: dict[tuple[int, ...], int] = {}
    for mon, c in perm.poly.items():
        d, a, e = mon[:_ATOMS], mon[_ATOMS : 2 * _ATOMS], mon[2 * _ATOMS :]
        assert all(x % 2 == 0 for x in d), "a difference enters the permanent with its sign"
        merged = tuple(x + y for x, y in zip(d, a))
        flipped[(0,) * _ATOMS + merged + e] = flipped.get((0,) * _ATOMS + merged + e, 0) + int(c)
    by_abs = _group(r.from_dict(flipped), slice(_ATOMS, 2 * _ATOMS))
    assert set(by_abs) == set(c0), "the permanent must have the determinant's monomials"
    kappa = Fraction(1)
    for t, coeffs in by_abs.items():
        const, dev = _deviation(coeffs)
        assert const == c0[t], f"permanent coefficient {const} of {t} is not |{c0[t]}|"
        lower = const - dev
        assert lower > 0
        kappa = min(kappa, lower / const)
    assert ngens == 2 * _ATOMS + _DELTAS
    b = Fraction(errbound)
    needed = (1 + U) * rho / ((1 - U) * kappa)
    assert b >= needed, f"ERRBOUND {float(b / U)}u is below the proved need {float(needed / U)}u"
    return b - needed


def _lifted_matrix(points: Sequence[tuple[str, str]]) -> sp.Matrix:
    rows = []
    for xn, yn in points:
        x, y = sp.Symbol(xn), sp.Symbol(yn)
        rows.append([x, y, x**2 + y**2, 1])
    return sp.Matrix(rows)


def proof_filter_bound_orient2d() -> None:
    """ERRBOUND_ORIENT2D is a sufficient filter constant for orient2d_terms, whose exact value is det[[x, y, 1]]."""
    names = ["ax", "ay", "bx", "by", "cx", "cy"]
    s = [sp.Symbol(n) for n in names]
    expected = sp.Matrix([[s[0], s[1], 1], [s[2], s[3], 1], [s[4], s[5], 1]]).det()
    _check_filter(fp.orient2d_terms, names, expected, fp.ERRBOUND_ORIENT2D)


def proof_filter_bound_orient3d() -> None:
    """ERRBOUND_ORIENT3D is a sufficient filter constant for orient3d_terms, whose exact value is det[[x, y, z, 1]]."""
    names = [f"{p}{c}" for p in "abcd" for c in "xyz"]
    s = [sp.Symbol(n) for n in names]
    expected = sp.Matrix([[s[3 * i], s[3 * i + 1], s[3 * i + 2], 1] for i in range(4)]).det()
    _check_filter(fp.orient3d_terms, names, expected, fp.ERRBOUND_ORIENT3D)


def proof_filter_bound_orient3d_plane() -> None:
    """ERRBOUND_PLANE_SIDE is a sufficient filter constant for orient3d_plane_terms (plane_terms, then
    plane_side_terms), whose exact value is det[[x, y, z, 1]] of a, b, c, q."""
    names = [f"{p}{c}" for p in "abcq" for c in "xyz"]
    s = [sp.Symbol(n) for n in names]
    expected = sp.Matrix([[s[3 * i], s[3 * i + 1], s[3 * i + 2], 1] for i in range(4)]).det()
    _check_filter(fp.orient3d_plane_terms, names, expected, fp.ERRBOUND_PLANE_SIDE)


def proof_filter_bound_incircle() -> None:
    """ERRBOUND_INCIRCLE is a sufficient filter constant for incircle_terms, whose exact value is det[[x, y, x²+y², 1]]."""
    names = [f"{p}{c}" for p in "abcd" for c in "xy"]
    expected = _lifted_matrix([(f"{p}x", f"{p}y") for p in "abcd"]).det()
    _check_filter(fp.incircle_terms, names, expected, fp.ERRBOUND_INCIRCLE)


class _Counter:
    """A number that counts the operations done on it."""

    count = 0

    def _tick(self, _other: object = None) -> _Counter:
        _Counter.count += 1
        return self

    __add__ = __sub__ = __mul__ = _tick

    def __abs__(self) -> _Counter:
        return self._tick()


def proof_filter_flop_counts() -> None:
    """FLOPS_* equal the operations (+, -, ×, |·|) of each filter function plus the threshold product."""
    for terms, arity, flops in (
        (fp.orient2d_terms, 6, fp.FLOPS_ORIENT2D),
        (fp.orient3d_terms, 12, fp.FLOPS_ORIENT3D),
        (fp.incircle_terms, 8, fp.FLOPS_INCIRCLE),
    ):
        _Counter.count = 0
        terms(*[_Counter() for _ in range(arity)])
        assert _Counter.count + 1 == flops, (terms.__name__, _Counter.count + 1, flops)
    # A prepared plane: its preparation once (no threshold), then per point the side test and its threshold.
    _Counter.count = 0
    fp.plane_terms(*[_Counter() for _ in range(9)])
    assert _Counter.count == fp.FLOPS_PLANE, ("plane_terms", _Counter.count, fp.FLOPS_PLANE)
    _Counter.count = 0
    fp.plane_side_terms(*[_Counter() for _ in range(12)])
    assert _Counter.count + 1 == fp.FLOPS_PLANE_SIDE, ("plane_side_terms", _Counter.count + 1, fp.FLOPS_PLANE_SIDE)


# -- lifting ------------------------------------------------------------------------------


def proof_lifting_identity() -> None:
    """incircle(a, b, c, d) is the orient3d determinant of the lifted points (x, y, x² + y²), no sign change.

    Checked for the implementation's exact formulas (``exact.incircle_det`` and
    ``exact.orient3d_det`` on lifted coordinates) against the 4×4 determinant
    with rows ``(x, y, x² + y², 1)``, and the sign convention on an instance:
    ``a, b, c`` counterclockwise on the unit circle, ``d`` at its centre (inside)
    gives a positive value, ``d`` outside a negative one.
    """
    xs = {p: (sp.Symbol(f"{p}x"), sp.Symbol(f"{p}y")) for p in "abcd"}
    lifted = _lifted_matrix([(f"{p}x", f"{p}y") for p in "abcd"]).det()
    incircle = exact.incircle_det(*[v for p in "abcd" for v in xs[p]])
    orient = exact.orient3d_det(*[v for p in "abcd" for v in (xs[p][0], xs[p][1], xs[p][0] ** 2 + xs[p][1] ** 2)])
    assert sp.expand(incircle - lifted) == 0
    assert sp.expand(orient - lifted) == 0
    ccw = [(1, 0), (0, 1), (-1, 0)]
    assert exact.orient2d_det(*[v for p in ccw for v in p]) > 0
    (ax, ay), (bx, by), (cx, cy) = ccw
    assert exact.incircle_det(ax, ay, bx, by, cx, cy, 0, 0) > 0
    assert exact.incircle_det(ax, ay, bx, by, cx, cy, 2, 0) < 0
