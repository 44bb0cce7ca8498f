"""The hypothesis test of each ``SIMPCOMP`` law on its own (and of the ``VERTEX`` and ``SIMPLEX`` laws of the
structure's sub-structures): random complexes, one law applied to each."""

from __future__ import annotations

from typing import Any

from hypothesis import assume, given, settings
from hypothesis import strategies as st

from persistri.spec.conformance.runner import ConformanceSkip
from persistri.spec.conformance.simpcomp_cases import ComplexCase, complex_cases
from persistri.spec.conformance.simpcomp_config import SimpCompSuiteConfig, pool_size, vertex_pool
from persistri.spec.conformance.simpcomp_history import (
    absent_simplex,
    bad_calls,
    check_version,
    faces_both_ways,
    flipped,
    rotated,
    simplex_of,
)
from persistri.spec.simpcomp_laws import (
    law_add,
    law_add_present,
    law_add_rem_inverse,
    law_agrees,
    law_bad_input,
    law_find,
    law_grep,
    law_new,
    law_rem,
    law_rem_absent,
    law_update,
    oriented_key,
    representative,
)
from persistri.spec.simplex_laws import check_simplex_laws, law_compare_order
from persistri.spec.vertex_laws import law_compare_total, law_new_deterministic, law_new_fresh, law_new_loc

__all__ = [
    "c_add",
    "c_add_present",
    "c_add_rem_inverse",
    "c_agrees",
    "c_find",
    "c_grep",
    "c_rem",
    "c_rem_absent",
    "c_update",
    "t_bad_input",
    "t_invariants",
    "t_new",
    "t_simplex",
    "t_vertex",
]

def c_agrees(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    _, c, model = case.build(cfg)
    law_agrees(cfg.structure, c, case.n, model, "the case's complex")


def c_add(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    pool, c, model = case.build(cfg)
    s = absent_simplex(cfg.structure, pool, case.n, model, case.target)
    assume(s is not None)
    law_add(cfg.structure, c, case.n, model, s, case.x)


def c_add_present(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    _, c, model = case.build(cfg)
    assume(bool(model))
    C = cfg.structure
    s = representative(C.Simplex, list(model)[case.pick % len(model)])
    law_add_present(C, c, case.n, model, flipped(C, s) if case.flip else rotated(C, s), case.x)


def c_rem(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    _, c, model = case.build(cfg)
    assume(bool(model))
    C = cfg.structure
    s = representative(C.Simplex, list(model)[case.pick % len(model)])
    law_rem(C, c, case.n, model, rotated(C, s) if case.flip else s)


def c_rem_absent(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    pool, c, model = case.build(cfg)
    C = cfg.structure
    s = simplex_of(C, pool, case.target)
    if oriented_key(C.Simplex, s) in model:
        s = flipped(C, s)  # held: its other orientation is absent
    law_rem_absent(C, c, case.n, model, s)


def c_add_rem_inverse(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    pool, c, model = case.build(cfg)
    s = absent_simplex(cfg.structure, pool, case.n, model, case.target)
    assume(s is not None)
    law_add_rem_inverse(cfg.structure, c, case.n, model, s, case.x)


def c_update(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    _, c, model = case.build(cfg)
    assume(bool(model))
    C = cfg.structure
    s = representative(C.Simplex, list(model)[case.pick % len(model)])
    x = case.x
    law_update(C, c, case.n, model, rotated(C, s) if case.flip else s, lambda old: (x, old))


def c_find(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    pool, c, model = case.build(cfg)
    C, n = cfg.structure, case.n
    faces = [simplex_of(C, pool, case.target[:n])]
    if model:  # the faces of a held simplex, each way round: find must tell the orientations apart
        faces += faces_both_ways(C, n, representative(C.Simplex, list(model)[case.pick % len(model)]))
    for f in faces:
        law_find(C, c, n, model, f)


def c_grep(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    pool, c, model = case.build(cfg)
    C, n = cfg.structure, case.n
    for k in range(n + 1):
        s = simplex_of(C, pool, case.target[: k + 1])
        law_grep(C, c, n, model, case.d, s)
        law_grep(C, c, n, model, n, s)


def t_vertex(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    V = cfg.structure.Simplex.Vertex

    @given(st.integers(2, 8))
    def vertex(k: int) -> None:
        law_compare_total(V, vertex_pool(cfg, k))

    hs(vertex)()
    if cfg.state is None:
        raise ConformanceSkip("no vertex state given: the laws of VERTEX.new were not run (only compare)")
    def fresh() -> Any:
        return cfg.state() if callable(cfg.state) else cfg.state

    @given(st.integers(0, 9), st.integers(0, 9), st.lists(st.integers(0, 99), max_size=6))
    def vertex_new(p: int, q: int, points: list[int]) -> None:
        law_new_loc(V, fresh(), p)
        law_new_deterministic(V, fresh(), p, q)
        law_new_fresh(V, fresh(), points)

    hs(vertex_new)()


def t_simplex(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    S = cfg.structure.Simplex
    top = max(cfg.dims)

    @given(st.integers(0, top), st.permutations(range(pool_size(top))), st.lists(st.permutations(range(pool_size(top))), min_size=2, max_size=5))
    def simplex(d: int, perm: list[int], others: list[list[int]]) -> None:
        pool = vertex_pool(cfg, pool_size(top))
        s = S.simplex([pool[i] for i in perm[: d + 1]])
        check_simplex_laws(S, s)
        law_compare_order(S, [s, *(S.simplex([pool[i] for i in p[: d + 1]]) for p in others)])

    hs(simplex)()


def t_new(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    for n in cfg.dims:
        c = law_new(cfg.structure, n)
        check_version(cfg, c, f"new({n})")


def t_bad_input(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    @given(complex_cases(cfg.dims, min_adds=1))
    def bad_input(case: ComplexCase) -> None:
        pool, c, model = case.build(cfg)
        C, n = cfg.structure, case.n
        for what, call in bad_calls(C, pool, n, c, case.target, case.x):
            law_bad_input(C, c, n, model, call, what)
        if model:
            held = representative(C.Simplex, list(model)[case.pick % len(model)])
            law_add_present(C, c, n, model, held, case.x)
            law_add_present(C, c, n, model, flipped(C, held), case.x)
            law_rem_absent(C, c, n, model, flipped(C, held))

    hs(bad_input)()


def t_invariants(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    if not cfg.check:
        raise ConformanceSkip("check is off")
    if cfg.checker is None:
        raise ConformanceSkip("the structure has no check(c) or _check(c)")

    @given(complex_cases(cfg.dims))
    def invariants(case: ComplexCase) -> None:
        case.build(cfg)  # the check runs on every version the build makes

    hs(invariants)()
