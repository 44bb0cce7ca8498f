"""The two ``ORD_MAP`` workloads of ``workload_size`` keys: insert all, find all, remove all (sequential and
random orders), with ``_check`` ten times per phase.  The growth workload of :mod:`.ord_map_growth` is the one
that keeps and rechecks versions at every size."""

from __future__ import annotations

import random
from typing import Any

from hypothesis import settings

from persistri.spec.conformance.ord_map_config import SuiteConfig
from persistri.spec.conformance.runner import ConformanceSkip
from persistri.spec.ord_map import NotFound
from persistri.spec.ord_map_laws import LawViolation, law_invariants, law_persistence

__all__ = ["t_workload_random", "t_workload_sequential"]

def _workload(cfg: SuiteConfig, inserted: list[int], removed: list[int], label: str) -> None:
    """Insert ``inserted`` (key ↦ its position), find all, remove all in the order ``removed``.

    ``_check`` runs ten times per phase (every n/10 steps, at most every 10^4)
    and at the end; the full version and the half-removed one are checked
    against their snapshots at the end.
    """
    s = cfg.structure
    n = len(inserted)
    every = max(1, min(10_000, n // 10))
    value = {k: i for i, k in enumerate(inserted)}
    m = s.empty()
    for i, k in enumerate(inserted):
        m = s.insert(m, k, i)
        if cfg.check and (i + 1) % every == 0:
            law_invariants(s, m, f"in the {label} workload after {i + 1} inserts")
    full = m
    if s.numItems(full) != n:
        raise LawViolation("numItems_insert", f"{label} workload: after inserting {n} distinct keys numItems = {s.numItems(full)!r}")
    for i, k in enumerate(inserted):
        o = s.find(full, k)
        if not (isinstance(o, tuple) and len(o) == 1 and o[0] == i):
            raise LawViolation("find_insert", f"{label} workload: after inserting key {k!r} ↦ {i} (and {n - 1} others), find = {o!r}")
    items = list(s.listItemsi(full))
    ordered = sorted(inserted)
    if len(items) != n or any(k != want or v != value[k] for (k, v), want in zip(items, ordered)):
        raise LawViolation("listItemsi", f"{label} workload: listItemsi after {n} inserts is not the sorted items")
    half: Any = None
    for j, k in enumerate(removed):
        try:
            m, v = s.remove(m, k)
        except NotFound as exc:
            raise LawViolation("remove", f"{label} workload: removing present key {k!r} (step {j}) raised NotFound") from exc
        if v != value[k]:
            raise LawViolation("remove", f"{label} workload: remove of key {k!r} returned {v!r}, want {value[k]!r}")
        if (j + 1) % every == 0:
            if s.numItems(m) != n - j - 1 or s.find(m, k) is not None:
                raise LawViolation(
                    "remove",
                    f"{label} workload: after {j + 1} removes numItems = {s.numItems(m)!r} (want {n - j - 1}), "
                    f"find of the last removed key {k!r} = {s.find(m, k)!r}",
                )
            if cfg.check:
                law_invariants(s, m, f"in the {label} workload after {j + 1} removes")
        if j + 1 == n // 2:
            half = m
    if s.isEmpty(m) is not True or s.numItems(m) != 0 or list(s.listItemsi(m)):
        raise LawViolation("remove", f"{label} workload: after removing all {n} keys the map is not empty ({s.numItems(m)!r} items)")
    if cfg.check:
        law_invariants(s, m, f"at the end of the {label} workload")
    history: list[tuple[Any, dict[Any, Any]]] = [(full, value)]
    if half is not None:
        gone = set(removed[: n // 2])
        history.append((half, {k: v for k, v in value.items() if k not in gone}))
    law_persistence(s, history, removed[:3])


def t_workload_sequential(cfg: SuiteConfig, hs: settings) -> None:
    n = cfg.workload_size
    if n == 0:
        raise ConformanceSkip("workload_size = 0")
    _workload(cfg, list(range(n)), list(range(n)), "sequential")


def t_workload_random(cfg: SuiteConfig, hs: settings) -> None:
    n = cfg.workload_size
    if n == 0:
        raise ConformanceSkip("workload_size = 0")
    rng = random.Random(20010101)  # fixed: the workload is the same every run
    inserted = rng.sample(range(-4 * n, 4 * n), n)
    removed = inserted[:]
    rng.shuffle(removed)
    _workload(cfg, inserted, removed, "random")

