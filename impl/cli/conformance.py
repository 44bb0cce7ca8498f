"""``persistri conformance``: run a conformance suite on a backend named on the command line.

``persistri conformance maps MODULE:ATTR`` runs the ``ORD_MAP`` suite
(:func:`persistri.spec.conformance.run_conformance`) on the structure
``ATTR`` of module ``MODULE`` (a class is instantiated with no arguments);
``persistri conformance complex MODULE:ATTR --state MODULE:ATTR`` runs the
``SIMPCOMP`` suite (:func:`persistri.spec.conformance.run_simpcomp_conformance`).
Exit status: 0 when it conforms, 1 when some law fails (each failure is
printed with the law, its statement, what was seen and hypothesis's minimal
counterexample or the operations of the workload that broke it), 2 when
``MODULE:ATTR`` cannot be loaded or is not a structure of the signature, a
``--state`` cannot make the structure's vertices, a ``--test`` name is not
one of the suite's, or every test that ran was skipped (one line on stderr).
"""

from __future__ import annotations

import importlib
import os
import sys
import tempfile
from collections.abc import Sequence
from typing import Any, NoReturn

import click

from persistri.impl.cli.errors import error_line, fail

__all__ = ["conformance", "maps", "complex_", "load_target", "TargetError"]


class TargetError(Exception):
    """``MODULE:ATTR`` names nothing usable; the message is the one line the CLI prints."""


def _fail(ctx: click.Context, message: str) -> NoReturn:
    fail(message)  # one line on stderr, exit status 2 (persistri.impl.cli.errors)


def load_target(target: str) -> object:
    """The object ``MODULE:ATTR`` names (``ATTR`` may be dotted); raises :class:`TargetError` with one line.

    ``MODULE`` is imported with the current directory on ``sys.path`` (a console
    script does not put it there; ``python -m`` and pytest do), so a module next
    to the user is found.  Shared by every ``persistri conformance`` sub-command.
    """
    module_name, sep, attr_path = target.partition(":")
    if not sep or not module_name or not attr_path:
        raise TargetError(f"expected MODULE:ATTR (e.g. persistri.impl.maps.red_black:red_black), got {target!r}")
    cwd = os.getcwd()
    if cwd not in sys.path and "" not in sys.path:
        sys.path.insert(0, cwd)
    try:
        module = importlib.import_module(module_name)
    except ModuleNotFoundError as exc:
        raise TargetError(f"cannot import module {module_name!r}: {exc}") from None
    except Exception as exc:  # the user's module failed while importing: say how, in one line
        first = str(exc).splitlines()[0] if str(exc) else ""
        raise TargetError(f"importing module {module_name!r} failed: {type(exc).__name__}: {first}") from None
    obj: object = module
    for part in attr_path.split("."):
        try:
            obj = getattr(obj, part)
        except AttributeError:
            raise TargetError(f"module {module_name!r} has no attribute {attr_path!r}") from None
    return obj


_TEST_OPTION = click.option(
    "--test",
    "tests",
    metavar="NAME",
    multiple=True,
    help="Run only this test of the suite (repeatable), e.g. --test growth; default: every test.",
)


def _check_tests(ctx: click.Context, tests: tuple[str, ...], known: Sequence[Any]) -> None:
    """One line and exit 2 when a --test name is not a test of the suite."""
    names = [t.name for t in known]
    unknown = [t for t in tests if t not in names]
    if unknown:
        _fail(ctx, f"--test: no test named {', '.join(map(repr, unknown))}; the tests are: {', '.join(names)}")


def _refuse_an_empty_run(ctx: click.Context, target: str, report: Any) -> None:
    """Exit 2 with one line when every test that ran was skipped: nothing was checked, so "conforms" (exit 0)
    would be a verdict no structure could fail (e.g. ``--test growth --workload-size 0``)."""
    if report.outcomes and all(o.status == "skipped" for o in report.outcomes):
        reasons = "; ".join(f"{o.test}: {o.reason}" for o in report.outcomes)
        _fail(ctx, f"{target}: nothing was checked, every selected test was skipped ({reasons})")


@click.group(short_help="The conformance suites, on your own map or complex backend.")
def conformance() -> None:
    """Check a backend of yours against persistri's conformance suites."""


@conformance.command("maps")
@click.argument("target", metavar="MODULE:ATTR")
@click.option(
    "--max-examples",
    type=click.IntRange(min=1),
    default=100,
    show_default=True,
    help="Hypothesis examples per test.",
)
@click.option(
    "--workload-size",
    type=click.IntRange(min=0),
    default=100_000,
    show_default=True,
    help="Keys in each of the two workloads and in the growth workload (0 skips them; lower it for an "
    "O(n)-per-operation map).",
)
@click.option(
    "--hashing/--no-hashing",
    default=True,
    show_default=True,
    help="Also use keys whose hashes collide (needs keys ordered by Python's <).",
)
@_TEST_OPTION
@click.pass_context
def maps(ctx: click.Context, target: str, max_examples: int, workload_size: int, hashing: bool, tests: tuple[str, ...]) -> None:
    """Run the ORD_MAP conformance suite on the structure MODULE:ATTR.

    ATTR names an ORD_MAP structure, or a class instantiated with no arguments
    (a class also lets the suite make a second instance for the isolation test
    without copying the first); MODULE is imported with the current directory
    on the module path.  Exit status 0: it conforms; 1: some law fails (printed
    with what was seen and the operations, or hypothesis's minimal
    counterexample); 2: MODULE:ATTR is not a loadable ORD_MAP structure, or
    every test that ran was skipped (nothing was checked).
    """
    try:
        from persistri.spec.conformance import ORD_MAP_TESTS, NotAnOrdMap, as_structure, run_conformance
    except ImportError as exc:
        _fail(ctx, str(exc))
    try:
        given = load_target(target)
        as_structure(given, target)
    except (TargetError, NotAnOrdMap) as exc:
        _fail(ctx, str(exc))
    _check_tests(ctx, tests, ORD_MAP_TESTS)
    click.echo(f"persistri: running the ORD_MAP conformance suite on {target} …", err=True)
    from hypothesis.configuration import set_hypothesis_home_dir

    # Hypothesis keeps caches in ./.hypothesis; a command run anywhere should not leave one behind.
    with tempfile.TemporaryDirectory(prefix="persistri-hypothesis-") as home:
        if not os.environ.get("HYPOTHESIS_STORAGE_DIRECTORY"):
            set_hypothesis_home_dir(home)
        try:
            report = run_conformance(
                given, max_examples=max_examples, workload_size=workload_size, hashing=hashing, name=target,
                tests=tests or None,
            )
        finally:
            set_hypothesis_home_dir(None)
    _refuse_an_empty_run(ctx, target, report)
    click.echo(report.format())
    ctx.exit(0 if report.ok else 1)


def _auto_dims(structure: Any, among: Sequence[int] = range(1, 5)) -> tuple[int, ...]:
    """The dimensions ``among`` (1–4) whose ``new(n)`` the structure accepts (a structure may make one dimension only)."""
    dims = []
    for n in among:
        try:
            structure.new(n)
        except Exception:  # noqa: BLE001 - refusing new(n) means: not this dimension
            continue
        dims.append(n)
    return tuple(dims)


def _check_state(ctx: click.Context, structure: Any, state: object, state_target: str) -> None:
    """Exit 2 with one line when the structure's ``Simplex.Vertex.new`` cannot make two vertices from ``state``.

    What ``--state`` names is set-up, not the structure's behaviour: a value of another kind (a function
    returning a string, a class instead of its ``initial``) would otherwise fail every test of the suite,
    each with the same exception, and exit 1 as if laws were broken.  O(1).
    """
    from persistri.spec.conformance.simpcomp_config import vertices_from_state

    try:
        vertices_from_state(structure, state)(2)
    except Exception as exc:  # noqa: BLE001 - whatever new raises, the suite cannot make vertices from it
        detail = error_line(exc)
        _fail(
            ctx,
            f"--state {state_target}: the structure's Simplex.Vertex.new cannot make vertices from it "
            f"({type(exc).__name__}: {detail}); give a vertex state of its VERTEX structure, "
            "or a function of no arguments returning one",
        )


def _parse_dims(text: str) -> tuple[int, ...] | None:
    if text == "auto":
        return None
    try:
        dims = tuple(int(x) for x in text.split(","))
    except ValueError:
        raise click.BadParameter(f"{text!r}: give 'auto' or dimensions separated by commas (e.g. 2,3)", param_hint="--dims") from None
    if not dims or any(n < 1 for n in dims):
        raise click.BadParameter(f"{text!r}: dimensions are positive integers", param_hint="--dims")
    return dims


@conformance.command("complex")
@click.argument("target", metavar="MODULE:ATTR")
@click.option(
    "--state",
    "state_target",
    metavar="MODULE:ATTR",
    default=None,
    help="A vertex state of the structure's Simplex.Vertex, or a function of no arguments returning one "
    "(the VERTEX signature has no initial state); see the example above.",
)
@click.option("--dims", default="auto", show_default=True, help="Dimensions to test, e.g. 2,3; auto: every n in 1..4 that new(n) accepts.")
@click.option("--max-examples", type=click.IntRange(min=1), default=100, show_default=True, help="Hypothesis examples per test.")
@click.option(
    "--workload-size",
    type=click.IntRange(min=0),
    default=300,
    show_default=True,
    help="Subdivisions of a closed complex in the workload; the growth workload grows to ten times as many "
    "n-simplices (0 skips both).",
)
@click.option("--stateful-steps", type=click.IntRange(min=0), default=25, show_default=True, help="Steps per example of the stateful test (0 skips it).")
@_TEST_OPTION
@click.pass_context
def complex_(
    ctx: click.Context,
    target: str,
    state_target: str | None,
    dims: str,
    max_examples: int,
    workload_size: int,
    stateful_steps: int,
    tests: tuple[str, ...],
) -> None:
    """Run the SIMPCOMP conformance suite on the structure MODULE:ATTR.

    ATTR names a SIMPCOMP structure, or a class instantiated with no
    arguments; --state names how to make its vertices.  Exit status 0: it
    conforms; 1: some law fails (printed with its minimal counterexample);
    2: MODULE:ATTR is not a loadable SIMPCOMP structure (or no vertex state),
    or every test that ran was skipped.

    Example, persistri's own complex with its vertex states:

    \b
      persistri conformance complex \\
        persistri.impl.complex.simpcomp:SimpComp \\
        --state persistri.impl.complex.vertex:VertexState.initial
    """
    try:
        from persistri.spec.conformance import SIMPCOMP_TESTS, NotASimpComp, as_simpcomp, run_simpcomp_conformance
    except ImportError as exc:
        _fail(ctx, str(exc))
    wanted = _parse_dims(dims)
    try:
        given = load_target(target)
        structure = as_simpcomp(given, target)
    except (TargetError, NotASimpComp) as exc:
        _fail(ctx, str(exc))
    _check_tests(ctx, tests, SIMPCOMP_TESTS)
    if state_target is None:
        _fail(ctx, f"{target}: give --state MODULE:ATTR, how to make its vertices (the VERTEX signature has no initial state)")
    try:
        state = load_target(state_target)
    except TargetError as exc:
        _fail(ctx, f"--state: {exc}")
    if callable(state):  # a function of no arguments returning the state: one that cannot be called is not one
        try:
            state()
        except Exception as exc:  # noqa: BLE001 - whatever it raises, it is no vertex state
            _fail(ctx, f"--state {state_target}: calling it with no arguments failed ({type(exc).__name__}: {exc})")
    _check_state(ctx, structure, state, state_target)
    chosen = wanted if wanted is not None else _auto_dims(structure)
    if not chosen:
        _fail(ctx, f"{target} is not a SIMPCOMP structure: new(n) fails for every n in 1..4")
    refused = [n for n in chosen if n not in _auto_dims(structure, chosen)]
    if refused:
        accepted = ", ".join(map(str, _auto_dims(structure))) or "none of 1..4"
        _fail(ctx, f"--dims {dims}: {target} refuses new({refused[0]}); the dimensions it makes: {accepted}")
    click.echo(f"persistri: running the SIMPCOMP conformance suite on {target} (dims {','.join(map(str, chosen))}) …", err=True)
    from hypothesis.configuration import set_hypothesis_home_dir

    with tempfile.TemporaryDirectory(prefix="persistri-hypothesis-") as home:
        if not os.environ.get("HYPOTHESIS_STORAGE_DIRECTORY"):
            set_hypothesis_home_dir(home)
        try:
            report = run_simpcomp_conformance(
                given,
                state=state,
                dims=chosen,
                max_examples=max_examples,
                workload_size=workload_size,
                stateful_steps=stateful_steps,
                name=target,
                tests=tests or None,
            )
        finally:
            set_hypothesis_home_dir(None)
    _refuse_an_empty_run(ctx, target, report)
    click.echo(report.format())
    ctx.exit(0 if report.ok else 1)
