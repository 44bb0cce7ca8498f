"""A branching history of ``SIMPCOMP`` versions, each with its model, and the simplex helpers the tests share.

A model is a ``dict`` from the oriented key of each held n-simplex to its datum
(:mod:`persistri.spec.simpcomp_laws`).  :class:`History` applies each operation
to a chosen version — old ones too, so the history branches — checks it by that
operation's law, and appends the result with its model; :meth:`History.check_all`
applies the persistence law to every version made.  Simplices are built from
index orders into a pool of the structure's own vertices.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from itertools import combinations
from typing import Any

from persistri.spec.conformance.simpcomp_config import SimpCompSuiteConfig
from persistri.spec.simpcomp_laws import (
    OrientedKey,
    law_add,
    law_add_present,
    law_bad_input,
    law_find,
    law_grep,
    law_invariants,
    law_new,
    law_persistence,
    law_rem,
    law_rem_absent,
    law_update,
    oriented_key,
    representative,
)

__all__ = [
    "History",
    "absent_simplex",
    "back",
    "bad_calls",
    "check_version",
    "faces_both_ways",
    "first_indices",
    "flipped",
    "held",
    "rotated",
    "simplex_of",
]

def simplex_of(C: Any, pool: Sequence[Any], order: Sequence[int]) -> Any:
    return C.Simplex.simplex([pool[i] for i in order])


def first_indices(perm: Sequence[int], k: int, size: int) -> list[int]:
    """The first ``size`` entries of the permutation ``perm`` that index a pool of ``k`` vertices."""
    return [i for i in perm if i < k][:size]


def flipped(C: Any, s: Any) -> Any:
    """``s`` with its first two vertices swapped: the other orientation, built from positions only."""
    vs = list(C.Simplex.vertices(s))
    return C.Simplex.simplex([vs[1], vs[0], *vs[2:]])


def rotated(C: Any, s: Any) -> Any:
    """An even reordering of ``s`` (its first three vertices rotated), or ``s`` itself below three vertices."""
    vs = list(C.Simplex.vertices(s))
    if len(vs) < 3:
        return s
    return C.Simplex.simplex([vs[1], vs[2], vs[0], *vs[3:]])


def held(C: Any, model: dict[OrientedKey, Any], s: Any) -> bool:
    """Whether ``s`` is held in either orientation."""
    return oriented_key(C.Simplex, s) in model or oriented_key(C.Simplex, flipped(C, s)) in model


def absent_simplex(C: Any, pool: Sequence[Any], n: int, model: dict[OrientedKey, Any], order: Sequence[int]) -> Any:
    """The simplex of ``order`` if held in neither orientation, else the first such simplex of the pool (or None)."""
    s = simplex_of(C, pool, order)
    if not held(C, model, s):
        return s
    for combo in combinations(range(len(pool)), n + 1):
        t = simplex_of(C, pool, combo)
        if not held(C, model, t):
            return t
    return None


def check_version(cfg: SimpCompSuiteConfig, c: Any, where: str) -> None:
    fn = cfg.checker
    if fn is not None:
        law_invariants(fn, c, where)


@dataclass
class History:
    """Every version of one dimension made so far, each with its model: a branching history."""

    cfg: SimpCompSuiteConfig
    n: int
    pool: list[Any]
    versions: list[tuple[Any, dict[OrientedKey, Any]]] = field(default_factory=list)

    def __post_init__(self) -> None:
        c = law_new(self.cfg.structure, self.n)
        check_version(self.cfg, c, f"new({self.n})")
        self.versions.append((c, {}))

    @property
    def C(self) -> Any:
        return self.cfg.structure

    def nonempty(self) -> list[int]:
        return [i for i, (_, m) in enumerate(self.versions) if m]

    def _made(self, c: Any, model: dict[OrientedKey, Any], what: str) -> None:
        check_version(self.cfg, c, what)
        self.versions.append((c, model))

    def add(self, i: int, order: Sequence[int], x: Any) -> None:
        """``add`` to version ``i``: the add law when the simplex is free, add_present when held either way."""
        c, model = self.versions[i]
        s = simplex_of(self.C, self.pool, order)
        if held(self.C, model, s):
            law_add_present(self.C, c, self.n, model, s, x)
            return
        c2, m2 = law_add(self.C, c, self.n, model, s, x)
        self._made(c2, m2, f"after add to version {i}")

    def rem(self, i: int, pick: int) -> None:
        """``rem`` of a held simplex of version ``i`` (given in another order of its orientation)."""
        c, model = self.versions[i]
        keys = list(model)
        s = rotated(self.C, representative(self.C.Simplex, keys[pick % len(keys)]))
        c2, m2 = law_rem(self.C, c, self.n, model, s)
        self._made(c2, m2, f"after rem from version {i}")

    def rem_absent(self, i: int, order: Sequence[int]) -> None:
        """``rem`` of a simplex not held in that orientation (the flip of a held one when it is held)."""
        c, model = self.versions[i]
        s = simplex_of(self.C, self.pool, order)
        if oriented_key(self.C.Simplex, s) in model:
            s = flipped(self.C, s)
        law_rem_absent(self.C, c, self.n, model, s)

    def update(self, i: int, pick: int, tag: Any) -> None:
        """``update`` of a held simplex of version ``i``."""
        c, model = self.versions[i]
        keys = list(model)
        s = representative(self.C.Simplex, keys[pick % len(keys)])
        c2, m2 = law_update(self.C, c, self.n, model, s, lambda x: (tag, x))
        self._made(c2, m2, f"after update of version {i}")

    def look(self, i: int, order: Sequence[int], d: int) -> None:
        """On version ``i``: ``find`` of a face of ``order``'s simplex and of the faces of a held simplex (both
        ways round), and ``grep`` of the first vertices of ``order``."""
        c, model = self.versions[i]
        n = self.n
        faces = [simplex_of(self.C, self.pool, order[:n])]
        if model:
            faces += faces_both_ways(self.C, n, representative(self.C.Simplex, list(model)[d % len(model)]))
        for f in faces:
            law_find(self.C, c, n, model, f)
        # d picks both grep's dimension and the size of the simplex grepped for.
        law_grep(self.C, c, n, model, d % (n + 1), simplex_of(self.C, self.pool, order[: (d // (n + 1)) % (n + 1) + 1]))

    def bad_call(self, i: int, order: Sequence[int], kind: int, x: Any) -> None:
        """One of :func:`bad_calls` on version ``i``: it must raise and leave the version as it was."""
        c, model = self.versions[i]
        calls = bad_calls(self.C, self.pool, self.n, c, order, x)
        what, call = calls[kind % len(calls)]
        law_bad_input(self.C, c, self.n, model, call, what)

    def check_all(self) -> None:
        law_persistence(self.C, self.n, self.versions)


def faces_both_ways(C: Any, n: int, t: Any) -> list[Any]:
    """The induced faces of the n-simplex ``t`` (built from positions) and, for n ≥ 2, their other orientations:
    ``find`` must tell them apart."""
    vs = list(C.Simplex.vertices(t))
    out = []
    for i in range(n + 1):
        rest = vs[:i] + vs[i + 1 :]
        if i % 2 == 1 and len(rest) >= 2:
            rest[-1], rest[-2] = rest[-2], rest[-1]
        f = C.Simplex.simplex(rest)
        out += [f, flipped(C, f)] if n >= 2 else [f]
    return out


def back(count: int, at: int) -> int:
    """Index of the version ``at`` steps before the latest of ``count`` (wrapping): shrinks to the latest."""
    return count - 1 - at % count


def bad_calls(C: Any, pool: Sequence[Any], n: int, c: Any, order: Sequence[int], x: Any) -> list[tuple[str, Callable[[], object]]]:
    """Calls on ``c`` with bad input, each with a description: a repeated vertex (``add``, ``rem``,
    ``data``), simplices of the wrong dimension (``add``, ``rem``, ``find``).  ``order`` is n+1 pool indices."""
    S = C.Simplex
    s = simplex_of(C, pool, order)
    repeated = [pool[order[0]], *(pool[i] for i in order[:n])]  # n+1 vertices, the first twice
    # Simplex.simplex may refuse the repeated vertex itself: that is a refusal of the call too.
    calls: list[tuple[str, Callable[[], object]]] = [
        (f"add(c, simplex({repeated!r}), x), a repeated vertex", lambda: C.add(c, S.simplex(repeated), x)),
        (f"rem(c, simplex({repeated!r})), a repeated vertex", lambda: C.rem(c, S.simplex(repeated))),
        (f"data(c, simplex({repeated!r})), a repeated vertex", lambda: C.data(c, S.simplex(repeated))),
    ]
    short = S.simplex([pool[i] for i in order[:n]])
    calls += [
        (f"add(c, {short!r}, x) of an (n-1)-simplex", lambda: C.add(c, short, x)),
        (f"rem(c, {short!r}) of an (n-1)-simplex", lambda: C.rem(c, short)),
        (f"find(c, {s!r}) of an n-simplex", lambda: C.find(c, s)),
    ]
    rest = [i for i in range(len(pool)) if i not in order]
    if rest:
        long = S.simplex([pool[i] for i in order] + [pool[rest[0]]])
        calls.append((f"add(c, {long!r}, x) of an (n+1)-simplex", lambda: C.add(c, long, x)))
    return calls
