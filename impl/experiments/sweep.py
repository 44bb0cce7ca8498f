"""The sweep of Figs. 6 and 7 as Dask tasks: every counted hull run of the experiments, in parallel.

Figs. 6 and 7 sweep the bulldozer over distributions, sizes and seeds (§4):
one counted :func:`~persistri.impl.experiments.counts.hull_counts` run each.
A run is a pure function of ``(distribution, n, seed, backend)`` — the points
and the random insertion order both come from the seed, and nothing is shared
between runs — so the sweep is a set of independent tasks, the paper's case of
computations that "parallelize without special provision".  :func:`count_runs`
submits them to a ``distributed`` cluster, longest first, and
keeps the records in the session's cache as they come back
(:meth:`~persistri.impl.experiments.counts.HullCountCache.prefill`); the figures then take them
as if they had made them, and write the same files.  Every count of a record
(key comparisons, dictionary operations, plane-side tests, flops, filter
failures, faces, hull vertices) is the same on a worker as in this process
(tested); only ``cpu_seconds``, a measurement, differs from run to run anyway.

Figs. 8 and 11 stay in this process: Fig. 8 *times* its runs (runs sharing the
machine's cores and memory bandwidth would distort the times it plots), and
Fig. 11's terrain counts take seconds at the paper's sizes.

Cost: the sweep's runs spread over the workers (a 512K-point OnSphere run is
minutes: with W workers the paper-size Figs. 6–7, 11 runs, take about the
longest W-th of them instead of their sum), one small record back per run.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

from persistri.impl.experiments import fig6 as f6
from persistri.impl.experiments import fig7 as f7
from persistri.impl.experiments.counts import HullCount, HullCountCache, hull_counts
from persistri.impl.experiments.output import Progress, size_label
from persistri.impl.scale.cluster import ClusterError

if TYPE_CHECKING:
    from distributed import Client

__all__ = ["SWEPT", "hull_runs", "count_runs"]

SWEPT = ("fig6", "fig7")
"""The figures whose runs :func:`count_runs` makes on a cluster."""


def hull_runs(plan: Mapping[str, Sequence[int]], seeds: Sequence[int]) -> list[tuple[str, int, int]]:
    """The ``(distribution, n, seed)`` runs that Figs. 6 and 7 of ``plan`` (figure → sizes) count, each once,
    largest ``n`` first (the longest tasks start first).

    >>> hull_runs({"fig6": (512, 1024), "fig8": (16,)}, (0,))
    [('OnSphere', 1024, 0), ('BordHeavy', 1024, 0), ('OnSphere', 512, 0), ('BordHeavy', 512, 0)]
    """
    runs: dict[tuple[str, int, int], None] = {}
    for n in plan.get("fig6", ()):
        runs.update({(d, n, s): None for d in f6.DISTS for s in seeds})
    for n in plan.get("fig7", ())[-1:]:  # Fig. 7 runs at one size: the largest (suite.sizes_for)
        runs.update({(d, n, s): None for d in f7.DISTS for s in seeds})
    return sorted(runs, key=lambda r: -r[1])


def count_runs(
    client: Client,
    runs: Sequence[tuple[str, int, int]],
    *,
    backend: str,
    cache: HullCountCache,
    progress: Progress | None = None,
) -> int:
    """Make the ``runs`` that ``cache`` does not hold yet as tasks on ``client``'s cluster and prefill ``cache``
    with their records; returns how many were made.

    ``progress(points done, points in all, what)`` as each run comes back.  Raises what a run raises
    (the first to fail), or :class:`~persistri.impl.scale.cluster.ClusterError` when a run kills the
    workers that take it.  Cost: the runs' own, spread over the workers.
    """
    from distributed import as_completed
    from distributed.scheduler import KilledWorker

    todo = [r for r in runs if cache.get(r[0], r[1], r[2], backend) is None]
    if not todo:
        return 0
    total = sum(n for _, n, _ in todo)
    workers = len(client.scheduler_info(n_workers=-1)["workers"])
    what = f"{len(todo)} counted hulls on {workers} Dask workers"
    if progress is not None:
        progress(0, total, what)
    futures = [client.submit(hull_counts, d, n, s, backend=backend, pure=False) for d, n, s in todo]
    done = 0
    try:
        for future in as_completed(futures):
            record: HullCount = future.result()
            cache.prefill(record)
            done += record.n
            if progress is not None:
                progress(done, total, f"{what}: {record.dist} {size_label(record.n)} seed {record.seed} done")
    except KilledWorker as exc:
        raise ClusterError(
            f"counted run {exc.task!r} was given up on: the {exc.allowed_failures + 1} workers that ran it died "
            "(out of memory, or killed); no figure was written"
        ) from None
    finally:
        for future in futures:
            future.release()
    return len(todo)
