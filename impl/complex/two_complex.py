"""The specialised 2-complex the algorithms use (paper §2 and §4): per vertex, a list of triangles.

One map of the ``ORD_MAP`` backend takes each vertex to an immutable tuple of
entries ``(second vertex, third vertex, datum)``.  An oriented triangle
``(a, b, c)`` with datum x is stored three times, once per rotation:

    under a: ``(b, c, x)``     under b: ``(c, a, x)``     under c: ``(a, b, x)``

so every order of the orientation is found by looking up its first vertex and
scanning that vertex's list for the other two.  The reverse side
``(a, c, b)`` would be ``(c, b, _)`` under a: ``add`` refuses it while
``(a, b, c)`` is present.  These per-vertex lists are the paper's
"association lists": its key comparisons are the tree nodes visited plus the
list entries visited, and so are persistri's (:class:`~persistri.impl.stats.Stats`).

Work per operation (δ = length of the list scanned, about 6 on average in a
triangulated sphere; O(lg V) per map operation with the red-black backend):

==========================  ==================================================
``data``, ``find``          one map lookup + δ entries
``neighbour``               one map lookup + the entries up to the triangle found
``add``                     three ``insertWith`` (the first also scans for the
                            triangle in either orientation)
``rem``                     three ``insertWith`` that each drop the triangle's
                            entry, the first also finding whether it is there
                            (a vertex left with no triangle is removed from the
                            map: one more operation)
``update``                  one lookup + three ``insertWith``
``vertices``                O(V);  ``simplices``, ``items``: O(V + N)
``grep``                    one lookup + δ (then the faces of the star)
==========================  ==================================================

Persistence: a list is a tuple, replaced (never changed) when one of its
entries is added, dropped or updated; the map is the backend's persistent map.
The hot operations validate their arguments in O(1) before touching the map,
and the functions ``insertWith`` combines lists with are module-level (no
closure per call; a counted structure wraps them to count the entries visited).
``rem`` relies on ``numItems`` being O(1) (it is in every persistri backend) to
tell a triangle whose first vertex has no list from one that is present.

This module holds the public operations, which validate their arguments, and
``replace``; the operations on the lists that they call after validating (and
the counting of the entries scanned) are in
:mod:`~persistri.impl.complex.two_complex_rep`, the base class.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, TypeVar

from persistri.impl.complex.replace import arguments, replace_per_vertex
from persistri.impl.complex.simplex import Simplex
from persistri.impl.complex.structure import Complex, Family
from persistri.impl.complex.two_complex_rep import Edge, Triangle, TwoComplexRep
from persistri.impl.complex.vertex import Lineage
from persistri.impl.complex.vertex_lists import (
    Changes,
    Missing,
    Present,
    Unbatched,
    cat,
    cat_first,
    cat_new,
    drop,
    drop_add,
    group,
    put,
    replace_batched,
)
from persistri.impl.complex.neighbours import (
    neighbours_in,
    neighbours_unchecked_in,
    neighbours_unchecked_in_tree,
    neighbours_unchecked_in_trie,
)
from persistri.impl.maps.int_trie_nodes import find_unchecked as _int_trie_find
from persistri.impl.maps.red_black_tree import find as _red_black_find
from persistri.impl.stats import Stats
from persistri.spec.option import Option

__all__ = ["TwoComplex", "Triangle", "Edge"]

D = TypeVar("D")


_new_complex = tuple.__new__


class TwoComplex(TwoComplexRep[D]):
    """``structure TwoComplex : SIMPCOMP`` for n = 2, specialised as in the paper's §4 (module docstring).

    ``TwoComplex(backend)`` is uncounted; ``TwoComplex(backend, stats)`` reports
    dictionary operations and key comparisons (tree nodes plus list entries
    visited), faces created and faces deleted to ``stats``.
    """

    kind = "two"

    def __init__(self, backend: Any, stats: Stats | None = None) -> None:
        self.n = 2
        self._init_maps(backend, stats)
        # The combining functions, chosen once: the module's own, or counting versions.
        self._cat_first = self._combiner(cat_first)
        self._cat = self._combiner(cat)
        self._drop = self._combiner(drop)
        self._put = self._combiner(put)
        self._drop_add = self._combiner(drop_add)
        self._cat_new = self._combiner(cat_new)
        # A backend that updates several keys in one descent (red-black's adjust_sorted; uncounted only:
        # the counting wrapper has none, so counted runs make the per-vertex insertWith the paper counts).
        # Unchecked: replace sorts the vertices itself, and they are validated.
        self._adjust_sorted: Callable[..., tuple[Any, list[int], list[int]]] | None = getattr(
            self._m, "adjust_sorted", None
        )
        # The same, inserting the new vertex of a cone in the same descent (red-black's adjust_insert); a
        # backend that then removes the emptied vertices itself (the arena's adjust_insert_remove, which reports
        # none left, and only when no vertex is absent: the same tree) keeps no path that the removal copies again.
        self._adjust_insert: Callable[..., tuple[Any, list[int], list[int], bool]] | None = getattr(
            self._m, "adjust_insert_remove", None
        ) or getattr(self._m, "adjust_insert", None)
        # The vertices it reports absent are known absent: the backend's unchecked insert if it has one.
        self._insert_absent: Callable[[Any, Any, Any], Any] = getattr(self._m, "insert_absent", None) or self._m.insert
        if stats is None:
            self.family = Family(self.kind, 2, backend, None, self)
        else:
            self.family = TwoComplex[D](backend).family
        # What replace_trusted (impl/complex/replace.py) needs to do what replace does, compiled: only where
        # replace is this class's own, uncounted and batched (else it calls the structure's replace).
        self._batched: tuple[Family, Any, Any, Any, Any] | None = None
        if stats is None and self._adjust_sorted is not None and type(self).replace is TwoComplex.replace:
            self._batched = (
                self.family,
                self._adjust_sorted,
                self._insert_absent,
                self._m.remove,
                self._adjust_insert,
            )

    # -- hot public operations ---------------------------------------------------------
    #
    # Each validates in O(1) inline (a complex of this family; vertices of its
    # lineage, distinct, and the right number of them) and only when that quick
    # test fails calls the general validator, which raises the precise error.
    # Inline because a function call costs as much as a third of a map lookup.

    def _slow(self, c: Any, s: Any, k: int, what: str) -> tuple[Any, Lineage | None, Simplex]:
        """The general validation (raises the specific error, or accepts e.g. a list of vertices)."""
        rep, lin = self._open(c, what)
        t, slin = self._arg(s, k, lin, what)
        return rep, slin, t

    def data(self, c: Complex[D], s: Simplex, /) -> Option[D]:
        """``data (c, s)``: ``(x,)`` if the triangle ``s`` is held in this orientation with datum x, else None.

        One map lookup and a scan of the list of ``s[0]``.
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
            rep, _, s = self._slow(c, s, 2, "data")
            a, b, cc = s
        found = self._m.find(rep, a)
        if found is None:
            return None
        if self._stats is not None:
            lst = found[0]
            i = self._scan(lst, b, cc)
            return None if i < 0 else (lst[i][2],)
        for e in found[0]:
            if e[0] == b and e[1] == cc:
                return (e[2],)
        return None

    def find(self, c: Complex[D], s: Simplex, /) -> list[Triangle]:
        """``find (c, (u, w))``: the triangles ``(u, w, x)`` having the oriented edge ``(u, w)`` as a face.

        In a closed surface there is exactly one: the neighbour across the
        reverse edge ``(w, u)`` of the triangle that holds ``(w, u)``.  One map
        lookup (u) and a scan of u's list for second vertex w.
        """
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
        found = self._m.find(rep, u)
        if found is None:
            return []
        lst = found[0]
        if self._stats is not None:
            self._stats.key_comparisons += len(lst)
        return [(u, w, e[1]) for e in lst if e[0] == w]

    def findi(self, c: Complex[D], s: Simplex, /) -> list[tuple[Triangle, D]]:
        """``find`` with each triangle's datum: ``[((u, w, x), datum), …]``.  One map lookup."""
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
        found = self._m.find(rep, u)
        if found is None:
            return []
        lst = found[0]
        if self._stats is not None:
            self._stats.key_comparisons += len(lst)
        return [((u, w, e[1]), e[2]) for e in lst if e[0] == w]

    def neighbour(self, c: Complex[D], s: Simplex, /) -> tuple[Triangle, D] | None:
        """The one triangle holding the directed edge ``s = (u, w)``, as ``((u, w, x), datum)``, or None.

        persistri's addition to the signature, for the walks of §3 and §5 that
        cross an edge: it means ``findi(c, s)[0]`` if ``findi`` finds anything,
        else None.  On an oriented surface an edge is in at most one triangle in
        a given direction; where ``findi`` finds several, the first in ``findi``'s
        order (the order of u's list) is returned.  Same validation and errors as
        ``findi`` (messages say "neighbour").  One map lookup (u) and a scan of u's
        list that stops at the triangle; counted as one dictionary operation and,
        besides the tree nodes, the list entries visited *up to and including the
        hit* (the whole list when there is none; ``findi`` always counts the whole list).
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
        found = self._m.find(rep, u)
        if found is None:
            return None
        if self._stats is None:
            for e in found[0]:
                if e[0] == w:
                    return (u, w, e[1]), e[2]
            return None
        st = self._stats
        visited = 0
        for e in found[0]:
            visited += 1
            if e[0] == w:
                st.key_comparisons += visited
                return (u, w, e[1]), e[2]
        st.key_comparisons += visited
        return None

    def neighbours(self, c: Complex[D], /) -> Callable[[Simplex], tuple[Triangle, D] | None]:
        """The function ``s ↦ neighbour(c, s)`` for the one version ``c``: for a walk that crosses many of its edges.

        It validates ``c`` once and reads each vertex's list from the map at most
        once: ``c`` never changes, so a list it has read stays right, and the next
        edge from the same vertex costs only the scan.  One bulldozer insertion
        crosses about ten edges from about six vertices.  The same results and
        the same errors as :meth:`neighbour`.  Counted structures, and
        subclasses that redefine :meth:`neighbour` (the ephemeral baseline, the
        recorder of traces), get :meth:`neighbour` itself, so that every call is
        counted or recorded as one.  O(1) to make; a call costs O(lg V + δ) the
        first time its vertex is met and O(δ) after.
        """
        if self._stats is not None or type(self).neighbour is not TwoComplex.neighbour:
            return lambda s: self.neighbour(c, s)
        rep, lin = self._unpack(c, "neighbour")
        neighbour = self.neighbour
        # The slow path raises the precise error, or accepts what neighbour accepts.
        # The backend's unchecked find if it has one (the red-black map): the vertices are validated first.
        find = getattr(self._m, "find_unchecked", None) or self._m.find
        return neighbours_in(rep, lin, find, lambda s: neighbour(c, s))

    def neighbours_unchecked(self, c: Complex[D], /) -> Callable[[Edge], tuple[Triangle, D] | None]:
        """:meth:`neighbours` for a caller that passes only edges ``(u, w)`` of triangles it holds in ``c``.

        The version is validated once; the edges are not (an edge of two
        distinct vertices of ``c``'s lineage is the caller's duty, as the
        bulldozer's walk over the faces it read from ``c`` guarantees).  The same
        answers as :meth:`neighbours` on such edges; counted structures and
        subclasses that redefine :meth:`neighbour` get :meth:`neighbours`, so
        every call is still counted or recorded.  O(lg V + δ) for a vertex met
        first, O(δ) after.
        """
        if self._stats is not None or type(self).neighbour is not TwoComplex.neighbour:
            return self.neighbours(c)
        rep, _ = self._unpack(c, "neighbour")
        find = getattr(self._m, "find_unchecked", None) or self._m.find
        if find is _red_black_find:  # the red-black map (size, tree): its search written out in the walk
            return neighbours_unchecked_in_tree(rep[1])
        if find is _int_trie_find:  # the integer trie (size, s, root, ns, nroot): its search written out
            return neighbours_unchecked_in_trie(rep)
        return neighbours_unchecked_in(rep, find)

    def add(self, c: Complex[D], s: Simplex, x: D, /) -> Complex[D]:
        """``add (c, s, x)``: ``c`` with the triangle ``s`` carrying ``x``: three ``insertWith``.

        Raises DimensionError, RepeatedVertexError, ForeignVertexError,
        DuplicateSimplexError or OppositeOrientationError; ``c`` is unchanged.
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
        rep = self._add(rep, s, x)
        if self._stats is not None:
            self._stats.faces_created += 1
        return _new_complex(Complex, (self.family, rep, la))

    def rem(self, c: Complex[D], s: Simplex, /) -> Complex[D]:
        """``rem (c, s)``: ``c`` without the triangle ``s``: one lookup, three updates.  AbsentSimplexError if absent."""
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
        rep = self._rem(rep, s)
        if self._stats is not None:
            self._stats.faces_deleted += 1
        return _new_complex(Complex, (self.family, rep, lin))

    def replace(
        self, c: Complex[D], removed: Sequence[Simplex], added: Sequence[tuple[Simplex, D]], /
    ) -> Complex[D]:
        """``c`` without the triangles ``removed`` and with the triangles ``added`` (each with its datum).

        Means exactly ``rem`` of each removed triangle in turn, then ``add`` of
        each added one (the fold; :meth:`ComplexStructure.replace`), and raises
        what that fold would raise, with ``c`` unchanged.  It is persistri's
        addition to the paper's signature, for the algorithms' one change per
        step: an insertion replaces a star (the visible faces by the tent, §3;
        a triangle's star by the new vertex's, §5).

        Done in one map operation per vertex touched instead of three per
        triangle (:mod:`~persistri.impl.complex.replace`): O(V_t·lg V + Σ δ)
        with V_t the vertices touched and δ their list lengths.
        """
        tr = type(removed)
        ta = type(added)
        if (tr is not list and tr is not tuple) or (ta is not list and ta is not tuple):  # inline: a call costs more
            removed, added = arguments(removed, added)
        try:
            fam, rep, lin = c
            if fam is not self.family and fam != self.family:  # equal: e.g. a counted twin's complex
                raise Unbatched
            changes, out_lin, fresh = group(removed, added, lin)
            adjust = self._adjust_sorted
            if adjust is not None:
                rep = replace_batched(
                    rep, changes, adjust, self._insert_absent, self._m.remove, fresh, self._adjust_insert
                )
            else:
                rep = self._replace_per_vertex(rep, changes)
        except (Unbatched, Missing, Present, TypeError, ValueError, AttributeError):
            # Something is wrong: the fold raises the precise error the signature promises.
            return self._replace_fold(c, removed, added)
        st = self._stats
        if st is not None:
            st.faces_deleted += len(removed)
            st.faces_created += len(added)
        return _new_complex(Complex, (self.family, rep, out_lin))

    def _replace_per_vertex(self, rep: Any, changes: Changes) -> Any:
        """``replace``'s map changes one vertex at a time (:func:`~persistri.impl.complex.replace.replace_per_vertex`)."""
        return replace_per_vertex(self._m, rep, changes, self._drop_add, self._cat_new)

    def _unpack(self, c: Any, what: str) -> tuple[Any, Lineage | None]:
        if type(c) is Complex:
            fam, rep, lin = c
            if fam is self.family:
                return rep, lin
        return self._open(c, what)

    def items(self, c: Complex[D], /) -> list[tuple[Triangle, D]]:
        """Each triangle once (as the rotation starting at its smallest vertex), with its datum.  O(V + N)."""
        rep, _ = self._unpack(c, "items")
        return list(self._items(rep))
