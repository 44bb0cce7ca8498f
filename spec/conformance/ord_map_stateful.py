"""Hypothesis-driven branching histories of ``ORD_MAP`` versions: random programs and a state machine.

Both keep *every* version with its model snapshot (:class:`~.ord_map_history.History`)
and recheck all of them after every step: the ``persistence`` test runs random
programs of a few steps, each applied to a version some steps back; the
``stateful_history`` test runs hypothesis's rule-based state machine, whose
failing histories shrink step by step.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any, Literal

from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.stateful import (
    RuleBasedStateMachine,
    initialize,
    invariant,
    precondition,
    rule,
    run_state_machine_as_test,
)

from persistri.spec.conformance.ord_map_config import SuiteConfig
from persistri.spec.conformance.ord_map_history import History, back
from persistri.spec.conformance.runner import ConformanceSkip
from persistri.spec.conformance.strategies import COLLIDING_INTS, KeyKind, fresh_key, key_kinds, small_keys, values

__all__ = ["Program", "Step", "machine", "t_persistence", "t_stateful"]

@dataclass(frozen=True)
class Step:
    """One step of a program: ``op`` applied ``back`` versions before the latest (wrapping).

    ``remove`` removes ``key`` when that version holds it and otherwise its
    smallest key (an empty version: as ``remove_absent``); ``remove_absent``
    removes ``key`` when the version lacks it and otherwise a key above all of
    the version's, expecting NotFound.
    """

    op: Literal["insert", "insertWith", "remove", "remove_absent"]
    back: int
    key: Any
    value: Any


@dataclass(frozen=True)
class Program:
    """A sequence of steps over keys of one kind."""

    kind: KeyKind
    steps: tuple[Step, ...]


@functools.cache
def _steps(kind: KeyKind, hashing: bool) -> st.SearchStrategy[list[Step]]:
    step = st.builds(
        Step,
        op=st.sampled_from(("insert", "insertWith", "remove", "remove_absent")),
        back=st.integers(0, 6),
        key=small_keys(kind, hashing),
        value=values(),
    )
    return st.lists(step, max_size=20)


@st.composite
def _programs(draw: st.DrawFn, hashing: bool) -> Program:
    kind = draw(st.sampled_from(key_kinds(hashing)))
    return Program(kind, tuple(draw(_steps(kind, hashing))))


def t_persistence(cfg: SuiteConfig, hs: settings) -> None:
    @given(_programs(cfg.hashing))
    def persistence(program: Program) -> None:
        h = History(cfg, program.kind)
        for step in program.steps:
            i = back(len(h.versions), step.back)
            snap = h.versions[i][1]
            if step.op == "insert":
                h.insert(i, step.key, step.value)
            elif step.op == "insertWith":
                h.insert_with(i, step.key, step.value)
            elif step.op == "remove" and snap:
                h.remove(i, step.key if step.key in snap else min(snap))
            else:
                h.remove_absent(i, fresh_key(program.kind, snap) if step.key in snap else step.key)
            h.check_all()

    hs(persistence)()


def machine(cfg: SuiteConfig) -> type[RuleBasedStateMachine]:
    """The stateful test's machine class for ``cfg`` (a class per configuration: rules cannot take one)."""
    # Small domains: each rule's arguments are cheap to shrink (a failing history shrinks
    # by deleting steps and lowering these numbers, every attempt a rerun of the machine).
    small = st.integers(-6, 6)
    ints = st.one_of(small, st.sampled_from(COLLIDING_INTS)) if cfg.hashing else small
    at = st.integers(0, 7)
    pick = st.integers(0, 7)
    vals = st.one_of(st.none(), st.integers(0, 3), st.tuples(st.integers(0, 1)))

    def has_items(self: OrdMapHistory) -> bool:
        return self.h is not None and bool(self.h.nonempty())

    class OrdMapHistory(RuleBasedStateMachine):
        """Every version ever made, each with its model snapshot, rechecked after every step.

        Each rule applies one operation to a version ``at`` steps before the
        latest (old versions too: branching histories, "multiple futures") and
        checks the result by that operation's laws and the query laws; the
        invariant then applies the persistence law to *all* versions.  Every
        rule changes the history (a rule that only looked would be a step the
        shrinker struggles to delete from a failing history).
        """

        def __init__(self) -> None:
            super().__init__()
            self.h: History | None = None

        @property
        def hist(self) -> History:
            assert self.h is not None, "the initialize rule runs first"
            return self.h

        @initialize(kind=st.sampled_from(key_kinds(cfg.hashing)))
        def start(self, kind: KeyKind) -> None:
            self.h = History(cfg, kind)

        @rule(at=at, i=ints, v=vals)
        def insert(self, at: int, i: int, v: Any) -> None:
            h = self.hist
            h.insert(back(len(h.versions), at), h.key(i), v)

        @precondition(has_items)
        @rule(at=at, pick=pick, v=vals)
        def overwrite(self, at: int, pick: int, v: Any) -> None:
            h = self.hist
            full = h.nonempty()
            i = full[back(len(full), at)]
            present = sorted(h.versions[i][1])
            h.insert(i, present[pick % len(present)], v)

        @rule(at=at, i=ints, v=vals)
        def insert_with(self, at: int, i: int, v: Any) -> None:
            h = self.hist
            h.insert_with(back(len(h.versions), at), h.key(i), v)

        @precondition(has_items)
        @rule(at=at, pick=pick)
        def remove(self, at: int, pick: int) -> None:
            h = self.hist
            full = h.nonempty()
            i = full[back(len(full), at)]
            present = sorted(h.versions[i][1])
            h.remove(i, present[pick % len(present)])

        @rule(at=at, i=ints)
        def remove_absent(self, at: int, i: int) -> None:
            h = self.hist
            v = back(len(h.versions), at)
            k = h.key(i)
            snap = h.versions[v][1]
            h.remove_absent(v, fresh_key(h.kind, snap) if k in snap else k)

        @invariant()
        def every_version_unchanged(self) -> None:
            if self.h is not None:
                self.h.check_all()

    return OrdMapHistory


def t_stateful(cfg: SuiteConfig, hs: settings) -> None:
    if cfg.stateful_steps == 0:
        raise ConformanceSkip("stateful_steps = 0")
    run_state_machine_as_test(machine(cfg), settings=settings(hs, stateful_step_count=cfg.stateful_steps))

