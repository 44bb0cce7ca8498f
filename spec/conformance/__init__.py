"""persistri.spec.conformance — the conformance suites backend authors point at their own code.

* :class:`OrdMapConformance` — subclass it in a pytest file and set
  ``structure = <your ORD_MAP structure>`` (the pattern of zarr's ``StoreTests``);
* :func:`run_conformance` — the same tests without pytest, returning a
  :class:`ConformanceReport` (what ``persistri conformance maps MODULE:ATTR`` prints);
* :func:`missing_operations` — the ``ORD_MAP`` operations an object lacks;
* :class:`SimpCompConformance` and :func:`run_simpcomp_conformance` — the same two
  front ends for ``SIMPCOMP`` structures (persistent simplicial complexes);
  ``persistri conformance complex MODULE:ATTR`` prints the report.

The suites need hypothesis (and pytest for the base class): install
``persistri[conformance]``.
"""

try:
    import hypothesis  # noqa: F401  - only to give a clear message when it is missing
except ImportError as exc:  # pragma: no cover - depends on the environment
    raise ImportError(
        "persistri.spec.conformance needs hypothesis: pip install 'persistri[conformance]'"
    ) from exc

from persistri.spec.conformance.ord_map import (
    ORD_MAP_OPERATIONS,
    ORD_MAP_TESTS,
    NotAnOrdMap,
    OrdMapConformance,
    SuiteConfig,
    as_structure,
    missing_operations,
    run_conformance,
)
from persistri.spec.conformance.runner import ConformanceReport, Failure, Outcome
from persistri.spec.conformance.simpcomp import (
    SIMPCOMP_OPERATIONS,
    SIMPCOMP_TESTS,
    NotASimpComp,
    SimpCompConformance,
    SimpCompSuiteConfig,
    as_simpcomp,
    missing_simpcomp_operations,
    run_simpcomp_conformance,
)
from persistri.spec.conformance.strategies import CollidingKey

__all__ = [
    "OrdMapConformance",
    "run_conformance",
    "missing_operations",
    "as_structure",
    "NotAnOrdMap",
    "SuiteConfig",
    "ORD_MAP_OPERATIONS",
    "ORD_MAP_TESTS",
    "ConformanceReport",
    "Failure",
    "Outcome",
    "CollidingKey",
    "SimpCompConformance",
    "run_simpcomp_conformance",
    "missing_simpcomp_operations",
    "as_simpcomp",
    "NotASimpComp",
    "SimpCompSuiteConfig",
    "SIMPCOMP_OPERATIONS",
    "SIMPCOMP_TESTS",
]
