"""GeoTIFF height grids: the first page's one band of heights, its transform, CRS and no-data value.

Read with ``tifffile`` (the optional extra ``persistri[geotiff]``), whose
``imagecodecs`` decodes the compressions GDAL writes — LZW, deflate, zstd,
PackBits, LZMA… with horizontal or floating-point predictors, in strips or tiles.

* the transform: ``ModelPixelScale`` and ``ModelTiepoint`` (a north-up raster) or
  an axis-aligned ``ModelTransformation`` (north-up or south-up); a sample is the
  centre of its pixel for ``PixelIsArea`` (the default) and the pixel position for
  ``PixelIsPoint`` (GeoTIFF 1.1, §2.6 and §7.1).  Rotated or sheared rasters are
  refused;
* the CRS: from the GeoKeys (:func:`~persistri.impl.terrain.crs.crs_from_geokeys`),
  carried by the transform;
* no-data: the cells holding the ``GDAL_NODATA`` tag's value (compared in the band's type; an integer
  band's tag read as the exact integer it spells, as GDAL reads Int64 bands' tags) become NaN;
* integer heights a double would round (int64 or uint64 beyond 2^53) are refused, naming the cell.

A codec nothing decodes, a missing ``imagecodecs`` and a multi-band raster are
each one error line naming the file.  Not in the paper: the inputs of §5's meshes.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from persistri.impl.file_errors import shown
from persistri.impl.terrain.crs import crs_from_geokeys
from persistri.impl.terrain.exact_heights import float_heights
from persistri.impl.terrain.grids import GridTransform, HeightGrid

__all__ = ["nodata_cells", "read_geotiff"]


def read_geotiff(path: Path) -> HeightGrid:
    """The height grid of the GeoTIFF ``path`` (module docstring); every failure a one-line :class:`ValueError` naming it."""
    try:
        import tifffile
    except ImportError:
        raise ValueError(f"{path}: reading GeoTIFF needs tifffile: pip install 'persistri[geotiff]'") from None
    try:
        tif = tifffile.TiffFile(path)
    except Exception as exc:  # tifffile raises many types for malformed files
        raise ValueError(f"{path}: cannot read TIFF ({exc})") from None
    with tif:
        page = tif.pages[0] if len(tif.pages) else None
        if not isinstance(page, tifffile.TiffPage):
            raise ValueError(f"{path}: the TIFF holds no image")
        codec = _codec_name(page)
        try:
            data = np.asarray(page.asarray())
        except Exception as exc:  # a codec imagecodecs lacks, or a corrupt strip or tile
            raise ValueError(f"{path}: cannot decode its {codec} compression ({_reason(exc)})") from None
        nodata = page.tags.valueof(42113)  # GDAL_NODATA
        geokeys: dict[str, Any] = dict(page.geotiff_tags or {}) if page.is_geotiff else {}
        # A file with model tags but no GeoKeyDirectory is no GeoTIFF to tifffile; its tags still place it.
        for code, name in ((33550, "ModelPixelScale"), (33922, "ModelTiepoint"), (34264, "ModelTransformation")):
            if name not in geokeys and page.tags.valueof(code) is not None:
                geokeys[name] = page.tags.valueof(code)
    # tifffile gives one band as (rows, cols); several as (rows, cols, samples) or (samples, rows, cols).
    if data.ndim == 3 and 1 in (data.shape[0], data.shape[-1]):
        data = data.reshape(data.shape[1:] if data.shape[0] == 1 else data.shape[:-1])
    if data.ndim != 2:
        raise ValueError(
            f"{path}: expected one band of heights, got {page.samplesperpixel} samples per pixel (shape {data.shape})"
        )
    missing: NDArray[np.bool_] | None = None
    if nodata is not None:
        text = str(nodata).strip().strip("\x00")
        try:
            # An integer band's tag is read as the integer it spells (GDAL 3.5+ for Int64/UInt64 bands): as a double,
            # 18446744073709551615 (UInt64 max, a usual no-data) would round to 2^64 and match no cell.
            value: float | int = int(text) if data.dtype.kind in "iu" and _INTEGER.fullmatch(text) else float(text)
        except ValueError:
            raise ValueError(f"{path}: GDAL_NODATA tag is not a number: {shown(str(nodata))}") from None
        missing = nodata_cells(data, value)
    heights = float_heights(data, str(path), missing).copy()  # no-data cells need not be exact heights
    if missing is not None:
        heights[missing] = np.nan
    return HeightGrid(heights, _tiff_transform(path, geokeys), str(path))


_INTEGER = re.compile(r"[-+]?\d+")
"""A GDAL_NODATA tag spelling an integer."""


def nodata_cells(data: NDArray[Any], value: float | int) -> NDArray[np.bool_]:
    """The cells of the band ``data`` that hold the no-data ``value`` (the GDAL_NODATA tag, as a double). O(size).

    As GDAL reads the tag: the value is first converted to the band's own type, and the
    cells are compared in that type.  A float32 band written with the tag
    ``-3.4028235e+38`` (float32's lowest value, printed as a float32) or ``-9999.9``
    holds float32 cells that equal no double of that spelling: compared as doubles,
    no cell would match and the no-data cells would become heights.  An integer band
    matches only an integral value within its range (``-9999.5`` matches no cell); an integer
    ``value`` (a tag spelling one, read exactly) is compared as that integer, so a 64-bit band's
    ``18446744073709551615`` or ``9007199254740993`` matches those cells, not their roundings.
    """
    if data.dtype.kind == "f":
        with np.errstate(over="ignore"):
            cast = np.asarray(value, dtype=np.float64).astype(data.dtype)
        if np.isinf(cast) and not np.isinf(value):  # beyond the band's range: no cell can hold it
            return np.zeros(data.shape, dtype=np.bool_)
        cells: NDArray[np.bool_] = data == cast
        return cells
    if isinstance(value, int) and not isinstance(value, bool) and data.dtype.kind in "iu":  # exactly, as GDAL's Int64 tag
        info = np.iinfo(data.dtype)
        if info.min <= value <= info.max:
            exact: NDArray[np.bool_] = data == data.dtype.type(value)
            return exact
        return np.zeros(data.shape, dtype=np.bool_)
    if data.dtype.kind in "iu" and np.isfinite(value) and value == int(value):
        info = np.iinfo(data.dtype)
        if info.min <= int(value) <= info.max:
            ints: NDArray[np.bool_] = data == data.dtype.type(int(value))
            return ints
    return np.zeros(data.shape, dtype=np.bool_)


def _codec_name(page: Any) -> str:
    """The page's compression and predictor as a reader names them: ``LZW``, ``ADOBE_DEFLATE + predictor FLOATINGPOINT``."""
    compression = getattr(page.compression, "name", str(page.compression))
    predictor = int(getattr(page, "predictor", 1) or 1)
    if predictor == 1:
        return str(compression)
    return f"{compression} + predictor {getattr(page.predictor, 'name', predictor)}"


def _reason(exc: BaseException) -> str:
    """Why decoding failed, in one line: tifffile says "<COMPRESSION.X: n> requires the 'imagecodecs' package"."""
    text = " ".join(str(exc).split()) or type(exc).__name__
    # tifffile names a codec it has no decoder for ("COMPRESSION.EER_V0: 65000") or cannot name ("… is not a known …").
    if isinstance(exc, KeyError) or "is not a known" in text or text.startswith(("COMPRESSION.", "PREDICTOR.")):
        return f"neither tifffile nor imagecodecs decodes it: {text}"
    if "imagecodecs" in text:
        return f"{text}: pip install 'persistri[geotiff]'"
    return text


def _tiff_transform(path: Path, geokeys: dict[str, Any]) -> GridTransform | None:
    """The transform of a GeoTIFF from its decoded GeoTIFF tags (GeoTIFF 1.1 §2.6 and §7.1), CRS included.

    Sample (row, col) is the centre of a pixel for ``PixelIsArea`` rasters (the
    default; tie points and the model transformation address pixel corners) and
    the pixel position itself for ``PixelIsPoint``.
    """
    raster_type = geokeys.get("GTRasterTypeGeoKey")
    shift = 0.0 if raster_type is not None and int(raster_type) == 2 else 0.5  # 2 = PixelIsPoint
    crs = crs_from_geokeys(geokeys)
    scale, tie = geokeys.get("ModelPixelScale"), geokeys.get("ModelTiepoint")
    if scale is not None and tie is not None and len(scale) >= 2 and len(tie) >= 6:
        i, j, x, y = float(tie[0]), float(tie[1]), float(tie[3]), float(tie[4])
        sx, sy = float(scale[0]), float(scale[1])
        # ModelPixelScale is positive along both axes with y decreasing down the rows: a north-up raster.
        return GridTransform(x + (shift - i) * sx, y - (shift - j) * sy, sx, -sy, crs)
    matrix = geokeys.get("ModelTransformation")
    if matrix is not None:
        m = np.asarray(matrix, dtype=np.float64).reshape(4, 4)
        if m[0, 1] != 0 or m[1, 0] != 0:
            raise ValueError(
                f"{path}: the raster is rotated or sheared (ModelTransformation {m[0, :2].tolist()}, "
                f"{m[1, :2].tolist()}); persistri reads axis-aligned rasters only"
            )
        sx, sy = float(m[0, 0]), float(m[1, 1])
        return GridTransform(float(m[0, 3]) + shift * sx, float(m[1, 3]) + shift * sy, sx, sy, crs)
    return None
