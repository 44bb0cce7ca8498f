"""The growth workload names the law of a spot check whose ``find`` raises, with the call that raised.

Before, an exception from ``find`` or ``data`` in the growth workload's spot checks was reported as "the
structure raised an exception outside any law", which sends the author to no law at all.
"""

from __future__ import annotations

from typing import Any

import outside_star_complex as star

from persistri.spec.conformance import run_simpcomp_conformance


class FindFailsWhenLarge(star.StarComplex):
    """Broken: ``find`` raises ``KeyError`` once the complex holds more than 40 simplices."""

    def find(self, c: star.Cx, f: Any) -> list[tuple[star.V, ...]]:
        if len(c.held) > 40:
            raise KeyError("index overflow")
        return super().find(c, f)


def test_a_find_that_raises_in_the_growth_workload_is_named_under_its_law() -> None:
    report = run_simpcomp_conformance(
        FindFailsWhenLarge(), state=star.initial_state, dims=(2,), tests=["growth"], workload_size=30,
        derandomize=True, name="find-fails",
    )
    assert len(report.failures) == 1, report.format()
    (failure,) = report.failures
    text = failure.format()
    assert failure.law == "add", text
    assert "raised KeyError" in text and "find(version" in text, text
    assert "outside any law" not in report.format()
