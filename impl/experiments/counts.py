"""Counted convex-hull runs: the operation counts of §4 (Figs. 6 and 7) for one distribution, size and seed.

One run of :func:`~persistri.impl.hull.api.convex_hull` with a
:class:`~persistri.impl.stats.Stats` attached gives both halves of the paper's
measure (§4).  The run is ``stepwise``: the complex changes as in the paper's
code, one ``rem`` per lit face and one ``add`` per tent face, so the
topological counts are those of the algorithm the paper measured (the default
hull batches each insertion into one ``replace``, which makes fewer dictionary
operations and key comparisons; the numerical half is the same either way):

* the **topological** half — dictionary operations and **key comparisons**
  (red-black tree nodes visited plus per-vertex list entries visited, as the
  paper counts them);
* the **numerical** half — plane-side tests and the **floating-point
  operations** they imply (each filtered test counts the flops of its
  expression and of its error bound: see ``persistri.impl.geometry.filter``).

Figs. 6 and 7 share runs (both use OnSphere and BordHeavy at 512K points), so
:class:`HullCountCache` keeps the records of a session: a run asked for twice is
made once.  A record is deterministic in ``(distribution, n, seed, backend)``
except its CPU time.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

from persistri.impl.stats import Stats

__all__ = ["HullCount", "HullCountCache", "hull_counts"]


@dataclass(frozen=True, slots=True)
class HullCount:
    """The counts of one bulldozer run (paper §4): ``n`` points of ``dist``, points and insertion order from ``seed``."""

    dist: str
    n: int
    seed: int
    backend: str
    key_comparisons: int
    dict_ops: int
    plane_side_tests: int
    flops: int
    filter_failures: int
    faces_created: int
    hull_vertices: int
    cpu_seconds: float
    """CPU time of the counted run (counting included; ``time.process_time``)."""

    @property
    def flops_per_key_comparison(self) -> float:
        """Floating-point operations per key comparison: ≈ 1 on the sphere distributions in the paper."""
        return self.flops / self.key_comparisons if self.key_comparisons else math.inf

    @property
    def n_lg_n(self) -> float:
        """``n lg n``, the expected growth of both counts (Theorem 11)."""
        return self.n * math.log2(self.n)

    def row(self) -> dict[str, object]:
        """The record as a CSV row (fields, then the derived ratio)."""
        out: dict[str, object] = asdict(self)
        out["flops_per_key_comparison"] = self.flops_per_key_comparison
        return out


class HullCountCache:
    """The counted runs made so far in this session, by ``(dist, n, seed, backend)`` (Figs. 6 and 7 share them).

    Runs made ahead of the figures (on a Dask cluster, :mod:`persistri.impl.experiments.sweep`) are
    kept apart (:meth:`prefill`): a figure that asks for one *takes* it (:meth:`take`) as if it had made
    it, so :meth:`get` still says which runs an earlier figure made (what Fig. 7 reports as reused).
    """

    def __init__(self) -> None:
        self._runs: dict[tuple[str, int, int, str], HullCount] = {}
        self._ready: dict[tuple[str, int, int, str], HullCount] = {}

    def get(self, dist: str, n: int, seed: int, backend: str) -> HullCount | None:
        """The record of that run, if made."""
        return self._runs.get((dist, n, seed, backend))

    def put(self, record: HullCount) -> None:
        """Remember ``record``."""
        self._runs[(record.dist, record.n, record.seed, record.backend)] = record

    def prefill(self, record: HullCount) -> None:
        """Keep ``record``, made ahead of the figure that will ask for it."""
        self._ready[(record.dist, record.n, record.seed, record.backend)] = record

    def take(self, dist: str, n: int, seed: int, backend: str) -> HullCount | None:
        """The prefilled record of that run, if any, now remembered as made (:meth:`put`)."""
        record = self._ready.pop((dist, n, seed, backend), None)
        if record is not None:
            self.put(record)
        return record

    def __len__(self) -> int:
        return len(self._runs)


def hull_counts(
    dist: str,
    n: int,
    seed: int = 0,
    *,
    backend: str = "red_black",
    cache: HullCountCache | None = None,
    on_points: Callable[[int], Any] | None = None,
) -> HullCount:
    """Count one bulldozer run on ``n`` points of ``dist`` (a §4 distribution), from ``seed``.

    ``on_points(k)`` is told as points are processed (``k`` since the last
    call), for progress; a cached run reports all its ``n`` points at once.
    ValueError for an unknown distribution or ``n < 4``.  Expected O(n lg n).
    """
    from persistri.impl.hull.api import convex_hull
    from persistri.impl.hull.distributions import generate

    if isinstance(n, bool) or not isinstance(n, int) or n < 4:
        raise ValueError(f"a hull needs at least 4 points, got n={n!r}")
    if cache is not None:
        hit = cache.get(dist, n, seed, backend) or cache.take(dist, n, seed, backend)
        if hit is not None:
            if on_points is not None:
                on_points(n)
            return hit
    points = generate(dist, n, seed)
    stats = Stats()
    t0 = time.process_time()
    hull = convex_hull(
        points,
        backend=backend,
        seed=seed,
        stats=stats,
        progress=on_points if on_points else False,
        stepwise=True,
        labels="input",
    )
    seconds = time.process_time() - t0
    if on_points is not None:
        on_points(4 + len(hull.duplicates))  # the first tetrahedron and merged duplicates are not in the order
    record = HullCount(
        dist=dist,
        n=n,
        seed=seed,
        backend=backend,
        key_comparisons=stats.key_comparisons,
        dict_ops=stats.dict_ops,
        plane_side_tests=stats.plane_side_tests,
        flops=stats.flops,
        filter_failures=stats.filter_failures,
        faces_created=stats.faces_created,
        hull_vertices=int(hull.vertices.size),
        cpu_seconds=seconds,
    )
    if cache is not None:
        cache.put(record)
    return record
