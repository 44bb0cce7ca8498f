"""The conformance suite rejects each deliberately broken map of :mod:`broken_maps`, naming the right law.

Three front ends are checked: the programmatic runner (:func:`run_conformance`),
the pytest base class called directly, and the base class collected and run by
pytest itself (in-process, on a generated test file).  The association list,
which conforms, is run through the same selections so that a rejection cannot
come from the selection itself.
"""

from __future__ import annotations

import os
import textwrap
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from hypothesis import Phase, settings

from broken_maps import BROKEN, absent_remove, iterator_listing
from persistri.impl.maps.assoc_list import assoc_list
from persistri.spec.conformance import ORD_MAP_TESTS, NotAnOrdMap, OrdMapConformance, run_conformance
from persistri.spec.ord_map_laws import ORD_MAP_LAWS, LawViolation

# What these tests check is the conformance engine (persistri.spec), which the compiled twin does not
# compile: they run once, on the interpreted build (tests/conftest.py, ``build_independent``).
pytestmark = pytest.mark.build_independent

# Laws a history may legitimately find broken first: the miscounting map's insertWith
# miscounts as its insert does, and the insertWith law checks the count too.
ALSO = {"miscounting": {"insertWith"}}

# The base class runs under the active profile.  Here every run *fails*, so the profile's
# failure-time work (the explain phase, shrinking several distinct bugs) dominates; these
# tests load a profile derived from the active one without it.
_ACTIVE = os.environ.get("HYPOTHESIS_PROFILE", "dev")
settings.register_profile(
    "conformance-rejects",
    parent=settings.get_profile(_ACTIVE),
    max_examples=25,
    phases=[p for p in Phase if p is not Phase.explain],
    report_multiple_bugs=False,
    database=None,
    derandomize=True,
)


@pytest.fixture
def rejects_profile() -> Iterator[None]:
    settings.load_profile("conformance-rejects")
    try:
        yield
    finally:
        settings.load_profile(_ACTIVE)


@pytest.mark.parametrize("name", sorted(BROKEN))
def test_runner_names_the_broken_law(name: str) -> None:
    structure, law = BROKEN[name]
    tests = (law, "stateful_history")  # the test named after the law, and the stateful history test
    report = run_conformance(structure, max_examples=30, workload_size=200, name=name, tests=tests, derandomize=True)
    assert not report.ok
    assert "does NOT conform to ORD_MAP" in report.summary()
    by_test = {f.test: f for f in report.failures}
    # The test of that law fails under that law, with hypothesis's minimal example ...
    failure = by_test[law]
    assert failure.law == law and failure.statement == ORD_MAP_LAWS[law]
    assert failure.detail and f"{law}(" in failure.example
    # ... and the stateful history test finds the same defect by itself.
    stateful = by_test["stateful_history"]
    assert stateful.law in {law, *ALSO.get(name, ())}, stateful.format()
    assert "state = OrdMapHistory()" in stateful.example
    # The full text an outsider reads carries law, statement and counterexample.
    text = report.format()
    assert f"law {law}: {ORD_MAP_LAWS[law]}" in text and "counterexample:" in text


def test_the_same_selection_passes_on_a_conforming_map() -> None:
    tests = ("persistence", "remove", "numItems_insert", "invariants", "stateful_history")
    report = run_conformance(assoc_list, max_examples=30, workload_size=200, tests=tests, derandomize=True)
    assert report.ok, report.format()
    assert report.count("passed") == len(tests)


def test_full_run_on_a_mutating_map_blames_persistence_only() -> None:
    structure, law = BROKEN["mutating"]
    report = run_conformance(structure, max_examples=20, workload_size=200, derandomize=True)
    assert report.failed_laws == {"persistence"}, report.format()
    assert [o.test for o in report.outcomes] == [t.name for t in ORD_MAP_TESTS]
    assert report.count("skipped") == 1  # no _check
    assert {f.test for f in report.failures} >= {"persistence", "stateful_history", "find_insert"}


def test_the_same_wrong_answer_printed_with_addresses_is_not_hidden_state() -> None:
    # absent_remove answers remove of an absent key with a map (whose repr names its address) every time: the
    # session replays of `determinism` see the same answers, and every test that fails names remove_absent.
    tests = ("determinism", "remove_absent", "edge_empty_map", "edge_remove_absent", "persistence")
    report = run_conformance(absent_remove, max_examples=30, workload_size=200, tests=tests, derandomize=True)
    outcomes = {o.test: o for o in report.outcomes}
    assert outcomes["determinism"].status == "passed", report.format()
    failed = {f.test: f.law for f in report.failures}
    assert failed == {t: "remove_absent" for t in tests[1:]}, report.format()
    assert "0x" in report.failures[0].detail  # the address is shown, as the structure printed it


def test_a_listing_that_reads_once_is_named_by_the_listItemsi_law_not_determinism() -> None:
    report = run_conformance(iterator_listing, max_examples=30, workload_size=200, tests=("listItemsi", "determinism"), derandomize=True)
    assert report.failed_laws == {"listItemsi"}, report.format()
    assert "returned a list_iterator, not a list" in report.failures[0].detail


def test_runner_rejects_non_structures_and_bad_options() -> None:
    with pytest.raises(NotAnOrdMap, match="missing .*remove"):
        run_conformance({})
    with pytest.raises(ValueError, match="max_examples"):
        run_conformance(assoc_list, max_examples=0)
    with pytest.raises(ValueError, match="workload_size"):
        run_conformance(assoc_list, workload_size=-1)
    with pytest.raises(ValueError, match="unknown conformance tests"):
        run_conformance(assoc_list, tests=["no_such_test"])


def _suite_class(structure: Any) -> type[OrdMapConformance]:
    return type("TestBroken", (OrdMapConformance,), {"structure": structure, "workload_size": 200})


@pytest.mark.usefixtures("rejects_profile")
@pytest.mark.parametrize("name", sorted(BROKEN))
def test_base_class_methods_fail_with_the_law(name: str) -> None:
    structure, law = BROKEN[name]
    with pytest.raises(LawViolation) as info:
        getattr(_suite_class(structure)(), f"test_{law}")()
    assert info.value.law == law, str(info.value)


def test_base_class_without_structure_says_so() -> None:
    with pytest.raises(TypeError, match="set `structure = "):
        OrdMapConformance().test_empty()
    with pytest.raises(NotAnOrdMap, match="TestBroken.structure is not an ORD_MAP structure: missing"):
        _suite_class(dict)().test_empty()


class _Collect:
    """A pytest plugin recording the outcome of every test's call phase."""

    def __init__(self) -> None:
        self.outcomes: dict[str, str] = {}

    def pytest_runtest_logreport(self, report: pytest.TestReport) -> None:
        if report.when == "call" or report.outcome != "passed":
            self.outcomes[report.nodeid.split("::", 1)[1]] = report.outcome


@pytest.mark.usefixtures("rejects_profile")
def test_pytest_collects_the_base_class_and_fails_the_broken_map(tmp_path: Path) -> None:
    (tmp_path / "pytest.ini").write_text("[pytest]\n")
    (tmp_path / "test_outsider.py").write_text(
        textwrap.dedent(
            """
            from broken_maps import lossy_remove
            from persistri.impl.maps.assoc_list import assoc_list
            from persistri.spec.conformance import OrdMapConformance

            class TestGood(OrdMapConformance):
                structure = assoc_list
                workload_size = 200

            class TestLossy(OrdMapConformance):
                structure = lossy_remove
                workload_size = 200
            """
        )
    )
    collect = _Collect()
    code = pytest.main(
        [
            str(tmp_path / "test_outsider.py"),
            "-c",
            str(tmp_path / "pytest.ini"),
            "--rootdir",
            str(tmp_path),
            "-p",
            "no:cacheprovider",
            "--hypothesis-profile=conformance-rejects",
            "--import-mode=importlib",
            "-q",
            "-k",
            "(test_remove and not absent) or test_edge_remove_last_key or test_empty",
        ],
        plugins=[collect],
    )
    assert code == pytest.ExitCode.TESTS_FAILED
    assert collect.outcomes == {
        "TestGood::test_empty": "passed",
        "TestGood::test_remove": "passed",
        "TestGood::test_edge_remove_last_key": "passed",
        "TestLossy::test_empty": "passed",
        "TestLossy::test_remove": "failed",
        "TestLossy::test_edge_remove_last_key": "failed",
    }
