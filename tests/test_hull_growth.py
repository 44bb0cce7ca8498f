"""The bulldozer's operation counts grow as n lg n (paper §3, Theorem 11; issue 4 item 9).

Counts are machine-independent and deterministic (fixed points, fixed seed),
so these are exact statements about one run per size, not timings.

* **OnSphere** (every point on the hull: the expensive case the theory is
  tight for): key comparisons and plane-side tests, each divided by
  ``n · log2 n``, stay within 20% of each other from 2^12 to 2^16 points.
* **InBall**: O(n lg n) is an upper bound, and it is not tight here — most
  points are discarded as interior after a bounded number of tests, and the
  hull (hence the complex work) has only O(n^(1/3)) vertices.  So the test
  asserts what holds: divided by ``n · log2 n`` neither count grows (each stays
  at most 20% above its value at 2^12), and the plane-side tests divided by
  ``n`` are stable within 20% (the actual, linear growth).
"""

from __future__ import annotations

import math

import pytest

from persistri.impl.hull.api import convex_hull
from persistri.impl.hull.distributions import generate
from persistri.impl.stats import Stats

EXPONENTS = (12, 14, 16)


def _counts(dist: str) -> dict[int, Stats]:
    out = {}
    for k in EXPONENTS:
        stats = Stats()
        convex_hull(generate(dist, 2**k, seed=1), stats=stats, seed=1)
        out[k] = stats
    return out


def _spread(values: list[float]) -> float:
    return max(values) / min(values)


@pytest.mark.slow
def test_onsphere_counts_grow_as_n_lg_n() -> None:
    counts = _counts("OnSphere")
    per = {k: 2**k * k for k in EXPONENTS}
    kc = [counts[k].key_comparisons / per[k] for k in EXPONENTS]
    tests = [counts[k].plane_side_tests / per[k] for k in EXPONENTS]
    assert _spread(kc) <= 1.2, f"key comparisons / (n lg n) at 2^{EXPONENTS}: {kc}"
    assert _spread(tests) <= 1.2, f"plane-side tests / (n lg n) at 2^{EXPONENTS}: {tests}"
    # Every point is a vertex: 2n - 4 faces at the end, O(1) complex operations per insertion.
    for k in EXPONENTS:
        st = counts[k]
        assert st.faces_created - st.faces_deleted == 2 * 2**k - 4
        assert st.dict_ops / 2**k < 60


def test_inball_counts_grow_no_faster_than_n_lg_n() -> None:
    counts = _counts("InBall")
    per = {k: 2**k * math.log2(2**k) for k in EXPONENTS}
    first = EXPONENTS[0]
    for what in ("key_comparisons", "plane_side_tests"):
        ratios = [getattr(counts[k], what) / per[k] for k in EXPONENTS]
        assert max(ratios) <= 1.2 * ratios[0], f"{what} / (n lg n) at 2^{EXPONENTS}: {ratios}"
    linear = [counts[k].plane_side_tests / 2**k for k in EXPONENTS]
    assert _spread(linear) <= 1.2, f"plane-side tests / n at 2^{EXPONENTS}: {linear}"
    # The complex work follows the hull's size, not n: sublinear growth.
    last = EXPONENTS[-1]
    assert counts[last].key_comparisons < counts[first].key_comparisons * 2 ** (last - first)
