"""Scale-out on Dask: the same exact algorithms over chunks, on a local or remote cluster (``persistri[dask]``).

* :mod:`persistri.impl.scale.cluster` — where the work runs: the one place that
  turns ``--workers``/``--scheduler`` (and ``PERSISTRI_SCHEDULER``) into a
  ``distributed.Client`` or the sequential path;
* :mod:`persistri.impl.scale.hull` — the exact convex hull of points in chunks
  (arrays, Dask arrays, memory-mapped ``.npy``, Zarr, directories of ``.npy``):
  chunk hulls on workers, merged by a tree reduction, equal to the one-process hull;
* :mod:`persistri.impl.scale.extend` — points added to such a hull, resuming its final
  merge (``persistri.ConvexHull.add_points`` on chunked input);
* :mod:`persistri.impl.scale.futures` — several futures of one version (quality
  refinements of one mesh) run as tasks from the shared version.

Nothing outside this package imports Dask: ``import persistri`` and every other
``persistri.impl`` module stay free of it (tested).  This file itself does not
either, so that callers can ask :func:`dask_missing` first.
"""

from __future__ import annotations

from importlib.util import find_spec

__all__ = ["dask_missing"]


def dask_missing() -> str | None:
    """None when Dask's parallel side can run here, else why not (one line: what to install)."""
    missing = [name for name in ("dask", "distributed") if find_spec(name) is None]
    if not missing:
        return None
    return f"{' and '.join(missing)} not installed: the parallel path needs persistri[dask] (pip install 'persistri[dask]')"
