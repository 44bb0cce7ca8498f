"""What Triangle's output files carry besides the mesh: boundary markers and vertex attributes, by Triangle's rules.

Triangle writes, with ``-p``, a ``.node`` whose vertices carry their attributes and a
boundary marker, and a ``.poly`` whose segments carry a marker; persistri's
``-o mesh.ele`` writes the same (:mod:`persistri.impl.cli.mesh`), computed here from a
:class:`~persistri.impl.mesh.api.QualityMesh` and the run that made it.

**Markers** (Triangle's documented rule, ``triangle.markers.html``):

* a *segment* keeps its input marker when it is nonzero; otherwise it is 1 if it lies on
  a boundary of the meshed domain (domain triangles on one side only: the outer boundary,
  a hole's, the convex hull of a ``.node`` file or of ``--convex``), else 0.  Every mesh
  edge on the segment (subsegment) carries the segment's marker; a segment with no domain
  triangle on either side (inside a hole) is not written, as Triangle deletes it;
* a *vertex* keeps its input marker when it is nonzero; otherwise an input vertex takes
  the marker of the first segment, in input order, that ends at it and has a nonzero
  input marker (Triangle marks a segment's ends as it inserts the segments, in file
  order), else 1 if a boundary segment ends at it, else 0; a split point takes its
  segment's marker; a circumcentre or off-centre is 0.

**Attributes** (``triangle.node.html``: copied unchanged, and "each new Steiner point …
will have quantities assigned to it by linear interpolation"): an input vertex keeps its
own; a split point gets the linear interpolation along its segment at its parameter
``t`` (``A + t (B − A)``; Triangle interpolates along the subsegment it splits, which is
the same line); a circumcentre or off-centre gets the affine interpolation, at its
position, of the three corners of the bad triangle it was the Steiner point of
(``SegmentGeometry.made_in``; Triangle's ``findcircumcenter`` ξ, η), those corners'
values computed the same way first.  Each value is computed exactly from its parents'
doubles (integers times a power of two) and rounded once (Triangle computes in floating point: the two agree up to
rounding where the meshes agree).

Cost: markers O(N + T log T); attributes O(k) exact integer operations per Steiner point
(and ancestor deleted since), only when the domain has attributes.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from persistri.impl.mesh.api import QualityMesh

__all__ = ["TriangleMarkers", "triangle_markers", "vertex_attributes", "output_points"]

IntArray = NDArray[np.intp]


class TriangleMarkers:
    """The markers Triangle would write for a mesh (module docstring): ``vertex`` ``(N,)`` for its rows,
    ``segment`` ``(S,)`` for its ``segments`` rows, and ``kept`` ``(S,)``: the rows Triangle writes (a domain
    triangle beside them)."""

    __slots__ = ("vertex", "segment", "kept")

    def __init__(self, vertex: IntArray, segment: IntArray, kept: NDArray[np.bool_]) -> None:
        self.vertex = vertex
        self.segment = segment
        self.kept = kept


def output_points(mesh: QualityMesh) -> IntArray:
    """The index in the run's point set of each row of ``mesh.vertices``. O(1) when the mesh kept it, else O(size)."""
    points = mesh.points
    return points if points is not None else mesh.history.mesh(len(mesh.history) - 1).points


def _sides(mesh: QualityMesh) -> IntArray:
    """The number of domain triangles beside each row of ``mesh.segments`` (0, 1 or 2). O(T log T)."""
    tri = np.asarray(mesh.triangles, dtype=np.int64).reshape(-1, 3)
    seg = np.sort(np.asarray(mesh.segments, dtype=np.int64).reshape(-1, 2), axis=1)
    n = max(int(mesh.vertices.shape[0]), 1)
    edges = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    keys = np.sort(edges[:, 0] * n + edges[:, 1])
    wanted = seg[:, 0] * n + seg[:, 1]
    return (np.searchsorted(keys, wanted, "right") - np.searchsorted(keys, wanted, "left")).astype(np.intp)


def triangle_markers(mesh: QualityMesh) -> TriangleMarkers:
    """The boundary markers of ``mesh``'s vertices and subsegments by Triangle's rule (module docstring). O(N + T log T)."""
    d = mesh.domain
    m = d.segments.shape[0]
    n_in = d.vertices.shape[0]
    given = np.zeros(m, dtype=np.intp) if d.segment_markers is None else np.asarray(d.segment_markers, dtype=np.intp).reshape(m)
    sides = _sides(mesh)
    segment_of = np.asarray(mesh.segment_of, dtype=np.intp)
    boundary = np.zeros(m, dtype=bool)
    boundary[segment_of[sides == 1]] = True
    effective = given.copy()
    effective[(given == 0) & boundary] = 1

    vertex = np.zeros(mesh.vertices.shape[0], dtype=np.intp)
    if d.vertex_markers is not None:
        vertex[:n_in] = np.asarray(d.vertex_markers, dtype=np.intp).reshape(n_in)
    ends = np.asarray(d.segments, dtype=np.intp).reshape(m, 2)
    origin = d.segment_origin if d.segment_origin is not None else np.arange(m, dtype=np.intp)
    # Triangle inserts the segments in file order (the convex hull's after them), marking each end not marked yet.
    order = np.lexsort((np.arange(m), np.where(origin < 0, m + 1, origin)))
    for s in order[given[order] != 0].tolist():
        for v in ends[s].tolist():
            if vertex[v] == 0:
                vertex[v] = given[s]
    on_boundary = ends[boundary & (given == 0)].reshape(-1)
    vertex[on_boundary[vertex[on_boundary] == 0]] = 1
    if vertex.shape[0] > n_in:
        on_segment = mesh._run.geo.on_segment
        for row, p in enumerate(output_points(mesh)[n_in:].tolist(), start=n_in):
            found = on_segment.get(p)
            if found is not None:
                vertex[row] = effective[found[0]]
    return TriangleMarkers(vertex, effective[segment_of], sides > 0)


def vertex_attributes(mesh: QualityMesh) -> NDArray[np.float64] | None:
    """Every row of ``mesh.vertices``' attributes, or None when the domain has none (module docstring: input vertices'
    kept, Steiner points' interpolated as Triangle does, exactly and rounded once). O(k) integer operations per Steiner
    point."""
    d = mesh.domain
    given = d.vertex_attributes
    if given is None or given.size == 0:
        return None
    n_in, k = given.shape
    points = output_points(mesh)
    out = np.zeros((points.shape[0], k), dtype=np.float64)
    out[:n_in] = given
    if points.shape[0] == n_in:
        return out
    geo = mesh._run.geo
    pred = mesh._run.T.pred
    # The Steiner points whose values are needed: the output's, and their parents' (deleted since, some), recursively.
    needed: set[int] = set()
    stack = [p for p in points[n_in:].tolist()]
    while stack:
        p = stack.pop()
        if p < n_in or p in needed:
            continue
        needed.add(p)
        parents = geo.made_in.get(p)
        if parents is not None:
            stack.extend(parents)
    value: dict[int, list[float]] = {v: given[v].tolist() for v in range(n_in)}
    for p in sorted(needed):  # parents are older than their children: smaller indices
        found = geo.on_segment.get(p)
        if found is not None:
            s, t = found
            a, b = geo.ends[s]
            tn, td = t.numerator, t.denominator
            value[p] = [_affine(x, ((y, tn, td),)) for x, y in zip(value[a], value[b])]
        else:
            a, b, c = geo.made_in[p]
            (ax, ay, bx, by, cx, cy, px, py), _ = _scaled((*pred.xy(a), *pred.xy(b), *pred.xy(c), *pred.xy(p)))
            det = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
            xi = (px - ax) * (cy - ay) - (py - ay) * (cx - ax)  # ξ = xi / det, η = eta / det: p = a + ξ (b − a) + η (c − a)
            eta = (bx - ax) * (py - ay) - (by - ay) * (px - ax)
            value[p] = [_affine(x, ((y, xi, det), (z, eta, det))) for x, y, z in zip(value[a], value[b], value[c])]
    for row, p in enumerate(points[n_in:].tolist(), start=n_in):
        out[row] = value[p]
    return out


def _scaled(values: tuple[float, ...]) -> tuple[list[int], int]:
    """The doubles ``values`` as integers times one power of two ``2^-shift``: ``(integers, shift)``, exactly."""
    ratios = [v.as_integer_ratio() for v in values]
    shift = max(d.bit_length() for _, d in ratios) - 1  # every denominator is a power of two
    return [n << (shift - d.bit_length() + 1) for n, d in ratios], shift


def _affine(x: float, terms: tuple[tuple[float, int, int], ...]) -> float:
    """``x + Σ (n / d)(y − x)`` over ``terms`` ``(y, n, d)`` (one ``d`` for all), exactly, rounded once to a double:
    Python's ``int / int`` rounds correctly."""
    d = terms[0][2]
    (xs, *ys), shift = _scaled((x, *(y for y, _, _ in terms)))
    num = xs * d + sum(n * (y - xs) for y, (_, n, _) in zip(ys, terms))
    return num / (d << shift)
