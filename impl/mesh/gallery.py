"""The bench gallery: deterministic planar domains for quality meshing, each a validated :class:`PSLG`.

The domains of issue 16's comparison with Triangle (``persistri bench mesh``),
each with a name and a one-line description (:data:`GALLERY`):

* ``square-hole`` — a square with a square hole (a hole point eats it);
* ``l-shape`` — an L-shaped polygon: one reflex corner;
* ``star`` — a five-pointed star whose tips are 20° input angles, below Ruppert's 60°;
* ``circle`` — a 96-gon approximating the unit circle;
* ``crack`` — a square with an internal crack and one from the boundary (dangling segments);
* ``utm-tile`` — a 40 m lot at UTM offsets (x ≈ 5e5, y ≈ 4e6 m) with centimetre detail
  and a building footprint as a hole;
* ``comb`` — a comb of twelve thin teeth (width 0.25, height 3);
* ``needle`` — a triangle of length 1 whose tip is a 1e-6 rad input angle;
* ``fan`` — a rectangle with five unit segments from one interior vertex, 1e-6 rad apart
  (a cluster of small input angles at one vertex).

Coordinates computed from trigonometry are rounded to a dyadic grid
(multiples of 2^-40), so every machine builds the same doubles.  Every domain
passes :func:`~persistri.impl.mesh.domain.as_pslg` with no repair note.  O(size).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from persistri.impl.mesh.domain import PSLG, as_pslg

__all__ = ["GalleryDomain", "GALLERY", "gallery", "gallery_domain", "star_tip_angle", "needle", "fan"]

_GRID = 2.0**-40


def _snap(values: NDArray[np.float64]) -> NDArray[np.float64]:
    snapped: NDArray[np.float64] = np.round(np.asarray(values, dtype=np.float64) / _GRID) * _GRID
    return snapped + 0.0


def _ring(first: int, count: int) -> list[list[int]]:
    """Segments closing the polygon of vertices ``first .. first + count - 1``."""
    return [[first + k, first + (k + 1) % count] for k in range(count)]


@dataclass(frozen=True)
class GalleryDomain:
    """A named domain of the gallery: ``name``, a one-line ``description`` and its ``pslg``."""

    name: str
    description: str
    pslg: PSLG


def square_hole() -> PSLG:
    """The square [0, 10]² less the square (4, 6)²."""
    outer = [[0, 0], [10, 0], [10, 10], [0, 10]]
    inner = [[4, 4], [6, 4], [6, 6], [4, 6]]
    return as_pslg(outer + inner, _ring(0, 4) + _ring(4, 4), holes=[[5, 5]])


def l_shape() -> PSLG:
    """The L [0, 2]² less [1, 2]²: one reflex corner at (1, 1)."""
    return as_pslg([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]], _ring(0, 6))


def star_tip_angle(points: int, inner: float) -> float:
    """The tip angle (degrees) of a regular star of outer radius 1 and inner radius ``inner``."""
    a = math.pi / points
    return math.degrees(2 * math.atan2(inner * math.sin(a), 1 - inner * math.cos(a)))


def star(points: int = 5, tip: float = 20.0) -> PSLG:
    """A regular star of outer radius 1 whose tips have (about, after snapping) the angle ``tip`` degrees."""
    a = math.pi / points
    t = math.tan(math.radians(tip) / 2)
    inner = t / (math.sin(a) + t * math.cos(a))
    k = np.arange(2 * points)
    radius = np.where(k % 2 == 0, 1.0, inner)
    xy = np.stack([radius * np.cos(k * a + math.pi / 2), radius * np.sin(k * a + math.pi / 2)], axis=1)
    return as_pslg(_snap(xy), _ring(0, 2 * points))


def circle(n: int = 96) -> PSLG:
    """A regular ``n``-gon inscribed in the unit circle."""
    k = np.arange(n)
    xy = np.stack([np.cos(2 * math.pi * k / n), np.sin(2 * math.pi * k / n)], axis=1)
    return as_pslg(_snap(xy), _ring(0, n))


def crack() -> PSLG:
    """The square [0, 4]² with an internal crack (1, 2)–(2.5, 2.5) and a crack from the boundary (4, 1)–(3, 1.25)."""
    boundary = [[0, 0], [4, 0], [4, 1], [4, 4], [0, 4]]
    cracks = [[1, 2], [2.5, 2.5], [3, 1.25]]
    segments = _ring(0, 5) + [[5, 6], [2, 7]]
    return as_pslg(boundary + cracks, segments)


def utm_tile() -> PSLG:
    """A 40 m × 25 m lot at UTM offsets with a 5 cm notch and a building footprint hole, in centimetres."""
    x0, y0 = 500_000.0, 4_000_000.0
    lot = [
        (0.00, 0.00),
        (40.00, 0.00),
        (40.00, 11.37),
        (39.95, 11.37),  # the 5 cm notch
        (39.95, 11.42),
        (40.00, 11.42),
        (40.00, 25.00),
        (17.63, 24.18),
        (0.00, 25.00),
    ]
    house = [(12.41, 6.03), (27.58, 6.03), (27.58, 15.96), (12.41, 15.96)]
    pts = [[round(x0 + dx, 2), round(y0 + dy, 2)] for dx, dy in lot + house]
    segments = _ring(0, len(lot)) + _ring(len(lot), len(house))
    return as_pslg(pts, segments, holes=[[x0 + 20.0, y0 + 11.0]])


def comb(teeth: int = 12) -> PSLG:
    """A spine [0, teeth] × [0, 1] with ``teeth`` teeth of width 0.25 and height 3 along its top."""
    top: list[list[float]] = []
    for k in range(teeth):
        left = k + 0.375
        top += [[left, 1.0], [left, 4.0], [left + 0.25, 4.0], [left + 0.25, 1.0]]
    pts = [[0.0, 0.0], [float(teeth), 0.0], [float(teeth), 1.0]] + top[::-1] + [[0.0, 1.0]]
    return as_pslg(pts, _ring(0, len(pts)))


def needle(half_width: float = 5e-7) -> PSLG:
    """The triangle (0, 0), (1, ∓``half_width``): its tip at the origin is an input angle of about
    ``2 · half_width`` radians.  Not snapped: a full-precision ``half_width`` (5e-7 has a 53-bit significand)
    leaves few doubles exactly on the two long segments, as real-world coordinates do."""
    return as_pslg([[0.0, 0.0], [1.0, -half_width], [1.0, half_width]], _ring(0, 3))


def fan(spokes: int = 5, gap: float = 1e-6) -> PSLG:
    """The rectangle [−1, 2] × [−1, 1] with ``spokes`` unit segments from the origin, ``gap`` radians apart: a
    cluster of small input angles at one vertex, inside the domain."""
    pts = [[-1.0, -1.0], [2.0, -1.0], [2.0, 1.0], [-1.0, 1.0], [0.0, 0.0]]
    for k in range(spokes):
        a = (k - (spokes - 1) / 2) * gap
        pts.append([math.cos(a), math.sin(a)])
    return as_pslg(_snap(np.array(pts)), _ring(0, 4) + [[4, 5 + k] for k in range(spokes)])


_BUILDERS: tuple[tuple[str, str, Callable[[], PSLG]], ...] = (
    ("square-hole", "a square with a square hole", square_hole),
    ("l-shape", "an L-shaped polygon with one reflex corner", l_shape),
    ("star", "a five-pointed star with 20° tips (input angles below 60°)", star),
    ("circle", "a 96-gon inscribed in the unit circle", circle),
    ("crack", "a square with an internal crack and a crack from the boundary", crack),
    ("utm-tile", "a 40 m lot at UTM offsets (5e5, 4e6) with a 5 cm notch and a building hole", utm_tile),
    ("comb", "a comb of twelve thin teeth", comb),
    ("needle", "a triangle with a 1e-6 rad tip (an input angle far below 60°)", needle),
    ("fan", "five segments from one interior vertex, 1e-6 rad apart", fan),
)

GALLERY: tuple[str, ...] = tuple(name for name, _, _ in _BUILDERS)
"""The names of the gallery's domains, in bench order."""


def gallery_domain(name: str) -> GalleryDomain:
    """The gallery domain called ``name`` (one of :data:`GALLERY`); a clear :class:`KeyError` otherwise."""
    for key, description, build in _BUILDERS:
        if key == name:
            return GalleryDomain(key, description, build())
    raise KeyError(f"no gallery domain {name!r}; the domains are {', '.join(GALLERY)}")


def gallery() -> list[GalleryDomain]:
    """Every gallery domain, in :data:`GALLERY` order."""
    return [gallery_domain(name) for name in GALLERY]
