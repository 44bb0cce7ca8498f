"""Tiled terrain on Dask: greedy insertion (paper §5) on the tiles of a DEM larger than memory, stitched watertight.

:func:`tiled_terrain` meshes a height grid read in windows
(:mod:`persistri.impl.scale.terrain_source`) tile by tile, on a
``distributed`` cluster or in this process, and stitches one mesh whose every
sample is within ``max_error`` — the guarantee of
:func:`~persistri.impl.terrain.greedy.greedy_insertion`, kept across the seams.

The plan (:class:`~persistri.impl.scale.terrain_seams.Tiling`): tiles of at most
``tile × tile`` samples overlapping by one row or column; the samples on a border
line belong to the tiles on both sides.

1. **Seams first.**  One task per tile decides its top and left seams (and its
   bottom and right ones on the grid's last row and column of tiles): each seam's
   vertices by Douglas–Peucker on its own profile, exactly within ``max_error``
   (:func:`~persistri.impl.scale.terrain_seams.seam_vertices`).  Every seam is
   decided once, by one task, from its samples only; tile corners are vertices
   of the four seams that meet there.
2. **Tiles.**  One task per tile reads its window and meshes it by greedy
   insertion of its *interior* samples, with its four corners and its four
   seams' vertices as vertices, until every interior sample is within
   ``max_error`` (:func:`~persistri.impl.scale.terrain_tile.mesh_tile`).
3. **Stitch.**  Vertices are named by their global sample index
   ``row · cols + col``, so the two copies of a seam vertex are one vertex.

**Why the stitched mesh is watertight.**  The boundary of a tile's mesh is
exactly the polyline of its border vertices (:mod:`persistri.impl.scale.terrain_tile`:
in persistri's Delaunay triangulation a point on a hull edge splits it, and no
interior insertion touches the hull).  The two tiles across a seam have the
same vertices on it — the seam's, decided once — so each edge of the seam's
polyline is an edge of exactly one triangle of each tile, traversed in opposite
directions (both tiles are counterclockwise and lie on opposite sides).  At a
tile corner the four tiles' meshes meet at the one shared vertex.  The tiles'
interiors are disjoint open rectangles covering the grid's rectangle, and each
tile's mesh triangulates its rectangle, so the union triangulates the grid's
rectangle: no gap, no overlap, no T-junction (a vertex lying inside another
tile's edge would have to be a seam vertex that tile lacks).  Every edge is
then in two triangles of opposite orientation except the grid's rim, which is
in one.

**Why ``max_error`` holds at every sample.**  An interior sample of a tile
lies strictly inside the tile's rectangle, so the triangle that holds it in the
tile's mesh holds it in the stitched mesh, and the tile's greedy insertion stopped
only once its error there was within the bound (measured as greedy insertion
measures it).  A seam sample lies on an edge ``(u, w)`` of the seam's polyline;
each triangle on that edge is linear along it and takes the heights of ``u`` and
``w`` at its ends, so its height at the sample is the polyline's: the sample's
error is its error against the polyline, which the seam's task bounded exactly.

**Cost model.**  With ``n = rows · cols`` samples, ``t`` samples a side per tile
and ``T ≈ n / t²`` tiles: the seam tasks do O(n / t) float work in all (each
sample of a border line once, O(t log t) per seam); the tile tasks do what
greedy insertion does on ``t²`` samples each — its cost grows slightly faster
than linearly in the samples (each sample moves between triangles about
``log k`` times for ``k`` vertices), so tiles cost no more in total than one
run on the whole grid, and they are independent: with ``W`` workers the wall
time is about ``T / W`` tile runs once ``T ≫ W``.  Each task reads only its
window (the survey reads every chunk once more), so a worker's peak memory
is one tile's — ``O(t²)`` heights, sample lists and coordinates, plus the
persistent complex of one tile — whatever the grid's size.  The client holds
the result: the stitched mesh, ``O(vertices)``.  The seams cost vertices: a
seam keeps what its profile needs, which the single-process mesh would place
anyway about as densely; a smaller tile means more seams.

Determinism: every task is a function of its inputs (the grid, the tile's
window, the seams), and the stitch orders everything by tile and sample index,
so the mesh is the same on one worker or many, in any completion order.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import NDArray

from persistri.impl.scale.tasks import Task, run, task
from persistri.impl.scale.terrain_seams import Seam, Tiling, seam_vertices
from persistri.impl.scale.terrain_nodata import NodataRule, filled_window, survey
from persistri.impl.scale.terrain_source import ArraySource, Dem, DemSource, open_dem
from persistri.impl.scale.terrain_tile import mesh_tile
from persistri.impl.terrain.crs import Crs
from persistri.impl.terrain.delaunay import canonical_triangles
from persistri.impl.terrain.grids import GridTransform

if TYPE_CHECKING:
    from distributed import Client

__all__ = [
    "DEFAULT_TILE",
    "BorderSeams",
    "TilePiece",
    "TiledTin",
    "tiled_terrain",
    "decide_seams",
    "mesh_tile_piece",
    "tile_tin",
    "write_tile_meshes",
    "MissingHeights",
]

IntArray = NDArray[np.intp]
FloatArray = NDArray[np.float64]

class MissingHeights(ValueError):
    """No-data cells in a grid meshed with ``nodata="error"``: how many, and the first as ``(row, col)``."""

    def __init__(self, name: str, count: int, first: tuple[int, int]) -> None:
        self.name, self.count, self.first = name, count, first
        super().__init__(
            f"{name}: {count:,} no-data cell{'s' if count != 1 else ''} (NaN), the first at (row {first[0]}, col "
            f"{first[1]}); say how to treat them with nodata='fill', 'min' or a height"
        )


DEFAULT_TILE: Final = 1025
"""Samples a side of a tile when none is given: 1024 cells, about a million samples (a few hundred MB per worker)."""


@dataclass(frozen=True, slots=True)
class BorderSeams:
    """The seams one task decides for tile ``(i, j)``: its top and left, and its bottom and right on the grid's rim."""

    top: Seam
    left: Seam
    bottom: Seam | None
    right: Seam | None

    def seams(self) -> list[Seam]:
        """The seams decided here (each seam of the grid is in exactly one task's list)."""
        return [s for s in (self.top, self.left, self.bottom, self.right) if s is not None]


@dataclass(frozen=True, slots=True)
class TilePiece:
    """One tile's mesh in global terms.

    * ``window`` — ``(r0, r1, c0, c1)``, ends included;
    * ``samples`` — the global sample index ``row · cols + col`` of each vertex, and ``heights`` their heights;
    * ``triangles`` — ``(m, 3)`` global sample indices, counterclockwise in ``(x, y) = (col, row)``;
    * ``interior_max``, ``interior_scale``, ``interior_squares`` — the interior samples' errors
      (largest; sum of squares as ``scale² · squares``);
    * ``max_error``, ``rms_error`` — over the whole window, seams included (the tile's own file).
    """

    i: int
    j: int
    window: tuple[int, int, int, int]
    samples: NDArray[np.int64]
    heights: FloatArray
    triangles: NDArray[np.int64]
    interior_max: float
    interior_scale: float
    interior_squares: float
    max_error: float
    rms_error: float


def _combine(parts: list[tuple[float, float]]) -> tuple[float, float]:
    """Sums of squares ``scale² · squares`` added up without overflow: ``(largest scale, squares relative to it)``."""
    top = max((s for s, _ in parts), default=0.0)
    if top == 0.0:
        return 0.0, 0.0
    return top, float(sum(q * (s / top) ** 2 for s, q in parts if s > 0.0))


def _source(source: DemSource | FloatArray) -> DemSource:
    """A task's grid: a source, or an array the cluster was sent once (:mod:`persistri.impl.scale.tasks`)."""
    return ArraySource(source, "array") if isinstance(source, np.ndarray) else source


def decide_seams(source: DemSource | FloatArray, tiling: Tiling, i: int, j: int, max_error: float, rule: NodataRule) -> BorderSeams:
    """The seam task of tile ``(i, j)``: read its top row and left column (and bottom, right on the rim) and
    choose each seam's vertices (:func:`~persistri.impl.scale.terrain_seams.seam_vertices`). O(tile)."""
    source = _source(source)
    r0, r1, c0, c1 = tiling.window(i, j)
    ti, tj = tiling.shape

    def row(r: int) -> Seam:
        return seam_vertices(filled_window(source, r, r, c0, c1, rule)[0], max_error)

    def col(c: int) -> Seam:
        return seam_vertices(filled_window(source, r0, r1, c, c, rule)[:, 0], max_error)

    return BorderSeams(
        top=row(r0),
        left=col(c0),
        bottom=row(r1) if i == ti - 1 else None,
        right=col(c1) if j == tj - 1 else None,
    )


def mesh_tile_piece(
    source: DemSource | FloatArray,
    tiling: Tiling,
    i: int,
    j: int,
    own: BorderSeams,
    below: BorderSeams | None,
    beside: BorderSeams | None,
    max_error: float,
    rule: NodataRule,
    backend: str,
) -> TilePiece:
    """The tile task of tile ``(i, j)``: read its window, mesh it from its seams, name vertices globally. O(tile²)."""
    source = _source(source)
    r0, r1, c0, c1 = tiling.window(i, j)
    top, left = own.top, own.left
    bottom = below.top if below is not None else own.bottom
    right = beside.left if beside is not None else own.right
    assert bottom is not None and right is not None, "the rim's seams are decided by the rim's tiles"
    z = filled_window(source, r0, r1, c0, c1, rule)
    mesh = mesh_tile(z, top.vertices, right.vertices, bottom.vertices, left.vertices, max_error, backend=backend)
    h, w = z.shape
    cols = tiling.cols

    def glob(local: IntArray) -> NDArray[np.int64]:
        loc = local.astype(np.int64)
        out: NDArray[np.int64] = (r0 + loc // w) * cols + (c0 + loc % w)
        return out

    seams = (top, right, bottom, left)
    window_max = max([mesh.max_error] + [s.max_error for s in seams])
    scale, squares = _combine([(mesh.scale, mesh.scaled_squares)] + [(s.scale, s.scaled_squares) for s in seams])
    return TilePiece(
        i=i,
        j=j,
        window=(r0, r1, c0, c1),
        samples=glob(mesh.vertices),
        heights=z.ravel()[mesh.vertices],
        triangles=glob(mesh.triangles),
        interior_max=mesh.max_error,
        interior_scale=mesh.scale,
        interior_squares=mesh.scaled_squares,
        max_error=window_max,
        rms_error=scale * float(np.sqrt(squares / (h * w))),
    )


@dataclass(frozen=True, eq=False)
class TiledTin:
    """The stitched mesh of :func:`tiled_terrain`; the same reading as :class:`~persistri.impl.terrain.greedy.Tin`.

    * ``vertices`` — ``(k, 3)``: ``x`` = column, ``y`` = row, ``z`` = height, sorted by sample index;
    * ``triangles`` — ``(m, 3)`` indices into ``vertices``, counterclockwise in ``(x, y)``
      (rotated to start at their smallest index, rows sorted);
    * ``samples`` — the flat grid index ``row · cols + col`` of each vertex (increasing);
    * ``max_error``, ``rms_error`` — over every sample of the grid;
    * ``shape``, ``transform`` (and :attr:`crs`) — as for a :class:`Tin`;
    * ``tiling`` — the tiles; ``pieces`` — each tile's mesh when asked for (``keep_tiles=True``), else empty.

    No persistent complex and no history: each tile's complex stayed on its worker.
    """

    vertices: FloatArray
    triangles: IntArray
    samples: NDArray[np.int64]
    max_error: float
    rms_error: float
    shape: tuple[int, int]
    transform: GridTransform | None
    tiling: Tiling
    pieces: tuple[TilePiece, ...] = field(default=())

    @property
    def n_points(self) -> int:
        """The number of vertices."""
        return int(self.vertices.shape[0])

    @property
    def crs(self) -> Crs | None:
        """The coordinate reference system of :meth:`world_vertices`, when the grid's file states one."""
        return None if self.transform is None else self.transform.crs

    def world_vertices(self) -> FloatArray:
        """The vertices in world coordinates (a copy of :attr:`vertices` without a transform). O(k)."""
        return self.vertices.copy() if self.transform is None else self.transform.apply(self.vertices)

    def world_triangles(self) -> IntArray:
        """The triangles, counterclockwise seen from above in world coordinates (reversed where the transform mirrors)."""
        return self.triangles.copy() if self.transform is None else self.transform.world_triangles(self.triangles)


def tiled_terrain(
    source: Any,
    *,
    max_error: float,
    tile: int = DEFAULT_TILE,
    client: Client | None = None,
    nodata: str | float = "error",
    fill_reach: int | None = None,
    backend: str = "red_black",
    progress: bool = False,
    keep_tiles: bool = False,
    transform: GridTransform | None = None,
) -> TiledTin:
    """Mesh the DEM ``source`` by tiles (module docstring) so that every sample is within ``max_error``.

    * ``source`` — a path (``.npy``, ``.tif``/``.tiff`` and ``.zarr`` are read in
      windows; ``.npz``, ``.asc``, ``jacksboro`` whole), a numpy array, a Dask
      array, or a :class:`~persistri.impl.scale.terrain_source.Dem`;
    * ``tile`` — samples a side of a tile (≥ 3), neighbours sharing one row or column;
    * ``client`` — a :class:`distributed.Client` to run the tasks on
      (:func:`persistri.impl.scale.cluster.connect`), or None to run them in this
      process, one after the other — the same mesh either way;
    * ``nodata`` — as :func:`~persistri.impl.terrain.grids.as_heights`; ``fill``
      searches ``fill_reach`` cells around each window (default: ``tile``);
    * ``backend`` — the ``ORD_MAP`` backend of each tile's complex;
    * ``progress`` — a progress bar of finished tasks on stderr (Dask's diagnostics on a cluster);
    * ``keep_tiles`` — keep each tile's mesh (:attr:`TiledTin.pieces`, for :func:`write_tile_meshes`).

    Errors: :class:`ValueError`/:class:`TypeError`, one line naming the grid, for
    an unreadable or invalid grid (checked by :func:`~persistri.impl.scale.terrain_nodata.survey`
    before any meshing), a bad ``max_error`` or ``tile``; an error inside a task
    is raised here.
    """
    e = _bound(max_error)
    dem = source if isinstance(source, Dem) else open_dem(source, transform=transform)
    tiling = Tiling.of(dem.shape, tile)
    reach = int(tile if fill_reach is None else fill_reach)
    if reach < 1:
        raise ValueError(f"fill_reach must be at least 1, got {reach}")
    rule = NodataRule.of(nodata, reach=reach)
    found = survey(dem, client=client, chunks=max(256, min(tile, 4096)))
    if found.missing:
        if rule.kind == "error":
            raise MissingHeights(dem.name, found.missing, found.first_missing or (0, 0))
        if rule.kind == "min":
            rule = NodataRule("min", found.lowest, reach)
    # A grid held in memory goes as its array, which the cluster receives once (tasks.run scatters it).
    src: DemSource | FloatArray = dem.source.heights if isinstance(dem.source, ArraySource) else dem.source
    done = run(client, _tasks(src, tiling, e, rule, backend), progress=progress, title="terrain tiles")
    n = len(tiling)
    return _stitch(done[n:], done[:n], tiling, dem.transform, keep_tiles)


def _bound(max_error: Any) -> float:
    if isinstance(max_error, bool) or not isinstance(max_error, (int, float, np.integer, np.floating)):
        raise TypeError(f"max_error must be a number, not {type(max_error).__name__}")
    e = float(max_error)
    if not (e >= 0 and np.isfinite(e)):
        raise ValueError(f"max_error must be a finite number >= 0, got {max_error}")
    return e


def _tasks(source: DemSource | FloatArray, tiling: Tiling, e: float, rule: NodataRule, backend: str) -> list[Task]:
    """The graph: a seam task per tile, and a tile task per tile reading its own, its lower and its right neighbour's."""
    ti, tj = tiling.shape
    seams = {(i, j): task(decide_seams, source, tiling, i, j, e, rule) for i, j in tiling.tiles()}
    tiles = []
    for i, j in tiling.tiles():
        below = seams[i + 1, j] if i + 1 < ti else None
        beside = seams[i, j + 1] if j + 1 < tj else None
        tiles.append(task(mesh_tile_piece, source, tiling, i, j, seams[i, j], below, beside, e, rule, backend))
    return [seams[k] for k in tiling.tiles()] + tiles


def _stitch(pieces: list[TilePiece], borders: list[BorderSeams], tiling: Tiling, transform: GridTransform | None,
            keep_tiles: bool) -> TiledTin:
    """One mesh from the tiles' meshes: vertices by global sample index (seam vertices merged), errors combined."""
    ids = np.concatenate([p.samples for p in pieces])
    heights = np.concatenate([p.heights for p in pieces])
    samples, first = np.unique(ids, return_index=True)
    tri = np.searchsorted(samples, np.concatenate([p.triangles for p in pieces])).astype(np.intp)
    cols = tiling.cols
    vertices = np.column_stack([(samples % cols).astype(np.float64), (samples // cols).astype(np.float64), heights[first]])
    seams = [s for b in borders for s in b.seams()]
    max_error = max([p.interior_max for p in pieces] + [s.max_error for s in seams])
    scale, squares = _combine([(p.interior_scale, p.interior_squares) for p in pieces] + [(s.scale, s.scaled_squares) for s in seams])
    rms = scale * float(np.sqrt(squares / (tiling.rows * tiling.cols)))
    return TiledTin(
        vertices=vertices,
        triangles=canonical_triangles(tri),
        samples=samples.astype(np.int64),
        max_error=float(max_error),
        rms_error=rms,
        shape=(tiling.rows, tiling.cols),
        transform=transform,
        tiling=tiling,
        pieces=tuple(pieces) if keep_tiles else (),
    )


def tile_tin(tin: TiledTin, piece: TilePiece) -> TiledTin:
    """One tile's mesh as a :class:`TiledTin` of the whole grid's coordinates (for writing it beside the others)."""
    order = np.argsort(piece.samples)
    samples, heights = piece.samples[order], piece.heights[order]
    tri = np.searchsorted(samples, piece.triangles).astype(np.intp)
    cols = tin.tiling.cols
    vertices = np.column_stack([(samples % cols).astype(np.float64), (samples // cols).astype(np.float64), heights])
    return TiledTin(vertices, canonical_triangles(tri), samples.astype(np.int64), piece.max_error, piece.rms_error,
                    tin.shape, tin.transform, tin.tiling)


def write_tile_meshes(directory: str | Path, tin: TiledTin, *, suffix: str = ".npz", world: bool = False) -> list[Path]:
    """Write each kept tile's mesh to ``directory/tile_<i>_<j><suffix>`` with the terrain writer; the files written.

    Vertices are in the whole grid's coordinates (or world ones), so the tiles
    line up; each file's ``max_error`` and ``rms_error`` are its window's.
    :class:`ValueError` when the run kept no tiles (``keep_tiles=False``).
    """
    from persistri.impl.terrain.export import write_tin

    if not tin.pieces:
        raise ValueError("this run kept no tile meshes: pass keep_tiles=True")
    out = Path(directory)
    out.mkdir(exist_ok=True)
    width = len(str(max(tin.tiling.shape)))
    written: list[Path] = []
    for piece in tin.pieces:
        written += write_tin(out / f"tile_{piece.i:0{width}d}_{piece.j:0{width}d}{suffix}", tile_tin(tin, piece), world=world)
    return written
