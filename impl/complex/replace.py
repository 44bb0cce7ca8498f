"""The 2-complex's ``replace``: one star for another in one map operation per vertex touched (paper §3, §5).

Every insertion of the algorithms is a ``replace``: the bulldozer swaps the
faces a new point sees for its tent (§3), the Delaunay and terrain insertions
a cavity for the new vertex's star (§5).  Its meaning is the fold — ``rem``
each removed triangle, then ``add`` each added one — and
:meth:`~persistri.impl.complex.two_complex.TwoComplex.replace` keeps that
meaning while doing less: :func:`~persistri.impl.complex.vertex_changes.group`
gathers the changes by vertex, and each vertex's list is rebuilt once.  A
bulldozer insertion that replaces 4 faces by 6 touches 7 vertices: 7 map
updates where the fold makes 30.

Two ways to make those updates, both here or in
:mod:`~persistri.impl.complex.vertex_changes`:

* :func:`replace_per_vertex` — one ``insertWith`` per vertex (``remove`` for a
  vertex left in no triangle), through any ``ORD_MAP`` backend.  Counted
  structures use it, so the counts are those of the paper's operations;
* :func:`~persistri.impl.complex.vertex_changes.replace_batched` — the
  red-black map's ``adjust_sorted`` rebuilds every present
  vertex's list in one descent, copying the tree nodes their search paths
  share once.

A cone from a fresh vertex over a cycle given in order (the scattered Delaunay's
fan, §5) is grouped from the cycle itself: :func:`replace_cone`.

Each raises a signal (``Missing``, ``Present``, ``Unbatched``) when the
change is not valid, and the structure then runs the fold, which raises the
signature's precise error with the complex unchanged.  O(V_t·lg V + Σ δ) with
V_t the vertices touched and δ their list lengths.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.vertex_lists import Combine, Emptied, Missing, Present, Unbatched
from persistri.impl.complex.vertex_changes import Changes, group, group_cone, rebuild_cone, replace_batched

__all__ = ["arguments", "replace_per_vertex", "replace_trusted", "replace_cone", "same_replace"]

_new_complex = tuple.__new__


def _sequence(xs: Any, what: str) -> list[Any]:
    """``xs`` as a list (``replace`` reads its arguments twice on its error path); TypeError if not iterable."""
    try:
        return list(xs)
    except TypeError:
        raise TypeError(f"replace: {what} must be an iterable of triangles, got {type(xs).__name__}") from None


def arguments(removed: Any, added: Any) -> tuple[Sequence[Any], Sequence[Any]]:
    """``replace``'s two arguments as sequences (lists and tuples as they are; read twice on the error path).  O(1) or O(k)."""
    if type(removed) is not list and type(removed) is not tuple:
        removed = _sequence(removed, "removed")
    if type(added) is not list and type(added) is not tuple:
        added = _sequence(added, "added")
    return removed, added


def replace_per_vertex(m: Any, rep: Any, changes: Changes, drop_add: Combine, cat_new: Combine) -> Any:
    """The map ``rep`` with ``changes`` made one vertex at a time through the ``ORD_MAP`` ``m``.

    A vertex with nothing to drop gets its new entries by one ``insertWith``
    of ``cat_new``; any other by one ``insertWith`` of ``drop_add``, or
    ``remove`` when that empties its list (``Emptied``).  Raises what the
    combining functions raise (``Missing``, ``Present``) and ``Unbatched`` for
    a triangle to remove at a vertex with no list (``insertWith`` made one:
    ``numItems`` grew).  One map operation per vertex, O(V_t·lg V + Σ δ).
    """
    n = m.numItems(rep)  # kept up to date: one numItems per vertex with drops, not two
    for v, change in changes.items():
        if not change[0]:
            rep = m.insertWith(cat_new, rep, v, tuple(change[1] + change[2]))
            n = m.numItems(rep)  # v may be new
            continue
        try:
            out = m.insertWith(drop_add, rep, v, change)
        except Emptied:  # v is in no triangle any more
            rep = m.remove(rep, v)[0]
            n -= 1
            continue
        if m.numItems(out) != n:  # v had no list: a triangle to remove is absent
            raise Unbatched
        rep = out
    return rep


def replace_trusted(S: Any, c: Any, removed: list[Any], added: list[Any]) -> Any:
    """``S.replace(c, removed, added)`` for a caller that passes two lists: the same result, compiled on the twin.

    The public :meth:`~persistri.impl.complex.two_complex.TwoComplex.replace`
    is interpreted on both builds (a subclass may override it); this entry is
    the same body in a compiled module, for the algorithms' one call per step
    (the scattered Delaunay's insertion, §5).  It trusts only the arguments'
    types (lists, not any iterable); everything else is checked as the public
    ``replace`` checks it (:func:`~persistri.impl.complex.vertex_changes.group`
    validates the triangles), and on anything unusual — a structure whose
    ``replace`` is overridden or counted (no ``_batched``), a complex of
    another family, an invalid change — it calls ``S.replace`` itself, which
    raises the precise error.  So the result (and the persistence of ``c``) is
    that of ``S.replace`` in every case.  O(V_t·lg V + Σ δ) as ``replace``.
    """
    batched: tuple[Any, Any, Any, Any, Any] | None = getattr(S, "_batched", None)
    if batched is None:
        return S.replace(c, removed, added)
    family, adjust, insert, remove, adjust_insert = batched
    try:
        fam, rep, lin = c
        if fam is not family:
            raise Unbatched
        changes, out_lin, fresh = group(removed, added, lin)
        rep = replace_batched(rep, changes, adjust, insert, remove, fresh, adjust_insert)
    except (Unbatched, Missing, Present, TypeError, ValueError, AttributeError):
        return S.replace(c, removed, added)
    return _new_complex(Complex, (family, rep, out_lin))


def replace_cone(S: Any, c: Any, removed: list[Any], added: list[Any]) -> Any:
    """:func:`replace_trusted` for a star replaced by a cone from a fresh apex, grouped from the cone's cycle.

    ``added`` lists the cone's triangles ``(ci, c(i+1), x)`` around the cycle in order (the scattered
    Delaunay's fan and its ghosts, §5): :func:`~persistri.impl.complex.vertex_changes.group_cone` reads each
    cycle vertex's two new entries off its two triangles instead of grouping them through a dictionary,
    and :func:`~persistri.impl.complex.vertex_changes.rebuild_cone` rebuilds its list with the entries already
    in their final tuple; the apex is inserted in the tree's one descent (``adjust_insert``), as
    :func:`~persistri.impl.complex.vertex_changes.replace_batched` does for a fresh vertex.  The same
    complex as ``S.replace(c, removed, added)`` — every list with the same entries in the same order —
    in every case: anything that is not such a cone over a backend with ``adjust_insert`` goes to
    :func:`replace_trusted`, and anything invalid to ``S.replace``, which raises the precise error.
    O(V_t·lg V + Σ δ) as ``replace``.
    """
    batched: tuple[Any, Any, Any, Any, Any] | None = getattr(S, "_batched", None)
    if batched is None:
        return S.replace(c, removed, added)
    family, _, insert, remove, adjust_insert = batched
    try:
        fam, rep, lin = c
        if fam is not family or adjust_insert is None:
            raise Unbatched
        changes = group_cone(removed, added, lin)
    except (Unbatched, TypeError, ValueError, AttributeError):
        return replace_trusted(S, c, removed, added)
    try:
        keys = sorted(changes)
        vals = [changes[k] for k in keys]
        apex = added[0][0][2]
        j = 0
        while keys[j] is not apex:
            j += 1
        rep, absent, emptied, inserted = adjust_insert(rebuild_cone, rep, keys, vals, j, vals[j][1])
        fresh: Any = None if inserted else apex  # the apex, until confirmed absent
        for i in absent:  # a vertex with no list: inserted with its new entries if it drops nothing
            change = vals[i]
            if change[0]:
                raise Unbatched
            k = keys[i]
            if k is fresh:
                fresh = None
            rep = insert(rep, k, change[1])
        if fresh is not None:  # the apex has a list: a triangle to add may be in the complex
            raise Unbatched
        for i in emptied:  # never for a cone (each cycle vertex keeps its two new entries): as replace_batched
            rep = remove(rep, keys[i])[0]
    except (Unbatched, Missing, Present, TypeError, ValueError, AttributeError):
        return S.replace(c, removed, added)
    return _new_complex(Complex, (family, rep, lin))


def same_replace(S: Any, mine: Any, theirs: Any, removed: list[Any], added: list[Any]) -> bool:
    """Whether two results of one ``replace`` agree where it changed them: each touched vertex's list
    (the same triangles, the same datum objects, in the same order) and the number of vertices.

    For ``check=True`` callers of :func:`replace_trusted`, comparing it with the
    public ``replace``.  O(V_t·lg V + Σ δ).
    """
    m = S._m
    if m.numItems(mine[1]) != m.numItems(theirs[1]) or mine[2] is not theirs[2]:
        return False
    touched = {v for t in removed for v in t} | {v for t, _ in added for v in t}
    for v in touched:
        x = m.find(mine[1], v)
        y = m.find(theirs[1], v)
        if (x is None) != (y is None):
            return False
        if x is not None and y is not None:
            ex, ey = x[0], y[0]
            if len(ex) != len(ey):
                return False
            for e, f in zip(ex, ey):
                if e[0] is not f[0] or e[1] is not f[1] or e[2] is not f[2]:
                    return False
    return True
