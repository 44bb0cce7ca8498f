"""The proofs runner (``python -m proofs``) reports failing proofs as FAILED and passing ones as ok.

A temporary package of proof modules stands in for ``proofs/``: it holds a
proof that holds, one whose identity fails, and the ways a proof can be
malformed (no docstring, arguments, a return value, another exception), plus a
module that does not import.  The CrossHair report parser is checked on
synthetic CrossHair output (the subprocess itself is exercised by
``tests/test_crosshair_catches.py``).
"""

from __future__ import annotations

import io
import itertools
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from proofs import contracts as crosshair_step  # noqa: E402
from proofs import runner  # noqa: E402

_fresh = itertools.count()

PROOFS = '''
"""Proofs for the runner's test."""

from fake_helpers import proof_imported  # noqa: F401  (defined elsewhere: must not run here)


def proof_holds():
    """1 + 1 == 2."""
    assert 1 + 1 == 2


def proof_fails():
    """A false identity."""
    assert 1 + 1 == 3, "1 + 1 is 2, not 3"


def proof_returns_false():
    """Returns False instead of raising."""
    return False


def proof_no_doc():
    assert True


def proof_needs_argument(x):
    """Takes an argument."""


def proof_divides_by_zero():
    """Raises something other than AssertionError."""
    1 / 0


def helper_not_a_proof():
    raise AssertionError("helpers are not run")
'''


def _package(tmp_path: Path, *, broken: bool = True) -> Path:
    """A fresh proofs package (a new name each time, so imports never collide)."""
    d = tmp_path / f"fakeproofs_{next(_fresh)}"
    d.mkdir()
    (d / "__init__.py").write_text("")
    (d / "proof_alpha.py").write_text(textwrap.dedent(PROOFS))
    (tmp_path / "fake_helpers.py").write_text('def proof_imported():\n    """Imported."""\n    raise AssertionError\n')
    if broken:
        (d / "proof_beta.py").write_text("raise ImportError('beta needs a missing package')\n")
    return d


def _run(d: Path, *argv: str) -> tuple[int, str]:
    out = io.StringIO()
    status = runner.main(["--no-crosshair", *argv], directory=d, out=out)
    return status, out.getvalue()


def _status_of(output: str, name: str) -> str:
    lines = [line for line in output.splitlines() if line.split() and line.split()[0] == name]
    assert len(lines) == 1, (name, output)
    return lines[0].split()[1]


def test_failing_and_malformed_proofs_are_failures(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.syspath_prepend(str(tmp_path))
    status, output = _run(_package(tmp_path))
    assert status == 1
    assert _status_of(output, "proof_alpha.proof_holds") == "ok"
    for name in (
        "proof_alpha.proof_fails",
        "proof_alpha.proof_returns_false",
        "proof_alpha.proof_no_doc",
        "proof_alpha.proof_needs_argument",
        "proof_alpha.proof_divides_by_zero",
        "proof_beta",
    ):
        assert _status_of(output, name) == "FAILED", (name, output)
    assert "identity fails: 1 + 1 is 2, not 3" in output
    assert "returned False" in output
    assert "no docstring" in output
    assert "takes arguments ['x']" in output
    assert "raised ZeroDivisionError" in output
    assert "import failed: ImportError: beta needs a missing package" in output
    assert "proof_imported" not in output and "helper_not_a_proof" not in output
    assert "proofs: 1/7 ok" in output


def test_passing_proofs_are_ok(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.syspath_prepend(str(tmp_path))
    d = _package(tmp_path, broken=False)
    status, output = _run(d, "--only", "proof_holds")
    assert status == 0, output
    assert _status_of(output, "proof_alpha.proof_holds") == "ok"
    assert "proof_fails" not in output
    assert "proofs: 1/1 ok" in output


def test_only_matching_nothing_fails(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.syspath_prepend(str(tmp_path))
    status, output = _run(_package(tmp_path, broken=False), "--only", "no_such_proof")
    assert status == 1
    assert "no proof or contract matches" in output


def test_run_proof_directly() -> None:
    def proof_ok() -> None:
        """Holds."""

    def proof_bad() -> None:
        """Fails."""
        raise AssertionError("no")

    ok, bad = runner.run_proof("ok", proof_ok), runner.run_proof("bad", proof_bad)
    assert ok.ok and ok.seconds is not None
    assert not bad.ok and bad.detail == "identity fails: no"


# -- the CrossHair report parser ---------------------------------------------------

_CONTRACTS = '''
def law_a(x: int) -> bool:
    """
    post: __return__
    """
    return True


def law_b(x: int) -> bool:
    """
    pre: x > 0
    post: __return__
    """
    return x > 0


def helper(x: int) -> bool:
    """No contract: not a target."""
    return True
'''


def _contracts(tmp_path: Path) -> tuple[Path, list[runner.Contract]]:
    path = tmp_path / "crosshair_fake.py"
    path.write_text(_CONTRACTS)
    contracts = runner.discover_contracts([path])
    assert [c.function for c in contracts] == ["law_a", "law_b"]
    return path, contracts


def test_crosshair_reports_are_judged(tmp_path: Path) -> None:
    path, contracts = _contracts(tmp_path)
    a, b = contracts
    post_a, post_b = a.first_line + 3, b.first_line + 4
    # A counterexample for law_b, and law_a not confirmed within the budget.
    out = f"{path}:{post_a}: info: Not confirmed.\n{path}:{post_b}: error: false when calling law_b(1)\n"
    ra, rb = crosshair_step._judge_batch(contracts, 1, out, "")
    assert ra.ok and ra.detail == "no counterexample within the budget"
    assert not rb.ok and rb.detail == "counterexample: false when calling law_b(1)"
    # Confirmed over all paths.
    out = f"{path}:{post_a}: info: Confirmed over all paths.\n{path}:{post_b}: info: Confirmed over all paths.\n"
    assert all(r.ok and r.detail == "confirmed over all paths" for r in crosshair_step._judge_batch(contracts, 0, out, ""))
    # A contract CrossHair says nothing about is not checked: a failure.
    ra, rb = crosshair_step._judge_batch(contracts, 0, f"{path}:{post_a}: info: Not confirmed.\n", "")
    assert ra.ok and not rb.ok and "did not check it" in rb.detail
    # A CrossHair crash fails every contract it did not refute.
    crash = "Traceback (most recent call last):\n  ...\ncrosshair.util.CrossHairInternal: boom\n"
    results = crosshair_step._judge_batch(contracts, 2, f"{path}:{post_a}: info: Not confirmed.\n", crash)
    assert not any(r.ok for r in results) and "CrossHairInternal: boom" in results[0].detail
    # Exit status 1 with no error line that a contract owns is never passed silently.
    out = f"{path}:{post_a}: info: Not confirmed.\n{path}:{post_b}: info: Not confirmed.\nelsewhere.py:3: error: boom\n"
    assert not any(r.ok for r in crosshair_step._judge_batch(contracts, 1, out, ""))


_BUDGETED = '''
# crosshair: per_condition_timeout=3


def cheap(x: int) -> bool:
    """
    post: __return__
    """
    return True


def dear(x: int) -> bool:
    """
    post: __return__
    """
    # crosshair: per_condition_timeout=12
    return True
'''


def test_budgets_come_from_crosshair_directives(tmp_path: Path) -> None:
    budgeted = tmp_path / "crosshair_budgeted.py"
    budgeted.write_text(_BUDGETED)
    plain_path, plain = _contracts(tmp_path)
    cheap, dear = runner.discover_contracts([budgeted])
    assert (cheap.budget, cheap.module_budget) == (3.0, 3.0)
    assert (dear.budget, dear.module_budget) == (12.0, 3.0)
    assert all(c.budget is None and c.module_budget is None for c in plain)

    # Directives are honoured (no command-line timeout); a module without one gets the default on the command line.
    batches = crosshair_step._plan([cheap, dear, *plain], None, 2)
    by_path = {b.contracts[0].path: b for b in batches if len(b.contracts) == 1 and b.contracts[0] is dear}
    assert by_path[budgeted.resolve()].cli_timeout is None and by_path[budgeted.resolve()].budgets == [12.0]
    plain_batches = [b for b in batches if b.contracts[0].path == plain_path.resolve()]
    assert all(b.cli_timeout == runner.PER_CONDITION_TIMEOUT for b in plain_batches)
    assert sorted(c.function for b in batches for c in b.contracts) == ["cheap", "dear", "law_a", "law_b"]
    # An explicit timeout overrides every directive.
    assert all(b.cli_timeout == 5.0 and set(b.budgets) == {5.0} for b in crosshair_step._plan([cheap, dear], 5.0, 2))
    # One job: one batch per module, holding all of its contracts.
    assert [len(b.contracts) for b in crosshair_step._plan([cheap, dear], None, 1)] == [2]
