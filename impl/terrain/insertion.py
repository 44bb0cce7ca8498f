"""One insertion of the Delaunay triangulator, as its caller reads it (paper §5): the record and its conventions.

:class:`~persistri.impl.terrain.delaunay.Triangulator` inserts a point and
returns an :class:`Insertion`: the new version, the cavity's triangles, the
fan's, and the samples (for a terrain: the grid points not yet inserted) each
fan triangle now holds.  This module holds that record and what it is made of:
the datum of a triangle ``(id, samples)`` (:data:`TriDatum`), the sample
lists' dtype (:func:`sample_dtype`), the way a fan's pooled samples are sorted
into its sectors (:class:`FanSort`), the canonical form of a list of
triangles used to compare meshes (:func:`canonical_triangles`), and what an
insertion changes besides the complex when the triangulator keeps an index of
the current version's directed edges (``Triangulator.edges``: ``index[u][w]``
is the record ``(triangle, datum)`` of the triangle holding ``(u, w)``;
:func:`enter`, :func:`reindex`, :func:`third`).  The compiled twin compiles it
with the triangulator (an insertion makes one record).
"""

from __future__ import annotations

from typing import Any, Final, Protocol, TypeVar

import numpy as np
from numpy.typing import NDArray

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.vertex import Vertex
from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.stats import Stats

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
    "enter",
    "reindex",
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


def third(tri: Any, w: Any) -> Any:
    """The vertex of triangle ``tri`` after the directed edge that starts at its vertex ``w``: ``x`` for the
    edge ``(w, u)`` of ``tri = (w, u, x)`` in any rotation (vertices compared by identity: each is made once). O(1)."""
    return tri[2] if tri[0] is w else (tri[0] if tri[1] is w else tri[1])


def enter(index: dict[Any, dict[Any, tuple[Any, ...]]], tri: Any, datum: Any) -> None:
    """Enter the live triangle ``tri`` (three vertices) with its datum into the edge index ``index``: one record
    ``(tri, datum)`` for its three directed edges. O(1)."""
    rec = (tri, datum)
    for u in tri:
        if u not in index:
            index[u] = {}
    a, b, c = tri
    index[a][b] = index[b][c] = index[c][a] = rec


def reindex(
    index: dict[Any, dict[Any, tuple[Any, ...]]],
    removed: list[Any],
    succ: dict[Any, Any],
    fan: list[tuple[Any, ...]],
    ring: list[Any],
    nfan: int,
    p: Any,
) -> None:
    """The edge index ``index`` of the version before an insertion of ``p``, made the index of the version after it.

    ``removed`` are the cavity's triangles, ``succ`` its boundary edges ``(u, w)`` as
    ``u -> w``, ``fan`` the new triangles' records: ``fan[i] = ((ring[i], ring[i+1], p),
    datum)`` for ``i < nfan``, then an open fan's two ghosts.  The cavity's interior
    edges leave the index (a directed edge of a removed triangle is on the boundary iff
    ``succ`` has it: it is in one triangle only); every boundary edge is entered again by
    the fan triangle on it, and the spokes to ``p`` are new.  Each ring vertex's row is
    read once (it takes the edges of two fan triangles).  O(k) for ``k`` triangles
    removed and made.
    """
    for t in removed:
        ta, tb, tc = t
        if succ.get(ta) is not tb:
            del index[ta][tb]
        if succ.get(tb) is not tc:
            del index[tb][tc]
        if succ.get(tc) is not ta:
            del index[tc][ta]
    row_p: dict[Any, tuple[Any, ...]] = {}
    index[p] = row_p
    u = ring[0]
    row_u = index[u]
    for rec, w in zip(fan, ring[1 : nfan + 1]):
        row_w = index[w]
        row_u[w] = row_w[p] = row_p[u] = rec
        u = w
        row_u = row_w
    for rec in fan[nfan:]:
        ta, tb, tc = rec[0]
        index[ta][tb] = index[tb][tc] = index[tc][ta] = rec


def canonical_triangles(tris: IntArray) -> IntArray:
    """Each row rotated to start at its smallest index (orientation kept), rows sorted: a canonical mesh. O(m log m)."""
    t = np.asarray(tris, dtype=np.intp).reshape(-1, 3)
    if t.size == 0:
        return np.zeros((0, 3), dtype=np.intp)
    k = np.argmin(t, axis=1)
    rot = np.take_along_axis(t, (k[:, None] + np.arange(3)[None, :]) % 3, axis=1)
    out: IntArray = rot[np.lexsort(rot.T[::-1])]
    return out
