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

Both front ends run a body through :func:`run_body`, which names what a
failure means.  Hypothesis's :class:`~hypothesis.errors.Flaky` — a failing
example that passed when hypothesis ran it again — becomes a violation of the
law ``determinism`` (:func:`flaky_violation`): the structure answered the same
calls differently, so its answers depend on state outside the versions and
arguments it was given.  Any other law a test (marked ``confirm``) finds
broken is checked once more: the test reruns on a second instance of the
structure that keeps every version it makes alive (:mod:`.hidden_state`),
replaying hypothesis's failing example (the run keeps its examples in memory).
When the rerun does not repeat the failure exactly, the failure came from the
structure's hidden state — a cache keyed by ``id``, say — and is reported
under ``determinism``; when it does, the first failure is reported as it was.
Either way the report says which law the first run broke.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Generic, Literal, TypeVar

from hypothesis import HealthCheck, Phase, settings
from hypothesis.database import InMemoryExampleDatabase, MultiplexedDatabase
from hypothesis.errors import Flaky
from hypothesis.reporting import with_reporter

from persistri.spec.conformance.hidden_state import Ballast, Holding, same_observation
from persistri.spec.law import LawViolation, SignatureLawViolation

__all__ = [
    "ConformanceSkip",
    "ConformanceTest",
    "Failure",
    "Outcome",
    "ConformanceReport",
    "explicit_settings",
    "flaky_violation",
    "run_body",
    "run_tests",
]

C = TypeVar("C")


class ConformanceSkip(Exception):
    """Raised by a test body that does not apply to the structure (e.g. it has no ``_check``)."""


@dataclass(frozen=True)
class ConformanceTest(Generic[C]):
    """One conformance test: ``body(config, settings)`` returns on success and raises on failure.

    ``laws`` names the laws the test exercises (for reports and docs); ``doc``
    says in one line what it does; ``confirm`` says whether :func:`run_body`
    confirms its failures by a rerun (off for the tests that confirm their own).
    """

    name: str
    laws: tuple[str, ...]
    doc: str
    body: Callable[[C, settings], None]
    confirm: bool = True


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
    (the suite checks results, not speed), no example database (nothing is saved between runs; the
    run keeps its failing examples in memory to confirm them, :func:`run_body`), one reported bug per
    test, and no *explain* phase (it traces coverage: slow, and the report already names the law).
    ``derandomize`` makes every run generate the same examples."""
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


def _first_violation(exc: BaseException) -> BaseException | None:
    """The first exception inside ``exc`` (a group's members, then causes) that is not hypothesis's own."""
    seen: set[int] = set()
    todo: list[BaseException] = [exc]
    while todo:
        e = todo.pop(0)
        if id(e) in seen:
            continue
        seen.add(id(e))
        if not isinstance(e, Flaky):
            return e
        if isinstance(e, BaseExceptionGroup):
            todo.extend(e.exceptions)
        for linked in (e.__cause__, e.__context__):
            if linked is not None:
                todo.append(linked)
    return None


def flaky_violation(exc: Flaky, violation: type[SignatureLawViolation]) -> SignatureLawViolation:
    """Hypothesis's ``Flaky`` as a violation of the law ``determinism`` of the suite's signature (``violation``).

    The detail says what the first run saw (the law it broke, or the
    exception) and keeps hypothesis's notes (the example) on the new exception.
    """
    first = _first_violation(exc)
    if isinstance(first, LawViolation):
        what = f"law {first.law}: {first.detail or first.statement}"
    elif first is not None:
        what = f"{type(first).__name__}: {first}"
    else:
        what = str(exc).splitlines()[0]
    detail = "\n".join(
        [
            f"determinism: hypothesis found a failing example, ran it again, and it passed ({type(exc).__name__}): "
            "the same calls answered differently the second time",
            f"the first run: {what}",
            "the answers depend on state outside the versions and arguments given (a cache keyed by id, "
            "a cache that is not invalidated, state shared between calls or instances)",
        ]
    )
    out = violation("determinism", detail)
    notes = [str(n) for n in getattr(exc, "__notes__", ())]
    if first is not None and not notes:
        notes = [str(n) for n in getattr(first, "__notes__", ())]
    for note in notes:
        out.add_note(note)
    return out


Second = Callable[[C, Callable[[Any], Any]], tuple[C | None, str]]
"""``second(config, wrap)``: the configuration with ``wrap`` of a second instance of its structure, and how
that instance was made (``(None, why not)`` when none can be made)."""


def _first_run_settings(hs: settings, private: InMemoryExampleDatabase) -> settings:
    """``hs`` with the run's failing example also saved in ``private``, a database no other test can touch.

    The confirming rerun replays the example from ``private``.  It cannot rely on ``hs.database`` alone: a
    directory database is shared by every test (and by pytest-xdist's workers), and another test of the same
    body on a conforming structure replays the saved example, sees it pass and deletes it.  The user's database
    still receives the example, for their next run.
    """
    if hs.derandomize:
        return hs
    both = private if hs.database is None else MultiplexedDatabase(private, hs.database)
    return settings(hs, database=both)


def _rerun_settings(hs: settings, private: InMemoryExampleDatabase) -> tuple[settings, bool]:
    """Settings for the rerun that confirms a failure, and whether that rerun searches again.

    Either way the rerun meets the *same* failing example.  Normally it replays
    the example the first run saved in ``private``, and nothing else.  A
    derandomized run instead searches and shrinks again along the same path to
    the same example; so does a run whose random seed is forced
    (``--hypothesis-seed``), for which hypothesis saves nothing.
    """
    if hs.derandomize or not private.data:
        return hs, True
    return settings(hs, database=private, phases=[Phase.explicit, Phase.reuse]), False


def _holding_all(inner: Any) -> Holding:
    """:class:`Holding` without a bound: a rerun that searches again makes every version the first run made,
    and must keep them all alive (past the bound, freed versions' ids would be reused as in the first run)."""
    return Holding(inner, bound=sys.maxsize)


def _confirmed(
    test: ConformanceTest[C],
    config: C,
    hs: settings,
    private: InMemoryExampleDatabase,
    exc: LawViolation,
    violation: type[SignatureLawViolation],
    second: Second[C],
) -> LawViolation:
    """``exc`` when ``test`` fails the same way on a second instance that keeps its versions alive, else
    ``determinism``.  "The same way": the same law and the same observation on the same example (the rerun
    meets it, :func:`_rerun_settings`); a structure that is simply wrong repeats itself exactly, but for the
    memory addresses its values print with (:func:`~.hidden_state.same_observation`)."""
    rerun, searches = _rerun_settings(hs, private)
    # Two reruns of the same example, with different ballast, must both repeat the failure (an id-keyed cache
    # copied with its stale entries can repeat one by the accident of the allocator).
    for drops in (256, 4_096):
        other, how = second(config, _holding_all if searches else Holding)
        if other is None:
            return exc
        ballast = Ballast()
        for _ in range(drops):  # the rerun's objects take fresh memory, not the first run's ids
            ballast.drop()
        try:
            test.body(other, rerun)
        except Flaky:
            seen = "it failed and then passed the same example (hypothesis's Flaky)"
            break
        except LawViolation as again:
            if again.law == exc.law and same_observation(exc.detail, again.detail):
                continue
            seen = f"it failed differently: law {again.law}: {again.detail}"
            break
        except Exception as again:
            seen = f"it raised {type(again).__name__}: {again}"
            break
        else:
            seen = "it passed"
            break
    else:
        return exc
    detail = "\n".join(
        [
            f"determinism: law {exc.law} failed, but not the same way when the test ran again (hypothesis's "
            f"failing example first) on {how}, with every version it made kept alive",
            f"the first run: {exc.detail}",
            f"the rerun: {seen}",
            "the answers depend on state outside the versions and arguments given (a cache keyed by id, "
            "a cache that is not invalidated, state shared between calls or instances)",
        ]
    )
    out = violation("determinism", detail)
    for note in getattr(exc, "__notes__", ()):
        out.add_note(str(note))
    return out


def run_body(test: ConformanceTest[C], config: C, hs: settings, violation: type[SignatureLawViolation], second: Second[C]) -> None:
    """Run ``test``'s body; on failure raise the violation it means (module docstring): a ``Flaky`` as
    ``determinism``, and a failure of a ``confirm`` test as found or, when a second run differs, as
    ``determinism``.  :class:`ConformanceSkip` and other exceptions pass through."""
    private = InMemoryExampleDatabase()
    try:
        test.body(config, _first_run_settings(hs, private))
    except Flaky as exc:
        raise flaky_violation(exc, violation) from exc
    except LawViolation as exc:
        if not test.confirm:
            raise
        out = _confirmed(test, config, hs, private, exc, violation, second)
        if out is exc:
            raise
        raise out from exc


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
    violation: type[SignatureLawViolation],
    second: Second[C],
    options: Sequence[tuple[str, object]] = (),
) -> ConformanceReport:
    """Run every test of ``tests`` on ``config`` with settings ``hs``; never raises for a failing test.

    Hypothesis's own output is captured (and used as the counterexample when an
    exception carries no notes), so nothing is printed.  ``violation`` is the
    signature's :class:`~persistri.spec.law.SignatureLawViolation` and
    ``second`` makes a second instance: both for :func:`run_body`.
    """
    outcomes: list[Outcome] = []
    for test in tests:
        reported: list[str] = []
        try:
            with with_reporter(lambda line: reported.append(str(line))):
                run_body(test, config, hs, violation, second)
        except ConformanceSkip as skip:
            outcomes.append(Outcome(test.name, "skipped", reason=str(skip)))
        except Exception as exc:
            outcomes.append(Outcome(test.name, "failed", failure=_failure(test, exc, reported)))
        else:
            outcomes.append(Outcome(test.name, "passed"))
    return ConformanceReport(structure, signature, tuple(outcomes), tuple(options))
