"""Exact geometric predicates: integer scaling, float filters, Simulation of Simplicity.

=====================  ==========================================================
module                 concept
=====================  ==========================================================
:mod:`.predicates`     the public API: :class:`Predicates3` (orient3d),
                       :class:`Predicates2` (orient2d, incircle), affine rank
:mod:`.points`         input validation and exact duplicate detection
:mod:`.exact`          doubles as integers at a common power-of-two scale
:mod:`.filter`         float64 filters with proven error bounds
:mod:`.sos`            Simulation of Simplicity (Edelsbrunner–Mücke)
:mod:`.zorder`         z-order (Morton) labels: near points, near keys
=====================  ==========================================================
"""

from persistri.impl.geometry.points import UniqueRows, as_points, unique_rows
from persistri.impl.geometry.predicates import Predicates2, Predicates3, affine_dimension

__all__ = ["Predicates2", "Predicates3", "affine_dimension", "as_points", "unique_rows", "UniqueRows"]
