"""The edge look-ups of one version of the 2-complex that the walks call: ``s ↦ neighbour(c, s)``, many times.

A walk (the bulldozer's over the lit faces, §3; the Delaunay point location,
§5) crosses many edges of one version.  :func:`neighbours_in` answers
:meth:`~persistri.impl.complex.two_complex.TwoComplex.neighbour` for each,
reading every vertex's list from the map at most once; :func:`neighbours_unchecked_in`
does the same for callers that pass only edges of triangles they hold, without
checking each edge, and :func:`neighbours_unchecked_in_tree` the same again over
the red-black backend's tree with its search written out in the function (the
hull's walk: a vertex met first costs a descent and no Python call), as
:func:`neighbours_unchecked_in_trie` does over the integer trie's.  The
compiled twin compiles this module (docs/performance.md).
Vertices are ``Any`` here: the structure has validated the version.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from persistri.impl.complex.vertex_lists import VertexList
from persistri.impl.maps.int_trie_absent import ABSENT
from persistri.impl.maps.int_trie_nodes import find as _trie_find
from persistri.impl.maps.red_black_tree import Tree

__all__ = ["neighbours_in", "neighbours_unchecked_in", "neighbours_unchecked_in_tree", "neighbours_unchecked_in_trie"]


def neighbours_in(
    rep: Any, lin: Any, find: Callable[[Any, Any], Any], slow: Callable[[Any], Any]
) -> Callable[[Any], Any]:
    """``TwoComplex.neighbours`` of one version: ``s ↦ ((u, w, x), datum)`` for the triangle holding the
    directed edge ``s = (u, w)``, or None.

    ``rep`` is the version's map and ``lin`` its lineage, ``find`` the backend's
    ``find``; ``slow`` is called for any ``s`` that is not a valid edge of the
    lineage (it raises the signature's error, or answers as ``neighbour``
    does).  Each vertex's list is read from the map at most once (the version
    never changes, so a list read stays right).  O(lg V + δ) for a vertex met
    first, O(δ) after.
    """
    lists: dict[Any, VertexList] = {}

    def neighbour_in_c(s: Any) -> Any:
        try:
            u, w = s
            lu = u.lineage
            ok = type(s) is tuple and (lu is lin or lin is None) and w.lineage is lu and u != w
        except (TypeError, ValueError, AttributeError):
            ok = False
        if not ok:
            return slow(s)
        lst = lists.get(u)
        if lst is None:
            found = find(rep, u)
            if found is None:
                return None
            lst = lists[u] = found[0]
        for e in lst:
            if e[0] == w:
                return (u, w, e[1]), e[2]
        return None

    return neighbour_in_c


def neighbours_unchecked_in(rep: Any, find: Callable[[Any, Any], Any]) -> Callable[[Any], Any]:
    """:func:`neighbours_in` without checking each edge: ``s`` must be a tuple ``(u, w)`` of two distinct
    vertices of the version's lineage (an edge of a triangle the caller read from this version, say).

    An invalid ``s`` gets an unspecified answer or error, never the signature's.
    ``rep`` is the version's map and ``find`` the backend's ``find``.  The same
    answers as :func:`neighbours_in` on valid edges; O(lg V + δ) for a vertex met
    first, O(δ) after.
    """
    lists: dict[Any, VertexList] = {}

    def neighbour_in_c(s: Any) -> Any:
        u, w = s
        lst = lists.get(u)
        if lst is None:
            found = find(rep, u)
            if found is None:
                return None
            lst = lists[u] = found[0]
        for e in lst:
            if e[0] == w:
                return (u, w, e[1]), e[2]
        return None

    return neighbour_in_c


def neighbours_unchecked_in_tree(tree: Tree) -> Callable[[Any], Any]:
    """:func:`neighbours_unchecked_in` of a red-black map ``(size, tree)`` with ``find`` its
    :func:`~persistri.impl.maps.red_black_tree.find`, that search written out here: the same answers.

    The walk's look-up of a vertex met first is a descent of the tuple tree
    (Andersson's, one ``<`` a level, as ``find``) in this function's frame,
    without the Python call of ``find`` and its ``(value,)`` tuple: on the
    interpreter a call costs about as much as two levels' work (the OnSphere
    8K hull, six look-ups an insertion: −4,800 instructions an insertion,
    docs/performance.md, "The price of persistence").  O(lg V + δ) for a
    vertex met first, O(δ) after.
    """
    lists: dict[Any, VertexList] = {}

    def neighbour_in_c(s: Any) -> Any:
        u, w = s
        lst = lists.get(u)
        if lst is None:
            t = tree
            cand: Tree = None
            while t is not None:
                if u < t[2]:
                    t = t[1]
                else:
                    cand = t
                    t = t[4]
            if cand is None or cand[2] < u:
                return None
            lst = lists[u] = cand[3]
        for e in lst:
            if e[0] == w:
                return (u, w, e[1]), e[2]
        return None

    return neighbour_in_c


def neighbours_unchecked_in_trie(rep: Any) -> Callable[[Any], Any]:
    """:func:`neighbours_unchecked_in` of an integer trie map ``(size, s, root, ns, nroot)``
    (:mod:`persistri.impl.maps.int_trie`), its search written out here for the vertices ``≥ 0``: the same
    answers.  A vertex met first costs a shift, a mask and an index a level (3 levels below 32,768
    vertices) and no Python call; O(lg V + δ) for a vertex met first, O(δ) after.
    """
    lists: dict[Any, VertexList] = {}
    height: int = rep[1]
    root: Any = rep[2]
    top = height + 5

    def neighbour_in_c(s: Any) -> Any:
        u, w = s
        lst = lists.get(u)
        if lst is None:
            if u < 0:
                x = _trie_find(rep[4], rep[3], ~u)
            elif root is None or u >> top:
                return None
            else:
                t = root
                h = height
                while h:
                    t = t[(u >> h) & 31]
                    if t is None:
                        return None
                    h -= 5
                x = t[(u & 31) + 1]
            if x is ABSENT:
                return None
            lst = lists[u] = x
        for e in lst:
            if e[0] == w:
                return (u, w, e[1]), e[2]
        return None

    return neighbour_in_c
