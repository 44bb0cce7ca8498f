"""The specialised 2-complex's internal operations: its per-vertex lists read and changed one triangle at a time (paper §4).

:class:`~persistri.impl.complex.two_complex.TwoComplex` is the 2-complex the
algorithms use; its docstring describes the representation (one map from each
vertex to the tuple of its entries ``(second vertex, third vertex, datum)``)
and the cost of each operation.  Its public operations validate their
arguments and then work through the methods of :class:`TwoComplexRep`, its
base class here: the reads (``_data``, ``_find``, ``_star``, ``_items``) and
the fold's changes (``_add``, ``_rem``, ``_update``) on the map value ``rep``
of one version, with arguments already validated, raising the signature's
errors for a triangle absent or present and RepresentationError for lists
that disagree.  Each change is one ``insertWith`` per vertex of the triangle
with a combining function of :mod:`~persistri.impl.complex.vertex_lists`; a
counted structure wraps those functions so that the list entries they visit
are counted as key comparisons (paper §4: tree nodes plus list entries).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any, TypeAlias, TypeVar

from persistri.impl.complex.checks import check_vertex_lists
from persistri.impl.complex.errors import (
    AbsentSimplexError,
    DuplicateSimplexError,
    OppositeOrientationError,
    RepresentationError,
)
from persistri.impl.complex.simplex import Simplex
from persistri.impl.complex.structure import ComplexStructure
from persistri.impl.complex.vertex import Vertex
from persistri.impl.complex.vertex_lists import (
    Combine,
    Emptied,
    Entry,
    Missing,
    Present,
    cat_first,
    cat_new,
    drop,
    drop_add,
    put,
    visited,
)
from persistri.impl.stats import Stats
from persistri.spec.option import Option

__all__ = ["TwoComplexRep", "Triangle", "Edge"]

D = TypeVar("D")

Triangle: TypeAlias = tuple[Vertex, Vertex, Vertex]
"""A 2-simplex as the 2-complex returns it (a :data:`~persistri.impl.complex.simplex.Simplex` of length 3)."""

Edge: TypeAlias = tuple[Vertex, Vertex]
"""A 1-simplex."""


def _counting(stats: Stats, f: Combine) -> Combine:
    """``f`` that also adds the list entries it visits to ``stats.key_comparisons`` (counted structures only)."""

    def counted(old: tuple[Entry, ...], arg: Any) -> tuple[Entry, ...]:
        if f is cat_first:
            stats.key_comparisons += len(old)  # add scans the whole list, for either orientation
        elif f is drop:
            stats.key_comparisons += visited(old, arg[0], arg[1])
        elif f is put:
            stats.key_comparisons += visited(old, arg[0][0], arg[0][1])
        elif f is drop_add or f is cat_new:
            stats.key_comparisons += len(old)  # replace scans the whole list once
        return f(old, arg)

    return counted



class TwoComplexRep(ComplexStructure[D]):
    """The internal operations of :class:`~persistri.impl.complex.two_complex.TwoComplex` (module docstring).

    Not a structure by itself: :class:`~persistri.impl.complex.two_complex.TwoComplex`
    sets the combining functions below when it is made, plain or counting.
    """

    _cat_first: Combine
    _cat: Combine
    _drop: Combine
    _put: Combine
    _drop_add: Combine
    _cat_new: Combine

    def _scan(self, lst: tuple[Entry, ...], b: Vertex, c: Vertex) -> int:
        """The index of entry ``(b, c, _)`` in ``lst``, or -1; counts the entries visited."""
        for i, e in enumerate(lst):
            if e[0] == b and e[1] == c:
                if self._stats is not None:
                    self._stats.key_comparisons += i + 1
                return i
        if self._stats is not None:
            self._stats.key_comparisons += len(lst)
        return -1

    def _data(self, rep: Any, s: Simplex) -> Option[D]:
        a, b, c = s
        found = self._m.find(rep, a)
        if found is None:
            return None
        lst = found[0]
        i = self._scan(lst, b, c)
        return None if i < 0 else (lst[i][2],)

    def _find(self, rep: Any, f: Simplex) -> list[Triangle]:
        u, w = f
        found = self._m.find(rep, u)
        if found is None:
            return []
        lst = found[0]
        if self._stats is not None:
            self._stats.key_comparisons += len(lst)
        return [(u, w, t) for v, t, _ in lst if v == w]

    def _star(self, rep: Any, v: Vertex) -> list[Triangle]:
        found = self._m.find(rep, v)
        if found is None:
            return []
        lst = found[0]
        if self._stats is not None:
            self._stats.key_comparisons += len(lst)
        return [(v, b, c) for b, c, _ in lst]

    def _items(self, rep: Any) -> Iterator[tuple[Triangle, D]]:
        for a, lst in self._m.listItemsi(rep):
            for b, c, x in lst:
                if a < b and a < c:
                    yield (a, b, c), x

    def _combiner(self, f: Combine) -> Combine:
        """``f`` itself, or a counting version of it when a Stats is attached."""
        return f if self._stats is None else _counting(self._stats, f)

    def _add(self, rep: Any, s: Simplex, x: D) -> Any:
        a, b, c = s
        m = self._m
        try:
            # The triangle, in either orientation, would be in a's list: (b, c) or (c, b).
            rep = m.insertWith(self._cat_first, rep, a, ((b, c, x),))
        except Present as present:
            if present.opposite:
                raise OppositeOrientationError(
                    f"add: triangle {s!r} is present with the opposite orientation {(a, c, b)!r}"
                ) from None
            raise DuplicateSimplexError(f"add: triangle {s!r} is already present") from None
        cat = self._cat
        rep = m.insertWith(cat, rep, b, ((c, a, x),))
        return m.insertWith(cat, rep, c, ((a, b, x),))

    def _change(self, rep: Any, key: Vertex, b: Vertex, c: Vertex, y: Any, drop: bool) -> Any:
        """Drop (or give datum ``y`` to) entry ``(b, c, _)`` of ``key``'s list: one ``insertWith``
        (plus a ``remove`` if the list empties).  RepresentationError if the entry is not there."""
        m = self._m
        n0 = m.numItems(rep)
        try:
            if drop:
                out = m.insertWith(self._drop, rep, key, (b, c))
            else:
                out = m.insertWith(self._put, rep, key, ((b, c, y),))
        except Emptied:
            return m.remove(rep, key)[0]
        except Missing:
            out = None
        if out is None or m.numItems(out) != n0:  # numItems grew: key had no list, insertWith made one
            raise RepresentationError(f"2-complex: entry {(b, c)!r} missing from the list of {key!r}")
        return out

    def _locate(self, rep: Any, s: Simplex, what: str) -> tuple[tuple[Entry, ...], int]:
        a, b, c = s
        found = self._m.find(rep, a)
        if found is not None:
            lst = found[0]
            i = self._scan(lst, b, c)
            if i >= 0:
                return lst, i
        raise AbsentSimplexError(f"{what}: triangle {s!r} is not in the complex (in this orientation)")

    def _rem(self, rep: Any, s: Simplex) -> Any:
        # Three insertWith that each drop the triangle's entry from one list, the first
        # also finding out whether the triangle is there: no separate lookup.
        a, b, c = s
        m = self._m
        drop = self._drop
        n0 = m.numItems(rep)
        try:
            out = m.insertWith(drop, rep, a, (b, c))
        except Emptied:
            out = m.remove(rep, a)[0]
        except Missing:
            out = None
        if out is None or m.numItems(out) > n0:  # numItems grew: a had no list, insertWith made one
            raise AbsentSimplexError(f"rem: triangle {s!r} is not in the complex (in this orientation)")
        n1 = m.numItems(out)
        try:
            try:
                out = m.insertWith(drop, out, b, (c, a))
            except Emptied:
                out = m.remove(out, b)[0]
            try:
                out = m.insertWith(drop, out, c, (a, b))
            except Emptied:
                out = m.remove(out, c)[0]
        except Missing:
            out = None
        if out is None or m.numItems(out) > n1:  # an entry of the triangle missing under b or c
            raise RepresentationError(f"2-complex: triangle {s!r} is in the list of {a!r} but not in those of {b!r} and {c!r}")
        return out

    def _update(self, rep: Any, s: Simplex, f: Callable[[D], D]) -> Any:
        a, b, c = s
        lst, i = self._locate(rep, s, "update")
        y = f(lst[i][2])  # f may raise: nothing has been built yet
        rep = self._change(rep, a, b, c, y, False)
        rep = self._change(rep, b, c, a, y, False)
        return self._change(rep, c, a, b, y, False)

    def _check_rep(self, rep: Any) -> None:
        check = getattr(self._raw, "_check", None)
        if check is not None:
            check(rep)
        check_vertex_lists(dict(self._raw.listItemsi(rep)), "2-complex")
