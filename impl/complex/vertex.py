"""Vertices: integer labels that carry their point and their state lineage (paper §2, Fig. 1).

The paper's ``VERTEX`` signature asks for three things: a total order (the
complexes key their maps by vertex), a point per vertex (``loc v`` takes no
state), and purely functional creation through a state
(``new : state * point -> state * vertex``).  This module meets them with

* :class:`Vertex` — a subclass of :class:`int`.  The label *is* the integer, so
  the red-black tree's ``<`` and the HAMT's hash and ``==`` run at C speed, and
  a vertex is as cheap a map key as an ``int``.  Each vertex also carries its
  ``point`` (opaque to the complex) and its ``lineage``;
* :class:`VertexState` — an immutable state: a lineage and the next free label.
  ``new(state, p)`` returns ``(state with label + 1, Vertex(label, p))`` and
  leaves ``state`` as it was, so calling it again gives the same vertex;
* :class:`Lineage` — a token made once by :meth:`VertexState.initial` and shared
  by every state and vertex descended from it.  A complex adopts the lineage of
  its first simplex; a vertex of another lineage is refused with
  :class:`~persistri.impl.complex.errors.ForeignVertexError` (labels of two
  lineages collide, so mixing them would silently confuse vertices).

Starting a lineage is outside the paper's signature (it has no initial state):
``VertexState.initial()`` is persistri's addition.

A vertex compares and hashes as its label: ``Vertex`` 3 ``== 3``.  Labels are
unique *along one history of states*; two branches forked from one state both
hand out the next label, and mixing the vertices of two branches in one complex
is a caller error that :func:`~persistri.impl.complex.checks.check_complex`
reports (one label, two points).

>>> s0 = VertexState.initial()
>>> s1, a = int_vertex.new(s0, (0, 0, 0))
>>> s2, b = int_vertex.new(s1, (1, 0, 0))
>>> a, b, int_vertex.loc(b)
(v0, v1, (1, 0, 0))
>>> int_vertex.new(s0, (0, 0, 0))[1] == a      # s0 is unchanged: same vertex again
True
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable
from typing import Any, NoReturn

from persistri.impl.complex.errors import NotAVertexError
from persistri.spec.order import Order

__all__ = ["Lineage", "Vertex", "VertexState", "IntVertex", "int_vertex"]

_lineage_numbers = itertools.count()


class Lineage:
    """The identity of one family of vertex states, made by :meth:`VertexState.initial`.

    Compared by identity only.  Copying (shallow or deep) returns the same
    token, so a copied vertex stays in its lineage; unpickling makes a new
    token (one per pickle, shared by the vertices and states it held).

    A lineage also holds what its vertices do not: the classes of its
    vertices (made on first use, see :class:`Vertex`) and, for vertices whose
    point is neither ``None`` nor their own label, the table of their points.
    """

    __slots__ = ("number", "_kinds")

    number: int
    """A serial number, for messages only (``L3``)."""
    _kinds: dict[str, type[Vertex]]

    def __init__(self) -> None:
        self.number = next(_lineage_numbers)
        self._kinds = {}

    def __copy__(self) -> Lineage:
        return self

    def __deepcopy__(self, memo: dict[int, Any]) -> Lineage:
        return self

    def __reduce__(self) -> tuple[Any, tuple[int]]:
        return (_unpickled_lineage, (self.number,))

    def __repr__(self) -> str:
        return f"L{self.number}"

    def _kind(self, kind: str) -> type[Vertex]:
        """The class of this lineage's vertices of one ``kind`` (made on first use).  O(1) amortised."""
        cls = self._kinds.get(kind)
        if cls is None:
            ns: dict[str, Any] = {"lineage": self, "__module__": __name__, "__qualname__": "Vertex"}
            if kind == "none":
                ns["point"] = None
            elif kind == "label":
                ns["point"] = property(int, doc="``loc v``: the vertex's own label.")
            elif kind == "table":
                # The class holds its own table: two threads racing to make the class make two
                # consistent classes, never a class that reads another's table.
                points: dict[Vertex, Any] = {}
                ns["_table"] = points
                ns["point"] = property(points.__getitem__, doc="``loc v``: from the lineage's table.")
            if kind != "loose":
                ns["__slots__"] = ()  # "loose": a per-instance __dict__ holds the point
            cls = type("Vertex", (Vertex,), ns)
            self._kinds[kind] = cls
        return cls


def _unpickled_lineage(number: int) -> Lineage:
    """A fresh lineage for an unpickled one (the number kept for messages)."""
    lin = Lineage()
    lin.number = number
    return lin


_MISSING: Any = object()


class Vertex(int):
    """A vertex: an integer label with a ``point`` and a ``lineage``; immutable.

    Ordered, hashed and compared for equality as its label (C speed).  Made by
    :meth:`IntVertex.new`; constructing one directly is possible but bypasses
    the state, so labels are no longer guaranteed unique.

    A vertex is as small as an ``int`` (no per-instance ``__dict__``; CPython
    allows no slots on a subclass of ``int``): ``Vertex(label, point, lineage)``
    returns an instance of a subclass that its lineage makes once, whose class
    attribute is the lineage and whose ``point`` is one of

    * ``None`` (a class attribute), for vertices made without a point;
    * the label itself (``int(v)``), for a point that is the ``int`` label
      (the hull's vertices are their input rows);
    * otherwise an entry of the lineage's table, keyed by the vertex.  The
      table keeps each such vertex and its point as long as the lineage lives
      (a vertex made and dropped is not freed before its lineage is).  A
      second vertex of a label already in the table with another point (two
      branches forked from one state) gets a class of its own with a
      ``__dict__`` ("loose"), so no vertex's point ever changes.

    ``type(v)`` is therefore a subclass of :class:`Vertex`, never
    :class:`Vertex` itself: test with ``isinstance``.  All O(1).
    """

    __slots__ = ()

    point: Any
    """``loc v``: where the vertex is; opaque to the complex."""
    lineage: Lineage
    """The state lineage the vertex was made in."""

    def __new__(cls, label: int, point: Any, lineage: Lineage) -> Vertex:
        kinds = lineage._kinds
        if point is None:
            return int.__new__(kinds.get("none") or lineage._kind("none"), label)
        if type(point) is int and point == label:
            return int.__new__(kinds.get("label") or lineage._kind("label"), label)
        table = kinds.get("table") or lineage._kind("table")
        v: Vertex = int.__new__(table, label)
        points: dict[Vertex, Any] = table.__dict__["_table"]
        old = points.setdefault(v, point)
        if old is point:
            return v
        loose: Vertex = int.__new__(lineage._kind("loose"), label)
        # Written into __dict__ directly: __setattr__ is closed to keep vertices immutable.
        loose.__dict__["point"] = point
        return loose

    def __setattr__(self, name: str, value: Any) -> NoReturn:
        raise AttributeError(f"vertex {self!r} is immutable (cannot set {name!r})")

    def __delattr__(self, name: str) -> NoReturn:
        raise AttributeError(f"vertex {self!r} is immutable (cannot delete {name!r})")

    def __reduce__(self) -> tuple[Any, tuple[int, Any, Lineage]]:
        # Rebuilt through Vertex(...), which finds the (new) lineage's class: the classes are not picklable.
        return (Vertex, (int(self), self.point, self.lineage))

    def __repr__(self) -> str:
        return f"v{int(self)}"

    @property
    def label(self) -> int:
        """The integer label (the vertex's place in the total order)."""
        return int(self)


class VertexState:
    """An immutable vertex state: a :class:`Lineage` and the next free label (paper's ``state``).

    Start one with :meth:`initial`; advance it only through :meth:`IntVertex.new`.
    """

    __slots__ = ("lineage", "next_label")

    lineage: Lineage
    next_label: int

    def __init__(self, lineage: Lineage, next_label: int) -> None:
        object.__setattr__(self, "lineage", lineage)
        object.__setattr__(self, "next_label", next_label)

    @classmethod
    def initial(cls) -> VertexState:
        """A fresh state of a new lineage, whose first vertex will be labelled 0.  O(1)."""
        return cls(Lineage(), 0)

    def __setattr__(self, name: str, value: Any) -> NoReturn:
        raise AttributeError("VertexState is immutable")

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, VertexState):
            return NotImplemented
        return self.lineage is other.lineage and self.next_label == other.next_label

    def __hash__(self) -> int:
        return hash((id(self.lineage), self.next_label))

    def __repr__(self) -> str:
        return f"VertexState({self.lineage!r}, next={self.next_label})"


class IntVertex:
    """``structure IntVertex : VERTEX``: :class:`Vertex` values made from :class:`VertexState` s.

    All three operations are O(1).  Points are of any type (``Any``): the complex
    never looks at them.
    """

    __slots__ = ()

    name = "int_vertex"

    def compare(self, a: Vertex, b: Vertex, /) -> Order:
        """``compare (a, b)``: the order of the labels.  O(1)."""
        if a < b:
            return Order.LESS
        if b < a:
            return Order.GREATER
        return Order.EQUAL

    def new(self, state: VertexState, point: Any, /) -> tuple[VertexState, Vertex]:
        """``new (state, point)``: the vertex labelled ``state.next_label`` at ``point``, and the state after it.

        Purely functional: ``state`` is not changed, and ``new(state, point)``
        again returns an equal vertex.  O(1).
        """
        if not isinstance(state, VertexState):
            raise TypeError(
                f"new: expected a VertexState (start one with VertexState.initial()), got {type(state).__name__}"
            )
        k = state.next_label
        return VertexState(state.lineage, k + 1), Vertex(k, point, state.lineage)

    def new_many(self, state: VertexState, points: Iterable[Any], /) -> tuple[VertexState, list[Vertex]]:
        """``new`` over ``points`` in order: the final state and the vertices, labelled consecutively.  O(len)."""
        if not isinstance(state, VertexState):
            raise TypeError(
                f"new_many: expected a VertexState (start one with VertexState.initial()), got {type(state).__name__}"
            )
        lineage, k = state.lineage, state.next_label
        vs = [Vertex(k + i, p, lineage) for i, p in enumerate(points)]
        return VertexState(lineage, k + len(vs)), vs

    def loc(self, v: Vertex, /) -> Any:
        """``loc v``: the point of ``v``.  O(1)."""
        if not isinstance(v, Vertex):
            raise NotAVertexError(f"loc: {v!r} of type {type(v).__name__} is not a Vertex")
        return v.point

    def __repr__(self) -> str:
        return "int_vertex"


int_vertex = IntVertex()
"""The vertex structure every persistri simplex and complex uses."""
