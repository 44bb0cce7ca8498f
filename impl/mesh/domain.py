"""Planar straight-line graphs (PSLGs): the domains of quality meshing (Ruppert 1995; Triangle's input).

A :class:`PSLG` is what Shewchuk's Triangle reads from a ``.poly`` file, as
numpy arrays: vertices, segments between them, hole points (a hole is the
region around a hole point bounded by segments) and, optionally, region
points with an attribute and an area bound.  The domain it describes, as in
Triangle: the convex hull of the vertices, less every region reachable from
outside the hull or from a hole point without crossing a segment
("concavities and holes eaten away").
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

__all__ = ["PSLG"]


def _no_pairs() -> NDArray[np.intp]:
    return np.zeros((0, 2), dtype=np.intp)


def _no_points() -> NDArray[np.float64]:
    return np.zeros((0, 2), dtype=np.float64)


def _no_regions() -> NDArray[np.float64]:
    return np.zeros((0, 4), dtype=np.float64)


@dataclass(frozen=True, eq=False)
class PSLG:
    """A planar straight-line graph with holes and regions (Triangle's ``.poly`` contents).

    * ``vertices`` — ``(n, 2)`` float64, exact input coordinates;
    * ``segments`` — ``(m, 2)`` intp, pairs of vertex rows (order irrelevant);
    * ``holes`` — ``(h, 2)`` float64, one point strictly inside each hole;
    * ``regions`` — ``(r, 4)`` float64 rows ``(x, y, attribute, max_area)``
      (``max_area <= 0``: no bound), Triangle's regional attributes;
    * ``vertex_markers`` / ``segment_markers`` — ``(n,)`` / ``(m,)`` intp boundary markers
      (Triangle's; 0 when the file gives none).

    A ``PSLG`` built directly is NOT validated; :func:`~persistri.impl.mesh.domain.as_pslg`
    builds a validated one (crossing segments, vertices on segment interiors, duplicates,
    holes outside the domain, NaN/inf are clear errors).
    """

    vertices: NDArray[np.float64]
    segments: NDArray[np.intp] = field(default_factory=_no_pairs)
    holes: NDArray[np.float64] = field(default_factory=_no_points)
    regions: NDArray[np.float64] = field(default_factory=_no_regions)
    vertex_markers: NDArray[np.intp] | None = None
    segment_markers: NDArray[np.intp] | None = None
