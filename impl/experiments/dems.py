"""The real elevation models Fig. 11 runs on: two DEMs that installed packages ship, read offline.

The paper's terrains (Ozark, Missouri and the west end of Crater Lake, Oregon)
are not available to us; two real DEMs that Python packages ship are:

* ``jacksboro`` — the Jacksboro fault DEM shipped with matplotlib
  (``jacksboro_fault_dem.npz``, read by :func:`persistri.impl.terrain.grids.jacksboro`):
  344 × 403 integer heights in metres, cells of 1/1200 degree (≈ 3 arc-seconds).
* ``lidar`` — ``lidar/data/dem.tif``, the sample DEM shipped in the wheel of the
  PyPI package `lidar <https://pypi.org/project/lidar/>`_ (Qiusheng Wu; MIT
  licence), a LiDAR-derived DEM: 400 × 400 float32 heights in metres (379.7 to
  410.8), cells of 1 m, NAD83 / UTM zone 15N with its north-west corner at
  E 429,252 m, N 5,150,885 m — about 46.5° N, 93.9° W (central Minnesota).
  The package's runtime dependencies are not needed: install it with
  ``pip install --no-deps lidar==0.8.4`` (``make install-dev`` does).  The file is
  found through the package's installed metadata, without importing the package,
  and read by :func:`persistri.impl.terrain.grids.read_grid` (``tifffile``, the
  ``geotiff`` extra).  It is optional: :func:`dem_missing` says whether it and its
  reader are installed, and Fig. 11 leaves it out, with a note, when they are not.

Both are loaded without a network.  matplotlib's other elevation sample,
``topobathy.npz`` (91 × 120 cells), has fewer samples than Fig. 11's largest
mesh (12,800 points), so it cannot serve.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "Dem", "DemUnavailableError", "DEMS", "LIDAR_REQUIREMENT", "dem_missing", "load_dem", "jacksboro_dem", "lidar_dem",
]

LIDAR_REQUIREMENT: Final = "lidar==0.8.4"
"""The PyPI release whose wheel ships the second DEM (``lidar/data/dem.tif``)."""


class DemUnavailableError(LookupError):
    """A DEM's shipping package is not installed (the message says how to install it)."""


@dataclass(frozen=True, slots=True)
class Dem:
    """A height grid and where it comes from."""

    name: str
    """Short name (``jacksboro``, ``lidar``)."""
    label: str
    """For figure legends."""
    heights: NDArray[np.float64]
    source: str
    """Where the data come from, in a sentence."""
    cell: str
    """The cell size, in words."""

    @property
    def shape(self) -> tuple[int, int]:
        """``(rows, cols)``."""
        return (int(self.heights.shape[0]), int(self.heights.shape[1]))


def jacksboro_dem() -> Dem:
    """matplotlib's Jacksboro fault DEM (344 × 403, metres)."""
    from persistri.impl.terrain.grids import jacksboro

    g = jacksboro()
    return Dem(
        "jacksboro",
        "Jacksboro",
        g.heights,
        "matplotlib's sample data jacksboro_fault_dem.npz (the Jacksboro fault, Tennessee)",
        "1/1200 degree (≈ 3 arc-seconds)",
    )


@contextmanager
def _quiet_tifffile() -> Iterator[None]:
    """Silence tifffile's log line about the file's GDAL_NODATA tag (-3.4e38 does not fit its float32 parser;
    the grid has no no-data cell, which :func:`lidar_dem` checks)."""
    log = logging.getLogger("tifffile")
    level = log.level
    log.setLevel(logging.CRITICAL)
    try:
        yield
    finally:
        log.setLevel(level)


def _lidar_path() -> Path:
    from importlib.metadata import PackageNotFoundError, distribution

    try:
        dist = distribution("lidar")
    except PackageNotFoundError:
        raise DemUnavailableError(
            "the second DEM of Fig. 11 ships in the PyPI package 'lidar' (lidar/data/dem.tif), which is not "
            f"installed: pip install --no-deps {LIDAR_REQUIREMENT}"
        ) from None
    path = Path(str(dist.locate_file("lidar/data/dem.tif")))
    if not path.is_file():
        raise DemUnavailableError(f"the installed lidar {dist.version} has no lidar/data/dem.tif; install {LIDAR_REQUIREMENT}")
    return path


def _lidar_reader() -> None:
    from importlib.util import find_spec

    if find_spec("tifffile") is None:
        raise DemUnavailableError(
            "the second DEM of Fig. 11 (lidar/data/dem.tif) is a GeoTIFF, and reading it needs tifffile, which is "
            "not installed: pip install 'persistri[geotiff]'"
        )


def lidar_dem() -> Dem:
    """The LiDAR DEM shipped by the PyPI package ``lidar`` (400 × 400, 1 m cells); module docstring.

    Raises :class:`DemUnavailableError` when the package or the GeoTIFF reader
    (tifffile) is not installed, and ValueError if the file holds no-data cells
    (this release's has none).
    """
    from persistri.impl.terrain.grids import as_heights, read_grid

    path = _lidar_path()
    _lidar_reader()
    with _quiet_tifffile():
        grid = read_grid(path)
    heights = as_heights(grid.heights, what=str(path))  # ValueError on no-data cells
    return Dem(
        "lidar",
        "LiDAR, Minnesota",
        heights,
        f"lidar/data/dem.tif from the PyPI package {LIDAR_REQUIREMENT} (a LiDAR-derived DEM, NAD83 / UTM 15N, "
        "≈ 46.5° N 93.9° W)",
        "1 m",
    )


DEMS: Final[dict[str, Callable[[], Dem]]] = {"jacksboro": jacksboro_dem, "lidar": lidar_dem}
"""The DEMs Fig. 11 can run on, by name."""


def _lidar_installed() -> None:
    _lidar_path()
    _lidar_reader()


_INSTALLED: Final[dict[str, Callable[[], None]]] = {"jacksboro": lambda: None, "lidar": _lidar_installed}
"""Per DEM, a check that what ships and reads it is installed (:class:`DemUnavailableError` if not);
matplotlib, which ships the Jacksboro DEM, is a dependency of persistri."""


def dem_missing(name: str) -> str | None:
    """Why the DEM ``name`` cannot be loaded here (one line saying what to install), or ``None`` if it can.

    Checks the installed packages without reading the DEM.  ValueError names the known DEMs.
    """
    if name not in DEMS:
        raise ValueError(f"unknown DEM {name!r}; known: {', '.join(DEMS)}")
    try:
        _INSTALLED[name]()
    except DemUnavailableError as exc:
        return str(exc)
    return None


def load_dem(name: str) -> Dem:
    """The DEM called ``name`` (:data:`DEMS`); ValueError names the known ones."""
    try:
        make = DEMS[name]
    except KeyError:
        raise ValueError(f"unknown DEM {name!r}; known: {', '.join(DEMS)}") from None
    return make()
