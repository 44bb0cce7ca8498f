"""Random complexes for the ``SIMPCOMP`` law tests: :class:`ComplexCase` and its hypothesis strategy."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from hypothesis import given, settings
from hypothesis import strategies as st

from persistri.spec.conformance.simpcomp_config import SimpCompSuiteConfig, pool_size, vertex_pool
from persistri.spec.conformance.simpcomp_history import check_version, held, simplex_of
from persistri.spec.simpcomp_laws import LawViolation, OrientedKey, law_agrees, oriented_key, representative

__all__ = ["VALUES", "ComplexCase", "case_test", "complex_cases"]

_MAX_ADDS = 12


@dataclass(frozen=True)
class ComplexCase:
    """One law's input: an n-complex made by adding the simplices ``adds`` (index orders into a pool of
    :func:`pool_size` vertices; one already held either way is skipped) with the data ``data``, then
    removing the held simplices picked by ``removes``; and what the law is applied to: an index order
    ``target``, a pick among held simplices, a dimension ``d``, a datum ``x`` and a flag ``flip``."""

    n: int
    adds: tuple[tuple[int, ...], ...]
    data: tuple[Any, ...]
    removes: tuple[int, ...]
    target: tuple[int, ...]
    pick: int
    d: int
    x: Any
    flip: bool

    def build(self, cfg: SimpCompSuiteConfig) -> tuple[list[Any], Any, dict[OrientedKey, Any]]:
        """The pool, the complex and its model (the structure's check runs on every version)."""
        C, n = cfg.structure, self.n
        pool = vertex_pool(cfg, pool_size(n))
        c = C.new(n)
        model: dict[OrientedKey, Any] = {}
        for order, x in zip(self.adds, self.data, strict=True):
            s = simplex_of(C, pool, order)
            if held(C, model, s):
                continue
            try:
                c = C.add(c, s, x)
            except Exception as exc:
                raise LawViolation("add", f"while building the case's complex: add(c, {s!r}, {x!r}) raised {exc!r}") from exc
            model[oriented_key(C.Simplex, s)] = x
            check_version(cfg, c, "while building the case's complex")
        for pick in self.removes:
            if not model:
                break
            key = list(model)[pick % len(model)]
            s = representative(C.Simplex, key)
            try:
                c = C.rem(c, s)
            except Exception as exc:
                raise LawViolation("rem", f"while building the case's complex: rem(c, {s!r}) of a held simplex raised {exc!r}") from exc
            del model[key]
            check_version(cfg, c, "while building the case's complex")
            # A wrong rem is named here, not later as "persistence" of the version a law is given.
            law_agrees(C, c, n, model, f"after rem(c, {s!r}) while building the case's complex")
        return pool, c, model


VALUES = st.one_of(st.none(), st.integers(-3, 3), st.text(max_size=2), st.tuples(st.integers(0, 2)))


@st.composite
def complex_cases(draw: st.DrawFn, dims: tuple[int, ...], min_adds: int = 0) -> ComplexCase:
    """A :class:`ComplexCase` in one of ``dims``."""
    n = draw(st.sampled_from(dims))
    k = pool_size(n)
    order = st.permutations(range(k)).map(lambda p: tuple(p[: n + 1]))
    adds = draw(st.lists(order, min_size=min_adds, max_size=_MAX_ADDS))
    data = tuple(draw(VALUES) for _ in adds)
    removes = tuple(draw(st.lists(st.integers(0, 20), max_size=4)))
    return ComplexCase(n, tuple(adds), data, removes, draw(order), draw(st.integers(0, 50)), draw(st.integers(0, n)), draw(VALUES), draw(st.booleans()))


def case_test(name: str, check: Callable[[SimpCompSuiteConfig, ComplexCase], None], min_adds: int = 0) -> Callable[[SimpCompSuiteConfig, settings], None]:
    """A test body: ``check(cfg, case)`` for random cases (hypothesis prints the function as ``name``)."""

    def body(cfg: SimpCompSuiteConfig, hs: settings) -> None:
        def run(case: ComplexCase) -> None:
            check(cfg, case)

        run.__name__ = run.__qualname__ = name
        hs(given(complex_cases(cfg.dims, min_adds))(run))()

    return body
