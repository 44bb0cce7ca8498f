"""Terrain meshes to files a GIS or a mesh viewer opens: the vertices the triangles use, normals up, the CRS beside.

:func:`write_tin` writes one :class:`~persistri.impl.terrain.greedy.Tin` by the
output's extension (:data:`TIN_FORMATS`):

* the mesh in grid coordinates (``x`` = column, ``y`` = row, ``z`` = height,
  triangles counterclockwise in ``(x, y)``), or with ``world=True`` in the world
  coordinates of the grid's transform, triangles counterclockwise seen from
  above there (:meth:`~persistri.impl.terrain.greedy.Tin.world_triangles`:
  a north-up raster's transform mirrors the plane, and this is where it is undone);
* only the vertices the triangles use, renumbered
  (:func:`~persistri.impl.files.compact_mesh`); the ``.npz`` keeps, for each
  written vertex, the flat index ``row · cols + col`` of its grid sample
  (``samples``) and the grid's shape, so no information is lost;
* the CRS: in the ``.npz`` as the array ``crs`` (``EPSG:32614``, or the WKT when
  the file gave no code) and ``crs_wkt`` (when the input held a WKT); beside a
  ``.ply``/``.obj``/``.stl``/``.off`` written with ``world=True`` — formats with no
  place for it — as a ``.prj`` file of the same name holding WKT, the convention
  GIS software reads (GDAL, QGIS, ArcGIS).  An EPSG code with no WKT is written as
  its ESRI WKT1 by ``pyproj`` (:meth:`~persistri.impl.terrain.crs.Crs.to_wkt`).
  Grid-coordinate meshes get no ``.prj``: their coordinates are not in the CRS.
  No CRS, no sidecar.

The ``.npz`` arrays: ``vertices`` (k, 3), ``triangles`` (m, 3), ``samples`` (k,),
``grid_shape`` (2,), ``max_error``, ``rms_error``, ``world`` (whether ``vertices``
are world coordinates) and, when the grid is georeferenced, ``transform``
``(x0, y0, dx, dy)`` (world = ``(x0 + col·dx, y0 + row·dy)``), ``crs`` and
``crs_wkt`` as above.  Not in the paper: the files around §5's terrain meshes.
"""

from __future__ import annotations

from pathlib import Path
from typing import Final, Protocol

import numpy as np
from numpy.typing import NDArray

from persistri.impl.files import compact_mesh, write_mesh
from persistri.impl.terrain.crs import Crs, read_prj
from persistri.impl.terrain.grids import GridTransform

__all__ = [
    "TIN_FORMATS",
    "SIDECAR_SUFFIX",
    "TerrainMesh",
    "tin_mesh",
    "tin_arrays",
    "sidecar_wkt",
    "holds_wkt",
    "write_tin",
]

TIN_FORMATS: Final = (".ply", ".obj", ".stl", ".off", ".npz")
"""The output formats of :func:`write_tin`, by extension."""

SIDECAR_SUFFIX: Final = ".prj"
"""The CRS sidecar beside a mesh file: ``mesh.ply`` → ``mesh.prj`` (WKT)."""


class TerrainMesh(Protocol):
    """What the writer reads from a terrain mesh: a :class:`~persistri.impl.terrain.greedy.Tin`, or the stitched
    mesh of tiles (:class:`~persistri.impl.scale.terrain.TiledTin`)."""

    @property
    def vertices(self) -> NDArray[np.float64]: ...
    @property
    def triangles(self) -> NDArray[np.intp]: ...
    @property
    def samples(self) -> NDArray[np.integer]: ...
    @property
    def shape(self) -> tuple[int, int]: ...
    @property
    def max_error(self) -> float: ...
    @property
    def rms_error(self) -> float: ...
    @property
    def transform(self) -> GridTransform | None: ...
    @property
    def crs(self) -> Crs | None: ...
    def world_vertices(self) -> NDArray[np.float64]: ...
    def world_triangles(self) -> NDArray[np.intp]: ...


def _format(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix not in TIN_FORMATS:
        raise ValueError(f"{path}: unknown mesh format {suffix!r}; use one of {', '.join(TIN_FORMATS)}")
    return suffix


def tin_mesh(tin: TerrainMesh, *, world: bool = False) -> tuple[NDArray[np.float64], NDArray[np.intp], NDArray[np.integer]]:
    """``(vertices, triangles, samples)`` as written: used vertices only, triangles counterclockwise from above. O(k + m).

    ``world=True`` gives world coordinates (:class:`ValueError` if the TIN has no
    transform); ``samples`` is the flat grid index of each returned vertex.
    """
    if world:
        if tin.transform is None:
            raise ValueError("world coordinates need georeferencing, and this terrain has none")
        vertices, triangles = tin.world_vertices(), tin.world_triangles()
    else:
        vertices, triangles = tin.vertices, tin.triangles
    used_vertices, renumbered, used = compact_mesh(vertices, triangles)
    return used_vertices, renumbered, tin.samples[used]


def tin_arrays(tin: TerrainMesh, *, world: bool = False) -> dict[str, NDArray[np.generic]]:
    """The named arrays of a terrain ``.npz`` (module docstring). O(k + m)."""
    vertices, triangles, samples = tin_mesh(tin, world=world)
    arrays: dict[str, NDArray[np.generic]] = {
        "vertices": vertices,
        "triangles": triangles,
        "samples": samples,
        "grid_shape": np.array(tin.shape, dtype=np.int64),
        "max_error": np.array(tin.max_error, dtype=np.float64),
        "rms_error": np.array(tin.rms_error, dtype=np.float64),
        "world": np.array(world),
    }
    tf = tin.transform
    if tf is not None:
        arrays["transform"] = np.array([tf.x0, tf.y0, tf.dx, tf.dy], dtype=np.float64)
    crs = tin.crs
    if crs is not None:
        arrays["crs"] = np.array(crs.name)
        if crs.wkt is not None:
            arrays["crs_wkt"] = np.array(crs.wkt)
    return arrays


def sidecar_wkt(path: str | Path, crs: Crs | None, *, world: bool) -> str | None:
    """The WKT :func:`write_tin` will write beside ``path``, or None when it writes no sidecar.

    A sidecar is written for a mesh format (not ``.npz``) in world coordinates with
    a known CRS.  Raises :class:`ValueError` when one is due and cannot be made
    (only an EPSG code, and no ``pyproj``): call it before a long computation.
    """
    if not world or crs is None or _format(Path(path)) == ".npz":
        return None
    return crs.to_wkt()


def write_tin(path: str | Path, tin: TerrainMesh, *, world: bool = False, sidecar_at: Path | None = None) -> list[Path]:
    """Write ``tin`` to ``path`` by its extension (:data:`TIN_FORMATS`), and its ``.prj`` sidecar when due.

    Returns the files written, the mesh first (a ``.prj`` that already holds the
    CRS — the input's own, for ``dem.asc`` meshed to ``dem.ply`` — is listed but
    left as it is; ``sidecar_at``, when a caller writes ``path`` under another name
    first, is where the ``.prj`` will end up, and decides that).  ``world=True`` writes world
    coordinates (:class:`ValueError` without a transform).  Everything that can
    fail before the mesh is written (format, georeferencing, the sidecar's WKT) is
    decided first, so a failure leaves no partial output.  O(k + m).
    """
    p = Path(path)
    suffix = _format(p)
    wkt = sidecar_wkt(p, tin.crs, world=world)
    if suffix == ".npz":
        arrays = tin_arrays(tin, world=world)
        written = [write_mesh(p, arrays["vertices"], arrays["triangles"], npz_arrays=dict(arrays))]
    else:
        vertices, triangles, _ = tin_mesh(tin, world=world)
        written = [write_mesh(p, vertices, triangles)]
    if wkt is not None:
        prj = p.with_suffix(SIDECAR_SUFFIX)
        if not holds_wkt(prj if sidecar_at is None else sidecar_at, wkt):  # dem.asc meshed to dem.ply: its dem.prj
            prj.write_text(wkt + "\n", encoding="utf-8")
            written.append(prj)
        else:
            written.append(prj if sidecar_at is None else sidecar_at)
    return written


def holds_wkt(prj: Path, wkt: str) -> bool:
    """Whether the file ``prj`` exists and already holds the CRS ``wkt`` (then it is not rewritten). O(file)."""
    if not prj.is_file():
        return False
    try:
        return read_prj(prj).wkt == wkt
    except ValueError:
        return False
