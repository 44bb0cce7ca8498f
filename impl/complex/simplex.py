"""Simplices: tuples of distinct vertices, apex first (paper §2, Fig. 2).

An *ordered* n-simplex is a tuple of n+1 distinct :class:`~persistri.impl.complex.vertex.Vertex`
values; its first vertex is the *apex*.  An *oriented* simplex is the class of
an ordered one under even permutations: ``(a, b, c)``, ``(b, c, a)`` and
``(c, a, b)`` are one oriented triangle, ``(a, c, b)`` is its reverse side.
Python's ``==`` on tuples is *ordered* equality; :meth:`TupleSimplex.compare`
is the order on oriented classes the paper asks for.

Canonical form.  :func:`canonical` picks one ordered representative of each
oriented class: the vertices in increasing order if that order is an even
permutation of the simplex, else increasing order with the last two swapped.
``compare`` orders simplices by dimension, then by canonical form, so two
orders of one orientation compare ``EQUAL`` and the two orientations of one
vertex set do not.

Operations (n = dimension, at most 4 in practice so all are O(1)):

* ``faces t``: the n+1 faces with the *induced orientation*, ``faces(t)[i]``
  being ``t`` without its i-th vertex, flipped when i is odd —
  for ``(a, b, c)``: ``(b, c), (c, a), (a, b)``.  ``faces(t)[0]`` is the face
  opposite the apex, and for n ≥ 2 ``join(t[i], faces(t)[i])`` is ``t``'s
  orientation for every i (the bootstrapping functor relies on this; an edge
  cannot have it, since its faces are vertices);
* ``flip t``: swaps the last two vertices (so the apex stays first when n ≥ 2;
  for an edge it is the reverse).  A vertex has one orientation only: ``flip``
  of a 0-simplex is itself;
* ``down t = (t[0], t[1:])`` and ``join(v, f) = (v,) + f``, inverse to each other.

The empty tuple is the (−1)-simplex, so that ``down`` of a 0-simplex
``(v,)`` is ``(v, ())`` and ``join`` inverts it.  Complexes never hold it.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, TypeAlias

from persistri.impl.complex.errors import (
    DimensionError,
    ForeignVertexError,
    NotAVertexError,
    RepeatedVertexError,
)
from persistri.impl.complex.vertex import IntVertex, Lineage, Vertex, int_vertex
from persistri.spec.order import Order

__all__ = [
    "Simplex",
    "TupleSimplex",
    "tuple_simplex",
    "parity",
    "canonical",
    "same_orientation",
    "check_simplex",
]

Simplex: TypeAlias = tuple[Vertex, ...]
"""An ordered simplex: a tuple of distinct vertices, apex first."""

_Vertex: TypeAlias = Vertex
# Inside TupleSimplex the name ``Vertex`` is the SIMPLEX signature's sub-structure.


def parity(s: Sequence[Any]) -> int:
    """0 if sorting ``s`` takes an even permutation, 1 if odd.  O(n²) for n ≤ 5 vertices: counts inversions."""
    inv = 0
    n = len(s)
    for i in range(n):
        si = s[i]
        for j in range(i + 1, n):
            if s[j] < si:
                inv += 1
    return inv & 1


def canonical(s: Simplex) -> Simplex:
    """The canonical ordered representative of ``s``'s oriented class (see the module docstring).

    Two simplices are the same oriented simplex iff their canonical forms are
    equal tuples.  O(n log n).
    """
    srt = sorted(s)
    if len(srt) >= 2 and parity(s):
        srt[-1], srt[-2] = srt[-2], srt[-1]
    return tuple(srt)


def same_orientation(s: Simplex, t: Simplex) -> bool:
    """Whether ``s`` and ``t`` are orders of one oriented simplex (same vertices, same parity)."""
    return len(s) == len(t) and canonical(s) == canonical(t)


def _coerce(s: Any, what: str) -> Simplex:
    """``s`` as a tuple (a list is accepted); :class:`TypeError` for a non-sequence."""
    if type(s) is tuple:
        return s
    if isinstance(s, (str, bytes)) or not isinstance(s, Sequence):
        raise TypeError(f"{what}: expected a simplex (a tuple of vertices), got {type(s).__name__}")
    return tuple(s)


def check_simplex(s: Any, what: str, lineage: Lineage | None = None) -> tuple[Simplex, Lineage | None]:
    """Validate ``s`` as an ordered simplex for the operation ``what``; return it as a tuple and its lineage.

    Raises :class:`~persistri.impl.complex.errors.NotAVertexError`,
    :class:`~persistri.impl.complex.errors.RepeatedVertexError` or
    :class:`~persistri.impl.complex.errors.ForeignVertexError` (a vertex not of
    ``lineage``, or, when ``lineage`` is None, of another lineage than the
    simplex's first vertex).  O(n²) for n+1 vertices.
    """
    t = _coerce(s, what)
    lin = lineage
    for v in t:
        try:
            vl = v.lineage
        except AttributeError:
            raise NotAVertexError(f"{what}: {v!r} of type {type(v).__name__} in {t!r} is not a Vertex") from None
        if not isinstance(v, Vertex):
            raise NotAVertexError(f"{what}: {v!r} of type {type(v).__name__} in {t!r} is not a Vertex")
        if lin is None:
            lin = vl
        elif vl is not lin:
            raise ForeignVertexError(
                f"{what}: vertex {v!r} of {t!r} belongs to lineage {vl!r}, not {lin!r} "
                "(vertices of another VertexState.initial())"
            )
    if len(set(t)) != len(t):
        raise RepeatedVertexError(f"{what}: simplex {t!r} repeats a vertex")
    return t, lin


class TupleSimplex:
    """``structure TupleSimplex : SIMPLEX``: simplices as tuples of :class:`Vertex`, apex first.

    Every operation is O(1) for the dimensions persistri uses (n ≤ 4).
    See the module docstring for the canonical form and the induced orientation.
    """

    __slots__ = ()

    name = "tuple_simplex"

    @property
    def Vertex(self) -> IntVertex:
        """``structure Vertex : VERTEX``: :data:`~persistri.impl.complex.vertex.int_vertex`."""
        return int_vertex

    def compare(self, s: Simplex, t: Simplex, /) -> Order:
        """``compare (s, t)``: by dimension, then canonical form; EQUAL iff one oriented simplex."""
        s = _coerce(s, "compare")
        t = _coerce(t, "compare")
        ks = (len(s), canonical(s))
        kt = (len(t), canonical(t))
        if ks < kt:
            return Order.LESS
        if kt < ks:
            return Order.GREATER
        return Order.EQUAL

    def dim(self, s: Simplex, /) -> int:
        """``dim s``: one less than the number of vertices.  O(1)."""
        return len(_coerce(s, "dim")) - 1

    def vertices(self, s: Simplex, /) -> Simplex:
        """``vertices s``: the vertices in their stored order, apex first (the tuple itself).  O(1)."""
        return _coerce(s, "vertices")

    def simplex(self, vs: Sequence[_Vertex], /) -> Simplex:
        """``simplex vs``: the ordered simplex of the distinct vertices ``vs`` (all of one lineage), apex ``vs[0]``.

        Raises NotAVertexError, RepeatedVertexError or ForeignVertexError.
        """
        return check_simplex(vs, "simplex")[0]

    def faces(self, s: Simplex, /) -> list[Simplex]:
        """``faces s``: the n+1 faces with the induced orientation; ``faces(s)[i]`` is opposite ``s[i]``.  O(n²)."""
        s = _coerce(s, "faces")
        out: list[Simplex] = []
        for i in range(len(s)):
            f = s[:i] + s[i + 1 :]
            if i & 1 and len(f) >= 2:
                f = f[:-2] + (f[-1], f[-2])
            out.append(f)
        return out

    def flip(self, s: Simplex, /) -> Simplex:
        """``flip s``: the reverse orientation, by swapping the last two vertices (identity on a vertex).  O(n)."""
        s = _coerce(s, "flip")
        if len(s) < 2:
            return s
        return s[:-2] + (s[-1], s[-2])

    def down(self, s: Simplex, /) -> tuple[_Vertex, Simplex]:
        """``down s``: the apex and the face opposite it, ``(s[0], s[1:])``.  O(n)."""
        s = _coerce(s, "down")
        if not s:
            raise DimensionError("down: the empty simplex has no apex")
        return s[0], s[1:]

    def join(self, v: _Vertex, f: Simplex, /) -> Simplex:
        """``join (v, f)``: the simplex with apex ``v`` and opposite face ``f``, ``(v,) + f``; inverse of ``down``.

        Raises RepeatedVertexError if ``v`` is in ``f``, and the other
        :func:`check_simplex` errors.
        """
        return check_simplex((v,) + _coerce(f, "join"), "join")[0]

    def __repr__(self) -> str:
        return "tuple_simplex"


tuple_simplex = TupleSimplex()
"""The simplex structure every persistri complex uses."""
