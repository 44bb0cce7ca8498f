"""Exact checks of quality meshes for the mesh tests, and the test domains built by hand.

:func:`check_mesh` checks a mesh (arrays) of a domain exactly with
:class:`~persistri.impl.geometry.predicates.Predicates2` over the mesh's own
vertices — independently of the mesher's data structures:

* every triangle strictly counterclockwise; no directed edge used twice (no overlap);
* every mesh segment lies exactly on its input segment, and the mesh segments of
  each input segment chain from one end to the other;
* every input vertex that a domain triangle could use is a vertex;
* constrained Delaunay: across every edge shared by two triangles that is not a
  segment, the fourth vertex is not strictly inside the circle (exact incircle);
* twice the total area, exactly, when the caller gives it.
"""

from __future__ import annotations

from collections import defaultdict
from fractions import Fraction
from typing import Any

import numpy as np
import triangle as tr
from hypothesis import strategies as st
from numpy.typing import NDArray

from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.mesh.angles import angle_at_least
from persistri.impl.mesh.domain import PSLG, as_pslg
from persistri.impl.mesh.verify import verify_mesh


def twice_area(vertices: NDArray[np.float64], triangles: NDArray[np.intp]) -> Fraction:
    """Twice the total area of ``triangles``, exactly (Fractions of the doubles)."""
    total = Fraction(0)
    for a, b, c in triangles.tolist():
        (ax, ay), (bx, by), (cx, cy) = (tuple(map(Fraction, vertices[i])) for i in (a, b, c))
        total += (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    return total


def polygon_area2(vertices: NDArray[np.float64], cycle: list[int]) -> Fraction:
    """Twice the signed area of the polygon through ``vertices[cycle]``, exactly (the shoelace formula)."""
    pts = [tuple(map(Fraction, vertices[i])) for i in cycle]
    return sum(
        (pts[i][0] * pts[(i + 1) % len(pts)][1] - pts[(i + 1) % len(pts)][0] * pts[i][1] for i in range(len(pts))),
        Fraction(0),
    )


def hole_square_area2(d: PSLG) -> Fraction:
    """Twice the area of :func:`square_with_hole`'s domain: the outer square less the hole, exactly."""
    return polygon_area2(d.vertices, [0, 1, 2, 3]) - polygon_area2(d.vertices, [4, 5, 6, 7])


def check_mesh(
    domain: PSLG,
    vertices: NDArray[np.float64],
    triangles: NDArray[np.intp],
    segments: NDArray[np.intp],
    segment_of: NDArray[np.intp],
    *,
    area2: Fraction | None = None,
) -> None:
    """Assert that the mesh is a constrained Delaunay triangulation of ``domain`` (module docstring)."""
    P = Predicates2(vertices)
    n_in = domain.vertices.shape[0]
    assert np.array_equal(vertices[:n_in], domain.vertices), "the input vertices come first, in their rows"
    owner: dict[tuple[int, int], int] = {}
    for k, (a, b, c) in enumerate(triangles.tolist()):
        assert P.orient2d_sign(a, b, c) > 0, f"triangle {k} {(a, b, c)} is not strictly counterclockwise"
        for u, w in ((a, b), (b, c), (c, a)):
            assert (u, w) not in owner, f"edge {(u, w)} is in two triangles: they overlap"
            owner[(u, w)] = k
    seg_edges = {(min(u, w), max(u, w)) for u, w in segments.tolist()}
    # Every mesh segment exactly on its input segment; each input segment a chain of them.
    pieces: dict[int, list[tuple[int, int]]] = defaultdict(list)
    for (u, w), s in zip(segments.tolist(), segment_of.tolist()):
        a, b = domain.segments[s]
        for v in (u, w):
            if v not in (a, b):
                assert P.orient2d_sign(int(a), int(b), v) == 0, f"vertex {v} is off segment {s}"
                lo, hi = np.minimum(vertices[a], vertices[b]), np.maximum(vertices[a], vertices[b])
                assert np.all(lo <= vertices[v]) and np.all(vertices[v] <= hi), f"vertex {v} is beyond segment {s}"
        pieces[s].append((u, w))
    for s, (a, b) in enumerate(domain.segments.tolist()):
        adj: dict[int, list[int]] = defaultdict(list)
        for u, w in pieces[s]:
            adj[u].append(w)
            adj[w].append(u)
        assert len(adj[a]) == 1 and len(adj[b]) == 1, f"segment {s} is not a chain of mesh segments from {a} to {b}"
        prev, v, steps = -1, a, 0
        while v != b:
            nxt = [x for x in adj[v] if x != prev]
            assert len(nxt) == 1, f"segment {s}: the chain branches at vertex {v}"
            prev, v = v, nxt[0]
            steps += 1
        assert steps == len(pieces[s]), f"segment {s}: pieces off the chain"
    # Constrained Delaunay across every shared edge that is not a segment.
    for (u, w), k in owner.items():
        j = owner.get((w, u))
        if j is None or (min(u, w), max(u, w)) in seg_edges:
            continue
        t1 = triangles[k].tolist()
        apex = [v for v in triangles[j].tolist() if v not in (u, w)][0]
        assert P.incircle_sign(t1[0], t1[1], t1[2], apex) <= 0, f"edge {(u, w)} is not locally Delaunay"
    if area2 is not None:
        assert twice_area(vertices, triangles) == area2, "the triangles do not cover the domain exactly"
    # And the package's independent exact checker (verify_mesh) agrees.
    report = verify_mesh(domain, vertices, triangles, exact_segments=True)
    assert report.ok, f"verify_mesh: {report.problems[:3]}"


def check_quality(
    vertices: NDArray[np.float64],
    triangles: NDArray[np.intp],
    min_angle: float,
    max_area: float | None,
    exempt: int = 0,
) -> None:
    """Assert every triangle's angles are >= ``min_angle`` (except at most ``exempt`` triangles) and areas <= ``max_area``."""
    below = 0
    for a, b, c in triangles.tolist():
        pts = [tuple(map(Fraction, vertices[i])) for i in (a, b, c)]
        scale = 1
        for p in pts:
            for x in p:
                scale = max(scale, x.denominator)
        ints = [(int(x * scale), int(y * scale)) for x, y in pts]
        ok = True
        for k in range(3):
            o, p, q = ints[k], ints[(k + 1) % 3], ints[(k + 2) % 3]
            u = (p[0] - o[0], p[1] - o[1])
            v = (q[0] - o[0], q[1] - o[1])
            if not angle_at_least(u[0] * v[0] + u[1] * v[1], u[0] ** 2 + u[1] ** 2, v[0] ** 2 + v[1] ** 2, min_angle):
                ok = False
        below += not ok
        if max_area is not None:
            (ax, ay), (bx, by), (cx, cy) = pts
            assert ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax)) / 2 <= Fraction(max_area), "a triangle is too large"
    assert below <= exempt, f"{below} triangles below {min_angle} degrees, {exempt} exempt"


def check_verified(domain: PSLG, mesh: Any) -> None:
    """The package's checker on a finished mesh, with its bounds: valid, and the quality it reports reached."""
    report = verify_mesh(
        domain, mesh.vertices, mesh.triangles, min_angle=mesh.min_angle or None, max_area=mesh.max_area, exact_segments=True
    )
    assert report.ok, f"verify_mesh: {report.problems[:3]}"


# -- domains ------------------------------------------------------------------------------------


def ring(n: int) -> list[list[int]]:
    """The segments of a closed polygon over vertices ``0 .. n-1``."""
    return [[i, (i + 1) % n] for i in range(n)]


def square_with_hole(offset: tuple[float, float] = (0.0, 0.0), size: float = 4.0) -> PSLG:
    """A square of side ``size`` with a square hole of side ``size / 4`` off its centre (area 15/16 of the square)."""
    s, q = size, size / 4
    pts = np.array([[0, 0], [s, 0], [s, s], [0, s], [q, q], [2 * q, q], [2 * q, 2 * q], [q, 2 * q]], dtype=np.float64)
    pts += np.array(offset)
    hole = np.array([[1.5 * q, 1.5 * q]]) + np.array(offset)
    return as_pslg(pts, ring(4) + [[4 + i, 4 + (i + 1) % 4] for i in range(4)], holes=hole)


def l_shape() -> PSLG:
    """The L of three unit squares (area 3)."""
    return as_pslg([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]], ring(6))


def star(k: int = 7) -> PSLG:
    """A star with ``k`` sharp tips (input angles near 16° for k = 7), vertices on a 1/1024 grid."""
    ang = np.arange(2 * k) * np.pi / k
    rad = np.where(np.arange(2 * k) % 2 == 0, 1.0, 0.25)
    pts = np.round(np.c_[rad * np.cos(ang), rad * np.sin(ang)] * 1024) / 1024
    return as_pslg(pts, ring(2 * k))


def circle(n: int = 32) -> PSLG:
    """A regular ``n``-gon inscribed in the unit circle, vertices on a 1/4096 grid."""
    ang = np.arange(n) * 2 * np.pi / n
    return as_pslg(np.round(np.c_[np.cos(ang), np.sin(ang)] * 4096) / 4096, ring(n))


@st.composite
def pslgs(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray]:
    """Integer points (cocircular and collinear sets common) and a random subset of their Delaunay edges
    (which never cross) plus the hull: a valid PSLG."""
    n = draw(st.integers(4, 24))
    pts = draw(
        st.lists(st.tuples(st.integers(0, 12), st.integers(0, 12)), min_size=n, max_size=n, unique=True)
    )
    arr = np.array(pts, dtype=np.float64)
    if abs(np.linalg.matrix_rank(arr[1:] - arr[0])) < 2:
        arr = np.vstack([arr, [[13.0, 13.0], [0.0, 13.0]]])
    t = tr.triangulate({"vertices": arr}, "c")
    edges = {tuple(sorted(e)) for tri in t["triangles"].tolist() for e in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0]))}
    chosen = sorted(e for e in edges if draw(st.booleans()))
    return t["vertices"], np.array(chosen, dtype=np.intp).reshape(-1, 2)
