"""DEMs read in windows: a height grid as a Dask array, never loaded whole by one process (issue 18).

:func:`open_dem` opens a grid lazily — only its header is read — as a :class:`Dem`:
a :class:`DemSource` that reads any window of samples on demand, the grid's
transform (and CRS), and :attr:`Dem.heights`, the same grid as a
:class:`dask.array.Array` whose chunks are windows read by the source.

* ``.npy`` — memory-mapped (``numpy.load(mmap_mode="r")``): a window reads its rows;
* ``.tif`` / ``.tiff`` — through ``tifffile``'s Zarr interface
  (``tifffile.imread(path, aszarr=True)`` opened with ``zarr``): a window decodes
  only the strips or tiles it touches; the transform, CRS and ``GDAL_NODATA`` as
  :mod:`persistri.impl.terrain.geotiff` reads them;
* ``.zarr`` — a Zarr store (a directory): its 2D array, or in a group the array
  named ``elevation``, ``heights``, ``z`` or ``dem``, or the only 2D one;
* anything else :func:`~persistri.impl.terrain.grids.read_grid` reads (``.npz``,
  ``.asc``, ``jacksboro``), a numpy array or a Dask array: these are held in
  memory (an ``.npz`` or ``.asc`` cannot be read in windows), and a cluster's
  workers each get one copy.

A source is a small picklable value (a path and a shape): a worker given one
opens the file itself, so a task's memory is its window's, whatever the grid's
size.  On a cluster the path must name a file every worker can read.

No-data cells, and the one pass that checks every cell, are
:mod:`persistri.impl.scale.terrain_nodata`'s.  Not in the paper: the input side
of §5's meshes at scale.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final, Protocol

import numpy as np
from numpy.typing import NDArray

from persistri.impl.terrain.grids import GridTransform, read_grid

if TYPE_CHECKING:
    import dask.array as da

__all__ = [
    "LAZY_FORMATS",
    "DemSource",
    "NpySource",
    "TiffSource",
    "ZarrSource",
    "ArraySource",
    "DaskSource",
    "Dem",
    "open_dem",
]

FloatArray = NDArray[np.float64]

LAZY_FORMATS: Final = (".npy", ".tif", ".tiff", ".zarr")
"""The formats read in windows (the others are read whole)."""

_ZARR_NAMES: Final = ("elevation", "heights", "z", "dem")


class DemSource(Protocol):
    """What reads windows of a grid: its ``shape``, a ``name`` for messages, and :meth:`read`."""

    @property
    def shape(self) -> tuple[int, int]: ...

    @property
    def name(self) -> str: ...

    def read(self, r0: int, r1: int, c0: int, c1: int) -> FloatArray:
        """Rows ``r0 … r1 − 1`` and columns ``c0 … c1 − 1`` as float64, NaN where the file has no data."""
        ...


def _as_float(raw: NDArray[Any], name: str, r0: int, c0: int, nodata: NDArray[np.bool_] | None = None) -> FloatArray:
    """A window as float64 (a copy), refusing integers float64 cannot hold exactly (their cell named; the
    ``nodata`` cells, which the caller makes NaN, are not heights and may be anything)."""
    if raw.dtype.kind not in "biuf":
        raise ValueError(f"{name}: the heights are not numbers (dtype {raw.dtype})")
    out: FloatArray = np.array(raw, dtype=np.float64, copy=True)
    if raw.dtype.kind in "iu" and raw.dtype.itemsize >= 8 and raw.size:
        from persistri.impl.terrain.exact_heights import rounded_integers

        inexact = rounded_integers(raw, out)  # 2^53 + 1 becomes 2^53, which is not beyond 2^53: cast back
        if nodata is not None:
            inexact &= ~nodata
        if bool(inexact.any()):
            r, c = np.argwhere(inexact)[0]
            raise ValueError(f"{name}: the integer height at (row {r0 + r}, col {c0 + c}) is not exactly representable as float64")
    return out


@dataclass(frozen=True, slots=True)
class NpySource:
    """A ``.npy`` grid, memory-mapped on every read (a window costs its rows' pages)."""

    path: str
    shape: tuple[int, int]

    @property
    def name(self) -> str:
        return self.path

    def read(self, r0: int, r1: int, c0: int, c1: int) -> FloatArray:
        arr = np.load(self.path, mmap_mode="r", allow_pickle=False)
        return _as_float(np.asarray(arr[r0:r1, c0:c1]), self.path, r0, c0)


@dataclass(frozen=True, slots=True)
class TiffSource:
    """A GeoTIFF's first page, through tifffile's Zarr store: a read decodes only the strips or tiles of its window."""

    path: str
    shape: tuple[int, int]
    nodata: float | int | None

    @property
    def name(self) -> str:
        return self.path

    def read(self, r0: int, r1: int, c0: int, c1: int) -> FloatArray:
        import logging

        import tifffile
        import zarr

        log = logging.getLogger("tifffile")
        quiet, log.disabled = log.disabled, True  # it logs what it then raises
        try:
            with tifffile.imread(self.path, aszarr=True, key=0) as store:
                z: Any = zarr.open_array(store, mode="r")
                raw = np.asarray(z[r0:r1, c0:c1]).reshape(r1 - r0, c1 - c0)  # one band: (rows, cols[, 1])
        except Exception as exc:  # a codec imagecodecs lacks, a corrupt tile: one line naming the file
            raise ValueError(f"{self.path}: cannot decode rows {r0}–{r1 - 1}: {' '.join(str(exc).split()) or type(exc).__name__}") from None
        finally:
            log.disabled = quiet
        missing = None
        if self.nodata is not None:
            from persistri.impl.terrain.geotiff import nodata_cells  # in the band's type, as GDAL compares

            missing = nodata_cells(raw, self.nodata)
        out = _as_float(raw, self.path, r0, c0, missing)
        if missing is not None:
            out[missing] = np.nan
        return out


@dataclass(frozen=True, slots=True)
class ZarrSource:
    """A 2D array in a Zarr store (``key`` names it inside a group; None: the store is the array)."""

    path: str
    key: str | None
    shape: tuple[int, int]

    @property
    def name(self) -> str:
        return self.path

    def read(self, r0: int, r1: int, c0: int, c1: int) -> FloatArray:
        import zarr

        node: Any = zarr.open(self.path, mode="r")
        arr: Any = node[self.key] if self.key is not None else node
        return _as_float(np.asarray(arr[r0:r1, c0:c1]), self.path, r0, c0)


@dataclass(frozen=True, slots=True, eq=False)
class ArraySource:
    """A grid held in memory (float64, NaN for no-data)."""

    heights: FloatArray
    source: str

    @property
    def shape(self) -> tuple[int, int]:
        return (int(self.heights.shape[0]), int(self.heights.shape[1]))

    @property
    def name(self) -> str:
        return self.source

    def read(self, r0: int, r1: int, c0: int, c1: int) -> FloatArray:
        return np.array(self.heights[r0:r1, c0:c1], dtype=np.float64, copy=True)


class DaskSource:
    """A user's Dask array: a window is computed in the reading process (synchronously) from its chunks.

    A plain class, not a dataclass: ``dask.delayed`` looks inside dataclasses for
    collections and would compute the whole array as a task's input.
    """

    __slots__ = ("array", "source")

    def __init__(self, array: da.Array, source: str) -> None:
        self.array = array
        self.source = source

    @property
    def shape(self) -> tuple[int, int]:
        return (int(self.array.shape[0]), int(self.array.shape[1]))

    @property
    def name(self) -> str:
        return self.source

    def read(self, r0: int, r1: int, c0: int, c1: int) -> FloatArray:
        raw = np.asarray(self.array[r0:r1, c0:c1].compute(scheduler="sync"))
        return _as_float(raw, self.source, r0, c0)


class _Chunks:
    """A :class:`DemSource` seen as an array (``shape``, ``dtype``, ``ndim``, slicing) for :func:`dask.array.from_array`."""

    def __init__(self, source: DemSource) -> None:
        self.source = source
        self.shape = source.shape
        self.dtype = np.dtype(np.float64)
        self.ndim = 2

    def __getitem__(self, key: tuple[slice, slice]) -> FloatArray:
        rows, cols = key
        r0, r1, _ = rows.indices(self.shape[0])
        c0, c1, _ = cols.indices(self.shape[1])
        return self.source.read(r0, r1, c0, c1)


@dataclass(frozen=True, eq=False)
class Dem:
    """A grid opened lazily: its :class:`DemSource`, transform (CRS included) and a name for messages."""

    source: DemSource
    transform: GridTransform | None
    name: str

    @property
    def shape(self) -> tuple[int, int]:
        """``(rows, cols)``."""
        return self.source.shape

    def heights(self, chunks: int = 1024) -> da.Array:
        """The grid as a Dask array of float64 (NaN for no-data) in ``chunks × chunks`` windows, each read by the source."""
        import dask.array as da
        from dask.base import tokenize

        from_array: Any = da.from_array  # dask's functions are not annotated
        if isinstance(self.source, DaskSource):
            cast: Any = self.source.array.astype
            out: da.Array = cast(np.float64)
            return out
        if isinstance(self.source, ArraySource):
            out = from_array(self.source.heights, chunks=(chunks, chunks))
            return out
        name = f"persistri-dem-{tokenize(type(self.source).__name__, self.name, self.shape, chunks)}"
        out = from_array(_Chunks(self.source), chunks=(chunks, chunks), asarray=True, lock=False, fancy=False, name=name)
        return out


def open_dem(source: Any, *, transform: GridTransform | None = None) -> Dem:
    """Open ``source`` lazily (module docstring): a path, the word ``jacksboro``, a numpy array or a Dask array.

    Reads headers only for ``.npy``, ``.tif``/``.tiff`` and ``.zarr``.  Every
    failure is a one-line :class:`ValueError` naming the file (missing, unreadable,
    not 2D, not numbers, smaller than 2 × 2).  ``transform`` georeferences an array.
    """
    if _is_dask(source):
        arr = source
        _check_shape(tuple(int(v) for v in arr.shape), arr.dtype, "dask array")
        return Dem(DaskSource(arr, "dask array"), transform, "dask array")
    if isinstance(source, np.ndarray):
        _check_shape(source.shape, source.dtype, "array")
        return Dem(ArraySource(_as_float(source, "array", 0, 0), "array"), transform, "array")
    text = str(source)
    path = Path(text)
    suffix = path.suffix.lower()
    if suffix == ".npy" and path.is_file():
        return Dem(_open_npy(path), None, text)
    if suffix in (".tif", ".tiff") and path.is_file():
        src, tf = _open_tiff(path)
        return Dem(src, tf, text)
    if suffix == ".zarr" or (path.is_dir() and ((path / "zarr.json").exists() or (path / ".zarray").exists() or (path / ".zgroup").exists())):
        return Dem(_open_zarr(path), None, text)
    grid = read_grid(text)
    return Dem(ArraySource(grid.heights, grid.source), grid.transform, grid.source)


def _is_dask(obj: Any) -> bool:
    return type(obj).__module__.startswith("dask.array") and hasattr(obj, "chunks")


def _check_shape(shape: tuple[int, ...], dtype: np.dtype[Any], name: str) -> None:
    if dtype.kind not in "biuf" or dtype.fields is not None:
        raise ValueError(f"{name}: holds {dtype} values, not real numbers")
    if len(shape) != 2:
        raise ValueError(f"{name}: expected a 2D grid (rows, cols), got shape {shape}")
    if shape[0] < 2 or shape[1] < 2:
        raise ValueError(f"{name}: a terrain needs at least 2 rows and 2 columns, got shape {shape}")


def _open_npy(path: Path) -> NpySource:
    from persistri.impl.files import InputFileError

    with path.open("rb") as fh:
        if fh.read(6) != b"\x93NUMPY":
            raise InputFileError(path, "not a .npy file (no NumPy header)")
    try:
        arr = np.load(path, mmap_mode="r", allow_pickle=False)
    except (ValueError, OSError, EOFError) as exc:
        raise InputFileError(path, f"cannot read .npy ({str(exc).splitlines()[0]})") from None
    _check_shape(tuple(arr.shape), arr.dtype, str(path))
    return NpySource(str(path), (int(arr.shape[0]), int(arr.shape[1])))


def _open_tiff(path: Path) -> tuple[TiffSource, GridTransform | None]:
    """The page's shape and no-data value and the file's transform, from its tags (no pixel is decoded)."""
    try:
        import tifffile
    except ImportError:
        raise ValueError(f"{path}: reading GeoTIFF needs tifffile: pip install 'persistri[geotiff]'") from None
    from persistri.impl.terrain.geotiff import _tiff_transform

    try:
        tif = tifffile.TiffFile(path)
    except Exception as exc:  # tifffile raises many types for malformed files
        raise ValueError(f"{path}: cannot read TIFF ({exc})") from None
    with tif:
        page = tif.pages[0] if len(tif.pages) else None
        if not isinstance(page, tifffile.TiffPage):
            raise ValueError(f"{path}: the TIFF holds no image")
        shape = tuple(int(v) for v in page.shape)
        if len(shape) == 3 and 1 in (shape[0], shape[-1]):
            shape = shape[1:] if shape[0] == 1 else shape[:-1]
        if len(shape) != 2:
            raise ValueError(f"{path}: expected one band of heights, got {page.samplesperpixel} samples per pixel (shape {page.shape})")
        _check_shape(shape, np.dtype(page.dtype), str(path))
        nodata_tag = page.tags.valueof(42113)  # GDAL_NODATA
        geokeys: dict[str, Any] = dict(page.geotiff_tags or {}) if page.is_geotiff else {}
        for code, name in ((33550, "ModelPixelScale"), (33922, "ModelTiepoint"), (34264, "ModelTransformation")):
            if name not in geokeys and page.tags.valueof(code) is not None:
                geokeys[name] = page.tags.valueof(code)
    nodata: float | int | None = None
    if nodata_tag is not None:
        text = str(nodata_tag).strip().strip("\x00")
        try:  # an integer band's tag as the integer it spells (UInt64 max rounds to 2^64 as a double), as GDAL reads it
            nodata = int(text) if np.dtype(page.dtype).kind in "iu" and re.fullmatch(r"[-+]?\d+", text) else float(text)
        except ValueError:
            raise ValueError(f"{path}: GDAL_NODATA tag is not a number: {nodata_tag!r}") from None
    return TiffSource(str(path), (shape[0], shape[1]), nodata), _tiff_transform(path, geokeys)


def _open_zarr(path: Path) -> ZarrSource:
    try:
        import zarr
    except ImportError:
        raise ValueError(f"{path}: reading Zarr needs zarr: pip install 'persistri[dask]'") from None
    if not path.exists():
        raise ValueError(f"{path}: no such file or directory")
    try:
        node = zarr.open(str(path), mode="r")
    except Exception as exc:  # zarr raises several types for what is not a store
        raise ValueError(f"{path}: not a Zarr store ({' '.join(str(exc).split()) or type(exc).__name__})") from None
    key: str | None = None
    if isinstance(node, zarr.Group):
        arrays = {k: v for k, v in node.arrays() if len(v.shape) == 2}
        key = next((k for k in _ZARR_NAMES if k in arrays), None)
        if key is None:
            if len(arrays) != 1:
                raise ValueError(f"{path}: cannot tell which array holds the heights; name it one of {', '.join(_ZARR_NAMES)}")
            key = next(iter(arrays))
        arr = arrays[key]
    else:
        arr = node
    _check_shape(tuple(int(v) for v in arr.shape), np.dtype(str(arr.dtype)), str(path))
    return ZarrSource(str(path), key, (int(arr.shape[0]), int(arr.shape[1])))
