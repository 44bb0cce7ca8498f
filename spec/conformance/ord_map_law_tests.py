"""The hypothesis test of each ``ORD_MAP`` law on its own: random maps, one law applied to each.

Each test body takes the suite's configuration and the hypothesis settings;
:func:`case_test` makes the bodies of the laws applied to a
:class:`~.strategies.MapCase` (a map built by inserts and removes, a key, a
value and some probes).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Literal

from hypothesis import given, settings
from hypothesis import strategies as st

from persistri.spec.conformance.ord_map_config import SuiteConfig
from persistri.spec.conformance.ord_map_history import combine
from persistri.spec.conformance.runner import ConformanceSkip
from persistri.spec.conformance.strategies import MapCase, key_kinds, keys, map_cases
from persistri.spec.ord_map_laws import (
    law_empty,
    law_inDomain,
    law_invariants,
    law_key_order,
    law_lookup,
    law_singleton,
)

__all__ = ["case_test", "inDomain_all", "lookup_all", "probed", "t_empty", "t_invariants", "t_key_order", "t_singleton"]

def probed(case: MapCase) -> list[Any]:
    return [*case.model, *case.removed, *case.probes]


def t_key_order(cfg: SuiteConfig, hs: settings) -> None:
    kinds = key_kinds(cfg.hashing)
    ks = st.sampled_from(kinds).flatmap(lambda kind: st.lists(keys(kind, cfg.hashing), min_size=1, max_size=7))

    @given(ks)
    def key_order(keys_used: list[Any]) -> None:
        law_key_order(cfg.structure, keys_used)

    hs(key_order)()


def t_empty(cfg: SuiteConfig, hs: settings) -> None:
    @given(st.lists(keys("int", cfg.hashing), max_size=6))
    def empty(probes: list[Any]) -> None:
        law_empty(cfg.structure, probes)

    hs(empty)()


def t_singleton(cfg: SuiteConfig, hs: settings) -> None:
    @given(map_cases(cfg.hashing, max_items=0))
    def singleton(case: MapCase) -> None:
        law_singleton(cfg.structure, case.key, case.value, case.probes)

    hs(singleton)()


def case_test(
    name: str, key_mode: Literal["present", "absent", "any"], check: Callable[[Any, Any, MapCase], object]
) -> Callable[[SuiteConfig, settings], None]:
    """A test body: build the case's map, then ``check(structure, m, case)``."""

    def body(cfg: SuiteConfig, hs: settings) -> None:
        def run(case: MapCase) -> None:
            s = cfg.structure
            check(s, case.build(s), case)

        run.__name__ = run.__qualname__ = name  # the name hypothesis prints in the failing example
        hs(given(map_cases(cfg.hashing, key_mode))(run))()

    return body


def lookup_all(s: Any, m: Any, case: MapCase) -> None:
    for k in [case.key, *case.probes]:
        law_lookup(s, m, k)


def inDomain_all(s: Any, m: Any, case: MapCase) -> None:
    for k in [case.key, *case.probes]:
        law_inDomain(s, m, k)

def t_invariants(cfg: SuiteConfig, hs: settings) -> None:
    s = cfg.structure
    if not cfg.check:
        raise ConformanceSkip("check is off")
    if getattr(s, "_check", None) is None:
        raise ConformanceSkip("the structure has no _check(m)")

    @given(map_cases(cfg.hashing))
    def invariants(case: MapCase) -> None:
        m = case.build(s, after=lambda v: law_invariants(s, v, "while building the case's map"))
        law_invariants(s, s.insert(m, case.key, case.value), "after insert(m, key, value)")
        law_invariants(s, s.insertWith(combine, m, case.key, case.value), "after insertWith(f, m, key, value)")
        if case.key in case.model:
            law_invariants(s, s.remove(m, case.key)[0], "after remove(m, key)")
        law_invariants(s, s.singleton(case.key, case.value), "after singleton(key, value)")

    hs(invariants)()

