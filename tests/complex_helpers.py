"""Shared fixtures of the complex tests: the structures under test, fresh vertices, closed surfaces.

``STRUCTURES`` pairs a test id with a factory ``make(n, stats=None)`` of an
n-complex structure: the specialised representation over every map backend
that imports, the paper's unspecialised functor (the 2-complex bootstrapped
from the 1-complex too) over two backends, and the all-dimensions
:class:`~persistri.impl.complex.simpcomp.SimpComp` dispatcher.

The surfaces are given as oriented triangles over vertex indices; their
orientation is made consistent (outward normals) here, in the test helper,
with floating-point normals of well-shaped polytopes — the complex under test
never sees coordinates.
"""

from __future__ import annotations

import importlib
import itertools
import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from persistri.impl.complex import Complex, ComplexStructure, SimpComp, complex_structure
from persistri.impl.complex.vertex import Vertex, VertexState, int_vertex
from persistri.impl.maps import BACKENDS
from persistri.impl.stats import Stats

__all__ = [
    "BACKEND_NAMES",
    "STRUCTURES",
    "Make",
    "fresh",
    "tetrahedron",
    "octahedron",
    "icosahedron",
    "random_polytope",
    "torus",
    "build",
]


def _importable(name: str) -> bool:
    module = BACKENDS[name].split(":")[0]
    try:
        importlib.import_module(module)
    except ImportError:
        return False
    return True


BACKEND_NAMES = [name for name in BACKENDS if _importable(name)]
"""Every registered map backend whose module imports (red_black and hamt included once written)."""

Make = Callable[..., Any]


def _specialised(name: str) -> Make:
    return lambda n, stats=None: complex_structure(n, name, stats=stats)


def _unspecialised(name: str) -> Make:
    return lambda n, stats=None: complex_structure(n, name, stats=stats, specialised=False)


def _dispatch(name: str) -> Make:
    return lambda n, stats=None: SimpComp(name, stats)


STRUCTURES: list[tuple[str, Make]] = (
    [(name, _specialised(name)) for name in BACKEND_NAMES]
    + [(f"{name}-functor", _unspecialised(name)) for name in ("assoc_list", "red_black") if name in BACKEND_NAMES]
    + [("simpcomp-dispatch", _dispatch(BACKEND_NAMES[-1] if "hamt" not in BACKEND_NAMES else "hamt"))]
)
STRUCTURE_IDS = [sid for sid, _ in STRUCTURES]


def fresh(k: int, points: Sequence[Any] | None = None) -> list[Vertex]:
    """``k`` vertices of a new lineage (at ``points``, or at their own index)."""
    pts = list(range(k)) if points is None else list(points)
    return int_vertex.new_many(VertexState.initial(), pts)[1]


def _orient_outward(points: np.ndarray, tris: Sequence[Sequence[int]]) -> list[tuple[int, int, int]]:
    centre = points.mean(axis=0)
    out = []
    for a, b, c in tris:
        normal = np.cross(points[b] - points[a], points[c] - points[a])
        if float(np.dot(normal, points[a] - centre)) < 0:
            b, c = c, b
        out.append((int(a), int(b), int(c)))
    return out


def _hull(points: np.ndarray) -> list[tuple[int, int, int]]:
    from scipy.spatial import ConvexHull

    return _orient_outward(points, ConvexHull(points).simplices.tolist())


def tetrahedron() -> tuple[int, list[tuple[int, int, int]]]:
    """4 vertices, 4 outward-oriented triangles."""
    pts = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float)
    return 4, _orient_outward(pts, list(itertools.combinations(range(4), 3)))


def octahedron() -> tuple[int, list[tuple[int, int, int]]]:
    """6 vertices, 8 triangles."""
    pts = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=float)
    return 6, _hull(pts)


def icosahedron() -> tuple[int, list[tuple[int, int, int]]]:
    """12 vertices, 20 triangles."""
    phi = (1 + math.sqrt(5)) / 2
    pts = []
    for s1 in (1, -1):
        for s2 in (1, -1):
            pts += [[0, s1, s2 * phi], [s1, s2 * phi, 0], [s2 * phi, 0, s1]]
    return 12, _hull(np.array(pts, dtype=float))


def random_polytope(k: int, seed: int) -> tuple[int, list[tuple[int, int, int]]]:
    """The boundary of the convex hull of ``k`` random points on the unit sphere (all k are vertices)."""
    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(k, 3))
    pts /= np.linalg.norm(pts, axis=1)[:, None]
    return k, _hull(pts)


def torus(m: int, k: int) -> tuple[int, list[tuple[int, int, int]]]:
    """An m×k grid on the torus (m, k ≥ 3), each square cut into two consistently oriented triangles."""

    def v(i: int, j: int) -> int:
        return (i % m) * k + (j % k)

    tris = []
    for i in range(m):
        for j in range(k):
            tris.append((v(i, j), v(i + 1, j), v(i + 1, j + 1)))
            tris.append((v(i, j), v(i + 1, j + 1), v(i, j + 1)))
    return m * k, tris


def build(
    C: ComplexStructure[Any] | SimpComp[Any],
    vs: Sequence[Vertex],
    tris: Sequence[Sequence[int]],
    n: int = 2,
) -> Complex[Any]:
    """The n-complex of the simplices ``tris`` (vertex indices into ``vs``), each carrying its index."""
    c = C.new(n)
    for i, t in enumerate(tris):
        c = C.add(c, tuple(vs[j] for j in t), i)
    return c


def stats_of(make: Make, n: int) -> tuple[Any, Stats]:
    """A counted structure from ``make`` and its Stats."""
    st = Stats()
    return make(n, st), st
