"""``connect``: where persistri's parallel work runs — the one place that decides.

The paper argues that purely functional triangulations "parallelize without
special provision, precisely because they avoid mutation entirely" (§1): a
version is a value, so a worker can be handed one (pickled) and nothing it
does can disturb anyone else's.  persistri's parallel side runs on Dask's
``distributed`` scheduler, and every entry point (the ``--workers`` and
``--scheduler`` options, :func:`persistri.impl.scale.hull.parallel_hull`,
:mod:`persistri.impl.scale.futures`, the tiled terrain) asks this module for
its :class:`distributed.Client`.  The rules, in order:

1. ``workers=1`` — the **sequential path**: ``None``, and the caller runs
   in-process without Dask (no cluster is started; ``PERSISTRI_SCHEDULER`` is
   ignored: an explicit one worker is a request not to distribute).
2. ``scheduler="tcp://host:8786"`` — an **existing cluster**: a client of that
   scheduler (its workers are whatever that cluster has, so ``workers`` must
   not be given too).
3. ``workers=N`` (N ≥ 2) — a **local cluster** of N worker processes.
4. Neither given: the sequential path when the work is a single task (the
   caller says so with ``tasks=1``: a cluster could only add its start-up) or
   the machine has one core; otherwise the environment variable
   ``PERSISTRI_SCHEDULER``, when set, names an existing cluster as in 2, and
   without it a **local cluster** with one worker per core.

A local cluster is a :class:`distributed.LocalCluster` of worker
**processes**, one thread each: persistri's work is pure Python and holds the
GIL, so threads would take turns on one core.  It listens on the loopback
interface only, and lives exactly as long as the ``with`` block.  Its
dashboard is off unless asked for (``dashboard=True``: a free port, whose link
is :attr:`distributed.Client.dashboard_link`; the commands print it).

Worker processes start by importing persistri, so a remote cluster's workers
need ``persistri[dask]`` installed, and paths given to them (memory-mapped
``.npy``, Zarr stores) must name files they can read.

Starting a local cluster costs a few seconds (one Python interpreter per
worker); a client of an existing cluster, one round trip.  Importing this module
imports no Dask (only :func:`connect` does, when it starts one), so that
commands can apply :func:`plan` before they know Dask is installed.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from distributed import Client

__all__ = ["ClusterError", "ENV_SCHEDULER", "connect", "default_workers", "plan"]

ENV_SCHEDULER = "PERSISTRI_SCHEDULER"
"""The environment variable naming an existing scheduler (used when neither ``workers`` nor ``scheduler`` is given)."""

CONNECT_TIMEOUT = 10.0
"""Seconds to wait for an existing scheduler to answer before giving up with :class:`ClusterError`."""


class ClusterError(ConnectionError):
    """No cluster could be had (the scheduler did not answer, the local workers did not start), or it lost
    the run (workers kept dying).  An :class:`OSError`, so the command line reports it as one line."""


def default_workers() -> int:
    """The cores this process may run on (its CPU affinity where the OS reports it), at least 1."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux: every core the machine has
        return max(1, os.cpu_count() or 1)


def plan(workers: int | None = None, scheduler: str | None = None, *, tasks: int | None = None) -> tuple[str, int | str | None]:
    """What :func:`connect` will do, without doing it: ``("sequential", None)``,
    ``("scheduler", address)`` or ``("local", worker count)``.

    The rules are those of the module docstring (``tasks``: how many independent
    tasks the work has, when the caller knows).  Raises :class:`ValueError` for
    a worker count below 1, an empty address, or both ``workers`` and
    ``scheduler`` given.

    >>> plan(workers=1)
    ('sequential', None)
    >>> plan(workers=3)
    ('local', 3)
    >>> plan(scheduler="tcp://10.0.0.5:8786")
    ('scheduler', 'tcp://10.0.0.5:8786')
    """
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ValueError(f"workers must be a whole number of at least 1, got {workers!r}")
    if scheduler is not None and not scheduler.strip():
        raise ValueError("scheduler must be an address such as tcp://host:8786, got an empty string")
    if workers is not None and scheduler is not None:
        raise ValueError("give either a worker count or a scheduler address, not both (a cluster has its own workers)")
    if workers == 1:
        return ("sequential", None)
    if scheduler is not None:
        return ("scheduler", scheduler.strip())
    if workers is not None:
        return ("local", workers)
    if tasks is not None and tasks < 2:
        return ("sequential", None)
    env = os.environ.get(ENV_SCHEDULER, "").strip()
    if env:
        return ("scheduler", env)
    cores = default_workers()
    return ("sequential", None) if cores == 1 else ("local", cores)


@contextmanager
def connect(
    workers: int | None = None,
    scheduler: str | None = None,
    *,
    tasks: int | None = None,
    dashboard: bool = False,
) -> Iterator[Client | None]:
    """A :class:`distributed.Client` for the block, or ``None`` for the sequential path.

    See the module docstring for the rules (:func:`plan` applies them).  A local
    cluster is closed when the block ends, however it ends; a client of an
    existing cluster is closed, the cluster left running.  ``dashboard`` serves
    a local cluster's dashboard on a free port (an existing cluster's is its own).

    >>> with connect(workers=1) as client:
    ...     print(client)
    None

    Raises :class:`ValueError` as :func:`plan` does, and :class:`ClusterError`
    (one line) when the scheduler does not answer within
    :data:`CONNECT_TIMEOUT` seconds or local workers fail to start.
    """
    kind, arg = plan(workers, scheduler, tasks=tasks)
    if kind == "sequential":
        yield None
        return
    from distributed import Client, LocalCluster  # here, not at import: plan() needs no Dask
    if kind == "scheduler":
        assert isinstance(arg, str)
        try:
            client = Client(arg, timeout=CONNECT_TIMEOUT)
        except (OSError, TimeoutError, ValueError) as exc:
            raise ClusterError(f"cannot reach the Dask scheduler at {arg}: {_first_line(exc)}") from None
        try:
            yield client
        finally:
            client.close()
        return
    assert isinstance(arg, int)
    try:
        cluster = LocalCluster(
            n_workers=arg,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            # The scheduler's HTTP server (health checks, and the dashboard if asked for) on a free port: its
            # default, 8787, may be another cluster's.
            dashboard_address=":0",
            scheduler_kwargs={"dashboard": dashboard},
            silence_logs=logging.ERROR,
        )
    except (OSError, TimeoutError, RuntimeError) as exc:
        raise ClusterError(f"cannot start a local Dask cluster of {arg} workers: {_first_line(exc)}{_main_hint()}") from None
    try:
        client = Client(cluster)
        try:
            yield client
        finally:
            client.close()
    finally:
        cluster.close()


def _main_hint() -> str:
    """Why worker processes may fail to start from a script: each re-imports the script's ``__main__``."""
    import sys

    main = sys.modules.get("__main__")
    if main is None or not hasattr(main, "__file__"):  # the REPL, python -c: nothing to re-import
        return ""
    return ' (from a script, start it under `if __name__ == "__main__":`; worker processes re-import the script)'


def _first_line(exc: BaseException) -> str:
    """An exception's message, on one line (distributed's can run to several)."""
    text = str(exc).strip().splitlines()
    return text[0] if text else type(exc).__name__
