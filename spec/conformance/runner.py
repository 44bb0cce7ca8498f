"""Running conformance tests without pytest, and the report they produce.

A conformance suite is a tuple of :class:`ConformanceTest` s: named test bodies
that take the suite's configuration and a hypothesis :class:`~hypothesis.settings`
and raise on failure.  The same bodies back two front ends:

* a pytest base class (e.g. :class:`~persistri.spec.conformance.OrdMapConformance`),
  whose ``test_*`` methods call them with the user's *active* hypothesis profile;
* :func:`run_tests`, which calls them with *explicit* settings, catches each
  failure and returns a :class:`ConformanceReport`: for each failing test the
  law it broke (from the :class:`~persistri.spec.law.LawViolation`), the law's
  statement, what was observed, and hypothesis's minimal failing example.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Generic, Literal, TypeVar

from hypothesis import HealthCheck, Phase, settings
from hypothesis.reporting import with_reporter

from persistri.spec.law import LawViolation

__all__ = [
    "ConformanceSkip",
    "ConformanceTest",
    "Failure",
    "Outcome",
    "ConformanceReport",
    "explicit_settings",
    "run_tests",
]

C = TypeVar("C")


class ConformanceSkip(Exception):
    """Raised by a test body that does not apply to the structure (e.g. it has no ``_check``)."""


@dataclass(frozen=True)
class ConformanceTest(Generic[C]):
    """One conformance test: ``body(config, settings)`` returns on success and raises on failure.

    ``laws`` names the laws the test exercises (for reports and docs); ``doc``
    says in one line what it does.
    """

    name: str
    laws: tuple[str, ...]
    doc: str
    body: Callable[[C, settings], None]


@dataclass(frozen=True)
class Failure:
    """Why a test failed: the broken law (``None`` when the structure crashed outside any law),
    its statement, what was observed, and the minimal failing example hypothesis found."""

    test: str
    law: str | None
    statement: str
    detail: str
    example: str

    def format(self) -> str:
        """Several lines: the law and its statement, the observation, the counterexample."""
        head = f"law {self.law}: {self.statement}" if self.law else f"error: {self.statement}"
        lines = [f"FAILED {self.test} — {head}"]
        lines += ["  " + line for line in self.detail.splitlines()]
        if self.example:
            lines.append("  counterexample:")
            lines += ["    " + line for line in self.example.splitlines()]
        return "\n".join(lines)


@dataclass(frozen=True)
class Outcome:
    """The outcome of one test: ``passed``, ``failed`` (with a :class:`Failure`) or ``skipped`` (with a reason)."""

    test: str
    status: Literal["passed", "failed", "skipped"]
    failure: Failure | None = None
    reason: str = ""


@dataclass(frozen=True)
class ConformanceReport:
    """The outcomes of a conformance run over one structure, with the options it ran with."""

    structure: str
    signature: str
    outcomes: tuple[Outcome, ...]
    options: tuple[tuple[str, object], ...]

    @property
    def ok(self) -> bool:
        """Whether no test failed."""
        return not self.failures

    @property
    def failures(self) -> list[Failure]:
        """The failures, in test order."""
        return [o.failure for o in self.outcomes if o.failure is not None]

    @property
    def failed_laws(self) -> set[str]:
        """The names of the laws some test found broken."""
        return {f.law for f in self.failures if f.law is not None}

    def count(self, status: Literal["passed", "failed", "skipped"]) -> int:
        """How many tests ended with ``status``."""
        return sum(1 for o in self.outcomes if o.status == status)

    def summary(self) -> str:
        """One line: the verdict and the counts."""
        verdict = f"conforms to {self.signature}" if self.ok else f"does NOT conform to {self.signature}"
        counts = f"{self.count('passed')} passed, {self.count('failed')} failed, {self.count('skipped')} skipped"
        opts = ", ".join(f"{k}={v}" for k, v in self.options)
        return f"{self.structure} {verdict}: {counts} ({opts})"

    def format(self) -> str:
        """The summary, the skipped tests with their reasons, and every failure in full."""
        lines = [self.summary()]
        lines += [f"skipped {o.test}: {o.reason}" for o in self.outcomes if o.status == "skipped"]
        lines += [f.format() for f in self.failures]
        return "\n".join(lines)


def explicit_settings(max_examples: int, *, derandomize: bool = False) -> settings:
    """Settings independent of any loaded profile: hypothesis's defaults, ``max_examples``, no deadline
    (the suite checks results, not speed), no example database (nothing is saved between runs),
    one reported bug per test, and no *explain* phase (it traces coverage: slow, and the report
    already names the law).  ``derandomize`` makes every run generate the same examples."""
    return settings(
        settings.get_profile("default"),
        max_examples=max_examples,
        derandomize=derandomize,
        deadline=None,
        database=None,
        report_multiple_bugs=False,
        print_blob=False,
        suppress_health_check=[HealthCheck.too_slow],
        phases=[p for p in Phase if p is not Phase.explain],
    )


def _failure(test: ConformanceTest[C], exc: BaseException, reported: list[str]) -> Failure:
    notes = [str(n) for n in getattr(exc, "__notes__", ())]
    example = "\n".join(notes) if notes else "\n".join(reported)
    if isinstance(exc, LawViolation):
        return Failure(test.name, exc.law, exc.statement, exc.detail, example)
    detail = f"{type(exc).__name__}: {exc}"
    return Failure(test.name, None, "the structure raised an exception outside any law", detail, example)


def run_tests(
    tests: Sequence[ConformanceTest[C]],
    config: C,
    hs: settings,
    *,
    structure: str,
    signature: str,
    options: Sequence[tuple[str, object]] = (),
) -> ConformanceReport:
    """Run every test of ``tests`` on ``config`` with settings ``hs``; never raises for a failing test.

    Hypothesis's own output is captured (and used as the counterexample when an
    exception carries no notes), so nothing is printed.
    """
    outcomes: list[Outcome] = []
    for test in tests:
        reported: list[str] = []
        try:
            with with_reporter(lambda line: reported.append(str(line))):
                test.body(config, hs)
        except ConformanceSkip as skip:
            outcomes.append(Outcome(test.name, "skipped", reason=str(skip)))
        except Exception as exc:
            outcomes.append(Outcome(test.name, "failed", failure=_failure(test, exc, reported)))
        else:
            outcomes.append(Outcome(test.name, "passed"))
    return ConformanceReport(structure, signature, tuple(outcomes), tuple(options))
