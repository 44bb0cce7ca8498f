"""``signature SIMPLEX`` (paper, Fig. 2): ordered and oriented simplices.

::

    signature SIMPLEX = sig
      structure Vertex : VERTEX
      type simplex
      val compare  : simplex * simplex -> order
      val dim      : simplex -> int
      val vertices : simplex -> Vertex.vertex seq
      val simplex  : Vertex.vertex seq -> simplex
      val faces    : simplex -> simplex seq
      val flip     : simplex -> simplex
      val down     : simplex -> Vertex.vertex * simplex
      val join     : Vertex.vertex * simplex -> simplex
    end

The last four lines were lost in the paper's text extraction; the prose names
them and their meaning.  Semantics (written as laws in
:mod:`persistri.spec.simplex_laws`):

* an *ordered* n-simplex is a tuple of n+1 distinct vertices, apex first; an
  *oriented* simplex is its class under even permutations;
* ``compare`` orders oriented classes: two orders of one orientation compare
  ``EQUAL``, the two orientations of one vertex set do not;
* ``faces t`` of an n-simplex are its n+1 boundary faces with the *induced
  orientation*: drop vertex i, and flip when i is odd.  For (a, b, c): (b, c),
  (c, a), (a, b);
* ``down t = (apex, face opposite the apex)`` and ``join`` is its inverse;
* ``flip`` reverses the orientation and is an involution.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Protocol, TypeVar

from persistri.spec.order import Order
from persistri.spec.vertex import VERTEX

__all__ = ["SIMPLEX"]

Vx = TypeVar("Vx")
Sx = TypeVar("Sx")


class SIMPLEX(Protocol[Vx, Sx]):
    """A structure of operations on simplices ``Sx`` over vertices ``Vx``."""

    @property
    def Vertex(self) -> VERTEX[Vx, Any, Any]:
        """``structure Vertex : VERTEX``: the vertices simplices are made of."""
        ...

    def compare(self, s: Sx, t: Sx, /) -> Order:
        """``compare (s, t)``: a total order on *oriented* simplices (orders of one orientation are EQUAL)."""
        ...

    def dim(self, s: Sx, /) -> int:
        """``dim s``: the dimension n of an n-simplex (one less than its number of vertices)."""
        ...

    def vertices(self, s: Sx, /) -> Sequence[Vx]:
        """``vertices s``: the vertices of ``s`` in their stored order, apex first."""
        ...

    def simplex(self, vs: Sequence[Vx], /) -> Sx:
        """``simplex vs``: the n-simplex of the n+1 distinct vertices ``vs``, apex ``vs[0]``."""
        ...

    def faces(self, s: Sx, /) -> Sequence[Sx]:
        """``faces s``: the n+1 (n−1)-faces of ``s`` with the induced orientation."""
        ...

    def flip(self, s: Sx, /) -> Sx:
        """``flip s``: ``s`` with the opposite orientation (its reverse side)."""
        ...

    def down(self, s: Sx, /) -> tuple[Vx, Sx]:
        """``down s``: the apex of ``s`` and the (n−1)-simplex opposite it."""
        ...

    def join(self, v: Vx, f: Sx, /) -> Sx:
        """``join (v, f)``: the simplex with apex ``v`` and opposite face ``f``; inverse of ``down``."""
        ...
