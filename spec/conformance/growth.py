"""What the growth workloads of both suites share: where versions are kept, how failures are pinned down.

A *growth workload* (:mod:`.ord_map_growth`, :mod:`.simpcomp_growth`) is a
fixed plan of operations, made before the structure is touched and the same on
every run: grow one structure to a size N operation by operation (the
*trunk*), keep the versions made at the :func:`checkpoints` sizes, then branch
from each kept version with a few mutations, and finally recheck every kept
version against the model it had when it was made.  Every operation is also
spot-checked as it is done — its operand before and after, its result — so a
structure that starts writing into its operand at *any* size up to N is caught
at the first operation that does it, and named with it.

Failures are pinned down by *replays* of the plan (a structure that is
deterministic answers the same way every time):

* a version found changed at a later check is replayed until the first
  operation after which it differs (:func:`first_change`, a bisection of
  O(lg N) replays), so the report names that operation;
* every failure is reproduced once more on another instance of the structure
  (:func:`~.hidden_state.second_instance`) while other objects are kept alive
  between operations (:class:`~.hidden_state.Ballast`), so that freed objects'
  ids are reused differently.  A failure that does not come back depended on
  something other than the versions and arguments (a cache keyed by ``id``,
  say): it is reported under the law ``determinism``, not as the law the first
  run happened to trip over.

Replays run only after a failure; a conforming structure pays for one run.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence, Set
from dataclasses import dataclass
from typing import Any, Protocol

from persistri.spec.conformance.hidden_state import Ballast, same_observation, second_instance
from persistri.spec.law import SignatureLawViolation

__all__ = ["Growth", "GrowthFailure", "GrowthPlan", "GrowthRun", "checkpoints", "counted", "first_change"]


def checkpoints(n: int) -> list[int]:
    """The sizes 1, 2, 4, 8, … below ``n``, then ``n`` (empty for ``n`` < 1): where growing versions are kept.

    Geometric, so the kept versions hold fewer than 3n items in all and the
    recheck of every one of them costs O(n) — while each power of two (the
    depth of a balanced tree, a HAMT level at 32 = 2^5, 1,024 = 2^10 and
    32,768 = 2^15 entries) has a version kept just past it.
    """
    out: list[int] = []
    size = 1
    while size < n:
        out.append(size)
        size *= 2
    if n >= 1:
        out.append(n)
    return out


def counted(n: int, noun: str, plural: str | None = None) -> str:
    """``n`` with thousands separators and ``noun``, plural when ``n`` ≠ 1: ``1 item``, ``1,203 items``."""
    word = noun if n == 1 else (plural if plural is not None else noun + "s")
    return f"{n:,} {word}"


def first_change(lo: int, hi: int, changed: Callable[[int], bool]) -> int:
    """The operation index ``t`` in ``(lo, hi]`` with ``changed(t)`` and not ``changed(t - 1)``, by bisection.

    ``changed(t)`` says whether the watched version differs from its model
    after operation ``t`` (by a replay); the caller knows ``changed(lo)`` is
    false and ``changed(hi)`` true.  ``⌈lg(hi − lo)⌉`` calls of ``changed``.
    """
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if changed(mid):
            hi = mid
        else:
            lo = mid
    return hi


@dataclass(frozen=True)
class GrowthFailure:
    """A check of a growth workload that failed: the law, the operation it was checked at, what was seen.

    ``at`` is the index of the operation in the plan (the check ran while or
    right after it was done; ``-1`` for the final recheck), ``key`` says which
    check it was so that a replay can tell the *same* failure from another one,
    and ``detail`` is the report's text (its first line names the law, the
    version and the operation).
    """

    law: str
    at: int
    key: str
    detail: str


class GrowthPlan(Protocol):
    """What the engine needs of a plan: its operations (each with the ``operand`` version it applies to and
    the ``result`` version it makes, ``-1`` for none), the models of the versions kept to the end, the
    operation that made each version, and the operations after which kept versions are glanced at."""

    @property
    def ops(self) -> Sequence[Any]: ...

    @property
    def kept(self) -> Mapping[int, Any]: ...

    @property
    def made_by(self) -> Mapping[int, int]: ...

    @property
    def checkpoints(self) -> Set[int]: ...


class GrowthRun(Protocol):
    """One run of a plan on one instance: the live versions, the checks, and how to describe things."""

    versions: dict[int, Any]

    def step(self, i: int, checked: bool) -> GrowthFailure | None:
        """Do operation ``i``; with ``checked``, spot-check its operand and result (the first failure)."""
        ...

    def operand_problem(self, i: int) -> str | None:
        """What is wrong with operation ``i``'s operand before it is applied (the first spot check), or None."""
        ...

    def agrees(self, v: int) -> str | None:
        """How kept version ``v`` disagrees with its model, or None."""
        ...

    def glance(self, v: int) -> str | None:
        """The cheap recheck of kept version ``v``: how it disagrees on a few samples, or None."""
        ...

    def version(self, v: int) -> str:
        """``version 17 (1,203 items)``."""
        ...

    def call(self, i: int) -> str:
        """Operation ``i`` as a call."""
        ...

    def made(self, i: int) -> str:
        """Operation ``i`` with what it makes."""
        ...

    def verb(self, i: int) -> str:
        """What operation ``i`` does, in a word or three (``insert``, ``remove of an absent key``)."""
        ...

    def law(self, i: int) -> str:
        """The law stating what operation ``i`` must return."""
        ...

    def history(self, v: int) -> str:
        """How version ``v`` was made."""
        ...


class _Unreplayable(Exception):
    """A replay failed before reaching the operation it was for (so it cannot confirm or pin anything)."""


@dataclass
class Growth:
    """The checked run of a growth plan, and the replays that pin a failure down and confirm it.

    ``make_run(structure, ballast, keep)`` starts a run of the plan on an
    instance; ``fresh`` makes second instances (:func:`~.hidden_state.second_instance`);
    ``violation`` is the signature's law violation; ``rerun`` tells the reader
    how to run the workload again.  :meth:`run` raises the violation of the
    first failure and returns when every check passed.
    """

    plan: GrowthPlan
    make_run: Callable[[Any, Ballast | None, frozenset[int]], GrowthRun]
    structure: Any
    fresh: Callable[[], Any] | None
    violation: type[SignatureLawViolation]
    rerun: str
    replays: int = 0

    def run(self) -> GrowthRun:
        """Every operation, spot-checked; the kept versions glanced at at each checkpoint and rechecked at the end.
        Returns the run (its kept versions) when every check passed."""
        plan = self.plan
        first = self.make_run(self.structure, None, frozenset())
        for i in range(len(plan.ops)):
            f = first.step(i, True)
            if f is not None:
                raise self.settle(f, first)
            if i in plan.checkpoints:
                for v in plan.kept:
                    if v in first.versions:
                        problem = first.glance(v)
                        if problem:
                            raise self.pin(v, i, first, problem, self._changed(v), f"at the recheck after operation {i:,}")
        last = len(plan.ops) - 1
        for v in sorted(plan.kept):
            problem = first.agrees(v)
            if problem:
                raise self.pin(v, last, first, problem, self._changed(v), "at the final recheck")
        return first

    def replay(self, upto: int, keep: frozenset[int] = frozenset()) -> tuple[GrowthRun, str]:
        """Operations 0 … ``upto`` − 1, unchecked, on a second instance (else the same one) with ballast."""
        self.replays += 1
        other, how = second_instance(self.structure, self.fresh)
        if other is None:
            other, how = self.structure, "the same instance"
        run = self.make_run(other, Ballast(), keep)
        for j in range(upto):
            f = run.step(j, False)
            if f is not None:
                raise _Unreplayable(f"the replay on {how} failed earlier, at {run.call(j)}: {f.detail}")
        return run, how

    def report(self, f: GrowthFailure, first: GrowthRun) -> list[str]:
        """The headline and detail lines of a failure of operation ``f.at``."""
        op = self.plan.ops[f.at]
        verb = first.verb(f.at)
        if f.key.startswith("after:"):
            head = f"persistence: {first.version(op.operand)} changed after {verb} on version {op.operand}"
        elif f.key == "invariants":
            head = f"invariants: the check rejected {first.version(op.result)}, made by {verb} on version {op.operand}"
        else:
            head = f"{f.law}: {verb} on {first.version(op.operand)} answered wrongly"
        return [
            head,
            f"the operation: {first.made(f.at)} (operation {f.at:,} of the workload)",
            f"seen: {f.detail}",
            f"how version {op.operand} was made: {first.history(op.operand)}",
        ]

    def confirm(self, f: GrowthFailure, first: GrowthRun) -> SignatureLawViolation:
        """The violation to report for ``f``: as found when a replay fails the same way, else ``determinism``."""
        lines = self.report(f, first)
        try:
            run, how = self.replay(f.at)
            again = run.step(f.at, True)
        except _Unreplayable as exc:
            return self.violation(
                "determinism", "\n".join([f"determinism: {lines[0]}, but a replay did not get there", *lines[1:], str(exc)])
            )
        if again is not None and again.key == f.key and same_observation(f.detail, again.detail):
            return self.violation(f.law, "\n".join([*lines, self.rerun]))
        seen = "it passed" if again is None else f"it failed differently: {again.detail}"
        return self.violation(
            "determinism",
            "\n".join(
                [
                    f"determinism: {lines[0]}, but not when the same operations were replayed on {how}",
                    *lines[1:],
                    f"the replay (other objects kept alive in between, so ids were reused differently): {seen}",
                    self.rerun,
                ]
            ),
        )

    def pin(
        self, v: int, hi: int, first: GrowthRun, seen: str, changed: Callable[[int], bool], where: str
    ) -> SignatureLawViolation:
        """Version ``v`` was found changed after operation ``hi`` (``seen`` says how): replay to find the operation
        after which it first differs, and report that operation (``changed(t)``: whether it differs after ``t``)."""
        made = self.plan.made_by.get(v, -1)
        try:
            if not changed(hi):
                _, how = second_instance(self.structure, self.fresh)
                return self.violation(
                    "determinism",
                    "\n".join(
                        [
                            f"determinism: {first.version(v)} was found changed {where}, but not when the same "
                            f"operations were replayed on {how}",
                            f"seen: {seen}",
                            f"how version {v} was made: {first.history(v)}",
                            self.rerun,
                        ]
                    ),
                )
            if made >= 0 and changed(made):
                op = self.plan.ops[made]
                law = first.law(made)
                return self.violation(
                    law,
                    "\n".join(
                        [
                            f"{law}: {first.verb(made)} on {first.version(op.operand)} made a version that is wrong",
                            f"the operation: {first.made(made)}",
                            f"seen: {seen}",
                            f"how version {op.operand} was made: {first.history(op.operand)}",
                            self.rerun,
                        ]
                    ),
                )
            t = first_change(made, hi, changed)
        except _Unreplayable as exc:
            lines = [
                f"persistence: {first.version(v)} was found changed {where}",
                f"seen: {seen}",
                f"how version {v} was made: {first.history(v)}",
                f"not pinned to one operation: {exc}",
            ]
            return self.violation("persistence", "\n".join(lines))
        op = self.plan.ops[t]
        lines = [
            f"persistence: {first.version(v)} changed after {first.verb(t)} on version {op.operand}",
            f"the operation: {first.made(t)} (operation {t:,} of the workload)",
            f"seen {where}: {seen}",
            f"how version {v} was made: {first.history(v)}",
        ]
        if op.operand != v:
            lines.append(f"how version {op.operand} was made: {first.history(op.operand)}")
        lines += [f"pinned to the operation by {self.replays} replays", self.rerun]
        return self.violation("persistence", "\n".join(lines))

    def settle(self, f: GrowthFailure, first: GrowthRun) -> SignatureLawViolation:
        """The violation for a spot check that failed: pinned when the operand had changed before, else confirmed."""
        if not f.key.startswith("before:"):
            return self.confirm(f, first)
        v = self.plan.ops[f.at].operand

        def changed(t: int) -> bool:
            run, _ = self.replay(t + 1, frozenset({v}))
            return run.operand_problem(f.at) is not None

        return self.pin(v, f.at - 1, first, f.detail, changed, f"before {first.call(f.at)}")

    def _changed(self, v: int) -> Callable[[int], bool]:
        """``changed(t)`` for a kept version: whether it disagrees with its model after operation ``t`` (a replay)."""

        def changed(t: int) -> bool:
            run, _ = self.replay(t + 1, frozenset({v}))
            return run.agrees(v) is not None

        return changed
