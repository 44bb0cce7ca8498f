"""Closed ``SIMPCOMP`` complexes and their subdivisions: the neighbour test and the subdivision workload.

The boundary of an (n+1)-simplex, consistently oriented, is a closed n-complex;
a stellar subdivision of one of its simplices from a new vertex keeps it closed
and oriented.  The growth workload of :mod:`.simpcomp_growth` builds on the same
two functions.
"""

from __future__ import annotations

import random
from typing import Any

from hypothesis import given, settings
from hypothesis import strategies as st

from persistri.spec.conformance.runner import ConformanceSkip
from persistri.spec.conformance.simpcomp_config import SimpCompSuiteConfig, vertex_pool
from persistri.spec.conformance.simpcomp_history import History, back, check_version
from persistri.spec.simpcomp_laws import (
    LawViolation,
    OrientedKey,
    law_add,
    law_agrees,
    law_neighbour,
    law_persistence,
    law_rem,
    oriented_key,
)

__all__ = ["closed_boundary", "subdivide", "t_neighbour", "t_workload"]

def closed_boundary(cfg: SimpCompSuiteConfig, n: int, extra: int) -> tuple[list[Any], list[list[int]]]:
    """A pool of n + 2 + ``extra`` vertices and the boundary of the (n+1)-simplex on the first n + 2,
    as index lists with the induced orientation: a closed, consistently oriented n-complex."""
    pool = vertex_pool(cfg, n + 2 + extra)
    top = list(range(n + 2))
    faces = []
    for i in range(n + 2):
        rest = top[:i] + top[i + 1 :]
        if i % 2 == 1:
            rest[-1], rest[-2] = rest[-2], rest[-1]
        faces.append(rest)
    return pool, faces


def subdivide(t: list[int], p: int) -> list[list[int]]:
    """The stellar subdivision of the simplex ``t`` from the new vertex ``p``: ``t`` with each vertex in
    turn replaced by ``p`` (same orientation as ``t``, so a closed complex stays closed and oriented)."""
    return [t[:i] + [p] + t[i + 1 :] for i in range(len(t))]


def t_neighbour(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    dims = tuple(n for n in cfg.dims if n >= 2)
    if not dims:
        raise ConformanceSkip("the neighbour law is for dimensions 2 and up")

    @given(st.sampled_from(dims), st.lists(st.integers(0, 30), max_size=6), st.integers(0, 5))
    def neighbour(n: int, picks: list[int], at: int) -> None:
        C = cfg.structure
        pool, tops = closed_boundary(cfg, n, len(picks))
        h = History(cfg, n, pool)
        for i, t in enumerate(tops):
            h.add(len(h.versions) - 1, t, i)
        law_neighbour(C, h.versions[-1][0], n)
        closed = [h.versions[-1][0]]
        for j, pick in enumerate(picks):
            t = tops.pop(pick % len(tops))
            c, model = h.versions[-1]
            s = C.Simplex.simplex([pool[i] for i in t])
            c, model = law_rem(C, c, n, model, s)
            for u in subdivide(t, n + 2 + j):
                c, model = law_add(C, c, n, model, C.Simplex.simplex([pool[i] for i in u]), ("sub", j))
                tops.append(u)
            check_version(cfg, c, f"after subdivision {j}")
            h.versions.append((c, model))
            closed.append(c)
            law_neighbour(C, c, n)
        # An older closed version is still closed after later subdivisions.
        law_neighbour(C, closed[back(len(closed), at)], n)
        h.check_all()

    hs(neighbour)()


def t_workload(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    """Grow the boundary of an (n+1)-simplex by ``workload_size`` stellar subdivisions at random simplices
    (fixed seed), removing one simplex and adding n+1 each time; every few hundred steps the check runs
    and a snapshot is kept; at the end the final complex agrees with its model, every snapshot with its
    own (persistence), and for n ≥ 2 the neighbour law holds."""
    size = cfg.workload_size
    if size == 0:
        raise ConformanceSkip("workload_size = 0")
    C = cfg.structure
    S = C.Simplex
    for n in cfg.dims:
        rng = random.Random(f"persistri-simpcomp-workload:{n}:{size}")
        pool, tops = closed_boundary(cfg, n, size)
        c = C.new(n)
        model: dict[OrientedKey, Any] = {}
        serial = 0

        def add(u: list[int]) -> None:
            nonlocal c, serial
            s = S.simplex([pool[i] for i in u])
            try:
                c = C.add(c, s, serial)
            except Exception as exc:
                raise LawViolation("add", f"workload in dimension {n}: add(c, {s!r}, {serial}) raised {exc!r}") from exc
            model[oriented_key(S, s)] = serial
            serial += 1

        for t in tops:
            add(t)
        snapshots: list[tuple[Any, dict[OrientedKey, Any]]] = [(c, dict(model))]
        every = max(1, size // 4)
        for j in range(size):
            t = tops.pop(rng.randrange(len(tops)))
            s = S.simplex([pool[i] for i in t])
            try:
                c = C.rem(c, s)
            except Exception as exc:
                raise LawViolation("rem", f"workload in dimension {n}: rem(c, {s!r}) of a held simplex raised {exc!r}") from exc
            del model[oriented_key(S, s)]
            for u in subdivide(t, n + 2 + j):
                add(u)
                tops.append(u)
            if (j + 1) % every == 0:
                check_version(cfg, c, f"in the workload of dimension {n} after {j + 1} subdivisions")
                snapshots.append((c, dict(model)))
        law_agrees(C, c, n, model, f"the workload's final complex in dimension {n}")
        if n >= 2:
            law_neighbour(C, c, n)
        law_persistence(C, n, snapshots)
