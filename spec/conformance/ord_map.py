"""The ``ORD_MAP`` conformance suite: is *your* persistent map a correct ``ORD_MAP``?

Point it at a structure (an object whose methods are the operations of
:class:`~persistri.spec.ord_map.OrdMap`) in one of two ways:

* **pytest** — subclass :class:`OrdMapConformance` in your test file and set
  ``structure``; pytest collects the ``test_*`` methods (the pattern of zarr's
  ``StoreTests``)::

      from persistri.spec.conformance import OrdMapConformance
      from mypackage import my_map

      class TestMyMap(OrdMapConformance):
          structure = my_map

* **a program** — :func:`run_conformance` returns a
  :class:`~persistri.spec.conformance.runner.ConformanceReport`; the command
  ``persistri conformance maps MODULE:ATTR`` prints it.

Both run the same test bodies (:data:`ORD_MAP_TESTS`): a hypothesis test of
every law of :mod:`persistri.spec.ord_map_laws`; a stateful test that keeps
*every* version with a model snapshot and rechecks all of them after each step,
on branching histories; edge cases (the empty map, removing an absent key,
overwriting, removing the last key, colliding hashes, ``None`` values); two
workloads of ``workload_size`` keys (sequential and random: insert all, find
all, remove all, with ``_check`` every n/10 steps and at the end); the growth
workload, which checks persistence at every size up to ``workload_size``
(:mod:`.ord_map_growth`); and the tests of hidden state, ``determinism`` and
``isolation`` (:mod:`.ord_map_determinism`).  A failure that hypothesis could
not reproduce (``Flaky``), or that a rerun on a second instance does not
reproduce, is reported under ``determinism`` (:mod:`.runner`).

The suite lives in one module per concept: the configuration
(:mod:`.ord_map_config`), the branching history with its model snapshots
(:mod:`.ord_map_history`), the random programs and the state machine
(:mod:`.ord_map_stateful`), the law tests (:mod:`.ord_map_law_tests`), the
edge cases (:mod:`.ord_map_edges`), the workloads (:mod:`.ord_map_workloads`,
:mod:`.ord_map_growth`), the hidden-state tests; this module assembles them.

Hypothesis settings: under pytest the tests use your *active* profile, except
that the deadline is off (the suite checks results, not speed) and the
stateful test runs ``stateful_steps`` steps; :func:`run_conformance` uses
explicit settings, independent of any profile.

Keys are Python integers and, with ``hashing``, :class:`CollidingKey` s (see
:mod:`persistri.spec.conformance.strategies`); values are arbitrary.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable, Iterable
from typing import Any, ClassVar

from hypothesis import settings

from persistri.spec.conformance.hidden_state import fresh_for
from persistri.spec.conformance.ord_map_config import (
    ORD_MAP_OPERATIONS,
    NotAnOrdMap,
    SuiteConfig,
    as_structure,
    missing_operations,
    second_config,
)
from persistri.spec.conformance.ord_map_determinism import t_determinism, t_isolation
from persistri.spec.conformance.ord_map_edges import (
    t_edge_colliding_hashes,
    t_edge_empty_map,
    t_edge_none_value,
    t_edge_overwrite,
    t_edge_remove_absent,
    t_edge_remove_last_key,
)
from persistri.spec.conformance.ord_map_growth import t_growth
from persistri.spec.conformance.ord_map_history import combine
from persistri.spec.conformance.ord_map_law_tests import (
    case_test,
    inDomain_all,
    lookup_all,
    probed,
    t_empty,
    t_invariants,
    t_key_order,
    t_singleton,
)
from persistri.spec.conformance.ord_map_stateful import t_persistence, t_stateful
from persistri.spec.conformance.ord_map_workloads import t_workload_random, t_workload_sequential
from persistri.spec.conformance.runner import (
    ConformanceReport,
    ConformanceSkip,
    ConformanceTest,
    explicit_settings,
    run_body,
    run_tests,
)
from persistri.spec.ord_map_laws import (
    LawViolation,
    law_find_insert,
    law_find_insert_other,
    law_foldli,
    law_insertWith,
    law_isEmpty,
    law_listItemsi,
    law_listKeys,
    law_numItems_insert,
    law_remove,
    law_remove_absent,
)

__all__ = [
    "ORD_MAP_OPERATIONS",
    "ORD_MAP_TESTS",
    "NotAnOrdMap",
    "OrdMapConformance",
    "SuiteConfig",
    "as_structure",
    "missing_operations",
    "run_conformance",
]

def _test(
    name: str, laws: tuple[str, ...], doc: str, body: Callable[[SuiteConfig, settings], None], *, confirm: bool = True
) -> ConformanceTest[SuiteConfig]:
    return ConformanceTest(name, laws, doc, body, confirm)


ORD_MAP_TESTS: tuple[ConformanceTest[SuiteConfig], ...] = (
    _test("key_order", ("key_order",), "Key.compare is a total order on generated keys", t_key_order),
    _test("empty", ("empty",), "empty is empty", t_empty),
    _test("singleton", ("singleton",), "singleton(k, v) = insert(empty, k, v)", t_singleton),
    _test(
        "find_insert",
        ("find_insert",),
        "find(insert(m, k, v), k) = SOME v",
        case_test("find_insert", "any", lambda s, m, c: law_find_insert(s, m, c.key, c.value)),
    ),
    _test(
        "find_insert_other",
        ("find_insert_other",),
        "find(insert(m, k, v), j) = find(m, j) for j ≠ k",
        case_test("find_insert_other", "any", lambda s, m, c: law_find_insert_other(s, m, c.key, c.value, probed(c))),
    ),
    _test("lookup", ("lookup",), "lookup agrees with find; NotFound when absent", case_test("lookup", "any", lookup_all)),
    _test("inDomain", ("inDomain",), "inDomain = isSome o find", case_test("inDomain", "any", inDomain_all)),
    _test(
        "insertWith",
        ("insertWith",),
        "insertWith stores f(old, v), or v for a new key",
        case_test("insertWith", "any", lambda s, m, c: law_insertWith(s, combine, m, c.key, c.value, probed(c))),
    ),
    _test(
        "numItems_insert",
        ("numItems_insert",),
        "numItems grows by one for a new key, not for an overwrite",
        case_test("numItems_insert", "any", lambda s, m, c: law_numItems_insert(s, m, c.key, c.value)),
    ),
    _test(
        "remove",
        ("remove",),
        "remove of a present key returns its value and changes nothing else",
        case_test("remove", "present", lambda s, m, c: law_remove(s, m, c.key)),
    ),
    _test(
        "remove_absent",
        ("remove_absent",),
        "remove of an absent key raises NotFound",
        case_test("remove_absent", "absent", lambda s, m, c: law_remove_absent(s, m, c.key)),
    ),
    _test(
        "listItemsi",
        ("listItemsi",),
        "listItemsi is sorted, complete and agrees with find",
        case_test("listItemsi", "any", lambda s, m, c: law_listItemsi(s, m, [c.key, *c.removed, *c.probes])),
    ),
    _test("listKeys", ("listKeys",), "listKeys = keys of listItemsi", case_test("listKeys", "any", lambda s, m, c: law_listKeys(s, m))),
    _test("foldli", ("foldli",), "foldli visits the items in increasing order", case_test("foldli", "any", lambda s, m, c: law_foldli(s, m))),
    _test("isEmpty", ("isEmpty",), "isEmpty exactly when numItems = 0", case_test("isEmpty", "any", lambda s, m, c: law_isEmpty(s, m))),
    _test("persistence", ("persistence",), "random branching programs; every version rechecked after each step", t_persistence),
    _test("invariants", ("invariants",), "_check accepts every map the operations make", t_invariants),
    _test(
        "stateful_history",
        ("persistence", "find_insert", "find_insert_other", "numItems_insert", "insertWith", "remove", "remove_absent",
         "listItemsi", "lookup", "inDomain", "listKeys", "foldli", "isEmpty", "invariants"),
        "a state machine keeping every version (multiple futures), all rechecked after every step",
        t_stateful,
    ),
    _test("edge_empty_map", ("empty", "lookup", "remove_absent"), "every operation on the empty map", t_edge_empty_map),
    _test("edge_remove_absent", ("remove_absent",), "removing absent keys below, between and above, and twice", t_edge_remove_absent),
    _test("edge_overwrite", ("numItems_insert", "find_insert"), "overwriting a key (with None and back)", t_edge_overwrite),
    _test("edge_remove_last_key", ("remove",), "removing the last key leaves a working empty map", t_edge_remove_last_key),
    _test("edge_colliding_hashes", ("find_insert", "remove"), "keys whose hashes collide stay distinct", t_edge_colliding_hashes),
    _test("edge_none_value", ("find_insert", "lookup", "remove"), "None as a stored value: find returns (None,)", t_edge_none_value),
    _test(
        "workload_sequential",
        ("numItems_insert", "find_insert", "remove", "invariants", "persistence"),
        "workload_size increasing keys: insert, find, remove all",
        t_workload_sequential,
    ),
    _test(
        "workload_random",
        ("numItems_insert", "find_insert", "remove", "invariants", "persistence"),
        "workload_size random keys: insert, find, remove all (another order)",
        t_workload_random,
    ),
    _test(
        "growth",
        ("persistence", "find_insert", "insertWith", "remove", "remove_absent", "invariants", "determinism"),
        "grow to workload_size keys, branch from kept versions, recheck every kept version",
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
"""Every test of the suite, in the order they run; :class:`OrdMapConformance` has one ``test_<name>`` per entry."""

_TESTS_BY_NAME = {t.name: t for t in ORD_MAP_TESTS}


_FRESH: weakref.WeakKeyDictionary[type, Callable[[], Any] | None] = weakref.WeakKeyDictionary()
"""Per test class, how second instances of its structure are made (:func:`~.hidden_state.fresh_for`)."""


class OrdMapConformance:
    """Base class of a pytest test class that checks one ``ORD_MAP`` structure.

    Subclass it in a test module (the subclass's name must start with ``Test``)
    and set ``structure``; each ``test_*`` method runs one entry of
    :data:`ORD_MAP_TESTS`.  Knobs (class attributes):

    * ``structure`` — the structure under test (a class is instantiated with no arguments);
    * ``hashing = True`` — also use keys whose hashes collide;
    * ``workload_size = 100_000`` — keys in each workload, the growth workload's
      included; a backend that is O(n) per operation sets it lower (say why),
      0 skips the workloads;
    * ``check = True`` — call the structure's ``_check(m)`` after each step when it has one;
    * ``stateful_steps = 25`` — steps per example of the stateful test.

    Hypothesis runs with your active settings profile (deadline off).
    """

    structure: ClassVar[Any] = None
    hashing: ClassVar[bool] = True
    workload_size: ClassVar[int] = 100_000
    check: ClassVar[bool] = True
    stateful_steps: ClassVar[int] = 25

    def conformance_config(self) -> SuiteConfig:
        """The suite's configuration from the class attributes; :class:`NotAnOrdMap` for a bad ``structure``."""
        cls = type(self)
        if cls.structure is None:
            raise TypeError(f"{cls.__name__}: set `structure = <your ORD_MAP structure>` in the class body")
        s = as_structure(cls.structure, f"{cls.__name__}.structure")
        if cls not in _FRESH:  # one snapshot per test class, taken before its first test runs
            _FRESH[cls] = fresh_for(cls.structure, s)
        fresh = _FRESH[cls]
        return SuiteConfig(s, bool(cls.hashing), cls.workload_size, bool(cls.check), cls.stateful_steps, fresh)

    def run_conformance_test(self, name: str) -> None:
        """Run the suite's test ``name`` under the active hypothesis profile (a skip becomes a pytest skip)."""
        test = _TESTS_BY_NAME[name]
        cfg = self.conformance_config()
        try:
            run_body(test, cfg, settings(deadline=None, report_multiple_bugs=False), LawViolation, second_config)
        except ConformanceSkip as skip:
            import pytest  # only here: run_conformance works without pytest

            pytest.skip(str(skip))

    def test_key_order(self) -> None:
        """Key.compare is a total order on the keys the suite uses."""
        self.run_conformance_test("key_order")

    def test_empty(self) -> None:
        """empty is empty and has no items."""
        self.run_conformance_test("empty")

    def test_singleton(self) -> None:
        """singleton(k, v) = insert(empty, k, v)."""
        self.run_conformance_test("singleton")

    def test_find_insert(self) -> None:
        """find(insert(m, k, v), k) = SOME v."""
        self.run_conformance_test("find_insert")

    def test_find_insert_other(self) -> None:
        """find(insert(m, k, v), j) = find(m, j) for j ≠ k."""
        self.run_conformance_test("find_insert_other")

    def test_lookup(self) -> None:
        """lookup agrees with find and raises NotFound when absent."""
        self.run_conformance_test("lookup")

    def test_inDomain(self) -> None:
        """inDomain(m, k) = isSome(find(m, k))."""
        self.run_conformance_test("inDomain")

    def test_insertWith(self) -> None:
        """insertWith stores f(old, v) when present, v otherwise."""
        self.run_conformance_test("insertWith")

    def test_numItems_insert(self) -> None:
        """numItems: +1 for a new key, +0 for an overwrite."""
        self.run_conformance_test("numItems_insert")

    def test_remove(self) -> None:
        """remove of a present key returns its value, drops it and keeps every other item."""
        self.run_conformance_test("remove")

    def test_remove_absent(self) -> None:
        """remove of an absent key raises NotFound."""
        self.run_conformance_test("remove_absent")

    def test_listItemsi(self) -> None:
        """listItemsi is strictly increasing, agrees with find and has numItems entries."""
        self.run_conformance_test("listItemsi")

    def test_listKeys(self) -> None:
        """listKeys = the keys of listItemsi."""
        self.run_conformance_test("listKeys")

    def test_foldli(self) -> None:
        """foldli visits the items in increasing key order."""
        self.run_conformance_test("foldli")

    def test_isEmpty(self) -> None:
        """isEmpty(m) exactly when numItems(m) = 0."""
        self.run_conformance_test("isEmpty")

    def test_persistence(self) -> None:
        """Every earlier version is unchanged by later operations (random branching programs)."""
        self.run_conformance_test("persistence")

    def test_invariants(self) -> None:
        """The structure's _check accepts every map its operations make."""
        self.run_conformance_test("invariants")

    def test_stateful_history(self) -> None:
        """A state machine keeps every version and rechecks all of them after each step."""
        self.run_conformance_test("stateful_history")

    def test_edge_empty_map(self) -> None:
        """Every operation on the empty map."""
        self.run_conformance_test("edge_empty_map")

    def test_edge_remove_absent(self) -> None:
        """Removing absent keys raises NotFound and leaves the map unchanged."""
        self.run_conformance_test("edge_remove_absent")

    def test_edge_overwrite(self) -> None:
        """Overwriting a key keeps the count and replaces the value."""
        self.run_conformance_test("edge_overwrite")

    def test_edge_remove_last_key(self) -> None:
        """Removing the last key leaves a working empty map."""
        self.run_conformance_test("edge_remove_last_key")

    def test_edge_colliding_hashes(self) -> None:
        """Distinct keys with equal hashes stay distinct."""
        self.run_conformance_test("edge_colliding_hashes")

    def test_edge_none_value(self) -> None:
        """None is a value like any other: find returns (None,)."""
        self.run_conformance_test("edge_none_value")

    def test_workload_sequential(self) -> None:
        """workload_size increasing keys: insert all, find all, remove all."""
        self.run_conformance_test("workload_sequential")

    def test_workload_random(self) -> None:
        """workload_size random keys: insert all, find all, remove all in another order."""
        self.run_conformance_test("workload_random")

    def test_growth(self) -> None:
        """Grow to workload_size keys keeping versions, branch from old ones, recheck every kept version."""
        self.run_conformance_test("growth")

    def test_determinism(self) -> None:
        """One session replayed (versions kept, versions freed, a second instance) gives equal answers."""
        self.run_conformance_test("determinism")

    def test_isolation(self) -> None:
        """Operations on one instance never change what another instance's versions show."""
        self.run_conformance_test("isolation")


def run_conformance(
    structure: object,
    *,
    max_examples: int = 100,
    workload_size: int = 100_000,
    hashing: bool = True,
    check: bool = True,
    stateful_steps: int = 25,
    name: str | None = None,
    tests: Iterable[str] | None = None,
    derandomize: bool = False,
) -> ConformanceReport:
    """Run the whole ``ORD_MAP`` suite on ``structure`` without pytest and report every failure.

    ``max_examples`` is hypothesis's per test (explicit settings: the loaded
    profile does not matter); the other knobs are :class:`SuiteConfig`'s.
    ``name`` is how the report calls the structure (default: its ``repr``);
    ``tests`` runs only the named entries of :data:`ORD_MAP_TESTS` (say, to
    rerun one failure); ``derandomize`` makes the run reproducible (the
    same examples every time).  Raises :class:`NotAnOrdMap` (a :class:`TypeError`) when ``structure`` lacks
    operations and :class:`ValueError` for a bad knob; a failing law is never
    raised, it is reported.  The time is dominated by the three workloads
    (O(workload_size) operations each: about 3 s each for the red-black tree at
    the default 100,000) and ``max_examples`` × the number of hypothesis tests.
    A class given as ``structure`` is instantiated, and instantiated again for
    a second instance (``isolation``, and the reruns that confirm a failure);
    an instance is deep-copied for that (a snapshot taken before any test runs).
    """
    if isinstance(max_examples, bool) or not isinstance(max_examples, int) or max_examples < 1:
        raise ValueError(f"max_examples must be a positive int, got {max_examples!r}")
    if tests is None:
        selected = ORD_MAP_TESTS
    else:
        wanted = list(tests)
        unknown = [t for t in wanted if t not in _TESTS_BY_NAME]
        if unknown:
            raise ValueError(f"unknown conformance tests {unknown}; known: {', '.join(_TESTS_BY_NAME)}")
        selected = tuple(t for t in ORD_MAP_TESTS if t.name in wanted)
    label = name if name is not None else repr(structure)
    s = as_structure(structure, label)
    fresh = fresh_for(structure, s)
    cfg = SuiteConfig(s, hashing, workload_size, check, stateful_steps, fresh)
    options: list[tuple[str, object]] = [
        ("max_examples", max_examples),
        ("workload_size", workload_size),
        ("hashing", hashing),
        ("check", check),
    ]
    hs = explicit_settings(max_examples, derandomize=derandomize)
    return run_tests(
        selected, cfg, hs, structure=label, signature="ORD_MAP", violation=LawViolation, second=second_config, options=options
    )
