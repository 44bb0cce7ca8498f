"""CrossHair, as the proofs runner drives it, really catches broken laws.

The runner's CrossHair step (:func:`proofs.contracts.run_crosshair`) is run on
``tests/crosshair_fixtures/broken_laws.py``: three deliberately false contracts
(a false property of ``compare``; the ``remove`` laws on an association list
whose ``remove`` keeps the old count; the ``_check`` invariant on one that
inserts new keys unsorted) must each be reported as a counterexample, and the
true control contract in the same run must pass.  CrossHair stops at the first
counterexample of a condition, so this takes seconds, not the budget.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from proofs.contracts import discover_contracts, run_crosshair  # noqa: E402

FIXTURE = Path(__file__).resolve().parent / "crosshair_fixtures" / "broken_laws.py"


def test_crosshair_reports_each_false_contract_and_passes_the_true_one() -> None:
    contracts = discover_contracts([FIXTURE])
    names = sorted(c.function for c in contracts)
    assert names == [
        "false_compare_never_equal",
        "false_front_insert_invariant",
        "false_leaky_remove",
        "true_compare_antisymmetric",
    ]
    results, _, _ = run_crosshair(contracts, per_condition_timeout=20, jobs=2)
    by_name = {r.name.rsplit(".", 1)[1]: r for r in results}
    assert set(by_name) == set(names)
    for name in names:
        r = by_name[name]
        if name.startswith("false_"):
            assert not r.ok, f"CrossHair missed the broken law {name}: {r.detail}"
            assert r.detail.startswith("counterexample: "), r.detail
            assert f"when calling {name}(" in r.detail, r.detail
        else:
            assert r.ok, f"the true control contract failed: {r.detail}"
    assert "LawRaised: AssertionError: assoc_list: keys out of order" in by_name["false_front_insert_invariant"].detail
