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
overwriting, removing the last key, colliding hashes, ``None`` values); and two
workloads of ``workload_size`` keys (sequential and random: insert all, find
all, remove all, with ``_check`` every n/10 steps and at the end).

Hypothesis settings: under pytest the tests use your *active* profile, except
that the deadline is off (the suite checks results, not speed) and the
stateful test runs ``stateful_steps`` steps; :func:`run_conformance` uses
explicit settings, independent of any profile.

Keys are Python integers and, with ``hashing``, :class:`CollidingKey` s (see
:mod:`persistri.spec.conformance.strategies`); values are arbitrary.
"""

from __future__ import annotations

import functools
import random
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar, Literal

from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.stateful import (
    RuleBasedStateMachine,
    initialize,
    invariant,
    precondition,
    rule,
    run_state_machine_as_test,
)

from persistri.spec.conformance.runner import (
    ConformanceReport,
    ConformanceSkip,
    ConformanceTest,
    explicit_settings,
    run_tests,
)
from persistri.spec.conformance.strategies import (
    COLLIDING_INTS,
    CollidingKey,
    KeyKind,
    MapCase,
    fresh_key,
    key_kinds,
    keys,
    map_cases,
    small_keys,
    values,
)
from persistri.spec.ord_map import NotFound
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
    law_key_order,
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
    "ORD_MAP_OPERATIONS",
    "ORD_MAP_TESTS",
    "NotAnOrdMap",
    "OrdMapConformance",
    "SuiteConfig",
    "as_structure",
    "missing_operations",
    "run_conformance",
]

ORD_MAP_OPERATIONS: tuple[str, ...] = (
    "Key",
    "empty",
    "isEmpty",
    "singleton",
    "insert",
    "insertWith",
    "find",
    "lookup",
    "inDomain",
    "remove",
    "numItems",
    "listItemsi",
    "listKeys",
    "foldli",
)
"""The values of ``signature ORD_MAP``, in the signature's order (``Key`` is a structure with ``compare``)."""


def missing_operations(obj: object) -> list[str]:
    """The ``ORD_MAP`` operations the structure ``obj`` lacks or has as non-callables, in signature order.

    ``Key`` is reported as ``Key.compare`` when ``Key`` exists but has no
    callable ``compare``.  ``obj`` is the structure itself (an instance, not its
    class).  An empty list means every operation is there (not that they are right).
    """
    missing: list[str] = []
    for name in ORD_MAP_OPERATIONS:
        try:
            attr = getattr(obj, name)
        except Exception:  # a missing attribute, or a property that raises: either way unusable
            missing.append(name)
            continue
        if name == "Key":
            if not callable(getattr(attr, "compare", None)):
                missing.append("Key.compare")
        elif not callable(attr):
            missing.append(name)
    return missing


class NotAnOrdMap(TypeError):
    """The object given as a structure is not an ``ORD_MAP`` structure (it lacks operations)."""


def as_structure(obj: object, name: str | None = None) -> Any:
    """``obj`` as a structure: a class is instantiated with no arguments; raises :class:`NotAnOrdMap`
    naming the missing operations (``name`` is how messages call ``obj``)."""
    label = name if name is not None else repr(obj)
    if isinstance(obj, type):
        try:
            obj = obj()
        except Exception as exc:
            raise NotAnOrdMap(f"{label} is a class that cannot be instantiated with no arguments: {exc}") from None
    missing = missing_operations(obj)
    if missing:
        raise NotAnOrdMap(f"{label} is not an ORD_MAP structure: missing {', '.join(missing)}")
    return obj


@dataclass(frozen=True)
class SuiteConfig:
    """What the suite runs against and how hard.

    ``structure`` — the structure under test; ``hashing`` — also use keys whose
    hashes collide; ``workload_size`` — keys in each workload (0 skips them);
    ``check`` — call the structure's ``_check(m)`` after each step when it has
    one; ``stateful_steps`` — steps per stateful example.
    """

    structure: Any
    hashing: bool = True
    workload_size: int = 100_000
    check: bool = True
    stateful_steps: int = 25

    def __post_init__(self) -> None:
        for knob in ("workload_size", "stateful_steps"):
            value = getattr(self, knob)
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise ValueError(f"{knob} must be a non-negative int, got {value!r}")


# -- shared machinery: versions with model snapshots ----------------------------------------


def _combine(old: Any, new: Any) -> Any:
    """The ``insertWith`` function the suite uses: not commutative, so argument order shows."""
    return (old, new)


def _extra_probes(kind: KeyKind) -> list[Any]:
    """Two keys outside the generated range (below and above it) to look up in every version."""
    ints = [-(10**6), 10**6]
    return ints if kind == "int" else [CollidingKey(i) for i in ints]


def _back(n: int, at: int) -> int:
    """Index of the version ``at`` steps before the latest of ``n`` (wrapping): shrinks to the latest."""
    return n - 1 - at % n


@dataclass
class _History:
    """Every version made so far with its model snapshot.

    Each operation is applied to a chosen (possibly old) version, checked by
    the laws of that operation, and its result appended (and checked by the
    query laws): a branching history.
    :meth:`check_all` applies the persistence law to every version.
    """

    cfg: SuiteConfig
    kind: KeyKind
    versions: list[tuple[Any, dict[Any, Any]]] = field(default_factory=list)
    used: list[Any] = field(default_factory=list)

    def __post_init__(self) -> None:
        s = self.cfg.structure
        e = law_empty(s, self.probes())
        self._checked(e, "empty")
        self.versions.append((e, {}))

    def probes(self) -> list[Any]:
        """Every key used so far (the colliding integers among them, once used) and two others."""
        return [*_extra_probes(self.kind), *self.used]

    def key(self, i: int) -> Any:
        """The key of kind ``kind`` made from the integer ``i``."""
        return i if self.kind == "int" else CollidingKey(i)

    def nonempty(self) -> list[int]:
        """Indices of the versions that hold at least one item."""
        return [i for i, (_, snap) in enumerate(self.versions) if snap]

    def _checked(self, m: Any, what: str) -> None:
        if self.cfg.check:
            law_invariants(self.cfg.structure, m, f"after {what}")

    def _use(self, k: Any) -> None:
        if k not in self.used:
            self.used.append(k)

    def _add(self, m: Any, snap: dict[Any, Any], k: Any, what: str) -> None:
        """Check the new version ``m`` (made by an operation on key ``k``) and append it."""
        law_listItemsi(self.cfg.structure, m, self.probes())
        self._checked(m, what)
        self.versions.append((m, snap))
        self.observe(len(self.versions) - 1, k)

    def insert(self, i: int, k: Any, v: Any) -> None:
        """``insert`` into version ``i``, checked by find_insert, find_insert_other, numItems_insert, listItemsi."""
        s = self.cfg.structure
        m, snap = self.versions[i]
        self._use(k)
        m2 = s.insert(m, k, v)
        law_numItems_insert(s, m, k, v, result=(m2,))
        law_find_insert(s, m, k, v, result=(m2,))
        law_find_insert_other(s, m, k, v, [*snap, *self.probes()], result=(m2,))
        self._add(m2, {**snap, k: v}, k, f"insert into version {i}")

    def insert_with(self, i: int, k: Any, v: Any) -> None:
        """``insertWith`` into version ``i``, checked by the insertWith law."""
        s = self.cfg.structure
        m, snap = self.versions[i]
        self._use(k)
        m2 = law_insertWith(s, _combine, m, k, v, [*snap, *self.probes()])
        self._add(m2, {**snap, k: _combine(snap[k], v) if k in snap else v}, k, f"insertWith into version {i}")

    def remove(self, i: int, k: Any) -> None:
        """``remove`` of the present key ``k`` from version ``i``, checked by the remove law."""
        s = self.cfg.structure
        m, snap = self.versions[i]
        m2, _ = law_remove(s, m, k)
        self._add(m2, {kk: vv for kk, vv in snap.items() if kk != k}, k, f"remove from version {i}")

    def remove_absent(self, i: int, k: Any) -> None:
        """``remove`` of the absent key ``k`` from version ``i``: NotFound, version untouched."""
        self._use(k)
        law_remove_absent(self.cfg.structure, self.versions[i][0], k)

    def observe(self, i: int, k: Any) -> None:
        """The query laws (lookup, inDomain, listKeys, foldli, isEmpty) on version ``i`` and key ``k``."""
        s = self.cfg.structure
        m = self.versions[i][0]
        law_lookup(s, m, k)
        law_inDomain(s, m, k)
        law_listKeys(s, m)
        law_foldli(s, m)
        law_isEmpty(s, m)

    def check_all(self) -> None:
        """The persistence law over every version made so far."""
        law_persistence(self.cfg.structure, self.versions, self.probes())


@dataclass(frozen=True)
class Step:
    """One step of a program: ``op`` applied ``back`` versions before the latest (wrapping).

    ``remove`` removes ``key`` when that version holds it and otherwise its
    smallest key (an empty version: as ``remove_absent``); ``remove_absent``
    removes ``key`` when the version lacks it and otherwise a key above all of
    the version's, expecting NotFound.
    """

    op: Literal["insert", "insertWith", "remove", "remove_absent"]
    back: int
    key: Any
    value: Any


@dataclass(frozen=True)
class Program:
    """A sequence of steps over keys of one kind."""

    kind: KeyKind
    steps: tuple[Step, ...]


@functools.cache
def _steps(kind: KeyKind, hashing: bool) -> st.SearchStrategy[list[Step]]:
    step = st.builds(
        Step,
        op=st.sampled_from(("insert", "insertWith", "remove", "remove_absent")),
        back=st.integers(0, 6),
        key=small_keys(kind, hashing),
        value=values(),
    )
    return st.lists(step, max_size=20)


@st.composite
def _programs(draw: st.DrawFn, hashing: bool) -> Program:
    kind = draw(st.sampled_from(key_kinds(hashing)))
    return Program(kind, tuple(draw(_steps(kind, hashing))))


# -- the tests ------------------------------------------------------------------------------


def _probed(case: MapCase) -> list[Any]:
    return [*case.model, *case.removed, *case.probes]


def _t_key_order(cfg: SuiteConfig, hs: settings) -> None:
    kinds = key_kinds(cfg.hashing)
    ks = st.sampled_from(kinds).flatmap(lambda kind: st.lists(keys(kind, cfg.hashing), min_size=1, max_size=7))

    @given(ks)
    def key_order(keys_used: list[Any]) -> None:
        law_key_order(cfg.structure, keys_used)

    hs(key_order)()


def _t_empty(cfg: SuiteConfig, hs: settings) -> None:
    @given(st.lists(keys("int", cfg.hashing), max_size=6))
    def empty(probes: list[Any]) -> None:
        law_empty(cfg.structure, probes)

    hs(empty)()


def _t_singleton(cfg: SuiteConfig, hs: settings) -> None:
    @given(map_cases(cfg.hashing, max_items=0))
    def singleton(case: MapCase) -> None:
        law_singleton(cfg.structure, case.key, case.value, case.probes)

    hs(singleton)()


def _case_test(
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


def _lookup_all(s: Any, m: Any, case: MapCase) -> None:
    for k in [case.key, *case.probes]:
        law_lookup(s, m, k)


def _inDomain_all(s: Any, m: Any, case: MapCase) -> None:
    for k in [case.key, *case.probes]:
        law_inDomain(s, m, k)


def _t_persistence(cfg: SuiteConfig, hs: settings) -> None:
    @given(_programs(cfg.hashing))
    def persistence(program: Program) -> None:
        h = _History(cfg, program.kind)
        for step in program.steps:
            i = _back(len(h.versions), step.back)
            snap = h.versions[i][1]
            if step.op == "insert":
                h.insert(i, step.key, step.value)
            elif step.op == "insertWith":
                h.insert_with(i, step.key, step.value)
            elif step.op == "remove" and snap:
                h.remove(i, step.key if step.key in snap else min(snap))
            else:
                h.remove_absent(i, fresh_key(program.kind, snap) if step.key in snap else step.key)
            h.check_all()

    hs(persistence)()


def _t_invariants(cfg: SuiteConfig, hs: settings) -> None:
    s = cfg.structure
    if not cfg.check:
        raise ConformanceSkip("check is off")
    if getattr(s, "_check", None) is None:
        raise ConformanceSkip("the structure has no _check(m)")

    @given(map_cases(cfg.hashing))
    def invariants(case: MapCase) -> None:
        m = case.build(s, after=lambda v: law_invariants(s, v, "while building the case's map"))
        law_invariants(s, s.insert(m, case.key, case.value), "after insert(m, key, value)")
        law_invariants(s, s.insertWith(_combine, m, case.key, case.value), "after insertWith(f, m, key, value)")
        if case.key in case.model:
            law_invariants(s, s.remove(m, case.key)[0], "after remove(m, key)")
        law_invariants(s, s.singleton(case.key, case.value), "after singleton(key, value)")

    hs(invariants)()


def _machine(cfg: SuiteConfig) -> type[RuleBasedStateMachine]:
    """The stateful test's machine class for ``cfg`` (a class per configuration: rules cannot take one)."""
    # Small domains: each rule's arguments are cheap to shrink (a failing history shrinks
    # by deleting steps and lowering these numbers, every attempt a rerun of the machine).
    small = st.integers(-6, 6)
    ints = st.one_of(small, st.sampled_from(COLLIDING_INTS)) if cfg.hashing else small
    at = st.integers(0, 7)
    pick = st.integers(0, 7)
    vals = st.one_of(st.none(), st.integers(0, 3), st.tuples(st.integers(0, 1)))

    def has_items(self: OrdMapHistory) -> bool:
        return self.h is not None and bool(self.h.nonempty())

    class OrdMapHistory(RuleBasedStateMachine):
        """Every version ever made, each with its model snapshot, rechecked after every step.

        Each rule applies one operation to a version ``at`` steps before the
        latest (old versions too: branching histories, "multiple futures") and
        checks the result by that operation's laws and the query laws; the
        invariant then applies the persistence law to *all* versions.  Every
        rule changes the history (a rule that only looked would be a step the
        shrinker struggles to delete from a failing history).
        """

        def __init__(self) -> None:
            super().__init__()
            self.h: _History | None = None

        @property
        def hist(self) -> _History:
            assert self.h is not None, "the initialize rule runs first"
            return self.h

        @initialize(kind=st.sampled_from(key_kinds(cfg.hashing)))
        def start(self, kind: KeyKind) -> None:
            self.h = _History(cfg, kind)

        @rule(at=at, i=ints, v=vals)
        def insert(self, at: int, i: int, v: Any) -> None:
            h = self.hist
            h.insert(_back(len(h.versions), at), h.key(i), v)

        @precondition(has_items)
        @rule(at=at, pick=pick, v=vals)
        def overwrite(self, at: int, pick: int, v: Any) -> None:
            h = self.hist
            full = h.nonempty()
            i = full[_back(len(full), at)]
            present = sorted(h.versions[i][1])
            h.insert(i, present[pick % len(present)], v)

        @rule(at=at, i=ints, v=vals)
        def insert_with(self, at: int, i: int, v: Any) -> None:
            h = self.hist
            h.insert_with(_back(len(h.versions), at), h.key(i), v)

        @precondition(has_items)
        @rule(at=at, pick=pick)
        def remove(self, at: int, pick: int) -> None:
            h = self.hist
            full = h.nonempty()
            i = full[_back(len(full), at)]
            present = sorted(h.versions[i][1])
            h.remove(i, present[pick % len(present)])

        @rule(at=at, i=ints)
        def remove_absent(self, at: int, i: int) -> None:
            h = self.hist
            v = _back(len(h.versions), at)
            k = h.key(i)
            snap = h.versions[v][1]
            h.remove_absent(v, fresh_key(h.kind, snap) if k in snap else k)

        @invariant()
        def every_version_unchanged(self) -> None:
            if self.h is not None:
                self.h.check_all()

    return OrdMapHistory


def _t_stateful(cfg: SuiteConfig, hs: settings) -> None:
    if cfg.stateful_steps == 0:
        raise ConformanceSkip("stateful_steps = 0")
    run_state_machine_as_test(_machine(cfg), settings=settings(hs, stateful_step_count=cfg.stateful_steps))


# -- edge cases -----------------------------------------------------------------------------


def _check_history(cfg: SuiteConfig, history: Sequence[tuple[Any, dict[Any, Any]]], probes: Iterable[Any]) -> None:
    s = cfg.structure
    for m, _ in history:
        law_listItemsi(s, m)
        if cfg.check:
            law_invariants(s, m)
    law_persistence(s, history, probes)


def _t_edge_empty_map(cfg: SuiteConfig, hs: settings) -> None:
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


def _t_edge_remove_absent(cfg: SuiteConfig, hs: settings) -> None:
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


def _t_edge_overwrite(cfg: SuiteConfig, hs: settings) -> None:
    s = cfg.structure
    m1 = s.insert(s.empty(), 1, "a")
    m1 = s.insert(m1, 2, "b")
    m2 = law_numItems_insert(s, m1, 1, "c")
    law_find_insert(s, m1, 1, "c", result=(m2,))
    law_find_insert_other(s, m1, 1, "c", [2, 3], result=(m2,))
    m3 = law_find_insert(s, m2, 1, None)  # overwrite with None
    m4 = law_find_insert(s, m3, 1, "d")  # and back from None
    m5 = law_insertWith(s, _combine, m4, 1, "e", [2])
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


def _t_edge_remove_last_key(cfg: SuiteConfig, hs: settings) -> None:
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


def _t_edge_colliding_hashes(cfg: SuiteConfig, hs: settings) -> None:
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


def _t_edge_none_value(cfg: SuiteConfig, hs: settings) -> None:
    s = cfg.structure
    m = law_find_insert(s, s.empty(), 1, None)  # find must return (None,)
    law_lookup(s, m, 1)
    law_inDomain(s, m, 1)
    law_listItemsi(s, m, [1, 2])
    law_foldli(s, m)
    one = law_singleton(s, 2, None, [1])
    m2 = law_insertWith(s, _combine, m, 1, None)  # f(None, None)
    m3 = law_find_insert(s, m, 3, (None,))  # a 1-tuple value is not an option
    m4, _ = law_remove(s, m, 1)
    _check_history(cfg, [(m, {1: None}), (one, {2: None}), (m2, {1: (None, None)}), (m3, {1: None, 3: (None,)}), (m4, {})], [1, 2, 3])


# -- workloads ------------------------------------------------------------------------------


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


def _t_workload_sequential(cfg: SuiteConfig, hs: settings) -> None:
    n = cfg.workload_size
    if n == 0:
        raise ConformanceSkip("workload_size = 0")
    _workload(cfg, list(range(n)), list(range(n)), "sequential")


def _t_workload_random(cfg: SuiteConfig, hs: settings) -> None:
    n = cfg.workload_size
    if n == 0:
        raise ConformanceSkip("workload_size = 0")
    rng = random.Random(20010101)  # fixed: the workload is the same every run
    inserted = rng.sample(range(-4 * n, 4 * n), n)
    removed = inserted[:]
    rng.shuffle(removed)
    _workload(cfg, inserted, removed, "random")


def _test(name: str, laws: tuple[str, ...], doc: str, body: Callable[[SuiteConfig, settings], None]) -> ConformanceTest[SuiteConfig]:
    return ConformanceTest(name, laws, doc, body)


ORD_MAP_TESTS: tuple[ConformanceTest[SuiteConfig], ...] = (
    _test("key_order", ("key_order",), "Key.compare is a total order on generated keys", _t_key_order),
    _test("empty", ("empty",), "empty is empty", _t_empty),
    _test("singleton", ("singleton",), "singleton(k, v) = insert(empty, k, v)", _t_singleton),
    _test(
        "find_insert",
        ("find_insert",),
        "find(insert(m, k, v), k) = SOME v",
        _case_test("find_insert", "any", lambda s, m, c: law_find_insert(s, m, c.key, c.value)),
    ),
    _test(
        "find_insert_other",
        ("find_insert_other",),
        "find(insert(m, k, v), j) = find(m, j) for j ≠ k",
        _case_test("find_insert_other", "any", lambda s, m, c: law_find_insert_other(s, m, c.key, c.value, _probed(c))),
    ),
    _test("lookup", ("lookup",), "lookup agrees with find; NotFound when absent", _case_test("lookup", "any", _lookup_all)),
    _test("inDomain", ("inDomain",), "inDomain = isSome o find", _case_test("inDomain", "any", _inDomain_all)),
    _test(
        "insertWith",
        ("insertWith",),
        "insertWith stores f(old, v), or v for a new key",
        _case_test("insertWith", "any", lambda s, m, c: law_insertWith(s, _combine, m, c.key, c.value, _probed(c))),
    ),
    _test(
        "numItems_insert",
        ("numItems_insert",),
        "numItems grows by one for a new key, not for an overwrite",
        _case_test("numItems_insert", "any", lambda s, m, c: law_numItems_insert(s, m, c.key, c.value)),
    ),
    _test(
        "remove",
        ("remove",),
        "remove of a present key returns its value and changes nothing else",
        _case_test("remove", "present", lambda s, m, c: law_remove(s, m, c.key)),
    ),
    _test(
        "remove_absent",
        ("remove_absent",),
        "remove of an absent key raises NotFound",
        _case_test("remove_absent", "absent", lambda s, m, c: law_remove_absent(s, m, c.key)),
    ),
    _test(
        "listItemsi",
        ("listItemsi",),
        "listItemsi is sorted, complete and agrees with find",
        _case_test("listItemsi", "any", lambda s, m, c: law_listItemsi(s, m, [c.key, *c.removed, *c.probes])),
    ),
    _test("listKeys", ("listKeys",), "listKeys = keys of listItemsi", _case_test("listKeys", "any", lambda s, m, c: law_listKeys(s, m))),
    _test("foldli", ("foldli",), "foldli visits the items in increasing order", _case_test("foldli", "any", lambda s, m, c: law_foldli(s, m))),
    _test("isEmpty", ("isEmpty",), "isEmpty exactly when numItems = 0", _case_test("isEmpty", "any", lambda s, m, c: law_isEmpty(s, m))),
    _test("persistence", ("persistence",), "random branching programs; every version rechecked after each step", _t_persistence),
    _test("invariants", ("invariants",), "_check accepts every map the operations make", _t_invariants),
    _test(
        "stateful_history",
        ("persistence", "find_insert", "find_insert_other", "numItems_insert", "insertWith", "remove", "remove_absent",
         "listItemsi", "lookup", "inDomain", "listKeys", "foldli", "isEmpty", "invariants"),
        "a state machine keeping every version (multiple futures), all rechecked after every step",
        _t_stateful,
    ),
    _test("edge_empty_map", ("empty", "lookup", "remove_absent"), "every operation on the empty map", _t_edge_empty_map),
    _test("edge_remove_absent", ("remove_absent",), "removing absent keys below, between and above, and twice", _t_edge_remove_absent),
    _test("edge_overwrite", ("numItems_insert", "find_insert"), "overwriting a key (with None and back)", _t_edge_overwrite),
    _test("edge_remove_last_key", ("remove",), "removing the last key leaves a working empty map", _t_edge_remove_last_key),
    _test("edge_colliding_hashes", ("find_insert", "remove"), "keys whose hashes collide stay distinct", _t_edge_colliding_hashes),
    _test("edge_none_value", ("find_insert", "lookup", "remove"), "None as a stored value: find returns (None,)", _t_edge_none_value),
    _test(
        "workload_sequential",
        ("numItems_insert", "find_insert", "remove", "invariants", "persistence"),
        "workload_size increasing keys: insert, find, remove all",
        _t_workload_sequential,
    ),
    _test(
        "workload_random",
        ("numItems_insert", "find_insert", "remove", "invariants", "persistence"),
        "workload_size random keys: insert, find, remove all (another order)",
        _t_workload_random,
    ),
)
"""Every test of the suite, in the order they run; :class:`OrdMapConformance` has one ``test_<name>`` per entry."""

_TESTS_BY_NAME = {t.name: t for t in ORD_MAP_TESTS}


class OrdMapConformance:
    """Base class of a pytest test class that checks one ``ORD_MAP`` structure.

    Subclass it in a test module (the subclass's name must start with ``Test``)
    and set ``structure``; each ``test_*`` method runs one entry of
    :data:`ORD_MAP_TESTS`.  Knobs (class attributes):

    * ``structure`` — the structure under test (a class is instantiated with no arguments);
    * ``hashing = True`` — also use keys whose hashes collide;
    * ``workload_size = 100_000`` — keys in each workload; a backend that is
      O(n) per operation sets it lower (say why), 0 skips the workloads;
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
        return SuiteConfig(s, bool(cls.hashing), cls.workload_size, bool(cls.check), cls.stateful_steps)

    def run_conformance_test(self, name: str) -> None:
        """Run the suite's test ``name`` under the active hypothesis profile (a skip becomes a pytest skip)."""
        test = _TESTS_BY_NAME[name]
        cfg = self.conformance_config()
        try:
            test.body(cfg, settings(deadline=None))
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
    raised, it is reported.  The time is dominated by the two workloads
    (O(workload_size) operations each) and ``max_examples`` × the number of
    hypothesis tests.
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
    cfg = SuiteConfig(s, hashing, workload_size, check, stateful_steps)
    options: list[tuple[str, object]] = [
        ("max_examples", max_examples),
        ("workload_size", workload_size),
        ("hashing", hashing),
        ("check", check),
    ]
    return run_tests(selected, cfg, explicit_settings(max_examples, derandomize=derandomize), structure=label, signature="ORD_MAP", options=options)
