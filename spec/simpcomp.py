"""``signature SIMPCOMP`` (paper, Fig. 3): persistent oriented simplicial complexes.

::

    signature SIMPCOMP = sig
      structure Simplex : SIMPLEX
      type 'a complex
      val dim       : 'a complex -> int
      val new       : int -> 'a complex
      val isEmpty   : 'a complex -> bool
      val vertices  : 'a complex -> Simplex.Vertex.vertex seq
      val simplices : 'a complex -> int -> Simplex.simplex seq
      val data      : 'a complex * Simplex.simplex -> 'a option
      val grep      : 'a complex -> int * Simplex.simplex -> Simplex.simplex seq
      val find      : 'a complex * Simplex.simplex -> Simplex.simplex seq
      val add       : 'a complex * Simplex.simplex * 'a -> 'a complex
      val rem       : 'a complex * Simplex.simplex -> 'a complex
      val update    : 'a complex * Simplex.simplex * ('a -> 'a) -> 'a complex
    end

An n-complex holds oriented n-simplices, each with a datum of type ``'a``
(``D`` here); its lower-dimensional simplices are the faces of those.  There
are no mutation operations: ``add``, ``rem`` and ``update`` return new
complexes and leave the one they were given valid and unchanged.  Curried SML
functions are uncurried (``simplices c d`` is ``simplices(c, d)``, ``grep c
(d, s)`` is ``grep(c, d, s)``).

Semantics (laws in :mod:`persistri.spec.simpcomp_laws`):

* simplices are oriented, not ordered: any order of the stored orientation finds it;
* ``find(c, s)`` for an (n−1)-simplex ``s``: the n-simplices having ``s`` as a face
  *with its orientation* — in a closed, consistently oriented surface the
  neighbour of triangle t across its edge e is ``find(c, flip(e))``;
* ``grep(c, d, s)``: the d-simplices having ``s`` as a face; for ``dim s = d − 1``
  orientation matters as in ``find``, for lower dimensions it is vertex-set
  containment; each oriented simplex is reported once;
* ``simplices(c, d)`` for ``d < n`` reports each face once (in one orientation).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Protocol, TypeVar

from persistri.spec.option import Option
from persistri.spec.simplex import SIMPLEX

__all__ = ["SIMPCOMP"]

Vx = TypeVar("Vx")
Sx = TypeVar("Sx")
D = TypeVar("D")
Cx = TypeVar("Cx")


class SIMPCOMP(Protocol[Vx, Sx, D, Cx]):
    """A structure of operations on complexes ``Cx`` of simplices ``Sx`` (over ``Vx``) carrying data ``D``."""

    @property
    def Simplex(self) -> SIMPLEX[Vx, Sx]:
        """``structure Simplex : SIMPLEX``: the simplices complexes are made of."""
        ...

    def dim(self, c: Cx, /) -> int:
        """``dim c``: the dimension n of the n-complex ``c``."""
        ...

    def new(self, n: int, /) -> Cx:
        """``new n``: the empty n-complex."""
        ...

    def isEmpty(self, c: Cx, /) -> bool:
        """``isEmpty c``: whether ``c`` has no simplices."""
        ...

    def vertices(self, c: Cx, /) -> Sequence[Vx]:
        """``vertices c``: the vertices of ``c``, in unspecified order."""
        ...

    def simplices(self, c: Cx, d: int, /) -> Sequence[Sx]:
        """``simplices c d``: the d-simplices of ``c``, each oriented simplex once."""
        ...

    def data(self, c: Cx, s: Sx, /) -> Option[D]:
        """``data (c, s)``: ``(x,)`` when the n-simplex ``s`` (this orientation) carries ``x``, else ``None``."""
        ...

    def grep(self, c: Cx, d: int, s: Sx, /) -> Sequence[Sx]:
        """``grep c (d, s)``: the d-simplices of ``c`` having ``s`` as a face."""
        ...

    def find(self, c: Cx, s: Sx, /) -> Sequence[Sx]:
        """``find (c, s)``: the n-simplices having the (n−1)-simplex ``s`` as an oriented face."""
        ...

    def add(self, c: Cx, s: Sx, x: D, /) -> Cx:
        """``add (c, s, x)``: ``c`` with the n-simplex ``s`` carrying ``x``."""
        ...

    def rem(self, c: Cx, s: Sx, /) -> Cx:
        """``rem (c, s)``: ``c`` without the n-simplex ``s``."""
        ...

    def update(self, c: Cx, s: Sx, f: Callable[[D], D], /) -> Cx:
        """``update (c, s, f)``: ``c`` with the datum ``x`` of ``s`` replaced by ``f(x)``."""
        ...
