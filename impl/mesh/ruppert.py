"""Ruppert's Delaunay refinement with undo by persistence (Ruppert 1995; Shewchuk 1997; the paper's §1).

The paper's introduction names this algorithm as the reason to want
persistent triangulations: a refinement "in which we undo a partial
triangulation on the fly in the rare case that boundary constraints lead to
undesirable acute triangles".  Here every insertion makes a new version of the
persistent complex (:mod:`persistri.impl.mesh.triangulation`), and the undo is
just *not adopting* it: the version before the insertion is still there, intact,
in O(1).

**The algorithm** (:class:`Refiner`), on the constrained Delaunay triangulation
of a PSLG (:mod:`persistri.impl.mesh.cdt`):

1. A *subsegment* (a mesh edge on an input segment) is **encroached** when the
   apex of a domain triangle beside it lies strictly inside its diametral
   circle — exactly, ``(u − x) · (w − x) < 0``
   (:meth:`~persistri.impl.geometry.growing.GrowingPredicates2.dot_sign`;
   Thales' theorem, ``proofs/proof_mesh.py``) — Ruppert's definition
   (``lens=False``); or, by default as in Triangle, inside its diametral
   *lens*, the part of that circle where the apex angle is at least
   ``180° − 2θ`` (Chew's; :func:`~persistri.impl.mesh.quality.inside_lens`):
   a vertex there would make a triangle with two angles below ``θ`` on the
   subsegment, and one only in the circle would not, so the lens splits fewer
   subsegments and gives fewer triangles.  Encroached subsegments are split
   first, before any triangle (Ruppert's priority).
2. A domain triangle is **bad** when its smallest angle is below ``min_angle``
   or its area above ``max_area`` (or its region's bound), decided exactly
   (:mod:`~persistri.impl.mesh.quality`).  Bad triangles are taken shortest
   shortest-edge first (Triangle's order: buckets by the binary exponent of the
   squared shortest edge, first in first out within one.  Triangle's
   ``enqueuebadtriang()`` uses half exponents; measured, that moves the counts at
   small-angle clusters both ways, so it is not copied: docs/meshing.md, "The
   order of the work"), and each is split by
   its circumcentre or, when nearer, its off-centre (:mod:`~persistri.impl.mesh.steiner`).
3. **The undo.**  The new point ``c``'s cavity is found in the current
   version (its conflict search).  If ``c`` encroaches a subsegment on the
   cavity's boundary — one the new version would hold on its fan — the
   insertion is undone: the refinement goes on from the version it started
   from, which persistence kept unchanged, the subsegments ``c`` encroaches are
   split instead, and the triangle goes back to the queue (:attr:`Counts.undos`;
   the record: :class:`~persistri.impl.mesh.record.Undone`).  Since the
   encroachment is decided on the cavity's boundary, the new version is not
   even built: the undo costs the conflict search and nothing else.  Built or
   not, the version returned to is the point — a mutable mesh must delete ``c``
   and restore the cavity (Triangle's ``undovertex``).  When ``c`` lies beyond a segment as seen from its
   triangle (only possible for an off-centre or a rounding near a segment:
   Ruppert's lemma says a circumcentre lies in the domain when no subsegment
   is encroached), the straight walk to it stops at that segment and the
   subsegment is split without inserting ``c`` (:attr:`Counts.blocked`).

**Splitting a subsegment** (:mod:`~persistri.impl.mesh.splitting`) puts a point on
it, exactly wherever a double lies there: at its midpoint, or on the *concentric
shell* around an end.  With lenses (Chew's algorithm, Triangle's default), the
*free* vertices — circumcentres and off-centres, on no segment — that lie strictly
inside the subsegment's diametral circle, as apexes of the triangles beside it, are
**deleted** first (Chew 1989; Triangle's ``splitencsegs``), on each side where the
triangle beside has no second constrained edge: the deletions
(:func:`~persistri.impl.mesh.deletion.star_replacement`, each star replaced by the
Delaunay triangulation of its link) and the split together make one new version, by
one ``replace`` from the version before them.  It undoes earlier refinement that the split would
make skinny, and is what brings the triangle counts down to Triangle's
(:attr:`Counts.deletions`).

**Termination.**  With no input angle below 60° (Shewchuk 1997, Theorem 8 and
after; Ruppert's original argument with bound ``arcsin(1/(2√2)) ≈ 20.7°``), every
new vertex is at least a constant times the *local feature size* away from every
other, so the mesh has bounded size for ``min_angle <= 20.7°``; in practice
(Triangle's experience) bounds up to about 33.8° terminate.  **Small input
angles** (below 60°) break the argument: splitting one segment near the angle
encroaches the other, forever.  Concentric shells make the splits on both
segments land at equal distances from the apex, and, following Miller, Pav and
Walkington (as Triangle does), a bad triangle whose shortest edge joins two
Steiner vertices on *different* segments that share an endpoint ``o`` and meet
there at an angle below 60°, at equal distance from ``o`` — both placed on the same shell around ``o``, or with squared
distances to ``o`` within a factor 1.001 of each other (Triangle's rule; the
comparison is exact, on integers: the factor is a tolerance of the rule, which
splits at midpoints when both ends of a segment are shared vertices, not of any
predicate) — is **exempt**: it is not split (such a triangle's small angle is
forced by the input angle; :attr:`Counts.exempt`).  Both devices need the splits on their shells: on a
segment at an input angle ``α`` below 60°, a split point exactly on the segment but farther than
``min(α²/4, 2^-12)`` of its distance from the apex off its wanted place is rounded to the nearest doubles instead
(:func:`~persistri.impl.mesh.splitting.placement_tolerances`), else its twin on the other segment encroaches and
the two sides split each other without end.  Triangles exempt this way are
the only ones allowed below the bound; :attr:`Refinement.reached` says whether
every other triangle meets it.  ``max_steiner`` caps the number of Steiner
points for bounds beyond the theory's reach (Triangle's ``-S``).

The run reads the version it stands at through an edge index of it, changed only
when it adopts a step (:mod:`~persistri.impl.mesh.edges`): O(1) per look-up.

Costs per accepted insertion: the new version's ``replace`` (O(k) vertex lists,
O(lg n) each) and the cavity's exact tests, plus O(1) quality and encroachment tests per new
triangle (float stage first, exact when it cannot tell:
:class:`~persistri.impl.mesh.quality_filter.QualityTests`); an undone one costs its
conflict search and O(k) encroachment tests, no complex operation, and leaves
nothing behind but its point's index (the point set is append-only) and its record.
Whether a queued triangle is still there is a set lookup: triangle ids are never
reused, and the run only ever moves forward from its current version, so an id
removed once is gone for good (the undone versions' ids never enter the queue).
"""

from __future__ import annotations

import heapq
from collections.abc import Callable
from typing import Any

from persistri.impl.complex.structure import Complex
from persistri.impl.geometry.growing import ERRBOUND_DOT
from persistri.impl.mesh.cdt import param_on_segment
from persistri.impl.mesh.datum import Pending
from persistri.impl.mesh.deletion import star_replacement
from persistri.impl.mesh.edges import index_of
from persistri.impl.mesh.precision import crowded_apex, nearest_features, valid_split
from persistri.impl.mesh.record import Counts, Refinement
from persistri.impl.mesh.refine_state import Bad, RefinerState
from persistri.impl.mesh.splitting import rounded_candidates, split_point
from persistri.impl.mesh.steiner import PrecisionLimitError, steiner_point
from persistri.impl.mesh.triangulation import (
    EXTERIOR,
    Cavity,
    Constraint,
    Insertion,
    MeshDatum,
    MeshError,
    Tri,
    constraint_of,
    edge_key,
)
from persistri.impl.mesh.walk import walk_to

__all__ = ["Counts", "Refinement", "Refiner", "Bad"]


class Refiner(RefinerState):
    """One refinement run from one version (module docstring); :meth:`run` returns a :class:`Refinement`.

    * ``T`` / ``geo`` — the triangulation and the segments' geometry (shared with
      other runs from the same CDT: both are append-only);
    * ``bound`` — the minimum angle; ``max_area`` — a global area bound or None;
      ``region_area`` — area bounds by region code (Triangle's regional ``-a``);
    * ``offconstant`` — the off-centre constant (0: circumcentres only);
    * ``lens`` — Chew's algorithm as Triangle runs it (encroachment by diametral lenses, and free
      vertices deleted from a subsegment's diametral circle before it is split), or Ruppert's
      (diametral circles, no deletion: Triangle's ``-D``);
    * ``exact_segments`` — True: split points exactly on their segments, or a clear error where no
      double lies on one; False: split points exactly on their segments wherever a double lies there,
      and else the nearest doubles (as Triangle), counted.
    """

    # -- steps -----------------------------------------------------------------------------

    def _delete_free(
        self, c: Complex[MeshDatum], lo: int, hi: int, sides: list[tuple[Tri, MeshDatum] | None]
    ) -> tuple[Pending | None, list[int]]:
        """Chew's rule before a split: delete the free vertices inside the diametral circle of ``{lo, hi}`` that are
        apexes of the triangles beside it (a side whose triangle has a second constrained edge is left alone).

        ``sides``: the triangles on ``(lo, hi)`` and on ``(hi, lo)`` in ``c``, kept up to date in place.  The run
        adopts each deletion (its index and queues follow), but no version is made for them: they are returned as
        :class:`~persistri.impl.mesh.datum.Pending` from ``c`` (None if there were none), and the split makes one
        version for them and itself."""
        T, P, geo = self.T, self.P, self.geo
        deleted: list[int] = []
        pending: Pending | None = None
        get = self._edges.get
        vu, vw = T.vertex(lo), T.vertex(hi)
        for k, edge in enumerate(((vu, vw), (vw, vu))):
            while True:
                side = sides[k]
                if side is None:
                    break
                (_, _, apex), d = side
                if apex < 0 or d[1] == EXTERIOR or len(d[2]) > 1:
                    break
                if apex < geo.n_input or apex in geo.on_segment or P.dot_sign(lo, hi, apex) >= 0:
                    break
                star, made = star_replacement(T, apex, side, get)
                if pending is None:
                    pending = Pending(c, [], {})
                pending.after(star, made)
                deleted.append(int(apex))
                self.counts.deletions += 1
                self._adopt(Insertion(c, star, made))
                sides[0], sides[1] = self._beside(vu, vw), self._beside(vw, vu)
        return pending, deleted

    def _split(self, c: Complex[MeshDatum], sub: Constraint) -> tuple[Complex[MeshDatum], int, list[int]] | None:
        """Split the subsegment ``sub`` of version ``c``: the new version, the point and the vertices deleted
        first, or None if the subsegment is gone."""
        T, P, geo = self.T, self.P, self.geo
        lo, hi, s = sub
        vu, vw = T.vertex(lo), T.vertex(hi)
        first = self._beside(vu, vw)
        if first is None or constraint_of(first[1], lo, hi) != s:
            return None
        deleted: list[int] = []
        sides = [first, self._beside(vw, vu)]
        pending: Pending | None = None
        if self.lens:
            pending, deleted = self._delete_free(c, lo, hi, sides)
        start = sides[0] if sides[0] is not None else sides[1]
        assert start is not None, "the subsegment is still there after the deletions"
        clear = self._clear_of_band
        for side in sides:
            if side is None or side[1][1] == EXTERIOR or (s, side[0][2]) in clear:
                continue
            crowded = crowded_apex(P, geo, s, side[0][2])
            if crowded is not None:
                raise PrecisionLimitError(
                    f"{crowded}: a mesh meeting the bounds would need edges shorter than the spacing of doubles there "
                    "(move the vertex onto it or away from it, or mesh without an angle bound)"
                )
            clear.add((s, side[0][2]))
        t, x, y, shell, rounded = split_point(
            P, geo, lo, hi, s, sides, self.angles.small_angle, self.exact_segments, self.angles.tolerances
        )
        p = P.append(x, y)
        # Exactly on the segment between ends exactly on it: exactly on the subsegment's line (no test needed).
        on_line = not rounded and lo not in geo.off_segment and hi not in geo.off_segment
        step = T.insert(c, p, start, (lo, hi, s), self._edges, on_line, pending)
        if rounded and not valid_split(P, step, lo, hi):
            # Off the segment by an ulp, p may not see every edge of its cavity from inside (a vertex within an ulp
            # of the segment), or may leave the old subsegment standing.  Persistence makes trying cheap: the
            # invalid version is dropped like an undone one, and the next nearby double is inserted into c instead.
            a, b = geo.ends[s]
            tu, tw = sorted((param_on_segment(P, geo, s, lo), param_on_segment(P, geo, s, hi)))
            for t2, x2, y2 in rounded_candidates(P, a, b, lo, hi, tu, tw, t):
                if (x2, y2) == (x, y):
                    continue
                self.counts.rounding_retries += 1
                p = P.append(x2, y2)
                step = T.insert(c, p, start, (lo, hi, s), self._edges, False, pending)
                if valid_split(P, step, lo, hi):
                    if t2 != t:
                        shell = None  # another parameter: off the shell
                    t = t2
                    break
            else:
                raise PrecisionLimitError(
                    f"no pair of doubles near the subsegment {int(lo)}–{int(hi)} (mesh vertices) of {geo.name(P, s)} "
                    "splits it into a valid mesh (every candidate makes a flat or inverted triangle): the mesh is at the limit of "
                    "double precision here"
                )
        geo.on_segment[p] = (s, t)
        if shell is not None:
            geo.shell[p] = shell
        if rounded or lo in geo.off_segment or hi in geo.off_segment:
            # Rounded, or exactly on a piece that ends at a rounded point: off the segment unless exactly on its line
            # (a nearby double can happen to lie on it).
            a, b = geo.ends[s]
            rounded = P.orient2d_sign(a, b, p) != 0
        if rounded:
            geo.off_segment.add(p)
            self.counts.rounded_splits += 1
            self.counts.rounded_segments.add(s)
        self.counts.segment_splits += 1
        self._adopt(step)
        return step.version, p, deleted

    def _split_triangle(self, c: Complex[MeshDatum], bad: Bad) -> tuple[Complex[MeshDatum], int] | None:
        """Try to split a bad triangle: the new version and point, or None when undone or blocked (the
        subsegments to split instead are queued and the triangle goes back to the queue)."""
        T, P = self.T, self.P
        _, _, t, d, sp, sq, sr = bad
        x, y, off = steiner_point(P, sp, sq, sr, self.offconstant)
        p = P.append(x, y)
        where = walk_to(T, c, (t, d), p, self._edges)
        if where[0] == "blocked":
            tri = (int(t[0]), int(t[1]), int(t[2]))
            lo, hi, s = where[1]
            if s < 0:
                raise MeshError(f"internal: the Steiner point of triangle {t} lies outside the triangulation")
            self.counts.blocked += 1
            self.log.blocked(self._version, p, (x, y), tri, off, (int(lo), int(hi), s))
            self._segs.append((lo, hi, s))
            self._requeue(bad)
            return None
        ft, fd = where[1]
        v = P.same_as_any(p, ft)
        if v is not None:
            raise PrecisionLimitError(
                f"the Steiner point of triangle {tuple(int(v) for v in t)} rounds onto vertex {int(v)}: "
                "the mesh is at the limit of double precision here"
            )
        if fd[2]:
            for u, w in ((ft[0], ft[1]), (ft[1], ft[2]), (ft[2], ft[0])):
                s = constraint_of(fd, u, w)
                if s >= 0 and P.orient2d_sign(u, w, p) == 0:
                    # On a subsegment: it encroaches it (strictly inside its diametral circle).
                    lo, hi = edge_key(u, w)
                    self.counts.blocked += 1
                    tri = (int(t[0]), int(t[1]), int(t[2]))
                    self.log.blocked(self._version, p, (x, y), tri, off, (int(lo), int(hi), s))
                    self._segs.append((lo, hi, s))
                    self._requeue(bad)
                    return None
        cav = T.cavity(c, p, (ft, fd), None, self._edges)
        # The subsegments the new version would hold on its fan are the cavity's constrained boundary edges: whether p
        # encroaches one is decided before the version is built.
        encroached = self._encroached_on(cav, p)
        if encroached:
            # The paper's undo: go on from c, which persistence kept unchanged (the new version is not even built).
            self.counts.undos += 1
            # Recorded as they are (the log reads them as point indices when the records are first read).
            self.log.undone(self._version, p, (x, y), t, off, encroached, cav.triangles)
            self._segs.extend(encroached)
            self._requeue(bad)
            return None
        step = T.build(cav)
        if off:
            self.counts.offcenters += 1
        else:
            self.counts.circumcenters += 1
        # Every subsegment edge of the new triangles is a constrained edge of the cavity's boundary, with apex p: each
        # was tested above and none is encroached, so they are not tested again.
        self._adopt(step, False)
        self.geo.made_in[p] = (int(t[0]), int(t[1]), int(t[2]))
        return step.version, p

    def _encroached_on(self, cav: Cavity, p: int) -> list[Constraint]:
        """The constrained edges of the cavity's boundary that ``p`` encroaches, in the order the fan would make them
        (around the boundary from its first edge, as :meth:`~persistri.impl.mesh.triangulation.MeshTriangulation.build`
        walks it). O(k)."""
        boundary = cav.boundary
        tests = self.tests
        encroaches = tests.encroaches
        rows = tests.rows
        px, py = rows[p]
        # The tests are pure: made in boundary order, they are put in the fan's order only when two or more succeed.
        hits: list[Constraint] = []
        for u, w, _, seg in boundary:
            if seg >= 0:
                lo, hi = (u, w) if u < w else (w, u)  # edge_key(u, w), inlined
                # encroaches(lo, hi, p)'s first test, inlined (its operations: dot_terms): p clearly outside the
                # diametral circle encroaches neither it nor the lens; anything else is asked of encroaches.
                ux, uy = rows[lo]
                wx, wy = rows[hi]
                left = (ux - px) * (wx - px)
                right = (uy - py) * (wy - py)
                if left + right > ERRBOUND_DOT * (abs(left) + abs(right)):
                    continue
                if encroaches(lo, hi, p):
                    hits.append((lo, hi, seg))
        if len(hits) <= 1:
            return hits
        succ = {u: (w, seg) for u, w, _, seg in boundary}
        inf = self.T.infinite
        first = succ[inf][0] if inf in succ else boundary[0][0]
        out: list[Constraint] = []
        u = first
        for _ in range(len(boundary)):
            w, seg = succ[u]
            if seg >= 0:
                lo, hi = (u, w) if u < w else (w, u)
                if encroaches(lo, hi, p):
                    out.append((lo, hi, seg))
            u = w
            if u == first:
                break
        return out

    # -- the run ---------------------------------------------------------------------------

    def run(
        self, start: Complex[MeshDatum], *, max_steiner: int | None = None, progress: Callable[[int], Any] | None = None
    ) -> Refinement:
        """Refine from version ``start`` until no subsegment is encroached and no triangle is bad (or
        ``max_steiner`` points were added).  O(output · log) expected in practice."""
        versions = [start]
        inserted: list[int] = []
        deleted: list[tuple[int, ...]] = []
        c = start
        encroaches = self.tests.encroaches
        # Each subsegment once, at its first domain triangle, if the apex of a domain triangle beside it encroaches
        # it: both such triangles are among the items (:meth:`_encroached`, read off them instead of looked up).
        subsegments: dict[tuple[int, int], list[Any]] = {}
        items = self.S.items(c)
        self._edges = index_of(items)
        # self._judge(t, d) for each domain triangle, in one call (the queue of bad triangles and that of subsegments
        # are apart: judging first, then the subsegments, queues the same entries in the same order as one pass).
        for t, d, found in self.tests.assess_all(items):
            self._judge_bad(t, d, found)
        for t, d in items:
            if d[1] == EXTERIOR:
                continue
            if d[2]:
                a, b, cc = t
                for lo, hi, s in d[2]:
                    apex = a if a != lo and a != hi else b if b != lo and b != hi else cc
                    entry = subsegments.get((lo, hi))
                    if entry is None:
                        subsegments[(lo, hi)] = [s, apex >= 0 and encroaches(lo, hi, apex)]
                    elif not entry[1] and apex >= 0 and encroaches(lo, hi, apex):
                        entry[1] = True
        for (lo, hi), (s, hit) in subsegments.items():
            if hit:
                self._segs.append((lo, hi, s))
        dead = self._dead
        buckets, queues, segs = self._buckets, self._queues, self._segs  # the objects the steps append to
        self._version = len(versions) - 1
        finished = False
        where = -1
        try:
            while True:
                if max_steiner is not None and len(inserted) >= max_steiner:
                    break
                if segs:
                    sub = segs.popleft()
                    where = sub[0]
                    split = self._split(c, sub)
                    if split is None:
                        continue
                    c, p, gone = split
                    deleted.append(tuple(gone))
                    self.log.split(int(sub[0]), int(sub[1]), len(versions), deleted[-1])
                elif buckets:
                    # The first bad triangle of the lowest non-empty bucket: the least (bucket, sequence) queued,
                    # first in first out within a bucket.  Most of what is popped is dead already.
                    bucket = buckets[0]
                    queue = queues[bucket]
                    bad = queue.popleft()
                    if not queue:
                        heapq.heappop(buckets)
                        del queues[bucket]
                    if bad[3][0] in dead:
                        continue
                    where = bad[4]
                    step = self._split_triangle(c, bad)
                    if step is None:
                        continue
                    c, p = step
                    deleted.append(())
                else:
                    finished = True
                    break
                versions.append(c)
                inserted.append(p)
                self._version += 1  # len(versions) - 1
                if progress is not None:
                    progress(1)
        except PrecisionLimitError as exc:
            if where < 0 or " lies " in str(exc):
                raise
            x, y = self.P.xy(where)
            raise PrecisionLimitError(f"{exc}{nearest_features(self.P, self.geo, x, y)}") from None
        counts = self.counts
        counts.insertions = len(inserted)
        if finished:
            # Every triangle of c was judged when it was made (or at the start), and none is queued or bad: the
            # bounds hold, and the exempt triangles are those judged so that are still there.
            angle_ok = area_ok = True
            self._exempt.difference_update(dead)
        else:
            angle_ok, area_ok = self._final(c)
        counts.exempt = len(self._exempt)
        return Refinement(versions, inserted, counts, angle_ok, area_ok, set(self._exempt), deleted, self.log)

    def _final(self, c: Complex[MeshDatum]) -> tuple[bool, bool]:
        """Whether every domain triangle of ``c`` meets the angle bound (exempt ones excepted) and the area bounds,
        rejudging all of them (the run stopped early); the exempt ones are recorded. O(size)."""
        self._exempt.clear()
        angle_ok = area_ok = True
        tests = self.tests
        for t, d in self.S.items(c):
            if d[1] == EXTERIOR:
                continue
            found = tests.assess(t[0], t[1], t[2], d[1])
            if found is None:
                continue
            if area_ok and tests.area_bad(t[0], t[1], t[2], d[1]):
                area_ok = False
            if not found[4]:
                if self.angles.exempt_edge(found[0], found[1]):
                    self._exempt.add(d[0])
                else:
                    angle_ok = False
        return angle_ok, area_ok

