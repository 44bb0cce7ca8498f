"""Shared pytest configuration: the hypothesis profiles, and which build of persistri is under test.

``HYPOTHESIS_PROFILE=ci`` (set by ``make test`` under CI) is thorough;
``dev`` (the default) is quick.  Neither has a deadline: persistri's tests check
results and operation counts, never wall-clock time.
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci",
    max_examples=100,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    print_blob=True,
)
settings.register_profile(
    "dev",
    max_examples=40,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "dev"))


def pytest_report_header() -> str:
    """Which persistri the suite runs on: interpreted, or the compiled twin (``make test`` runs both)."""
    from persistri.impl.bench.hull import persistri_build

    return f"persistri: {persistri_build()}"
