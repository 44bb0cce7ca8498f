"""The EPHEMERAL baseline's table: one mutable ``dict`` of vertex lists and its version tokens — NOT persistent.

:class:`~persistri.impl.complex.ephemeral.EphemeralTwoComplex` (its module
docstring says what the baseline is for and how its versions go stale) keeps
every version of one history in one :class:`_Table`: the ``dict`` from each
vertex to its immutable tuple of entries, and the token of the one version that
is current.  This module is that table and :class:`EphemeralTable`, the base
class that reads and changes it for the operations the baseline inherits from
:class:`~persistri.impl.complex.structure.ComplexStructure` (``vertices``,
``simplices``, ``grep``, ``items``, ``update``, ``check``): each first checks
that the version it was given is the current one (StaleVersionError if not),
then works on the ``dict`` in place.  O(1) dict operations plus the list
scanned, as the module docstring of the baseline says.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any, TypeVar

from persistri.impl.complex.checks import check_vertex_lists
from persistri.impl.complex.errors import AbsentSimplexError, StaleVersionError
from persistri.impl.complex.simplex import Simplex
from persistri.impl.complex.two_complex import Triangle, TwoComplex
from persistri.impl.complex.vertex import Vertex
from persistri.impl.complex.vertex_lists import Entry
from persistri.spec.option import Option

__all__ = ["EphemeralDict", "EphemeralTable"]

D = TypeVar("D")


class EphemeralDict:
    """Stands where a persistent complex's ``ORD_MAP`` backend would (in its :class:`Family`): Python's ``dict``.

    Not an ``ORD_MAP`` — it has no operations; it names the representation in
    messages and makes the family of every ephemeral complex the same.
    """

    __slots__ = ()

    name = "dict (ephemeral, NOT persistent)"

    def __repr__(self) -> str:
        return "EphemeralDict"


_DICT = EphemeralDict()


class _Table:
    """The one mutable table of an ephemeral complex's history, and its current version token."""

    __slots__ = ("lists", "current")

    lists: dict[Vertex, tuple[Entry, ...]]
    current: tuple[_Table]

    def __init__(self) -> None:
        self.lists = {}
        self.current = (self,)


def _stale(what: str) -> StaleVersionError:
    return StaleVersionError(
        f"{what}: this version of an EPHEMERAL 2-complex is stale — a later operation changed its table in place "
        "(only the newest version of the ephemeral baseline is valid; use a persistent backend to keep versions)"
    )



class EphemeralTable(TwoComplex[D]):
    """The internal operations of :class:`~persistri.impl.complex.ephemeral.EphemeralTwoComplex` on its table.

    Not a structure by itself: :class:`~persistri.impl.complex.ephemeral.EphemeralTwoComplex`
    makes the family and overrides every public operation that makes a version.
    """

    # -- versions -----------------------------------------------------------------------

    @staticmethod
    def _live(rep: Any, what: str) -> dict[Vertex, tuple[Entry, ...]]:
        """The table of ``rep`` if ``rep`` is its current version; StaleVersionError otherwise."""
        table: _Table = rep[0]
        if table.current is not rep:
            raise _stale(what)
        return table.lists

    def _count(self, lookups: int, scanned: int) -> None:
        st = self._stats
        if st is not None:
            st.dict_ops += lookups
            st.key_comparisons += lookups + scanned


    # -- internal operations (what the base class's other public operations use) ---------

    def _empty(self) -> Any:
        return _Table().current

    def _is_empty(self, rep: Any) -> bool:
        return not self._live(rep, "isEmpty")

    def _vertices(self, rep: Any) -> list[Vertex]:
        lists = self._live(rep, "vertices")
        self._count(len(lists), 0)
        return sorted(lists)

    def _data(self, rep: Any, s: Simplex) -> Option[D]:
        lists = self._live(rep, "data")
        a, b, c = s
        lst = lists.get(a)
        if lst is None:
            return None
        i = _index(lst, b, c)
        return None if i < 0 else (lst[i][2],)

    def _find(self, rep: Any, f: Simplex) -> list[Triangle]:
        lists = self._live(rep, "find")
        u, w = f
        return [(u, w, t) for v, t, _ in lists.get(u, ()) if v == w]

    def _star(self, rep: Any, v: Vertex) -> list[Triangle]:
        lists = self._live(rep, "grep")
        return [(v, b, c) for b, c, _ in lists.get(v, ())]

    def _items(self, rep: Any) -> Iterator[tuple[Triangle, D]]:
        lists = self._live(rep, "items")
        out: list[tuple[Triangle, D]] = []
        for a in sorted(lists):
            for b, c, x in lists[a]:
                if a < b and a < c:
                    out.append(((a, b, c), x))
        return iter(out)

    def _add(self, rep: Any, s: Simplex, x: D) -> Any:  # pragma: no cover - add is overridden whole
        raise NotImplementedError("EphemeralTwoComplex.add works on the table directly")

    def _rem(self, rep: Any, s: Simplex) -> Any:  # pragma: no cover - rem is overridden whole
        raise NotImplementedError("EphemeralTwoComplex.rem works on the table directly")

    def _update(self, rep: Any, s: Simplex, f: Callable[[D], D]) -> Any:
        lists = self._live(rep, "update")
        a, b, c = s
        la = lists.get(a)
        i = -1 if la is None else _index(la, b, c)
        if i < 0:
            raise AbsentSimplexError(f"update: triangle {s!r} is not in the complex (in this orientation)")
        assert la is not None
        y = f(la[i][2])  # f may raise: nothing has changed yet
        for key, p, q in ((a, b, c), (b, c, a), (c, a, b)):
            lst = lists[key]
            j = _index(lst, p, q)
            lists[key] = lst[:j] + ((p, q, y),) + lst[j + 1 :]
        table: _Table = rep[0]
        new = (table,)
        table.current = new
        return new

    def _check_rep(self, rep: Any) -> None:
        check_vertex_lists(self._live(rep, "check"), "ephemeral 2-complex")


def _index(lst: tuple[Entry, ...], b: Vertex, c: Vertex) -> int:
    """The index of entry ``(b, c, _)`` in ``lst``, or -1."""
    for i, e in enumerate(lst):
        if e[0] == b and e[1] == c:
            return i
    return -1
