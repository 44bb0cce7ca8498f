"""The predicate benchmark: what an exact orientation test costs, by stage.

Measured on ``n`` points uniform in the unit cube (a fixed seed), best of
``repeat`` runs, the cyclic garbage collector off while timing:

* ``scalar_us`` — one :meth:`~persistri.impl.geometry.predicates.Predicates3.orient3d`
  call on random distinct indices, decided by the float filter (the common case);
* ``batch_us_per_point`` — :meth:`~persistri.impl.geometry.predicates.Predicates3.orient3d_batch`
  over all ``n - 3`` other points against one plane, per point;
* ``exact_us`` — one test decided by exact integer arithmetic (the filter's
  fallback: a nonzero determinant on integers);
* ``sos_us`` — one test on an exactly degenerate quadruple (filter, exact zero,
  then Simulation of Simplicity), on a 10×10×10 integer grid;
* ``exact_batch_us_per_point`` — the vectorised exact fallback of a batch whose
  every entry the filter cannot decide (grid points on one plane, true signs).

Run ``python -m persistri.impl.bench.predicates [n]``; figures are CPU time
of this process and depend on the machine (and, through shared caches, its load).
"""

from __future__ import annotations

import gc
import itertools
import sys
import time
from collections.abc import Callable

import numpy as np

from persistri.impl.geometry.predicates import Predicates3

__all__ = ["run_predicate_bench", "main"]


def _best(run: Callable[[], object], repeat: int) -> float:
    """The best CPU seconds (this process) of ``repeat`` calls of ``run``, collector off.

    CPU time rather than wall-clock time, so that other processes on a shared
    machine inflate the figures less (caches are still shared).
    """
    enabled = gc.isenabled()
    gc.disable()
    try:
        best = float("inf")
        for _ in range(repeat):
            t = time.process_time()
            run()
            best = min(best, time.process_time() - t)
        return best
    finally:
        if enabled:
            gc.enable()


def run_predicate_bench(n: int = 100_000, *, seed: int = 0, repeat: int = 5, calls: int = 20_000) -> dict[str, float]:
    """The figures described in the module docstring, in microseconds."""
    rng = np.random.default_rng(seed)
    pts = rng.random((n, 3))
    p = Predicates3(pts)
    quads = [tuple(int(v) for v in rng.choice(n, 4, replace=False)) for _ in range(calls)]
    orient3d = p.orient3d

    def scalar() -> None:
        for a, b, c, d in quads:
            orient3d(a, b, c, d)

    qs = np.arange(3, n)
    exact = p._orient3d_exact  # the fallback alone, on the same quadruples

    def exact_only() -> None:
        p._ints.clear()  # include the conversion of each point to integers
        for a, b, c, d in quads[:2000]:
            exact(a, b, c, d, True)

    grid = np.array(list(itertools.product(range(10), repeat=3)), dtype=float)
    g = Predicates3(grid)
    # Rows 0, 1, 10 span the plane x = 0, which holds 100 grid points.
    flat = [q for q in range(100) if q not in (0, 1, 10)]

    def sos() -> None:
        for q in flat:
            g.orient3d(0, 1, 10, q)

    plane = np.array(flat * 40, dtype=np.intp)
    return {
        "n": float(n),
        "scalar_us": _best(scalar, repeat) / len(quads) * 1e6,
        "batch_us_per_point": _best(lambda: p.orient3d_batch(0, 1, 2, qs), repeat) / qs.size * 1e6,
        "exact_us": _best(exact_only, repeat) / 2000 * 1e6,
        "sos_us": _best(sos, repeat) / len(flat) * 1e6,
        "exact_batch_us_per_point": _best(lambda: g.orient3d_sign_batch(0, 1, 10, plane), repeat) / plane.size * 1e6,
    }


def main(argv: list[str] | None = None) -> None:
    """Print the figures for ``n`` points (first argument, default 100000)."""
    args = sys.argv[1:] if argv is None else argv
    n = int(float(args[0])) if args else 100_000
    for name, value in run_predicate_bench(n).items():
        print(f"{name:28s} {value:10.3f}")


if __name__ == "__main__":
    main()
