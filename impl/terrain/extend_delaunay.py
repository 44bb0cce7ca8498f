"""``extend_delaunay``: adding points to a finished Delaunay triangulation, as a new one sharing structure with it.

The incremental Delaunay triangulation (paper §5) needs nothing of a run but
its last version to go on: a new point is located by a walk, its cavity
replaced by its fan, one new version per point.  On the persistent complex the
old version is not touched by that, so the old triangulation, its complex and
every version of its history stay valid; the new one shares every triangle,
datum, vertex list and map node the new points leave alone (paper §1's
"multiple futures": two extensions of one triangulation are two branches).

What continuing needs, and how it is kept exact:

1. **Labels.**  A vertex's label is its index in the predicates' point array.
   The old run numbered its distinct points ``0 … m−1`` along a Hilbert curve
   and gave the symbolic infinite vertex the label ``m``; the new distinct points
   take the labels after those (``m+1, m+2, …``, along a Hilbert curve of their
   own), and the predicates are rebuilt over the old points, a stand-in row at
   ``m`` (never read: no test takes the infinite vertex as a point; the ghost rule
   decides those) and the new points.  Every old decision stands: the exact
   signs are of the same rationals, and Simulation of Simplicity ranks the points
   by input row (``Predicates2(sos_rank=…)``), in the first run and here alike —
   so the result is exactly the triangulation of the whole input computed in one
   run, cocircular and collinear ties included (tested on grids).
2. **The triangulator's scratch.**  The live-triangle index and the edge index
   of the last version are read back from the complex (its triangles and data,
   the same objects), and the vertices are the complex's own, so new triangles
   join the same lineage
   (:meth:`~persistri.impl.terrain.delaunay.Triangulator.resume`).  O(n) once.
3. **Insertion.**  The distinct new points are inserted in a biased randomised
   order of their own (:func:`~persistri.impl.terrain.scattered.insertion_order`,
   drawn from the old seed and the old number of labels, so each step of a
   chain draws afresh), each walk starting in the fan of the previous one.
   Expected O(n + k log(n + k)) for ``k`` new points.

New rows equal to an old row or to an earlier new row are merged and reported
in ``duplicates``, like the first run's.

>>> import numpy as np
>>> from persistri.impl.terrain.scattered import delaunay
>>> old = delaunay(np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [2.0, 2.0]]))
>>> new = extend_delaunay(old, [[1.0, 1.0], [0.0, 0.0]])   # the centre, and a repeat of row 0
>>> new.triangles.tolist(), new.duplicates, old.triangles.shape
([[0, 1, 4], [0, 4, 2], [1, 3, 4], [2, 4, 3]], ((5, 0),), (2, 3))
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.collector import collector_paused
from persistri.impl.complex.structure import Complex
from persistri.impl.geometry.points import appended_rows, as_points
from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.terrain.delaunay import Triangulator
from persistri.impl.terrain.insertion import TriDatum, canonical_triangles
from persistri.impl.terrain.scattered import (
    DelaunayTriangulation,
    hilbert_keys,
    hull_rows,
    insertion_order,
    run_insertions,
    verify_result,
)

__all__ = ["extend_delaunay"]

IntArray = NDArray[np.intp]


def extend_delaunay(tri: DelaunayTriangulation, points: ArrayLike, *, check: bool = False) -> DelaunayTriangulation:
    """The Delaunay triangulation of ``tri.points`` and ``points`` together, continuing ``tri``'s run; ``tri`` is unchanged.

    * ``points`` of the result are ``tri.points`` followed by the rows of
      ``points``; ``triangles``, ``hull`` and ``duplicates`` index that
      concatenation, and the triangles are exactly those of
      :func:`~persistri.impl.terrain.scattered.delaunay` run on it (module docstring).
    * The new complex shares everything the new points leave alone with
      ``tri.complex``; if every new row repeats an old one, it *is* ``tri.complex``.
    * ``history``: if ``tri`` kept one, its versions (the same objects) followed by
      one version per new distinct point; else None.
    * ``seed``, the structure (its backend) and ``stats`` are ``tri``'s: a counted
      run's :class:`~persistri.impl.stats.Stats` counts the extension's work too.
    * ``check`` — the insertion invariants at every step and the result verified
      exactly, as ``delaunay(check=True)``.

    Errors: :class:`TypeError`/:class:`ValueError` for ``points`` that are not a
    ``(k, 2)`` array of finite reals (naming the first bad row). Expected
    O(n + k log(n + k)).
    """
    if not isinstance(tri, DelaunayTriangulation):
        raise TypeError(f"extend_delaunay: tri must be a DelaunayTriangulation made by delaunay, not {type(tri).__name__}")
    new = as_points(points, 2, what="new points")
    n_old = tri.points.shape[0]
    arr = np.concatenate([tri.points, new])
    arr.setflags(write=False)

    # Each row's representative is its first equal row, as delaunay's (the old rows keep theirs: this only appends).
    merged, fresh = appended_rows(arr, n_old)
    m_old = tri.labels.size
    # The new points' labels follow the Hilbert curve among themselves, after the old ones (scattered.py says why).
    keys = hilbert_keys(arr[fresh])
    fresh = fresh[np.argsort(keys, kind="stable")]
    labels = np.concatenate([tri.labels, fresh])
    # The predicates' rows, by label; the infinite vertex's slot holds a stand-in (label 0's point), never read.
    # Simulation of Simplicity ranks the points by input row (the stand-in below them all), as the first run did.
    stand_in = np.where(labels >= 0, labels, labels[0])
    structure = tri.structure
    pred = Predicates2(arr[stand_in], stats=structure.stats, sos_rank=labels)
    with collector_paused():
        T = Triangulator.resume(pred, structure, tri.complex, tri.infinite, check=check)

    drawn = int(np.random.default_rng((tri.seed, m_old)).integers(1 << 62))
    order = (insertion_order(arr[fresh], drawn, np.sort(keys)) + m_old).tolist()
    versions: list[Complex[TriDatum]] | None = None if tri.history is None else []
    triangles, cycle = run_insertions(T, order, versions, check=check)
    history = None
    if tri.history is not None:
        assert versions is not None
        history = tri.history.continued(versions, labels[order].tolist(), labels)
    result = DelaunayTriangulation(
        points=arr,
        triangles=canonical_triangles(labels[triangles]),
        hull=hull_rows(labels, cycle),
        duplicates=tri.duplicates + merged,
        complex=T.complex,
        structure=structure,
        seed=tri.seed,
        backend=tri.backend,
        labels=labels,
        infinite=tri.infinite,
        stats=tri.stats,
        history=history,
    )
    if check:
        verify_result(result)
    return result
