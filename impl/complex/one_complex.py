"""The 1-complex, implemented specially (paper §2): oriented edges in per-vertex lists, no map of maps.

The bootstrapping functor would make a 1-complex a map from each vertex to the
0-complex of the vertices opposite it — a map of maps for a set of edges.  As
in the paper, persistri special-cases dimension 1: a single map of the
``ORD_MAP`` backend from each vertex to an immutable tuple of entries

    ``(other vertex, forward, datum)``

An oriented edge ``(u, w)`` with datum x is stored twice: under ``u`` as
``(w, True, x)`` and under ``w`` as ``(u, False, x)``.  The flag keeps the
orientation, which the faces cannot carry (a vertex has one orientation only).

Costs, with the red-black backend (V vertices, δ = the degree of the vertex
looked up): ``data``, ``find`` one map lookup + O(δ); ``add`` two map updates;
``rem``, ``update`` one lookup + two updates; each O(lg V + δ).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any, TypeVar

from persistri.impl.complex.errors import (
    AbsentSimplexError,
    DuplicateSimplexError,
    OppositeOrientationError,
    OrientationError,
    RepresentationError,
)
from persistri.impl.complex.simplex import Simplex
from persistri.impl.complex.structure import ComplexStructure, Family, same_datum
from persistri.impl.complex.vertex import Vertex
from persistri.impl.stats import Stats
from persistri.spec.option import Option

__all__ = ["OneComplex"]

D = TypeVar("D")

Entry = tuple[Vertex, bool, Any]
"""``(other vertex, forward, datum)``: the edge (key, other) if forward, else (other, key)."""


class _Emptied(Exception):
    """Raised inside ``insertWith`` when dropping an entry would leave a vertex's list empty."""


def _cat(old: tuple[Entry, ...], new: tuple[Entry, ...]) -> tuple[Entry, ...]:
    return old + new


class OneComplex(ComplexStructure[D]):
    """``structure OneComplex : SIMPCOMP`` for n = 1 over an ``ORD_MAP`` backend (see the module docstring).

    ``OneComplex(backend)`` is uncounted; ``OneComplex(backend, stats)`` reports
    dictionary operations and key comparisons (tree nodes plus list entries
    visited) to ``stats``.
    """

    kind = "one"

    def __init__(self, backend: Any, stats: Stats | None = None) -> None:
        self.n = 1
        self._init_maps(backend, stats)
        if stats is None:
            self.family = Family(self.kind, 1, backend, None, self)
        else:
            self.family = OneComplex[D](backend).family

    def _visited(self, k: int) -> None:
        st = self._stats
        if st is not None:
            st.key_comparisons += k

    def _data(self, rep: Any, s: Simplex) -> Option[D]:
        u, w = s
        found = self._m.find(rep, u)
        if found is None:
            return None
        lst = found[0]
        for i, (v, fwd, x) in enumerate(lst):
            if fwd and v == w:
                self._visited(i + 1)
                return (x,)
        self._visited(len(lst))
        return None

    def _find(self, rep: Any, f: Simplex) -> list[Simplex]:
        # A vertex has one orientation, so every edge at it has it as a face.
        return self._star(rep, f[0])

    def _star(self, rep: Any, v: Vertex) -> list[Simplex]:
        found = self._m.find(rep, v)
        if found is None:
            return []
        lst = found[0]
        self._visited(len(lst))
        return [(v, w) if fwd else (w, v) for w, fwd, _ in lst]

    def _items(self, rep: Any) -> Iterator[tuple[Simplex, D]]:
        for u, lst in self._m.listItemsi(rep):
            for w, fwd, x in lst:
                if fwd:
                    yield (u, w), x

    def _add(self, rep: Any, s: Simplex, x: D) -> Any:
        u, w = s
        visited = self._visited

        def check_cat(old: tuple[Entry, ...], new: tuple[Entry, ...]) -> tuple[Entry, ...]:
            for v, fwd, _ in old:
                if v == w:
                    visited(len(old))
                    if fwd:
                        raise DuplicateSimplexError(f"add: edge {s!r} is already present")
                    raise OppositeOrientationError(f"add: edge {s!r} is present with the opposite orientation {(w, u)!r}")
            visited(len(old))
            return old + new

        m = self._m
        rep = m.insertWith(check_cat, rep, u, ((w, True, x),))
        return m.insertWith(_cat, rep, w, ((u, False, x),))

    def _locate(self, rep: Any, s: Simplex, what: str) -> tuple[tuple[Entry, ...], int]:
        """The list of ``s[0]`` and the index of ``s``'s forward entry in it; AbsentSimplexError if absent."""
        u, w = s
        found = self._m.find(rep, u)
        if found is not None:
            lst = found[0]
            for i, (v, fwd, _) in enumerate(lst):
                if fwd and v == w:
                    self._visited(i + 1)
                    return lst, i
            self._visited(len(lst))
        raise AbsentSimplexError(f"{what}: edge {s!r} is not in the complex")

    def _replace_at(self, rep: Any, key: Vertex, other: Vertex, fwd: bool, y: Any, drop: bool) -> Any:
        """Replace (or drop) the entry ``(other, fwd, _)`` in ``key``'s list; remove ``key`` if the list empties."""
        visited = self._visited

        def change(old: tuple[Entry, ...], _: tuple[Entry, ...]) -> tuple[Entry, ...]:
            for i, (v, f, _x) in enumerate(old):
                if f is fwd and v == other:
                    visited(i + 1)
                    if drop:
                        if len(old) == 1:
                            raise _Emptied
                        return old[:i] + old[i + 1 :]
                    return old[:i] + ((v, f, y),) + old[i + 1 :]
            raise RepresentationError(f"1-complex: entry {(other, fwd)!r} missing from the list of {key!r}")

        m = self._m
        try:
            return m.insertWith(change, rep, key, ())
        except _Emptied:
            return m.remove(rep, key)[0]

    def _rem(self, rep: Any, s: Simplex) -> Any:
        u, w = s
        lst, i = self._locate(rep, s, "rem")
        m = self._m
        rest = lst[:i] + lst[i + 1 :]
        rep = m.insert(rep, u, rest) if rest else m.remove(rep, u)[0]
        return self._replace_at(rep, w, u, False, None, True)

    def _update(self, rep: Any, s: Simplex, f: Callable[[D], D]) -> Any:
        u, w = s
        lst, i = self._locate(rep, s, "update")
        y = f(lst[i][2])
        rep = self._m.insert(rep, u, lst[:i] + ((w, True, y),) + lst[i + 1 :])
        return self._replace_at(rep, w, u, False, y, False)

    def _check_rep(self, rep: Any) -> None:
        check = getattr(self._raw, "_check", None)
        if check is not None:
            check(rep)
        table: dict[Vertex, tuple[Entry, ...]] = dict(self._raw.listItemsi(rep))
        for u, lst in table.items():
            if not lst:
                raise RepresentationError(f"1-complex: vertex {u!r} is mapped to an empty list (it is in no edge)")
            seen: dict[Vertex, bool] = {}
            for w, fwd, x in lst:
                if w == u:
                    raise RepresentationError(f"1-complex: the list of {u!r} holds a loop to itself")
                if w in seen:
                    if seen[w] == fwd:
                        raise OrientationError(f"1-complex: edge {(u, w) if fwd else (w, u)!r} is held twice")
                    raise OrientationError(f"1-complex: edge {{{u!r}, {w!r}}} is held in both orientations")
                seen[w] = fwd
                mirror = [e for e in table.get(w, ()) if e[0] == u and e[1] is not fwd]
                edge = (u, w) if fwd else (w, u)
                if len(mirror) != 1:
                    raise RepresentationError(
                        f"1-complex: edge {edge!r} is in the list of {u!r} but {len(mirror)} times in the list of {w!r}"
                    )
                if not same_datum(mirror[0][2], x):
                    raise RepresentationError(f"1-complex: edge {edge!r} carries different data under {u!r} and {w!r}")

