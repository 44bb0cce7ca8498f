"""The CrossHair step of ``python -m proofs``: contracts found, batched, checked and judged.

Every top-level function of ``proofs/crosshair_*.py`` whose docstring has a
PEP 316 ``post:`` line is a :class:`Contract`.  :func:`discover_contracts` finds
them by reading the source (never importing it: CrossHair imports it in its own
process), with the CPU budget per condition that CrossHair's own directive
``# crosshair: per_condition_timeout=SECONDS`` sets inside the function or at the
top level of its module (:data:`PER_CONDITION_TIMEOUT` when there is neither).
:func:`run_crosshair` runs ``crosshair check --analysis_kind=PEP316 --report_all``
as subprocesses, at most ``jobs`` at a time, each under a CPU limit
(:data:`CPU_FACTOR`) and a wall-clock limit against hangs (:data:`WALL_FACTOR`),
and judges each contract from CrossHair's report: a counterexample, an error, a
contract CrossHair did not report on, a crash or an overrun is a failure.
"""

from __future__ import annotations

import ast
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
from typing import IO

from proofs.result import PROOFS_DIR, Result

__all__ = [
    "PER_CONDITION_TIMEOUT",
    "JOBS",
    "CPU_FACTOR",
    "WALL_FACTOR",
    "CONFIRMED",
    "NOT_CONFIRMED",
    "Contract",
    "discover_contracts",
    "run_crosshair",
]

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
