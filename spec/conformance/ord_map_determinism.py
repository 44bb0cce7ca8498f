"""The ``ORD_MAP`` tests of hidden state: ``determinism`` (replays answer alike) and ``isolation`` (instances
share nothing).

Neither compares answers with a model — the other tests do that.  They
compare the structure with *itself*:

* ``determinism`` runs one fixed session of a few hundred operations and
  queries three times: with every version kept alive; again on the same
  instance, freeing each version as soon as it is no longer needed (so that
  new versions reuse the ids of freed ones); and on a second instance.  The
  three must give the same answers, one by one.  A ``find`` memoised by
  ``id(m)``, a cache that is not invalidated, a counter that leaks into the
  answers: each makes a replay answer differently.
* ``isolation`` makes two instances the same way (two copies, or two calls of
  the class the user gave), builds a branching history of versions on the
  first, then operates on the second, looking at every version of the first
  after each operation — and the other way round.  State kept at class level
  (a table of versions, a shared cache) shows up as a version of one instance
  changed by an operation of the other.

Hypothesis's :class:`~hypothesis.errors.Flaky` — a failure that did not come
back when hypothesis replayed its example — is the same symptom in the other
tests; the runner and the pytest base class report it under ``determinism``
too (:mod:`.runner`).
"""

from __future__ import annotations

import random
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any

from hypothesis import settings

from persistri.spec.conformance.growth import counted
from persistri.spec.conformance.hidden_state import second_instance
from persistri.spec.conformance.ord_map_config import SuiteConfig
from persistri.spec.conformance.ord_map_history import combine
from persistri.spec.conformance.runner import ConformanceSkip
from persistri.spec.ord_map import NotFound
from persistri.spec.ord_map_laws import LawViolation

__all__ = ["t_determinism", "t_isolation"]

ROUNDS = 240
"""Rounds of the determinism session; each makes two to four versions and asks about a dozen questions."""

_KEYS = 48
"""The session's keys are 0 … _KEYS − 1, so that keys recur and later versions overwrite and remove them."""


@dataclass
class _Session:
    """One run of the fixed session on structure ``s``: the answers, in order, with the question each answers.

    Versions are numbered in the order they are made; ``made`` says how each
    was made (for messages).  With ``keep`` every version stays alive to the
    end; without it a version is freed as soon as the session no longer needs
    it, and ``ballast`` (if any) is fed at each round.
    """

    s: Any
    keep: bool
    questions: list[str] = field(default_factory=list)
    answers: list[object] = field(default_factory=list)
    made: dict[int, str] = field(default_factory=dict)
    _alive: list[Any] = field(default_factory=list)

    def ask(self, question: str, call: Callable[[], object]) -> object:
        """Record ``call()``'s answer (or the exception it raised) to ``question``."""
        try:
            answer: object = call()
        except NotFound:
            answer = "raises NotFound"
        except Exception as exc:
            answer = f"raises {type(exc).__name__}: {exc}"
        if isinstance(answer, Iterator):  # read once: its items are the answer (the listItemsi law refuses it)
            answer = ("an iterator over", tuple(answer))
        if isinstance(answer, list):
            answer = tuple(answer)
        self.questions.append(question)
        self.answers.append(answer)
        return answer

    def version(self, made: str, m: Any) -> int:
        v = len(self.made)
        self.made[v] = made
        if self.keep:
            self._alive.append(m)
        return v

    def run(self) -> None:
        s = self.s
        rng = random.Random("persistri-ord-map-determinism")
        keys = [rng.randrange(_KEYS) for _ in range(ROUNDS + 2)]
        base = s.empty()
        b = self.version("empty()", base)
        for r in range(ROUNDS):
            k, nxt, after = keys[r], keys[r + 1], keys[r + 2]
            m = s.insert(base, k, r)
            v = self.version(f"insert(version {b}, {k}, {r})", m)
            self.ask(f"find(version {v}, {k})", lambda: s.find(m, k))
            self.ask(f"find(version {v}, {nxt})", lambda: s.find(m, nxt))
            self.ask(f"inDomain(version {v}, {after})", lambda: s.inDomain(m, after))
            self.ask(f"numItems(version {v})", lambda: s.numItems(m))
            if r % 3 == 0:
                m2 = s.insertWith(combine, m, nxt, r)
                v2 = self.version(f"insertWith(f, version {v}, {nxt}, {r})", m2)
                self.ask(f"find(version {v2}, {nxt})", lambda: s.find(m2, nxt))
                self.ask(f"lookup(version {v2}, {k})", lambda: s.lookup(m2, k))
                removed = self.ask(f"remove(version {v2}, {k})", lambda: s.remove(m2, k))
                if isinstance(removed, tuple) and len(removed) == 2:
                    m3, value = removed
                    self.answers[-1] = ("the value", value)  # the map itself is not an answer
                    v3 = self.version(f"remove(version {v2}, {k})", m3)
                    self.ask(f"find(version {v3}, {k})", lambda: s.find(m3, k))
                    self.ask(f"numItems(version {v3})", lambda: s.numItems(m3))
                    del m3
                del m2, removed
            if r % 7 == 0:
                self.ask(f"listItemsi(version {v})", lambda: s.listItemsi(m))
                wrong = self.ask(f"remove(version {v}, {-1 - r}) of an absent key", lambda: s.remove(m, -1 - r))
                if isinstance(wrong, tuple) and len(wrong) == 2:  # returned where it must raise (remove_absent's law)
                    self.answers[-1] = ("returned, with the value", wrong[1])  # the map itself is not an answer
                del wrong
            if r % 4 == 0:
                base, b = m, v
            del m  # without keep, the version is freed here: the next one may get its id


def _sessions(s: Any, keep: bool) -> _Session:
    session = _Session(s, keep)
    session.run()
    return session


def _answer(question: str, answer: object) -> str:
    """An answer as a message shows it: the options ``find`` returns as SOME v and NONE."""
    if question.startswith("find("):
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
        v = int(question.split("version ", 1)[1].split(",")[0].split(")")[0])
        chain = _history(a, v)
        return LawViolation(
            "determinism",
            "\n".join(
                [
                    f"determinism: {question} answered {_answer(question, x)} {how_a}, and {_answer(question, y)} {how_b}",
                    f"how version {v} was made: {chain}",
                    f"question {i + 1:,} of {len(a.answers):,} of a fixed session of {ROUNDS} rounds of insert, "
                    "insertWith, remove and queries over the keys 0 … 47",
                ]
            ),
        )
    return None


def _history(session: _Session, v: int) -> str:
    """How version ``v`` of the session was made, back to ``empty()``: the operations, oldest first."""
    steps: list[str] = []
    while True:
        made = session.made[v]
        steps.append(f"version {v} = {made}")
        if made == "empty()":
            break
        v = int(made.split("version ", 1)[1].split(",")[0])
    if len(steps) > 8:
        steps = [*steps[:7], f"… ({len(steps) - 8} more)", steps[-1]]
    return "; ".join(reversed(steps))


def t_determinism(cfg: SuiteConfig, hs: settings) -> None:
    """The same session with every version kept, with versions freed, and on a second instance: equal answers."""
    s = cfg.structure
    kept = _sessions(s, keep=True)
    freed = _Session(s, keep=False)
    freed.run()
    found = _difference(kept, freed, "when every version was kept alive",
                        "when the same session ran again on the same instance, freeing each version once unused")
    if found is not None:
        raise found
    other, how = second_instance(s, cfg.fresh)
    if other is None:
        return  # the replays on one instance were the test; a second one cannot be made (see isolation)
    again = _sessions(other, keep=True)
    found = _difference(kept, again, "on the structure", f"when the same session ran on {how}")
    if found is not None:
        raise found


@dataclass
class _Instance:
    """One instance's branching history for the isolation test: versions, how each was made, what each showed."""

    s: Any
    name: str
    versions: list[Any] = field(default_factory=list)
    made: list[str] = field(default_factory=list)
    seen: list[object] = field(default_factory=list)

    def look(self, i: int) -> object:
        """What version ``i`` shows: its items (with their order) and count."""
        m = self.versions[i]
        try:
            return (tuple(self.s.listItemsi(m)), self.s.numItems(m))
        except Exception as exc:
            return f"reading it raises {type(exc).__name__}: {exc}"

    def make(self, m: Any, made: str) -> None:
        self.versions.append(m)
        self.made.append(made)
        self.seen.append(self.look(len(self.versions) - 1))

    def step(self, rng: random.Random, tag: str) -> str:
        """One operation on a random version (a branching history); returns it as a call."""
        s = self.s
        i = rng.randrange(len(self.versions))
        m = self.versions[i]
        k = rng.randrange(12)
        present = s.find(m, k) is not None
        if present and rng.random() < 0.3:
            call = f"remove(version {i}, {k})"
            self.make(s.remove(m, k)[0], call)
        elif rng.random() < 0.3:
            call = f"insertWith(f, version {i}, {k}, {tag!r})"
            self.make(s.insertWith(combine, m, k, tag), call)
        else:
            call = f"insert(version {i}, {k}, {tag!r})"
            self.make(s.insert(m, k, tag), call)
        return f"{call} on {self.name}, which made its version {len(self.versions) - 1}"

    def settle(self) -> None:
        """Take what each version shows now as what it must keep showing while the other instance operates
        (changes by this instance's own operations are the persistence tests' business)."""
        self.seen = [self.look(i) for i in range(len(self.versions))]

    def changed(self, after: str, other: str) -> LawViolation | None:
        """The violation if a version shows something other than it did when made, or None."""
        for i, before in enumerate(self.seen):
            now = self.look(i)
            if now != before:
                return LawViolation(
                    "isolation",
                    "\n".join(
                        [
                            f"isolation: version {i} of {self.name} changed after {after}",
                            f"seen: version {i} ({self.made[i]}) showed {_shown(before)} before the other instance "
                            f"operated; now it shows {_shown(now)}",
                            f"the two instances: {other}; each made its own versions, and only the second one operated",
                        ]
                    ),
                )
        return None


def _shown(look: object) -> str:
    if isinstance(look, tuple) and len(look) == 2 and isinstance(look[0], tuple):
        items = dict(look[0])
        shown = repr(items) if len(items) <= 8 else repr(dict(list(items.items())[:8]))[:-1] + ", …}"
        return f"{counted(int(look[1]), 'item')} {shown}"
    return str(look)


STEPS = 30
"""Operations of each instance in the isolation test (its versions stay small: every one is looked at after
every operation of the other instance)."""


def t_isolation(cfg: SuiteConfig, hs: settings) -> None:
    """Two instances made alike: operations on either never change what the other's versions show."""
    a_s, how = second_instance(cfg.structure, cfg.fresh)
    b_s, _ = second_instance(cfg.structure, cfg.fresh)
    if a_s is None or b_s is None:
        raise ConformanceSkip(f"cannot make a second instance: {how}")
    made = how.replace("a second instance, ", "")
    pair = f"the first and the second instance, each {made}"
    a = _Instance(a_s, "the first instance")
    b = _Instance(b_s, "the second instance")
    rng = random.Random("persistri-ord-map-isolation")
    a.make(a_s.empty(), "empty()")
    for j in range(STEPS):
        a.step(rng, f"a{j}")
    a.settle()
    b.make(b_s.empty(), "empty()")
    found = a.changed("empty() on the second instance", pair)
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
