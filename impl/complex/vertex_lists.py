"""The per-vertex lists of the specialised 2-complex (paper §4) and the functions that rebuild them.

:class:`~persistri.impl.complex.two_complex.TwoComplex` maps each vertex a to
one flat, immutable tuple holding a's entries — one per triangle at a, the
paper's association list — laid end to end:

    ``(b_0, c_0, x_0,  b_1, c_1, x_1,  …)``

entry i being the triangle ``(a, b_i, c_i)`` with datum ``x_i``; a list with one
entry is the 3-tuple ``(b, c, x)``.  Flat, because a tuple per entry (64 bytes)
held three references (24 bytes): even where successive versions shared the
entry objects, the flat lists keep less (docs/structures/complex.md).  Scans
step by three and compare only the vertices, never a datum.  (A layout in three
blocks, ``b…, c…, x…``, which lets ``tuple.index`` scan the second vertices in
C, was measured too: its rebuilds, cut and spliced in three places, cost
CPython about 60% more instructions than these, which are one cut and one
concatenation.)

This module holds what works on those lists: the functions ``insertWith``
combines a vertex's old list with (``add``, ``rem``, ``update``,
``replace``), the grouping of a ``replace`` by vertex, and the edge lookup of
one version that the walks call (:func:`neighbours_in`).  They are a module of
their own because the 2-complex spends its time here: the compiled twin
(``make compiled``, docs/performance.md) compiles it with mypyc, and
:mod:`~persistri.impl.complex.two_complex`, which validates the public
arguments and raises the signature's errors, stays interpreted.

Lists are typed as tuples of *any* length (``tuple[Any, ...]``): mypyc stores a
fixed-length tuple type unboxed and boxes it again on the way out, so a list
kept by a rebuilt map would come back as a new, equal tuple, no longer shared
with the older versions that hold it.  Typed this way each stays one object
(``tests/test_complex_replace.py`` checks the untouched lists and the map's
subtrees by identity).  Vertices are ``Any`` here: the structure has
validated them.

The exceptions are signals between these functions and the structure, never
seen by a caller of the 2-complex: the structure turns them into the
signature's errors (or, in ``replace``, falls back to the fold that raises
them).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, TypeAlias

__all__ = [
    "Entry",
    "VertexList",
    "Change",
    "Changes",
    "Emptied",
    "Missing",
    "Unbatched",
    "Present",
    "size",
    "entries",
    "from_entries",
    "from_flat",
    "index",
    "cat",
    "cat_first",
    "drop",
    "put",
    "drop_add",
    "cat_new",
    "rebuild",
    "visited",
    "group",
    "replace_batched",
    "neighbours_in",
]

Entry: TypeAlias = tuple[Any, ...]
"""``(second vertex, third vertex, datum)``: one entry, as :func:`entries` returns it (a list of one entry is
this very tuple)."""

VertexList: TypeAlias = tuple[Any, ...]
"""A vertex's list: the blocks of second vertices, third vertices and data (module docstring)."""

Change: TypeAlias = tuple[list[Any], list[Any], list[Any]]
"""What ``replace`` does to one vertex's list, each part flat: the pairs ``b, c`` of the entries to drop, the
triples ``b, c, x`` to add of the triangles that start at the vertex (checked against the list), and the other
triples ``b, c, x`` to add."""


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


# -- reading a list ---------------------------------------------------------------------


def size(lst: VertexList) -> int:
    """The number of entries of ``lst``.  O(1)."""
    return len(lst) // 3


def entries(lst: VertexList) -> list[Entry]:
    """The entries ``(b, c, x)`` of ``lst``, in order.  O(k)."""
    return list(zip(lst[0::3], lst[1::3], lst[2::3]))


def from_entries(es: Sequence[Entry]) -> VertexList:
    """The list of the entries ``es`` ``(b, c, x)``, in order (the inverse of :func:`entries`).  O(k)."""
    return tuple([y for e in es for y in e])


def from_flat(flat: list[Any]) -> VertexList:
    """The list of the triples ``b, c, x`` laid end to end in ``flat`` (the list itself, as a tuple).  O(k)."""
    return tuple(flat)


def index(lst: VertexList, b: Any, c: Any) -> int:
    """The index i of entry ``(b, c, _)`` in ``lst`` (its datum is ``lst[3i + 2]``), or -1.  O(k)."""
    for j in range(0, len(lst), 3):
        if lst[j] == b and lst[j + 1] == c:
            return j // 3
    return -1


def visited(old: VertexList, b: Any, c: Any) -> int:
    """How many entries a scan of ``old`` for ``(b, c, _)`` visits (the paper's count: up to the hit, or all)."""
    i = index(old, b, c)
    return len(old) // 3 if i < 0 else i + 1


def _holds(lst: VertexList, b: Any, c: Any) -> bool:
    """Whether ``lst`` holds the triangle ``(b, c)`` or ``(c, b)``."""
    for j in range(0, len(lst), 3):
        e0 = lst[j]
        if e0 == b:
            if lst[j + 1] == c:
                return True
        elif e0 == c and lst[j + 1] == b:
            return True
    return False


# The functions ``insertWith`` combines a vertex's old list with.  Module-level, so
# no closure is made per operation: what they need travels in ``insertWith``'s
# value argument (the new list of one entry, or the (second, third) pair to find).


def cat(old: VertexList, new: VertexList) -> VertexList:
    """``old`` followed by the entries of ``new`` (both lists)."""
    return old + new


def cat_first(old: VertexList, new: VertexList) -> VertexList:
    """``old`` plus ``new``'s one entry ``(b, c, x)`` unless its triangle is in ``old`` in either orientation."""
    b = new[0]
    c = new[1]
    for j in range(0, len(old), 3):
        e0 = old[j]
        if e0 == b:
            if old[j + 1] == c:
                raise Present(False)
        elif e0 == c and old[j + 1] == b:
            raise Present(True)
    return old + new


def drop(old: VertexList, pair: tuple[Any, Any]) -> VertexList:
    """``old`` without its entry ``(b, c, _)`` for ``pair = (b, c)``; Emptied if that was the only one."""
    i = index(old, pair[0], pair[1])
    if i < 0:
        raise Missing
    if len(old) == 3:
        raise Emptied
    j = 3 * i
    return old[:j] + old[j + 3 :]


def put(old: VertexList, new: VertexList) -> VertexList:
    """``old`` with its entry ``(b, c, _)`` replaced by ``new``'s one entry ``(b, c, y)``."""
    i = index(old, new[0], new[1])
    if i < 0:
        raise Missing
    j = 3 * i
    return old[:j] + new + old[j + 3 :]


def drop_add(old: VertexList, change: Change) -> VertexList:
    """``old`` without the entries ``(b, c, _)`` for the pairs of ``change[0]``, plus the entries of
    ``change[1]`` and ``change[2]`` (``replace``).

    The entries of ``change[1]`` are those of triangles whose first vertex is this
    list's: each is looked for in the kept entries, in either orientation (one
    vertex suffices, as for ``add``).  Missing if a pair to drop is not there (or
    is asked twice), Present if a triangle to add is kept, Emptied if nothing
    is left.  One pass over ``old``: on a surface every vertex the change keeps
    has exactly one checked entry (the new triangle that starts at it), and that
    case drops and checks in the same loop, then cuts the dropped entries out of
    a copy of ``old`` and appends the new ones.
    """
    drops, checked, plain = change
    if len(checked) != 3:
        return _drop_add_general(old, drops, checked, plain)
    b0 = checked[0]
    c0 = checked[1]
    nd = len(drops)
    bs = old[0::3]
    cs = old[1::3]
    if nd == 2:
        b = drops[0]
        c = drops[1]
        try:
            i = bs.index(b)
            while cs[i] != c:
                i = bs.index(b, i + 1)
        except ValueError:
            raise Missing from None
        if b0 in bs or c0 in bs:  # else the triangle cannot be kept (a C-level test)
            j = 0
            for e0, e1 in zip(bs, cs):
                if j != i and ((e0 == b0 and e1 == c0) or (e0 == c0 and e1 == b0)):
                    raise Present(False)
                j += 1
        out = list(old)
        del out[3 * i : 3 * i + 3]
    else:
        gone: set[tuple[Any, Any]] = set()
        for j in range(0, nd, 2):
            gone.add((drops[j], drops[j + 1]))
        ats: list[int] = []
        j = 0
        for e0, e1 in zip(bs, cs):
            if (e0, e1) in gone:
                ats.append(j)
            elif (e0 == b0 and e1 == c0) or (e0 == c0 and e1 == b0):
                raise Present(False)
            j += 3
        if 2 * len(ats) != nd:  # a pair absent, or asked twice
            raise Missing
        out = list(old)
        for at in reversed(ats):
            del out[at : at + 3]
    out += checked
    out += plain
    return tuple(out)


def _drop_add_general(old: VertexList, drops: list[Any], checked: list[Any], plain: list[Any]) -> VertexList:
    """:func:`drop_add` for no checked entry or several (a vertex left with nothing, or a change that is not a
    star's)."""
    gone: set[tuple[Any, Any]] = set()
    for j in range(0, len(drops), 2):
        gone.add((drops[j], drops[j + 1]))
    out: list[Any] = []
    for j in range(0, len(old), 3):
        if (old[j], old[j + 1]) not in gone:
            out += old[j : j + 3]
    if len(gone) != len(drops) // 2 or len(out) + 3 * len(gone) != len(old):  # asked twice, or absent
        raise Missing
    kept = tuple(out)
    for j in range(0, len(checked), 3):
        if _holds(kept, checked[j], checked[j + 1]):
            raise Present(False)
    out += checked
    out += plain
    if not out:
        raise Emptied
    return tuple(out)


def cat_new(old: VertexList, adds: VertexList) -> VertexList:
    """``old`` followed by the entries of the list ``adds``; Present if a triangle of ``adds`` is in ``old``
    in either orientation (``replace``)."""
    for j in range(0, len(adds), 3):
        if _holds(old, adds[j], adds[j + 1]):
            raise Present(False)
    return old + adds


def rebuild(old: VertexList, arg: tuple[Change, Any, list[Any]]) -> VertexList:
    """``replace``'s combine for a batched update (``adjust_many``): ``arg = (change, v, emptied)``.

    The vertex's new list as ``cat_new`` or ``drop_add`` make it; when nothing is
    left, ``()`` — never a list of a valid complex — with ``v`` appended to
    ``emptied`` so that the caller removes it.
    """
    change, v, emptied = arg
    if not change[0]:
        return cat_new(old, tuple(change[1] + change[2]))
    try:
        return drop_add(old, change)
    except Emptied:
        emptied.append(v)
        return ()


Changes: TypeAlias = dict[Any, Change]
"""What ``replace`` does to each vertex's list (:data:`Change`), by vertex."""


def group(removed: Sequence[Any], added: Sequence[Any], lin: Any) -> tuple[Changes, Any]:
    """The changes of ``replace`` grouped by vertex, and the lineage of the result.

    Validates each triangle inline as ``add`` and ``rem`` do (a tuple of three
    distinct vertices of the complex's lineage) and refuses a triangle added
    twice or in both orientations; raises Unbatched (or the TypeError /
    ValueError / AttributeError of a malformed argument) on anything unusual,
    and the caller lets the fold raise the precise error.  O(|removed| + |added|).
    (The loop variables' types let the compiled twin unpack the triangles
    natively; it raises TypeError for any other element, which the caller
    treats alike.)
    """
    changes: Changes = {}
    get = changes.get
    s: tuple[Any, Any, Any]
    sx: tuple[tuple[Any, Any, Any], Any]
    for s in removed:
        a, b, cc = s
        la = a.lineage
        if not (type(s) is tuple and la is lin and b.lineage is la and cc.lineage is la and a != b and b != cc and a != cc):
            raise Unbatched
        ch = get(a)
        if ch is None:
            changes[a] = ([b, cc], [], [])
        else:
            ch[0].extend((b, cc))
        ch = get(b)
        if ch is None:
            changes[b] = ([cc, a], [], [])
        else:
            ch[0].extend((cc, a))
        ch = get(cc)
        if ch is None:
            changes[cc] = ([a, b], [], [])
        else:
            ch[0].extend((a, b))
    out_lin = lin
    for sx in added:
        s, x = sx
        a, b, cc = s
        la = a.lineage
        if out_lin is None:
            out_lin = la
        if not (type(s) is tuple and la is out_lin and b.lineage is la and cc.lineage is la and a != b and b != cc and a != cc):
            raise Unbatched
        ch = get(a)
        if ch is None:
            changes[a] = ([], [b, cc, x], [])
        else:
            # Added twice, or in both orientations: every triangle of the batch is already
            # under each of its vertices, so one test at the first vertex finds it.
            for part in (ch[1], ch[2]):
                for j in range(0, len(part), 3):
                    e0 = part[j]
                    e1 = part[j + 1]
                    if (e0 == b and e1 == cc) or (e0 == cc and e1 == b):
                        raise Unbatched
            ch[1].extend((b, cc, x))
        ch = get(b)
        if ch is None:
            changes[b] = ([], [], [cc, a, x])
        else:
            ch[2].extend((cc, a, x))
        ch = get(cc)
        if ch is None:
            changes[cc] = ([], [], [a, b, x])
        else:
            ch[2].extend((a, b, x))
    return changes, out_lin


def replace_batched(
    rep: Any,
    changes: Changes,
    adjust_many: Callable[..., tuple[Any, list[Any]]],
    insert: Callable[[Any, Any, Any], Any],
    remove: Callable[[Any, Any], tuple[Any, Any]],
) -> Any:
    """``replace``'s map changes through a backend's ``adjust_many`` (its ``insert`` and ``remove`` besides).

    Every present vertex's list rebuilt in one descent (the red-black tree
    copies the nodes its search paths share once), then the new vertices
    inserted and the emptied ones removed.  Raises what the per-vertex updates
    raise (Missing, Present; Unbatched for a triangle to remove at a vertex
    with no list).
    """
    emptied: list[Any] = []
    items = [(v, (changes[v], v, emptied)) for v in sorted(changes)]
    rep, absent = adjust_many(rebuild, rep, items)
    for item in absent:
        change = item[1][0]
        if change[0]:  # the vertex had no list: a triangle to remove is absent
            raise Unbatched
        rep = insert(rep, item[0], tuple(change[1] + change[2]))
    for v in emptied:  # v is in no triangle any more
        rep = remove(rep, v)[0]
    return rep


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
        try:
            j = 3 * lst[0::3].index(w)  # the second vertices: a C-level scan that never meets a datum
        except ValueError:
            return None
        return (u, w, lst[j + 1]), lst[j + 2]

    return neighbour_in_c
