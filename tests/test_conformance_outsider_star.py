"""docs/conformance.md followed literally for a simplicial complex written from scratch (``outside_star_complex``).

The guide's three front ends on one correct complex (the pytest base class, the command and
``run_simpcomp_conformance``), and a broken one — ``rem`` forgets the simplex in one vertex's
star — caught with the law named: by its own ``check`` (invariants) and, without one, by the laws.
"""

from __future__ import annotations

import outside_star_complex as star
import pytest
from cli_contract import invoke

from persistri.spec.conformance import SimpCompConformance, missing_simpcomp_operations, run_simpcomp_conformance

# What these tests check is the conformance engine (persistri.spec), which the compiled twin does not
# compile: they run once, on the interpreted build (tests/conftest.py, ``build_independent``).
pytestmark = pytest.mark.build_independent

SMALL = {"max_examples": 10, "workload_size": 20, "stateful_steps": 6, "derandomize": True}


class TestStarComplex(SimpCompConformance):
    """The guide's pytest example, as written there (a smaller workload: the complex copies on every update)."""

    structure = star.star_complex
    state = star.initial_state
    dims = (2, 3)
    workload_size = 20
    stateful_steps = 6
    max_examples = 10


def test_it_has_every_operation() -> None:
    assert missing_simpcomp_operations(star.star_complex) == []


def test_the_command_says_it_conforms() -> None:
    result, _ = invoke(["conformance", "complex", "outside_star_complex:star_complex", "--state", "outside_star_complex:initial_state",
                        "--dims", "2", "--max-examples", "10", "--workload-size", "20", "--stateful-steps", "6"])
    assert result.exit_code == 0, result.output
    assert "outside_star_complex:star_complex conforms to SIMPCOMP: 21 passed, 0 failed, 0 skipped" in result.output


@pytest.mark.parametrize(("structure", "laws"), [(star.ForgetfulRem(), {"invariants", "rem"}), (star.ForgetfulRemNoCheck(), {"rem"})])
def test_a_forgotten_star_entry_is_caught_by_name(structure: object, laws: set[str]) -> None:
    report = run_simpcomp_conformance(structure, state=star.initial_state, dims=(2,), tests=["rem", "stateful_history", "invariants"],
                                      name="forgetful", **SMALL)
    assert not report.ok
    failed = {f.test: f for f in report.failures}
    assert failed["rem"].law == "rem" and "vertices(c) = [" in failed["rem"].detail, failed["rem"].format()
    assert set(report.failed_laws) <= laws | {"persistence"} and laws <= set(report.failed_laws), report.format()
    text = report.format()
    assert "FAILED rem — law rem: rem(c, s) of a held n-simplex" in text, text


def test_the_command_names_the_law_and_exits_1() -> None:
    result, _ = invoke(["conformance", "complex", "outside_star_complex:forgetful_nocheck", "--state", "outside_star_complex:initial_state",
                        "--dims", "2", "--max-examples", "10", "--workload-size", "20", "--test", "rem"])
    assert result.exit_code == 1, result.output
    assert "does NOT conform to SIMPCOMP" in result.output and "FAILED rem — law rem:" in result.output, result.output
