"""The workloads of the complex benchmark (:mod:`persistri.impl.bench.complex`): traces to replay, and the walk.

:func:`sphere_trace` records the SIMPCOMP operations of growing a triangulated
sphere the way the bulldozer grows a hull, without geometry; :func:`hull_trace`
records the bulldozer itself on OnSphere points; :func:`walk` visits every
triangle of a closed surface across its edges (the paper's neighbour query,
§2).  The benchmark's module docstring says how each is used and measured.
"""

from __future__ import annotations

import random
from typing import Any, Final

from persistri.impl.complex.ephemeral import EphemeralTwoComplex
from persistri.impl.complex.structure import Complex
from persistri.impl.complex.trace import Trace, TracingTwoComplex
from persistri.impl.complex.two_complex import Triangle, TwoComplex
from persistri.impl.complex.vertex import Vertex, VertexState, int_vertex

__all__ = ["DEFAULT_SEED", "ComplexBenchError", "even_size", "hull_trace", "sphere_trace", "walk"]

DEFAULT_SEED: Final = 2001
"""Seed of the workload (the paper's year)."""


class ComplexBenchError(RuntimeError):
    """A complex gave a wrong result during the benchmark (its figures would be meaningless)."""


def even_size(triangles: int) -> int:
    """A closed triangulated sphere has an even number (≥ 4) of triangles: ``triangles`` rounded up."""
    if isinstance(triangles, bool) or not isinstance(triangles, int) or triangles < 1:
        raise ValueError(f"triangles: a positive integer, got {triangles!r}")
    return max(4, triangles + (triangles & 1))


def sphere_trace(triangles: int, seed: int = DEFAULT_SEED, *, stepwise: bool = False) -> Trace:
    """The trace of growing a triangulated sphere of ``triangles`` triangles (rounded up to an even count ≥ 4)
    the way the bulldozer grows a hull, without geometry (module docstring); ``stepwise``: rem and add per
    triangle instead of one replace per step.

    Deterministic in ``(triangles, seed)``.  Recorded on the ephemeral complex
    (the fastest; the history is linear).  O(triangles) operations.
    """
    target = even_size(triangles)
    rng = random.Random(f"persistri-bench-complex:{seed}:{target}")
    rec: TracingTwoComplex[int] = TracingTwoComplex(EphemeralTwoComplex[int](), window=4)
    state, (a, b, c, d) = int_vertex.new_many(VertexState.initial(), range(4))
    cx = rec.new(2)
    faces: list[tuple[Triangle, int]] = []  # the current triangles, for random choice
    where: dict[int, int] = {}  # datum -> index in faces
    serial = 0

    def remember(t: Triangle) -> int:
        """Record ``t`` among the current triangles; its datum (a serial number)."""
        nonlocal serial
        x = serial
        where[x] = len(faces)
        faces.append((t, x))
        serial += 1
        return x

    def add(t: Triangle) -> None:
        nonlocal cx
        cx = rec.add(cx, t, remember(t))

    def forget(x: int) -> None:
        i = where.pop(x)
        last = faces.pop()
        if last[1] != x:
            faces[i] = last
            where[last[1]] = i

    for t in ((a, b, c), (a, c, d), (a, d, b), (b, d, c)):  # a consistently oriented tetrahedron
        add(t)
    while len(faces) < target:
        state, p = int_vertex.new(state, len(faces))
        t0, x0 = faces[rng.randrange(len(faces))]
        rec.data(cx, t0)
        size = min(16, 1 + _geometric(rng, 0.25))  # mean 4: the bulldozer's visible faces per point
        patch: dict[int, Triangle] = {x0: t0}
        verts = set(t0)
        cycle: list[tuple[Vertex, Vertex]] = [(t0[0], t0[1]), (t0[1], t0[2]), (t0[2], t0[0])]
        for _ in range(3 * size):
            if len(patch) >= size:
                break
            i = rng.randrange(len(cycle))
            u, w = cycle[i]
            ((g, y),) = rec.findi(cx, (w, u))
            x = g[2]
            if x in verts:  # the disk keeps every vertex on its boundary, so the cone stays a sphere
                continue
            patch[y] = g
            verts.add(x)
            cycle[i : i + 1] = [(u, x), (x, w)]
        for t in patch.values():  # the walking-graph test looks across every edge of a visible face
            for u, w in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                rec.findi(cx, (w, u))
        if stepwise:
            for xid, t in patch.items():
                cx = rec.rem(cx, t)
                forget(xid)
            for u, w in cycle:
                add((u, w, p))
            continue
        tent = [((u, w, p), remember((u, w, p))) for u, w in cycle]
        cx = rec.replace(cx, list(patch.values()), tent)
        for xid in patch:
            forget(xid)
    return rec.stop()


def _geometric(rng: random.Random, p: float) -> int:
    """The number of failures before the first success of a p-coin (mean (1 − p)/p)."""
    k = 0
    while rng.random() >= p:
        k += 1
    return k


def hull_trace(triangles: int, seed: int = DEFAULT_SEED, *, stepwise: bool = False, labels: str = "spatial") -> Trace:
    """The trace of the bulldozer's convex hull of ``triangles / 2 + 2`` OnSphere points (all on the hull,
    so the hull has ``triangles`` triangles, rounded up to even).  Minutes at 10^5 triangles.
    ``stepwise``: the bulldozer's paper-style rem and add per face instead of one replace per insertion;
    ``labels``: the vertices' labels, as :func:`~persistri.impl.hull.api.convex_hull` takes them."""
    from persistri.impl.hull.api import convex_hull
    from persistri.impl.hull.distributions import on_sphere

    target = even_size(triangles)
    rec: TracingTwoComplex[Any] = TracingTwoComplex(EphemeralTwoComplex[Any](), window=4)
    convex_hull(on_sphere(target // 2 + 2, seed), seed=seed, structure=rec, stepwise=stepwise, labels=labels)
    return rec.stop()


def walk(S: TwoComplex[Any], c: Complex[Any], start: Triangle) -> int:
    """Visit every triangle of the closed surface ``c`` once from ``start``, depth first, crossing each edge
    with ``findi`` of the reversed edge; returns the number of triangles visited.  3 ``findi`` per triangle.

    The triangles' data must identify them (a replayed trace's data do: each is the event that added it).
    """
    findi = S.findi
    x0 = S.data(c, start)
    if x0 is None:
        raise ComplexBenchError(f"walk: the start triangle {start!r} is not in the complex")
    seen = {x0[0]}
    stack = [start]
    while stack:
        a, b, d = stack.pop()
        for u, w in ((a, b), (b, d), (d, a)):
            ((g, x),) = findi(c, (w, u))
            if x not in seen:
                seen.add(x)
                stack.append(g)
    return len(seen)
