"""The bootstrapping functor: an n-complex from an (n−1)-complex (paper §2).

An n-complex is represented by a map of the ``ORD_MAP`` backend from each
vertex v to the (n−1)-complex of the faces *opposite* v: for each n-simplex t
containing v, the face ``faces(t)[i]`` where ``t[i] = v``.  The induced
orientation makes ``join(v, faces(t)[i])`` an order of t's orientation, so the
(n−1)-complex under v holds t's orientation faithfully; the other orientation
of t would be the reverse face.  For t = (a, b, c, d):

    under a: (b, c, d)   under b: (a, d, c)   under c: (a, b, d)   under d: (a, c, b)

``Bootstrap(sub, backend)`` is the functor applied to the structure ``sub`` of
(n−1)-complexes (the paper's ``functor`` taking a ``SIMPCOMP`` structure and a
map structure).  Starting from the special :class:`~persistri.impl.complex.one_complex.OneComplex`
it gives 2-, 3-, 4-complexes…; starting from the specialised
:class:`~persistri.impl.complex.two_complex.TwoComplex` it gives faster 3- and
4-complexes.  The inner complexes are bare ``rep`` maps driven through
``sub``'s internal (unvalidated) operations: arguments are checked once, at the
top.

Work per operation on an n-complex (each map operation O(lg V) with the
red-black backend, plus the inner complex's own work):

* ``data``: one lookup, then ``data`` in the inner complex of the apex;
* ``find``: one lookup (the first vertex of the face), then ``find`` in its
  inner complex;
* ``add``, ``rem``, ``update``: for each of the n+1 vertices, one lookup, the
  inner operation, and one insert (or remove, when an inner complex empties).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any, TypeVar

from persistri.impl.complex.errors import (
    AbsentSimplexError,
    DuplicateSimplexError,
    OppositeOrientationError,
    RepresentationError,
)
from persistri.impl.complex.simplex import Simplex, same_orientation, tuple_simplex
from persistri.impl.complex.structure import ComplexStructure, Family, same_datum
from persistri.impl.complex.vertex import Vertex
from persistri.impl.stats import Stats
from persistri.spec.option import Option

__all__ = ["Bootstrap"]

D = TypeVar("D")

_faces = tuple_simplex.faces
_flip = tuple_simplex.flip


class Bootstrap(ComplexStructure[D]):
    """``functor Bootstrap (Sub : SIMPCOMP, Map : ORD_MAP) : SIMPCOMP`` for n = dim Sub + 1.

    ``Bootstrap(sub, backend)`` is uncounted; ``Bootstrap(sub, backend, stats)``
    reports to ``stats`` (give ``sub`` the same ``stats`` to count the inner
    complexes too, as :func:`persistri.impl.complex.simpcomp` does).
    """

    kind = "bootstrap"

    def __init__(self, sub: ComplexStructure[D], backend: Any, stats: Stats | None = None) -> None:
        if not isinstance(sub, ComplexStructure):
            raise TypeError(f"Bootstrap: sub must be a persistri complex structure, got {type(sub).__name__}")
        self.n = sub.n + 1
        self._sub = sub
        self._init_maps(backend, stats)
        if stats is None and sub.stats is None:
            self.family = Family(self.kind, self.n, backend, sub.family, self)
        else:
            self.family = Bootstrap[D](sub.family.plain, backend).family

    @property
    def sub(self) -> ComplexStructure[D]:
        """The structure of the (n−1)-complexes under each vertex."""
        return self._sub

    def _inner(self, rep: Any, v: Vertex) -> Any:
        """The inner complex under ``v``, or None."""
        found = self._m.find(rep, v)
        return None if found is None else found[0]

    def _data(self, rep: Any, s: Simplex) -> Option[D]:
        inner = self._inner(rep, s[0])
        if inner is None:
            return None
        return self._sub._data(inner, s[1:])

    def _find(self, rep: Any, f: Simplex) -> list[Simplex]:
        # t has f as a face iff t ~ join(x, f) = (x, u, rest…); under u = f[0] it is
        # join(u, g) with g ~ flip(join(x, rest)): g has flip(rest) as a face.
        u = f[0]
        inner = self._inner(rep, u)
        if inner is None:
            return []
        rest = f[1:]
        out: list[Simplex] = []
        fset = set(f)
        for g in self._sub._find(inner, _flip(rest)):
            t = (u,) + g
            # Only the 1-complex below a 2-complex returns both orientations (a vertex has one).
            (x,) = [v for v in g if v not in fset]
            if same_orientation(t, (x,) + f):
                out.append(t)
        return out

    def _star(self, rep: Any, v: Vertex) -> list[Simplex]:
        inner = self._inner(rep, v)
        if inner is None:
            return []
        return [(v,) + g for g, _ in self._sub._items(inner)]

    def _items(self, rep: Any) -> Iterator[tuple[Simplex, D]]:
        for a, inner in self._m.listItemsi(rep):
            for g, x in self._sub._items(inner):
                if a < min(g):
                    yield (a,) + g, x

    def _add(self, rep: Any, s: Simplex, x: D) -> Any:
        sub, m = self._sub, self._m
        fs = _faces(s)
        for i, v in enumerate(s):
            found = m.find(rep, v)
            inner = sub._empty() if found is None else found[0]
            if i == 0:
                # The inner complex of the apex holds s's face iff s is present, its reverse iff flip(s) is.
                try:
                    inner = sub._add(inner, fs[0], x)
                except DuplicateSimplexError:
                    raise DuplicateSimplexError(f"add: {s!r} is already present") from None
                except OppositeOrientationError:
                    raise OppositeOrientationError(
                        f"add: {s!r} is present with the opposite orientation {_flip(s)!r}"
                    ) from None
            else:
                inner = sub._add(inner, fs[i], x)
            rep = m.insert(rep, v, inner)
        return rep

    def _rem(self, rep: Any, s: Simplex) -> Any:
        sub, m = self._sub, self._m
        fs = _faces(s)
        for i, v in enumerate(s):
            found = m.find(rep, v)
            try:
                if found is None:
                    raise AbsentSimplexError
                inner = sub._rem(found[0], fs[i])
            except AbsentSimplexError:
                if i == 0:
                    raise AbsentSimplexError(f"rem: {s!r} is not in the complex (in this orientation)") from None
                raise RepresentationError(f"{self.n}-complex: face {fs[i]!r} of {s!r} missing under {v!r}") from None
            rep = m.remove(rep, v)[0] if sub._is_empty(inner) else m.insert(rep, v, inner)
        return rep

    def _update(self, rep: Any, s: Simplex, f: Callable[[D], D]) -> Any:
        old = self._data(rep, s)
        if old is None:
            raise AbsentSimplexError(f"update: {s!r} is not in the complex (in this orientation)")
        y = f(old[0])
        sub, m = self._sub, self._m
        fs = _faces(s)
        for i, v in enumerate(s):
            found = m.find(rep, v)
            if found is None:
                raise RepresentationError(f"{self.n}-complex: {s!r} is held but {v!r} has no inner complex")
            rep = m.insert(rep, v, sub._update(found[0], fs[i], lambda _old: y))
        return rep

    def _check_rep(self, rep: Any) -> None:
        check = getattr(self._raw, "_check", None)
        if check is not None:
            check(rep)
        sub = self._sub
        table = dict(self._raw.listItemsi(rep))
        plain_sub = sub.family.plain
        for v, inner in table.items():
            if plain_sub._is_empty(inner):
                raise RepresentationError(f"{self.n}-complex: vertex {v!r} is mapped to an empty inner complex")
            plain_sub._check_rep(inner)
            for g, x in plain_sub._items(inner):
                if v in g:
                    raise RepresentationError(f"{self.n}-complex: the inner complex of {v!r} holds {g!r}, containing it")
                t = (v,) + g
                for i, (w, fw) in enumerate(zip(t, _faces(t))):
                    if i == 0:
                        continue
                    other = table.get(w)
                    got = None if other is None else plain_sub._data(other, fw)
                    if got is None:
                        raise RepresentationError(
                            f"{self.n}-complex: {t!r} is held under {v!r} but its face {fw!r} is missing under {w!r}"
                        )
                    if not same_datum(got[0], x):
                        raise RepresentationError(
                            f"{self.n}-complex: {t!r} carries different data under {v!r} and {w!r}"
                        )
