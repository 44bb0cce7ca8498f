"""Height grids: validation at the API boundary, georeferencing, and reading them from files.

A height grid is a 2D array of samples: ``heights[row, col]``.  persistri puts
sample ``(row, col)`` at ``x = col``, ``y = row`` — row 0 is the array's first
row, nothing is flipped — and an optional :class:`GridTransform` maps these grid
coordinates to world coordinates (``x0 + col·dx``, ``y0 + row·dy``; north-up
rasters have ``dy < 0``), and carries the coordinate reference system the file
states (:class:`~persistri.impl.terrain.crs.Crs`), if any.  A transform whose
determinant ``dx·dy`` is negative (north-up, or east-left) mirrors the plane:
:meth:`GridTransform.world_triangles` reverses triangles that are
counterclockwise in grid coordinates so that they stay counterclockwise — normals
up — in world coordinates.

Inputs (:func:`read_grid`):

* ``.npy`` — a 2D array;
* ``.npz`` — the array named ``elevation``, ``heights``, ``z`` or ``dem``, or the
  only 2D array in the file; if the file also holds ``xmin``, ``ymin``, ``dx`` and
  ``dy`` (as matplotlib's Jacksboro sample does), they give the transform;
* ``.asc`` — an ESRI ASCII grid (header ``ncols``, ``nrows``, ``xllcorner`` or
  ``xllcenter``, ``yllcorner`` or ``yllcenter``, ``cellsize`` or ``dx``/``dy``,
  optional ``NODATA_value``; rows from north to south, which become rows 0, 1, …),
  and its CRS from the ``.prj`` file of the same name beside it, if there is one
  (:mod:`persistri.impl.terrain.esri_grid`, which also writes one);
* ``.csv`` / ``.txt`` (or gzip-compressed, ``.csv.gz``) — text, one row of heights per line, every row as long
  (the text rules of the point files, :mod:`persistri.impl.files`: commas,
  semicolons, tabs or spaces; header lines, ``#`` comments; ``nan`` is no-data).
  A ragged row is an error naming its line.  A table of exactly three columns
  is refused as what it almost always is, ``x y z`` points (mesh those with
  ``persistri delaunay``); no georeferencing;
* ``.tif`` / ``.tiff`` — a GeoTIFF, compressed or not, through ``tifffile`` (the
  optional extra ``persistri[geotiff]``): its transform, CRS and ``GDAL_NODATA``
  (:mod:`persistri.impl.terrain.geotiff`);
* ``.png`` — a heightmap: one grayscale band of 8 or 16 bits (or 32-bit integers or
  floats), each pixel's value its height as stored (scale it yourself: a 16-bit
  heightmap's 0–65535 are rarely metres); row 0 is the image's top row; read by
  Pillow (which matplotlib needs); no georeferencing.  A colour image is refused: its
  colours are not heights;
* the word ``jacksboro``: the DEM shipped with matplotlib
  (``jacksboro_fault_dem.npz``, 344 × 403 integer heights in metres, cells of
  1/1200 degree).

No-data cells (the file's no-data value, NaN) become NaN in :attr:`HeightGrid.heights`;
:func:`as_heights` decides what happens to them (``nodata=``).
"""

from __future__ import annotations

import logging
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.terrain.crs import Crs
from persistri.impl.terrain.exact_heights import exact_objects, float_heights, ragged_row, refuse_rounded

__all__ = [
    "GRID_FORMATS",
    "NODATA_RULES",
    "HEIGHT_LIMIT",
    "GridTransform",
    "HeightGrid",
    "as_heights",
    "as_transform",
    "read_grid",
    "jacksboro",
]

GRID_FORMATS: Final = (".npy", ".npz", ".asc", ".csv", ".txt", ".tif", ".tiff", ".png")
"""The file extensions :func:`read_grid` reads (and the word ``jacksboro``)."""

NODATA_RULES: Final = ("error", "fill", "min")
"""The named no-data rules of :func:`as_heights` (a number is accepted too)."""


_NPZ_NAMES: Final = ("elevation", "heights", "z", "dem")

HEIGHT_LIMIT: Final = 1e250
"""Largest accepted |height|: planes through heights and grid coordinates stay far from float64 overflow."""


@dataclass(frozen=True, slots=True)
class GridTransform:
    """The affine map from grid coordinates to world coordinates: ``(x0 + col·dx, y0 + row·dy)``.

    ``(x0, y0)`` is the world position of sample ``(row 0, col 0)`` and ``dx``,
    ``dy`` the cell size along columns and rows (``dy`` negative for north-up
    rasters, whose row 0 is the northernmost); ``crs`` the coordinate reference
    system of the world coordinates, when the file states one.  A presentation of
    results: the triangulation itself is computed in exact grid coordinates.
    """

    x0: float
    y0: float
    dx: float
    dy: float
    crs: Crs | None = None

    @property
    def mirrors(self) -> bool:
        """Whether the map reverses orientation: its determinant ``dx·dy`` is negative (north-up or east-left rasters)."""
        return (self.dx < 0) != (self.dy < 0)

    def world_triangles(self, triangles: NDArray[np.intp]) -> NDArray[np.intp]:
        """``triangles``, counterclockwise in grid coordinates, made counterclockwise in world coordinates. O(m).

        The one place persistri decides the orientation of world output: a
        mirroring transform (:attr:`mirrors`) turns counterclockwise into clockwise,
        so each triangle ``(a, b, c)`` becomes ``(a, c, b)`` — the same first vertex,
        normals up (+z) again.  A new array either way.
        """
        tri = np.array(triangles, dtype=np.intp, copy=True).reshape(-1, 3)
        if self.mirrors:
            tri[:, [1, 2]] = tri[:, [2, 1]]
        return tri

    def apply(self, xy: NDArray[np.float64]) -> NDArray[np.float64]:
        """World coordinates of the grid coordinates ``xy`` (``(k, 2)`` or ``(k, 3)``; a third column is copied)."""
        out = np.array(xy, dtype=np.float64, copy=True)
        out[:, 0] = self.x0 + out[:, 0] * self.dx
        out[:, 1] = self.y0 + out[:, 1] * self.dy
        return out


def as_transform(transform: Any) -> GridTransform | None:
    """``transform`` as a :class:`GridTransform`: None, a GridTransform, ``(x0, y0, dx, dy)``, or
    ``((x0, y0), (dx, dy))`` / ``((x0, y0), cell)`` (origin and cell size).

    Raises :class:`TypeError`/:class:`ValueError` for anything else, for non-finite
    numbers or for a zero cell size.
    """
    if transform is None or isinstance(transform, GridTransform):
        return transform
    try:
        parts = list(transform)
        if len(parts) == 2:
            origin = list(parts[0])
            cell = parts[1]
            size = [cell, cell] if np.ndim(cell) == 0 else list(cell)
            values = [*origin, *size]
        else:
            values = parts
        nums = [float(v) for v in values]
    except (TypeError, ValueError):
        raise TypeError(
            "transform must be (x0, y0, dx, dy) or ((x0, y0), (dx, dy)) or ((x0, y0), cell) of real numbers"
        ) from None
    if len(nums) != 4:
        raise ValueError(f"transform needs 4 numbers (x0, y0, dx, dy), got {len(nums)}")
    if not all(np.isfinite(nums)):
        raise ValueError(f"transform has a non-finite number: {nums}")
    if nums[2] == 0 or nums[3] == 0:
        raise ValueError(f"transform has a zero cell size: dx={nums[2]}, dy={nums[3]}")
    return GridTransform(nums[0], nums[1], nums[2], nums[3])


@dataclass(frozen=True)
class HeightGrid:
    """A grid as read from a file: ``heights`` (float64, NaN where the file had no data), its transform, and its source."""

    heights: NDArray[np.float64]
    transform: GridTransform | None
    source: str

    @property
    def crs(self) -> Crs | None:
        """The coordinate reference system of the world coordinates (carried by :attr:`transform`), if the file states one."""
        return None if self.transform is None else self.transform.crs


def as_heights(
    heights: ArrayLike, *, nodata: str | float = "error", what: str = "heights", copy: bool = True
) -> NDArray[np.float64]:
    """``heights`` as a validated, C-contiguous ``(rows, cols)`` float64 array with no NaN. O(size).

    ``copy`` — return an array of its own (default), which later changes to the
    caller's array cannot reach; with False, a valid float64 C-contiguous input
    without negative zeros is returned as a read-only view of itself (no copy:
    for a caller that only reads it while it runs).

    Raises :class:`TypeError` for non-numeric input and :class:`ValueError` for
    a ragged, empty, 1-D, 1-row or 1-column array (a terrain needs at least
    2 × 2 samples), for an infinite height or one beyond :data:`HEIGHT_LIMIT`,
    and for NaN (no-data) cells unless
    ``nodata`` says how to treat them:

    * ``"error"`` (default) — a :class:`ValueError` naming how many cells and the first one;
    * ``"fill"`` — each no-data cell takes the height of the nearest valid cell
      (Euclidean distance in grid cells; among equally near cells, the one
      ``scipy.ndimage.distance_transform_edt`` returns, which is deterministic);
    * ``"min"`` — each no-data cell takes the lowest valid height;
    * a number — each no-data cell takes that height.

    A grid with no valid cell at all is an error whatever ``nodata`` says.
    Heights must be exactly representable as float64: integers beyond 2^53 that are not doubles,
    Fractions like 1/3, integers of a list numpy reads as float64 are refused, never rounded.
    """
    if isinstance(heights, (str, bytes)):
        raise TypeError(f"{what}: expected a 2D array of real numbers, not {type(heights).__name__}")
    try:
        raw = np.asarray(heights)
    except (ValueError, TypeError) as exc:
        raise ValueError(f"{what}: not a rectangular 2D array{ragged_row(heights) or f' (ragged rows?): {exc}'}") from None
    if raw.dtype == object:
        raw = exact_objects(raw, what)
    elif raw.dtype.kind == "f" and raw.ndim == 2 and not isinstance(heights, np.ndarray):
        refuse_rounded(heights, raw, what)
    if raw.dtype.kind not in "biuf":
        raise TypeError(f"{what}: expected real numbers, not {raw.dtype}")
    if raw.ndim != 2:
        raise ValueError(f"{what}: expected a 2D array (rows, cols), got {raw.ndim} dimension(s) of shape {raw.shape}")
    rows, cols = raw.shape
    if rows < 2 or cols < 2:
        raise ValueError(f"{what}: a terrain needs at least 2 rows and 2 columns, got shape {raw.shape}")
    arr = np.ascontiguousarray(raw, dtype=np.float64)
    if raw.dtype.kind in "iuf" and raw.itemsize >= 8 and raw.dtype != np.float64:  # int64, uint64, long double
        with np.errstate(all="ignore"):
            inexact = (arr.astype(raw.dtype) != raw) & (raw == raw)  # NaN is a no-data cell
        if inexact.any():
            r, c = np.argwhere(inexact)[0]
            kind = "an integer height" if raw.dtype.kind in "iu" else f"a {raw.dtype} height"
            raise ValueError(
                f"{what}: {kind} is not exactly representable as float64: cell (row {r}, col {c}) is {raw[r, c]!r}"
            )
    # The extremes first: two reductions, no temporary of the grid's size (they are NaN if a cell is).
    lo, hi = float(arr.min()), float(arr.max())
    if lo != lo or hi != hi:
        valid = arr[~np.isnan(arr)]
        lo, hi = (float(valid.min()), float(valid.max())) if valid.size else (0.0, 0.0)
    if np.isinf(lo) or np.isinf(hi):
        r, c = np.argwhere(np.isinf(arr))[0]
        raise ValueError(f"{what}: cell (row {r}, col {c}) is infinite")
    if max(abs(lo), abs(hi)) > HEIGHT_LIMIT:
        r, c = np.argwhere(np.abs(arr) > HEIGHT_LIMIT)[0]
        raise ValueError(
            f"{what}: cell (row {r}, col {c}) is {arr[r, c]:g}, beyond ±{HEIGHT_LIMIT:g}: the float64 error "
            "measure would overflow"
        )
    missing = np.isnan(arr)
    if not bool(missing.any()):
        if not copy and arr is raw and not (lo <= 0.0 <= hi and bool(np.any(np.signbit(arr) & (arr == 0.0)))):
            view: NDArray[np.float64] = arr.view()
            view.setflags(write=False)
            return view
        out: NDArray[np.float64] = arr + 0.0  # -0.0 becomes 0.0
        return out
    count = int(missing.sum())
    r, c = (int(v) for v in np.argwhere(missing)[0])
    if count == arr.size:
        raise ValueError(f"{what}: every cell is no-data (NaN); nothing to triangulate")
    if isinstance(nodata, str):
        if nodata == "error":
            raise ValueError(
                f"{what}: {count:,} no-data cell{'s' if count != 1 else ''} (NaN), the first at (row {r}, col {c}); "
                "say how to treat them with nodata='fill', 'min' or a height"
            )
        if nodata == "fill":
            from scipy.ndimage import distance_transform_edt

            _, (ri, ci) = distance_transform_edt(missing, return_indices=True)
            arr = arr[ri, ci]
        elif nodata == "min":
            arr = np.where(missing, np.nanmin(arr), arr)
        else:
            raise ValueError(f"nodata must be one of {', '.join(NODATA_RULES)} or a number, got {nodata!r}")
    else:
        if isinstance(nodata, bool) or not isinstance(nodata, (int, float, np.integer, np.floating)):
            raise TypeError(f"nodata must be one of {', '.join(NODATA_RULES)} or a number, got {nodata!r}")
        fill = float(nodata)
        if not np.isfinite(fill) or abs(fill) > HEIGHT_LIMIT:
            raise ValueError(f"nodata fill height must be finite and within ±{HEIGHT_LIMIT:g}, got {fill}")
        arr = np.where(missing, fill, arr)
    filled: NDArray[np.float64] = np.ascontiguousarray(arr, dtype=np.float64) + 0.0
    return filled


# -- reading -------------------------------------------------------------------------------


def jacksboro() -> HeightGrid:
    """The Jacksboro fault DEM shipped with matplotlib: 344 × 403 heights (m), row 0 the northernmost.

    Its transform is in degrees: ``x0 = xmin`` (west edge), ``y0`` the first row's
    latitude (the file's ``ymin`` key, which is the *north* edge), ``dy = -dy``.
    """
    from matplotlib import cbook

    data = cbook.get_sample_data("jacksboro_fault_dem.npz")
    grid = _from_npz(data, "jacksboro")
    return grid


def _from_npz(data: Any, source: str) -> HeightGrid:
    names = list(data.keys())
    arrays = {k: np.asarray(data[k]) for k in names}
    chosen = next((k for k in _NPZ_NAMES if k in arrays and arrays[k].ndim == 2), None)
    if chosen is None:
        two_d = [k for k, a in arrays.items() if a.ndim == 2]
        if len(two_d) != 1:
            held = f"its 2D arrays are {', '.join(two_d)}" if two_d else f"it holds no 2D array (only {', '.join(names) or 'nothing'})"
            raise ValueError(
                f"{source}: cannot tell which array holds the heights ({held}); name it one of {', '.join(_NPZ_NAMES)}"
            )
        chosen = two_d[0]
    heights = float_heights(arrays[chosen], source)
    transform = None
    if all(k in arrays and arrays[k].ndim == 0 for k in ("xmin", "ymin", "dx", "dy")):
        # matplotlib's sample: 'ymin' is the latitude of row 0 (the north edge), rows go south.
        transform = GridTransform(float(arrays["xmin"]), float(arrays["ymin"]), float(arrays["dx"]), -abs(float(arrays["dy"])))
    return HeightGrid(heights, transform, source)


def read_grid(source: str | Path) -> HeightGrid:
    """The height grid in ``source`` (a path with one of :data:`GRID_FORMATS`, or the word ``jacksboro``).

    Every failure is a :class:`ValueError` with one readable line.  The heights
    are returned as read (NaN for no-data); validate them with :func:`as_heights`.
    """
    if isinstance(source, str) and source.lower() == "jacksboro":
        return jacksboro()
    path = Path(source)
    if not path.exists():
        raise ValueError(f"{path}: no such file")
    if path.is_dir():
        raise ValueError(f"{path}: a directory, not a file")
    from persistri.impl.file_errors import special_file

    special = special_file(path)
    if special is not None:  # a pipe: read twice (a header, then the data), it would block for ever
        raise ValueError(f"{path}: {special}")
    suffix = path.suffix.lower()
    if suffix == ".gz" and Path(path.stem).suffix.lower() in (".csv", ".txt"):
        suffix = Path(path.stem).suffix.lower()  # heights.csv.gz: the text reader decompresses it
    if suffix == ".npy":
        from persistri.impl.files import read_npy

        grid = HeightGrid(float_heights(read_npy(path), str(path)), None, str(path))
    elif suffix == ".npz":
        grid = _read_npz(path)
    elif suffix == ".asc":
        from persistri.impl.terrain.esri_grid import read_asc  # esri_grid imports grids: import late

        grid = read_asc(path)
    elif suffix in (".csv", ".txt"):
        grid = _read_text_grid(path)
    elif suffix == ".png":
        grid = _read_png(path)
    elif suffix in (".tif", ".tiff"):
        from persistri.impl.terrain.geotiff import read_geotiff  # grids is imported by geotiff: import late

        tifffile_log = logging.getLogger("tifffile")
        quiet, tifffile_log.disabled = tifffile_log.disabled, True  # it logs to stderr what it then raises or skips
        try:
            grid = read_geotiff(path)
        finally:
            tifffile_log.disabled = quiet
    else:
        from persistri.impl.file_errors import foreign_format

        raise ValueError(
            f"{path}: unknown grid format {suffix or '(no extension)'}; use one of {', '.join(GRID_FORMATS)} or jacksboro{foreign_format(path)}"
        )
    _check_grid(grid, path)
    return grid


_PNG_HEIGHT_MODES: Final = {"L": "8-bit", "I;16": "16-bit", "I;16B": "16-bit", "I": "32-bit integer", "F": "32-bit float"}
"""Pillow's modes of one band of numbers, which a heightmap is."""


def _read_png(path: Path) -> HeightGrid:
    """The grid of a grayscale PNG heightmap (module docstring); a colour or damaged image is one error line. O(pixels)."""
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(path) as image:
            if image.mode not in _PNG_HEIGHT_MODES:
                raise ValueError(
                    f"{path}: an image of mode {image.mode} (colour, palette or alpha); a heightmap is one grayscale "
                    "band of 8 or 16 bits (or 32-bit integers or floats): save it as one"
                )
            pixels = np.asarray(image)
    except (UnidentifiedImageError, OSError, SyntaxError) as exc:  # Pillow's words for a file that is no (whole) PNG
        raise ValueError(f"{path}: cannot read PNG ({' '.join(str(exc).split()) or type(exc).__name__})") from None
    return HeightGrid(float_heights(pixels, str(path)), None, str(path))


def _read_text_grid(path: Path) -> HeightGrid:
    """The grid of a text table of heights (module docstring); no transform."""
    from persistri.impl.files import read_text_table, rounded_integer, rounded_note
    from persistri.impl.text_tables import text_of

    heights = read_text_table(path, "heights")
    if (np.abs(heights) >= 2.0**53).any():  # a height of a list of integers read as its double: rounded?
        token = rounded_integer(text_of(path), heights.ravel())
        if token is not None:
            raise ValueError(f"{path}: the height {rounded_note(token)}")
    if heights.shape[1] == 3 and heights.shape[0] > 3:
        raise ValueError(
            f"{path}: {heights.shape[0]} rows of 3 numbers look like x y z points, not a grid of heights: "
            "triangulate them with `persistri delaunay`, or give the grid as rows of heights (.csv, .asc, .npy)"
        )
    return HeightGrid(heights, None, str(path))


def _read_npz(path: Path) -> HeightGrid:
    """The grid of a ``.npz`` archive (:func:`_from_npz`); a file that is not one is named as such."""
    if path.stat().st_size == 0:
        raise ValueError(f"{path}: the file is empty")
    if not zipfile.is_zipfile(path):
        raise ValueError(f"{path}: not a .npz archive (not a zip file, or a truncated one)")
    try:
        with np.load(path, allow_pickle=False) as data:
            return _from_npz(data, str(path))
    except ValueError as exc:
        if "allow_pickle" in str(exc):
            raise ValueError(f"{path}: holds Python objects (pickled arrays); persistri never unpickles: save numbers") from None
        if str(exc).startswith(f"{path}:"):
            raise
        raise ValueError(f"{path}: cannot read .npz ({str(exc).splitlines()[0]})") from None
    except (OSError, EOFError, zipfile.BadZipFile) as exc:
        raise ValueError(f"{path}: a damaged .npz archive ({str(exc).splitlines()[0] if str(exc) else type(exc).__name__})") from None


def _check_grid(grid: HeightGrid, path: Path) -> None:
    """Fail unless ``grid`` (as read from ``path``) can be a terrain whatever the no-data rule: :func:`as_heights`'s checks,
    and world coordinates within float64's range for every cell.

    The NaN cells are left to the caller's rule; a grid of nothing but NaN is refused here.
    """
    try:
        as_heights(grid.heights, nodata=0.0, what=str(path))
    except (TypeError, ValueError) as exc:
        raise ValueError(str(exc).splitlines()[0]) from None
    if grid.transform is not None:
        rows, cols = grid.heights.shape
        corners = np.array([[0.0, 0.0], [cols - 1.0, 0.0], [0.0, rows - 1.0], [cols - 1.0, rows - 1.0]])
        with np.errstate(over="ignore", invalid="ignore"):  # the overflow is what is looked for
            world = grid.transform.apply(corners)
        if not bool(np.isfinite(world).all()):
            raise ValueError(f"{path}: its georeferencing puts cells beyond float64's range (origin and cell size too large)")
