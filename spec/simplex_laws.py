"""The laws of ``signature SIMPLEX`` (paper Fig. 2), as executable code.

An ordered n-simplex is a sequence of n+1 distinct vertices, apex first; an
oriented simplex is its class under *even* permutations.  The laws pin down
what the paper's prose says of ``compare``, ``faces``, ``flip``, ``down`` and
``join`` (the four lines of Fig. 2 lost in extraction).  Each ``law_*``
function raises :class:`LawViolation` on failure; an unexpected exception from
the structure is reported as a violation of the law being checked.

The laws compute the expected orientation themselves, from the positions of
the vertices (the parity of a permutation of indices), and compare with the
structure's ``compare`` — so they test the structure's orientation handling,
not restate it.  All functions are O(n!) at worst (``compare_orientation``
tries every permutation); n ≤ 4 in practice.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import permutations
from typing import TypeVar

from persistri.spec.law import SignatureLawViolation, law_decorator
from persistri.spec.order import Order
from persistri.spec.simplex import SIMPLEX

__all__ = [
    "SIMPLEX_LAWS",
    "LawViolation",
    "permutation_parity",
    "law_dim",
    "law_simplex_vertices",
    "law_compare_order",
    "law_compare_orientation",
    "law_faces_induced",
    "law_down_join",
    "law_flip",
    "check_simplex_laws",
]

Vx = TypeVar("Vx")
Sx = TypeVar("Sx")

SIMPLEX_LAWS: dict[str, str] = {
    "dim": "dim(s) = len(vertices(s)) - 1",
    "simplex_vertices": "vertices(simplex(vs)) = vs, in order (apex first)",
    "compare_order": "compare is a total order on simplices: reflexive, antisymmetric and transitive",
    "compare_orientation": "compare(simplex(p), s) = EQUAL exactly when the order p is an even permutation "
    "of vertices(s); odd permutations are the other orientation",
    "faces_induced": "faces(s) of an n-simplex are n+1 (n-1)-simplices which, in some order, are the "
    "induced faces: vertices(s) without its i-th vertex, flipped when i is odd "
    "(for (a, b, c): (b, c), (c, a), (a, b))",
    "down_join": "down(s) = (vertices(s)[0], the simplex of vertices(s)[1:]) and vertices(join(down(s))) = vertices(s)",
    "flip": "flip(flip(s)) = s as an oriented simplex, flip(s) has the vertices of s, and for dim(s) >= 1 "
    "flip(s) is the other orientation (compare ≠ EQUAL)",
}
"""Every ``SIMPLEX`` law: name → statement."""


class LawViolation(SignatureLawViolation):
    """A structure broke a ``SIMPLEX`` law (a :class:`persistri.spec.law.LawViolation`)."""

    SIGNATURE = "SIMPLEX"
    LAWS = SIMPLEX_LAWS


_law = law_decorator(LawViolation)


def permutation_parity(p: Sequence[int]) -> int:
    """0 for an even permutation of ``range(len(p))``, 1 for an odd one (inversions mod 2)."""
    inv = sum(1 for i in range(len(p)) for j in range(i + 1, len(p)) if p[j] < p[i])
    return inv & 1


def _same_vertices(S: SIMPLEX[Vx, Sx], xs: Sequence[Vx], ys: Sequence[Vx]) -> bool:
    """Equal sequences of vertices, position by position (``Vertex.compare``)."""
    cmp = S.Vertex.compare
    return len(xs) == len(ys) and all(cmp(x, y) is Order.EQUAL for x, y in zip(xs, ys))


def _induced(S: SIMPLEX[Vx, Sx], vs: Sequence[Vx], i: int) -> Sx:
    """The i-th induced face, built from positions: drop vertex i, swap the last two when i is odd."""
    rest = list(vs[:i]) + list(vs[i + 1 :])
    if i % 2 == 1 and len(rest) >= 2:
        rest[-1], rest[-2] = rest[-2], rest[-1]
    return S.simplex(rest)


@_law("dim")
def law_dim(S: SIMPLEX[Vx, Sx], s: Sx) -> None:
    """``dim(s) = len(vertices(s)) - 1``."""
    d, vs = S.dim(s), S.vertices(s)
    if d != len(vs) - 1:
        raise LawViolation("dim", f"dim({s!r}) = {d} but it has {len(vs)} vertices")


@_law("simplex_vertices")
def law_simplex_vertices(S: SIMPLEX[Vx, Sx], vs: Sequence[Vx]) -> None:
    """``vertices(simplex(vs)) = vs`` in order."""
    got = S.vertices(S.simplex(vs))
    if not _same_vertices(S, got, vs):
        raise LawViolation("simplex_vertices", f"vertices(simplex({list(vs)!r})) = {list(got)!r}")


@_law("compare_order")
def law_compare_order(S: SIMPLEX[Vx, Sx], ss: Sequence[Sx]) -> None:
    """``compare`` is a total order on ``ss``.  O(len(ss)³)."""
    for a in ss:
        if S.compare(a, a) is not Order.EQUAL:
            raise LawViolation("compare_order", f"compare({a!r}, {a!r}) = {S.compare(a, a)}")
        for b in ss:
            ab, ba = S.compare(a, b), S.compare(b, a)
            if ab is not -ba:
                raise LawViolation("compare_order", f"compare({a!r}, {b!r}) = {ab} but compare({b!r}, {a!r}) = {ba}")
            for c in ss:
                bc, ac = S.compare(b, c), S.compare(a, c)
                if ab is not Order.GREATER and bc is not Order.GREATER and ac is Order.GREATER:
                    raise LawViolation("compare_order", f"{a!r} <= {b!r} <= {c!r} but compare({a!r}, {c!r}) = GREATER")


@_law("compare_orientation")
def law_compare_orientation(S: SIMPLEX[Vx, Sx], s: Sx) -> None:
    """Every reordering of ``s`` compares EQUAL to it exactly when it is an even permutation.  O((n+1)!)."""
    vs = list(S.vertices(s))
    for p in permutations(range(len(vs))):
        t = S.simplex([vs[i] for i in p])
        even = permutation_parity(p) == 0
        if (S.compare(t, s) is Order.EQUAL) != even:
            kind = "an even" if even else "an odd"
            raise LawViolation(
                "compare_orientation", f"compare({t!r}, {s!r}) = {S.compare(t, s)} for {kind} permutation {p!r}"
            )


@_law("faces_induced")
def law_faces_induced(S: SIMPLEX[Vx, Sx], s: Sx) -> None:
    """``faces(s)`` is, as oriented simplices and in some order, the induced faces of ``s``."""
    vs = list(S.vertices(s))
    fs = list(S.faces(s))
    if len(fs) != len(vs):
        raise LawViolation("faces_induced", f"faces({s!r}) has {len(fs)} faces, expected {len(vs)}")
    expected = [_induced(S, vs, i) for i in range(len(vs))]
    unmatched = list(fs)
    for i, e in enumerate(expected):
        hit = next((k for k, f in enumerate(unmatched) if S.compare(f, e) is Order.EQUAL), None)
        if hit is None:
            raise LawViolation(
                "faces_induced", f"faces({s!r}) = {fs!r} lacks {e!r} (vertex {i} dropped{', flipped' if i % 2 else ''})"
            )
        unmatched.pop(hit)
    for f in fs:
        if S.dim(f) != len(vs) - 2:
            raise LawViolation("faces_induced", f"face {f!r} of {s!r} has dimension {S.dim(f)}")


@_law("down_join")
def law_down_join(S: SIMPLEX[Vx, Sx], s: Sx) -> None:
    """``down(s) = (apex, rest)`` with ``rest`` the simplex of the other vertices in order, and ``join(down(s))`` is ``s``."""
    vs = list(S.vertices(s))
    v, f = S.down(s)
    if not _same_vertices(S, [v], vs[:1]) or not _same_vertices(S, list(S.vertices(f)), vs[1:]):
        raise LawViolation("down_join", f"down({s!r}) = ({v!r}, {f!r})")
    back = S.join(v, f)
    if not _same_vertices(S, list(S.vertices(back)), vs):
        raise LawViolation("down_join", f"join(down({s!r})) = {back!r}")


@_law("flip")
def law_flip(S: SIMPLEX[Vx, Sx], s: Sx) -> None:
    """``flip`` is an involution on oriented simplices that keeps the vertices and, from dimension 1, reverses."""
    f = S.flip(s)
    ff = S.flip(f)
    if S.compare(ff, s) is not Order.EQUAL:
        raise LawViolation("flip", f"flip(flip({s!r})) = {ff!r}")
    vs, fvs = list(S.vertices(s)), list(S.vertices(f))
    cmp = S.Vertex.compare
    if len(vs) != len(fvs) or not all(any(cmp(a, b) is Order.EQUAL for b in fvs) for a in vs):
        raise LawViolation("flip", f"flip({s!r}) = {f!r} has other vertices")
    if S.dim(s) >= 1 and S.compare(f, s) is Order.EQUAL:
        raise LawViolation("flip", f"flip({s!r}) = {f!r} has the same orientation")


def check_simplex_laws(S: SIMPLEX[Vx, Sx], s: Sx) -> None:
    """Every single-simplex law on ``s`` (all but ``compare_order``, which needs several)."""
    law_dim(S, s)
    law_simplex_vertices(S, list(S.vertices(s)))
    law_compare_orientation(S, s)
    if S.dim(s) >= 1:
        law_faces_induced(S, s)
    law_down_join(S, s)
    law_flip(S, s)
