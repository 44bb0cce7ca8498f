"""The ``SIMPCOMP`` growth workload: persistence checked at every size up to ten times ``workload_size`` simplices.

For each dimension n tested, the plan (:func:`~.simpcomp_growth_plan.growth_plan`, the same on every
run; see :mod:`.growth`):

1. **trunk** — the boundary of an (n+1)-simplex (a closed, consistently
   oriented n-complex: the tetrahedron's four triangles for n = 2), added
   face by face, then grown vertex by vertex: a stellar subdivision removes a
   random n-simplex and adds the n+1 that fill it around a new vertex, until
   the complex holds N = 10 · ``workload_size`` n-simplices (3,000 triangles
   at the default); the closed versions at the :func:`~.growth.checkpoints`
   sizes are kept;
2. **branches** — from every kept version, old ones included, one chain of
   mutations: a subdivision (a ``rem`` and n+1 ``add``), an ``update``, for
   n = 2 an edge flip (two ``rem``, two ``add``: the paper's replace-type
   change), a ``rem`` of the other orientation and an ``add`` of the other
   orientation of a held simplex (both refused with a ValueError), and a
   ``rem`` followed by an ``add`` of the same simplex with a new datum; the
   chain's end is kept too;
3. **recheck** — every kept version against its model (the law ``agrees``:
   its simplices, data of every order of each, vertices, lower faces), the
   structure's own check, and the neighbour law on the grown complex.

Every operation is spot-checked as it is done: ``data`` of its simplex on the
operand before and after, on the result after (and ``find`` of a face of an
added simplex; ``update`` calls its function once).  Failures name the law,
the version with its size and the operation, e.g.::

    persistence: version 84 (40 triangles) changed after add on version 84

and are pinned and confirmed by replays (:mod:`.growth`).
"""

from __future__ import annotations

from typing import Any

from hypothesis import settings

from persistri.spec.conformance.growth import Growth, GrowthFailure, counted
from persistri.spec.conformance.hidden_state import Ballast
from persistri.spec.conformance.runner import ConformanceSkip
from persistri.spec.conformance.simpcomp_config import SimpCompSuiteConfig, vertex_pool
from persistri.spec.conformance.simpcomp_growth_plan import ComplexPlan, face, flipped, growth_plan, index_key, noun, tops_of
from persistri.spec.law import raised
from persistri.spec.simpcomp_laws import LawViolation, law_agrees, law_neighbour, oriented_key

__all__ = ["GROWTH_FACTOR", "t_growth"]

_LAW: dict[str, str] = {"add": "add", "rem": "rem", "update": "update", "rem_absent": "rem_absent", "add_present": "add_present"}

_VERB: dict[str, str] = {
    "add": "add",
    "rem": "rem",
    "update": "update",
    "rem_absent": "rem of the other orientation",
    "add_present": "add of the other orientation",
}


def _show(o: object) -> str:
    if o is None:
        return "NONE"
    if isinstance(o, tuple) and len(o) == 1:
        return f"SOME {o[0]!r}"
    return repr(o)


def _same(a: tuple[Any] | None, b: object) -> bool:
    if a is None:
        return b is None
    return isinstance(b, tuple) and len(b) == 1 and (b[0] is a[0] or b[0] == a[0])


class _Run:
    """One run of a plan on one structure instance (with its own vertices): live versions and checks."""

    def __init__(
        self,
        cfg: SimpCompSuiteConfig,
        plan: ComplexPlan,
        C: Any,
        ballast: Ballast | None = None,
        keep: frozenset[int] = frozenset(),
    ) -> None:
        self.cfg = cfg
        self.plan = plan
        self.C = C
        self.ballast = ballast
        self.keep = keep
        self.check = cfg.checker
        self.pool = vertex_pool(cfg, plan.vertices)
        self.versions: dict[int, Any] = {0: C.new(plan.n)}
        self.one, self.many = noun(plan.n)

    def simplex(self, t: tuple[int, ...]) -> Any:
        return self.C.Simplex.simplex([self.pool[i] for i in t])

    # -- describing ------------------------------------------------------------------------------

    def size(self, v: int) -> int:
        if v in self.plan.kept:
            return len(self.plan.kept[v])
        op = self.plan.ops[self.plan.made_by[v]]
        return op.size + {"add": 1, "rem": -1}.get(op.kind, 0)

    def version(self, v: int) -> str:
        return f"version {v} ({counted(self.size(v), self.one, self.many)})"

    def _shown(self, t: tuple[int, ...]) -> str:
        return "(" + ", ".join(repr(self.pool[i]) for i in t) + ")"

    def call(self, i: int) -> str:
        op = self.plan.ops[i]
        kind = {"rem_absent": "rem", "add_present": "add"}.get(op.kind, op.kind)
        if kind == "add":
            return f"add(version {op.operand}, {self._shown(op.simplex)}, {op.datum!r})"
        if kind == "update":
            return f"update(version {op.operand}, {self._shown(op.simplex)}, x ↦ ({op.datum!r}, x))"
        return f"rem(version {op.operand}, {self._shown(op.simplex)})"

    def made(self, i: int) -> str:
        op = self.plan.ops[i]
        if op.result < 0:
            return f"{self.call(i)}, which must raise a ValueError (the other orientation is held)"
        return f"{self.call(i)}, which made version {op.result}"

    def verb(self, i: int) -> str:
        return _VERB[self.plan.ops[i].kind]

    def law(self, i: int) -> str:
        return _LAW[self.plan.ops[i].kind]

    def history(self, v: int) -> str:
        chain: list[str] = []
        while v > self.plan.trunk_end:
            i = self.plan.made_by[v]
            chain.append(f"version {v} = {self.call(i)}")
            v = self.plan.ops[i].operand
        n = self.plan.n
        trunk = (
            f"version {v} is the trunk's complex of {counted(self.size(v), self.one, self.many)} (the boundary of a "
            f"{n + 1}-simplex, then stellar subdivisions of random {self.many} from new vertices; every add and rem "
            "made a version)"
            if v
            else f"version 0 = new({n})"
        )
        if len(chain) > 10:
            chain = [*chain[:4], f"… ({len(chain) - 8} more)", *chain[-4:]]
        return "; ".join([trunk, *reversed(chain)])

    # -- checks ----------------------------------------------------------------------------------

    def data(self, v: int, t: tuple[int, ...], want: tuple[Any] | None, had: bool = True) -> str | None:
        try:
            got = self.C.data(self.versions[v], self.simplex(t))
        except Exception as exc:
            return f"data(version {v}, {self._shown(t)}) raised {type(exc).__name__}: {exc}"
        if _same(want, got):
            return None
        return f"data(version {v}, {self._shown(t)}) = {_show(got)}, but {'it was' if had else 'want'} {_show(want)}"

    def operand_problem(self, i: int) -> str | None:
        op = self.plan.ops[i]
        problem = self.data(op.operand, op.simplex, op.old)
        if problem is None and op.kind in ("rem_absent", "add_present"):
            problem = self.data(op.operand, flipped(op.simplex), op.other)
        return problem

    def agrees(self, v: int) -> str | None:
        S = self.C.Simplex
        model = {oriented_key(S, self.simplex(t)): x for t, x in zip(tops_of(self.plan.kept[v]), self.plan.kept[v].values())}
        try:
            law_agrees(self.C, self.versions[v], self.plan.n, model, f"version {v}")
        except LawViolation as exc:
            return exc.detail
        except Exception as exc:
            return f"reading version {v} raised {type(exc).__name__}: {exc}"
        return None

    def glance(self, v: int) -> str | None:
        model = self.plan.kept[v]
        for t in self.plan.samples.get(v, []):
            key = index_key(t)
            problem = self.data(v, t, (model[key],) if key in model else None)
            if problem:
                return problem
        return None

    def step(self, i: int, checked: bool) -> GrowthFailure | None:
        plan, C = self.plan, self.C
        op = plan.ops[i]
        if checked and (i == 0 or plan.ops[i - 1].result != op.operand):
            problem = self.operand_problem(i)
            if problem:
                return GrowthFailure("persistence", i, f"before:{op.operand}", problem)
        c = self.versions[op.operand]
        s = self.simplex(op.simplex)
        law = _LAW[op.kind]
        calls: list[Any] = []
        result: Any = None
        try:
            if op.kind == "add":
                result = C.add(c, s, op.datum)
            elif op.kind == "rem":
                result = C.rem(c, s)
            elif op.kind == "update":
                tag = op.datum

                def f(x: Any) -> Any:
                    calls.append(x)
                    return (tag, x)

                result = C.update(c, s, f)
            else:
                refused = False
                try:
                    if op.kind == "rem_absent":
                        C.rem(c, s)
                    else:
                        C.add(c, s, op.datum)
                except ValueError:
                    refused = True
                if not refused:
                    return GrowthFailure(law, i, "accepted", f"{self.call(i)} did not raise a ValueError")
        except Exception as exc:
            return GrowthFailure(law, i, "raised", f"{self.call(i)} raised {type(exc).__name__}: {exc}")
        if op.result >= 0:
            self.versions[op.result] = result
        if checked:
            problem = self.operand_problem(i)
            if problem:
                return GrowthFailure("persistence", i, f"after:{op.operand}", problem)
            if op.result >= 0:
                failure = self._result(i, calls)
                if failure is not None:
                    return failure
        self._release(i)
        return None

    def _result(self, i: int, calls: list[Any]) -> GrowthFailure | None:
        """The spot check of operation ``i``'s result (``calls``: the values ``update`` gave its function)."""
        op = self.plan.ops[i]
        law = _LAW[op.kind]
        want: tuple[Any] | None = None
        if op.kind == "add":
            want = (op.datum,)
        elif op.kind == "update":
            assert op.old is not None
            want = ((op.datum, op.old[0]),)
            if len(calls) != 1 or not _same(op.old, (calls[0],)):
                return GrowthFailure(law, i, "calls", f"{self.call(i)} called its function on {calls!r}, want once on {op.old[0]!r}")
        problem = self.data(op.result, op.simplex, want, had=False)
        if problem:
            return GrowthFailure(law, i, "result", problem)
        if op.kind == "add" and self.plan.n >= 1:
            S = self.C.Simplex
            f = face(op.simplex)
            try:
                found = [oriented_key(S, u) for u in self.C.find(self.versions[op.result], self.simplex(f))]
            except Exception as exc:
                detail = f"find(version {op.result}, {self._shown(f)}) raised {type(exc).__name__}: {exc}"
                return GrowthFailure(law, i, "find", detail)
            if oriented_key(S, self.simplex(op.simplex)) not in found:
                detail = f"find(version {op.result}, {self._shown(f)}) does not report the added {self._shown(op.simplex)}"
                return GrowthFailure(law, i, "find", detail)
        if self.check is not None and op.result in self.plan.kept:
            try:
                self.check(self.versions[op.result])
            except Exception as exc:
                detail = f"the check of version {op.result} raised {raised(exc)}"
                return GrowthFailure("invariants", i, "invariants", detail)
        return None

    def _release(self, i: int) -> None:
        op = self.plan.ops[i]
        for v in (op.operand, op.result):
            if v >= 0 and v not in self.plan.kept and v not in self.keep and self.plan.last_use.get(v, -1) <= i:
                self.versions.pop(v, None)
        if self.ballast is not None:
            self.ballast.drop()


GROWTH_FACTOR = 10
"""The growth workload grows each complex to ``GROWTH_FACTOR · workload_size`` n-simplices."""


def t_growth(cfg: SimpCompSuiteConfig, hs: settings) -> None:
    """The growth workload (module docstring) in each dimension of ``cfg.dims``; raises the :class:`LawViolation`
    of the first failure, pinned to its operation and confirmed by a replay (:class:`~.growth.Growth`)."""
    size = GROWTH_FACTOR * cfg.workload_size
    if size == 0:
        raise ConformanceSkip("workload_size = 0")
    for n in cfg.dims:
        plan = growth_plan(n, size)

        def make_run(C: Any, ballast: Ballast | None, keep: frozenset[int], plan: ComplexPlan = plan) -> _Run:
            return _Run(cfg, plan, C, ballast, keep)

        rerun = (
            f"in dimension {n}; to rerun: run_simpcomp_conformance(structure, state=..., dims=({n},), tests=['growth'], "
            f"workload_size={cfg.workload_size}) (the same operations every run)"
        )
        first = Growth(plan, make_run, cfg.structure, cfg.fresh, LawViolation, rerun).run()
        if n >= 2:
            law_neighbour(cfg.structure, first.versions[plan.trunk_end], n)
