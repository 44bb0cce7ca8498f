"""``signature VERTEX`` (paper, Fig. 1): totally ordered vertices located at points.

::

    signature VERTEX = sig
      type vertex
      val compare : vertex * vertex -> order
      type state
      type point
      val new : state * point -> state * vertex
      val loc : vertex -> point
    end

``vertex``, ``state`` and ``point`` become the type parameters ``Vx``, ``St`` and
``Pt``.  The total order is needed only by the implementation (complexes key
their maps by vertex).  ``new`` creates vertices *purely functionally*: it
returns a new state, and the state it was given still creates the same vertex
again.  Points are opaque to the complex.
"""

from __future__ import annotations

from typing import Protocol, TypeVar

from persistri.spec.order import Order

__all__ = ["VERTEX"]

Vx = TypeVar("Vx")
St = TypeVar("St")
Pt = TypeVar("Pt")


class VERTEX(Protocol[Vx, St, Pt]):
    """A structure of operations on vertices ``Vx`` created from states ``St`` at points ``Pt``.

    Laws: ``compare`` is a total order; ``new(s, p)`` returns a vertex ``v`` with
    ``loc(v) == p`` that is distinct from every vertex created from ``s``'s
    ancestors; calling ``new(s, p)`` again on the same ``s`` is deterministic.
    """

    def compare(self, a: Vx, b: Vx, /) -> Order:
        """``compare (a, b)``: the total order on vertices."""
        ...

    def new(self, state: St, point: Pt, /) -> tuple[St, Vx]:
        """``new (state, point)``: a fresh vertex located at ``point``, and the state after it."""
        ...

    def loc(self, v: Vx, /) -> Pt:
        """``loc v``: the point at which ``v`` is located."""
        ...
