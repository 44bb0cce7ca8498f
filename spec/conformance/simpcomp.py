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
neighbour law on closed complexes (boundaries of simplices, subdivided); a
workload of ``workload_size`` subdivisions; the growth workload, which checks
persistence at every size up to ten times ``workload_size`` n-simplices
(:mod:`.simpcomp_growth`); and the tests of hidden state, ``determinism`` and
``isolation`` (:mod:`.simpcomp_determinism`).  With ``check`` the structure's
own ``check(c)`` (or ``_check(c)``) runs on every version made.  Failures are
named as in the ``ORD_MAP`` suite (:mod:`.ord_map`): hypothesis's ``Flaky``,
and failures a rerun on a second instance does not reproduce, as ``determinism``.

The suite lives in one module per concept: the configuration
(:mod:`.simpcomp_config`), the branching history and simplex helpers
(:mod:`.simpcomp_history`), the random complexes (:mod:`.simpcomp_cases`), the
law tests (:mod:`.simpcomp_law_tests`), the random programs and the state
machine (:mod:`.simpcomp_stateful`), closed complexes and their workload
(:mod:`.simpcomp_workloads`), the growth workload (:mod:`.simpcomp_growth`,
:mod:`.simpcomp_growth_plan`), the hidden-state tests; this module assembles them.

Vertices are the structure's own; they must be hashable (the models are
dicts) and are never looked inside.  Data are arbitrary values, ``None``
included.  Hypothesis settings: under pytest the tests use your *active*
profile (deadline off; ``max_examples`` overrides its example count);
:func:`run_simpcomp_conformance` uses explicit settings, independent of any profile.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable, Iterable, Sequence
from typing import Any, ClassVar

from hypothesis import settings

from persistri.spec.conformance.hidden_state import fresh_for
from persistri.spec.conformance.runner import (
    ConformanceReport,
    ConformanceSkip,
    ConformanceTest,
    explicit_settings,
    run_body,
    run_tests,
)
from persistri.spec.conformance.simpcomp_cases import case_test
from persistri.spec.conformance.simpcomp_config import (
    SIMPCOMP_OPERATIONS,
    NotASimpComp,
    SimpCompSuiteConfig,
    as_simpcomp,
    missing_simpcomp_operations,
    second_config,
    vertices_from_state,
)
from persistri.spec.conformance.simpcomp_determinism import t_determinism, t_isolation
from persistri.spec.conformance.simpcomp_growth import t_growth
from persistri.spec.conformance.simpcomp_law_tests import (
    c_add,
    c_add_present,
    c_add_rem_inverse,
    c_agrees,
    c_find,
    c_grep,
    c_rem,
    c_rem_absent,
    c_update,
    t_bad_input,
    t_invariants,
    t_new,
    t_simplex,
    t_vertex,
)
from persistri.spec.conformance.simpcomp_stateful import t_persistence, t_stateful
from persistri.spec.conformance.simpcomp_workloads import t_neighbour, t_workload
from persistri.spec.simpcomp_laws import LawViolation

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


def _test(
    name: str, laws: tuple[str, ...], doc: str, body: Callable[[SimpCompSuiteConfig, settings], None], *, confirm: bool = True
) -> ConformanceTest[SimpCompSuiteConfig]:
    return ConformanceTest(name, laws, doc, body, confirm)


SIMPCOMP_TESTS: tuple[ConformanceTest[SimpCompSuiteConfig], ...] = (
    _test("vertex", ("compare_total", "new_loc", "new_deterministic", "new_fresh"), "the VERTEX laws of Simplex.Vertex", t_vertex),
    _test(
        "simplex",
        ("dim", "simplex_vertices", "compare_order", "compare_orientation", "faces_induced", "down_join", "flip"),
        "the SIMPLEX laws of Simplex",
        t_simplex,
    ),
    _test("new", ("new",), "new(n) is the empty n-complex in each dimension", t_new),
    _test("agrees", ("agrees",), "random complexes agree with their models", case_test("agrees", c_agrees)),
    _test("add", ("add", "persistence"), "add of a free simplex", case_test("add", c_add)),
    _test("add_present", ("add_present", "persistence"), "add of a held simplex, either orientation, is refused", case_test("add_present", c_add_present, 1)),
    _test("rem", ("rem", "persistence"), "rem of a held simplex, in any order of its orientation", case_test("rem", c_rem, 1)),
    _test("rem_absent", ("rem_absent", "persistence"), "rem of a simplex absent in that orientation is refused", case_test("rem_absent", c_rem_absent)),
    _test("add_rem_inverse", ("add_rem_inverse",), "rem(add(c, s, x), s) holds what c holds", case_test("add_rem_inverse", c_add_rem_inverse)),
    _test("update", ("update", "persistence"), "update calls f once and changes one datum", case_test("update", c_update, 1)),
    _test("find", ("find",), "find of (n-1)-simplices, both orientations of held faces", case_test("find", c_find)),
    _test("grep", ("grep",), "grep of simplices of every dimension, in every dimension d", case_test("grep", c_grep)),
    _test("neighbour", ("neighbour", "add", "rem", "persistence"), "closed complexes (subdivided simplex boundaries): find gives the neighbours", t_neighbour),
    _test("bad_input", ("bad_input", "add_present", "rem_absent"), "wrong dimensions, repeated vertices, held orientations: refused, version intact", t_bad_input),
    _test("invariants", ("invariants",), "the structure's check accepts every version", t_invariants),
    _test("persistence", ("persistence",), "random branching programs; every version rechecked after each step", t_persistence),
    _test(
        "stateful_history",
        ("persistence", "add", "add_present", "rem", "rem_absent", "update", "find", "grep", "bad_input", "invariants"),
        "a state machine keeping every version (multiple futures), all rechecked after every step",
        t_stateful,
    ),
    _test("workload", ("add", "rem", "agrees", "neighbour", "persistence", "invariants"), "workload_size subdivisions of a closed complex", t_workload),
    _test(
        "growth",
        ("persistence", "add", "rem", "update", "rem_absent", "add_present", "agrees", "neighbour", "invariants", "determinism"),
        "grow to 10 × workload_size n-simplices, branch from kept versions, recheck every kept version",
        t_growth,
        confirm=False,  # its replays pin each failure to its operation and confirm it
    ),
    _test(
        "determinism",
        ("determinism",),
        "one session replayed: versions kept, versions freed (ids reused), on a second instance",
        t_determinism,
        confirm=False,
    ),
    _test(
        "isolation",
        ("isolation",),
        "two instances: operations on one never change the other's versions",
        t_isolation,
        confirm=False,
    ),
)
"""Every test of the suite, in the order they run; :class:`SimpCompConformance` has one ``test_<name>`` per entry."""

_TESTS_BY_NAME = {t.name: t for t in SIMPCOMP_TESTS}


_FRESH: weakref.WeakKeyDictionary[type, Callable[[], Any] | None] = weakref.WeakKeyDictionary()
"""Per test class, how second instances of its structure are made (:func:`~.hidden_state.fresh_for`)."""


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
    * ``workload_size = 300`` — subdivisions in the workload; the growth workload grows to ten
      times as many n-simplices (0 skips both);
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
        if cls not in _FRESH:  # one snapshot per test class, taken before its first test runs
            _FRESH[cls] = fresh_for(cls.structure, s)
        fresh = _FRESH[cls]
        return SimpCompSuiteConfig(
            s, vertices, cls.state, tuple(cls.dims), bool(cls.check), cls.stateful_steps, cls.workload_size, fresh
        )

    def run_conformance_test(self, name: str) -> None:
        """Run the suite's test ``name`` under the active hypothesis profile (a skip becomes a pytest skip)."""
        test = _TESTS_BY_NAME[name]
        cfg = self.conformance_config()
        hs = settings(deadline=None, report_multiple_bugs=False)
        if self.max_examples is not None:
            hs = settings(hs, max_examples=self.max_examples)
        try:
            run_body(test, cfg, hs, LawViolation, second_config)
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

    def test_growth(self) -> None:
        """Grow to 10 × workload_size n-simplices keeping versions, branch from old ones, recheck every kept version."""
        self.run_conformance_test("growth")

    def test_determinism(self) -> None:
        """One session replayed (versions kept, versions freed, a second instance) gives equal answers."""
        self.run_conformance_test("determinism")

    def test_isolation(self) -> None:
        """Operations on one instance never change what another instance's versions show."""
        self.run_conformance_test("isolation")


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
    fresh = fresh_for(structure, s)
    cfg = SimpCompSuiteConfig(s, vertices, state, tuple(dims), check, stateful_steps, workload_size, fresh)
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
        violation=LawViolation,
        second=second_config,
        options=options,
    )
