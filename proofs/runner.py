"""The proofs runner: every ``proof_*`` function, then the CrossHair contract checks.

``python -m proofs`` (from the repository root; ``make test`` runs it) does two things.

1. **Proofs.**  It imports every module ``proofs/proof_*.py`` (sorted by name) and
   calls every function ``proof_*`` defined there, in source order.  A proof takes
   no arguments, has a docstring stating what it proves, raises
   :class:`AssertionError` (with a message) when its identity fails and returns
   ``None`` when it holds.  A proof that raises anything else, returns anything
   but ``None``, needs arguments or has no docstring is reported as FAILED, and
   so is a module that cannot be imported.
2. **CrossHair.**  It runs ``crosshair check --analysis_kind=PEP316 --report_all``
   as subprocesses (``--crosshair-jobs`` at a time, default 2) on every function
   with a ``post:`` contract in ``proofs/crosshair_*.py``.  Each contract has a
   CPU budget per condition, set in the source by CrossHair's own directive
   ``# crosshair: per_condition_timeout=SECONDS`` (in the function, else at the
   top level of the module; :data:`PER_CONDITION_TIMEOUT` for a module without
   one); ``--crosshair-timeout`` overrides them all.  Each subprocess also has
   a CPU-time limit and a generous wall-clock limit against hangs.  A
   counterexample, an error, a function CrossHair did not report on, a
   CrossHair crash or an overrun is a failure.

One line is printed per proof or checked contract (name, ok/FAILED, seconds),
then a summary; the exit status is 1 when anything failed.  ``--only SUBSTRING``
keeps the proofs and contracts whose qualified name contains ``SUBSTRING``;
``--no-crosshair`` skips step 2; ``--list`` prints what would run.  The runner
refuses to run under ``python -O``, which would strip the proofs' ``assert``
statements and let every proof pass.
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TextIO

from proofs.contracts import JOBS, PER_CONDITION_TIMEOUT, Contract, discover_contracts, run_crosshair
from proofs.result import PROOFS_DIR, Result

__all__ = [
    "PROOFS_DIR",
    "PER_CONDITION_TIMEOUT",
    "Result",
    "Contract",
    "discover_proofs",
    "run_proof",
    "discover_contracts",
    "run_crosshair",
    "main",
]

Proof = Callable[[], object]


# -- proofs -----------------------------------------------------------------------


def discover_proofs(directory: Path = PROOFS_DIR) -> tuple[list[tuple[str, Proof]], list[Result]]:
    """The ``proof_*`` functions of ``directory/proof_*.py``, and a FAILED result per module that did not import.

    ``directory`` is imported as a package named after it (its parent is put on
    ``sys.path`` if needed).  Functions are listed module by module (sorted by
    file name), each module's in source order; a name is ``module.function``.
    """
    package = directory.name
    parent = str(directory.parent)
    if parent not in sys.path:
        sys.path.insert(0, parent)
    found: list[tuple[str, Proof]] = []
    failed: list[Result] = []
    for path in sorted(directory.glob("proof_*.py")):
        qual = f"{package}.{path.stem}"
        start = time.perf_counter()
        try:
            module = importlib.import_module(qual)
        except Exception as exc:  # a module that does not import is a failed proof, not a crash
            failed.append(Result(path.stem, False, time.perf_counter() - start, f"import failed: {_describe(exc)}"))
            continue
        functions = [
            obj
            for name, obj in vars(module).items()
            if name.startswith("proof_") and inspect.isfunction(obj) and obj.__module__ == module.__name__
        ]
        functions.sort(key=lambda f: f.__code__.co_firstlineno)
        found.extend((f"{path.stem}.{f.__name__}", f) for f in functions)
    return found, failed


def run_proof(name: str, proof: Proof) -> Result:
    """Call ``proof()``; ok when it returns ``None`` (see the module docstring for what fails)."""
    if not (proof.__doc__ or "").strip():
        return Result(name, False, None, "no docstring: a proof states what it proves")
    required = [
        p.name
        for p in inspect.signature(proof).parameters.values()
        if p.default is p.empty and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)
    ]
    if required:
        return Result(name, False, None, f"takes arguments {required}: a proof takes none")
    start = time.perf_counter()
    try:
        value = proof()
    except AssertionError as exc:
        return Result(name, False, time.perf_counter() - start, f"identity fails: {exc}" if str(exc) else "identity fails")
    except Exception as exc:  # any other exception is a broken proof, reported the same way
        return Result(name, False, time.perf_counter() - start, f"raised {_describe(exc)}")
    seconds = time.perf_counter() - start
    if value is not None:
        return Result(name, False, seconds, f"returned {value!r}; a proof returns None or raises AssertionError")
    return Result(name, True, seconds)


def _describe(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {exc}" if str(exc) else type(exc).__name__


# -- the command --------------------------------------------------------------------


def _line(result: Result, out: TextIO) -> None:
    secs = "       -" if result.seconds is None else f"{result.seconds:7.2f}s"
    status = "ok" if result.ok else "FAILED"
    note = f"  ({result.detail})" if result.ok and result.detail else ""
    print(f"{result.name:<62} {status:>6} {secs}{note}", file=out)
    if not result.ok and result.detail:
        for text in result.detail.splitlines():
            print(f"    {text}", file=out)
    out.flush()


def main(argv: Sequence[str] | None = None, *, directory: Path = PROOFS_DIR, out: TextIO | None = None) -> int:
    """Run the proofs and the CrossHair checks of ``directory``; 0 when everything held."""
    out = sys.stdout if out is None else out
    parser = argparse.ArgumentParser(
        prog="python -m proofs", description="Run the proofs in proofs/proof_*.py, then the CrossHair contracts."
    )
    parser.add_argument("--only", metavar="SUBSTRING", help="run only proofs/contracts whose name contains SUBSTRING")
    parser.add_argument("--no-crosshair", action="store_true", help="skip the CrossHair contract checks")
    parser.add_argument(
        "--crosshair-timeout",
        type=float,
        default=None,
        metavar="SECONDS",
        help="CPU seconds per CrossHair condition for every contract, overriding the budgets in the source "
        "(default: each contract's '# crosshair: per_condition_timeout=' directive)",
    )
    parser.add_argument("--crosshair-jobs", type=int, default=JOBS, metavar="N", help=f"CrossHair subprocesses (default {JOBS})")
    parser.add_argument("--list", action="store_true", help="list the proofs and contracts, run nothing")
    args = parser.parse_args(argv)
    if not __debug__:
        print("python -O strips assert statements, so no proof could fail: run without -O", file=out)
        return 2
    if args.crosshair_jobs < 1 or (args.crosshair_timeout is not None and args.crosshair_timeout <= 0):
        parser.error("--crosshair-jobs must be ≥ 1 and --crosshair-timeout > 0")

    proofs, import_failures = discover_proofs(directory)
    contracts = [] if args.no_crosshair else discover_contracts(sorted(directory.glob("crosshair_*.py")))
    if args.only is not None:
        proofs = [(n, f) for n, f in proofs if args.only in n]
        import_failures = [r for r in import_failures if args.only in r.name]
        contracts = [c for c in contracts if args.only in c.name]
        if not (proofs or import_failures or contracts):
            print(f"no proof or contract matches --only {args.only!r}", file=out)
            return 1
    if args.list:
        for name, _ in proofs:
            print(name, file=out)
        for r in import_failures:
            print(f"{r.name} (does not import)", file=out)
        for c in contracts:
            print(c.name, file=out)
        return 0

    results = list(import_failures)
    for r in import_failures:
        _line(r, out)
    for name, proof in proofs:
        r = run_proof(name, proof)
        _line(r, out)
        results.append(r)
    n_proofs = len(results)
    if not proofs and not import_failures and args.only is None:
        print(f"(no proof_*.py module with proofs in {directory})", file=out)

    ch_seconds = ch_cpu = 0.0
    if contracts:
        print(
            f"crosshair: {len(contracts)} contracts, "
            + (
                f"{args.crosshair_timeout:g} CPU s per condition"
                if args.crosshair_timeout is not None
                else "the budgets of their directives"
            )
            + f", {args.crosshair_jobs} process(es) at a time …",
            file=out,
            flush=True,
        )
        ch_results, ch_seconds, ch_cpu = run_crosshair(
            contracts, per_condition_timeout=args.crosshair_timeout, jobs=args.crosshair_jobs
        )
        for r in ch_results:
            _line(r, out)
        results.extend(ch_results)

    failed = [r for r in results if not r.ok]
    ch = results[n_proofs:]
    confirmed = sum(1 for r in ch if r.ok and r.detail == "confirmed over all paths")
    crosshair = (
        "skipped (--no-crosshair)"
        if args.no_crosshair
        else f"{sum(1 for r in ch if r.ok)}/{len(ch)} ok ({confirmed} confirmed over all paths) "
        f"in {ch_seconds:.0f} s ({ch_cpu:.0f} CPU s)"
    )
    print(
        f"proofs: {n_proofs - sum(1 for r in results[:n_proofs] if not r.ok)}/{n_proofs} ok; crosshair: {crosshair}"
        + ("" if not failed else f"; FAILED: {', '.join(r.name for r in failed)}"),
        file=out,
    )
    return 1 if failed else 0
