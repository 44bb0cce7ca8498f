"""The state of one run of Ruppert's refinement: its work lists, where it stands, and how it moves (paper §1).

:class:`~persistri.impl.mesh.ruppert.Refiner` (the algorithm's steps and loop) is a
:class:`RefinerState`: the run's

* **work lists** — the encroached subsegments to split (first in, first out) and
  the bad triangles, in Triangle's queue: a first-in-first-out queue per bucket of
  the squared shortest edge's binary exponent, and a heap of the buckets that
  have one (shortest edges first; docs/meshing.md, "The order of the work");
* **judging** — each new domain triangle is assessed once, when it is made
  (:class:`~persistri.impl.mesh.quality_filter.QualityTests`): queued if bad, recorded if
  exempt at a small input angle (:class:`~persistri.impl.mesh.input_angles.InputAngles`),
  and the subsegments its apex encroaches queued;
* **position** — the history index of the version it stands at, the ids of the
  triangles gone from it for good, and its edge index
  (:mod:`~persistri.impl.mesh.edges`);
* **moving on** — :meth:`RefinerState._adopt` takes a step: its removed
  triangles are dead, the index follows, its new triangles are judged.

Costs: O(1) per triangle judged (plus O(lg buckets) for a bucket that was
empty) and per triangle a step removes or makes.
"""

from __future__ import annotations

import heapq
import math
from collections import deque
from fractions import Fraction

from persistri.impl.complex.vertex import Vertex
from persistri.impl.geometry.growing import ERRBOUND_DOT
from persistri.impl.mesh.cdt import SegmentGeometry
from persistri.impl.mesh.edges import EdgeIndex
from persistri.impl.mesh.input_angles import InputAngles
from persistri.impl.mesh.quality import AngleBound
from persistri.impl.mesh.quality_filter import BadShape, QualityTests
from persistri.impl.mesh.record import Counts, DropLog
from persistri.impl.mesh.triangulation import EXTERIOR, Constraint, Insertion, MeshDatum, MeshTriangulation, Tri

__all__ = ["Bad", "RefinerState"]

Bad = tuple[int, int, Tri, MeshDatum, int, int, int]
"""A queued bad triangle: ``(bucket, sequence, triangle, datum, p, q, r)`` with ``pq`` its shortest edge."""


class RefinerState:
    """What one refinement run holds and how it moves from version to version (module docstring); the arguments
    are :class:`~persistri.impl.mesh.ruppert.Refiner`'s."""

    def __init__(
        self,
        T: MeshTriangulation,
        geo: SegmentGeometry,
        bound: AngleBound,
        max_area: Fraction | None,
        region_area: dict[int, Fraction],
        offconstant: float,
        lens: bool = True,
        exact_segments: bool = False,
    ) -> None:
        self.T = T
        self.P = T.pred
        self.S = T.S
        self.geo = geo
        self.bound = bound
        self.max_area = max_area
        self.region_area = region_area
        self.offconstant = offconstant
        self.lens = lens
        self.exact_segments = exact_segments
        self.tests = QualityTests(T.pred, bound, max_area, region_area, lens)
        self.counts = Counts()
        # The bad triangles: a FIFO queue per bucket, and a heap of the buckets that have one (Triangle's queue).
        self._queues: dict[int, deque[Bad]] = {}
        self._buckets: list[int] = []
        self._seq = 0
        self._segs: deque[Constraint] = deque()
        self._exempt: set[int] = set()
        self.angles = InputAngles(T.pred, geo)
        self._dead: set[int] = set()
        self.log = DropLog()
        self._version = 0  # the history index of the version the run stands at
        self._edges: EdgeIndex = {}  # the triangles of that version by directed edge (persistri.impl.mesh.edges)
        # (segment, vertex) pairs found clear of the segment's tolerance band (precision.crowded_apex): the answer
        # depends on the segment and the point alone, and an apex is often beside the next subsegment split too.
        self._clear_of_band: set[tuple[int, int]] = set()

    # -- the queue -----------------------------------------------------------------------------

    def _push_bad(self, t: Tri, d: MeshDatum, p: int, q: int, r: int, edge2: float) -> None:
        """Queue the bad triangle ``t`` in the bucket of its squared shortest edge ``edge2`` (its binary exponent)."""
        bucket = math.frexp(edge2)[1] if 0.0 < edge2 < math.inf else 0
        self._seq += 1
        self._enqueue((bucket, self._seq, t, d, p, q, r))

    def _enqueue(self, bad: Bad) -> None:
        """Queue ``bad`` last in its bucket. O(1), plus O(lg buckets) for a bucket that was empty."""
        queue = self._queues.get(bad[0])
        if queue is None:
            queue = self._queues[bad[0]] = deque()
            heapq.heappush(self._buckets, bad[0])
        queue.append(bad)

    def _judge(self, t: Tri, d: MeshDatum) -> None:
        """Queue the domain triangle ``t`` if it must be split; record it if it is exempt."""
        found = self.tests.assess(t[0], t[1], t[2], d[1])
        if found is not None:
            self._judge_bad(t, d, found)

    def _judge_bad(self, t: Tri, d: MeshDatum, found: BadShape) -> None:
        """:meth:`_judge` for a triangle whose assessment ``found`` says it is bad: queue it, or record it exempt."""
        p, q, r, edge2, good = found
        if not good and self.angles.exempt_edge(p, q) and not self.tests.area_bad(t[0], t[1], t[2], d[1]):
            self._exempt.add(d[0])
            return
        self._push_bad(t, d, p, q, r, edge2)

    def _adopt(self, step: Insertion, apexes: bool = True) -> None:
        """The run takes ``step``: its removed triangles are gone for good, the edge index follows, and its new
        triangles are examined — the bad ones queued, the exempt ones recorded (:meth:`~persistri.impl.mesh.quality_filter.QualityTests.assess_all`), and, unless ``apexes`` is False, the
        subsegments their apexes encroach queued (False for a bad triangle's split: its new subsegment edges all have
        the new point as apex, already found to encroach none of them).  ``step.version`` is not read (Chew's
        deletions make none of their own). O(k)."""
        dead = self._dead
        edges = self._edges
        for (a, b, c), d in step.removed:
            dead.add(d[0])
            del edges[(a, b)]
            del edges[(b, c)]
            del edges[(c, a)]
        created = step.created
        for (a, b, c), d in created:
            edges[(a, b)] = (c, d)
            edges[(b, c)] = (a, d)
            edges[(c, a)] = (b, d)
        # self._judge(t, d) for each new domain triangle: one call for all of them; the bad ones, in their order.
        bad = self.tests.assess_all(created)
        if bad:
            exempt_edge = self.angles.exempt_edge
            on_segment = self.geo.on_segment  # exempt_edge is False unless both ends are split points: asked first
            queues = self._queues
            for t, d, (p, q, r, edge2, good) in bad:
                # self._judge_bad(t, d, found) and self._push_bad, inlined.
                if (
                    not good
                    and p in on_segment
                    and q in on_segment
                    and exempt_edge(p, q)
                    and not self.tests.area_bad(t[0], t[1], t[2], d[1])
                ):
                    self._exempt.add(d[0])
                else:
                    bucket = math.frexp(edge2)[1] if 0.0 < edge2 < math.inf else 0
                    self._seq += 1
                    queue = queues.get(bucket)
                    if queue is None:
                        queue = queues[bucket] = deque()
                        heapq.heappush(self._buckets, bucket)
                    queue.append((bucket, self._seq, t, d, p, q, r))
        if apexes:
            # The queue of bad triangles and that of subsegments are apart: judging all new triangles first and then
            # their apexes queues the same entries in the same order as one pass would.
            encroaches = self.tests.encroaches
            rows = self.tests.rows
            for (a, b, c), d in created:
                if d[2] and d[1] != EXTERIOR:
                    for lo, hi, s in d[2]:
                        k = a if a != lo and a != hi else b if b != lo and b != hi else c
                        # encroaches(lo, hi, k)'s first test, inlined (its operations: dot_terms): k clearly outside
                        # the diametral circle encroaches neither it nor the lens; anything else is asked of encroaches.
                        ux, uy = rows[lo]
                        wx, wy = rows[hi]
                        kx, ky = rows[k]
                        left = (ux - kx) * (wx - kx)
                        right = (uy - ky) * (wy - ky)
                        if left + right > ERRBOUND_DOT * (abs(left) + abs(right)):
                            continue
                        if encroaches(lo, hi, k):
                            self._segs.append((lo, hi, s))

    def _beside(self, u: Vertex, w: Vertex) -> tuple[Tri, MeshDatum] | None:
        """The triangle ``(u, w, x)`` of the current version holding the directed edge ``(u, w)``, or None. O(1)."""
        rec = self._edges.get((u, w))
        return None if rec is None else ((u, w, rec[0]), rec[1])

    def _requeue(self, bad: Bad) -> None:
        self._seq += 1
        self._enqueue((bad[0], self._seq, bad[2], bad[3], bad[4], bad[5], bad[6]))
