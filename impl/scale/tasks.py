"""A small task graph that runs on a Dask cluster or, unchanged, in this process.

The parallel algorithms of :mod:`persistri.impl.scale` are written once, as a
graph of :class:`Task` calls of plain module-level functions (picklable, so a
worker can import them); :func:`run` executes the graph:

* with a :class:`distributed.Client` — each task becomes a ``dask.delayed``
  call, the targets are submitted together (the scheduler runs independent
  tasks on all workers at once, sends each result only where it is needed, and
  releases it when no task needs it any more), and the caller waits on Dask's
  own progress diagnostics: the scheduler's progress feed drives a rich bar on
  stderr;
* with ``None`` — the sequential path: each task called in turn in this
  process, no Dask scheduler at all (a Dask array's blocks are computed in
  place).

Arrays and byte strings (pickled versions) passed as arguments are sent to the
cluster once each (:meth:`distributed.Client.scatter`), however many tasks read them.

**Failures.**  A worker that dies mid-task (killed, out of memory) does not
lose the run: the scheduler reassigns its tasks to the other workers (a local
cluster also restarts the dead one), and since the tasks are pure functions of
their arguments, recomputing them gives the same results.  A task that kills
``distributed.scheduler.allowed-failures + 1`` workers (4 by default) is given
up on: :func:`run` then raises :class:`~persistri.impl.scale.cluster.ClusterError`
naming it — one clear error, never a partial result.  An exception raised by a
task's function is re-raised here as itself.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from persistri.impl.scale.cluster import ClusterError

if TYPE_CHECKING:
    from distributed import Client

__all__ = ["Task", "run", "task"]

_SCATTER_BYTES = 1 << 16
"""Arrays and byte strings at least this large are scattered to the cluster rather than written into the task graph."""


@dataclass(frozen=True, eq=False)
class Task:
    """The call ``fn(*args)``, where an argument that is itself a :class:`Task` stands for its result."""

    fn: Callable[..., Any]
    args: tuple[Any, ...]


def task(fn: Callable[..., Any], *args: Any) -> Task:
    """The :class:`Task` ``fn(*args)`` (``fn`` a module-level function, so that workers can import it)."""
    return Task(fn, args)


def run(
    client: Client | None,
    targets: Sequence[Task],
    *,
    progress: bool = False,
    title: str = "tasks",
) -> list[Any]:
    """The results of ``targets`` (in order), computed on ``client``'s cluster or, for None, in this process.

    ``progress`` — a transient rich bar on stderr titled ``title`` (drawn only on
    a terminal), fed by the scheduler's progress diagnostics (tasks done of all
    tasks the targets need); in-process, by the tasks done.  Each task is run once
    however many tasks use its result.  Raises what a task raises, or
    :class:`~persistri.impl.scale.cluster.ClusterError` when a task is given up on
    after killing workers.
    """
    if client is None:
        return _run_here(targets, progress, title)
    return _run_on(client, targets, progress, title)


def _count(targets: Sequence[Task]) -> int:
    seen: set[int] = set()
    stack = list(targets)
    while stack:
        t = stack.pop()
        if id(t) in seen:
            continue
        seen.add(id(t))
        stack.extend(a for a in t.args if isinstance(a, Task))
    return len(seen)


def _run_here(targets: Sequence[Task], progress: bool, title: str) -> list[Any]:
    bar = _Bar(title, _count(targets)) if progress else None
    done: dict[int, Any] = {}

    def value(x: Any) -> Any:
        if isinstance(x, Task):
            return done[id(x)]
        if type(x).__module__.startswith("dask"):  # a Dask array's block: computed here, no scheduler
            return x.compute(scheduler="synchronous")
        return x

    # Post-order without recursion: a task runs once its Task arguments have.
    try:
        for t in targets:
            stack: list[tuple[Task, bool]] = [(t, False)]
            while stack:
                node, ready = stack.pop()
                if id(node) in done:
                    continue
                if ready:
                    done[id(node)] = node.fn(*(value(a) for a in node.args))
                    if bar is not None:
                        bar.update(1, None)
                    continue
                stack.append((node, True))
                stack.extend((a, False) for a in node.args if isinstance(a, Task) and id(a) not in done)
        return [done[id(t)] for t in targets]
    finally:
        if bar is not None:
            bar.close()


def _run_on(client: Client, targets: Sequence[Task], progress: bool, title: str) -> list[Any]:
    from dask.delayed import delayed as dask_delayed
    from distributed.scheduler import KilledWorker

    made: dict[int, Any] = {}
    scattered: dict[int, Any] = {}

    def arg(x: Any) -> Any:
        if isinstance(x, Task):
            return made[id(x)]
        if (isinstance(x, np.ndarray) and x.nbytes >= _SCATTER_BYTES) or (isinstance(x, bytes) and len(x) >= _SCATTER_BYTES):
            if id(x) not in scattered:
                scattered[id(x)] = client.scatter(x, hash=False)
            return scattered[id(x)]
        return x

    def build(t: Task) -> Any:
        stack: list[tuple[Task, bool]] = [(t, False)]
        while stack:
            node, ready = stack.pop()
            if id(node) in made:
                continue
            if ready:
                made[id(node)] = dask_delayed(node.fn, pure=False)(*(arg(a) for a in node.args))
                continue
            stack.append((node, True))
            stack.extend((a, False) for a in node.args if isinstance(a, Task) and id(a) not in made)
        return made[id(t)]

    delayed = [build(t) for t in targets]
    futures = client.compute(delayed)
    try:
        if progress:
            _feed_bar(client, futures, title)
        return list(client.gather(futures))
    except KilledWorker as exc:
        raise ClusterError(
            f"task {exc.task!r} was given up on: the {exc.allowed_failures + 1} workers that ran it died "
            "(out of memory, or killed); no result was made"
        ) from None
    finally:
        for f in futures:
            f.release()


class _Bar:
    """A transient rich bar on stderr (nothing off a terminal), advanced to an absolute count."""

    def __init__(self, title: str, total: int | None) -> None:
        from rich.console import Console
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

        console = Console(stderr=True)
        self._p = Progress(
            TextColumn(title),
            BarColumn(),
            MofNCompleteColumn(),
            TimeElapsedColumn(),
            transient=True,
            console=console,
            disable=not console.is_terminal,
        )
        self._task = self._p.add_task(title, total=total)
        self._p.start()

    def update(self, advance: int, total: int | None) -> None:
        if total is not None:
            self._p.update(self._task, total=total)
        self._p.advance(self._task, advance)

    def set(self, completed: int, total: int) -> None:
        self._p.update(self._task, completed=completed, total=total)

    def close(self) -> None:
        self._p.stop()


def _feed_bar(client: Client, futures: Sequence[Any], title: str) -> None:
    """Wait for ``futures`` while the scheduler's progress feed (Dask's diagnostics) draws :class:`_Bar`."""
    from distributed.diagnostics.progressbar import TextProgressBar

    bar = _Bar(title, None)

    class _RichFeed(TextProgressBar):
        def __init__(self, keys: Sequence[Any], scheduler: str) -> None:
            TextProgressBar.__init__(self, keys, scheduler=scheduler, interval="200ms")  # listens until they are done

        def _draw_bar(self, remaining: int, all: int, **kwargs: Any) -> None:  # noqa: A002 - dask's name
            bar.set(all - remaining, all)

        def _draw_stop(self, **kwargs: Any) -> None:
            pass

    scheduler = client.scheduler
    if scheduler is None:
        raise ClusterError("the Dask client is not connected to a scheduler")
    try:
        _RichFeed(futures, str(scheduler.address))
    finally:
        bar.close()
