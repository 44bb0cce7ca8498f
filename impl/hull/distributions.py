"""The five point distributions of the paper's §4, as seeded generators.

=============  ==============================================================
name           the paper's description
=============  ==============================================================
``OnSphere``   uniform on the unit 2-sphere
``EqHeavy``    on the sphere, mostly at the equator: uniform on the sphere,
               x and y stretched by 100, projected back to the sphere
``PolHeavy``   on the sphere, mostly at the poles: uniform on the sphere,
               z stretched by 100, projected back to the sphere
``InBall``     uniform in the unit ball
``BordHeavy``  uniform in the unit ball, then (x, y, z) ↦ (x, y, x²+y²+z²)
=============  ==============================================================

Every generator takes ``n`` and a ``seed`` and returns an ``(n, 3)`` float64
array; the same seed gives the same points (numpy's PCG64).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

__all__ = ["DISTRIBUTIONS", "generate", "on_sphere", "eq_heavy", "pol_heavy", "in_ball", "bord_heavy"]

Points = NDArray[np.float64]


def _unit_vectors(rng: np.random.Generator, n: int) -> Points:
    """n directions uniform on the sphere (normalised Gaussian vectors)."""
    v = rng.standard_normal((n, 3))
    norms = np.linalg.norm(v, axis=1)
    # A Gaussian vector is zero with probability 0; redraw the (practically never) tiny ones.
    bad = norms < 1e-300
    while bad.any():
        v[bad] = rng.standard_normal((int(bad.sum()), 3))
        norms = np.linalg.norm(v, axis=1)
        bad = norms < 1e-300
    out: Points = v / norms[:, None]
    return out


def _stretched(rng: np.random.Generator, n: int, factors: tuple[float, float, float]) -> Points:
    v = _unit_vectors(rng, n) * np.asarray(factors)
    out: Points = v / np.linalg.norm(v, axis=1)[:, None]
    return out


def on_sphere(n: int, seed: int = 0) -> Points:
    """OnSphere: ``n`` points uniform on the unit sphere."""
    return _unit_vectors(np.random.default_rng(seed), n)


def eq_heavy(n: int, seed: int = 0) -> Points:
    """EqHeavy: on the unit sphere, concentrated at the equator (x, y stretched by 100)."""
    return _stretched(np.random.default_rng(seed), n, (100.0, 100.0, 1.0))


def pol_heavy(n: int, seed: int = 0) -> Points:
    """PolHeavy: on the unit sphere, concentrated at the poles (z stretched by 100)."""
    return _stretched(np.random.default_rng(seed), n, (1.0, 1.0, 100.0))


def in_ball(n: int, seed: int = 0) -> Points:
    """InBall: ``n`` points uniform in the unit ball (radius ∝ U^(1/3))."""
    rng = np.random.default_rng(seed)
    v = _unit_vectors(rng, n)
    r = rng.random(n) ** (1.0 / 3.0)
    out: Points = v * r[:, None]
    return out


def bord_heavy(n: int, seed: int = 0) -> Points:
    """BordHeavy: uniform in the unit ball mapped by (x, y, z) ↦ (x, y, x²+y²+z²)."""
    p = in_ball(n, seed)
    out: Points = np.column_stack([p[:, 0], p[:, 1], (p * p).sum(axis=1)])
    return out


DISTRIBUTIONS: dict[str, Callable[[int, int], Points]] = {
    "OnSphere": on_sphere,
    "EqHeavy": eq_heavy,
    "PolHeavy": pol_heavy,
    "InBall": in_ball,
    "BordHeavy": bord_heavy,
}
"""The paper's distributions by name (§4), each ``(n, seed) -> (n, 3) array``."""


def generate(name: str, n: int, seed: int = 0) -> Points:
    """``n`` points of the distribution ``name`` (case-insensitive); ValueError names the known ones."""
    for key, gen in DISTRIBUTIONS.items():
        if key.lower() == name.lower():
            if n < 0:
                raise ValueError(f"the number of points must be non-negative, not {n}")
            return gen(n, seed)
    raise ValueError(f"unknown distribution {name!r}; known: {', '.join(DISTRIBUTIONS)}")
