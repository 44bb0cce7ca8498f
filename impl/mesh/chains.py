"""Input segments as chains of mesh edges, found exactly (for :func:`~persistri.impl.mesh.verify.verify_mesh`).

A mesh conforms to a segment ``u → v`` when a path of mesh edges runs from ``u``
to ``v`` whose vertices advance along the segment and lie on it.
:func:`segment_chains` walks it: from the current vertex, the next is the
neighbour of least progress ``(w − u) · (v − u)`` beyond the current one (and not
beyond ``v``) that lies on the segment (depth first: a walk that gets stuck backs
up and tries the next neighbour) — exactly (zero cross product), or within
its *tolerance box* (split points only: an input vertex is on a segment exactly or
not at all): the closed box of half-width ``rounding_ulps`` units in the
last place of the largest magnitude among its and the segment's coordinates,
axis by axis, which the closed segment must meet (:func:`in_tolerance_box`, exact
parametric clipping in rationals).  The second kind are the split points a
floating-point mesher such as Triangle rounds off the segment; they are counted
apart.  Every decision is on exact integers (the checker's scaled coordinates)
or rationals.  O(Σ degree along the chains), or more where a walk backs up (at
most a few times the number of edges per segment).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np
from numpy.typing import NDArray

__all__ = ["Chains", "segment_chains", "in_tolerance_box"]


@dataclass
class Chains:
    """The chains of mesh edges along the input segments.

    * ``paths`` — per segment, its mesh vertices from ``u`` to ``v``, or None (an end is
      not a mesh vertex, or the walk stopped);
    * ``on_segments`` — per mesh vertex on some chain, the segments it is on;
    * ``stuck`` — ``(segment, mesh vertex, edges walked)`` where a walk stopped;
    * ``rounded`` — ``(segment, vertices)`` for the chains using vertices off the segment
      within their tolerance boxes;
    * ``split_vertices`` / ``rounded_split_vertices`` — how many distinct interior chain
      vertices lie exactly on their segment, and how many only within tolerance.
    """

    paths: list[list[int] | None] = field(default_factory=list)
    on_segments: dict[int, list[int]] = field(default_factory=dict)
    stuck: list[tuple[int, int, int]] = field(default_factory=list)
    rounded: list[tuple[int, list[int]]] = field(default_factory=list)
    split_vertices: int = 0
    rounded_split_vertices: int = 0


def segment_chains(
    pts: NDArray[np.float64],
    xs: list[int],
    ys: list[int],
    nbr: NDArray[np.intp],
    nbr_ptr: NDArray[np.intp],
    segments: NDArray[np.intp],
    mesh_of: NDArray[np.intp],
    rounding_ulps: float,
) -> Chains:
    """Walk every segment's chain (module docstring).

    ``xs``, ``ys``: the mesh vertices' exact scaled integer coordinates; ``pts`` their
    doubles; the neighbours of mesh vertex ``w`` are ``nbr[nbr_ptr[w] : nbr_ptr[w + 1]]``;
    ``mesh_of[i]`` is the mesh vertex of input vertex ``i`` (-1 if none).
    """
    out = Chains()
    # Only split points may be off their segment within tolerance: an input vertex off it is off it (exactly).
    is_input = np.zeros(len(xs), dtype=bool)
    is_input[mesh_of[mesh_of >= 0]] = True
    exact_seen: set[int] = set()
    rounded_seen: set[int] = set()
    for s in range(segments.shape[0]):
        u, v = (int(mesh_of[w]) for w in segments[s])
        if u < 0 or v < 0:
            out.paths.append(None)
            continue
        dx, dy = xs[v] - xs[u], ys[v] - ys[u]
        length2 = dx * dx + dy * dy

        def steps(cur: int) -> list[tuple[int, int, bool]]:
            """The neighbours of ``cur`` that may come next on the chain, least progress first: ``(progress, w, rounded)``."""
            cur_t = (xs[cur] - xs[u]) * dx + (ys[cur] - ys[u]) * dy
            found: list[tuple[int, int, bool]] = []
            for w in nbr[nbr_ptr[cur] : nbr_ptr[cur + 1]].tolist():
                t = (xs[w] - xs[u]) * dx + (ys[w] - ys[u]) * dy
                if t <= cur_t or t > length2:
                    continue
                exact = w == v or dx * (ys[w] - ys[u]) == dy * (xs[w] - xs[u])
                if not exact and (is_input[w] or not in_tolerance_box(pts[w], pts[u], pts[v], rounding_ulps)):
                    continue
                found.append((t, w, not exact))
            return sorted(found)

        # Depth first, least progress first: near a second segment within an ulp of this one (two segments at a
        # tiny angle), a vertex of the other can look like the next one here; the walk then backs up.
        path, flags = [u], [False]
        pending = [steps(u)]
        budget = 4 * (len(nbr) + 1)
        cur = u
        furthest = (0, u)  # where a failed walk got furthest: (edges, vertex)
        while cur != v and pending and budget > 0:
            budget -= 1
            if not pending[-1]:
                pending.pop()
                path.pop()
                flags.pop()
                cur = path[-1] if path else u
                continue
            _, w, rounded_w = pending[-1].pop(0)
            path.append(w)
            flags.append(rounded_w)
            pending.append(steps(w) if w != v else [])
            cur = w
            furthest = max(furthest, (len(path) - 1, w))
        if cur != v:
            out.stuck.append((s, furthest[1], furthest[0]))
            out.paths.append(None)
            continue
        rounded = [w for w, f in zip(path, flags) if f]
        out.paths.append(path)
        for w in path:
            out.on_segments.setdefault(w, []).append(s)
        exact_seen.update(w for w in path[1:-1] if w not in rounded)
        rounded_seen.update(rounded)
        if rounded:
            out.rounded.append((s, rounded))
    out.split_vertices = len(exact_seen)
    out.rounded_split_vertices = len(rounded_seen)
    return out


def in_tolerance_box(w: NDArray[np.float64], u: NDArray[np.float64], v: NDArray[np.float64], ulps: float) -> bool:
    """Whether the closed segment ``u–v`` meets the closed tolerance box of ``w`` (module docstring). Exact.

    ``ulps = 0.5`` gives the closed rounding cell of ``w``: the reals that round to
    it to nearest, ties either way.
    """
    lower, upper = Fraction(0), Fraction(1)
    for axis in (0, 1):
        a, b, c = float(u[axis]), float(v[axis]), float(w[axis])
        h = Fraction(ulps) * Fraction(math.ulp(max(abs(a), abs(b), abs(c))))
        lo, hi = Fraction(c) - h, Fraction(c) + h
        fa, d = Fraction(a), Fraction(b) - Fraction(a)
        if d == 0:
            if not lo <= fa <= hi:
                return False
            continue
        t1, t2 = (lo - fa) / d, (hi - fa) / d
        lower, upper = max(lower, min(t1, t2)), min(upper, max(t1, t2))
    return lower <= upper
