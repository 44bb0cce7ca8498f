"""Several futures of one version, run as Dask tasks from the shared version (paper §1's "multiple futures").

A persistent version is a value: nothing done to it later changes it.  So the
futures explored from one version — the refinements of one constrained
Delaunay triangulation under several quality bounds, the extensions of one
hull by several point sets — are independent computations on one shared input,
the case the paper's introduction has in mind when it says such structures
"parallelize without special provision".  :func:`futures` runs them as tasks:
the version is pickled **once** (its shared structure once), sent to the
cluster once, and each task starts from its own copy of it; the results come
back as full persistent values (their histories included), equal to what the
same calls give one after another in this process — the same arrays, the same
counts (tested).

Each task unpickles the version afresh, so two tasks on one worker never share
anything — not even the append-only point set a mesh run draws its Steiner
points from (:mod:`persistri.impl.mesh.api`), whose indices then depend only
on the future itself.  Versions and results travel pickled by this module with
Python's cyclic garbage collector paused while they are rebuilt: a persistent
structure is millions of small acyclic objects, and the collector would walk
them again and again (unpickling a 16,000-triangle mesh with its history takes
8 s with it, 0.3 s without).

Cost: one pickling of the version, one unpickling per task, the futures' own
work spread over the workers, and one pickling and unpickling of each result.
"""

from __future__ import annotations

import pickle
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any, TypeVar

from persistri.impl.collector import collector_paused
from persistri.impl.scale.tasks import run, task

if TYPE_CHECKING:
    from distributed import Client

    from persistri.impl.hull.api import Hull
    from persistri.impl.mesh.api import QualityMesh

__all__ = ["futures", "refine_many", "extend_many"]

V = TypeVar("V")
R = TypeVar("R")


def _loads(blob: bytes) -> Any:
    with collector_paused(promote=False):
        return pickle.loads(blob)


def _future(fn: Callable[..., Any], version: bytes, kwargs: Mapping[str, Any]) -> bytes:
    """One task: ``fn(the version, **kwargs)``, from a fresh copy of the pickled version; the result pickled."""
    with collector_paused(promote=False):
        result = fn(_loads(version), **kwargs)
        return pickle.dumps(result, protocol=pickle.HIGHEST_PROTOCOL)


def futures(
    fn: Callable[..., R],
    version: Any,
    arguments: Sequence[Mapping[str, Any]],
    *,
    client: Client | None = None,
    progress: bool = False,
) -> list[R]:
    """``[fn(version, **a) for a in arguments]``, each call a task on ``client``'s cluster (None: in this process).

    ``fn`` must be a module-level function (workers import it by name) that leaves
    ``version`` unchanged — every persistri operation on a version does.  On a
    cluster ``version`` is pickled once and shared; the results are equal to the
    in-process calls'.  Raises what ``fn`` raises (the first failing future's
    error), or :class:`~persistri.impl.scale.cluster.ClusterError` when workers
    keep dying.
    """
    if client is None:
        return [fn(version, **a) for a in arguments]
    with collector_paused(promote=False):
        blob = pickle.dumps(version, protocol=pickle.HIGHEST_PROTOCOL)
    jobs = [task(_future, fn, blob, dict(a)) for a in arguments]
    return [_loads(b) for b in run(client, jobs, progress=progress, title="futures")]


def _refine_options() -> frozenset[str]:
    """``refine``'s keyword options (its signature, so that new ones need no change here), less ``progress``."""
    import inspect

    from persistri.impl.mesh.api import refine

    params = inspect.signature(refine).parameters.values()
    return frozenset(p.name for p in params if p.kind is inspect.Parameter.KEYWORD_ONLY and p.name != "progress")


def refine_many(
    mesh: QualityMesh,
    bounds: Sequence[Mapping[str, Any]],
    *,
    client: Client | None = None,
    progress: bool = False,
) -> list[QualityMesh]:
    """The refinements of ``mesh`` under each of ``bounds`` — :func:`~persistri.impl.mesh.api.refine`'s keyword
    arguments, e.g. ``[dict(min_angle=30), dict(min_angle=20, max_area=0.01)]`` — as futures of its last version.

    >>> from persistri.impl.mesh.api import triangulate
    >>> from persistri.impl.mesh.domain import as_pslg
    >>> cdt = triangulate(as_pslg([[0, 0], [4, 0], [4, 4], [0, 4]], [[0, 1], [1, 2], [2, 3], [3, 0]]))
    >>> coarse, fine = refine_many(cdt, [dict(min_angle=30, max_area=4.0), dict(min_angle=30, max_area=0.5)])
    >>> coarse.history[0] is fine.history[0] is cdt.complex, len(coarse.triangles) < len(fine.triangles)
    (True, True)

    (On a cluster each result's history starts at its own copy of the version, equal to
    ``mesh.complex``.)  Every bound needs ``min_angle``; an unknown key is a :class:`TypeError`
    naming it, before anything runs.  Cost: :func:`futures`.
    """
    from persistri.impl.mesh.api import QualityMesh, refine

    if not isinstance(mesh, QualityMesh):
        raise TypeError(f"refine_many takes a QualityMesh (from triangulate), not {type(mesh).__name__}")
    options = _refine_options()
    for k, b in enumerate(bounds):
        unknown = sorted(set(b) - options)
        if unknown:
            raise TypeError(f"bounds[{k}]: unknown refine option {unknown[0]!r}; known: {', '.join(sorted(options))}")
        if "min_angle" not in b:
            raise TypeError(f"bounds[{k}]: min_angle is required (0 for none)")
    return futures(refine, mesh, bounds, client=client, progress=progress)


def extend_many(
    hull: Hull,
    point_sets: Sequence[Any],
    *,
    client: Client | None = None,
    progress: bool = False,
) -> list[Hull]:
    """The hulls of ``hull``'s points with each of ``point_sets`` added
    (:func:`~persistri.impl.hull.extend.extend_hull`), as futures of ``hull``'s last version.

    Cost: :func:`futures`; each extension's own is ``extend_hull``'s.
    """
    from persistri.impl.hull.extend import extend_hull

    return futures(extend_hull, hull, [{"new_points": p} for p in point_sets], client=client, progress=progress)
