"""The EPHEMERAL baseline: the specialised 2-complex over one mutable ``dict`` — NOT persistent.

This module exists only to measure what persistence costs (the issue's
"ephemeral baseline"; ``persistri bench complex`` runs it beside every
persistent backend).  Never use it for anything else: **every operation that
makes a new version changes the one table in place**, so the version it was
given is gone.

It is the specialised 2-complex of :mod:`~persistri.impl.complex.two_complex`
(paper §4) with one difference, the map: Python's mutable ``dict`` from each
vertex to its immutable tuple of entries ``(second vertex, third vertex,
datum)``, instead of a persistent ``ORD_MAP``.  Everything else is the same —
the per-vertex lists, each triangle stored under its three vertices by
rotation, the scans, and the argument validation (the same O(1) inline test on
the hot operations, the same exceptions for bad input) — so the difference in
time between the two is the price of the persistent map.

Versions.  A complex value of this structure is a
:class:`~persistri.impl.complex.structure.Complex` whose ``rep`` is a 1-tuple
token ``(table,)``; the table remembers the one token that is current.
``add``, ``rem`` and ``update`` mutate the table and make a new token, so every
*older* value becomes **stale**: using it for anything — a query included —
raises :class:`~persistri.impl.complex.errors.StaleVersionError` instead of
silently reading the newer contents.  A call that raises for bad input changes
nothing (every check runs before the first mutation), so the version it was
given stays current.  ``new(2)`` starts a fresh table.

Selected by the backend name :data:`EPHEMERAL` (``"ephemeral"``) in
:func:`~persistri.impl.complex.simpcomp.complex_structure` and
:func:`~persistri.impl.complex.simpcomp.two_complex`, so
``convex_hull(points, backend="ephemeral")`` runs the bulldozer on it (without
``history``: there are no old versions to keep).  It is deliberately *not* in
the map registry :data:`persistri.impl.maps.BACKENDS`, whose every entry is a
persistent ``ORD_MAP``.

Costs (δ = the length of a vertex's list, about 6 on a triangulated sphere):
``data``, ``find``, ``findi``, ``neighbour`` one dict lookup + δ entries; ``add`` three dict
updates (the first also scans for the triangle in either orientation);
``rem`` three lookups + three updates; each O(δ) expected, independent of the
number of vertices.

The table, its version tokens and the internal operations the baseline
inherits are in :mod:`~persistri.impl.complex.ephemeral_table`; this module
holds the public operations that read or make a version.

>>> from persistri.impl.complex import VertexState, int_vertex
>>> _, (a, b, c, d) = int_vertex.new_many(VertexState.initial(), "abcd")
>>> E = EphemeralTwoComplex()
>>> e1 = E.add(E.new(2), (a, b, c), "x")
>>> e2 = E.add(e1, (a, c, d), "y")
>>> E.find(e2, (c, a))
[(v2, v0, v1)]
>>> E.data(e1, (a, b, c))                      # doctest: +ELLIPSIS
Traceback (most recent call last):
    ...
persistri.impl.complex.errors.StaleVersionError: data: this version of an EPHEMERAL 2-complex is stale ...
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Final, TypeVar

from persistri.impl.complex.errors import (
    AbsentSimplexError,
    DuplicateSimplexError,
    OppositeOrientationError,
    RepresentationError,
)
from persistri.impl.complex.simplex import Simplex
from persistri.impl.complex.ephemeral_table import _DICT, EphemeralDict, EphemeralTable, _stale, _Table
from persistri.impl.complex.replace import arguments
from persistri.impl.complex.structure import Complex, Family
from persistri.impl.complex.two_complex import Edge, Triangle
from persistri.impl.complex.vertex_lists import Entry, Missing, Present, Unbatched, group, rebuild, rebuild_fresh
from persistri.impl.complex.vertex import Vertex
from persistri.impl.stats import Stats
from persistri.spec.option import Option

__all__ = ["EPHEMERAL", "EphemeralTwoComplex", "EphemeralDict"]

D = TypeVar("D")

EPHEMERAL: Final = "ephemeral"
"""The backend name that selects :class:`EphemeralTwoComplex` in the complex factories."""

_new_complex = tuple.__new__



class EphemeralTwoComplex(EphemeralTable[D]):
    """The 2-complex of :class:`TwoComplex` over one mutable ``dict``: NOT persistent (module docstring).

    ``EphemeralTwoComplex()`` is uncounted; ``EphemeralTwoComplex(stats)``
    counts each dict access as one dictionary operation and one key
    comparison, plus the list entries scanned, faces created and deleted.
    """

    kind = EPHEMERAL

    def __init__(self, stats: Stats | None = None) -> None:
        self.n = 2
        self._raw = _DICT
        self._m = _DICT
        self._stats = stats
        if stats is None:
            self.family = Family(self.kind, 2, _DICT, None, self)
        else:
            self.family = EphemeralTwoComplex[D]().family

    # -- hot public operations (same inline validation as TwoComplex) --------------------

    def data(self, c: Complex[D], s: Simplex, /) -> Option[D]:
        """``data (c, s)``: ``(x,)`` if the triangle ``s`` is held in this orientation, else None.  One dict lookup."""
        try:
            fam, rep, lin = c
            a, b, cc = s
            la = a.lineage
            ok = (
                fam is self.family
                and type(s) is tuple
                and (la is lin or lin is None)
                and b.lineage is la
                and cc.lineage is la
                and a != b
                and b != cc
                and a != cc
            )
        except (TypeError, ValueError, AttributeError):
            ok = False
        if not ok:
            rep, _, s = self._slow(c, s, 2, "data")
            a, b, cc = s
        table: _Table = rep[0]
        if table.current is not rep:
            raise _stale("data")
        lst = table.lists.get(a)
        if self._stats is not None:
            self._count(1, 0 if lst is None else len(lst))
        if lst is None:
            return None
        for e in lst:
            if e[0] == b and e[1] == cc:
                return (e[2],)
        return None

    def find(self, c: Complex[D], s: Simplex, /) -> list[Triangle]:
        """``find (c, (u, w))``: the triangles ``(u, w, x)``.  One dict lookup and a scan of u's list."""
        try:
            fam, rep, lin = c
            u, w = s
            lu = u.lineage
            ok = fam is self.family and type(s) is tuple and (lu is lin or lin is None) and w.lineage is lu and u != w
        except (TypeError, ValueError, AttributeError):
            ok = False
        if not ok:
            rep, _, s = self._slow(c, s, 1, "find")
            u, w = s
        table: _Table = rep[0]
        if table.current is not rep:
            raise _stale("find")
        lst = table.lists.get(u)
        if lst is None:
            if self._stats is not None:
                self._count(1, 0)
            return []
        if self._stats is not None:
            self._count(1, len(lst))
        return [(u, w, e[1]) for e in lst if e[0] == w]

    def findi(self, c: Complex[D], s: Simplex, /) -> list[tuple[Triangle, D]]:
        """``find`` with each triangle's datum.  One dict lookup."""
        try:
            fam, rep, lin = c
            u, w = s
            lu = u.lineage
            ok = fam is self.family and type(s) is tuple and (lu is lin or lin is None) and w.lineage is lu and u != w
        except (TypeError, ValueError, AttributeError):
            ok = False
        if not ok:
            rep, _, s = self._slow(c, s, 1, "findi")
            u, w = s
        table: _Table = rep[0]
        if table.current is not rep:
            raise _stale("findi")
        lst = table.lists.get(u)
        if lst is None:
            if self._stats is not None:
                self._count(1, 0)
            return []
        if self._stats is not None:
            self._count(1, len(lst))
        return [((u, w, e[1]), e[2]) for e in lst if e[0] == w]

    def neighbour(self, c: Complex[D], s: Simplex, /) -> tuple[Triangle, D] | None:
        """``findi(c, s)[0]`` or None, as :meth:`TwoComplex.neighbour`: one dict lookup, a scan that stops at the hit.

        Counted as one dictionary operation plus the list entries visited up to
        and including the hit.  StaleVersionError for a stale ``c``.
        """
        try:
            fam, rep, lin = c
            u, w = s
            lu = u.lineage
            ok = fam is self.family and type(s) is tuple and (lu is lin or lin is None) and w.lineage is lu and u != w
        except (TypeError, ValueError, AttributeError):
            ok = False
        if not ok:
            rep, _, s = self._slow(c, s, 1, "neighbour")
            u, w = s
        table: _Table = rep[0]
        if table.current is not rep:
            raise _stale("neighbour")
        lst = table.lists.get(u)
        if lst is None:
            if self._stats is not None:
                self._count(1, 0)
            return None
        visited = 0
        for e in lst:
            visited += 1
            if e[0] == w:
                if self._stats is not None:
                    self._count(1, visited)
                return (u, w, e[1]), e[2]
        if self._stats is not None:
            self._count(1, visited)
        return None

    def neighbours_unchecked(self, c: Complex[D], /) -> Callable[[Edge], tuple[Triangle, D] | None]:
        """:meth:`TwoComplex.neighbours_unchecked` on the table: ``c`` checked once (current, of this structure),
        the edges not; each a dict lookup and a scan.  ``c`` must stay current while the function is used (a
        walk reads, then changes).  Counted structures and subclasses that redefine :meth:`neighbour` get
        :meth:`neighbours`.  O(δ) per call."""
        if self._stats is not None or type(self).neighbour is not EphemeralTwoComplex.neighbour:
            return self.neighbours(c)
        rep, _ = self._unpack(c, "neighbour")
        table: _Table = rep[0]
        if table.current is not rep:
            raise _stale("neighbour")
        lists = table.lists

        def neighbour_in_c(s: Edge) -> tuple[Triangle, D] | None:
            u, w = s
            lst = lists.get(u)
            if lst is None:
                return None
            for e in lst:
                if e[0] == w:
                    return (u, w, e[1]), e[2]
            return None

        return neighbour_in_c

    def add(self, c: Complex[D], s: Simplex, x: D, /) -> Complex[D]:
        """``add (c, s, x)``: the triangle ``s`` with datum ``x`` put in the table IN PLACE; ``c`` becomes stale.

        Raises DimensionError, RepeatedVertexError, ForeignVertexError,
        DuplicateSimplexError or OppositeOrientationError before changing
        anything (``c`` then stays current); StaleVersionError for a stale ``c``.
        """
        try:
            fam, rep, lin = c
            a, b, cc = s
            la = a.lineage
            ok = (
                fam is self.family
                and type(s) is tuple
                and (la is lin or lin is None)
                and b.lineage is la
                and cc.lineage is la
                and a != b
                and b != cc
                and a != cc
            )
        except (TypeError, ValueError, AttributeError):
            ok = False
        if not ok:
            rep, slin, s = self._slow(c, s, 2, "add")
            assert slin is not None  # a validated triangle has a lineage
            la = slin
            a, b, cc = s
        table: _Table = rep[0]
        if table.current is not rep:
            raise _stale("add")
        lists = table.lists
        old = lists.get(a)
        if old is None:
            lists[a] = ((b, cc, x),)
            scanned = 0
        else:
            # The triangle, in either orientation, would be in a's list: (b, c) or (c, b).
            for e in old:
                e0 = e[0]
                if e0 == b:
                    if e[1] == cc:
                        raise DuplicateSimplexError(f"add: triangle {s!r} is already present")
                elif e0 == cc and e[1] == b:
                    raise OppositeOrientationError(
                        f"add: triangle {s!r} is present with the opposite orientation {(a, cc, b)!r}"
                    )
            lists[a] = old + ((b, cc, x),)
            scanned = len(old)
        old = lists.get(b)
        lists[b] = ((cc, a, x),) if old is None else old + ((cc, a, x),)
        old = lists.get(cc)
        lists[cc] = ((a, b, x),) if old is None else old + ((a, b, x),)
        st = self._stats
        if st is not None:
            self._count(6, scanned)
            st.faces_created += 1
        new = (table,)
        table.current = new
        return _new_complex(Complex, (self.family, new, la))

    def rem(self, c: Complex[D], s: Simplex, /) -> Complex[D]:
        """``rem (c, s)``: the triangle ``s`` taken out of the table IN PLACE; ``c`` becomes stale.

        AbsentSimplexError (before changing anything) if ``s`` is not held in this orientation.
        """
        try:
            fam, rep, lin = c
            a, b, cc = s
            la = a.lineage
            ok = (
                fam is self.family
                and type(s) is tuple
                and la is lin
                and b.lineage is la
                and cc.lineage is la
                and a != b
                and b != cc
                and a != cc
            )
        except (TypeError, ValueError, AttributeError):
            ok = False
        if not ok:
            rep, lin, s = self._slow(c, s, 2, "rem")
            a, b, cc = s
        table: _Table = rep[0]
        if table.current is not rep:
            raise _stale("rem")
        self._take_out(table.lists, a, b, cc, "rem")
        st = self._stats
        if st is not None:
            st.faces_deleted += 1
        new = (table,)
        table.current = new
        return _new_complex(Complex, (self.family, new, lin))

    def _take_out(self, lists: dict[Vertex, tuple[Entry, ...]], a: Vertex, b: Vertex, c: Vertex, what: str) -> None:
        """Take triangle (a, b, c) out of the three lists; every entry is located before the first change."""
        # Scans inlined (this is the baseline: it must not pay for calls the persistent complex avoids).
        la = lists.get(a)
        i = 0
        if la is not None:
            for e in la:
                if e[0] == b and e[1] == c:
                    break
                i += 1
        if la is None or i == len(la):
            raise AbsentSimplexError(f"{what}: triangle {(a, b, c)!r} is not in the complex (in this orientation)")
        lb = lists.get(b)
        j = 0
        if lb is not None:
            for e in lb:
                if e[0] == c and e[1] == a:
                    break
                j += 1
        lc = lists.get(c)
        k = 0
        if lc is not None:
            for e in lc:
                if e[0] == a and e[1] == b:
                    break
                k += 1
        if lb is None or lc is None or j == len(lb) or k == len(lc):
            raise RepresentationError(f"ephemeral 2-complex: triangle {(a, b, c)!r} is missing from a vertex list")
        if len(la) == 1:
            del lists[a]
        else:
            lists[a] = la[:i] + la[i + 1 :]
        if len(lb) == 1:
            del lists[b]
        else:
            lists[b] = lb[:j] + lb[j + 1 :]
        if len(lc) == 1:
            del lists[c]
        else:
            lists[c] = lc[:k] + lc[k + 1 :]
        if self._stats is not None:
            self._count(6, i + j + k + 3)

    def replace(
        self, c: Complex[D], removed: Sequence[Simplex], added: Sequence[tuple[Simplex, D]], /
    ) -> Complex[D]:
        """``replace`` of :class:`TwoComplex` on the table IN PLACE; ``c`` becomes stale.

        The same grouping by vertex, then one dict read and one dict write (or
        delete) per vertex touched; every new list is computed before the first
        write, so bad input (what the fold of ``rem`` and ``add`` would raise,
        decided on a copy of the table) changes nothing.
        """
        removed, added = arguments(removed, added)
        try:
            fam, rep, lin = c
            if fam is not self.family and fam != self.family:  # equal: e.g. a counted twin's complex
                raise Unbatched
            table: _Table = rep[0]
            if table.current is not rep:
                raise _stale("replace")
            lists = table.lists
            changes, out_lin, fresh = group(removed, added, lin)
            if fresh is not None and fresh in lists:  # a list of fresh may hold a triangle to add
                raise Unbatched
            combine = rebuild if fresh is None else rebuild_fresh
            new_lists: list[tuple[Vertex, tuple[Entry, ...] | None]] = []
            scanned = 0
            for v, change in changes.items():
                old = lists.get(v)
                if old is None:
                    if change[0]:
                        raise Unbatched
                    new_lists.append((v, tuple(change[1] + change[2])))
                    continue
                scanned += len(old)
                rebuilt = combine(old, change)
                new_lists.append((v, rebuilt if rebuilt else None))
        except (Unbatched, Missing, Present, TypeError, ValueError, AttributeError):
            return self._replace_on_copy(c, removed, added)
        for v, lst in new_lists:
            if lst is None:
                del lists[v]
            else:
                lists[v] = lst
        st = self._stats
        if st is not None:
            self._count(2 * len(new_lists), scanned)
            st.faces_deleted += len(removed)
            st.faces_created += len(added)
        new = (table,)
        table.current = new
        return _new_complex(Complex, (self.family, new, out_lin))

    def _replace_on_copy(self, c: Complex[D], removed: Sequence[Simplex], added: Sequence[tuple[Simplex, D]]) -> Complex[D]:
        """Raise what the fold of ``rem`` and ``add`` raises, running it on a copy of the table.  O(V).

        Only reached when ``replace`` found its input wrong; the copy keeps the
        table (and so ``c``) unchanged.  A fold that succeeds (a complex of an
        equal family, accepted by the general validation) is redone on the table.
        """
        rep, lin = self._open(c, "replace")
        table: _Table = rep[0]
        if table.current is not rep:
            raise _stale("replace")
        scratch = _Table()
        scratch.lists = dict(table.lists)
        self._replace_fold(_new_complex(Complex, (self.family, scratch.current, lin)), removed, added)
        return self._replace_fold(c, removed, added)
