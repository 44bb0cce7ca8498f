"""One insertion of the Delaunay triangulator, as its caller reads it (paper §5): the record and its conventions.

:class:`~persistri.impl.terrain.delaunay.Triangulator` inserts a point and
returns an :class:`Insertion`: the new version, the cavity's triangles, the
fan's, and the samples (for a terrain: the grid points not yet inserted) each
fan triangle now holds.  This module holds that record and what it is made of:
the datum of a triangle ``(id, samples)`` (:data:`TriDatum`), the sample
lists' dtype (:func:`sample_dtype`), the way a cavity's samples are pooled, sorted
into the fan's sectors and cut into its triangles' lists (:func:`fan_samples`,
:class:`FanSort`), the canonical form of a list of
triangles used to compare meshes (:func:`canonical_triangles`), and what an
insertion changes besides the complex when the triangulator keeps neighbour
records of the current version's triangles (``Triangulator.adj``: the record of
a triangle names the triangle across each of its edges; :func:`link` makes them
for a whole surface, :func:`third` reads a triangle's third vertex;
:meth:`~persistri.impl.terrain.delaunay.Triangulator.insert` updates them as it
goes).  The compiled twin compiles it with the triangulator (an insertion makes one record).
"""

from __future__ import annotations

from typing import Any, Final, Protocol, TypeVar

import numpy as np
from numpy.typing import NDArray

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.vertex import Vertex
from persistri.impl.geometry.grid_predicates import GridPredicates2
from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.stats import Stats
from persistri.impl.terrain.errors import TriangulationCheckError
from persistri.impl.terrain.sectors import FLOPS_SECTOR_TEST, PYTHON_SECTORS, fan_lists, fan_sectors, small_buckets

__all__ = [
    "EMPTY",
    "LARGE_FAN",
    "NO_SECTOR",
    "FanSort",
    "Insertion",
    "IntArray",
    "Samples",
    "Triangle",
    "TriDatum",
    "canonical_triangles",
    "fan_samples",
    "link",
    "sample_dtype",
    "third",
]

IntArray = NDArray[np.intp]
Samples = NDArray[np.signedinteger[Any]]
"""A read-only array of point indices: ``int32`` when every index fits (:func:`sample_dtype`), else ``intp``."""
Triangle = tuple[Vertex, Vertex, Vertex]
TriDatum = tuple[int, Samples]
"""The datum of a triangle: ``(triangle id, samples)``; the samples are a read-only array of point indices
(:data:`Samples`)."""


def sample_dtype(n: int) -> np.dtype[np.signedinteger[Any]]:
    """The dtype of sample lists over points ``0 … n − 1``: ``int32`` (4 bytes a sample) when every index fits
    (``n ≤ 2^31``), else ``intp``.

    A height grid's samples are all in some triangle's list at every moment, so their dtype is the
    mesher's memory per sample: half of ``intp``'s.  The values are the same either way.  O(1).
    """
    return np.dtype(np.int32) if n - 1 <= np.iinfo(np.int32).max else np.dtype(np.intp)

LARGE_FAN: Final[int] = 1 << 16
"""Above this many pooled samples an insertion sorts them into one array per fan triangle
(:func:`~persistri.impl.terrain.sectors.fan_lists`, in blocks, from the cavity's lists without pooling them)
and reports no pooled array; below it, one sorted pooled array whose slices are copied (fewer numpy calls)."""

EMPTY: Final[Samples] = np.zeros(0, dtype=np.intp)
"""The empty (read-only) sample list of ghosts and of triangles without samples."""
EMPTY.setflags(write=False)

NO_SECTOR: Final[IntArray] = np.zeros(0, dtype=np.intp)
"""The (read-only) ``fan_index`` of an insertion without samples (scattered points have none)."""
NO_SECTOR.setflags(write=False)


_A = TypeVar("_A", bound=NDArray[Any])
_R = TypeVar("_R")
_S = TypeVar("_S")
_R_co = TypeVar("_R_co", covariant=True)
_S_contra = TypeVar("_S_contra", contravariant=True)


class FanSort(Protocol[_S_contra, _R_co]):
    """How an insertion sorts its pooled samples into the fan's sectors: ``fan_sectors`` (the pool as one
    array) or ``fan_lists`` (the pool as the cavity's lists; :mod:`persistri.impl.terrain.sectors`), called
    with the fan's rays and the pool."""

    def __call__(
        self,
        pred: Predicates2,
        p: int,
        rays: IntArray,
        samples: _S_contra,
        closed: bool,
        *,
        exact_floats: bool,
        stats: Stats | None = None,
        check: bool = False,
    ) -> _R_co: ...


class Insertion:
    """What one insertion did (the caller, e.g. greedy insertion, reads the new triangles from it).

    * ``point`` — the inserted point;
    * ``version`` — the complex after it;
    * ``removed`` — ids of the triangles of the cavity (ghosts included);
    * ``created`` — the new *finite* triangles, ``(id, triangle)``, in the order of
      the fan around ``point``;
    * ``samples`` — the pooled samples of the cavity, sorted by the position of
      their new triangle in ``created`` (``point`` excluded); ``counts[i]`` of them
      belong to ``created[i]``, consecutively; None when there were more than
      :data:`LARGE_FAN` (``lists`` has them);
    * ``counts`` — how many samples each triangle of ``created`` holds;
    * ``hull_vertex`` — whether ``point`` is a vertex of the new convex hull (it lay on or
      beyond the old one: ghosts were in the cavity);
    * ``rays`` — the fan's boundary vertices in order, ``len(created) + 1`` of them:
      ``created[i]`` is ``(rays[i], rays[i + 1], point)`` (a closed fan repeats its first vertex at the end);
    * ``fan_index`` — for each of ``samples``, the position of its triangle in ``created`` (nondecreasing);
      None with ``samples``;
    * ``lists`` — the samples of each triangle of ``created`` (the arrays its datum holds).

    A record made once per insertion and only read afterwards (a plain slotted class: a frozen
    dataclass costs a microsecond more per insertion to make); the lists are the insertion's own.
    """

    __slots__ = ("point", "version", "removed", "created", "samples", "counts", "hull_vertex", "rays", "fan_index", "lists")

    def __init__(
        self,
        point: int,
        version: Complex[TriDatum],
        removed: list[int],
        created: list[tuple[int, Triangle]],
        samples: Samples | None,
        counts: list[int],
        hull_vertex: bool,
        rays: list[Vertex],
        fan_index: IntArray | None,
        lists: list[Samples],
    ) -> None:
        self.point = point
        self.version = version
        self.removed = removed
        self.created = created
        self.samples = samples
        self.counts = counts
        self.hull_vertex = hull_vertex
        self.rays = rays
        self.fan_index = fan_index
        self.lists = lists

    def __repr__(self) -> str:
        return f"Insertion(point={self.point}, created={len(self.created)}, removed={len(self.removed)}, samples={sum(self.counts)})"


_INTP: Final = np.dtype(np.intp)
"""The dtype of fan indices, made once (numpy converts a type such as ``np.intp`` to its dtype at every call)."""


_INDEX_FROM_LIST: Final[int] = 16
"""Up to this many samples :func:`_small_fan` makes the fan index from a Python list; above it by ``repeat``
of the fan's positions (a larger fixed cost, numpy's per-element conversion avoided; break-even about 17
samples, cachegrind, 2026-11-28)."""

_FAN_POSITIONS: Final[IntArray] = np.arange(1 << 12, dtype=np.intp)
"""``0, 1, 2, …``: the positions of a fan's triangles, sliced by :func:`_small_fan` (more than any grid fan has)."""
_FAN_POSITIONS.setflags(write=False)

_SET_FLAGS: Any = np.ndarray.setflags
"""``ndarray.setflags``, called with ``write`` by position (:func:`_frozen`)."""


def _frozen(a: _A) -> _A:
    """``a``, made read-only.  O(1)."""
    # Arguments by position: numpy's methods and constructors parse keywords at a few times the cost of a
    # positional argument (``setflags(write=False)`` 0.26 µs, ``setflags(False)`` 0.09 µs, timeit, 2026-11-28).
    # (numpy's stubs take ``write`` by keyword only; the method itself takes it by position.)
    _SET_FLAGS(a, False)
    return a


def fan_samples(
    pred: Predicates2,
    p: int,
    lists: list[Samples],
    ring: list[Vertex],
    closed: bool,
    nfan: int,
    *,
    exact_floats: bool,
    check: bool,
) -> tuple[list[Samples], Samples | None, list[int], IntArray | None]:
    """The samples of an insertion's cavity (the removed triangles' ``lists``), sorted into the fan's sectors and
    cut into the fan triangles' lists: ``(lists, samples, counts, fan_index)`` of the :class:`Insertion`.

    Fan triangle ``i`` is ``(ring[i], ring[i+1], p)`` (``nfan`` of them).  Up to
    :data:`LARGE_FAN` samples are pooled into one array without ``p``, sorted by
    :func:`~persistri.impl.terrain.sectors.fan_sectors` and cut into copies (a view would
    keep the whole pool alive as long as any one of the fan's triangles lives: on a
    2,048² grid, kept only for the final mesh, the pools held 92 MB for 32 MB of live
    samples at the end of the run, measured; a copy costs about 0.1 µs more); above it,
    :func:`~persistri.impl.terrain.sectors.fan_lists` sorts the lists in blocks into one
    array per triangle without pooling them, and ``samples`` is None.  A triangle without
    samples gets :data:`EMPTY`.  A sample in no sector is a :class:`TriangulationCheckError`.
    O(m · len(ring)) for ``m`` samples.
    """
    sized: list[Samples] = []
    total = 0
    for s in lists:
        size: int = s.size
        if size:
            sized.append(s)
            total += size
    if 0 < total <= PYTHON_SECTORS + 1 and nfan > 1 and exact_floats and isinstance(pred, GridPredicates2):
        # Few samples on a grid (most insertions): sorted on Python lists, without the arrays in between.
        small = _small_fan(pred, p, sized, ring, closed, nfan)
        if small is not None:
            return small
    parts: list[Samples] | None = None
    sector: IntArray | None = None
    samples: Samples | None
    if nfan > 1 and (total > LARGE_FAN + 1 or (total == LARGE_FAN + 1 and not any([bool((s == p).any()) for s in sized]))):
        # Millions of samples (a large grid's first insertions): one array per triangle, made in blocks
        # from the cavity's lists without pooling them (fan_lists: no array of the pool's size but the result).
        parts = _into_sectors(fan_lists, pred, p, ring, closed, sized, exact_floats, check)
        counts = [part.size for part in parts]
        samples = None
        pooled = EMPTY
    else:
        pooled = sized[0] if len(sized) == 1 else (np.concatenate(sized) if sized else EMPTY)
        if pooled is not EMPTY and pooled.size:
            pooled = pooled[pooled != p]
        if pooled is not EMPTY and pooled.size and nfan > 1:
            order, sector = _into_sectors(fan_sectors, pred, p, ring, closed, pooled, exact_floats, check)
            pooled = pooled[order]
            counts = np.bincount(sector, None, nfan).tolist()
        elif pooled is EMPTY:
            sector = NO_SECTOR
            counts = [0] * nfan
        else:
            sector = np.zeros(pooled.size, dtype=np.intp) if pooled.size else NO_SECTOR
            counts = [0] * nfan
            counts[0] = pooled.size
        samples = pooled if pooled is EMPTY else _frozen(pooled)
    whole = 0 if pooled is EMPTY else pooled.size
    own: list[Samples] = []
    start_at = 0
    for i in range(nfan):
        cnt = counts[i]
        if not cnt:
            part = EMPTY
        elif parts is not None:
            part = _frozen(parts[i])
        else:
            stop = start_at + cnt
            part = pooled if cnt == whole else _frozen(pooled[start_at:stop].copy())
            start_at = stop
        own.append(part)
    return own, samples, counts, sector if sector is None or sector is NO_SECTOR else _frozen(sector)


def _small_fan(
    pred: GridPredicates2, p: int, sized: list[Samples], ring: list[Vertex], closed: bool, nfan: int,
    bound: int = PYTHON_SECTORS,
) -> tuple[list[Samples], Samples, list[int], IntArray] | None:
    """:func:`fan_samples` for a few samples on a grid, or None when they are none or more than ``bound``
    (:data:`~persistri.impl.terrain.sectors.PYTHON_SECTORS`; tests pass others) once ``p`` is left out (the
    general path then).

    The cavity's lists (``sized``, none empty, all of one dtype: the triangulator's :func:`sample_dtype`) read
    once into one Python list, ``p`` left out, sorted into the fan's triangles by
    :func:`~persistri.impl.terrain.sectors.small_buckets` (:func:`~persistri.impl.terrain.sectors.fan_small`'s
    loop) and made into arrays once: the same lists, pool, counts, fan index, dtypes, counted tests and
    :class:`TriangulationCheckError` as the general path, whose ``fan_sectors`` would run that loop too but
    with the ring, the pool and the answer each turned from list to array and back (measured:
    docs/performance.md, "The fan's samples without round trips").  The arrays: the pool converted once from
    the Python list, each triangle's list a copy of its slice, the fan index from a list up to
    :data:`_INDEX_FROM_LIST` samples and by ``repeat`` above.  O(m · len(ring)) for ``m`` samples.
    """
    qs: list[Any] = []
    for s in sized:
        qs += s.tolist()
    if p in qs:
        # p leaves; compared unboxed (compiled: a comparison of two objects costs a call each), kept as objects.
        kept: list[Any] = []
        for qo in qs:
            q: int = qo
            if q != p:
                kept.append(qo)
        qs = kept
    m = len(qs)
    if not m or m > bound:
        return None
    stats = pred.stats
    if stats is not None:
        tested = nfan if closed else nfan - 1
        stats.plane_side_tests += m * tested
        stats.flops += FLOPS_SECTOR_TEST * m * tested
    try:
        buckets = small_buckets(pred.shape[1], p, ring, qs, closed, False)
    except ValueError as exc:
        raise TriangulationCheckError(f"inserting point {p}: {exc}") from None
    dtype = sized[0].dtype
    counts: list[int] = []
    pooled: list[Any] = []
    index: list[int] = []
    by_list = m <= _INDEX_FROM_LIST or nfan > _FAN_POSITIONS.size
    for i in range(nfan):
        b = buckets[i]
        c = len(b)
        counts.append(c)
        if c:
            pooled += b
            if by_list:
                index += [i] * c
    # Python integers enter an array at about 200–280 instructions each (numpy converts them one by one): the pool
    # is converted once, and each triangle's list is a copy of its slice of it (a memory copy).
    samples = _frozen(np.fromiter(pooled, dtype, m))
    own: list[Samples] = []
    start = 0
    for c in counts:
        if not c:
            own.append(EMPTY)
        elif c == m:
            own.append(samples)
        else:
            own.append(_frozen(samples[start : start + c].copy()))
        start += c
    fan_index = np.array(index, _INTP) if by_list else _FAN_POSITIONS[:nfan].repeat(counts)
    return own, samples, counts, _frozen(fan_index)


def _into_sectors(
    sort: FanSort[_S, _R], pred: Predicates2, p: int, ring: list[Vertex], closed: bool, pooled: _S, exact_floats: bool, check: bool
) -> _R:
    """The pooled samples sorted into the fan's sectors by ``sort``; fan triangle ``i`` is ``(ring[i], ring[i+1], p)``.

    ``sort`` is :func:`~persistri.impl.terrain.sectors.fan_sectors` (``(order, i)``: the
    samples, one array without ``p``, sorted by triangle) or, for very many samples,
    :func:`~persistri.impl.terrain.sectors.fan_lists` (the cavity's lists, ``p`` among
    them, to one array per triangle): the sector
    test of :mod:`persistri.impl.terrain.sectors`, true orient2d signs against the ray to
    every boundary vertex (the two ends of an open chain are known: ``p`` split a hull edge
    and every sample is on its inner side); ``exact_floats``: the sector test's float path is
    exact (when orient2d's is: the docs of kernel2d and sectors).  A sample in no sector is a
    :class:`TriangulationCheckError`.  O(len(pooled) · len(ring)).
    """
    try:
        return sort(
            pred,
            p,
            np.fromiter(ring, _INTP, len(ring)),
            pooled,
            closed,
            exact_floats=exact_floats,
            stats=pred.stats,
            check=check,
        )
    except ValueError as exc:
        raise TriangulationCheckError(f"inserting point {p}: {exc}") from None


def third(tri: Any, w: Any) -> Any:
    """The vertex of triangle ``tri`` after the directed edge that starts at its vertex ``w``: ``x`` for the
    edge ``(w, u)`` of ``tri = (w, u, x)`` in any rotation (vertices compared by identity: each is made once). O(1)."""
    return tri[2] if tri[0] is w else (tri[0] if tri[1] is w else tri[1])


def link(adj: list[Any], items: list[Any]) -> None:
    """Make the neighbour records of a closed surface's triangles in ``adj`` (the triangulator's list by triangle
    id; ``Triangulator.adj``): ``items`` are its ``(triangle, datum)`` pairs, ``datum[0]`` the triangle's id, and
    each gets the record ``[triangle, datum, n0, n1, n2, None]``, ``nk`` the id of the triangle across its edge
    ``k``.  ``adj`` is extended with None to the largest id.  O(len(items)) (one dictionary of directed edges).
    """
    holder: dict[tuple[Any, Any], Any] = {}
    item: Any
    for item in items:
        a, b, c = item[0]
        tid = item[1][0]
        holder[(a, b)] = holder[(b, c)] = holder[(c, a)] = tid
    top = max([item[1][0] for item in items], default=-1)
    if top >= len(adj):
        adj.extend([None] * (top + 1 - len(adj)))
    for item in items:
        tri = item[0]
        a, b, c = tri
        adj[item[1][0]] = [tri, item[1], holder[(b, a)], holder[(c, b)], holder[(a, c)], None]


def canonical_triangles(tris: IntArray) -> IntArray:
    """Each row rotated to start at its smallest index (orientation kept), rows sorted: a canonical mesh. O(m log m).

    The rows are sorted lexicographically: by one ``int64`` key ``(r0 · b + r1) · b + r2`` (``b`` one more than
    the largest index: the key's order is the rows' lexicographic order) when ``b³`` fits in 63 bits, a
    quarter of ``lexsort``'s time on three columns (10K-point meshes); by ``lexsort`` otherwise or for negative
    indices.
    """
    t = np.asarray(tris, dtype=np.intp).reshape(-1, 3)
    if t.size == 0:
        return np.zeros((0, 3), dtype=np.intp)
    k = np.argmin(t, axis=1)
    rot = np.take_along_axis(t, (k[:, None] + np.arange(3)[None, :]) % 3, axis=1)
    lo, base = int(rot.min()), int(rot.max()) + 1
    if lo >= 0 and base <= _KEY_BASE_MAX:
        key = rot[:, 0].astype(np.int64) * base
        key += rot[:, 1]
        key *= base
        key += rot[:, 2]
        order = np.argsort(key, kind="stable")
    else:
        order = np.lexsort(rot.T[::-1])
    out: IntArray = rot[order]
    return out


_KEY_BASE_MAX: Final[int] = 2**21 - 1
"""The largest ``b`` with ``b³ < 2^63``: :func:`canonical_triangles` sorts by one ``int64`` key up to it."""
