"""The per-vertex lists of the specialised 2-complex (paper §4) and the functions that rebuild them.

:class:`~persistri.impl.complex.two_complex.TwoComplex` maps each vertex a to
one flat, immutable tuple holding a's entries — one per triangle at a, the
paper's association list — in three blocks of equal length k:

    ``(b_0, …, b_{k-1},  c_0, …, c_{k-1},  x_0, …, x_{k-1})``

entry i being the triangle ``(a, b_i, c_i)`` with datum ``x_i``.  A list with one
entry is the 3-tuple ``(b, c, x)``.  Flat, because a tuple per entry (64 bytes)
cost more memory than the three pointers it holds (24 bytes) even where the
entry was shared by successive versions (docs/structures/complex.md); blocked,
so that the entry with second vertex w is found by ``lst.index(w, 0, k)``, one
C-level scan, and no datum is ever compared with a vertex.

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
    k = len(lst) // 3
    return list(zip(lst[:k], lst[k : 2 * k], lst[2 * k :]))


def from_entries(es: Sequence[Entry]) -> VertexList:
    """The list of the entries ``es`` ``(b, c, x)``, in order (the inverse of :func:`entries`).  O(k)."""
    return tuple([e[0] for e in es] + [e[1] for e in es] + [e[2] for e in es])


def from_flat(flat: list[Any]) -> VertexList:
    """The list of the triples ``b, c, x`` laid end to end in ``flat``, in order.  O(k)."""
    return tuple(flat[0::3] + flat[1::3] + flat[2::3])


def index(lst: VertexList, b: Any, c: Any) -> int:
    """The position of entry ``(b, c, _)`` in ``lst`` (its datum is ``lst[2k + i]``), or -1.  O(k), in C."""
    k = len(lst) // 3
    i = 0
    while True:
        try:
            i = lst.index(b, i, k)
        except ValueError:
            return -1
        if lst[k + i] == c:
            return i
        i += 1


def visited(old: VertexList, b: Any, c: Any) -> int:
    """How many entries a scan of ``old`` for ``(b, c, _)`` visits (the paper's count: up to the hit, or all)."""
    i = index(old, b, c)
    return len(old) // 3 if i < 0 else i + 1


def _holds(lst: list[Any] | VertexList, k: int, b: Any, c: Any) -> bool:
    """Whether the first k entries of the blocked ``lst`` (blocks of length k) hold the triangle ``(b, c)``
    or ``(c, b)``."""
    for i in range(k):
        e0 = lst[i]
        if e0 == b:
            if lst[k + i] == c:
                return True
        elif e0 == c and lst[k + i] == b:
            return True
    return False


# The functions ``insertWith`` combines a vertex's old list with.  Module-level, so
# no closure is made per operation: what they need travels in ``insertWith``'s
# value argument (the new list of one entry, or the (second, third) pair to find).


def _merged(out: list[Any], m: int, adds: list[Any] | VertexList) -> VertexList:
    """The list of the m entries blocked in ``out`` (length 3m) followed by the triples ``adds`` (flat)."""
    out += adds[2::3]
    out[2 * m : 2 * m] = adds[1::3]
    out[m:m] = adds[0::3]
    return tuple(out)


def _spliced(out: list[Any], m: int, adds: VertexList) -> VertexList:
    """The list of the m entries blocked in ``out`` (length 3m) followed by the entries of the list ``adds``."""
    j = len(adds) // 3
    out += adds[2 * j :]
    out[2 * m : 2 * m] = adds[j : 2 * j]
    out[m:m] = adds[:j]
    return tuple(out)


def cat(old: VertexList, new: VertexList) -> VertexList:
    """``old`` followed by the entries of ``new`` (both lists)."""
    return _spliced(list(old), len(old) // 3, new)


def cat_first(old: VertexList, new: VertexList) -> VertexList:
    """``old`` plus ``new``'s one entry ``(b, c, x)`` unless its triangle is in ``old`` in either orientation."""
    b, c, _ = new
    k = len(old) // 3
    for i in range(k):
        e0 = old[i]
        if e0 == b:
            if old[k + i] == c:
                raise Present(False)
        elif e0 == c and old[k + i] == b:
            raise Present(True)
    return _spliced(list(old), k, new)


def drop(old: VertexList, pair: tuple[Any, Any]) -> VertexList:
    """``old`` without its entry ``(b, c, _)`` for ``pair = (b, c)``; Emptied if that was the only one."""
    i = index(old, pair[0], pair[1])
    if i < 0:
        raise Missing
    k = len(old) // 3
    if k == 1:
        raise Emptied
    out = list(old)
    del out[2 * k + i]
    del out[k + i]
    del out[i]
    return tuple(out)


def put(old: VertexList, new: VertexList) -> VertexList:
    """``old`` with its entry ``(b, c, _)`` replaced by ``new``'s one entry ``(b, c, y)``."""
    b, c, y = new
    i = index(old, b, c)
    if i < 0:
        raise Missing
    k = len(old) // 3
    out = list(old)
    out[i] = b
    out[k + i] = c
    out[2 * k + i] = y
    return tuple(out)


def drop_add(old: VertexList, change: Change) -> VertexList:
    """``old`` without the entries ``(b, c, _)`` for the pairs of ``change[0]``, plus the entries of
    ``change[1]`` and ``change[2]`` (``replace``).

    The entries of ``change[1]`` are those of triangles whose first vertex is this
    list's: each is looked for in the kept entries, in either orientation (one
    vertex suffices, as for ``add``).  Missing if a pair to drop is not there (or
    is asked twice), Present if a triangle to add is kept, Emptied if nothing
    is left.  Each entry to drop is found by a C-level scan of the first block,
    and the new list is cut and spliced by list operations (no tuple per entry):
    O(k) with few interpreted steps.
    """
    drops, checked, plain = change
    k = len(old) // 3
    out = list(old)
    nd = len(drops)
    if nd == 2:  # one entry dropped (most vertices of a star replacement)
        i = index(old, drops[0], drops[1])
        if i < 0:
            raise Missing
        del out[2 * k + i]
        del out[k + i]
        del out[i]
    elif nd:
        gone: list[int] = []
        for j in range(0, nd, 2):
            i = index(old, drops[j], drops[j + 1])
            if i < 0 or i in gone:  # absent, or asked twice
                raise Missing
            gone.append(i)
        gone.sort(reverse=True)
        for base in (2 * k, k, 0):  # the data block first: cutting it moves nothing before it
            for i in gone:
                del out[base + i]
    m = k - nd // 2
    for j in range(0, len(checked), 3):
        if _holds(out, m, checked[j], checked[j + 1]):
            raise Present(False)
    if not checked and not plain:
        if not m:
            raise Emptied
        return tuple(out)
    return _merged(out, m, checked + plain)


def cat_new(old: VertexList, adds: VertexList) -> VertexList:
    """``old`` followed by the entries of the list ``adds``; Present if a triangle of ``adds`` is in ``old``
    in either orientation (``replace``)."""
    k = len(old) // 3
    j = len(adds) // 3
    for i in range(j):
        if _holds(old, k, adds[i], adds[j + i]):
            raise Present(False)
    return _spliced(list(old), k, adds)


def rebuild(old: VertexList, arg: tuple[Change, Any, list[Any]]) -> VertexList:
    """``replace``'s combine for a batched update (``adjust_many``): ``arg = (change, v, emptied)``.

    The vertex's new list as ``cat_new`` or ``drop_add`` make it; when nothing is
    left, ``()`` — never a list of a valid complex — with ``v`` appended to
    ``emptied`` so that the caller removes it.
    """
    change, v, emptied = arg
    if not change[0]:
        return cat_new(old, from_flat(change[1] + change[2]))
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
        rep = insert(rep, item[0], from_flat(change[1] + change[2]))
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
    first, O(δ) after (a C-level scan).
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
        k = len(lst) // 3
        try:
            i = lst.index(w, 0, k)
        except ValueError:
            return None
        return (u, w, lst[k + i]), lst[2 * k + i]

    return neighbour_in_c
