"""The per-vertex lists of the specialised 2-complex (paper §4) and the functions that rebuild them.

:class:`~persistri.impl.complex.two_complex.TwoComplex` maps each vertex to an
immutable tuple of entries ``(second vertex, third vertex, datum)``, the
paper's association list; its docstring describes the representation and the
costs.  This module holds what works on those lists: the functions
``insertWith`` combines a vertex's old list with (``add``, ``rem``, ``update``,
``replace``).  The grouping of a ``replace`` by vertex and its batched update are
:mod:`~persistri.impl.complex.vertex_changes` (their names are importable from here too), the edge
lookups of one version that the walks call :mod:`~persistri.impl.complex.neighbours`.  They are a module of
their own because the 2-complex spends its time here: the compiled twin
(``make compiled``, docs/performance.md) compiles it with mypyc, and
:mod:`~persistri.impl.complex.two_complex`, which validates the public
arguments and raises the signature's errors, stays interpreted.

Entries and lists are typed as tuples of *any* length (``tuple[Any, ...]``):
mypyc stores a fixed-length tuple type unboxed and boxes it again on the way
out, so an entry kept by a rebuilt list would come back as a new, equal tuple,
no longer shared with the older versions that hold it.  Typed this way each
stays one object (``tests/test_complex_replace.py`` checks the kept entries,
the untouched lists and the map's subtrees by identity).  Vertices are
``Any`` here: the structure has validated them.

A tuple per entry, not one flat tuple per list: flat lists keep 8 % less and
cost 8 % more instructions (docs/performance.md, "Memory of a full history").

The exceptions are signals between these functions and the structure, never
seen by a caller of the 2-complex: the structure turns them into the
signature's errors (or, in ``replace``, falls back to the fold that raises
them).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeAlias

__all__ = [
    "Entry",
    "VertexList",
    "Change",
    "Changes",
    "Combine",
    "Emptied",
    "Missing",
    "Unbatched",
    "Present",
    "cat",
    "cat_first",
    "drop",
    "put",
    "drop_add",
    "drop_add_general",
    "cat_new",
    "rebuild",
    "rebuild_fresh",
    "rebuild_cone",
    "visited",
    "group",
    "group_cone",
    "replace_batched",
]

Entry: TypeAlias = tuple[Any, ...]
"""``(second vertex, third vertex, datum)`` in the list of the first vertex (any length for mypyc: see above)."""

VertexList: TypeAlias = tuple[Entry, ...]
"""A vertex's list: its entries, one per triangle at the vertex."""

Change: TypeAlias = tuple[Any, ...]
"""What ``replace`` does to one vertex's list, ``(drops, checked, plain, v)``: the list of pairs ``(b, c)`` to
drop, the list of entries to add of the triangles that start at the vertex (checked against the list), the
list of the other entries to add, and the vertex object whose lineage
:func:`~persistri.impl.complex.vertex_changes.group` checked (the combining functions read the first three
only: a 3-tuple does too).  Any length for mypyc, as entries (see above).
:func:`~persistri.impl.complex.vertex_changes.group` tells a repeated vertex by two changes sharing their
lists: a change tuple may be boxed twice by the compiled twin (two objects), the lists it holds never are."""


Combine: TypeAlias = Callable[[VertexList, Any], VertexList]
"""A function ``insertWith`` combines a vertex's old list with: ``(old list, argument) -> new list``."""


class Emptied(Exception):
    """Raised inside ``insertWith`` when dropping an entry would leave a vertex's list empty."""


class Missing(Exception):
    """Raised inside ``insertWith`` when the entry to drop or change is not in the vertex's list."""


class Unbatched(Exception):
    """Raised inside ``replace`` when its batched path meets anything unusual: the fold decides instead."""


class Present(Exception):
    """Raised inside ``insertWith`` when ``add`` finds its triangle already in the first vertex's list."""

    def __init__(self, opposite: bool) -> None:
        super().__init__()
        self.opposite = opposite


# The functions ``insertWith`` combines a vertex's old list with.  Module-level, so
# no closure is made per operation: what they need travels in ``insertWith``'s
# value argument (the new entry, or the (second, third) pair to find).


def cat(old: VertexList, new: VertexList) -> VertexList:
    """``old + new``, unchecked: ``add``'s second and third lists, once the first (``cat_first``) has found the
    triangle absent in either orientation. O(len(old) + len(new))."""
    return old + new


def cat_first(old: VertexList, new: VertexList) -> VertexList:
    """``old + new`` unless the triangle of ``new``'s entry (b, c) is in ``old`` in either orientation."""
    b, c, _ = new[0]
    for e in old:
        e0 = e[0]
        if e0 == b:
            if e[1] == c:
                raise Present(False)
        elif e0 == c and e[1] == b:
            raise Present(True)
    return old + new


def drop(old: VertexList, pair: tuple[Any, Any]) -> VertexList:
    """``old`` without its entry ``(b, c, _)`` for ``pair = (b, c)``; Emptied if that was the only one."""
    b, c = pair
    i = 0
    for e in old:
        if e[0] == b and e[1] == c:
            if len(old) == 1:
                raise Emptied
            return old[:i] + old[i + 1 :]
        i += 1
    raise Missing


def put(old: VertexList, new: VertexList) -> VertexList:
    """``old`` with its entry ``(b, c, _)`` replaced by ``new``'s entry ``(b, c, y)``."""
    b, c, _ = new[0]
    i = 0
    for e in old:
        if e[0] == b and e[1] == c:
            return old[:i] + new + old[i + 1 :]
        i += 1
    raise Missing


def drop_add(old: VertexList, change: Change) -> VertexList:
    """``old`` without the entries ``(b, c, _)`` for the pairs of ``change[0]``, plus the entries of
    ``change[1]`` and ``change[2]`` (``replace``).

    The entries of ``change[1]`` are those of triangles whose first vertex is this
    list's: each is looked for in the kept entries, in either orientation (one
    vertex suffices, as for ``add``).  Missing if a pair to drop is not there (or
    is asked twice), Present if a triangle to add is kept, Emptied if nothing
    is left.  :func:`rebuild` does the work (one pass over ``old``).
    """
    if change[0]:
        new = rebuild(old, change)
    else:
        new = drop_add_general(old, change[0], change[1], change[2])
    if not new:
        raise Emptied
    return new


def drop_add_general(
    old: VertexList, drops: list[tuple[Any, Any]], checked: list[Entry], plain: list[Entry]
) -> VertexList:
    """:func:`drop_add` for no checked entry or several (a vertex left with nothing, or a change that is not a
    star's); ``()`` when nothing is left."""
    gone = set(drops)
    kept = [e for e in old if (e[0], e[1]) not in gone]
    if len(kept) + len(drops) != len(old):
        raise Missing
    for b, c, _ in checked:
        for e in kept:
            e0 = e[0]
            if (e0 == b and e[1] == c) or (e0 == c and e[1] == b):
                raise Present(False)
    kept += checked
    kept += plain
    return tuple(kept)


def cat_new(old: VertexList, adds: VertexList) -> VertexList:
    """``old + adds``; Present if a triangle of ``adds`` is in ``old`` in either orientation (``replace``)."""
    for e in old:
        e0, e1 = e[0], e[1]
        for b, c, _ in adds:
            if (e0 == b and e1 == c) or (e0 == c and e1 == b):
                raise Present(False)
    return old + adds


def rebuild(old: VertexList, change: Change) -> VertexList:
    """A vertex's new list in ``replace``: ``cat_new`` of the entries to add when ``change`` drops nothing,
    else :func:`drop_add`'s list, ``()`` when nothing is left (never a list of a valid complex:
    ``adjust_sorted`` reports it as emptied, and the caller removes the vertex).

    The combine of the batched update (``adjust_sorted``) and of the ephemeral
    baseline.  One pass over ``old``: on a surface every vertex that a star's
    replacement keeps has exactly one checked entry (the new triangle that
    starts at it), and that case drops and checks in the same loop (a set of
    the vertices the change names was measured slower: docs/performance.md).
    """
    drops: list[tuple[Any, Any]] = change[0]
    checked: list[Entry] = change[1]
    plain: list[Entry] = change[2]
    n = len(drops)
    if n == 0:
        return cat_new(old, tuple(checked + plain))
    if len(checked) != 1:
        return drop_add_general(old, drops, checked, plain)
    b0, c0, _ = checked[0]
    kept: list[Entry] = []
    append = kept.append
    if n == 1:
        ((b, c),) = drops
        for e in old:
            e0 = e[0]
            e1 = e[1]
            if e0 == b and e1 == c:
                continue
            if (e0 == b0 and e1 == c0) or (e0 == c0 and e1 == b0):
                raise Present(False)
            append(e)
    elif n == 2:  # a vertex that loses two triangles (common where the visible region is several faces)
        (b, c), (b2, c2) = drops
        for e in old:
            e0 = e[0]
            e1 = e[1]
            if (e0 == b and e1 == c) or (e0 == b2 and e1 == c2):
                continue
            if (e0 == b0 and e1 == c0) or (e0 == c0 and e1 == b0):
                raise Present(False)
            append(e)
    else:
        gone = set(drops)
        for e in old:
            e0 = e[0]
            e1 = e[1]
            if (e0, e1) in gone:
                continue
            if (e0 == b0 and e1 == c0) or (e0 == c0 and e1 == b0):
                raise Present(False)
            append(e)
    if len(kept) + n != len(old):
        raise Missing
    append(checked[0])
    kept += plain
    return tuple(kept)


def rebuild_fresh(old: VertexList, change: Change) -> VertexList:
    """:func:`rebuild` without looking for the triangles to add in the kept entries: for a ``replace`` whose every
    added triangle names one *fresh* vertex, in no list of the complex
    (:func:`~persistri.impl.complex.vertex_changes.group`'s third result).

    Such a triangle cannot be in the complex (a triangle's vertices all have lists): no ``Present`` to
    look for; the caller confirms that the fresh vertex is absent, else the fold decides.  Missing and
    the emptied list as :func:`rebuild`.  With one or two pairs to drop (every vertex a star's
    replacement keeps, on the recorded hull and Delaunay runs) the scan stops at the entries dropped
    and the new list is cut from ``old`` by slices: on a list of a valid complex each ``(b, c)`` is
    at most once, so finding each pair once is :func:`rebuild`'s count.  Fewer comparisons than a
    full scan, and no list built entry by entry: −13 % a rebuild on the compiled twin, the same
    interpreted (docs/performance.md, "The price of persistence").
    """
    drops: list[tuple[Any, Any]] = change[0]
    checked: list[Entry] = change[1]
    plain: list[Entry] = change[2]
    n = len(drops)
    tail: VertexList
    if len(checked) == 1 and len(plain) == 1:
        tail = (checked[0], plain[0])
    else:
        tail = tuple(checked + plain)
    if n == 0:
        return old + tail
    k = 0
    if n == 1:
        ((b, c),) = drops
        for e in old:
            if e[0] == b and e[1] == c:
                return old[:k] + old[k + 1 :] + tail
            k += 1
        raise Missing
    if n == 2:
        (b, c), (b2, c2) = drops
        i = -1
        j = -1
        for e in old:
            e0 = e[0]
            if e0 == b and e[1] == c:
                i = k
                if j >= 0:
                    break
            elif e0 == b2 and e[1] == c2:
                j = k
                if i >= 0:
                    break
            k += 1
        else:
            raise Missing
        if j < i:
            i, j = j, i
        return old[:i] + old[i + 1 : j] + old[j + 1 :] + tail
    gone = set(drops)
    kept: list[Entry] = []
    append = kept.append
    for e in old:
        if (e[0], e[1]) not in gone:
            append(e)
    if len(kept) + n != len(old):
        raise Missing
    return tuple(kept) + tail


def visited(old: VertexList, b: Any, c: Any) -> int:
    """How many entries a scan of ``old`` for ``(b, c, _)`` visits."""
    for i, e in enumerate(old):
        if e[0] == b and e[1] == c:
            return i + 1
    return len(old)


# ``replace``'s grouping by vertex and its batched update live in their own module (it imports this one);
# their names stay importable from here, where the structures import them.
from persistri.impl.complex.vertex_changes import (  # noqa: E402
    Changes,
    group,
    group_cone,
    rebuild_cone,
    replace_batched,
)
