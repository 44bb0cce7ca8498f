"""A wrong ``rem`` made while building a law's case complex is named there, not as "persistence" later.

Before, a complex whose ``rem`` leaves a stale entry (and which has no check) failed the ``add``,
``add_present``, ``rem_absent`` and ``bad_input`` tests under ``persistence`` — "the version given to
add, afterwards" — sending its author after a mutation that never happened.
"""

from __future__ import annotations

import outside_star_complex as star
import pytest

from persistri.spec.conformance import run_simpcomp_conformance

# What this checks is the conformance engine (persistri.spec), which the compiled twin does not compile:
# it runs once, on the interpreted build (tests/conftest.py, ``build_independent``).
pytestmark = pytest.mark.build_independent


def test_a_stale_rem_in_the_build_is_not_called_persistence() -> None:
    report = run_simpcomp_conformance(
        star.ForgetfulRemNoCheck(), state=star.initial_state, dims=(2,), tests=["add", "add_present", "rem_absent", "bad_input"],
        max_examples=30, workload_size=20, derandomize=True, name="forgetful",
    )
    assert len(report.failures) == 4, report.format()
    for failure in report.failures:
        assert failure.law == "agrees" and "while building the case's complex" in failure.detail, failure.format()
