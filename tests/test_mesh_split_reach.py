"""A split point's reach: the lattice search told how far from the wanted place a usable point can be.

At a small input angle a split point must be placed well (splitting.placement_tolerances); the search for a double
exactly on the segment is then given that reach and skips a dyadic fallback whose every point is farther.  These
tests check the grid test against rationals, and that every split point of the sharp gallery domains is the one the
search without a reach gives.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from persistri.impl.mesh import ruppert, splitting
from persistri.impl.mesh.api import triangulate
from persistri.impl.mesh.gallery import gallery_domain
from persistri.impl.mesh.steiner import PrecisionLimitError, _grid_within, split_parameter


@settings(max_examples=300, deadline=None)
@given(
    bound=st.integers(-3, 70),
    wanted=st.fractions(min_value=Fraction(1, 10**9), max_value=1 - Fraction(1, 10**9), max_denominator=10**30),
    reach=st.fractions(min_value=Fraction(0), max_value=Fraction(1, 2), max_denominator=10**30),
)
def test_grid_within_is_the_distance_to_the_grid(bound: int, wanted: Fraction, reach: Fraction) -> None:
    if bound < 0:
        expected = False  # no candidate's level is below 0
    else:
        step = Fraction(1, 2**bound)
        m = wanted // step
        expected = min(wanted - m * step, (m + 1) * step - wanted) <= reach
    assert _grid_within(bound, wanted, reach.as_integer_ratio()) == expected


@pytest.mark.parametrize("name,angle", [("needle", 20.0), ("needle", 30.0), ("fan", 33.0), ("fan", 30.0)])
def test_split_points_with_a_reach_are_those_without(name: str, angle: float, monkeypatch: pytest.MonkeyPatch) -> None:
    seen = 0
    skipped = 0
    original = splitting.split_point
    within = splitting.split_parameter_within

    def counting(*args: Any) -> Any:
        nonlocal skipped
        found = within(*args)
        skipped += found is None
        return found

    def both(P: Any, geo: Any, lo: int, hi: int, s: int, sides: Any, small: Any, exact: bool, tolerances: Any = None) -> Any:
        nonlocal seen
        got = original(P, geo, lo, hi, s, sides, small, exact, tolerances)
        # The same split without a reach: the plain search, then the placement test and the rounding, as before.
        with monkeypatch.context() as m:
            m.setattr(splitting, "split_parameter_within", lambda P, a, b, u, w, tu, tw, wanted, reach: _plain(P, a, b, u, w, tu, tw, wanted))
            plain = original(P, geo, lo, hi, s, sides, small, exact, tolerances)
        assert got == plain
        seen += 1
        return got

    monkeypatch.setattr(splitting, "split_parameter_within", counting)
    monkeypatch.setattr(ruppert, "split_point", both)
    m = triangulate(gallery_domain(name).pslg, min_angle=angle)
    assert seen == m.segment_splits > 0
    assert skipped > 0  # the reach did skip searches here


def _plain(P: Any, a: int, b: int, u: int, w: int, tu: Fraction, tw: Fraction, wanted: Fraction) -> Any:
    try:
        return split_parameter(P, a, b, u, w, tu, tw, wanted)
    except PrecisionLimitError:
        return None
