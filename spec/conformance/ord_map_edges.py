"""Edge cases of ``ORD_MAP``, each a fixed scenario: the empty map, absent keys, overwriting, the last key,
colliding hashes and ``None`` values.  Every version a scenario makes is rechecked at its end."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

from hypothesis import settings

from persistri.spec.conformance.ord_map_config import SuiteConfig
from persistri.spec.conformance.ord_map_history import combine
from persistri.spec.conformance.runner import ConformanceSkip
from persistri.spec.conformance.strategies import CollidingKey
from persistri.spec.ord_map_laws import (
    LawViolation,
    law_empty,
    law_find_insert,
    law_find_insert_other,
    law_foldli,
    law_inDomain,
    law_insertWith,
    law_invariants,
    law_isEmpty,
    law_listItemsi,
    law_listKeys,
    law_lookup,
    law_numItems_insert,
    law_persistence,
    law_remove,
    law_remove_absent,
    law_singleton,
)

__all__ = [
    "t_edge_colliding_hashes",
    "t_edge_empty_map",
    "t_edge_none_value",
    "t_edge_overwrite",
    "t_edge_remove_absent",
    "t_edge_remove_last_key",
]

def _check_history(cfg: SuiteConfig, history: Sequence[tuple[Any, dict[Any, Any]]], probes: Iterable[Any]) -> None:
    s = cfg.structure
    for m, _ in history:
        law_listItemsi(s, m)
        if cfg.check:
            law_invariants(s, m)
    law_persistence(s, history, probes)


def t_edge_empty_map(cfg: SuiteConfig, hs: settings) -> None:
    s = cfg.structure
    e = law_empty(s, [0, 1, -1])
    law_lookup(s, e, 0)
    law_inDomain(s, e, 0)
    law_remove_absent(s, e, 0)
    law_listItemsi(s, e, [0])
    law_listKeys(s, e)
    law_foldli(s, e)
    law_isEmpty(s, e)
    _check_history(cfg, [(e, {})], [0])


def t_edge_remove_absent(cfg: SuiteConfig, hs: settings) -> None:
    s = cfg.structure
    m = s.empty()
    for k in (10, 20, 30):
        m = s.insert(m, k, str(k))
    for k in (5, 15, 25, 35):  # below, between, above
        law_remove_absent(s, m, k)
    m2, _ = law_remove(s, m, 20)
    law_remove_absent(s, m2, 20)  # removed once: removing it again is an error
    one = s.singleton(1, "one")
    law_remove_absent(s, one, 2)
    law_remove_absent(s, one, 0)
    _check_history(
        cfg, [(m, {10: "10", 20: "20", 30: "30"}), (m2, {10: "10", 30: "30"}), (one, {1: "one"})], [0, 2, 5, 15, 20, 25, 35]
    )


def t_edge_overwrite(cfg: SuiteConfig, hs: settings) -> None:
    s = cfg.structure
    m1 = s.insert(s.empty(), 1, "a")
    m1 = s.insert(m1, 2, "b")
    m2 = law_numItems_insert(s, m1, 1, "c")
    law_find_insert(s, m1, 1, "c", result=(m2,))
    law_find_insert_other(s, m1, 1, "c", [2, 3], result=(m2,))
    m3 = law_find_insert(s, m2, 1, None)  # overwrite with None
    m4 = law_find_insert(s, m3, 1, "d")  # and back from None
    m5 = law_insertWith(s, combine, m4, 1, "e", [2])
    m6 = law_find_insert(s, m5, 2, "b")  # same key, equal value
    _check_history(
        cfg,
        [
            (m1, {1: "a", 2: "b"}),
            (m2, {1: "c", 2: "b"}),
            (m3, {1: None, 2: "b"}),
            (m4, {1: "d", 2: "b"}),
            (m5, {1: ("d", "e"), 2: "b"}),
            (m6, {1: ("d", "e"), 2: "b"}),
        ],
        [0, 3],
    )


def t_edge_remove_last_key(cfg: SuiteConfig, hs: settings) -> None:
    s = cfg.structure
    one = s.singleton(7, "x")
    none, _ = law_remove(s, one, 7)
    if s.isEmpty(none) is not True or s.numItems(none) != 0 or list(s.listItemsi(none)):
        raise LawViolation(
            "remove",
            f"removing the last key left isEmpty = {s.isEmpty(none)!r}, numItems = {s.numItems(none)!r}, "
            f"listItemsi = {list(s.listItemsi(none))!r}",
        )
    again = law_find_insert(s, none, 8, "y")  # the emptied map is a working map
    history: list[tuple[Any, dict[Any, Any]]] = [(one, {7: "x"}), (none, {}), (again, {8: "y"})]
    m = s.empty()
    snap: dict[Any, Any] = {}
    order = [5, 1, 9, 3, 7, 0, 8, 2, 6, 4]
    for k in order:
        m = s.insert(m, k, -k)
        snap = {**snap, k: -k}
        history.append((m, snap))
    for k in reversed(order):
        m, _ = law_remove(s, m, k)
        snap = {kk: vv for kk, vv in snap.items() if kk != k}
        history.append((m, snap))
    law_isEmpty(s, m)
    _check_history(cfg, history, [*order, 10, -1])


def t_edge_colliding_hashes(cfg: SuiteConfig, hs: settings) -> None:
    if not cfg.hashing:
        raise ConformanceSkip("hashing is off")
    s = cfg.structure
    groups: list[list[Any]] = [[-1, -2], [0, 2**61 - 1, -(2**61 - 1)], [1, 2**61], [CollidingKey(r) for r in range(-8, 24)]]
    for group in groups:
        history: list[tuple[Any, dict[Any, Any]]] = []
        m = s.empty()
        snap: dict[Any, Any] = {}
        for i, k in enumerate(group):
            m = law_find_insert_other(s, m, k, i, group)
            m = law_find_insert(s, m, k, i, result=(m,))
            snap = {**snap, k: i}
            history.append((m, snap))
        for k in group[::2] + group[1::2]:
            law_lookup(s, m, k)
            m, _ = law_remove(s, m, k)
            law_remove_absent(s, m, k)
            snap = {kk: vv for kk, vv in snap.items() if kk != k}
            history.append((m, snap))
        _check_history(cfg, history, group)


def t_edge_none_value(cfg: SuiteConfig, hs: settings) -> None:
    s = cfg.structure
    m = law_find_insert(s, s.empty(), 1, None)  # find must return (None,)
    law_lookup(s, m, 1)
    law_inDomain(s, m, 1)
    law_listItemsi(s, m, [1, 2])
    law_foldli(s, m)
    one = law_singleton(s, 2, None, [1])
    m2 = law_insertWith(s, combine, m, 1, None)  # f(None, None)
    m3 = law_find_insert(s, m, 3, (None,))  # a 1-tuple value is not an option
    m4, _ = law_remove(s, m, 1)
    _check_history(cfg, [(m, {1: None}), (one, {2: None}), (m2, {1: (None, None)}), (m3, {1: None, 3: (None,)}), (m4, {})], [1, 2, 3])

