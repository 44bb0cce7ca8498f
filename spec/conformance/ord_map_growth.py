"""The ``ORD_MAP`` growth workload: persistence checked at every size up to ``workload_size``.

The plan (:func:`growth_plan`, the same on every run; see :mod:`.growth`):

1. **trunk** — insert the keys 0 … N−1 in a fixed random order, each into the
   previous version: N versions of 1 … N items, crossing every depth of a
   balanced tree and every level of a 32-way HAMT (32, 1,024, 32,768 entries
   for N = 100,000); the versions of :func:`~.growth.checkpoints` sizes
   (1, 2, 4, … items, and N) are kept, and ``_check`` runs on each;
2. **branches** — from every kept version, old ones included, a chain of
   mutations — insert a new key above, between and below the others,
   overwrite, ``insertWith`` on a present and an absent key, remove, remove
   an absent key (NotFound) — whose end is kept too (``_check`` runs on it
   up to 1,024 items); and a few more mutations, spot-checked only: remove a
   key and give it back, overwrite it;
3. **recheck** — every kept version against its model: its items in order
   (by ``Key.compare``), its count, ``find`` of sample keys.

Every operation is spot-checked as it is done: its operand still holds what it
held at the key, with the same count, before and after; the result holds the
new binding and count.  Cheap rechecks (count and sample keys) of every kept
version run at each checkpoint.  Cost: O(N) operations and about 5N items
rechecked, O(N lg N) time for a balanced tree (some 3 s for the red-black tree
at N = 100,000).

A failure names the law, the version (with its size) and the operation::

    persistence: version 2000 (2,000 items) changed after insert on version 2000

followed by the operation, what was seen, and how the versions involved were
made.  Failures found late are pinned to the operation by replays, and every
failure is confirmed by one (:mod:`.growth`): one that does not come back is a
``determinism`` failure.
"""

from __future__ import annotations

import functools
import itertools
import random
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Literal, NamedTuple

from hypothesis import settings

from persistri.spec.conformance.growth import Growth, GrowthFailure, checkpoints, counted
from persistri.spec.conformance.hidden_state import Ballast
from persistri.spec.conformance.ord_map_config import SuiteConfig
from persistri.spec.conformance.ord_map_history import combine
from persistri.spec.conformance.runner import ConformanceSkip
from persistri.spec.ord_map import NotFound
from persistri.spec.law import raised
from persistri.spec.ord_map_laws import LawViolation
from persistri.spec.order import Order

__all__ = ["MapOp", "MapPlan", "growth_plan", "t_growth"]

OpKind = Literal["insert", "insertWith", "remove", "remove_absent"]

_LAW: dict[str, str] = {
    "insert": "find_insert",
    "insertWith": "insertWith",
    "remove": "remove",
    "remove_absent": "remove_absent",
}
"""The law that states what each operation's result must be."""


class MapOp(NamedTuple):
    """One operation of the plan: ``kind`` applied to version ``operand`` at ``key`` (with ``value``).

    ``result`` is the serial number of the version it makes (``-1`` for a
    remove of an absent key, which makes none); ``old`` is the operand's
    binding of ``key`` (``(v,)`` or ``None``) and ``size`` its number of items:
    what the spot checks expect of the operand before and after.
    """

    kind: OpKind
    operand: int
    key: Any
    value: Any
    result: int
    old: tuple[Any] | None
    size: int


@dataclass
class MapPlan:
    """The whole workload for one N, made before any structure is touched (so replays repeat it exactly).

    Versions are numbered in the order they are made (version 0 is ``empty()``,
    version i ≤ N the trunk's map of i items).  ``kept`` holds the model of
    each version rechecked at the end; ``samples`` the keys probed by the cheap
    rechecks; ``checkpoints`` the operations after which the cheap rechecks
    run; ``made_by`` and ``last_use`` the operation that made each version and
    the last one applied to it (a version is dropped after that unless kept).
    """

    n: int
    ops: list[MapOp] = field(default_factory=list)
    kept: dict[int, dict[Any, Any]] = field(default_factory=dict)
    samples: dict[int, list[Any]] = field(default_factory=dict)
    checkpoints: set[int] = field(default_factory=set)
    made_by: dict[int, int] = field(default_factory=dict)
    last_use: dict[int, int] = field(default_factory=dict)

    def add(self, kind: OpKind, operand: int, model: dict[Any, Any], key: Any, value: Any, result: int, size: int = -1) -> None:
        """Append an operation on ``operand``, whose model ``model`` is updated in place to the result's.

        ``size`` is the operand's number of items when ``model`` is only part of
        its model (the key's binding); by default ``len(model)``.
        """
        old = (model[key],) if key in model else None
        self.ops.append(MapOp(kind, operand, key, value, result, old, len(model) if size < 0 else size))
        i = len(self.ops) - 1
        self.last_use[operand] = i
        if result >= 0:
            self.made_by[result] = i
        if kind == "insert":
            model[key] = value
        elif kind == "insertWith":
            model[key] = combine(model[key], value) if key in model else value
        elif kind == "remove":
            del model[key]


@functools.lru_cache(maxsize=2)
def growth_plan(n: int) -> MapPlan:
    """The growth workload of ``n`` keys (module docstring).  O(n) time and about 5n model entries.

    Cached: the plan depends on ``n`` only, and every backend tested in one
    process at the same size shares it.
    """
    rng = random.Random(f"persistri-ord-map-growth:{n}")
    keys = list(range(n))
    rng.shuffle(keys)
    plan = MapPlan(n)
    sizes = set(checkpoints(n))
    model: dict[Any, Any] = {}
    plan.kept[0] = {}
    plan.samples[0] = [keys[0]] if n else [0]
    trunk = [0]
    for i, k in enumerate(keys):
        plan.add("insert", i, model, k, i, i + 1)
        if i + 1 in sizes:
            plan.kept[i + 1] = dict(model)
            plan.samples[i + 1] = [keys[0], keys[i // 2], k, *keys[i + 1 : i + 2]]
            plan.checkpoints.add(i)
            trunk.append(i + 1)
    serial = itertools.count(n + 1)
    above = itertools.count(n)  # keys no trunk version holds: above all of them ...
    below = itertools.count(-1, -1)  # ... and below
    for x in trunk:
        s = len(plan.kept[x])
        middle = keys[s] if s < n else next(above)  # absent from version x, between its keys
        # Chain A: insert above, between and below; overwrite; insertWith present; remove; remove absent.
        chain = dict(plan.kept[x])
        cur, q_hi, q_lo = x, next(above), next(below)
        touched = [q_hi, middle, q_lo]

        def step(kind: OpKind, key: Any, value: Any) -> None:
            nonlocal cur
            if kind == "remove_absent":
                plan.add(kind, cur, chain, key, value, -1)
                return
            made = next(serial)
            plan.add(kind, cur, chain, key, value, made)
            cur = made

        step("insert", q_hi, f"a{x}")
        step("insert", middle, f"b{x}")
        if s:
            p = keys[rng.randrange(s)]
            touched.append(p)
            step("insert", p, f"c{x}")
            step("insertWith", p, f"d{x}")
        step("insertWith", q_lo, f"e{x}")
        if s:
            step("remove", p, None)
            step("remove_absent", p, None)
        step("remove", q_hi, None)
        plan.kept[cur] = chain
        plan.samples[cur] = touched
        if s:
            # Chain B, spot-checked only: remove a present key and give it back with insertWith; and straight
            # from x, overwrite it.  The models are the operations' own (old binding and count).
            p2 = keys[rng.randrange(s)]
            b1, b2, b3 = next(serial), next(serial), next(serial)
            chain = {p2: plan.kept[x][p2]}
            size = len(plan.kept[x])
            plan.add("remove", x, chain, p2, None, b1, size)
            plan.add("insertWith", b1, chain, p2, f"f{x}", b2, size - 1)
            plan.add("insert", x, {p2: plan.kept[x][p2]}, p2, f"g{x}", b3, size)
        plan.add("remove_absent", x, plan.kept[x], q_hi, None, -1)
        plan.checkpoints.add(len(plan.ops) - 1)
    return plan


_ABSENT = object()


def _show(o: tuple[Any] | None) -> str:
    return "NONE" if o is None else f"SOME {o[0]!r}"


def _same(a: tuple[Any] | None, b: object) -> bool:
    """Whether the option ``b`` (an answer of ``find``) is the option ``a``: identity or ``==`` of the value."""
    if a is None:
        return b is None
    return isinstance(b, tuple) and len(b) == 1 and (b[0] is a[0] or b[0] == a[0])


class _Run:
    """One run of a plan on one structure instance: the live versions, and the checks of each operation.

    ``check`` is the structure's ``_check`` (or None): it runs on every kept
    trunk version and on the branch ends of versions of up to 1,024 items.
    ``keep`` names versions a replay must not drop (the one it watches);
    ``ballast`` (replays only) is fed at every operation.
    """

    def __init__(
        self,
        plan: MapPlan,
        s: Any,
        check: Callable[[Any], object] | None,
        ballast: Ballast | None = None,
        keep: frozenset[int] = frozenset(),
    ) -> None:
        self.plan = plan
        self.s = s
        self.check = check
        self.ballast = ballast
        self.keep = keep
        self.versions: dict[int, Any] = {0: s.empty()}

    # -- describing versions and operations --------------------------------------------------

    def size(self, v: int) -> int:
        """How many items version ``v`` holds by its model."""
        if v in self.plan.kept:
            return len(self.plan.kept[v])
        op = self.plan.ops[self.plan.made_by[v]]
        if op.kind == "remove":
            return op.size - 1
        return op.size + (op.old is None)

    def version(self, v: int) -> str:
        """``version 17 (1,203 items)``."""
        return f"version {v} ({counted(self.size(v), 'item')})"

    def call(self, i: int) -> str:
        """Operation ``i`` as a call: ``insert(version 17, 58213, 17)``."""
        op = self.plan.ops[i]
        if op.kind in ("insert", "insertWith"):
            f = "f, " if op.kind == "insertWith" else ""
            return f"{op.kind}({f}version {op.operand}, {op.key!r}, {op.value!r})"
        return f"remove(version {op.operand}, {op.key!r})"

    def made(self, i: int) -> str:
        """Operation ``i`` with what it makes."""
        op = self.plan.ops[i]
        if op.result < 0:
            return f"{self.call(i)}, which must raise NotFound"
        return f"{self.call(i)}, which made version {op.result}"

    def history(self, v: int) -> str:
        """How version ``v`` was made: the trunk, then the branch operations leading to it."""
        chain: list[str] = []
        while v > self.plan.n:
            i = self.plan.made_by[v]
            chain.append(f"version {v} = {self.call(i)}")
            v = self.plan.ops[i].operand
        trunk = (
            f"version {v} is the trunk's map of {counted(v, 'item')} (the keys 0 … {self.plan.n - 1:,} inserted in a "
            "fixed random order, each into the previous version)"
            if v
            else "version 0 = empty()"
        )
        return "; ".join([trunk, *reversed(chain)])

    # -- the checks --------------------------------------------------------------------------

    def holds(self, v: int, key: Any, want: tuple[Any] | None, size: int, *, had: bool = True) -> str | None:
        """None if version ``v`` has ``size`` items and binds ``key`` as ``want``; else what it does instead
        (``had``: phrased as what the version had, else as what it should have)."""
        m = self.versions[v]
        got = self.s.find(m, key)
        if not _same(want, got):
            return f"find(version {v}, {key!r}) = {_show(got)}, but {'it was' if had else 'want'} {_show(want)}"
        n = self.s.numItems(m)
        if n != size:
            return f"numItems(version {v}) = {n!r}, but {'it had' if had else 'want'} {size:,}"
        return None

    def agrees(self, v: int) -> str | None:
        """None if version ``v`` still agrees with its model (items in order, count, sample keys); else how not.

        The items are compared with the model directly: O(N) for a version of N items.
        """
        s, m, model = self.s, self.versions[v], self.plan.kept[v]
        items = list(s.listItemsi(m))
        if len(items) != len(model):
            return f"listItemsi(version {v}) has {counted(len(items), 'item')}, but it had {len(model):,}"
        compare = s.Key.compare
        prev: Any = _ABSENT
        for k, x in items:
            want = model.get(k, _ABSENT)
            if want is _ABSENT or not (want is x or want == x):
                shown = "absent" if want is _ABSENT else f"bound to {want!r}"
                return f"listItemsi(version {v}) lists {k!r} ↦ {x!r}, but {k!r} was {shown}"
            if prev is not _ABSENT and compare(prev, k) is not Order.LESS:
                return f"listItemsi(version {v}) lists {prev!r} before {k!r}"
            prev = k
        n = s.numItems(m)
        if n != len(model):
            return f"numItems(version {v}) = {n!r}, but it had {len(model):,} items"
        for k in self.plan.samples.get(v, []):
            want_o = (model[k],) if k in model else None
            got = s.find(m, k)
            if not _same(want_o, got):
                return f"find(version {v}, {k!r}) = {_show(got)}, but it was {_show(want_o)}"
        return None

    def operand_problem(self, i: int) -> str | None:
        """What is wrong with operation ``i``'s operand: its binding of the key, or its count."""
        op = self.plan.ops[i]
        return self.holds(op.operand, op.key, op.old, op.size)

    def verb(self, i: int) -> str:
        op = self.plan.ops[i]
        return "remove of an absent key" if op.kind == "remove_absent" else op.kind

    def law(self, i: int) -> str:
        return _LAW[self.plan.ops[i].kind]

    def glance(self, v: int) -> str | None:
        """The cheap recheck of a kept version: its count and its sample keys."""
        model = self.plan.kept[v]
        for k in self.plan.samples.get(v, []):
            problem = self.holds(v, k, (model[k],) if k in model else None, len(model))
            if problem:
                return problem
        return None

    def step(self, i: int, checked: bool) -> GrowthFailure | None:
        """Do operation ``i``; with ``checked``, spot-check operand and result and return the first failure."""
        plan, s = self.plan, self.s
        op = plan.ops[i]
        # The operand made by the operation just before was checked a moment ago, as its result.
        if checked and (i == 0 or plan.ops[i - 1].result != op.operand):
            problem = self.operand_problem(i)
            if problem:
                return GrowthFailure("persistence", i, f"before:{op.operand}", problem)
        m = self.versions[op.operand]
        law = _LAW[op.kind]
        result: Any = None
        try:
            if op.kind == "insert":
                result = s.insert(m, op.key, op.value)
            elif op.kind == "insertWith":
                result = s.insertWith(combine, m, op.key, op.value)
            elif op.kind == "remove":
                result, got = s.remove(m, op.key)
                if checked and not _same(op.old, (got,)):
                    return GrowthFailure(law, i, "value", f"{self.call(i)} returned the value {got!r}, but want {_show(op.old)}")
            else:
                try:
                    s.remove(m, op.key)
                except NotFound:
                    pass
                else:
                    return GrowthFailure(law, i, "found", f"{self.call(i)} of an absent key did not raise NotFound")
        except Exception as exc:
            return GrowthFailure(law, i, "raised", f"{self.call(i)} raised {type(exc).__name__}: {exc}")
        if op.result >= 0:
            self.versions[op.result] = result
        if checked:
            problem = self.holds(op.operand, op.key, op.old, op.size)
            if problem:
                return GrowthFailure("persistence", i, f"after:{op.operand}", problem)
            if op.result >= 0:
                problem = self.holds(op.result, op.key, _bound(op), self.size(op.result), had=False)
                if problem:
                    return GrowthFailure(law, i, "result", problem)
                if self.check is not None and self._checks(op.result):
                    try:
                        self.check(result)
                    except Exception as exc:
                        detail = f"_check(version {op.result}) raised {raised(exc)}"
                        return GrowthFailure("invariants", i, "invariants", detail)
        self._release(i)
        return None

    def _checks(self, v: int) -> bool:
        """Whether ``_check`` runs on the new version ``v``: the kept trunk versions, the small branch ends."""
        if v not in self.plan.kept:
            return False
        return v <= self.plan.n or self.size(v) <= 1_024

    def _release(self, i: int) -> None:
        """Drop the versions no later operation uses and nothing keeps (so that their memory is reused)."""
        op = self.plan.ops[i]
        for v in (op.operand, op.result):
            if v >= 0 and v not in self.plan.kept and v not in self.keep and self.plan.last_use.get(v, -1) <= i:
                self.versions.pop(v, None)
        if self.ballast is not None:
            self.ballast.drop()


def _bound(op: MapOp) -> tuple[Any] | None:
    """What the version ``op`` makes binds ``op.key`` to."""
    if op.kind == "remove":
        return None
    if op.kind == "insert" or op.old is None:
        return (op.value,)
    return (combine(op.old[0], op.value),)


def t_growth(cfg: SuiteConfig, hs: settings) -> None:
    """The growth workload (module docstring) on ``cfg.structure``; raises the :class:`LawViolation` of the first
    failure, pinned to its operation and confirmed by a replay (:class:`~.growth.Growth`)."""
    n = cfg.workload_size
    if n == 0:
        raise ConformanceSkip("workload_size = 0")
    plan = growth_plan(n)
    check = getattr(cfg.structure, "_check", None) if cfg.check else None

    def make_run(s: Any, ballast: Ballast | None, keep: frozenset[int]) -> _Run:
        return _Run(plan, s, check, ballast, keep)

    rerun = f"to rerun: run_conformance(structure, tests=['growth'], workload_size={n}) (the same operations every run)"
    Growth(plan, make_run, cfg.structure, cfg.fresh, LawViolation, rerun).run()
