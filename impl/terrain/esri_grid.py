"""The ESRI ASCII grid (``.asc``): reading one as a :class:`~persistri.impl.terrain.grids.HeightGrid`, and writing one.

The format: a header of ``keyword value`` lines — ``ncols``, ``nrows``, the
lower-left corner or centre (``xllcorner``/``yllcorner`` or ``xllcenter``/``yllcenter``),
``cellsize`` (or ``dx`` and ``dy``), optionally ``NODATA_value`` — then the heights,
blank-separated, the northernmost row first.  Cells holding the no-data value become
NaN (no-data, refused by the terrain unless a ``nodata`` rule says how to treat them);
without a ``NODATA_value`` line the value is -9999, the format's default (ESRI's
definition of the format: "NODATA_value ... Optional. Default is -9999"), so a file
that leaves the line out does not have its holes meshed as pits 9,999 units deep.  A ``.prj`` file of the same name beside
it gives the coordinate system (:mod:`persistri.impl.terrain.crs`).  Read by
:func:`~persistri.impl.terrain.grids.read_grid` for a ``.asc`` path.
"""

from __future__ import annotations

import codecs
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from persistri.impl.file_errors import shown
from persistri.impl.files import rounded_integer, rounded_note
from persistri.impl.terrain.crs import prj_beside, read_prj
from persistri.impl.terrain.grids import GridTransform, HeightGrid

__all__ = ["ESRI_DEFAULT_NODATA", "read_asc", "write_asc"]

ESRI_DEFAULT_NODATA = -9999.0
"""The no-data value of a grid whose header has no ``NODATA_value`` line (the format's default)."""


def read_asc(path: Path) -> HeightGrid:
    """The grid in the ESRI ASCII file ``path`` (module docstring), its CRS from a ``.prj`` beside it.

    Every failure is a :class:`ValueError` naming the file (and the line, for a bad field). O(size).
    """
    header: dict[str, float] = {}
    data = path.read_bytes()
    if data.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):  # saved as "Unicode" by a Windows editor
        text = data.decode("utf-16", errors="replace")
    else:  # ASCII by the format; a UTF-8 byte order mark is not part of "ncols"
        text = data.decode("utf-8-sig", errors="replace")
    lines = text.splitlines()
    body_start = 0
    for i, line in enumerate(lines):
        parts = line.split()
        if len(parts) == 2 and parts[0][:1].isalpha():
            try:
                header[parts[0].lower()] = float(parts[1])
            except ValueError:
                raise ValueError(f"{path}: line {i + 1}: the header value of {parts[0]} is not a number: {shown(parts[1])}") from None
            if not np.isfinite(header[parts[0].lower()]):
                raise ValueError(f"{path}: line {i + 1}: the header value of {parts[0]} is not finite: {shown(parts[1])}")
            body_start = i + 1
        else:
            break
    for key in ("ncols", "nrows"):
        if key not in header:
            raise ValueError(f"{path}: not an ESRI ASCII grid (no {key} in the header)")
        if header[key] != int(header[key]) or header[key] < 1:
            raise ValueError(f"{path}: {key} in the header must be a positive integer, not {header[key]:g}")
    for key in ("cellsize", "dx", "dy"):
        if key in header and header[key] <= 0:
            raise ValueError(f"{path}: {key} in the header must be positive, not {header[key]:g}")
    ncols, nrows = int(header["ncols"]), int(header["nrows"])
    try:
        values = np.array(" ".join(lines[body_start:]).split(), dtype=np.float64)
    except ValueError:
        raise ValueError(f"{path}: {_first_non_number(lines, body_start)}") from None
    if values.size != ncols * nrows:
        raise ValueError(f"{path}: the header says {nrows} rows × {ncols} columns but the file holds {values.size} values")
    token = rounded_integer(" ".join(lines[body_start:]), values)
    if token is not None:
        raise ValueError(f"{path}: the height {rounded_note(token)}")
    heights = values.reshape(nrows, ncols)
    heights = np.where(heights == header.get("nodata_value", ESRI_DEFAULT_NODATA), np.nan, heights)
    if "cellsize" in header:
        dx = dy = header["cellsize"]
    elif "dx" in header and "dy" in header:
        dx, dy = header["dx"], header["dy"]
    else:
        raise ValueError(f"{path}: no cellsize (or dx and dy) in the header")
    if "xllcenter" in header:
        x0 = header["xllcenter"]
    elif "xllcorner" in header:
        x0 = header["xllcorner"] + dx / 2
    else:
        raise ValueError(f"{path}: no xllcorner or xllcenter in the header")
    if "yllcenter" in header:
        ylow = header["yllcenter"]
    elif "yllcorner" in header:
        ylow = header["yllcorner"] + dy / 2
    else:
        raise ValueError(f"{path}: no yllcorner or yllcenter in the header")
    prj = prj_beside(path)
    crs = None if prj is None else read_prj(prj)
    # The first data row is the northernmost: row 0 sits (nrows - 1) cells above the lowest row's centre.
    return HeightGrid(heights, GridTransform(x0, ylow + (nrows - 1) * dy, dx, -dy, crs), str(path))


def _first_non_number(lines: list[str], start: int) -> str:
    """Where the body of an ESRI grid (``lines[start:]``) first holds a field that is no number, as an error's words.

    Only on the error path; O(size).
    """
    for i in range(start, len(lines)):
        for field in lines[i].split():
            try:
                float(field)
            except ValueError:
                comma = " (fields are separated by blanks in an ESRI grid, and decimals written with a point)" if "," in field else ""
                return f"line {i + 1}: {shown(field)} is not a number{comma}"
    return "the grid holds something that is not a number"


def write_asc(path: str | Path, heights: ArrayLike, *, x0: float = 0.0, y0: float = 0.0, cellsize: float = 1.0,
              nodata: float = -9999.0) -> Path:
    """Write ``heights`` as an ESRI ASCII grid (row 0 first, i.e. northernmost); NaN cells as ``nodata``.

    ``(x0, y0)`` is the lower-left corner (``xllcorner``, ``yllcorner``).  For tests and examples.
    """
    arr = np.asarray(heights, dtype=np.float64)
    p = Path(path)
    rows, cols = arr.shape
    lines = [
        f"ncols {cols}",
        f"nrows {rows}",
        f"xllcorner {x0!r}",
        f"yllcorner {y0!r}",
        f"cellsize {cellsize!r}",
        f"NODATA_value {nodata!r}",
    ]
    for row in arr:
        lines.append(" ".join(repr(float(nodata)) if np.isnan(v) else repr(float(v)) for v in row))
    p.write_text("\n".join(lines) + "\n", encoding="ascii")
    return p
