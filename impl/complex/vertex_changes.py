"""``replace``'s changes by vertex (paper §3, §5): grouped from its two arguments, and made in one batch.

A ``replace`` names the triangles it removes and adds; the 2-complex stores a list per vertex
(:mod:`~persistri.impl.complex.vertex_lists`).  This module turns the first into changes of the second
— :func:`group` for any ``replace``, :func:`group_cone` for a star replaced by a cone from a fresh vertex
over a cycle given in order (the scattered Delaunay's fan, the mesh's insertion) — and makes them: each
vertex's list rebuilt once (:func:`rebuild_cone` for a cone's change), every present vertex in one descent
of the red-black map (:func:`replace_batched`).  :mod:`~persistri.impl.complex.replace` chooses among
them.  The names are importable from :mod:`~persistri.impl.complex.vertex_lists` too, where the
structures import them.

The compiled twin compiles this module with mypyc, as it does the lists' functions: entries, lists and
changes are typed as tuples of any length for the reason :mod:`~persistri.impl.complex.vertex_lists`
gives (each stays the one object older versions share).  Vertices are ``Any``: the structure has
validated them, or the grouping raises ``Unbatched`` and the structure's fold decides.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, Final, TypeAlias

# vertex_lists re-exports this module's names at its end: it is imported first (the package's modules and
# replace.py import it before this one), and this import finds its names defined.
from persistri.impl.complex.vertex_lists import (
    Change,
    Entry,
    Unbatched,
    VertexList,
    rebuild,
    rebuild_fresh,
)

__all__ = ["Changes", "group", "group_cone", "rebuild_cone", "replace_batched"]

Changes: TypeAlias = dict[Any, Change]
"""What ``replace`` does to each vertex's list (:data:`~persistri.impl.complex.vertex_lists.Change`), by vertex."""

_NO_APEX: Final[Any] = object()
""":func:`group`'s apex before the first added triangle (no vertex is this object)."""


def group(removed: Sequence[Any], added: Sequence[Any], lin: Any) -> tuple[Changes, Any, Any]:
    """The changes of ``replace`` grouped by vertex, the lineage of the result, and the fresh vertex or None.

    Validates each triangle as ``add`` and ``rem`` do (a tuple of three distinct
    vertices of the complex's lineage) and refuses a triangle added twice or in
    both orientations; raises Unbatched (or the TypeError / ValueError /
    AttributeError of a malformed argument) on anything unusual, and the caller
    lets the fold raise the precise error.  O(|removed| + |added|).  A lineage is
    read once per vertex object, and a repeated vertex is told by two changes
    sharing their lists: identity tests, where ``a.lineage`` and ``!=`` on an
    ``int`` subclass are generic (unspecialised) steps.

    *fresh* is the vertex every added triangle ends with when it is one object
    in no removed triangle (a star replaced by a cone from a new vertex), else
    None: if it has no list, no added triangle can be in the complex
    (:func:`~persistri.impl.complex.vertex_lists.rebuild_fresh`; the caller confirms the absence).  The apex's
    change is kept in locals, so an added triangle that ends with it costs
    two dictionary look-ups, not three.  The loop variables' types let the
    compiled twin unpack the triangles natively, and ``changes.get`` called
    as a method is a native dictionary look-up there (through a bound method
    it was a generic call: −8 % of the twin's ``group``, docs/performance.md).
    """
    changes: Changes = {}
    # Each triangle's type is tested on the object as passed (t), then unpacked through s: the compiled twin
    # unboxes s, and a test on s would box a new tuple for it (12 an insertion of the Delaunay's).
    t: Any
    s: tuple[Any, Any, Any]
    sx: tuple[Any, Any]
    # The lists of a change, typed for the compiled twin (a list's append, not a generic method call).
    drops: list[tuple[Any, Any]]
    adds: list[Entry]
    for t in removed:
        if type(t) is not tuple:
            raise Unbatched
        s = t
        a, b, cc = s
        cha = changes.get(a)
        if cha is None:
            if a.lineage is not lin:
                raise Unbatched
            cha = ([(b, cc)], [], [], a)
            changes[a] = cha
        elif cha[3] is a or a.lineage is lin:
            drops = cha[0]
            drops.append((b, cc))
        else:
            raise Unbatched
        chb = changes.get(b)
        if chb is None:
            if b.lineage is not lin:
                raise Unbatched
            chb = ([(cc, a)], [], [], b)
            changes[b] = chb
        elif chb[3] is b or b.lineage is lin:
            drops = chb[0]
            drops.append((cc, a))
        else:
            raise Unbatched
        chc = changes.get(cc)
        if chc is None:
            if cc.lineage is not lin:
                raise Unbatched
            chc = ([(a, b)], [], [], cc)
            changes[cc] = chc
        elif chc[3] is cc or cc.lineage is lin:
            drops = chc[0]
            drops.append((a, b))
        else:
            raise Unbatched
        if cha[0] is chb[0] or chb[0] is chc[0] or cha[0] is chc[0]:  # a repeated vertex: one change
            raise Unbatched
    out_lin = lin
    # The apex: the object the first added triangle ends with; fch and fplain its change and plain entries.
    fresh: Any = _NO_APEX
    fch: Change = ()
    fplain: list[Entry] = []
    cone = True  # every added triangle so far ends with the object fresh
    for sx in added:
        t, x = sx
        if type(t) is not tuple:
            raise Unbatched
        s = t
        a, b, cc = s
        if out_lin is None:
            out_lin = a.lineage
        cha = changes.get(a)
        if cha is None:
            if a.lineage is not out_lin:
                raise Unbatched
            cha = ([], [(b, cc, x)], [], a)
            changes[a] = cha
        elif cha[3] is a or a.lineage is out_lin:
            # Added twice, or in both orientations: every triangle of the batch is already
            # under each of its vertices, so one test at the first vertex finds it.
            adds = cha[1]
            for e in adds:
                if (e[0] == b and e[1] == cc) or (e[0] == cc and e[1] == b):
                    raise Unbatched
            plain: list[Entry] = cha[2]
            for e in plain:
                if (e[0] == b and e[1] == cc) or (e[0] == cc and e[1] == b):
                    raise Unbatched
            adds.append((b, cc, x))
        else:
            raise Unbatched
        chb = changes.get(b)
        if chb is None:
            if b.lineage is not out_lin:
                raise Unbatched
            chb = ([], [], [(cc, a, x)], b)
            changes[b] = chb
        elif chb[3] is b or b.lineage is out_lin:
            adds = chb[2]
            adds.append((cc, a, x))
        else:
            raise Unbatched
        if cc is fresh:  # a cone's triangle: its apex's change is known
            chc = fch
            adds = fplain
            adds.append((a, b, x))
        else:
            chc = changes.get(cc)
            if chc is None:
                if cc.lineage is not out_lin:
                    raise Unbatched
                chc = ([], [], [(a, b, x)], cc)
                changes[cc] = chc
            elif chc[3] is cc or cc.lineage is out_lin:
                adds = chc[2]
                adds.append((a, b, x))
            else:
                raise Unbatched
            if fresh is _NO_APEX:
                fresh = cc
                fch = chc
                fplain = chc[2]
            else:
                cone = False
        if cha[0] is chb[0] or chb[0] is chc[0] or cha[0] is chc[0]:  # a repeated vertex: one change
            raise Unbatched
    if not cone or fresh is _NO_APEX or changes[fresh][0]:
        fresh = None
    return changes, out_lin, fresh


def group_cone(removed: Sequence[Any], added: Sequence[Any], lin: Any) -> Changes:
    """:func:`group` for a star replaced by a *cone*, read off the cone's cycle: the changes by vertex, each
    ``(drops, tail, v)`` — the flat list of the pairs to drop, the entries to append, the vertex — for
    :func:`rebuild_cone`; the apex's ``tail`` is its whole list.

    The cone: ``added`` is ``[((c0, c1, x), d0), ((c1, c2, x), d1), …, ((c(m-1), c0, x), d(m-1))]``, the
    triangles from the apex ``x`` over a cycle of ``m ≥ 3`` distinct vertices, in the cycle's order (the
    scattered Delaunay's fan with its ghosts, paper §5; the hull's tent, §3).  Then each cycle vertex ``ci``
    gets the checked entry ``(c(i+1), x, di)`` and the plain entry ``(x, c(i-1), d(i-1))`` — the tail
    :func:`group` gives it, in its order — and the apex the entries ``(ci, c(i+1), di)`` in the order of
    ``added``, with no dictionary read for any of them; ``removed`` is grouped as :func:`group` groups it,
    each pair's drops in the same order.  So the changes mean what :func:`group`'s mean
    (``tests/test_complex_replace_cone.py`` compares them), and the lists :func:`rebuild_cone` makes are
    :func:`~persistri.impl.complex.vertex_lists.rebuild_fresh`'s.

    Validates as :func:`group` does, more strictly: the apex of the complex's lineage ``lin`` and in no
    removed triangle, every cycle vertex of the apex's class (a lineage's vertices of one kind share a
    class: one identity test) or of its lineage, every vertex of a removed triangle the very object of a
    cycle vertex, the triangles tuples.
    Anything else — ``added`` not such a cone, an empty complex, a vertex of a removed triangle off the
    cycle — raises Unbatched (or the TypeError / ValueError of a malformed argument), and the caller
    lets :func:`group` or the fold decide.  O(|removed| + m).
    """
    m = len(added)
    if m < 3 or lin is None:
        raise Unbatched
    changes: Changes = {}
    t: Any
    s: tuple[Any, Any, Any]
    sx: tuple[Any, Any]
    # The last triangle (c(m-1), c0, x): the apex, the first cycle vertex c0, and c(m-1) with its datum.
    sx = added[m - 1]
    t, xp = sx
    if type(t) is not tuple:
        raise Unbatched
    s = t
    ap, a, apex = s
    if apex.lineage is not lin:
        raise Unbatched
    vt = type(apex)
    fan: list[Entry] = []
    for sx in added:
        t, x = sx
        if type(t) is not tuple:
            raise Unbatched
        s = t
        c0, b, cc = s
        if c0 is not a or cc is not apex or (type(a) is not vt and a.lineage is not lin):
            raise Unbatched
        changes[a] = ([], ((b, cc, x), (cc, ap, xp)), a)
        fan.append((a, b, x))
        ap = a
        a = b
        xp = x
    if len(changes) != m or apex in changes:  # a repeated cycle vertex, or the apex on the cycle
        raise Unbatched
    drops: list[Any]
    for t in removed:
        if type(t) is not tuple:
            raise Unbatched
        s = t
        a, b, cc = s
        cha = changes.get(a)
        chb = changes.get(b)
        chc = changes.get(cc)
        if cha is None or chb is None or chc is None or cha[2] is not a or chb[2] is not b or chc[2] is not cc:
            raise Unbatched
        drops = cha[0]
        if drops is chb[0] or chb[0] is chc[0] or drops is chc[0]:  # a repeated vertex: one change
            raise Unbatched
        drops.append(b)
        drops.append(cc)
        drops = chb[0]
        drops.append(cc)
        drops.append(a)
        drops = chc[0]
        drops.append(a)
        drops.append(b)
    changes[apex] = ([], tuple(fan), apex)
    return changes


def rebuild_cone(old: VertexList, change: Change) -> VertexList:
    """A vertex's new list in a cone's ``replace`` (:func:`group_cone`'s change ``(drops, tail, v)``): ``old``
    without the entries ``(b, c, _)`` of the pairs in the flat list ``drops = [b0, c0, b1, c1, …]``, then
    the entries of ``tail``.

    :func:`~persistri.impl.complex.vertex_lists.rebuild_fresh` for a change already in its final form:
    no tail tuple to build, no pair tuple per drop.  Every added triangle names the fresh apex, so there is
    no ``Present`` to look for.  The scan for a pair compares vertex objects by identity first (an entry and
    the triangle that dropped it were made from the same objects by an algorithm that keeps one object per
    vertex) and by ``==`` only where identity finds nothing; on a list of a valid complex each ``(b, c)`` is
    there at most once, so either finds the same entry.  Missing if a pair is not there (or is asked
    twice).  O(len(old)).
    """
    drops: list[Any] = change[0]
    tail: VertexList = change[1]
    n = len(drops)
    if n == 2:
        b = drops[0]
        c = drops[1]
        k = 0
        for e in old:
            if e[0] is b and e[1] is c:
                return old[:k] + old[k + 1 :] + tail
            k += 1
        return rebuild_fresh(old, ([(b, c)], [], list(tail)))  # by ==, or Missing
    if n == 4:
        b = drops[0]
        c = drops[1]
        b2 = drops[2]
        c2 = drops[3]
        i = -1
        j = -1
        k = 0
        for e in old:
            e0 = e[0]
            if e0 is b and e[1] is c:
                i = k
                if j >= 0:
                    break
            elif e0 is b2 and e[1] is c2:
                j = k
                if i >= 0:
                    break
            k += 1
        else:
            return rebuild_fresh(old, ([(b, c), (b2, c2)], [], list(tail)))
        if j < i:
            i, j = j, i
        return old[:i] + old[i + 1 : j] + old[j + 1 :] + tail
    if n:  # three pairs or more (a fifth of a Delaunay's ring vertices): each entry against each pair
        kept: list[Entry] = []
        append = kept.append
        for e in old:
            e0 = e[0]
            e1 = e[1]
            k = 0
            while k < n:
                if drops[k] is e0 and drops[k + 1] is e1:
                    break
                k += 2
            else:
                append(e)
        if len(kept) * 2 + n == len(old) * 2:  # each pair found (entries are distinct): the lists agree
            return tuple(kept) + tail
    pairs = [(drops[k], drops[k + 1]) for k in range(0, n, 2)]
    return rebuild_fresh(old, (pairs, [], list(tail)))


def replace_batched(
    rep: Any,
    changes: Changes,
    adjust_sorted: Callable[..., tuple[Any, list[int], list[int]]],
    insert: Callable[[Any, Any, Any], Any],
    remove: Callable[[Any, Any], tuple[Any, Any]],
    fresh: Any = None,
    adjust_insert: Callable[..., tuple[Any, list[int], list[int], bool]] | None = None,
) -> Any:
    """``replace``'s map changes through a backend's ``adjust_sorted`` (its ``insert`` and ``remove`` besides).

    Every present vertex's list rebuilt in one descent (the red-black tree
    copies the nodes its search paths share once), then the new vertices
    inserted and the emptied ones removed.  Raises what the per-vertex updates
    raise (Missing, Present; Unbatched for a triangle to remove at a vertex
    with no list).  With ``fresh`` (:func:`group`'s third result) the lists are
    rebuilt by :func:`~persistri.impl.complex.vertex_lists.rebuild_fresh`, and Unbatched is raised unless ``fresh``
    is among the vertices the map does not hold; given the backend's
    ``adjust_insert`` too, ``fresh`` is inserted in the same descent
    (the red-black tree copies the top of the tree once, not twice).
    """
    keys = sorted(changes)
    vals = [changes[k] for k in keys]
    if fresh is None:
        rep, absent, emptied = adjust_sorted(rebuild, rep, keys, vals)
    elif adjust_insert is None:
        rep, absent, emptied = adjust_sorted(rebuild_fresh, rep, keys, vals)
    else:
        j = 0
        while keys[j] is not fresh:
            j += 1
        change = vals[j]
        rep, absent, emptied, inserted = adjust_insert(
            rebuild_fresh, rep, keys, vals, j, tuple(change[1] + change[2])
        )
        if inserted:
            fresh = None  # it was absent: confirmed, and inserted
    for i in absent:
        change = vals[i]
        if change[0]:  # the vertex had no list: a triangle to remove is absent
            raise Unbatched
        k = keys[i]
        if k is fresh:
            fresh = None  # confirmed absent
        rep = insert(rep, k, tuple(change[1] + change[2]))
    if fresh is not None:  # a list of fresh may hold a triangle to add: the fold decides
        raise Unbatched
    for i in emptied:  # keys[i] is in no triangle any more
        rep = remove(rep, keys[i])[0]
    return rep
