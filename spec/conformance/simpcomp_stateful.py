"""Hypothesis-driven branching histories of ``SIMPCOMP`` versions: random programs and a state machine.

Both keep *every* version with its model (:class:`~.simpcomp_history.History`)
and recheck all of them after every step.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, precondition, rule, run_state_machine_as_test

from persistri.spec.conformance.runner import ConformanceSkip
from persistri.spec.conformance.simpcomp_cases import VALUES
from persistri.spec.conformance.simpcomp_config import SimpCompSuiteConfig, pool_size, vertex_pool
from persistri.spec.conformance.simpcomp_history import History, back, first_indices

__all__ = ["Step", "machine", "t_persistence", "t_stateful"]

@dataclass(frozen=True)
class Step:
    """One step of a program: ``op`` applied ``back`` versions before the latest (wrapping)."""

    op: str
    back: int
    perm: tuple[int, ...]
    pick: int
    x: Any


_OPS = ("add", "add", "rem", "rem_absent", "update", "look", "bad")


@st.composite
def _programs(draw: st.DrawFn, dims: tuple[int, ...]) -> tuple[int, tuple[Step, ...]]:
    n = draw(st.sampled_from(dims))
    step = st.builds(
        Step,
        op=st.sampled_from(_OPS),
        back=st.integers(0, 6),
        perm=st.permutations(range(pool_size(n))).map(tuple),
        pick=st.integers(0, 20),
        x=VALUES,
    )
    return n, tuple(draw(st.lists(step, max_size=16)))


def _apply(h: History, step: Step) -> None:
    i = back(len(h.versions), step.back)
    n = h.n
    order = list(step.perm[: n + 1])
    if step.op == "rem" and h.versions[i][1]:
        h.rem(i, step.pick)
    elif step.op == "update" and h.versions[i][1]:
        h.update(i, step.pick, step.x)
    elif step.op == "rem_absent":
        h.rem_absent(i, order)
    elif step.op == "look":
        h.look(i, order, step.pick)
    elif step.op == "bad":
        h.bad_call(i, order, step.pick, step.x)
    else:
        h.add(i, order, step.x)


def t_persistence(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    @given(_programs(cfg.dims))
    def persistence(program: tuple[int, tuple[Step, ...]]) -> None:
        n, steps = program
        h = History(cfg, n, vertex_pool(cfg, pool_size(n)))
        for step in steps:
            _apply(h, step)
            h.check_all()

    hs(persistence)()


def machine(cfg: SimpCompSuiteConfig) -> type[RuleBasedStateMachine]:
    """The stateful test's machine class for ``cfg`` (a class per configuration: rules cannot take one)."""
    top = pool_size(max(cfg.dims))
    perm = st.permutations(range(top)).map(tuple)
    at = st.integers(0, 7)
    pick = st.integers(0, 7)

    def has_simplices(self: SimpCompHistory) -> bool:
        return self.h is not None and bool(self.h.nonempty())

    class SimpCompHistory(RuleBasedStateMachine):
        """Every version ever made, each with its model, rechecked after every step.

        Each rule applies one operation to a version ``at`` steps before the
        latest (old versions too: branching histories) and checks it by that
        operation's law (which also checks the new version against its model
        and the old one against its own); the invariant then applies the
        persistence law to *all* versions.
        """

        def __init__(self) -> None:
            super().__init__()
            self.h: History | None = None

        @property
        def hist(self) -> History:
            assert self.h is not None, "the initialize rule runs first"
            return self.h

        def _order(self, p: tuple[int, ...]) -> list[int]:
            h = self.hist
            return first_indices(p, len(h.pool), h.n + 1)

        @initialize(n=st.sampled_from(cfg.dims))
        def start(self, n: int) -> None:
            self.h = History(cfg, n, vertex_pool(cfg, pool_size(n)))

        @rule(at=at, p=perm, x=VALUES)
        def add(self, at: int, p: tuple[int, ...], x: Any) -> None:
            h = self.hist
            h.add(back(len(h.versions), at), self._order(p), x)

        @precondition(has_simplices)
        @rule(at=at, pick=pick)
        def rem(self, at: int, pick: int) -> None:
            h = self.hist
            full = h.nonempty()
            h.rem(full[back(len(full), at)], pick)

        @precondition(has_simplices)
        @rule(at=at, pick=pick, tag=st.integers(0, 3))
        def update(self, at: int, pick: int, tag: int) -> None:
            h = self.hist
            full = h.nonempty()
            h.update(full[back(len(full), at)], pick, tag)

        @rule(at=at, p=perm)
        def rem_absent(self, at: int, p: tuple[int, ...]) -> None:
            h = self.hist
            h.rem_absent(back(len(h.versions), at), self._order(p))

        @rule(at=at, p=perm, d=st.integers(0, 24))
        def look(self, at: int, p: tuple[int, ...], d: int) -> None:
            h = self.hist
            h.look(back(len(h.versions), at), self._order(p), d)

        @rule(at=at, p=perm, kind=st.integers(0, 6), x=VALUES)
        def bad_call(self, at: int, p: tuple[int, ...], kind: int, x: Any) -> None:
            h = self.hist
            h.bad_call(back(len(h.versions), at), self._order(p), kind, x)

        @invariant()
        def every_version_unchanged(self) -> None:
            if self.h is not None:
                self.h.check_all()

    return SimpCompHistory


def t_stateful(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    if cfg.stateful_steps == 0:
        raise ConformanceSkip("stateful_steps = 0")
    run_state_machine_as_test(machine(cfg), settings=settings(hs, stateful_step_count=cfg.stateful_steps))
