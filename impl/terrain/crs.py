"""Coordinate reference systems of georeferenced grids: what a file says its world coordinates mean.

persistri does no projection arithmetic: it carries the CRS a grid file states
from the input to the outputs, so that a GIS reads the mesh in the right place.
A :class:`Crs` holds what the file said — an EPSG code, a WKT text, or both —
and nothing guessed:

* GeoTIFF: ``ProjectedCSTypeGeoKey`` (3072) or, for a geographic raster,
  ``GeographicTypeGeoKey`` (2048), when it is an EPSG code (not 32767,
  "user-defined"); and a WKT found in a citation key (``GTCitationGeoKey``,
  ``PCSCitationGeoKey``, ``GeogCitationGeoKey`` — ArcGIS writes
  ``ESRI PE String = PROJCS[...]`` there).  A user-defined CRS spelled out in
  GeoKeys with no WKT is not rebuilt (that is a projection library's job): the
  grid then has no CRS.
* ESRI ASCII grid: the ``.prj`` file of the same name beside it, when there is one
  (the Esri convention), which must hold a WKT.

Writing (:mod:`persistri.impl.terrain.export`): :meth:`Crs.to_wkt` gives the WKT
of a ``.prj`` sidecar — the file's own WKT when it had one, else the ESRI WKT1 of
the EPSG code from ``pyproj`` (the ``geotiff`` extra); :attr:`Crs.name` is the short
text stored in an ``.npz`` (``EPSG:32614``, else the WKT).  Not in the paper: the
georeferencing around §5's terrain meshes.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final

__all__ = ["Crs", "crs_from_geokeys", "read_prj", "prj_beside"]

_WKT_START: Final = re.compile(
    r"\b(PROJCS|GEOGCS|GEOCCS|COMPD_CS|VERT_CS|PROJCRS|GEOGCRS|GEODCRS|COMPOUNDCRS|VERTCRS|BOUNDCRS|PROJECTEDCRS|GEOGRAPHICCRS)\s*\["
)
"""Where a WKT (version 1 or 2) begins: a CRS keyword and its opening bracket."""

_USER_DEFINED: Final = 32767
"""The GeoKey value for "user-defined" (GeoTIFF 1.1, §7.2): not an EPSG code."""

_CITATIONS: Final = ("PCSCitationGeoKey", "GTCitationGeoKey", "GeogCitationGeoKey")


@dataclass(frozen=True, slots=True)
class Crs:
    """A coordinate reference system as a file states it: an EPSG code, a WKT, or both (never neither).

    ``epsg`` — the code of the EPSG registry (e.g. 32614, WGS 84 / UTM zone 14N);
    ``wkt`` — the Well-Known Text the file held, verbatim.
    """

    epsg: int | None = None
    wkt: str | None = None

    def __post_init__(self) -> None:
        if self.epsg is None and self.wkt is None:
            raise ValueError("a CRS needs an EPSG code or a WKT")
        if self.epsg is not None and (isinstance(self.epsg, bool) or not isinstance(self.epsg, int) or self.epsg <= 0):
            raise ValueError(f"an EPSG code is a positive integer, got {self.epsg!r}")
        if self.wkt is not None and not _WKT_START.search(self.wkt):
            raise ValueError(f"not a WKT coordinate system: {self.wkt[:60]!r}")

    @property
    def name(self) -> str:
        """``EPSG:nnnn`` when the code is known, else the WKT: what ``pyproj.CRS(...)`` and GDAL accept."""
        return f"EPSG:{self.epsg}" if self.epsg is not None else str(self.wkt)

    @property
    def label(self) -> str:
        """A short name for messages: ``EPSG:nnnn``, else the name the WKT gives (``"NAD83 / UTM zone 15N"``)."""
        if self.epsg is not None:
            return f"EPSG:{self.epsg}"
        quoted = re.search(r'"([^"]*)"', str(self.wkt))
        return f"WKT {quoted.group(1)!r}" if quoted else "WKT"

    def __str__(self) -> str:
        return self.name

    def to_wkt(self) -> str:
        """The WKT for a ``.prj`` sidecar: the file's own, else the ESRI WKT1 of the EPSG code (needs ``pyproj``).

        Raises :class:`ValueError` when only the code is known and ``pyproj`` is not
        installed, or the code is not in pyproj's EPSG database.
        """
        if self.wkt is not None:
            return self.wkt
        try:
            from pyproj import CRS
            from pyproj.enums import WktVersion
            from pyproj.exceptions import CRSError
        except ImportError:
            raise ValueError(
                f"writing {self.name} as the WKT of a .prj file needs pyproj: pip install 'persistri[geotiff]'"
            ) from None
        code = self.epsg
        assert code is not None  # __post_init__: a CRS without WKT has a code
        try:
            wkt = CRS.from_epsg(code).to_wkt(WktVersion.WKT1_ESRI)
        except CRSError as exc:
            raise ValueError(f"{self.name} is not a coordinate system pyproj knows ({exc})") from None
        if not wkt:
            raise ValueError(f"{self.name} has no ESRI WKT1 form (pyproj)")
        return str(wkt)


def _epsg(value: Any) -> int | None:
    """A GeoKey's value as an EPSG code: None when absent, user-defined or undefined."""
    if value is None:
        return None
    try:
        code = int(value)
    except (TypeError, ValueError):
        return None
    return code if 0 < code < _USER_DEFINED else None


def _wkt_in(text: str) -> str | None:
    """The WKT inside a citation (``ESRI PE String = PROJCS[...]``), or None; bracket-balanced, so junk after it is cut."""
    found = _WKT_START.search(text)
    if found is None:
        return None
    depth = 0
    for i in range(found.start(), len(text)):
        if text[i] == "[":
            depth += 1
        elif text[i] == "]":
            depth -= 1
            if depth == 0:
                return text[found.start() : i + 1]
    return None


def crs_from_geokeys(geokeys: dict[str, Any]) -> Crs | None:
    """The CRS a GeoTIFF's GeoKeys state (as ``tifffile``'s ``TiffPage.geotiff_tags`` decodes them), or None. O(keys).

    The projected CRS code (3072) wins over the geographic one (2048), which for a
    projected raster is only the datum of its projection.
    """
    epsg = _epsg(geokeys.get("ProjectedCSTypeGeoKey"))
    if epsg is None and "ProjectedCSTypeGeoKey" not in geokeys:
        epsg = _epsg(geokeys.get("GeographicTypeGeoKey"))
    wkt = None
    for key in _CITATIONS:
        value = geokeys.get(key)
        if isinstance(value, str):
            wkt = _wkt_in(value)
            if wkt is not None:
                break
    if epsg is None and wkt is None:
        return None
    return Crs(epsg, wkt)


def prj_beside(path: Path) -> Path | None:
    """The ``.prj`` file of the same name beside ``path`` (``.prj`` or ``.PRJ``), if there is one."""
    for suffix in (".prj", ".PRJ"):
        candidate = path.with_suffix(suffix)
        if candidate.is_file():
            return candidate
    return None


def read_prj(path: Path) -> Crs:
    """The CRS in the ``.prj`` file ``path``: its WKT, verbatim (stripped).

    Raises :class:`ValueError` (naming the file) when it cannot be read or holds no
    WKT — e.g. the older ArcInfo ``Projection UTM`` layout, which persistri does not
    translate.
    """
    try:
        text = path.read_text(encoding="utf-8", errors="strict").strip()
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot read the coordinate system ({exc})") from None
    wkt = _wkt_in(text)
    if wkt is None:
        raise ValueError(f"{path}: not a WKT coordinate system; convert it to WKT or remove it")
    return Crs(wkt=wkt)
