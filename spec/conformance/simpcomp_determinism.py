"""The ``SIMPCOMP`` tests of hidden state: ``determinism`` (replays answer alike) and ``isolation`` (instances
share nothing), as :mod:`.ord_map_determinism` for maps.

``determinism`` runs one fixed session — adds, updates, removals and queries
(``data``, ``find``, ``simplices``, ``vertices``) on a slowly growing
complex — three times: every version kept alive; again on the same instance,
freeing each version as soon as it is no longer needed; and on a second
instance.  The answers must be equal, one by one.  ``isolation`` builds a
branching history on one of two instances made alike, then operates on the
other, looking at every version of the first after each operation, and the
other way round.  Neither compares with a model: the other tests do.
"""

from __future__ import annotations

import random
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from hypothesis import settings

from persistri.spec.conformance.growth import counted
from persistri.spec.conformance.hidden_state import second_instance
from persistri.spec.conformance.runner import ConformanceSkip
from persistri.spec.conformance.simpcomp_config import SimpCompSuiteConfig, vertex_pool
from persistri.spec.conformance.simpcomp_growth_plan import index_key, noun
from persistri.spec.order import Order
from persistri.spec.simpcomp_laws import LawViolation, oriented_key

__all__ = ["t_determinism", "t_isolation"]

ROUNDS = 150
"""Rounds of the determinism session; each makes one to three versions and asks about half a dozen questions."""

_POOL = 10
"""The sessions' simplices are drawn from this many vertices (n + 4 in dimensions above 6), so that they recur,
collide and get removed."""


def _pool_size(n: int) -> int:
    return max(_POOL, n + 4)


def _free(rng: random.Random, n: int, held: set[Any]) -> tuple[int, ...] | None:
    """A random n-simplex over the pool's indices held in neither orientation (None after a few tries)."""
    for _ in range(20):
        t = tuple(rng.sample(range(_pool_size(n)), n + 1))
        flipped = (t[1], t[0], *t[2:]) if n >= 1 else t
        if index_key(t) not in held and index_key(flipped) not in held:
            return t
    return None


@dataclass(frozen=True)
class PoolVertex:
    """A vertex in a session's answers: its place in the session's pool of vertices (shown as ``pool[i]``)."""

    index: int

    def __repr__(self) -> str:
        return f"pool[{self.index}]"


@dataclass
class _Session:
    """One run of the fixed session in dimension ``n``: the questions asked and the answers, in order."""

    cfg: SimpCompSuiteConfig
    C: Any
    n: int
    keep: bool
    questions: list[str] = field(default_factory=list)
    answers: list[object] = field(default_factory=list)
    made: dict[int, str] = field(default_factory=dict)
    _alive: list[Any] = field(default_factory=list)
    _pool: list[Any] = field(default_factory=list)

    def ask(self, question: str, call: Callable[[], object]) -> object:
        """Record ``call()``'s answer (or what it raised) to ``question``; simplices as oriented keys, sorted.

        Vertices are recorded as their places in this session's pool (:class:`PoolVertex`): each
        session makes its vertices afresh, and the ``VERTEX`` signature compares them by ``compare``
        only — an outside vertex type may well have identity equality and an address in its repr.
        """
        try:
            answer: object = call()
        except Exception as exc:
            answer = f"raises {type(exc).__name__}: {exc}"
        if isinstance(answer, (list, tuple)) and question.split("(")[0] in ("find", "simplices", "vertices"):
            S = self.C.Simplex
            if question.startswith(("find", "simplices")):
                keys: list[object] = []
                for x in answer:
                    vs, parity = oriented_key(S, x)
                    keys.append((tuple(self._place(v) for v in vs), parity))
            else:
                keys = [self._place(v) for v in answer]
            answer = tuple(sorted(keys, key=repr))
        self.questions.append(question)
        self.answers.append(answer)
        return answer

    def _place(self, v: Any) -> object:
        """``v`` as its place in the pool (the same object, else the vertex ``compare`` finds equal), or ``v``."""
        for i, p in enumerate(self._pool):
            if p is v:
                return PoolVertex(i)
        compare = self.C.Simplex.Vertex.compare
        for i, p in enumerate(self._pool):
            try:
                if compare(v, p) is Order.EQUAL:
                    return PoolVertex(i)
            except Exception:  # not a vertex of this structure: recorded as it is
                break
        return v

    def version(self, made: str, c: Any) -> int:
        v = len(self.made)
        self.made[v] = made
        if self.keep:
            self._alive.append(c)
        return v

    def run(self) -> None:
        C, n = self.C, self.n
        S = C.Simplex
        pool = vertex_pool(self.cfg, _pool_size(n))
        self._pool = pool
        rng = random.Random(f"persistri-simpcomp-determinism:{n}")

        def sx(t: tuple[int, ...]) -> Any:
            return S.simplex([pool[i] for i in t])

        def shown(t: tuple[int, ...]) -> str:
            return "(" + ", ".join(repr(pool[i]) for i in t) + ")"

        base = C.new(n)
        b = self.version(f"new({n})", base)
        held: set[Any] = set()
        upcoming = _free(rng, n, held)
        for r in range(ROUNDS):
            t = upcoming
            if t is None:
                break
            c = C.add(base, sx(t), r)
            v = self.version(f"add(version {b}, {shown(t)}, {r})", c)
            mine = held | {index_key(t)}
            upcoming = _free(rng, n, mine)
            self.ask(f"data(version {v}, {shown(t)})", lambda: C.data(c, sx(t)))
            if upcoming is not None:
                nxt = upcoming
                self.ask(f"data(version {v}, {shown(nxt)})", lambda: C.data(c, sx(nxt)))
            if n >= 1:
                self.ask(f"find(version {v}, {shown(t[1:])})", lambda: C.find(c, sx(t[1:])))
            self.ask(f"isEmpty(version {v})", lambda: C.isEmpty(c))
            if r % 3 == 0:
                c2 = C.update(c, sx(t), lambda x: ("u", x))
                v2 = self.version(f"update(version {v}, {shown(t)}, x ↦ ('u', x))", c2)
                self.ask(f"data(version {v2}, {shown(t)})", lambda: C.data(c2, sx(t)))
                c3 = C.rem(c2, sx(t))
                v3 = self.version(f"rem(version {v2}, {shown(t)})", c3)
                self.ask(f"data(version {v3}, {shown(t)})", lambda: C.data(c3, sx(t)))
                del c2, c3
            if r % 7 == 0:
                self.ask(f"simplices(version {v}, {n})", lambda: C.simplices(c, n))
                self.ask(f"vertices(version {v})", lambda: C.vertices(c))
            if r % 4 == 0:
                base, b, held = c, v, mine
            del c  # without keep, the version is freed here: the next one may get its id


def _version_of(question: str) -> int:
    return int(question.split("version ", 1)[1].split(",")[0].split(")")[0])


def _history(session: _Session, v: int) -> str:
    steps: list[str] = []
    while True:
        made = session.made[v]
        steps.append(f"version {v} = {made}")
        if made.startswith("new("):
            break
        v = _version_of(made)
    if len(steps) > 8:
        steps = [*steps[:7], f"… ({len(steps) - 8} more)", steps[-1]]
    return "; ".join(reversed(steps))


def _answer(question: str, answer: object) -> str:
    """An answer as a message shows it: the options ``data`` returns as SOME v and NONE."""
    if question.startswith("data("):
        if answer is None:
            return "NONE"
        if isinstance(answer, tuple) and len(answer) == 1:
            return f"SOME {answer[0]!r}"
    return repr(answer)


def _difference(a: _Session, b: _Session, how_a: str, how_b: str) -> LawViolation | None:
    """The violation for the first question two sessions answered differently, or None."""
    for i, (x, y) in enumerate(zip(a.answers, b.answers)):
        if x is y or x == y:
            continue
        question = a.questions[i]
        v = _version_of(question)
        return LawViolation(
            "determinism",
            "\n".join(
                [
                    f"determinism: {question} answered {_answer(question, x)} {how_a}, and {_answer(question, y)} {how_b}",
                    f"how version {v} was made: {_history(a, v)}",
                    f"question {i + 1:,} of {len(a.answers):,} of a fixed session of {ROUNDS} rounds of add, update, "
                    f"rem and queries in dimension {a.n}, over {_pool_size(a.n)} vertices",
                ]
            ),
        )
    if len(a.answers) != len(b.answers):
        return LawViolation("determinism", f"determinism: the session asked {len(a.answers)} questions {how_a} and {len(b.answers)} {how_b}")
    return None


def t_determinism(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    """The same session with every version kept, with versions freed, and on a second instance: equal answers."""
    C = cfg.structure
    other, how = second_instance(C, cfg.fresh)
    for n in cfg.dims:
        kept = _Session(cfg, C, n, keep=True)
        kept.run()
        freed = _Session(cfg, C, n, keep=False)
        freed.run()
        found = _difference(kept, freed, "when every version was kept alive",
                            "when the same session ran again on the same instance, freeing each version once unused")
        if found is not None:
            raise found
        if other is not None:
            again = _Session(cfg, other, n, keep=True)
            again.run()
            found = _difference(kept, again, "on the structure", f"when the same session ran on {how}")
            if found is not None:
                raise found


@dataclass
class _Instance:
    """One instance's branching history for the isolation test: versions, how each was made, what each shows."""

    C: Any
    n: int
    name: str
    pool: list[Any]
    versions: list[Any] = field(default_factory=list)
    models: list[set[Any]] = field(default_factory=list)
    made: list[str] = field(default_factory=list)
    seen: list[object] = field(default_factory=list)

    def look(self, i: int) -> object:
        """What version ``i`` shows: its n-simplices (as oriented keys) with their data."""
        C, c = self.C, self.versions[i]
        try:
            tops = list(C.simplices(c, self.n))
            return tuple(sorted(((oriented_key(C.Simplex, t), C.data(c, t)) for t in tops), key=repr))
        except Exception as exc:
            return f"reading it raises {type(exc).__name__}: {exc}"

    def make(self, c: Any, model: set[Any], made: str) -> None:
        self.versions.append(c)
        self.models.append(model)
        self.made.append(made)
        self.seen.append(self.look(len(self.versions) - 1))

    def settle(self) -> None:
        """What every version shows now is what it must keep showing while the other instance operates."""
        self.seen = [self.look(i) for i in range(len(self.versions))]

    def step(self, rng: random.Random, tag: str) -> str:
        """One add, update or rem on a random version (a branching history); returns it as a call."""
        C, n, S = self.C, self.n, self.C.Simplex
        i = rng.randrange(len(self.versions))
        c, model = self.versions[i], self.models[i]

        def shown(t: Sequence[int]) -> str:
            return "(" + ", ".join(repr(self.pool[j]) for j in t) + ")"

        held = sorted(model)
        if held and rng.random() < 0.4:
            vs, parity = held[rng.randrange(len(held))]
            t = list(vs)
            if parity and len(t) >= 2:
                t[-1], t[-2] = t[-2], t[-1]
            s = S.simplex([self.pool[j] for j in t])
            if rng.random() < 0.5:
                call = f"rem(version {i}, {shown(t)})"
                self.make(C.rem(c, s), model - {index_key(tuple(t))}, call)
            else:
                call = f"update(version {i}, {shown(t)}, x ↦ ({tag!r}, x))"
                self.make(C.update(c, s, lambda x: (tag, x)), model, call)
        else:
            t2 = _free(rng, n, model)
            if t2 is None:  # that version is full: start again from the empty one
                t2 = tuple(range(n + 1))
                i, c, model = 0, self.versions[0], set()
            call = f"add(version {i}, {shown(t2)}, {tag!r})"
            self.make(C.add(c, S.simplex([self.pool[j] for j in t2]), tag), model | {index_key(t2)}, call)
        return f"{call} on {self.name}, which made its version {len(self.versions) - 1}"

    def changed(self, after: str, pair: str) -> LawViolation | None:
        one, many = noun(self.n)
        for i, before in enumerate(self.seen):
            now = self.look(i)
            if now != before:
                size = len(before) if isinstance(before, tuple) else 0
                return LawViolation(
                    "isolation",
                    "\n".join(
                        [
                            f"isolation: version {i} ({counted(size, one, many)}) of {self.name} changed after {after}",
                            f"seen: version {i} ({self.made[i]}) showed {_shown(before)} before the other instance "
                            f"operated; now it shows {_shown(now)}",
                            f"the two instances: {pair}; each made its own versions, and only the other one operated",
                        ]
                    ),
                )
        return None


def _shown(look: object) -> str:
    if isinstance(look, tuple):
        items = [f"{k[0]}{'′' if k[1] else ''} ↦ {x!r}" for k, x in look[:6]]
        return "{" + ", ".join(items) + (", …" if len(look) > 6 else "") + "}"
    return str(look)


STEPS = 20
"""Operations of each instance in the isolation test."""


def t_isolation(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    """Two instances made alike: operations on either never change what the other's versions show."""
    a_C, how = second_instance(cfg.structure, cfg.fresh)
    b_C, _ = second_instance(cfg.structure, cfg.fresh)
    if a_C is None or b_C is None:
        raise ConformanceSkip(f"cannot make a second instance: {how}")
    pair = f"the first and the second instance, each {how.replace('a second instance, ', '')}"
    for n in cfg.dims:
        rng = random.Random(f"persistri-simpcomp-isolation:{n}")
        a = _Instance(a_C, n, "the first instance", vertex_pool(cfg, _pool_size(n)))
        b = _Instance(b_C, n, "the second instance", vertex_pool(cfg, _pool_size(n)))
        a.make(a_C.new(n), set(), f"new({n})")
        for j in range(STEPS):
            a.step(rng, f"a{j}")
        a.settle()
        b.make(b_C.new(n), set(), f"new({n})")
        found = a.changed(f"new({n}) on the second instance", pair)
        if found is not None:
            raise found
        for j in range(STEPS):
            call = b.step(rng, f"b{j}")
            found = a.changed(call, pair)
            if found is not None:
                raise found
        b.settle()
        for j in range(STEPS):
            call = a.step(rng, f"c{j}")
            found = b.changed(call, pair)
            if found is not None:
                raise found
