"""``persistri.ConvexHull``: the exact 3D convex hull in scipy.spatial's shape, every version kept.

A thin, immutable view of :func:`persistri.impl.hull.api.convex_hull` (the
bulldozer, paper §3 and Appendix A) with the attributes of
:class:`scipy.spatial.ConvexHull` (read by :class:`persistri._hull_view.HullView`,
its base), plus what persistence adds: ``history`` (every
intermediate hull, sharing structure) and :meth:`ConvexHull.add_points`, which
returns a *new* hull and leaves this one as it was.

Inputs too big to load — a Dask array, a Zarr array, the path of a ``.npy`` file,
of a directory of ``.npy`` files or of a Zarr store — are hulled chunk by chunk by
:func:`persistri.impl.scale.hull.parallel_hull` (in this process or on a Dask
cluster), which gives exactly the one-process hull; the view is then built from
the hull's vertices alone.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Literal, cast, overload

import numpy as np
from numpy.typing import ArrayLike

from persistri._arrays import refuse_other_dimension
from persistri._hull_chunked import chunked_hull, too_big_to_load
from persistri._hull_view import H, HullView
from persistri._scipy_options import check_qhull_options, closed_error, keeps_coplanar
from persistri.impl.geometry.points import as_points
from persistri.impl.hull.api import Hull, HullHistory, convex_hull
from persistri.impl.stats import Stats

if TYPE_CHECKING:
    from distributed import Client

__all__ = ["ConvexHull"]


class ConvexHull(HullView[H]):
    """The exact convex hull of 3D points (paper §3), in the shape of :class:`scipy.spatial.ConvexHull`.

    ``ConvexHull(points, incremental=False, qhull_options=None, *, backend="red_black",
    history=False, seed=0, check=False, stats=None, progress=False)`` computes the hull
    of ``points`` (``(n, 3)`` reals) by the bulldozer, every decision exact
    (:func:`persistri.impl.hull.api.convex_hull` documents the arguments).  scipy's
    arguments are taken in scipy's positions (:mod:`persistri._scipy_options`):
    ``incremental=True`` makes :meth:`add_points` change this object, as scipy's does,
    until ``close()`` (without it, ``add_points`` returns a new hull and leaves this
    one as it was); ``qhull_options`` that only tune Qhull's round-off (scipy's
    defaults among them) are accepted, since nothing here rounds, and others are a
    :class:`ValueError`.

    Attributes (arrays are read-only; index arrays are ``np.intc`` like scipy's):

    * ``points`` — ``(n, 3)`` float64, the input as validated;
    * ``simplices`` — ``(m, 3)`` the triangles as input rows, each **outward** by
      the right-hand rule (scipy's are unoriented), rotated to start at its
      smallest row, rows sorted;
    * ``vertices`` — the input rows that are hull vertices, sorted (scipy's order
      in 3D); every extreme point is one, and of exactly equal rows only the first
      (Qhull keeps any one of them, so ported code that compares rows may see another).
      Unlike scipy's, they may also include points lying *on* a flat facet or edge
      of the real hull: the symbolic perturbation moves such a point infinitesimally
      in or out, and those moved out become vertices, the flat facet triangulated
      through them (a 3 × 3 × 3 grid: 17 vertices and 30 triangles, scipy 8 and 12;
      docs/exactness.md, "What the perturbation leaves behind").  ``volume`` and
      ``area`` are those of the real hull either way;
    * ``neighbors`` — ``(m, 3)``: ``neighbors[i, j]`` is the triangle across the
      edge opposite ``simplices[i, j]`` (never -1: the hull is closed);
    * ``equations`` — ``(m, 4)``: ``[normal, offset]``, the outward unit normal and
      ``offset = −normal·a``, so ``normal·x + offset <= 0`` inside (scipy's
      convention), from the exact hull (:mod:`persistri.impl.hull.measures`);
    * ``area``, ``volume`` — the surface area, and the enclosed volume computed
      exactly and rounded once;
    * ``duplicates`` — ``(k, 2)``: ``[row, earlier equal row]`` for every input row
      merged into an earlier, exactly equal one; ``coplanar`` — ``(k, 3)``, scipy's
      report of points left out, ``[row, a triangle at its twin, the twin]``: empty, as
      scipy's, unless ``qhull_options`` holds ``Qc``, and then the merged duplicates of
      vertices (nothing is left out for round-off); ``good`` — None, as scipy's without ``QG``;
    * ``history`` — every intermediate hull (:class:`~persistri.impl.hull.api.HullHistory`)
      with ``history=True``, else None; the type says which (``ConvexHull[HullHistory]``
      for ``history=True``, ``ConvexHull[None]`` without it), so a type checker takes
      ``len(hull.history)`` as written;
    * ``min_bound``, ``max_bound`` — the input's bounding box (read from the
      vertices: the extremes of a point set are hull vertices), ``close()``
      (nothing to release);
    * ``npoints``, ``ndim`` (3), ``nsimplex``, ``backend``, ``seed``, and ``result``,
      the full :class:`~persistri.impl.hull.api.Hull` (its persistent complex,
      the structure that reads it, counts).

    Errors are the deep API's, one line each: :class:`TypeError` /
    :class:`ValueError` for input that is not ``(n, 3)`` finite reals,
    :class:`~persistri.impl.hull.errors.DegenerateInputError` (a ``ValueError``)
    when the distinct points do not span space.  Expected O(n lg n) time.

    **Inputs too big to load.**  ``points`` may also be a Dask array, a Zarr array,
    or the path (``str`` or :class:`os.PathLike`) of a ``.npy`` file (memory-mapped),
    of a directory of ``.npy`` files (one input, in file-name order) or of a Zarr
    store.  Such input is hulled chunk by chunk by
    :func:`~persistri.impl.scale.hull.parallel_hull` — each chunk's hull on a
    worker, the survivors merged — with exactly the one-process hull as result
    (same ``vertices``, ``simplices``, ``duplicates``).  Where it runs, as
    ``persistri hull`` decides (:func:`~persistri.impl.scale.cluster.plan`):

    * ``client=`` — on this ``distributed.Client``'s cluster;
    * ``workers=1`` — in this process, chunk by chunk (no Dask scheduler);
      ``workers=N`` — on a local cluster of N worker processes, started and closed here;
    * ``scheduler="tcp://host:8786"`` — on that existing cluster;
    * none of them — in this process for an input of at most one chunk
      (``chunk_rows``, by default :data:`~persistri.impl.scale.hull.MAX_CHUNK_ROWS`
      points), otherwise on the cluster named by ``PERSISTRI_SCHEDULER`` or a local
      one with one worker per core.

    ``chunk_rows`` — points per chunk (default: one chunk per worker, a Dask array's
    own chunks).  Giving any of these four with an in-memory array sends it the same
    way; without them an array (or a list) takes the one-process path, as always.
    On the chunked path ``vertices``, ``simplices``, ``neighbors``, ``duplicates``
    name rows of the whole input, and the measures are computed from the vertices
    alone, so only the hull needs to fit in memory: ``vertex_points`` holds the
    vertices' coordinates, and ``points`` is read on first access (a float64
    ``.npy`` file memory-mapped, read-only; any other input loaded whole — O(n)
    memory); ``history`` is the final merge's versions (hulls of growing sets of the
    candidates that reached it), its simplices as rows of the whole input; ``result``
    is that final run (its ``points`` are the candidates, input rows ``chunked.rows``)
    and ``chunked`` the whole run (chunks, merges, workers); :meth:`add_points`
    resumes that final run.  ``stats`` and a ``progress`` callback need the
    one-process path and are a :class:`ValueError` there.  Dask is imported only on this path (``persistri[dask]``
    for a cluster); ``import persistri`` never imports it.

    >>> import numpy as np, persistri
    >>> cube = np.array([[x, y, z] for x in (0, 2) for y in (0, 2) for z in (0, 2)], dtype=float)
    >>> hull = persistri.ConvexHull(cube)
    >>> hull.vertices.tolist(), hull.nsimplex, hull.volume, hull.area
    ([0, 1, 2, 3, 4, 5, 6, 7], 12, 8.0, 24.0)
    >>> bigger = hull.add_points([[1.0, 1.0, 5.0]])    # a new hull; the old one is unchanged
    >>> bigger.volume, hull.volume
    (12.0, 8.0)
    >>> grid = np.array([[x, y, z] for x in range(3) for y in range(3) for z in range(3)], dtype=float)
    >>> flat = persistri.ConvexHull(grid)    # points on the flat faces become vertices too
    >>> len(flat.vertices), flat.nsimplex, flat.volume, flat.area
    (17, 30, 8.0, 24.0)
    >>> chunked = persistri.ConvexHull(cube, workers=1, chunk_rows=3)   # chunk by chunk, here
    >>> chunked.vertices.tolist() == hull.vertices.tolist(), chunked.volume, len(chunked.chunked.chunks)
    (True, 8.0, 3)
    """

    __slots__ = ()

    @overload
    def __init__(
        self: ConvexHull[HullHistory], points: ArrayLike | os.PathLike[str], incremental: bool = ...,
        qhull_options: str | None = ..., *, backend: str = ..., history: Literal[True], seed: int = ...,
        check: bool = ..., stats: Stats | None = ..., progress: bool | Callable[[int], Any] = ...,
        client: Client | None = ..., workers: int | None = ..., scheduler: str | None = ..., chunk_rows: int | None = ...,
    ) -> None: ...

    @overload
    def __init__(
        self: ConvexHull[None], points: ArrayLike | os.PathLike[str], incremental: bool = ...,
        qhull_options: str | None = ..., *, backend: str = ..., history: Literal[False] = ..., seed: int = ...,
        check: bool = ..., stats: Stats | None = ..., progress: bool | Callable[[int], Any] = ...,
        client: Client | None = ..., workers: int | None = ..., scheduler: str | None = ..., chunk_rows: int | None = ...,
    ) -> None: ...

    @overload
    def __init__(
        self: ConvexHull[HullHistory | None], points: ArrayLike | os.PathLike[str], incremental: bool = ...,
        qhull_options: str | None = ..., *, backend: str = ..., history: bool, seed: int = ...,
        check: bool = ..., stats: Stats | None = ..., progress: bool | Callable[[int], Any] = ...,
        client: Client | None = ..., workers: int | None = ..., scheduler: str | None = ..., chunk_rows: int | None = ...,
    ) -> None: ...

    def __init__(
        self,
        points: ArrayLike | os.PathLike[str],
        incremental: bool = False,
        qhull_options: str | None = None,
        *,
        backend: str = "red_black",
        history: bool = False,
        seed: int = 0,
        check: bool = False,
        stats: Stats | None = None,
        progress: bool | Callable[[int], Any] = False,
        client: Client | None = None,
        workers: int | None = None,
        scheduler: str | None = None,
        chunk_rows: int | None = None,
    ) -> None:
        check_qhull_options(qhull_options, "ConvexHull")
        refuse_other_dimension(points, "ConvexHull")
        self._qc = keeps_coplanar(qhull_options, "ConvexHull")
        self._incremental = bool(incremental)
        self._closed = False
        where = (client, workers, scheduler, chunk_rows)
        if isinstance(points, os.PathLike) or too_big_to_load(points) or any(x is not None for x in where):
            if stats is not None:
                raise ValueError(
                    "stats= counts the operations of one process: give the points as an array, "
                    "without client/workers/scheduler/chunk_rows"
                )
            if not isinstance(progress, bool):
                raise ValueError("a progress callback follows the one-process run: give progress=True for chunked input")
            self._adopt_chunked(
                chunked_hull(
                    points, client=client, workers=workers, scheduler=scheduler, chunk_rows=chunk_rows,
                    seed=seed, backend=backend, history=history, check=check, progress=progress,
                ),
                check,
            )
            return
        hull = convex_hull(points, backend=backend, history=history, seed=seed, check=check, stats=stats, progress=progress)
        self._adopt(hull, check)

    @classmethod
    def from_hull(cls, hull: Hull, *, check: bool = False) -> ConvexHull[HullHistory | None]:
        """The public view of a :class:`~persistri.impl.hull.api.Hull` already computed (no work is redone).

        ``check`` is what :meth:`add_points` does by default.  O(m) (the index arrays' conversion).
        """
        if not isinstance(hull, Hull):
            raise TypeError(f"ConvexHull.from_hull needs a persistri Hull, not {type(hull).__name__}")
        self = cast("ConvexHull[HullHistory | None]", cls.__new__(cls))  # H is the history's kind: either here
        self._incremental = self._closed = False
        self._qc = False  # scipy's default options
        self._adopt(hull, check)
        return self

    # -- persistence ------------------------------------------------------------------

    def add_points(
        self,
        points: ArrayLike,
        restart: bool = False,
        *,
        check: bool | None = None,
        progress: bool | Callable[[int], Any] = False,
    ) -> ConvexHull[H]:
        """The hull of these points and ``points`` (``(k, 3)``): a NEW hull, or, in incremental mode, this one.

        Made without ``incremental=True``, this hull is left exactly as it was and a
        new one is returned, sharing its structure: the bulldozer resumes from this
        hull's final version (:func:`persistri.impl.hull.extend.extend_hull`).  Made
        with ``incremental=True`` (scipy's mode), this object moves to that new hull
        and returns itself — as scipy's ``add_points`` changes its hull — until
        :meth:`close`; the old hull is still there underneath (in ``history``, if
        kept).  Either way the ``points`` are this hull's rows followed by the new
        ones (row numbers keep their meaning), and ``history`` continues this one's
        when this one kept it.  ``restart=True`` (scipy's option) computes the hull
        of all the rows again from scratch instead (a history of its own).  Both are
        the hull of all the rows — the same volume, area and extreme points, and the
        same simplices in general position — but on degenerate input (a point on a hull
        edge or on a flat facet) they may differ in which such points are vertices:
        resuming keeps this run's labels and gives the new points later ones, a fresh
        run labels all the points anew, and Simulation of Simplicity breaks the ties in
        the order of the labels.  ``check`` defaults to this hull's.  Errors as for the constructor,
        about ``points``; :class:`RuntimeError` after :meth:`close` in incremental mode.

        A hull computed chunk by chunk resumes its final merge instead
        (:func:`~persistri.impl.scale.extend.extend_parallel`), with exactly the same result as
        the one-process hull's ``add_points``; that reads the input once, in this process, to
        find the new points equal to old ones (``restart=True`` is a :class:`ValueError` there:
        it would hull the whole input again).
        """
        from persistri.impl.hull.extend import extend_hull

        if self._closed:
            raise closed_error("ConvexHull")
        chk = self._check if check is None else check
        if self._incremental:
            out = self
        else:
            out = type(self).__new__(type(self))
            out._incremental = out._closed = False
            out._qc = self._qc
        if self._chunked is not None:
            if restart:
                raise ValueError(
                    "ConvexHull.add_points: restart=True on a chunked hull would hull the whole input again; "
                    "make a new ConvexHull of it instead"
                )
            from persistri.impl.scale.extend import extend_parallel

            out._adopt_chunked(extend_parallel(self._chunked, points, check=chk, progress=progress), chk)
            return out
        old = self._hull
        if restart:
            rows = np.concatenate([old.points, as_points(points, 3, what="new points")])
            hull = convex_hull(rows, backend=old.backend, history=old.history is not None, seed=old.seed, check=chk, progress=progress)
        else:
            hull = extend_hull(old, points, check=chk, progress=progress)
        out._adopt(hull, chk)
        return out

    def close(self) -> None:
        """End incremental mode (``incremental=True``: :meth:`add_points` then raises, as scipy's); otherwise nothing
        to do (a hull holds no resources, and :meth:`add_points` goes on returning new hulls). O(1)."""
        if self._incremental:
            self._closed = True
