"""Greedy insertion (Garland & Heckbert) on the persistent Delaunay triangulation: ``greedy_insertion`` and ``Tin``.

Paper §5.  Given a 2D array of height samples, start from the rectangle of the
four corner samples split into two triangles; every triangle carries the
samples inside it (its conflict list) and its *candidate*, the sample of
maximum vertical error against the triangle's plane.  A priority queue holds one
candidate per triangle; repeatedly the worst sample is inserted into the
Delaunay triangulation (:class:`~persistri.impl.terrain.delaunay.Triangulator`:
exact predicates, Simulation of Simplicity for ties, hull edges split by samples
lying exactly on them), the new triangles are assessed, and their candidates are
queued.  A queue entry whose triangle has died is skipped when it surfaces (lazy
invalidation).  The run stops when the maximum error is at most ``max_error``,
when the mesh has ``max_points`` vertices, or when the mesh is exact (error 0).

Every insertion is a new version of the persistent complex, and all of them are
kept (:class:`TinHistory`): any level of detail is read back afterwards —
``history.at(points=k)``, ``history.at(error=e)`` — without running anything
again, and it equals the mesh of a fresh run stopped there.

The error measure is a *measurement*, not a predicate: the vertical distance
``|z − plane(x, y)|`` is evaluated in float64, vectorised with numpy, by
:func:`plane_errors` and, for the fan of one insertion, :func:`fan_errors` (the
plane through the triangle's three samples, written around its *apex*, the
vertex whose insertion made it; the two functions give the same floats).  Grid
coordinates are small integers, so the plane's gradient has one rounding per
operation; the errors are accurate to a few units in the last place of the
heights.  All geometry (which triangle a sample is in, which triangles are
Delaunay) is decided exactly.  Ties between equal errors are broken
deterministically: within a triangle the first sample of its list, in the queue
the older triangle.  Where the new sample lies exactly on the circumcircle of a
triangle beside its cavity (four cocircular samples: common on a grid), that
triangle stays — the strict conflict rule of
:class:`~persistri.impl.terrain.delaunay.Triangulator` (``strict=True``), the
rule of Garland–Heckbert's and pydelatin's flips — rather than Simulation of
Simplicity deciding: connecting the sample of largest error across such a
quadrilateral spreads its height over a triangle that did not hold it, and on
grid DEMs costs 0.3–2.4 % of maximum error at equal vertex count
(docs/performance.md, "Max error at equal vertex count").

The maximum error is not monotone in the number of points: an insertion can
make a long triangle across a ridge, which the next insertions repair (on the
Jacksboro DEM about a quarter of the levels lie more than 10 % above the best
level before them — for pydelatin too).  With every level kept, the best mesh
within a budget of points is the level of least error among the first ones.

Grid convention: sample ``heights[row, col]`` is the point ``x = col``,
``y = row`` (row 0 is the array's first row; nothing is flipped).  Triangles are
counterclockwise in the ``(x, y)`` plane — ``orient2d > 0`` — which is clockwise
when drawn with row 0 at the top.  So it is in world coordinates of a north-up
raster (``dy < 0``: the transform mirrors the plane); :meth:`Tin.world_triangles`
gives the triangles for :meth:`Tin.world_vertices`, reversed where the transform
mirrors, so that world meshes are counterclockwise seen from above too.

>>> import numpy as np
>>> plane = np.fromfunction(lambda r, c: r + 2 * c, (5, 6))
>>> tin = greedy_insertion(plane, max_error=0)
>>> tin.n_points, tin.triangles.tolist()          # a plane needs only the corners
(4, [[0, 1, 3], [1, 2, 3]])
>>> spike = np.zeros((5, 6)); spike[2, 3] = 7.0
>>> tin = greedy_insertion(spike, max_points=5)
>>> tin.vertices[-1].tolist(), tin.max_error       # x = column 3, y = row 2: the peak
([3.0, 2.0, 7.0], 4.666666666666666)
>>> tin.history.at(points=4).max_error            # the level before it, read back
7.0
>>> north_up = greedy_insertion(plane, max_error=0, transform=(500.0, 900.0, 10.0, -10.0))
>>> north_up.world_vertices()[:, :2].tolist(), north_up.world_triangles().tolist()
([[500.0, 900.0], [550.0, 900.0], [550.0, 860.0], [500.0, 860.0]], [[0, 3, 1], [1, 3, 2]])
"""

from __future__ import annotations

from array import array
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from itertools import chain
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.collector import collector_paused
from persistri.impl.complex.structure import Complex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.maps import backend as map_backend
from persistri.impl.progress import progress_callback
from persistri.impl.stats import Stats
from persistri.impl.terrain.check import ScaledSquares, largest_magnitude
from persistri.impl.terrain.delaunay import Samples, TriDatum, canonical_triangles
from persistri.impl.terrain.greedy_run import GreedyRun
from persistri.impl.terrain.plane_errors import apex_first, fan_errors, grid_points, grid_xy, level_error_blocks, plane_errors, ranks
from persistri.impl.terrain.crs import Crs
from persistri.impl.terrain.grids import GridTransform, as_heights, as_transform

__all__ = ["greedy_insertion", "Tin", "TinHistory", "plane_errors", "fan_errors", "apex_first", "grid_points", "grid_xy"]

IntArray = NDArray[np.intp]
FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class Tin:
    """A triangulated irregular network: the result of :func:`greedy_insertion` (or one level of its history).

    * ``vertices`` — ``(k, 3)`` float64: ``x`` = column index, ``y`` = row index,
      ``z`` = height, in insertion order (the four corners first), so the mesh at
      ``j`` points has the first ``j`` of these vertices;
    * ``triangles`` — ``(m, 3)`` indices into ``vertices``, counterclockwise in ``(x, y)``
      (rotated to start at their smallest index, rows sorted);
    * ``samples`` — the flat grid index ``row · cols + col`` of each vertex;
    * ``max_error``, ``rms_error`` — over every sample of the grid (vertices count as 0);
    * ``shape`` — the grid's ``(rows, cols)``; ``transform`` — the optional
      :class:`~persistri.impl.terrain.grids.GridTransform` and with it the CRS
      (:attr:`crs`); the mesh in world coordinates is :meth:`world_vertices` with
      :meth:`world_triangles`;
    * ``history`` — every level of detail of the run (:class:`TinHistory`), or None
      when the run was asked not to keep it;
    * ``complex`` / ``structure`` — the persistent complex version of this mesh
      (ghost triangles included) and the structure that reads it;
    * ``stats`` — the counts, when a :class:`~persistri.impl.stats.Stats` was given.
    """

    vertices: FloatArray
    triangles: IntArray
    samples: IntArray
    max_error: float
    rms_error: float
    shape: tuple[int, int]
    transform: GridTransform | None
    history: TinHistory | None
    complex: Complex[TriDatum]
    structure: TwoComplex[TriDatum]
    stats: Stats | None = field(default=None, compare=False)

    @property
    def n_points(self) -> int:
        """The number of vertices."""
        return int(self.vertices.shape[0])

    @property
    def crs(self) -> Crs | None:
        """The coordinate reference system of :meth:`world_vertices`, when the grid's file states one."""
        return None if self.transform is None else self.transform.crs

    def world_vertices(self) -> FloatArray:
        """The vertices in world coordinates (through :attr:`transform`; a copy of :attr:`vertices` if there is none). O(k)."""
        if self.transform is None:
            return self.vertices.copy()
        return self.transform.apply(self.vertices)

    def world_triangles(self) -> IntArray:
        """The triangles for :meth:`world_vertices`: counterclockwise seen from above in world coordinates. O(m).

        :attr:`triangles` are counterclockwise in grid coordinates; a north-up
        raster's transform mirrors the plane, and there each triangle is reversed
        (:meth:`~persistri.impl.terrain.grids.GridTransform.world_triangles`).  A copy.
        """
        if self.transform is None:
            return self.triangles.copy()
        return self.transform.world_triangles(self.triangles)


@dataclass(frozen=True, eq=False)
class TinHistory:
    """Every level of detail of a greedy-insertion run, oldest first; the versions share structure.

    ``versions[j]`` is the mesh with ``4 + j`` vertices: the corners plus the
    first ``j`` inserted samples (``inserted[4 + j - 1]``); ``max_errors[j]`` is its
    maximum error.  Keeping every version costs the persistent complex's new
    nodes per insertion — O(lg n) per changed vertex with the red-black backend —
    plus the triangles' sample lists, not a copy of the mesh per version.
    """

    heights: FloatArray
    shape: tuple[int, int]
    structure: TwoComplex[TriDatum]
    versions: tuple[Complex[TriDatum], ...]
    inserted: IntArray
    max_errors: FloatArray
    transform: GridTransform | None
    infinite: int

    def __len__(self) -> int:
        return len(self.versions)

    @property
    def points(self) -> range:
        """The vertex counts available: ``range(4, 4 + len(self))``."""
        return range(4, 4 + len(self.versions))

    def index(self, *, points: int | None = None, error: float | None = None) -> int:
        """The version with ``points`` vertices, or the first (fewest vertices) whose maximum error is ≤ ``error``.

        Exactly one of the two must be given.  :class:`ValueError` when the run has no
        such version (it stopped before, or ``points`` < 4).  O(1) for points, O(len) for error.
        """
        if (points is None) == (error is None):
            raise ValueError("give exactly one of points= or error=")
        if points is not None:
            if isinstance(points, bool) or not isinstance(points, (int, np.integer)):
                raise TypeError(f"points must be an integer, not {type(points).__name__}")
            j = int(points) - 4
            if not 0 <= j < len(self.versions):
                raise ValueError(f"this run has meshes of 4 to {3 + len(self.versions)} points, not {points}")
            return j
        e = float(error)  # type: ignore[arg-type]  # error is not None here
        if not e >= 0:
            raise ValueError(f"error must be a number >= 0, got {error}")
        hits = np.flatnonzero(self.max_errors <= e)
        if not hits.size:
            raise ValueError(
                f"this run never reached a maximum error of {e:g} (its smallest is {float(self.max_errors.min()):g} "
                f"at {4 + int(np.argmin(self.max_errors))} points)"
            )
        return int(hits[0])

    def at(self, *, points: int | None = None, error: float | None = None) -> Tin:
        """The mesh of one level of detail (see :meth:`index`), read from the kept version. O(mesh + samples)."""
        j = self.index(points=points, error=error)
        return tin_of_version(self, j)

    def best(self, points: int) -> Tin:
        """The level of least maximum error among those with at most ``points`` vertices (the fewest points on ties).

        The maximum error of greedy insertion is not monotone (module docstring), so
        this can beat ``at(points=points)``; it is read from the kept versions.
        :class:`ValueError` if ``points`` < 4.  O(len) to choose, then as :meth:`at`.
        """
        if isinstance(points, bool) or not isinstance(points, (int, np.integer)):
            raise TypeError(f"points must be an integer, not {type(points).__name__}")
        if points < 4:
            raise ValueError(f"this run has meshes of 4 to {3 + len(self.versions)} points, not {points}")
        last = min(int(points), 3 + len(self.versions)) - 4
        return tin_of_version(self, int(np.argmin(self.max_errors[: last + 1])))


def tin_of_version(h: TinHistory, j: int) -> Tin:
    """The :class:`Tin` of version ``j`` of history ``h``: vertices, triangles and errors read from the complex."""
    k = 4 + j
    inserted = h.inserted[:k]
    version = h.versions[j]
    return _tin(h.structure, version, inserted, h.heights, h.shape, h.transform, h, h.infinite, None, float(h.max_errors[j]))


def _tin(
    structure: TwoComplex[TriDatum],
    version: Complex[TriDatum],
    inserted: IntArray,
    z: FloatArray,
    shape: tuple[int, int],
    transform: GridTransform | None,
    history: TinHistory | None,
    infinite: int,
    stats: Stats | None,
    expected: float | None = None,
) -> Tin:
    """The :class:`Tin` of ``version``; ``expected`` is its maximum error as the run's queue saw it, if known
    (:func:`_level_summary`). O(mesh + samples), no array of the samples' size."""
    tri, lists = _finite_triangles(structure, version, infinite)
    counts = np.fromiter(map(len, lists), dtype=np.intp, count=len(lists))
    n_total = z.size
    cols = shape[1]
    rank = ranks(tri.ravel(), inserted).reshape(-1, 3)
    total = int(counts.sum())
    if total:
        max_error, rms = _level_summary(cols, z, apex_first(tri, rank), counts, lists, n_total, expected)
    else:
        max_error = rms = 0.0
    vx, vy = grid_xy(inserted, cols)
    vertices = np.column_stack([vx, vy, z[inserted]])
    return Tin(
        vertices=vertices,
        triangles=canonical_triangles(rank),
        samples=inserted.copy(),
        max_error=max_error,
        rms_error=rms,
        shape=shape,
        transform=transform,
        history=history,
        complex=version,
        structure=structure,
        stats=stats,
    )


def _finite_triangles(
    structure: TwoComplex[TriDatum], version: Complex[TriDatum], infinite: int
) -> tuple[IntArray, list[Samples]]:
    """The finite triangles of ``version`` as an ``(m, 3)`` array of labels and their sample lists, in the
    order of ``items``, read in one pass of :meth:`~persistri.impl.complex.structure.ComplexStructure.iter_items`.

    No list of the ``(triangle, datum)`` pairs: on a 2,048² grid that list and its tuples took 18 MB while
    the final mesh was read (measured), where the array takes 24 bytes a triangle and the list of sample
    lists 8.  O(V + N).
    """
    lists: list[Samples] = []
    keep = lists.append

    def finite() -> Iterator[tuple[int, ...]]:
        for t, d in structure.iter_items(version):
            if infinite not in t:
                keep(d[1])
                yield t

    # fromiter over the flattened labels: numpy converts a list of tuples of int subclasses (Vertex) slowly.
    # chain flattens the triangles in C (a generator's ``yield from`` resumed it three times a triangle:
    # 116K triangles, 53 ms against 32 ms).
    tri = np.fromiter(chain.from_iterable(finite()), dtype=np.intp).reshape(-1, 3)
    return tri, lists


def _level_summary(
    cols: int, z: FloatArray, apex: IntArray, counts: IntArray, lists: list[Samples], n_total: int, expected: float | None
) -> tuple[float, float]:
    """The maximum and the RMS error of a level's listed samples — ``err.max()`` and
    :func:`~persistri.impl.terrain.check.root_mean_square` of their errors, bit for bit — without an
    array of the errors (32 MB on a 2,048² grid, and as much again for their magnitudes).

    The RMS is scaled by the maximum, which is known only once every error is measured.  The run's
    queue knows it already (``expected``: its top is the mesh's maximum error, the same floats;
    ``check=True`` asserts it): then one pass of :func:`level_error_blocks` sums with ``expected``
    as the scale while it finds the true maximum, and a second pass is made only if the two differ
    (never, unless the queue is wrong) or ``expected`` is unknown.  O(samples) per pass.
    """
    largest = -1.0
    acc = ScaledSquares(expected) if expected is not None and 0.0 < expected < float("inf") else None
    for block in level_error_blocks(cols, z, apex, counts, lists):
        m = largest_magnitude(block)
        if m != m or m > largest:
            largest = m
        if acc is not None:
            acc.add(block)
    if largest == 0.0 or not np.isfinite(largest):
        return largest, largest
    if acc is None or largest != expected:
        acc = ScaledSquares(largest)
        for block in level_error_blocks(cols, z, apex, counts, lists):
            acc.add(block)
    return largest, acc.rms(n_total)


def _stop_criteria(max_error: Any, max_points: Any) -> tuple[float | None, int | None]:
    if max_error is None and max_points is None:
        raise ValueError("give max_error, max_points or both: greedy insertion needs to know when to stop")
    e: float | None = None
    if max_error is not None:
        if isinstance(max_error, bool) or not isinstance(max_error, (int, float, np.integer, np.floating)):
            raise TypeError(f"max_error must be a number, not {type(max_error).__name__}")
        e = float(max_error)
        if not (e >= 0 and np.isfinite(e)):
            raise ValueError(f"max_error must be a finite number >= 0, got {max_error}")
    k: int | None = None
    if max_points is not None:
        if isinstance(max_points, bool) or not isinstance(max_points, (int, np.integer)):
            raise TypeError(f"max_points must be an integer, not {type(max_points).__name__}")
        k = int(max_points)
        if k < 4:
            raise ValueError(f"max_points must be at least 4 (the grid's corners), got {k}")
    return e, k


def greedy_insertion(
    heights: ArrayLike,
    *,
    max_error: float | None = None,
    max_points: int | None = None,
    backend: str = "red_black",
    check: bool = False,
    stats: Stats | None = None,
    progress: bool | Callable[[int], Any] = False,
    transform: Any = None,
    nodata: str | float = "error",
    history: bool = True,
    stepwise: bool = False,
) -> Tin:
    """Approximate the height grid ``heights`` by a Delaunay TIN, greedily (Garland–Heckbert; paper §5).

    * ``max_error`` — stop once every sample is within this vertical distance of the mesh;
    * ``max_points`` — stop once the mesh has this many vertices (≥ 4: the corners);
      at least one of the two is required; the run also stops when the mesh is exact;
    * ``backend`` — the ``ORD_MAP`` backend of the complex (``persistri.impl.maps.BACKENDS``);
    * ``check`` — assert the insertion invariants at every step and verify the result
      exactly (:func:`persistri.impl.terrain.check.verify_tin`: every interior edge
      Delaunay by exact ``incircle``, every sample in exactly one triangle, the
      errors recomputed independently); raises
      :class:`~persistri.impl.terrain.check.TerrainCheckError` on failure;
    * ``stats`` — a :class:`Stats` counting dictionary operations, key comparisons,
      plane-side (orient2d/incircle) tests and their flops;
    * ``progress`` — True for a progress bar on stderr, or a callable taking the
      number of insertions since its last call;
    * ``transform`` — georeferencing for :meth:`Tin.world_vertices` and
      :meth:`Tin.world_triangles` (:func:`persistri.impl.terrain.grids.as_transform`;
      a :class:`~persistri.impl.terrain.grids.GridTransform` read from a file carries its CRS);
    * ``nodata`` — what to do with NaN cells (:func:`persistri.impl.terrain.grids.as_heights`);
    * ``history`` — keep every level of detail (:attr:`Tin.history`); False keeps only the final mesh;
    * ``stepwise`` — change the complex as the paper's code does, a ``rem`` per cavity
      triangle and an ``add`` per fan triangle, instead of one ``replace`` per insertion
      (the same meshes and versions; more map operations: what Fig. 11 counts).

    Errors: :class:`TypeError`/:class:`ValueError` for bad heights (see
    ``as_heights``: empty, 1-row, 1-column or ragged grids, NaN without a
    ``nodata`` rule), bad stopping criteria, an unknown backend.

    Cost: per insertion O(k) complex operations (O(lg n) each) and exact tests
    for a cavity of k triangles, plus O(m·k) orient2d tests and O(m) float work
    for the m samples that change triangle.
    """
    # A copy of its own only when the history keeps the heights (a run alone only reads them while it runs).
    grid = as_heights(heights, nodata=nodata, copy=history)
    e_stop, k_stop = _stop_criteria(max_error, max_points)
    tf = as_transform(transform)
    if not isinstance(history, bool):
        raise TypeError(f"history must be a bool, not {type(history).__name__}")
    shape = (int(grid.shape[0]), int(grid.shape[1]))
    z = grid.ravel()
    tick = progress_callback(progress, "terrain", None if k_stop is None else k_stop - 4)

    # Persistent nodes form no reference cycles: the cyclic collector only costs time here.
    with collector_paused():
        run = GreedyRun(z, shape, TwoComplex(map_backend(backend), stats), stats, check, stepwise)
        T = run.T
        versions: list[Complex[TriDatum]] = [T.complex]
        # Machine numbers, not lists of Python objects: 8 bytes a number where a list holds a pointer (8) and
        # an int (32) or a float (24).
        inserted = array("q", run.corners)
        errors = array("d")
        try:
            run.run(e_stop, k_stop, history, versions, inserted, errors, tick)
        finally:
            if hasattr(tick, "close"):
                tick.close()
        # The run's scratch (the queue, the live-triangle index) is not needed to read the result: free it
        # before the final mesh's errors are measured, whose arrays are of the grid's size.
        run.heap = []
        T.tri_of = {}
        T.adj = None
        inserted_arr = np.frombuffer(inserted, dtype=np.int64).astype(np.intp)
        inserted_arr.setflags(write=False)
        errors_arr = np.frombuffer(errors, dtype=np.float64).copy()
        errors_arr.setflags(write=False)
        kept: TinHistory | None = None
        if history:
            kept = TinHistory(
                heights=z,
                shape=shape,
                structure=run.structure,
                versions=tuple(versions),
                inserted=inserted_arr,
                max_errors=errors_arr,
                transform=tf,
                infinite=int(T.infinite),
            )
        tin = _tin(run.structure, T.complex, inserted_arr, z, shape, tf, kept, int(T.infinite), stats, errors[-1])
    if check:
        from persistri.impl.terrain.check import verify_tin

        verify_tin(tin, grid.reshape(shape)).raise_if_failed()
        if tin.max_error != errors[-1]:
            from persistri.impl.terrain.check import TerrainCheckError

            raise TerrainCheckError(
                f"the queue's maximum error {errors[-1]!r} differs from the mesh's {tin.max_error!r} (lazy invalidation)"
            )
    return tin
