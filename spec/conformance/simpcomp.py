"""The ``SIMPCOMP`` conformance suite: is *your* persistent simplicial complex a correct ``SIMPCOMP``?

Point it at a structure (an object whose methods are the operations of
:class:`~persistri.spec.simpcomp.SIMPCOMP`, with its ``Simplex`` and
``Simplex.Vertex`` sub-structures) in one of two ways:

* **pytest** — subclass :class:`SimpCompConformance` in your test file, set
  ``structure`` and say how to make vertices (the ``VERTEX`` signature has no
  initial state, so the suite cannot make one itself): either ``state`` — a
  vertex state the suite calls ``Vertex.new`` on, or a function of no
  arguments returning a fresh one — or override ``make_vertices(k)``::

      from persistri.spec.conformance import SimpCompConformance
      from mypackage import my_complex, initial_state

      class TestMyComplex(SimpCompConformance):
          structure = my_complex
          state = initial_state
          dims = (2, 3)

* **a program** — :func:`run_simpcomp_conformance` returns a
  :class:`~persistri.spec.conformance.runner.ConformanceReport`; the command
  ``persistri conformance complex MODULE:ATTR --state MODULE:ATTR`` prints it.

Both run the same test bodies (:data:`SIMPCOMP_TESTS`), in every dimension of
``dims``: the ``VERTEX`` and ``SIMPLEX`` laws on the structure's own
sub-structures; a hypothesis test of each ``SIMPCOMP`` law of
:mod:`persistri.spec.simpcomp_laws` on random complexes; bad input (wrong
dimension, repeated vertex, a simplex whose other orientation is held, ``rem``
of an absent simplex) raising and leaving the version untouched; random
branching programs and a stateful test that keep *every* version with its
model — a dict from each held oriented simplex to its datum, from which the
laws derive the lower faces — and recheck all of them after every step; the
neighbour law on closed complexes (boundaries of simplices, subdivided); and a
workload of ``workload_size`` subdivisions.  With ``check`` the structure's
own ``check(c)`` (or ``_check(c)``) runs on every version made.

Vertices are the structure's own; they must be hashable (the models are
dicts) and are never looked inside.  Data are arbitrary values, ``None``
included.  Hypothesis settings: under pytest the tests use your *active*
profile (deadline off; ``max_examples`` overrides its example count);
:func:`run_simpcomp_conformance` uses explicit settings, independent of any profile.
"""

from __future__ import annotations

import random
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from itertools import combinations
from typing import Any, ClassVar

from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, precondition, rule, run_state_machine_as_test

from persistri.spec.conformance.runner import (
    ConformanceReport,
    ConformanceSkip,
    ConformanceTest,
    explicit_settings,
    run_tests,
)
from persistri.spec.order import Order
from persistri.spec.simpcomp_laws import (
    LawViolation,
    OrientedKey,
    law_add,
    law_add_present,
    law_add_rem_inverse,
    law_agrees,
    law_bad_input,
    law_find,
    law_grep,
    law_invariants,
    law_neighbour,
    law_new,
    law_persistence,
    law_rem,
    law_rem_absent,
    law_update,
    oriented_key,
    representative,
)
from persistri.spec.simplex_laws import check_simplex_laws, law_compare_order
from persistri.spec.vertex_laws import law_compare_total, law_new_deterministic, law_new_fresh, law_new_loc

__all__ = [
    "SIMPCOMP_OPERATIONS",
    "SIMPCOMP_TESTS",
    "NotASimpComp",
    "SimpCompConformance",
    "SimpCompSuiteConfig",
    "as_simpcomp",
    "missing_simpcomp_operations",
    "run_simpcomp_conformance",
    "vertices_from_state",
]

SIMPCOMP_OPERATIONS: tuple[str, ...] = (
    "Simplex",
    "dim",
    "new",
    "isEmpty",
    "vertices",
    "simplices",
    "data",
    "grep",
    "find",
    "add",
    "rem",
    "update",
)
"""The values of ``signature SIMPCOMP``, in the signature's order (``Simplex`` is a structure)."""

_SIMPLEX_OPERATIONS = ("Vertex", "compare", "dim", "vertices", "simplex", "faces", "flip", "down", "join")
_VERTEX_OPERATIONS = ("compare", "new", "loc")


def missing_simpcomp_operations(obj: object) -> list[str]:
    """The operations of ``SIMPCOMP`` (and of its ``Simplex`` and ``Simplex.Vertex``) that ``obj`` lacks or
    has as non-callables, in signature order, named by their path (``Simplex.faces``, ``Simplex.Vertex.new``).

    An empty list means every operation is there (not that they are right).
    """
    missing: list[str] = []

    def walk(o: object, names: Sequence[str], prefix: str, subs: dict[str, tuple[Sequence[str], dict[str, Any]]]) -> None:
        for name in names:
            try:
                attr = getattr(o, name)
            except Exception:  # a missing attribute, or a property that raises: either way unusable
                missing.append(prefix + name)
                continue
            if name in subs:
                sub_names, sub_subs = subs[name]
                walk(attr, sub_names, f"{prefix}{name}.", sub_subs)
            elif not callable(attr):
                missing.append(prefix + name)

    vertex: dict[str, tuple[Sequence[str], dict[str, Any]]] = {"Vertex": (_VERTEX_OPERATIONS, {})}
    walk(obj, SIMPCOMP_OPERATIONS, "", {"Simplex": (_SIMPLEX_OPERATIONS, vertex)})
    return missing


class NotASimpComp(TypeError):
    """The object given as a structure is not a ``SIMPCOMP`` structure (it lacks operations)."""


def as_simpcomp(obj: object, name: str | None = None) -> Any:
    """``obj`` as a structure: a class is instantiated with no arguments; raises :class:`NotASimpComp`
    naming the missing operations (``name`` is how messages call ``obj``)."""
    label = name if name is not None else repr(obj)
    if isinstance(obj, type):
        try:
            obj = obj()
        except Exception as exc:
            raise NotASimpComp(f"{label} is a class that cannot be instantiated with no arguments: {exc}") from None
    missing = missing_simpcomp_operations(obj)
    if missing:
        raise NotASimpComp(f"{label} is not a SIMPCOMP structure: missing {', '.join(missing)}")
    return obj


def vertices_from_state(structure: Any, state: Any) -> Callable[[int], list[Any]]:
    """``make_vertices(k)``: ``k`` vertices made by ``structure.Simplex.Vertex.new`` from ``state`` (or from
    ``state()`` when ``state`` is a function of no arguments), at the points 0 … k−1."""
    V = structure.Simplex.Vertex

    def make(k: int) -> list[Any]:
        s = state() if callable(state) else state
        out = []
        for i in range(k):
            s, v = V.new(s, i)
            out.append(v)
        return out

    return make


@dataclass(frozen=True)
class SimpCompSuiteConfig:
    """What the suite runs against and how hard.

    ``structure`` — the structure under test; ``vertices(k)`` — k distinct
    fresh vertices of the structure; ``state`` — a vertex state (or a function
    returning one) for the ``VERTEX`` laws of ``new`` (None skips them);
    ``dims`` — the dimensions n of the complexes tested; ``check`` — call the
    structure's ``check(c)`` or ``_check(c)`` on every version; ``stateful_steps``
    — steps per stateful example; ``workload_size`` — subdivisions in the workload (0 skips it).
    """

    structure: Any
    vertices: Callable[[int], Sequence[Any]]
    state: Any = None
    dims: tuple[int, ...] = (2,)
    check: bool = True
    stateful_steps: int = 25
    workload_size: int = 300

    def __post_init__(self) -> None:
        if not self.dims or any(isinstance(n, bool) or not isinstance(n, int) or n < 1 for n in self.dims):
            raise ValueError(f"dims must be a non-empty tuple of positive ints, got {self.dims!r}")
        for knob in ("stateful_steps", "workload_size"):
            value = getattr(self, knob)
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise ValueError(f"{knob} must be a non-negative int, got {value!r}")
        if not callable(self.vertices):
            raise TypeError(f"vertices must be a function k -> k vertices, got {type(self.vertices).__name__}")

    @property
    def checker(self) -> Callable[[Any], object] | None:
        """The structure's representation check (``check``, else ``_check``), or None when off or absent."""
        if not self.check:
            return None
        for name in ("check", "_check"):
            fn: Callable[[Any], object] | None = getattr(self.structure, name, None)
            if callable(fn):
                return fn
        return None


# -- shared machinery ----------------------------------------------------------------------


def pool_size(n: int) -> int:
    """How many vertices the complexes of dimension n are built on: n + 4 (C(n+4, n+1) simplices to choose from)."""
    return n + 4


def _pool(cfg: SimpCompSuiteConfig, k: int) -> list[Any]:
    """``k`` vertices from the configuration, checked to be distinct and hashable (a harness error otherwise)."""
    vs = list(cfg.vertices(k))
    if len(vs) != k:
        raise ValueError(f"make_vertices({k}) returned {len(vs)} vertices")
    try:
        distinct = len(set(vs)) == k
    except TypeError as exc:
        raise TypeError(f"the suite needs hashable vertices: {exc}") from None
    cmp = cfg.structure.Simplex.Vertex.compare
    if not distinct or any(cmp(a, b) is Order.EQUAL for a, b in combinations(vs, 2)):
        raise ValueError(f"make_vertices({k}) returned vertices that are not distinct: {vs!r}")
    return vs


def _simplex(C: Any, pool: Sequence[Any], order: Sequence[int]) -> Any:
    return C.Simplex.simplex([pool[i] for i in order])


def _first_indices(perm: Sequence[int], k: int, size: int) -> list[int]:
    """The first ``size`` entries of the permutation ``perm`` that index a pool of ``k`` vertices."""
    return [i for i in perm if i < k][:size]


def _flipped(C: Any, s: Any) -> Any:
    """``s`` with its first two vertices swapped: the other orientation, built from positions only."""
    vs = list(C.Simplex.vertices(s))
    return C.Simplex.simplex([vs[1], vs[0], *vs[2:]])


def _rotated(C: Any, s: Any) -> Any:
    """An even reordering of ``s`` (its first three vertices rotated), or ``s`` itself below three vertices."""
    vs = list(C.Simplex.vertices(s))
    if len(vs) < 3:
        return s
    return C.Simplex.simplex([vs[1], vs[2], vs[0], *vs[3:]])


def _held(C: Any, model: dict[OrientedKey, Any], s: Any) -> bool:
    """Whether ``s`` is held in either orientation."""
    return oriented_key(C.Simplex, s) in model or oriented_key(C.Simplex, _flipped(C, s)) in model


def _absent_simplex(C: Any, pool: Sequence[Any], n: int, model: dict[OrientedKey, Any], order: Sequence[int]) -> Any:
    """The simplex of ``order`` if held in neither orientation, else the first such simplex of the pool (or None)."""
    s = _simplex(C, pool, order)
    if not _held(C, model, s):
        return s
    for combo in combinations(range(len(pool)), n + 1):
        t = _simplex(C, pool, combo)
        if not _held(C, model, t):
            return t
    return None


def _check(cfg: SimpCompSuiteConfig, c: Any, where: str) -> None:
    fn = cfg.checker
    if fn is not None:
        law_invariants(fn, c, where)


@dataclass
class _History:
    """Every version of one dimension made so far, each with its model: a branching history."""

    cfg: SimpCompSuiteConfig
    n: int
    pool: list[Any]
    versions: list[tuple[Any, dict[OrientedKey, Any]]] = field(default_factory=list)

    def __post_init__(self) -> None:
        c = law_new(self.cfg.structure, self.n)
        _check(self.cfg, c, f"new({self.n})")
        self.versions.append((c, {}))

    @property
    def C(self) -> Any:
        return self.cfg.structure

    def nonempty(self) -> list[int]:
        return [i for i, (_, m) in enumerate(self.versions) if m]

    def _made(self, c: Any, model: dict[OrientedKey, Any], what: str) -> None:
        _check(self.cfg, c, what)
        self.versions.append((c, model))

    def add(self, i: int, order: Sequence[int], x: Any) -> None:
        """``add`` to version ``i``: the add law when the simplex is free, add_present when held either way."""
        c, model = self.versions[i]
        s = _simplex(self.C, self.pool, order)
        if _held(self.C, model, s):
            law_add_present(self.C, c, self.n, model, s, x)
            return
        c2, m2 = law_add(self.C, c, self.n, model, s, x)
        self._made(c2, m2, f"after add to version {i}")

    def rem(self, i: int, pick: int) -> None:
        """``rem`` of a held simplex of version ``i`` (given in another order of its orientation)."""
        c, model = self.versions[i]
        keys = list(model)
        s = _rotated(self.C, representative(self.C.Simplex, keys[pick % len(keys)]))
        c2, m2 = law_rem(self.C, c, self.n, model, s)
        self._made(c2, m2, f"after rem from version {i}")

    def rem_absent(self, i: int, order: Sequence[int]) -> None:
        """``rem`` of a simplex not held in that orientation (the flip of a held one when it is held)."""
        c, model = self.versions[i]
        s = _simplex(self.C, self.pool, order)
        if oriented_key(self.C.Simplex, s) in model:
            s = _flipped(self.C, s)
        law_rem_absent(self.C, c, self.n, model, s)

    def update(self, i: int, pick: int, tag: Any) -> None:
        """``update`` of a held simplex of version ``i``."""
        c, model = self.versions[i]
        keys = list(model)
        s = representative(self.C.Simplex, keys[pick % len(keys)])
        c2, m2 = law_update(self.C, c, self.n, model, s, lambda x: (tag, x))
        self._made(c2, m2, f"after update of version {i}")

    def look(self, i: int, order: Sequence[int], d: int) -> None:
        """On version ``i``: ``find`` of a face of ``order``'s simplex and of the faces of a held simplex (both
        ways round), and ``grep`` of the first vertices of ``order``."""
        c, model = self.versions[i]
        n = self.n
        faces = [_simplex(self.C, self.pool, order[:n])]
        if model:
            faces += _faces_both_ways(self.C, n, representative(self.C.Simplex, list(model)[d % len(model)]))
        for f in faces:
            law_find(self.C, c, n, model, f)
        # d picks both grep's dimension and the size of the simplex grepped for.
        law_grep(self.C, c, n, model, d % (n + 1), _simplex(self.C, self.pool, order[: (d // (n + 1)) % (n + 1) + 1]))

    def bad_call(self, i: int, order: Sequence[int], kind: int, x: Any) -> None:
        """One of :func:`_bad_calls` on version ``i``: it must raise and leave the version as it was."""
        c, model = self.versions[i]
        calls = _bad_calls(self.C, self.pool, self.n, c, order, x)
        what, call = calls[kind % len(calls)]
        law_bad_input(self.C, c, self.n, model, call, what)

    def check_all(self) -> None:
        law_persistence(self.C, self.n, self.versions)


def _faces_both_ways(C: Any, n: int, t: Any) -> list[Any]:
    """The induced faces of the n-simplex ``t`` (built from positions) and, for n ≥ 2, their other orientations:
    ``find`` must tell them apart."""
    vs = list(C.Simplex.vertices(t))
    out = []
    for i in range(n + 1):
        rest = vs[:i] + vs[i + 1 :]
        if i % 2 == 1 and len(rest) >= 2:
            rest[-1], rest[-2] = rest[-2], rest[-1]
        f = C.Simplex.simplex(rest)
        out += [f, _flipped(C, f)] if n >= 2 else [f]
    return out


def _back(count: int, at: int) -> int:
    """Index of the version ``at`` steps before the latest of ``count`` (wrapping): shrinks to the latest."""
    return count - 1 - at % count


# -- cases: random complexes ---------------------------------------------------------------

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
        pool = _pool(cfg, pool_size(n))
        c = C.new(n)
        model: dict[OrientedKey, Any] = {}
        for order, x in zip(self.adds, self.data, strict=True):
            s = _simplex(C, pool, order)
            if _held(C, model, s):
                continue
            try:
                c = C.add(c, s, x)
            except Exception as exc:
                raise LawViolation("add", f"while building the case's complex: add(c, {s!r}, {x!r}) raised {exc!r}") from exc
            model[oriented_key(C.Simplex, s)] = x
            _check(cfg, c, "while building the case's complex")
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
            _check(cfg, c, "while building the case's complex")
        return pool, c, model


_VALUES = st.one_of(st.none(), st.integers(-3, 3), st.text(max_size=2), st.tuples(st.integers(0, 2)))


@st.composite
def complex_cases(draw: st.DrawFn, dims: tuple[int, ...], min_adds: int = 0) -> ComplexCase:
    """A :class:`ComplexCase` in one of ``dims``."""
    n = draw(st.sampled_from(dims))
    k = pool_size(n)
    order = st.permutations(range(k)).map(lambda p: tuple(p[: n + 1]))
    adds = draw(st.lists(order, min_size=min_adds, max_size=_MAX_ADDS))
    data = tuple(draw(_VALUES) for _ in adds)
    removes = tuple(draw(st.lists(st.integers(0, 20), max_size=4)))
    return ComplexCase(n, tuple(adds), data, removes, draw(order), draw(st.integers(0, 50)), draw(st.integers(0, n)), draw(_VALUES), draw(st.booleans()))


def _case_test(name: str, check: Callable[[SimpCompSuiteConfig, ComplexCase], None], min_adds: int = 0) -> Callable[[SimpCompSuiteConfig, settings], None]:
    """A test body: ``check(cfg, case)`` for random cases (hypothesis prints the function as ``name``)."""

    def body(cfg: SimpCompSuiteConfig, hs: settings) -> None:
        def run(case: ComplexCase) -> None:
            check(cfg, case)

        run.__name__ = run.__qualname__ = name
        hs(given(complex_cases(cfg.dims, min_adds))(run))()

    return body


# -- the law tests -----------------------------------------------------------------------------


def _c_agrees(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    _, c, model = case.build(cfg)
    law_agrees(cfg.structure, c, case.n, model, "the case's complex")


def _c_add(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    pool, c, model = case.build(cfg)
    s = _absent_simplex(cfg.structure, pool, case.n, model, case.target)
    assume(s is not None)
    law_add(cfg.structure, c, case.n, model, s, case.x)


def _c_add_present(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    _, c, model = case.build(cfg)
    assume(bool(model))
    C = cfg.structure
    s = representative(C.Simplex, list(model)[case.pick % len(model)])
    law_add_present(C, c, case.n, model, _flipped(C, s) if case.flip else _rotated(C, s), case.x)


def _c_rem(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    _, c, model = case.build(cfg)
    assume(bool(model))
    C = cfg.structure
    s = representative(C.Simplex, list(model)[case.pick % len(model)])
    law_rem(C, c, case.n, model, _rotated(C, s) if case.flip else s)


def _c_rem_absent(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    pool, c, model = case.build(cfg)
    C = cfg.structure
    s = _simplex(C, pool, case.target)
    if oriented_key(C.Simplex, s) in model:
        s = _flipped(C, s)  # held: its other orientation is absent
    law_rem_absent(C, c, case.n, model, s)


def _c_add_rem_inverse(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    pool, c, model = case.build(cfg)
    s = _absent_simplex(cfg.structure, pool, case.n, model, case.target)
    assume(s is not None)
    law_add_rem_inverse(cfg.structure, c, case.n, model, s, case.x)


def _c_update(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    _, c, model = case.build(cfg)
    assume(bool(model))
    C = cfg.structure
    s = representative(C.Simplex, list(model)[case.pick % len(model)])
    x = case.x
    law_update(C, c, case.n, model, _rotated(C, s) if case.flip else s, lambda old: (x, old))


def _c_find(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    pool, c, model = case.build(cfg)
    C, n = cfg.structure, case.n
    faces = [_simplex(C, pool, case.target[:n])]
    if model:  # the faces of a held simplex, each way round: find must tell the orientations apart
        faces += _faces_both_ways(C, n, representative(C.Simplex, list(model)[case.pick % len(model)]))
    for f in faces:
        law_find(C, c, n, model, f)


def _c_grep(cfg: SimpCompSuiteConfig, case: ComplexCase) -> None:
    pool, c, model = case.build(cfg)
    C, n = cfg.structure, case.n
    for k in range(n + 1):
        s = _simplex(C, pool, case.target[: k + 1])
        law_grep(C, c, n, model, case.d, s)
        law_grep(C, c, n, model, n, s)


def _t_vertex(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    V = cfg.structure.Simplex.Vertex

    @given(st.integers(2, 8))
    def vertex(k: int) -> None:
        law_compare_total(V, _pool(cfg, k))

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


def _t_simplex(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    S = cfg.structure.Simplex
    top = max(cfg.dims)

    @given(st.integers(0, top), st.permutations(range(pool_size(top))), st.lists(st.permutations(range(pool_size(top))), min_size=2, max_size=5))
    def simplex(d: int, perm: list[int], others: list[list[int]]) -> None:
        pool = _pool(cfg, pool_size(top))
        s = S.simplex([pool[i] for i in perm[: d + 1]])
        check_simplex_laws(S, s)
        law_compare_order(S, [s, *(S.simplex([pool[i] for i in p[: d + 1]]) for p in others)])

    hs(simplex)()


def _t_new(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    for n in cfg.dims:
        c = law_new(cfg.structure, n)
        _check(cfg, c, f"new({n})")


def _bad_calls(C: Any, pool: Sequence[Any], n: int, c: Any, order: Sequence[int], x: Any) -> list[tuple[str, Callable[[], object]]]:
    """Calls on ``c`` with bad input, each with a description: a repeated vertex (``add``, ``rem``,
    ``data``), simplices of the wrong dimension (``add``, ``rem``, ``find``).  ``order`` is n+1 pool indices."""
    S = C.Simplex
    s = _simplex(C, pool, order)
    repeated = [pool[order[0]], *(pool[i] for i in order[:n])]  # n+1 vertices, the first twice
    # Simplex.simplex may refuse the repeated vertex itself: that is a refusal of the call too.
    calls: list[tuple[str, Callable[[], object]]] = [
        (f"add(c, simplex({repeated!r}), x), a repeated vertex", lambda: C.add(c, S.simplex(repeated), x)),
        (f"rem(c, simplex({repeated!r})), a repeated vertex", lambda: C.rem(c, S.simplex(repeated))),
        (f"data(c, simplex({repeated!r})), a repeated vertex", lambda: C.data(c, S.simplex(repeated))),
    ]
    short = S.simplex([pool[i] for i in order[:n]])
    calls += [
        (f"add(c, {short!r}, x) of an (n-1)-simplex", lambda: C.add(c, short, x)),
        (f"rem(c, {short!r}) of an (n-1)-simplex", lambda: C.rem(c, short)),
        (f"find(c, {s!r}) of an n-simplex", lambda: C.find(c, s)),
    ]
    rest = [i for i in range(len(pool)) if i not in order]
    if rest:
        long = S.simplex([pool[i] for i in order] + [pool[rest[0]]])
        calls.append((f"add(c, {long!r}, x) of an (n+1)-simplex", lambda: C.add(c, long, x)))
    return calls


def _t_bad_input(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    @given(complex_cases(cfg.dims, min_adds=1))
    def bad_input(case: ComplexCase) -> None:
        pool, c, model = case.build(cfg)
        C, n = cfg.structure, case.n
        for what, call in _bad_calls(C, pool, n, c, case.target, case.x):
            law_bad_input(C, c, n, model, call, what)
        if model:
            held = representative(C.Simplex, list(model)[case.pick % len(model)])
            law_add_present(C, c, n, model, held, case.x)
            law_add_present(C, c, n, model, _flipped(C, held), case.x)
            law_rem_absent(C, c, n, model, _flipped(C, held))

    hs(bad_input)()


def _closed(cfg: SimpCompSuiteConfig, n: int, extra: int) -> tuple[list[Any], list[list[int]]]:
    """A pool of n + 2 + ``extra`` vertices and the boundary of the (n+1)-simplex on the first n + 2,
    as index lists with the induced orientation: a closed, consistently oriented n-complex."""
    pool = _pool(cfg, n + 2 + extra)
    top = list(range(n + 2))
    faces = []
    for i in range(n + 2):
        rest = top[:i] + top[i + 1 :]
        if i % 2 == 1:
            rest[-1], rest[-2] = rest[-2], rest[-1]
        faces.append(rest)
    return pool, faces


def _subdivide(t: list[int], p: int) -> list[list[int]]:
    """The stellar subdivision of the simplex ``t`` from the new vertex ``p``: ``t`` with each vertex in
    turn replaced by ``p`` (same orientation as ``t``, so a closed complex stays closed and oriented)."""
    return [t[:i] + [p] + t[i + 1 :] for i in range(len(t))]


def _t_neighbour(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    dims = tuple(n for n in cfg.dims if n >= 2)
    if not dims:
        raise ConformanceSkip("the neighbour law is for dimensions 2 and up")

    @given(st.sampled_from(dims), st.lists(st.integers(0, 30), max_size=6), st.integers(0, 5))
    def neighbour(n: int, picks: list[int], at: int) -> None:
        C = cfg.structure
        pool, tops = _closed(cfg, n, len(picks))
        h = _History(cfg, n, pool)
        for i, t in enumerate(tops):
            h.add(len(h.versions) - 1, t, i)
        law_neighbour(C, h.versions[-1][0], n)
        closed = [h.versions[-1][0]]
        for j, pick in enumerate(picks):
            t = tops.pop(pick % len(tops))
            c, model = h.versions[-1]
            s = C.Simplex.simplex([pool[i] for i in t])
            c, model = law_rem(C, c, n, model, s)
            for u in _subdivide(t, n + 2 + j):
                c, model = law_add(C, c, n, model, C.Simplex.simplex([pool[i] for i in u]), ("sub", j))
                tops.append(u)
            _check(cfg, c, f"after subdivision {j}")
            h.versions.append((c, model))
            closed.append(c)
            law_neighbour(C, c, n)
        # An older closed version is still closed after later subdivisions.
        law_neighbour(C, closed[_back(len(closed), at)], n)
        h.check_all()

    hs(neighbour)()


def _t_invariants(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    if not cfg.check:
        raise ConformanceSkip("check is off")
    if cfg.checker is None:
        raise ConformanceSkip("the structure has no check(c) or _check(c)")

    @given(complex_cases(cfg.dims))
    def invariants(case: ComplexCase) -> None:
        case.build(cfg)  # the check runs on every version the build makes

    hs(invariants)()


# -- branching programs and the stateful test ------------------------------------------------------


@dataclass(frozen=True)
class Step:
    """One step of a program: ``op`` applied ``back`` versions before the latest (wrapping)."""

    op: str
    back: int
    perm: tuple[int, ...]
    pick: int
    x: Any


_OPS = ("add", "add", "rem", "rem_absent", "update", "look", "bad")


@st.composite
def _programs(draw: st.DrawFn, dims: tuple[int, ...]) -> tuple[int, tuple[Step, ...]]:
    n = draw(st.sampled_from(dims))
    step = st.builds(
        Step,
        op=st.sampled_from(_OPS),
        back=st.integers(0, 6),
        perm=st.permutations(range(pool_size(n))).map(tuple),
        pick=st.integers(0, 20),
        x=_VALUES,
    )
    return n, tuple(draw(st.lists(step, max_size=16)))


def _apply(h: _History, step: Step) -> None:
    i = _back(len(h.versions), step.back)
    n = h.n
    order = list(step.perm[: n + 1])
    if step.op == "rem" and h.versions[i][1]:
        h.rem(i, step.pick)
    elif step.op == "update" and h.versions[i][1]:
        h.update(i, step.pick, step.x)
    elif step.op == "rem_absent":
        h.rem_absent(i, order)
    elif step.op == "look":
        h.look(i, order, step.pick)
    elif step.op == "bad":
        h.bad_call(i, order, step.pick, step.x)
    else:
        h.add(i, order, step.x)


def _t_persistence(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    @given(_programs(cfg.dims))
    def persistence(program: tuple[int, tuple[Step, ...]]) -> None:
        n, steps = program
        h = _History(cfg, n, _pool(cfg, pool_size(n)))
        for step in steps:
            _apply(h, step)
            h.check_all()

    hs(persistence)()


def _machine(cfg: SimpCompSuiteConfig) -> type[RuleBasedStateMachine]:
    """The stateful test's machine class for ``cfg`` (a class per configuration: rules cannot take one)."""
    top = pool_size(max(cfg.dims))
    perm = st.permutations(range(top)).map(tuple)
    at = st.integers(0, 7)
    pick = st.integers(0, 7)

    def has_simplices(self: SimpCompHistory) -> bool:
        return self.h is not None and bool(self.h.nonempty())

    class SimpCompHistory(RuleBasedStateMachine):
        """Every version ever made, each with its model, rechecked after every step.

        Each rule applies one operation to a version ``at`` steps before the
        latest (old versions too: branching histories) and checks it by that
        operation's law (which also checks the new version against its model
        and the old one against its own); the invariant then applies the
        persistence law to *all* versions.
        """

        def __init__(self) -> None:
            super().__init__()
            self.h: _History | None = None

        @property
        def hist(self) -> _History:
            assert self.h is not None, "the initialize rule runs first"
            return self.h

        def _order(self, p: tuple[int, ...]) -> list[int]:
            h = self.hist
            return _first_indices(p, len(h.pool), h.n + 1)

        @initialize(n=st.sampled_from(cfg.dims))
        def start(self, n: int) -> None:
            self.h = _History(cfg, n, _pool(cfg, pool_size(n)))

        @rule(at=at, p=perm, x=_VALUES)
        def add(self, at: int, p: tuple[int, ...], x: Any) -> None:
            h = self.hist
            h.add(_back(len(h.versions), at), self._order(p), x)

        @precondition(has_simplices)
        @rule(at=at, pick=pick)
        def rem(self, at: int, pick: int) -> None:
            h = self.hist
            full = h.nonempty()
            h.rem(full[_back(len(full), at)], pick)

        @precondition(has_simplices)
        @rule(at=at, pick=pick, tag=st.integers(0, 3))
        def update(self, at: int, pick: int, tag: int) -> None:
            h = self.hist
            full = h.nonempty()
            h.update(full[_back(len(full), at)], pick, tag)

        @rule(at=at, p=perm)
        def rem_absent(self, at: int, p: tuple[int, ...]) -> None:
            h = self.hist
            h.rem_absent(_back(len(h.versions), at), self._order(p))

        @rule(at=at, p=perm, d=st.integers(0, 24))
        def look(self, at: int, p: tuple[int, ...], d: int) -> None:
            h = self.hist
            h.look(_back(len(h.versions), at), self._order(p), d)

        @rule(at=at, p=perm, kind=st.integers(0, 6), x=_VALUES)
        def bad_call(self, at: int, p: tuple[int, ...], kind: int, x: Any) -> None:
            h = self.hist
            h.bad_call(_back(len(h.versions), at), self._order(p), kind, x)

        @invariant()
        def every_version_unchanged(self) -> None:
            if self.h is not None:
                self.h.check_all()

    return SimpCompHistory


def _t_stateful(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    if cfg.stateful_steps == 0:
        raise ConformanceSkip("stateful_steps = 0")
    run_state_machine_as_test(_machine(cfg), settings=settings(hs, stateful_step_count=cfg.stateful_steps))


# -- the workload ------------------------------------------------------------------------------------


def _t_workload(cfg: SimpCompSuiteConfig, hs: settings) -> None:
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
        pool, tops = _closed(cfg, n, size)
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
            for u in _subdivide(t, n + 2 + j):
                add(u)
                tops.append(u)
            if (j + 1) % every == 0:
                _check(cfg, c, f"in the workload of dimension {n} after {j + 1} subdivisions")
                snapshots.append((c, dict(model)))
        law_agrees(C, c, n, model, f"the workload's final complex in dimension {n}")
        if n >= 2:
            law_neighbour(C, c, n)
        law_persistence(C, n, snapshots)


# -- the suite ---------------------------------------------------------------------------------------


def _test(name: str, laws: tuple[str, ...], doc: str, body: Callable[[SimpCompSuiteConfig, settings], None]) -> ConformanceTest[SimpCompSuiteConfig]:
    return ConformanceTest(name, laws, doc, body)


SIMPCOMP_TESTS: tuple[ConformanceTest[SimpCompSuiteConfig], ...] = (
    _test("vertex", ("compare_total", "new_loc", "new_deterministic", "new_fresh"), "the VERTEX laws of Simplex.Vertex", _t_vertex),
    _test(
        "simplex",
        ("dim", "simplex_vertices", "compare_order", "compare_orientation", "faces_induced", "down_join", "flip"),
        "the SIMPLEX laws of Simplex",
        _t_simplex,
    ),
    _test("new", ("new",), "new(n) is the empty n-complex in each dimension", _t_new),
    _test("agrees", ("agrees",), "random complexes agree with their models", _case_test("agrees", _c_agrees)),
    _test("add", ("add", "persistence"), "add of a free simplex", _case_test("add", _c_add)),
    _test("add_present", ("add_present", "persistence"), "add of a held simplex, either orientation, is refused", _case_test("add_present", _c_add_present, 1)),
    _test("rem", ("rem", "persistence"), "rem of a held simplex, in any order of its orientation", _case_test("rem", _c_rem, 1)),
    _test("rem_absent", ("rem_absent", "persistence"), "rem of a simplex absent in that orientation is refused", _case_test("rem_absent", _c_rem_absent)),
    _test("add_rem_inverse", ("add_rem_inverse",), "rem(add(c, s, x), s) holds what c holds", _case_test("add_rem_inverse", _c_add_rem_inverse)),
    _test("update", ("update", "persistence"), "update calls f once and changes one datum", _case_test("update", _c_update, 1)),
    _test("find", ("find",), "find of (n-1)-simplices, both orientations of held faces", _case_test("find", _c_find)),
    _test("grep", ("grep",), "grep of simplices of every dimension, in every dimension d", _case_test("grep", _c_grep)),
    _test("neighbour", ("neighbour", "add", "rem", "persistence"), "closed complexes (subdivided simplex boundaries): find gives the neighbours", _t_neighbour),
    _test("bad_input", ("bad_input", "add_present", "rem_absent"), "wrong dimensions, repeated vertices, held orientations: refused, version intact", _t_bad_input),
    _test("invariants", ("invariants",), "the structure's check accepts every version", _t_invariants),
    _test("persistence", ("persistence",), "random branching programs; every version rechecked after each step", _t_persistence),
    _test(
        "stateful_history",
        ("persistence", "add", "add_present", "rem", "rem_absent", "update", "find", "grep", "bad_input", "invariants"),
        "a state machine keeping every version (multiple futures), all rechecked after every step",
        _t_stateful,
    ),
    _test("workload", ("add", "rem", "agrees", "neighbour", "persistence", "invariants"), "workload_size subdivisions of a closed complex", _t_workload),
)
"""Every test of the suite, in the order they run; :class:`SimpCompConformance` has one ``test_<name>`` per entry."""

_TESTS_BY_NAME = {t.name: t for t in SIMPCOMP_TESTS}


class SimpCompConformance:
    """Base class of a pytest test class that checks one ``SIMPCOMP`` structure.

    Subclass it in a test module (the subclass's name must start with ``Test``),
    set ``structure`` and say how to make vertices; each ``test_*`` method runs
    one entry of :data:`SIMPCOMP_TESTS`.  Knobs (class attributes):

    * ``structure`` — the structure under test (a class is instantiated with no arguments);
    * ``state`` — a vertex state (or a function of no arguments returning a fresh one)
      the suite makes vertices from with ``Simplex.Vertex.new``; or override
      :meth:`make_vertices` instead (the VERTEX laws of ``new`` are then skipped);
    * ``dims = (2,)`` — the dimensions n of the complexes tested;
    * ``check = True`` — call the structure's ``check(c)`` (or ``_check(c)``) on every version;
    * ``stateful_steps = 25`` — steps per example of the stateful test;
    * ``workload_size = 300`` — subdivisions in the workload (0 skips it);
    * ``max_examples = None`` — hypothesis examples per test (None: the active profile's).

    Hypothesis runs with your active settings profile (deadline off).
    """

    structure: ClassVar[Any] = None
    state: ClassVar[Any] = None
    dims: ClassVar[tuple[int, ...]] = (2,)
    check: ClassVar[bool] = True
    stateful_steps: ClassVar[int] = 25
    workload_size: ClassVar[int] = 300
    max_examples: ClassVar[int | None] = None

    def make_vertices(self, k: int) -> Sequence[Any]:
        """``k`` distinct fresh vertices of the structure (override this, or set ``state``)."""
        raise TypeError(
            f"{type(self).__name__}: set `state = <a vertex state, or a function returning one>` "
            "or override make_vertices(self, k) (the VERTEX signature has no initial state)"
        )

    def conformance_config(self) -> SimpCompSuiteConfig:
        """The suite's configuration from the class attributes; :class:`NotASimpComp` for a bad ``structure``."""
        cls = type(self)
        if cls.structure is None:
            raise TypeError(f"{cls.__name__}: set `structure = <your SIMPCOMP structure>` in the class body")
        s = as_simpcomp(cls.structure, f"{cls.__name__}.structure")
        vertices: Callable[[int], Sequence[Any]]
        if cls.make_vertices is not SimpCompConformance.make_vertices:
            vertices = self.make_vertices
        elif cls.state is not None:
            vertices = vertices_from_state(s, cls.state)
        else:
            vertices = self.make_vertices  # raises, saying what to set
            vertices(0)
        return SimpCompSuiteConfig(s, vertices, cls.state, tuple(cls.dims), bool(cls.check), cls.stateful_steps, cls.workload_size)

    def run_conformance_test(self, name: str) -> None:
        """Run the suite's test ``name`` under the active hypothesis profile (a skip becomes a pytest skip)."""
        test = _TESTS_BY_NAME[name]
        cfg = self.conformance_config()
        hs = settings(deadline=None) if self.max_examples is None else settings(deadline=None, max_examples=self.max_examples)
        try:
            test.body(cfg, hs)
        except ConformanceSkip as skip:
            import pytest  # only here: run_simpcomp_conformance works without pytest

            pytest.skip(str(skip))

    def test_vertex(self) -> None:
        """The VERTEX laws of the structure's Simplex.Vertex."""
        self.run_conformance_test("vertex")

    def test_simplex(self) -> None:
        """The SIMPLEX laws of the structure's Simplex."""
        self.run_conformance_test("simplex")

    def test_new(self) -> None:
        """new(n) is the empty n-complex."""
        self.run_conformance_test("new")

    def test_agrees(self) -> None:
        """Random complexes agree with their models."""
        self.run_conformance_test("agrees")

    def test_add(self) -> None:
        """add of a free simplex."""
        self.run_conformance_test("add")

    def test_add_present(self) -> None:
        """add of a held simplex (either orientation) is refused, the version intact."""
        self.run_conformance_test("add_present")

    def test_rem(self) -> None:
        """rem of a held simplex."""
        self.run_conformance_test("rem")

    def test_rem_absent(self) -> None:
        """rem of an absent simplex is refused, the version intact."""
        self.run_conformance_test("rem_absent")

    def test_add_rem_inverse(self) -> None:
        """rem(add(c, s, x), s) holds what c holds."""
        self.run_conformance_test("add_rem_inverse")

    def test_update(self) -> None:
        """update calls f once and changes one datum."""
        self.run_conformance_test("update")

    def test_find(self) -> None:
        """find of (n-1)-simplices, orientation included."""
        self.run_conformance_test("find")

    def test_grep(self) -> None:
        """grep in every dimension."""
        self.run_conformance_test("grep")

    def test_neighbour(self) -> None:
        """In closed complexes find gives the neighbours."""
        self.run_conformance_test("neighbour")

    def test_bad_input(self) -> None:
        """Bad calls raise ValueError/TypeError and leave the version intact."""
        self.run_conformance_test("bad_input")

    def test_invariants(self) -> None:
        """The structure's own check accepts every version."""
        self.run_conformance_test("invariants")

    def test_persistence(self) -> None:
        """Random branching programs: every version unchanged by later operations."""
        self.run_conformance_test("persistence")

    def test_stateful_history(self) -> None:
        """A state machine keeps every version and rechecks all of them after each step."""
        self.run_conformance_test("stateful_history")

    def test_workload(self) -> None:
        """workload_size subdivisions of a closed complex."""
        self.run_conformance_test("workload")


def run_simpcomp_conformance(
    structure: object,
    *,
    state: Any = None,
    vertices: Callable[[int], Sequence[Any]] | None = None,
    dims: Iterable[int] = (2,),
    max_examples: int = 100,
    check: bool = True,
    stateful_steps: int = 25,
    workload_size: int = 300,
    name: str | None = None,
    tests: Iterable[str] | None = None,
    derandomize: bool = False,
) -> ConformanceReport:
    """Run the whole ``SIMPCOMP`` suite on ``structure`` without pytest and report every failure.

    Vertices come from ``vertices(k)`` or, when it is None, from ``state``
    (a vertex state, or a function of no arguments returning one) through
    ``Simplex.Vertex.new``; one of the two is needed.  ``max_examples`` is
    hypothesis's per test (explicit settings: the loaded profile does not
    matter); ``tests`` runs only the named entries of :data:`SIMPCOMP_TESTS`;
    ``derandomize`` makes the run reproducible.  Raises :class:`NotASimpComp`
    (a :class:`TypeError`) when ``structure`` lacks operations, and
    :class:`ValueError`/:class:`TypeError` for a bad knob; a failing law is
    never raised, it is reported.
    """
    if isinstance(max_examples, bool) or not isinstance(max_examples, int) or max_examples < 1:
        raise ValueError(f"max_examples must be a positive int, got {max_examples!r}")
    if tests is None:
        selected = SIMPCOMP_TESTS
    else:
        wanted = list(tests)
        unknown = [t for t in wanted if t not in _TESTS_BY_NAME]
        if unknown:
            raise ValueError(f"unknown conformance tests {unknown}; known: {', '.join(_TESTS_BY_NAME)}")
        selected = tuple(t for t in SIMPCOMP_TESTS if t.name in wanted)
    label = name if name is not None else repr(structure)
    s = as_simpcomp(structure, label)
    if vertices is None:
        if state is None:
            raise TypeError("run_simpcomp_conformance: give state= (a vertex state) or vertices= (k -> k vertices)")
        vertices = vertices_from_state(s, state)
    cfg = SimpCompSuiteConfig(s, vertices, state, tuple(dims), check, stateful_steps, workload_size)
    options: list[tuple[str, object]] = [
        ("dims", ",".join(map(str, cfg.dims))),
        ("max_examples", max_examples),
        ("workload_size", workload_size),
        ("check", check),
    ]
    return run_tests(
        selected,
        cfg,
        explicit_settings(max_examples, derandomize=derandomize),
        structure=label,
        signature="SIMPCOMP",
        options=options,
    )
