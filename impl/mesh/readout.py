"""One version of a mesh run read back as arrays: :class:`MeshArrays`, :func:`mesh_arrays` (paper §1).

A run (:class:`Run`) is what every future of one constrained Delaunay
triangulation shares: the triangulation (its exact predicates over the run's
append-only point set, the persistent 2-complex's structure), the segments'
geometry and the validated domain.  :func:`mesh_arrays` reads any version of the
run back in the style of ``triangle.triangulate``: the input vertices first, in
their rows, then the Steiner points the version holds, by point index; the
domain's triangles (counterclockwise), the mesh edges on input segments and the
region of each triangle.  O(size of the version): one pass over the complex's
triangles (:meth:`~persistri.impl.complex.two_complex.TwoComplex.items`), a mask
over the point set instead of a sort.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import chain
from operator import itemgetter

import numpy as np
from numpy.typing import NDArray

from persistri.impl.complex.structure import Complex
from persistri.impl.mesh.cdt import SegmentGeometry
from persistri.impl.mesh.domain import PSLG
from persistri.impl.mesh.triangulation import EXTERIOR, MeshDatum, MeshTriangulation

__all__ = ["MeshArrays", "Run", "mesh_arrays"]

IntArray = NDArray[np.intp]


@dataclass(frozen=True, eq=False)
class MeshArrays:
    """One version read back as arrays (the :class:`~persistri.impl.mesh.result.QualityMesh` fields of the same names).

    ``points[k]`` is the point index (in the run's append-only point set) of output vertex ``k``.
    """

    vertices: NDArray[np.float64]
    triangles: IntArray
    segments: IntArray
    segment_of: IntArray
    regions: IntArray
    points: IntArray


@dataclass(frozen=True, eq=False)
class Run:
    """What every future of one CDT shares: the triangulation (predicates, structure, vertices) and the segments.

    Immutable in the sense that matters: the point set only grows (a point index means one point in
    every future), the structure makes new versions and never changes one.
    """

    T: MeshTriangulation
    geo: SegmentGeometry
    domain: PSLG


def mesh_arrays(run: Run, c: Complex[MeshDatum]) -> MeshArrays:
    """Version ``c`` as arrays: the input vertices first (rows kept), then the Steiner vertices present, by index.

    O(size of ``c``).
    """
    items = run.T.S.items(c)
    n = run.geo.n_input
    # Every triangle's labels (ghosts' -1 too) and region in one pass each, as arrays (a vertex is an int).
    labels = np.fromiter(chain.from_iterable([t for t, _ in items]), dtype=np.intp, count=3 * len(items)).reshape(-1, 3)
    region_of = np.fromiter([d[1] for _, d in items], dtype=np.intp, count=len(items))
    # The input vertices (every row kept), then the Steiner points present, by index: a mask over the point set (the
    # ghosts' label -1 marks its extra last slot), not np.unique's hash and sort.
    present = np.zeros(len(run.T.pred) + 1, dtype=bool)
    present[labels] = True
    present[:n] = True
    points = np.flatnonzero(present[:-1])
    index = np.full(len(run.T.pred), -1, dtype=np.intp)
    index[points] = np.arange(points.size)
    inside = region_of != EXTERIOR
    segs: dict[tuple[int, int], int] = {}
    for _, d in items:
        if d[2]:
            for lo, hi, s in d[2]:
                segs[(lo, hi)] = s
    seg_rows = sorted(segs.items(), key=itemgetter(1, 0))  # by (segment, edge); the key made in C
    ns = len(seg_rows)
    return MeshArrays(
        vertices=np.array(run.T.pred.points[points], dtype=np.float64),
        triangles=index[labels[inside]],
        segments=index[np.fromiter(chain.from_iterable([k for k, _ in seg_rows]), dtype=np.intp, count=2 * ns).reshape(-1, 2)],
        segment_of=np.fromiter([s for _, s in seg_rows], dtype=np.intp, count=ns),
        regions=region_of[inside],
        points=points,
    )
