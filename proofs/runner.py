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
import ast
import importlib
import inspect
import io
import os
import re
import resource
import signal
import subprocess
import sys
import tempfile
import time
import tokenize
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import IO, TextIO

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

PROOFS_DIR = Path(__file__).resolve().parent
"""The ``proofs/`` directory."""

PER_CONDITION_TIMEOUT = 8.0
"""CPU seconds per postcondition for a ``crosshair_*.py`` module without a top-level budget directive.

``proofs/crosshair_maps.py`` and ``crosshair_order.py`` set their own budgets (see their module docstrings);
their sum keeps the CrossHair step near two minutes on 2 free cores, as
``make test`` requires.
"""

JOBS = 2
"""CrossHair subprocesses run at once (the machine has 2 cores)."""

CPU_FACTOR = 2.0
"""A CrossHair subprocess may use ``CPU_FACTOR × (the sum of its contracts' budgets) + 60`` CPU seconds.

CrossHair's budget is per condition and approximate (a path that is running
when the budget ends may finish first); this limit (``RLIMIT_CPU``, so the
kernel enforces it) catches a CrossHair that ignores its budget.  An overrun
is reported as a failure.
"""

WALL_FACTOR = 10.0
"""A CrossHair subprocess is killed after ``WALL_FACTOR ×`` its CPU limit of wall-clock time.

Only a hang (a process that neither computes nor ends) can reach it: on a
machine shared with other work the wall-clock time of the CrossHair step is a
multiple of its CPU time, so the wall-clock limit is generous.
"""

Proof = Callable[[], object]


@dataclass(frozen=True)
class Result:
    """The outcome of one proof or contract: its qualified name, whether it held, and why not."""

    name: str
    ok: bool
    seconds: float | None
    detail: str = ""


@dataclass(frozen=True)
class Contract:
    """A function with a PEP 316 ``post:`` contract, located by file and line span.

    ``budget`` is its CPU seconds per condition from a CrossHair directive
    (``# crosshair: per_condition_timeout=SECONDS``) inside the function, else
    from one at the top level of its module (``module_budget``); None when
    there is neither.
    """

    path: Path
    function: str
    first_line: int
    last_line: int
    budget: float | None = None
    module_budget: float | None = None

    @property
    def name(self) -> str:
        """The qualified name printed in reports: ``crosshair:module.function``."""
        return f"crosshair:{self.path.stem}.{self.function}"


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


# -- CrossHair --------------------------------------------------------------------


def discover_contracts(paths: Sequence[Path]) -> list[Contract]:
    """The top-level functions of ``paths`` whose docstring has a ``post:`` line, with their budgets.

    Read with :mod:`ast` and :mod:`tokenize`, never imported: CrossHair imports
    them in its own process.
    """
    out: list[Contract] = []
    for path in paths:
        source = path.read_text(encoding="utf-8")
        directives = _budget_directives(source)
        module_budget = next((b for line, col, b in directives if col == 0), None)
        tree = ast.parse(source, filename=str(path))
        for node in tree.body:
            if not isinstance(node, ast.FunctionDef):
                continue
            doc = ast.get_docstring(node) or ""
            if not any(line.strip().startswith("post:") for line in doc.splitlines()):
                continue
            assert node.end_lineno is not None
            own = [b for line, col, b in directives if node.lineno <= line <= node.end_lineno]
            budget = own[-1] if own else module_budget
            out.append(Contract(path.resolve(), node.name, node.lineno, node.end_lineno, budget, module_budget))
    return out


_DIRECTIVE = re.compile(r"^#\s*crosshair\s*:.*\bper_condition_timeout\s*=\s*(?P<seconds>[0-9.]+)")


def _budget_directives(source: str) -> list[tuple[int, int, float]]:
    """``(line, column, seconds)`` of every ``# crosshair: per_condition_timeout=`` comment in ``source``."""
    found = []
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type == tokenize.COMMENT:
            m = _DIRECTIVE.match(tok.string)
            if m is not None:
                found.append((tok.start[0], tok.start[1], float(m["seconds"])))
    return found


_REPORT = re.compile(r"^(?P<path>.+?):(?P<line>\d+): (?P<kind>error|warning|info): (?P<msg>.*)$")
CONFIRMED = "Confirmed over all paths."
NOT_CONFIRMED = "Not confirmed."


@dataclass
class _Batch:
    """Contracts checked by one ``crosshair check`` subprocess."""

    contracts: list[Contract]
    budgets: list[float]
    cli_timeout: float | None
    """``--per_condition_timeout`` for the command line (it overrides every directive), or None."""

    @property
    def cpu_limit(self) -> int:
        return int(CPU_FACTOR * sum(self.budgets) + 60)


def _plan(contracts: Sequence[Contract], override: float | None, jobs: int) -> list[_Batch]:
    """Split ``contracts`` into subprocesses: per module, ``jobs`` batches of about equal total budget.

    A module without a top-level budget directive is run with
    ``--per_condition_timeout`` = :data:`PER_CONDITION_TIMEOUT` (CrossHair would
    otherwise stop by iteration counts, not time); ``override`` replaces every
    budget.
    """
    groups: dict[tuple[Path, float | None], list[tuple[Contract, float]]] = {}
    for c in contracts:
        if override is not None:
            cli, budget = override, override
        elif c.module_budget is None:
            cli, budget = PER_CONDITION_TIMEOUT, PER_CONDITION_TIMEOUT
        else:
            cli, budget = None, c.budget if c.budget is not None else c.module_budget
        groups.setdefault((c.path, cli), []).append((c, budget))
    batches: list[_Batch] = []
    for (_, cli), members in groups.items():
        parts: list[_Batch] = [_Batch([], [], cli) for _ in range(min(jobs, len(members)))]
        # Longest budget first, each to the lightest batch: totals end up within one budget of each other.
        for c, budget in sorted(members, key=lambda cb: -cb[1]):
            lightest = min(parts, key=lambda b: sum(b.budgets))
            lightest.contracts.append(c)
            lightest.budgets.append(budget)
        batches.extend(parts)
    return batches


def run_crosshair(
    contracts: Sequence[Contract],
    *,
    per_condition_timeout: float | None = None,
    jobs: int = JOBS,
    python: str = sys.executable,
) -> tuple[list[Result], float, float]:
    """Check ``contracts`` with ``crosshair check`` subprocesses, at most ``jobs`` at a time.

    Each contract gets its budget (:class:`Contract`), or ``per_condition_timeout``
    CPU seconds when that is given.  Returns one :class:`Result` per contract
    (ok: CrossHair found no counterexample; the detail says whether CrossHair
    exhausted every path), the wall-clock seconds taken and the CPU seconds the
    subprocesses used.  A contract is FAILED when CrossHair reports an error for
    it (a counterexample, or an exception the contract does not allow), when
    CrossHair says nothing about it, or when its subprocess crashes or overruns.
    """
    if not contracts:
        return [], 0.0, 0.0
    pending = _plan(contracts, per_condition_timeout, max(1, jobs))
    env = dict(os.environ)
    # The contracts import persistri (installed) and may import proofs.* helpers (the repository root).
    root = str(PROOFS_DIR.parent)
    env["PYTHONPATH"] = root + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env.pop("PYTHONOPTIMIZE", None)  # the laws call the backends' assert-based _check
    start = time.perf_counter()
    cpu_before = _children_cpu()
    results: list[Result] = []
    running: list[tuple[_Batch, subprocess.Popen[bytes], float, IO[bytes], IO[bytes]]] = []
    while pending or running:
        while pending and len(running) < max(1, jobs):
            batch = pending.pop(0)
            cmd = [python, "-m", "crosshair", "check", "--analysis_kind=PEP316", "--report_all"]
            if batch.cli_timeout is not None:
                cmd.append(f"--per_condition_timeout={batch.cli_timeout:g}")
            cmd.extend(f"{c.path}:{c.first_line}" for c in batch.contracts)
            # Output goes to files, not pipes, so that a chatty CrossHair can never block on a full pipe.
            stdout_file: IO[bytes] = tempfile.TemporaryFile()
            stderr_file: IO[bytes] = tempfile.TemporaryFile()
            proc = subprocess.Popen(
                cmd, stdout=stdout_file, stderr=stderr_file, env=env, preexec_fn=_cpu_limiter(batch.cpu_limit)
            )
            running.append((batch, proc, time.perf_counter(), stdout_file, stderr_file))
        time.sleep(0.2)
        for entry in list(running):
            batch, proc, began, out, err = entry
            wall_limit = WALL_FACTOR * batch.cpu_limit
            if proc.poll() is None and time.perf_counter() - began < wall_limit:
                continue
            running.remove(entry)
            if proc.returncode is None:
                proc.kill()
                proc.wait()
                why = f"CrossHair hung: killed after {wall_limit:.0f} s of wall-clock time"
                results.extend(Result(c.name, False, None, why) for c in batch.contracts)
            elif proc.returncode in (-signal.SIGXCPU, -signal.SIGKILL):
                why = f"CrossHair overran its CPU limit of {batch.cpu_limit} s (RLIMIT_CPU) and was killed"
                results.extend(Result(c.name, False, None, why) for c in batch.contracts)
            else:
                stdout, stderr = (_read(f) for f in (out, err))
                results.extend(_judge_batch(batch.contracts, proc.returncode, stdout, stderr, batch.budgets))
            out.close()
            err.close()
    order = {c.name: i for i, c in enumerate(contracts)}
    results.sort(key=lambda r: order[r.name])
    return results, time.perf_counter() - start, _children_cpu() - cpu_before


def _read(f: IO[bytes]) -> str:
    f.seek(0)
    return f.read().decode("utf-8", errors="replace")


def _cpu_limiter(seconds: int) -> Callable[[], None]:
    """A ``preexec_fn`` that caps the child's CPU time (the kernel sends SIGXCPU, then SIGKILL)."""

    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_CPU, (seconds, seconds + 5))

    return limit


def _children_cpu() -> float:
    """CPU seconds used so far by this process's finished children."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _judge_batch(
    batch: list[Contract], returncode: int, stdout: str, stderr: str, budgets: list[float] | None = None
) -> list[Result]:
    """One result per contract of a finished CrossHair subprocess (see :func:`run_crosshair`)."""
    reports: dict[str, list[tuple[str, str]]] = {c.name: [] for c in batch}
    stray: list[str] = []
    for raw in stdout.splitlines():
        m = _REPORT.match(raw)
        owner = None
        if m is not None:
            path, line = Path(m["path"]).resolve(), int(m["line"])
            owner = next((c for c in batch if c.path == path and c.first_line <= line <= c.last_line), None)
        if m is None or owner is None:
            if raw.strip():
                stray.append(raw)
            continue
        reports[owner.name].append((m["kind"], m["msg"]))
    crashed = returncode not in (0, 1) or "Traceback (most recent call last)" in stderr
    tail = "\n".join((stderr.strip().splitlines() or [""])[-5:])
    results = []
    for i, c in enumerate(batch):
        within = "the budget" if budgets is None else f"{budgets[i]:g} CPU s"
        said = reports[c.name]
        errors = [msg for kind, msg in said if kind == "error"]
        infos = [msg for kind, msg in said if kind == "info"]
        if errors:
            results.append(Result(c.name, False, None, "counterexample: " + "; ".join(errors)))
        elif crashed:
            results.append(Result(c.name, False, None, f"CrossHair exited with status {returncode}: {tail}"))
        elif CONFIRMED in infos:
            results.append(Result(c.name, True, None, "confirmed over all paths"))
        elif NOT_CONFIRMED in infos:
            results.append(Result(c.name, True, None, f"no counterexample within {within}"))
        else:
            other = "; ".join(m for _, m in said) or "; ".join(stray) or "nothing"
            results.append(Result(c.name, False, None, f"CrossHair did not check it (it said: {other})"))
    if returncode == 1 and all(r.ok for r in results):
        # CrossHair says it found a counterexample that no contract line owns: never pass that silently.
        results = [Result(r.name, False, r.seconds, f"CrossHair exited 1: {'; '.join(stray)}") for r in results]
    return results


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
