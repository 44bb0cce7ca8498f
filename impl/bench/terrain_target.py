"""Terrain meshing to a maximum error, against pydelatin in the same run: time and peak memory (``persistri bench terrain --max-error``).

Where :mod:`persistri.impl.bench.terrain` compares the two meshers at equal
vertex counts, this compares them at equal *quality*: both refine the same grid
until every sample is within ``max_error`` of the mesh (issue 17's rows: the
Jacksboro DEM to 5 m, a 2,048 × 2,048 synthetic DEM to 1 % of its relief).

* **time** — CPU seconds (``process_time``) of ``Delatin(heights, max_error=e)``
  (pydelatin, C++, float32 heights as it requires) and of
  ``greedy_insertion(heights, max_error=e)`` (every level of detail kept, as by
  default), each the best of its repeats, run one after the other;
* **points** and the **maximum error** of each mesh, recomputed over every grid
  sample by :func:`persistri.impl.terrain.check.mesh_errors`;
* **peak memory** (``peak=True``) — each mesher run once in a fresh Python
  process: the growth of its resident set's high-water mark (``VmHWM``, reset
  through ``/proc/self/clear_refs`` just before the call) over the resident set
  just before it, the grid already loaded.  pydelatin allocates in C++, where
  ``tracemalloc`` cannot see, so both are measured the same way, by the
  operating system.  persistri is measured twice: keeping every level of detail
  (the default) and keeping only the final mesh (``history=False``, what
  pydelatin keeps).  Linux only; elsewhere the figures are absent.
"""

from __future__ import annotations

import gc
import json
import os
import subprocess
import sys
import tempfile
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["TerrainTargetRecord", "PeakMemory", "run_to_error", "peak_memory", "target_table", "relief"]


@dataclass(frozen=True, slots=True)
class PeakMemory:
    """Peak resident memory of one run, in bytes over the process's memory just before it (None if unmeasured)."""

    pydelatin: int | None
    persistri_history: int | None
    persistri_final_only: int | None

    @property
    def ratio(self) -> float:
        """persistri's (final mesh only) over pydelatin's."""
        if not self.pydelatin or self.persistri_final_only is None:
            return float("nan")
        return self.persistri_final_only / self.pydelatin

    @property
    def ratio_history(self) -> float:
        """persistri's (every level kept) over pydelatin's."""
        if not self.pydelatin or self.persistri_history is None:
            return float("nan")
        return self.persistri_history / self.pydelatin


@dataclass(frozen=True, slots=True)
class TerrainTargetRecord:
    """Both meshers refined to ``max_error`` on one grid."""

    grid: str
    shape: tuple[int, int]
    max_error: float
    pydelatin_s: float
    pydelatin_points: int
    pydelatin_error: float
    persistri_s: float
    persistri_points: int
    persistri_error: float
    repeat: int
    peak: PeakMemory | None = None

    @property
    def time_ratio(self) -> float:
        """persistri's time over pydelatin's."""
        return self.persistri_s / self.pydelatin_s if self.pydelatin_s > 0 else float("inf")

    def as_dict(self) -> dict[str, Any]:
        """A JSON-ready dictionary (ratios included)."""
        out = asdict(self)
        out["shape"] = list(self.shape)
        out["time_ratio"] = self.time_ratio
        if self.peak is not None:
            out["peak"]["ratio"] = self.peak.ratio
            out["peak"]["ratio_history"] = self.peak.ratio_history
        return out


def relief(heights: NDArray[np.float64]) -> float:
    """The grid's relief: highest minus lowest height."""
    return float(np.max(heights) - np.min(heights))


def _flip(heights: NDArray[np.float64], vertices: Any) -> NDArray[np.float64]:
    v = np.asarray(vertices, dtype=np.float64).copy()
    v[:, 1] = heights.shape[0] - 1 - v[:, 1]  # pydelatin's y runs up from the last row
    return v


def run_to_error(
    heights: NDArray[np.float64],
    max_error: float,
    *,
    grid_name: str,
    backend: str = "red_black",
    repeat: int = 1,
    peak: bool = False,
) -> TerrainTargetRecord:
    """Time pydelatin and persistri refining ``heights`` to ``max_error`` (module docstring). O(the two runs)."""
    from pydelatin import Delatin

    from persistri.impl.terrain.check import mesh_errors
    from persistri.impl.terrain.greedy import greedy_insertion

    h32 = heights.astype(np.float32)
    best_p = float("inf")
    mesh: Any = None
    for _ in range(max(3, repeat)):
        mesh = None
        gc.collect()
        t0 = time.process_time()
        mesh = Delatin(h32, max_error=max_error)
        best_p = min(best_p, time.process_time() - t0)
    pv = _flip(heights, mesh.vertices)
    p_err, _ = mesh_errors(heights, pv, mesh.triangles)
    p_points = int(pv.shape[0])
    del mesh
    best_o = float("inf")
    tin: Any = None
    for _ in range(repeat):
        tin = None
        gc.collect()
        t0 = time.process_time()
        tin = greedy_insertion(heights, max_error=max_error, backend=backend)
        best_o = min(best_o, time.process_time() - t0)
    o_err, _ = mesh_errors(heights, tin.vertices, tin.triangles)
    o_points = int(tin.n_points)
    del tin
    memory = peak_memory(heights, max_error, backend=backend) if peak else None
    return TerrainTargetRecord(
        grid_name,
        (int(heights.shape[0]), int(heights.shape[1])),
        float(max_error),
        best_p,
        p_points,
        float(np.nanmax(p_err)),
        best_o,
        o_points,
        float(np.nanmax(o_err)),
        repeat,
        memory,
    )


_PROBE = r"""
import gc, json, re, sys
import numpy as np
which, path, max_error, backend = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
heights = np.load(path)
if which == "pydelatin":
    from pydelatin import Delatin
    heights = heights.astype(np.float32)
else:
    from persistri.impl.terrain.greedy import greedy_insertion
def status():
    text = open("/proc/self/status").read()
    return [int(re.search(key + r":\s+(\d+) kB", text).group(1)) * 1024 for key in ("VmRSS", "VmHWM")]
gc.collect()
with open("/proc/self/clear_refs", "w") as f:
    f.write("5")
before, _ = status()
if which == "pydelatin":
    out = Delatin(heights, max_error=max_error)
else:
    out = greedy_insertion(heights, max_error=max_error, backend=backend, history=(which == "history"))
_, peak = status()
print(json.dumps({"peak": peak - before}))
"""


def _probe(which: str, path: Path, max_error: float, backend: str) -> int | None:
    done = subprocess.run(
        [sys.executable, "-c", _PROBE, which, str(path), repr(max_error), backend],
        capture_output=True,
        text=True,
        env=dict(os.environ),
    )
    if done.returncode != 0:
        return None
    try:
        return int(json.loads(done.stdout.strip().splitlines()[-1])["peak"])
    except (ValueError, KeyError, IndexError):
        return None


def peak_memory(heights: NDArray[np.float64], max_error: float, *, backend: str = "red_black") -> PeakMemory:
    """The peak memory of each mesher refining ``heights`` to ``max_error``, each in a fresh process (module docstring).

    Figures are None where the operating system does not report them (not Linux).
    """
    if not Path("/proc/self/clear_refs").exists():
        return PeakMemory(None, None, None)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "heights.npy"
        np.save(path, np.ascontiguousarray(heights, dtype=np.float64))
        return PeakMemory(
            _probe("pydelatin", path, max_error, backend),
            _probe("history", path, max_error, backend),
            _probe("final", path, max_error, backend),
        )


def _mb(n: int | None) -> str:
    return "—" if n is None else f"{n / 2**20:,.1f} MB"


def target_table(records: list[TerrainTargetRecord]) -> Any:
    """The records as a rich renderable: one row per grid and error, then the peak memory lines."""
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    from persistri.impl.bench.delaunay import terrain_build

    table = Table(title=f"Greedy insertion to a maximum error, against pydelatin (persistri {terrain_build()})")
    for name in ("grid", "max error", "pydelatin s", "points", "err", "persistri s", "points", "err", "time ×"):
        table.add_column(name, justify="right")
    parts: list[Any] = [table]
    for r in records:
        table.add_row(
            f"{r.grid} {r.shape[0]}×{r.shape[1]}",
            f"{r.max_error:.4g}",
            f"{r.pydelatin_s:.3f}",
            f"{r.pydelatin_points:,}",
            f"{r.pydelatin_error:.4g}",
            f"{r.persistri_s:.2f}",
            f"{r.persistri_points:,}",
            f"{r.persistri_error:.4g}",
            f"{r.time_ratio:,.1f}×",
        )
    for r in records:
        m = r.peak
        if m is not None:
            parts.append(
                Text(
                    f"peak memory, {r.grid} to {r.max_error:.4g}: pydelatin {_mb(m.pydelatin)}; persistri final mesh only "
                    f"{_mb(m.persistri_final_only)} ({m.ratio:.2f}×), every level kept {_mb(m.persistri_history)} "
                    f"({m.ratio_history:.2f}×)"
                )
            )
    parts.append(
        Text(
            "times: CPU seconds, best of the repeats (pydelatin at least 3), persistri keeping every level of detail; "
            "err: the maximum vertical error recomputed over every sample of the float64 grid (pydelatin meshes "
            "float32 heights); peak memory: growth of the resident set's high-water mark in a fresh process, the grid "
            "already loaded."
        )
    )
    return Group(*parts)
