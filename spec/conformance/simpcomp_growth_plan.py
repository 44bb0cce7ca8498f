"""The plan of the ``SIMPCOMP`` growth workload: which operations, on which versions, with which models.

Made before any structure is touched, from the dimension n and the size only,
so that every run and every replay (:mod:`.growth`) does exactly the same
operations.  Simplices are tuples of vertex *indices* (a run maps them to the
structure's own vertices); models are dicts from :func:`index_key` to datum.
What the plan contains is described in :mod:`.simpcomp_growth`.
"""

from __future__ import annotations

import functools
import itertools
import random
from dataclasses import dataclass, field
from typing import Any, Literal, NamedTuple

from persistri.spec.conformance.growth import checkpoints
from persistri.spec.simplex_laws import permutation_parity

__all__ = ["ComplexOp", "ComplexPlan", "IndexKey", "OpKind", "face", "flipped", "growth_plan", "index_key", "noun", "tops_of"]

OpKind = Literal["add", "rem", "update", "rem_absent", "add_present"]

IndexKey = tuple[tuple[int, ...], int]
"""An oriented simplex over vertex indices: its sorted indices and the parity of the sorting permutation."""

def index_key(t: tuple[int, ...]) -> IndexKey:
    """The oriented key of the simplex ``t`` over vertex indices (two orders of one orientation: one key)."""
    order = sorted(range(len(t)), key=lambda i: t[i])
    return tuple(t[i] for i in order), permutation_parity(order) if len(t) >= 2 else 0


def flipped(t: tuple[int, ...]) -> tuple[int, ...]:
    """``t`` with its first two vertices swapped: the other orientation."""
    return (t[1], t[0], *t[2:])


def face(t: tuple[int, ...]) -> tuple[int, ...]:
    """The induced face of ``t`` opposite its first vertex (with the induced orientation)."""
    return t[1:]


def noun(n: int) -> tuple[str, str]:
    """The n-simplices' name, singular and plural: edge, triangle, tetrahedron, then ``n-simplex``."""
    return {1: ("edge", "edges"), 2: ("triangle", "triangles"), 3: ("tetrahedron", "tetrahedra")}.get(
        n, (f"{n}-simplex", f"{n}-simplices")
    )


class ComplexOp(NamedTuple):
    """One operation: ``kind`` applied to version ``operand`` with the simplex ``simplex`` (vertex indices).

    ``datum`` is the datum added, or the tag of ``update``'s function
    (``x ↦ (tag, x)``); ``result`` the version made (``-1`` for a refused call);
    ``old`` the operand's ``data`` of the simplex and ``other`` that of its
    other orientation (held, for the refused calls); ``size`` the operand's
    number of n-simplices.
    """

    kind: OpKind
    operand: int
    simplex: tuple[int, ...]
    datum: Any
    result: int
    old: tuple[Any] | None
    other: tuple[Any] | None
    size: int


@dataclass
class ComplexPlan:
    """The whole workload for one dimension n and one size, made before any structure is touched.

    As :class:`~.ord_map_growth.MapPlan`: versions numbered as made (version 0
    is ``new(n)``); ``kept`` the model of each version rechecked at the end,
    ``samples`` a few of its simplices (held or not) for the cheap rechecks.
    """

    n: int
    size: int
    vertices: int = 0
    ops: list[ComplexOp] = field(default_factory=list)
    kept: dict[int, dict[IndexKey, Any]] = field(default_factory=dict)
    samples: dict[int, list[tuple[int, ...]]] = field(default_factory=dict)
    checkpoints: set[int] = field(default_factory=set)
    made_by: dict[int, int] = field(default_factory=dict)
    last_use: dict[int, int] = field(default_factory=dict)
    trunk_end: int = 0
    serials: itertools.count[int] = field(default_factory=lambda: itertools.count(1))

    def add(self, kind: OpKind, operand: int, model: dict[IndexKey, Any], t: tuple[int, ...], datum: Any) -> int:
        """Append an operation on ``operand`` (whose model ``model`` is updated in place); returns its result."""
        key = index_key(t)
        old = (model[key],) if key in model else None
        reverse = index_key(flipped(t))
        other = (model[reverse],) if reverse in model else None
        result = -1 if kind in ("rem_absent", "add_present") else next(self.serials)
        self.ops.append(ComplexOp(kind, operand, t, datum, result, old, other, len(model)))
        i = len(self.ops) - 1
        self.last_use[operand] = i
        if result >= 0:
            self.made_by[result] = i
        if kind == "add":
            model[key] = datum
        elif kind == "rem":
            del model[key]
        elif kind == "update":
            model[key] = (datum, model[key])
        return result

    def keep(self, v: int, model: dict[IndexKey, Any], tops: list[tuple[int, ...]]) -> None:
        """Keep version ``v`` (model copied) with samples: three of its simplices and one absent orientation."""
        self.kept[v] = dict(model)
        if tops:
            self.samples[v] = [tops[0], tops[len(tops) // 2], tops[-1], flipped(tops[-1])]
        else:
            self.samples[v] = []


def _boundary(n: int) -> list[tuple[int, ...]]:
    """The boundary of the (n+1)-simplex on the indices 0 … n+1, consistently oriented (induced orientation)."""
    top = list(range(n + 2))
    faces = []
    for i in range(n + 2):
        rest = top[:i] + top[i + 1 :]
        if i % 2 == 1:
            rest[-1], rest[-2] = rest[-2], rest[-1]
        faces.append(tuple(rest))
    return faces


def _subdivided(t: tuple[int, ...], p: int) -> list[tuple[int, ...]]:
    """The stellar subdivision of ``t`` from the new vertex ``p``: ``t`` with each vertex in turn replaced by ``p``."""
    return [(*t[:i], p, *t[i + 1 :]) for i in range(len(t))]


def _edges(t: tuple[int, ...]) -> list[tuple[int, int]]:
    """The directed edges of the triangle ``t``: (a, b), (b, c), (c, a)."""
    return [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]


@functools.lru_cache(maxsize=4)
def growth_plan(n: int, size: int) -> ComplexPlan:
    """The growth workload of dimension ``n`` to ``size`` n-simplices (module docstring).  O(size) operations."""
    rng = random.Random(f"persistri-simpcomp-growth:{n}:{size}")
    plan = ComplexPlan(n, size)
    model: dict[IndexKey, Any] = {}
    tops: list[tuple[int, ...]] = []
    plan.keep(0, model, tops)
    cur = 0
    for t in _boundary(n):
        cur = plan.add("add", cur, model, t, f"b{len(tops)}")
        tops.append(t)
    vertex = itertools.count(n + 2)
    sizes = checkpoints(size)
    trunk = [0]
    while True:
        while sizes and len(model) >= sizes[0]:
            sizes.pop(0)
            if trunk[-1] != cur:
                plan.keep(cur, model, tops)
                plan.checkpoints.add(len(plan.ops) - 1)
                trunk.append(cur)
        if len(model) >= size:
            break
        i = rng.randrange(len(tops))
        t = tops[i]
        tops[i] = tops[-1]
        tops.pop()
        cur = plan.add("rem", cur, model, t, None)
        p = next(vertex)
        for u in _subdivided(t, p):
            cur = plan.add("add", cur, model, u, f"s{p}")
            tops.append(u)
    plan.trunk_end = cur
    trunk_tops = {v: tops_of(plan.kept[v]) for v in trunk}
    for x in trunk:
        _branch(plan, rng, x, trunk_tops[x], vertex)
    plan.vertices = next(vertex)
    return plan


def tops_of(model: dict[IndexKey, Any]) -> list[tuple[int, ...]]:
    """The simplices of a model, each in its stored orientation (sorted, the last two swapped for parity 1)."""
    out = []
    for (vs, parity) in model:
        t = list(vs)
        if parity and len(t) >= 2:
            t[-1], t[-2] = t[-2], t[-1]
        out.append(tuple(t))
    return out


def _branch(plan: ComplexPlan, rng: random.Random, x: int, tops: list[tuple[int, ...]], vertex: itertools.count[int]) -> None:
    """The chain of mutations from kept version ``x`` (module docstring); its end is kept."""
    n = plan.n
    model = dict(plan.kept[x])
    tops = list(tops)
    cur = x
    if tops:
        t = tops.pop(rng.randrange(len(tops)))
        cur = plan.add("rem", cur, model, t, None)
        p = next(vertex)
        new = _subdivided(t, p)
        for u in new:
            cur = plan.add("add", cur, model, u, f"c{p}")
        tops += new
        cur = plan.add("update", cur, model, new[0], f"u{x}")
        if n == 2:
            cur = _flip_edge(plan, cur, model, tops, new[-1])
        held = tops[rng.randrange(len(tops))]
        if index_key(held) in model:
            plan.add("rem_absent", cur, model, flipped(held), None)
            plan.add("add_present", cur, model, flipped(held), f"z{x}")
            datum = model[index_key(held)]
            cur = plan.add("rem", cur, model, held, None)
            cur = plan.add("add", cur, model, held, ("again", datum))
    else:
        t = tuple(range(n + 1))
        cur = plan.add("add", cur, model, t, f"e{x}")
        plan.add("add_present", cur, model, flipped(t), f"z{x}")
        tops = [t]
    plan.keep(cur, model, [u for u in tops if index_key(u) in model])
    plan.checkpoints.add(len(plan.ops) - 1)


def _flip_edge(plan: ComplexPlan, cur: int, model: dict[IndexKey, Any], tops: list[tuple[int, ...]], t1: tuple[int, ...]) -> int:
    """Flip the edge (a, b) of the held triangle ``t1 = (a, b, c)`` with its neighbour ``(b, a, d)``: remove
    both, add ``(a, d, c)`` and ``(d, b, c)`` (when both are free); returns the version made."""
    a, b, c = t1
    t2 = next((u for u in tops if (b, a) in _edges(u) and index_key(u) in model), None)
    if t2 is None:
        return cur
    k = _edges(t2).index((b, a))
    d = t2[(k + 2) % 3]
    new: list[tuple[int, ...]] = [(a, d, c), (d, b, c)]
    if d == c or any(index_key(u) in model or index_key(flipped(u)) in model for u in new):
        return cur
    cur = plan.add("rem", cur, model, t1, None)
    cur = plan.add("rem", cur, model, t2, None)
    for u in new:
        cur = plan.add("add", cur, model, u, f"f{cur}")
    tops[:] = [u for u in tops if u not in (t1, t2)] + new
    return cur
