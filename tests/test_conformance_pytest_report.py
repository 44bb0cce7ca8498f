"""Under pytest, with the user's own hypothesis profile, a failing conformance test names its law.

A user's profile usually keeps hypothesis's ``report_multiple_bugs`` on; a broken complex can then fail
one test with two distinct errors, which hypothesis raises together as an ``ExceptionGroup`` whose first
line names no law (docs/conformance.md promises the law as the assertion message).  The suite's tests
report the first failure alone, whatever the profile.
"""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest
from hypothesis import settings

# What these tests check is the conformance engine (persistri.spec), which the compiled twin does not
# compile: they run once, on the interpreted build (tests/conftest.py, ``build_independent``).
pytestmark = pytest.mark.build_independent

settings.register_profile("conformance-user-default", max_examples=60, database=None, derandomize=True)


class _Failures:
    """A pytest plugin keeping the text of every failed test's report."""

    def __init__(self) -> None:
        self.texts: dict[str, str] = {}

    def pytest_runtest_logreport(self, report: pytest.TestReport) -> None:
        if report.failed:
            self.texts[report.nodeid.split("::", 1)[1]] = report.longreprtext


def test_a_forgetful_rem_fails_under_its_law_not_as_an_exception_group(tmp_path: Path) -> None:
    (tmp_path / "pytest.ini").write_text("[pytest]\n")
    (tmp_path / "test_outsider_complex_report.py").write_text(
        textwrap.dedent(
            """
            import outside_star_complex as star
            from persistri.spec.conformance import SimpCompConformance

            class TestForgetful(SimpCompConformance):
                structure = star.ForgetfulRemNoCheck
                state = star.initial_state
                dims = (2,)
                workload_size = 30
            """
        )
    )
    failures = _Failures()
    code = pytest.main(
        [str(tmp_path / "test_outsider_complex_report.py"), "-c", str(tmp_path / "pytest.ini"), "--rootdir", str(tmp_path),
         "-p", "no:cacheprovider", "--hypothesis-profile=conformance-user-default", "--import-mode=importlib",
         "-q", "-k", "test_rem or test_update"],
        plugins=[failures],
    )
    assert code == pytest.ExitCode.TESTS_FAILED
    assert failures.texts, "the forgetful rem passed"
    for name, text in failures.texts.items():
        assert "ExceptionGroup" not in text and "distinct failures" not in text, f"{name}:\n{text[-2000:]}"
        assert "law " in text, f"{name} names no law:\n{text[-2000:]}"
