"""A synthetic DEM of any size: fractional Brownian terrain, for benchmarks at sizes no shipped DEM has.

:func:`synthetic_dem` makes a square grid of heights by spectral synthesis
(Voss; Saupe, *Algorithms for random fractals*, 1988): random phases and
Gaussian amplitudes with power spectrum ``|f|^-β``, ``β = 2H + 2``, summed by one
inverse FFT.  The default Hurst exponent ``H = 0.8`` (fractal dimension 2.2) is
the classic value for natural-looking landscapes.  The heights are rescaled to
``[0, relief]`` metres, so "1 % of the relief" is a height of ``relief / 100``.
Deterministic for a seed (numpy's PCG64); the surface is periodic (an FFT's),
which a terrain mesher neither knows nor uses.

>>> g = synthetic_dem(65, seed=1)
>>> g.heights.shape, float(g.heights.min()), float(g.heights.max())
((65, 65), 0.0, 1000.0)
"""

from __future__ import annotations

from typing import Final

import numpy as np

from persistri.impl.terrain.grids import HeightGrid

__all__ = ["synthetic_dem", "SYNTHETIC_HURST", "SYNTHETIC_RELIEF", "parse_synthetic"]

SYNTHETIC_HURST: Final[float] = 0.8
"""The default Hurst exponent ``H`` (fractal dimension ``3 − H``)."""

SYNTHETIC_RELIEF: Final[float] = 1000.0
"""The default relief: heights span ``[0, 1000]`` metres."""


def synthetic_dem(size: int, *, seed: int = 0, hurst: float = SYNTHETIC_HURST, relief: float = SYNTHETIC_RELIEF) -> HeightGrid:
    """A ``size × size`` fractional Brownian terrain (module docstring), heights in ``[0, relief]``.

    :class:`ValueError` for ``size < 2``, ``hurst`` outside ``(0, 1)`` or a relief that is not a
    positive finite number.  O(size² log size), float64.
    """
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)) or size < 2:
        raise ValueError(f"a synthetic DEM needs an integer size of at least 2, got {size!r}")
    if not 0.0 < hurst < 1.0:
        raise ValueError(f"the Hurst exponent must lie strictly between 0 and 1, got {hurst}")
    if not (np.isfinite(relief) and relief > 0):
        raise ValueError(f"the relief must be a positive number, got {relief}")
    n = int(size)
    rng = np.random.default_rng(seed)
    fx = np.fft.fftfreq(n)[:, None]
    fy = np.fft.rfftfreq(n)[None, :]
    f = np.hypot(fx, fy)
    f[0, 0] = 1.0
    amplitude = f ** -(hurst + 1.0)  # the square root of |f|^-β, β = 2H + 2
    amplitude[0, 0] = 0.0  # no mean
    spectrum = amplitude * rng.standard_normal(amplitude.shape) * np.exp(2j * np.pi * rng.random(amplitude.shape))
    z = np.fft.irfft2(spectrum, s=(n, n))
    lo, hi = float(z.min()), float(z.max())
    heights = (z - lo) * (relief / (hi - lo)) if hi > lo else np.zeros((n, n))
    # The extremes exactly at 0 and relief (the rescaling rounds).
    heights[np.unravel_index(int(np.argmin(z)), z.shape)] = 0.0
    heights[np.unravel_index(int(np.argmax(z)), z.shape)] = relief if hi > lo else 0.0
    return HeightGrid(np.ascontiguousarray(heights, dtype=np.float64), None, f"synthetic:{n}:{seed}")


def parse_synthetic(word: str) -> tuple[int, int] | None:
    """``"synthetic"``, ``"synthetic:SIZE"`` or ``"synthetic:SIZE:SEED"`` → ``(size, seed)``; None for other words.

    The default size is 2,048 and the default seed 0.  :class:`ValueError` for a malformed one.
    """
    parts = word.lower().split(":")
    if parts[0] != "synthetic":
        return None
    if len(parts) > 3:
        raise ValueError(f"{word}: write synthetic, synthetic:SIZE or synthetic:SIZE:SEED")
    try:
        size = int(parts[1]) if len(parts) > 1 else 2048
        seed = int(parts[2]) if len(parts) > 2 else 0
    except ValueError:
        raise ValueError(f"{word}: the size and seed of a synthetic DEM are integers (synthetic:SIZE:SEED)") from None
    if size < 2:
        raise ValueError(f"{word}: a synthetic DEM needs a size of at least 2")
    return size, seed
