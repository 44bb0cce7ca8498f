"""A ``SIMPCOMP`` written the way an outside author would: vertices are plain objects, a complex a copied dict.

What makes it an outsider's is the vertex: an object with Python's default
equality (identity) and ``repr`` (an address), ordered by ``Vertex.compare``
alone — the ``VERTEX`` signature asks for nothing more.  Two runs that make
their vertices afresh from the same state make different objects for the same
vertex, so a suite that compared two sessions' answers with ``==`` would see
every answer holding a vertex change.  The complex itself is correct and
persistent (every update copies the dict of held simplices): O(size) a step.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from itertools import combinations
from typing import Any

from persistri.spec.order import Order

__all__ = ["OutsideComplex", "OutsideVertex", "initial_state", "outside_complex", "LowGrepOneOrientation", "VerticesDropTheLast"]


class OutsideVertex:
    """A vertex: its number (the order of ``new``) and its point; equality and hash by identity."""

    __slots__ = ("number", "point")

    def __init__(self, number: int, point: Any) -> None:
        self.number = number
        self.point = point


def _order(a: Any, b: Any) -> Order:
    return Order.LESS if a < b else Order.GREATER if b < a else Order.EQUAL


def initial_state() -> int:
    """The vertex state the suite starts from (``--state outside_complex:initial_state``): the next number."""
    return 0


class _Vertex:
    def compare(self, a: OutsideVertex, b: OutsideVertex) -> Order:
        return _order(a.number, b.number)

    def new(self, state: int, point: Any) -> tuple[int, OutsideVertex]:
        return state + 1, OutsideVertex(state, point)

    def loc(self, v: OutsideVertex) -> Any:
        return v.point


def _key(s: Sequence[OutsideVertex]) -> tuple[tuple[int, ...], int]:
    """``(sorted vertex numbers, parity of the permutation that sorts them)``: one key per orientation."""
    nums = [v.number for v in s]
    parity = sum(1 for i, j in combinations(range(len(nums)), 2) if nums[i] > nums[j]) % 2
    return tuple(sorted(nums)), parity


def _flip(s: tuple[OutsideVertex, ...]) -> tuple[OutsideVertex, ...]:
    return (s[1], s[0], *s[2:]) if len(s) >= 2 else s


def _faces(s: tuple[OutsideVertex, ...]) -> list[tuple[OutsideVertex, ...]]:
    """The induced faces: drop vertex i, and flip when i is odd."""
    out = []
    for i in range(len(s)):
        rest = s[:i] + s[i + 1 :]
        out.append(_flip(rest) if i % 2 else rest)
    return out


class _Simplex:
    Vertex = _Vertex()

    def compare(self, s: tuple[OutsideVertex, ...], t: tuple[OutsideVertex, ...]) -> Order:
        return _order(_key(s), _key(t))

    def dim(self, s: tuple[OutsideVertex, ...]) -> int:
        return len(s) - 1

    def vertices(self, s: tuple[OutsideVertex, ...]) -> list[OutsideVertex]:
        return list(s)

    def simplex(self, vs: Sequence[OutsideVertex]) -> tuple[OutsideVertex, ...]:
        return tuple(vs)

    def faces(self, s: tuple[OutsideVertex, ...]) -> list[tuple[OutsideVertex, ...]]:
        return _faces(s)

    def flip(self, s: tuple[OutsideVertex, ...]) -> tuple[OutsideVertex, ...]:
        return _flip(s)

    def down(self, s: tuple[OutsideVertex, ...]) -> tuple[OutsideVertex, tuple[OutsideVertex, ...]]:
        return s[0], s[1:]

    def join(self, v: OutsideVertex, f: tuple[OutsideVertex, ...]) -> tuple[OutsideVertex, ...]:
        return (v, *f)


Held = dict[tuple[tuple[int, ...], int], tuple[tuple[OutsideVertex, ...], Any]]


class OutsideComplex:
    """n-complexes as ``(n, {oriented key: (simplex, datum)})``, the dict copied by every update."""

    Simplex = _Simplex()

    def dim(self, c: tuple[int, Held]) -> int:
        return c[0]

    def new(self, n: int) -> tuple[int, Held]:
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise ValueError(f"new: dimension {n!r}")
        return n, {}

    def isEmpty(self, c: tuple[int, Held]) -> bool:
        return not c[1]

    def _checked(self, c: tuple[int, Held], s: Any) -> tuple[tuple[int, ...], int]:
        s = tuple(s)
        if len(s) != c[0] + 1:
            raise ValueError(f"a {len(s) - 1}-simplex in a {c[0]}-complex")
        if len({v.number for v in s}) != len(s):
            raise ValueError("repeated vertex")
        return _key(s)

    def add(self, c: tuple[int, Held], s: Any, x: Any) -> tuple[int, Held]:
        k = self._checked(c, s)
        if k in c[1] or (k[0], 1 - k[1]) in c[1]:
            raise ValueError("held, in this or the other orientation")
        held = dict(c[1])
        held[k] = (tuple(s), x)
        return c[0], held

    def rem(self, c: tuple[int, Held], s: Any) -> tuple[int, Held]:
        k = self._checked(c, s)
        if k not in c[1]:
            raise ValueError("not held in this orientation")
        held = dict(c[1])
        del held[k]
        return c[0], held

    def data(self, c: tuple[int, Held], s: Any) -> tuple[Any] | None:
        k = self._checked(c, s)
        return (c[1][k][1],) if k in c[1] else None

    def update(self, c: tuple[int, Held], s: Any, f: Callable[[Any], Any]) -> tuple[int, Held]:
        k = self._checked(c, s)
        if k not in c[1]:
            raise ValueError("not held in this orientation")
        held = dict(c[1])
        simplex, x = held[k]
        held[k] = (simplex, f(x))
        return c[0], held

    def find(self, c: tuple[int, Held], f: Any) -> list[tuple[OutsideVertex, ...]]:
        if len(tuple(f)) != c[0]:
            raise ValueError(f"find needs an ({c[0]} - 1)-simplex")
        want = _key(tuple(f))
        return [s for s, _ in c[1].values() if any(_key(g) == want for g in _faces(s))]

    def _of_dim(self, c: tuple[int, Held], d: int) -> list[tuple[OutsideVertex, ...]]:
        """The held d-simplices (d = n), or each d-face of a held simplex once, as the first held one induces it."""
        if d == c[0]:
            return [s for s, _ in c[1].values()]
        out: dict[tuple[int, ...], tuple[OutsideVertex, ...]] = {}
        layer = [s for s, _ in c[1].values()]
        for _ in range(c[0] - d):
            layer = [g for s in layer for g in _faces(s)]
        for g in layer:
            out.setdefault(_key(g)[0], g)
        return list(out.values())

    def simplices(self, c: tuple[int, Held], d: int) -> list[tuple[OutsideVertex, ...]]:
        return self._of_dim(c, d)

    def grep(self, c: tuple[int, Held], d: int, s: Any) -> list[tuple[OutsideVertex, ...]]:
        s = tuple(s)
        cands = self._of_dim(c, d)
        if len(s) == d and d == c[0]:  # an (n-1)-face: with its orientation, as find
            want = _key(s)
            return [t for t in cands if any(_key(g) == want for g in _faces(t))]
        if len(s) == d:  # a (d-1)-face of lower faces: each d-face holding it, oriented to induce it
            nums = {v.number for v in s}
            return [(other, *s) for t in cands if nums <= {v.number for v in t} for other in t if other.number not in nums]
        nums = {v.number for v in s}
        return [t for t in cands if nums <= {v.number for v in t}]

    def vertices(self, c: tuple[int, Held]) -> list[OutsideVertex]:
        seen: dict[int, OutsideVertex] = {}
        for s, _ in c[1].values():
            for v in s:
                seen.setdefault(v.number, v)
        return [seen[k] for k in sorted(seen)]


class LowGrepOneOrientation(OutsideComplex):
    """Broken: below dimension n, grep of a (d-1)-face keeps only the d-faces whose first-met orientation
    induces it (an easy slip), so it misses some (law grep)."""

    def grep(self, c: tuple[int, Held], d: int, s: Any) -> list[tuple[OutsideVertex, ...]]:
        s = tuple(s)
        if len(s) == d and d < c[0]:
            want = _key(s)
            return [t for t in self._of_dim(c, d) if any(_key(g) == want for g in _faces(t))]
        return super().grep(c, d, s)


class VerticesDropTheLast(OutsideComplex):
    """Broken: vertices(c) leaves out the greatest vertex (law agrees)."""

    def vertices(self, c: tuple[int, Held]) -> list[OutsideVertex]:
        return super().vertices(c)[:-1]


outside_complex = OutsideComplex()
