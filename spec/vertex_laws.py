"""The laws of ``signature VERTEX`` (paper Fig. 1), as executable code.

Each ``law_*`` function checks one law on the inputs it is given and raises
:class:`LawViolation` (naming the law, stating it, and showing the evidence)
when the structure breaks it; an unexpected exception from the structure is
reported as a violation of the law being checked.  :data:`VERTEX_LAWS` lists
them.  The laws speak only of the signature's operations: ``compare``, ``new``
and ``loc``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, TypeVar

from persistri.spec.law import SignatureLawViolation, law_decorator
from persistri.spec.order import Order
from persistri.spec.vertex import VERTEX

__all__ = [
    "VERTEX_LAWS",
    "LawViolation",
    "law_compare_total",
    "law_new_loc",
    "law_new_deterministic",
    "law_new_fresh",
]

Vx = TypeVar("Vx")
St = TypeVar("St")
Pt = TypeVar("Pt")

VERTEX_LAWS: dict[str, str] = {
    "compare_total": "compare is a total order: compare(a, a) = EQUAL, compare(b, a) = -compare(a, b), "
    "and LESS is transitive",
    "new_loc": "loc(v) is the point p when (s', v) = new(s, p)",
    "new_deterministic": "new is a function of its arguments: new(s, p) again gives an EQUAL vertex, "
    "and the two states it returns go on to make EQUAL vertices",
    "new_fresh": "a vertex made by new differs (compare ≠ EQUAL) from every vertex made earlier along its history of states",
}
"""Every ``VERTEX`` law: name → statement."""


class LawViolation(SignatureLawViolation):
    """A structure broke a ``VERTEX`` law (a :class:`persistri.spec.law.LawViolation`)."""

    SIGNATURE = "VERTEX"
    LAWS = VERTEX_LAWS


_law = law_decorator(LawViolation)


@_law("compare_total")
def law_compare_total(V: VERTEX[Vx, Any, Any], vs: Sequence[Vx]) -> None:
    """``compare`` is a total order on the vertices ``vs``.  O(len(vs)³) compares."""
    for a in vs:
        if V.compare(a, a) is not Order.EQUAL:
            raise LawViolation("compare_total", f"compare({a!r}, {a!r}) = {V.compare(a, a)}")
        for b in vs:
            ab, ba = V.compare(a, b), V.compare(b, a)
            if ab is not -ba:
                raise LawViolation("compare_total", f"compare({a!r}, {b!r}) = {ab} but compare({b!r}, {a!r}) = {ba}")
            if ab is not Order.LESS:
                continue
            for c in vs:
                if V.compare(b, c) is Order.LESS and V.compare(a, c) is not Order.LESS:
                    raise LawViolation("compare_total", f"{a!r} < {b!r} < {c!r} but compare({a!r}, {c!r}) = {V.compare(a, c)}")


@_law("new_loc")
def law_new_loc(V: VERTEX[Vx, St, Pt], s: St, p: Pt) -> None:
    """``loc(snd(new(s, p)))`` is ``p`` (identical, or ``==``)."""
    _, v = V.new(s, p)
    q = V.loc(v)
    if q is not p and q != p:
        raise LawViolation("new_loc", f"new(s, {p!r}) made {v!r} with loc {q!r}")


@_law("new_deterministic")
def law_new_deterministic(V: VERTEX[Vx, St, Pt], s: St, p: Pt, q: Pt) -> None:
    """``new(s, p)`` twice gives EQUAL vertices, and their states then make EQUAL vertices at ``q``."""
    s1, v1 = V.new(s, p)
    s2, v2 = V.new(s, p)
    if V.compare(v1, v2) is not Order.EQUAL:
        raise LawViolation("new_deterministic", f"new(s, {p!r}) gave {v1!r} and then {v2!r}")
    w1, w2 = V.new(s1, q)[1], V.new(s2, q)[1]
    if V.compare(w1, w2) is not Order.EQUAL:
        raise LawViolation("new_deterministic", f"the two states after new(s, {p!r}) made {w1!r} and {w2!r}")


@_law("new_fresh")
def law_new_fresh(V: VERTEX[Vx, St, Pt], s: St, points: Sequence[Pt]) -> list[Vx]:
    """Creating a vertex at each of ``points`` in turn gives pairwise distinct vertices, each at its point.

    Returns the vertices.  O(len(points)²) compares.
    """
    made: list[Vx] = []
    for p in points:
        s, v = V.new(s, p)
        for w in made:
            if V.compare(v, w) is Order.EQUAL:
                raise LawViolation("new_fresh", f"new made {v!r} at {p!r}, EQUAL to the earlier {w!r}")
        q = V.loc(v)
        if q is not p and q != p:
            raise LawViolation("new_fresh", f"new(s, {p!r}) made {v!r} with loc {q!r}")
        made.append(v)
    return made
