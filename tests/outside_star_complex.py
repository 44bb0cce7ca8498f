"""A SIMPCOMP written from scratch by following docs/conformance.md as an outsider: vertex stars, copied dicts.

A complex is an immutable record: its dimension, a dict from each held simplex's oriented key to
(simplex, datum), and a star: a dict from each vertex to the frozenset of held keys containing it.
Every update copies the two dicts (O(size)), so old versions never change.  Written from the guide's
"Complexes" section and the SIMPCOMP page (sml-python.md), without reading persistri's complexes;
``tests/test_conformance_outsider_star.py`` runs the suite on it.  ``ForgetfulRem`` is the slip a
star index invites: ``rem`` leaves the simplex in its last vertex's star (with and without a ``check``).
"""
from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations
from typing import Any

from persistri.spec.order import Order


def _cmp(a: Any, b: Any) -> Order:
    return Order.LESS if a < b else Order.GREATER if a > b else Order.EQUAL


@dataclass(frozen=True)
class V:
    """A vertex: its serial number and its point."""
    n: int
    point: Any = None

    def __hash__(self) -> int:
        return hash(self.n)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, V) and other.n == self.n


class Vertex:
    def compare(self, a: V, b: V) -> Order:
        return _cmp(a.n, b.n)

    def new(self, state: int, point: Any) -> tuple[int, V]:
        return state + 1, V(state, point)

    def loc(self, v: V) -> Any:
        return v.point


def initial_state() -> int:
    return 0


def key(s: tuple[V, ...]) -> tuple[tuple[int, ...], int]:
    nums = [v.n for v in s]
    if len(set(nums)) != len(nums):
        raise ValueError(f"repeated vertex in {nums}")
    inversions = sum(1 for i, j in combinations(range(len(nums)), 2) if nums[i] > nums[j])
    return tuple(sorted(nums)), inversions % 2


class Simplex:
    Vertex = Vertex()

    def compare(self, s: tuple[V, ...], t: tuple[V, ...]) -> Order:
        return _cmp((len(s), key(s)), (len(t), key(t)))

    def dim(self, s: tuple[V, ...]) -> int:
        return len(s) - 1

    def vertices(self, s: tuple[V, ...]) -> tuple[V, ...]:
        return s

    def simplex(self, vs: Any) -> tuple[V, ...]:
        vs = tuple(vs)
        if not all(isinstance(v, V) for v in vs):
            raise TypeError("not vertices")
        return vs

    def flip(self, s: tuple[V, ...]) -> tuple[V, ...]:
        if len(s) < 2:
            return s
        return s[:-2] + (s[-1], s[-2]) if len(s) > 2 else (s[1], s[0])

    def faces(self, s: tuple[V, ...]) -> list[tuple[V, ...]]:
        out = []
        for i in range(len(s)):
            rest = s[:i] + s[i + 1:]
            out.append(self.flip(rest) if i % 2 else rest)
        return out

    def down(self, s: tuple[V, ...]) -> tuple[V, tuple[V, ...]]:
        return s[0], s[1:]

    def join(self, v: V, f: tuple[V, ...]) -> tuple[V, ...]:
        return (v, *f)


@dataclass(frozen=True)
class Cx:
    n: int
    held: dict  # key -> (simplex, datum)
    star: dict  # vertex -> frozenset of keys


class StarComplex:
    Simplex = Simplex()

    def dim(self, c: Cx) -> int:
        return c.n

    def new(self, n: int) -> Cx:
        if not isinstance(n, int) or isinstance(n, bool) or n < 1:
            raise ValueError(f"dimension {n!r}")
        return Cx(n, {}, {})

    def isEmpty(self, c: Cx) -> bool:
        return not c.held

    def vertices(self, c: Cx) -> list[V]:
        return list(c.star)

    def _top(self, c: Cx, s: Any) -> tuple[tuple[V, ...], tuple[tuple[int, ...], int]]:
        s = tuple(s)
        if len(s) != c.n + 1:
            raise ValueError(f"a {len(s) - 1}-simplex in a {c.n}-complex")
        return s, key(s)

    def data(self, c: Cx, s: Any) -> tuple[Any] | None:
        s, k = self._top(c, s)
        hit = c.held.get(k)
        return None if hit is None else (hit[1],)

    def add(self, c: Cx, s: Any, x: Any) -> Cx:
        s, k = self._top(c, s)
        if k in c.held or (k[0], 1 - k[1]) in c.held:
            raise ValueError("already held (in some orientation)")
        held = dict(c.held)
        held[k] = (s, x)
        star = dict(c.star)
        for v in s:
            star[v] = star.get(v, frozenset()) | {k}
        return Cx(c.n, held, star)

    def rem(self, c: Cx, s: Any) -> Cx:
        s, k = self._top(c, s)
        if k not in c.held:
            raise ValueError("not held in this orientation")
        held = dict(c.held)
        del held[k]
        star = dict(c.star)
        for v in self._star_vertices(s):
            left = star[v] - {k}
            if left:
                star[v] = left
            else:
                del star[v]
        return Cx(c.n, held, star)

    def _star_vertices(self, s: tuple[V, ...]) -> tuple[V, ...]:
        return s

    def update(self, c: Cx, s: Any, f: Any) -> Cx:
        s, k = self._top(c, s)
        if k not in c.held:
            raise ValueError("not held")
        held = dict(c.held)
        t, x = held[k]
        held[k] = (t, f(x))
        return Cx(c.n, held, c.star)

    def _faces_of_dim(self, s: tuple[V, ...], d: int) -> list[tuple[V, ...]]:
        layer = [s]
        for _ in range(len(s) - 1 - d):
            layer = [g for t in layer for g in self.Simplex.faces(t)]
        return layer

    def simplices(self, c: Cx, d: int) -> list[tuple[V, ...]]:
        out: dict = {}
        for s, _ in c.held.values():
            for g in self._faces_of_dim(s, d):
                out.setdefault(key(g)[0] if d < c.n else key(g), g)
        return list(out.values())

    def find(self, c: Cx, f: Any) -> list[tuple[V, ...]]:
        f = tuple(f)
        if len(f) != c.n:
            raise ValueError("find needs an (n-1)-simplex")
        want = key(f)
        cands = c.star.get(f[0], frozenset())
        return [c.held[k][0] for k in cands if any(key(g) == want for g in self.Simplex.faces(c.held[k][0]))]

    def grep(self, c: Cx, d: int, s: Any) -> list[tuple[V, ...]]:
        s = tuple(s)
        nums = {v.n for v in s}
        if len(s) == d:  # a (d-1)-simplex: the d-simplices having it as a face with its orientation
            want = key(s)
            out = []
            for t in self.simplices(c, d):
                if nums <= {v.n for v in t}:
                    other = [v for v in t if v.n not in nums]
                    cand = (other[0], *s)
                    if d == c.n:
                        if any(key(g) == want for g in self.Simplex.faces(t)):
                            out.append(t)
                    else:
                        out.append(cand)
            return out
        return [t for t in self.simplices(c, d) if nums <= {v.n for v in t}]

    def check(self, c: Cx) -> None:
        for k, (s, _) in c.held.items():
            assert key(s) == k
            for v in s:
                assert k in c.star[v]
        for v, ks in c.star.items():
            assert ks, f"empty star for {v}"
            for k in ks:
                assert k in c.held and v.n in k[0]


class ForgetfulRem(StarComplex):
    """Broken: rem forgets to remove the simplex from its last vertex's star."""

    def _star_vertices(self, s: tuple[V, ...]) -> tuple[V, ...]:
        return s[:-1]


class ForgetfulRemNoCheck(ForgetfulRem):
    """The same, without the representation check (so only the laws can catch it)."""

    check = None  # type: ignore[assignment]  # no check(c): the suite skips `invariants`


star_complex = StarComplex()
forgetful = ForgetfulRem()
forgetful_nocheck = ForgetfulRemNoCheck()
