"""Exact geometric predicates over indexed points: the public API.

:class:`Predicates3` (3D: ``orient3d``, the plane-side test of the bulldozer,
paper §3 and Appendix A) and :class:`Predicates2` (2D: ``orient2d`` and
``incircle``, for the Delaunay terrain of §5) are built once from an ``(n, d)``
float64 array and answer tests by point *index*, as the algorithms need.

Every test is exact, in three stages:

1. **Filter** (:mod:`.filter`): the determinant and its permanent in float64
   on a copy of the points scaled by a power of two (exact); if
   ``|det| > ERRBOUND · permanent`` the sign is proved right.  Almost every
   test stops here.
2. **Exact** (:mod:`.exact`): the determinant on Python integers — the input
   doubles times a common power of two, with no rounding anywhere.
3. **Simulation of Simplicity** (:mod:`.sos`): an exact zero is broken by the
   symbolic perturbation indexed by point, so ``orient3d``, ``orient2d`` and
   ``incircle`` return ±1, never 0, and are antisymmetric in their arguments.
   The ``*_sign`` methods stop after stage 2 and return the true sign,
   0 included (for verification: "on or behind a face").

Sign conventions (Shewchuk's; all are determinants with a last column of ones):

* ``orient2d(a, b, c) = sign det[[a, 1], [b, 1], [c, 1]]``: +1 when ``a, b, c``
  turn counterclockwise.
* ``orient3d(a, b, c, d) = sign det[[a, 1], [b, 1], [c, 1], [d, 1]]``: +1 when
  ``d`` is *below* the plane of ``a, b, c``, "above" being where ``a, b, c``
  look counterclockwise.  For a face ``(a, b, c)`` of a convex polytope,
  outward-oriented by the right-hand rule, interior points give +1 and points
  that see the face (beyond its plane) give -1.  Moving one argument to
  another place permutes rows: ``orient3d(d, a, b, c) == -orient3d(a, b, c, d)``.
* ``incircle(a, b, c, d) = orient3d`` of the lifted points ``(x, y, x² + y²)``:
  +1 when ``d`` is inside the circle through ``a, b, c`` (counterclockwise).

Batches: ``*_batch(a, b, c, qs)`` tests many query points against fixed
points (a conflict list against a plane); ``*_many(a, b, c, d)`` takes any
mix of indices and index arrays, broadcast together (e.g. every (face, point)
pair of a visible region at once).  Both return int8 arrays equal, entry for
entry, to the scalar test; below :data:`SMALL_BATCH` entries they loop over
the scalar test, above it the filter runs vectorised and only the undecided
entries go to exact (vectorised) integer arithmetic and SoS.

Counting: with a :class:`~persistri.impl.stats.Stats` attached (``stats=``),
each test adds 1 to ``plane_side_tests`` (orient2d and incircle count as
orientation tests too), its filter's ``FLOPS_*`` to ``flops`` (the filter runs
for every test; integer work is not counted as flops), and 1 to
``filter_failures`` when exact arithmetic had to decide; batches add these per
query point.  With no ``Stats`` attached nothing is counted.

The code is in three modules, one concept each, whose public names this one
exports: :mod:`~persistri.impl.geometry.indexed_points` (what both dimensions
share: validation, the filter's scaled copy and its row table, exact integers,
counting, the batch engine), :mod:`~persistri.impl.geometry.predicates3` and
:mod:`~persistri.impl.geometry.predicates2`.
"""

from __future__ import annotations

from persistri.impl.geometry.indexed_points import SMALL_BATCH, IndexedPoints, RowTable
from persistri.impl.geometry.kernel import Indices, Orient3dKernel
from persistri.impl.geometry.predicates2 import Predicates2
from persistri.impl.geometry.predicates3 import Predicates3, affine_dimension

__all__ = [
    "Predicates2", "Predicates3", "Orient3dKernel", "Indices", "RowTable", "IndexedPoints", "SMALL_BATCH", "affine_dimension",
]
