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
   squared shortest edge, first in first out within one), and each is split by
   its circumcentre or, when nearer, its off-centre (:mod:`~persistri.impl.mesh.steiner`).
3. **The undo.**  The new point ``c`` is inserted (one new version).  If ``c``
   encroaches a subsegment of its cavity's boundary, the new version is
   dropped — the refinement goes on from the version it started from, which
   persistence kept — and the subsegments ``c`` encroaches are split instead;
   the triangle goes back to the queue.  :attr:`Counts.undos` counts these.
   (A mutable mesh must delete ``c`` and restore the cavity; Triangle does so
   with its ``deletevertex``.)  When ``c`` lies beyond a segment as seen from its
   triangle (only possible for an off-centre or a rounding near a segment:
   Ruppert's lemma says a circumcentre lies in the domain when no subsegment
   is encroached), the straight walk to it stops at that segment and the
   subsegment is split without inserting ``c`` (:attr:`Counts.blocked`).

**Splitting a subsegment** puts a point exactly on it (:func:`~persistri.impl.mesh.steiner.split_parameter`):
at its midpoint, or on the *concentric shell* around an end, at the power of
two ``2^k`` nearest to half the length (``1.5 · 2^k <= length < 3 · 2^k``;
Ruppert's and Shewchuk's fix for small input angles: the splits on two
segments meeting at a small angle land at the same distances from their common
vertex).  The shell's centre: the end that is an input vertex where another
segment meets this one at less than 60° (exact); when neither end or both are,
Triangle's choice — the end where the triangle beside the subsegment has a
second segment as an edge, else the midpoint.

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
forced by the input angle; :attr:`Counts.exempt`).  Triangles exempt this way are
the only ones allowed below the bound; :attr:`Refinement.reached` says whether
every other triangle meets it.  ``max_steiner`` caps the number of Steiner
points for bounds beyond the theory's reach (Triangle's ``-S``).

Costs per accepted insertion: the cavity's O(k) complex operations (O(lg n)
each) and exact tests, plus O(1) exact quality and encroachment tests per new
triangle; an undone one costs the same and leaves nothing behind but its
point's index (the point set is append-only).
"""

from __future__ import annotations

import heapq
import math
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from persistri.impl.complex.structure import Complex
from persistri.impl.mesh.cdt import SegmentGeometry, param_on_segment
from persistri.impl.mesh.angles import angle_at_least
from persistri.impl.mesh.quality import AngleBound, Shape, area_exceeds, inside_lens, shape
from persistri.impl.mesh.steiner import PrecisionLimitError, point_at, split_parameter, steiner_point
from persistri.impl.mesh.triangulation import (
    EXTERIOR,
    Constraint,
    MeshDatum,
    MeshError,
    MeshTriangulation,
    Tri,
    constraint_of,
    edge_key,
)

__all__ = ["Counts", "Refinement", "Refiner"]


@dataclass
class Counts:
    """What a refinement did.

    * ``insertions`` — accepted insertions (= new versions), ``segment_splits +
      circumcenters + offcenters``;
    * ``undos`` — insertions made and then dropped because the new point
      encroached a subsegment (the paper's undo by persistence);
    * ``blocked`` — circumcentres or off-centres not inserted because a segment
      stood between them and their triangle (the segment was split instead);
    * ``exempt`` — bad-angle triangles left alone at small input angles;
    * ``rounded_splits`` — split points not exactly on their input segment (``exact_segments=False``,
      the default): rounded to the nearest doubles where no double lies on the subsegment, or on a
      piece of the chain that ends at such a point; ``rounded_segments`` — the input segments they split.
    """

    insertions: int = 0
    segment_splits: int = 0
    circumcenters: int = 0
    offcenters: int = 0
    undos: int = 0
    blocked: int = 0
    exempt: int = 0
    rounded_splits: int = 0
    rounded_segments: set[int] = field(default_factory=set)


@dataclass
class Refinement:
    """The result of a run: ``versions[k]`` is the mesh after ``k`` insertions (``versions[0]`` the start);
    ``inserted[k - 1]`` the point inserted to make version ``k``; ``angle_reached`` / ``area_reached`` whether
    every domain triangle of the last version meets the angle bound (exempt ones excepted) / the area bounds,
    decided exactly (False only when ``max_steiner`` stopped the run)."""

    versions: list[Complex[MeshDatum]]
    inserted: list[int]
    counts: Counts
    angle_reached: bool
    area_reached: bool
    exempt: set[int] = field(default_factory=set)
    """Ids of the last version's exempt triangles."""


class Refiner:
    """One refinement run from one version (module docstring); :meth:`run` returns a :class:`Refinement`.

    * ``T`` / ``geo`` — the triangulation and the segments' geometry (shared with
      other runs from the same CDT: both are append-only);
    * ``bound`` — the minimum angle; ``max_area`` — a global area bound or None;
      ``region_area`` — area bounds by region code (Triangle's regional ``-a``);
    * ``offconstant`` — the off-centre constant (0: circumcentres only);
    * ``lens`` — encroachment by diametral lenses (Chew, Triangle's default) or circles (Ruppert);
    * ``exact_segments`` — True: split points exactly on their segments, or a clear error where no
      double lies on one; False: split points exactly on their segments wherever a double lies there,
      and else the nearest doubles (as Triangle), counted.
    """

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
        self.counts = Counts()
        self._bad: list[tuple[int, int, Tri, MeshDatum, Shape]] = []
        self._seq = 0
        self._segs: deque[Constraint] = deque()
        self._exempt: set[int] = set()
        self._small: dict[tuple[int, int], bool] = {}

    # -- tests -----------------------------------------------------------------------------

    def _area_bad(self, t: Tri, region: int) -> bool:
        bound = self.region_area.get(region, self.max_area)
        if bound is None:
            return False
        return area_exceeds(self.P, t[0], t[1], t[2], bound)

    def _is_bad(self, t: Tri, d: MeshDatum) -> Shape | None:
        """The shape of the domain triangle ``t`` if it must be split, else None; exempt triangles are recorded, not bad."""
        sh = shape(self.P, t[0], t[1], t[2], self.bound)
        if self._area_bad(t, d[1]):
            return sh
        if sh.good_angle:
            return None
        if self._exempt_edge(sh.p, sh.q):
            self._exempt.add(d[0])
            return None
        return sh

    def _exempt_edge(self, p: int, q: int) -> bool:
        """Whether edge ``pq`` joins two split points on different segments, equidistant from their common endpoint."""
        on = self.geo.on_segment
        sp, sq = on.get(p), on.get(q)
        if sp is None or sq is None or sp[0] == sq[0]:
            return False
        ends_p, ends_q = self.geo.ends[sp[0]], self.geo.ends[sq[0]]
        for o in set(ends_p) & set(ends_q):
            # Only at a small input angle (below 60°): elsewhere Ruppert's argument needs no exemption.
            far_p, far_q = ends_p[1] if ends_p[0] == o else ends_p[0], ends_q[1] if ends_q[0] == o else ends_q[0]
            (io, ip, iq), _ = self.P.integers(o, far_p, far_q)
            d1, d2 = (ip[0] - io[0], ip[1] - io[1]), (iq[0] - io[0], iq[1] - io[1])
            if angle_at_least(d1[0] * d2[0] + d1[1] * d2[1], d1[0] ** 2 + d1[1] ** 2, d2[0] ** 2 + d2[1] ** 2, 60.0):
                continue
            shp, shq = self.geo.shell.get(p), self.geo.shell.get(q)
            if shp is not None and shp == shq and shp[0] == o:
                return True
            (po, pp, pq), _ = self.P.integers(o, p, q)
            dp = (pp[0] - po[0]) ** 2 + (pp[1] - po[1]) ** 2
            dq = (pq[0] - po[0]) ** 2 + (pq[1] - po[1]) ** 2
            # Triangle's test, decided on integers: squared distances within a factor 1.001 of each other.
            if 999 * dq < 1000 * dp < 1001 * dq:
                return True
        return False

    def _push_bad(self, t: Tri, d: MeshDatum, sh: Shape) -> None:
        edge2 = sh.edge2
        bucket = math.frexp(edge2)[1] if 0.0 < edge2 < math.inf else 0
        self._seq += 1
        heapq.heappush(self._bad, (bucket, self._seq, t, d, sh))

    def _encroaches(self, u: int, w: int, x: int) -> bool:
        """Whether point ``x`` encroaches the subsegment ``uw``: inside its diametral lens, or circle (exact)."""
        if self.lens:
            return inside_lens(self.P, u, w, x, self.bound.degrees)
        return self.P.dot_sign(u, w, x) < 0

    def _encroached(self, c: Complex[MeshDatum], u: Any, w: Any) -> bool:
        """Whether the subsegment ``{u, w}`` of version ``c`` has a domain triangle whose apex is strictly inside its diametral circle."""
        for x, y in ((u, w), (w, u)):
            found = self.S.neighbour(c, (x, y))
            if found is None:
                continue
            t, d = found
            if d[1] != EXTERIOR and t[2] >= 0 and self._encroaches(x, y, t[2]):
                return True
        return False

    def _examine(self, c: Complex[MeshDatum], created: tuple[tuple[Tri, MeshDatum], ...]) -> None:
        """Queue the bad triangles among ``created`` and the subsegments their apexes encroach."""
        P = self.P
        for t, d in created:
            if d[1] == EXTERIOR:
                continue
            sh = self._is_bad(t, d)
            if sh is not None:
                self._push_bad(t, d, sh)
            for lo, hi, s in d[2]:
                k = [v for v in t if v != lo and v != hi][0]
                if self._encroaches(lo, hi, k):
                    self._segs.append((lo, hi, s))

    # -- steps -----------------------------------------------------------------------------

    def _alive(self, c: Complex[MeshDatum], t: Tri, d: MeshDatum) -> bool:
        found = self.S.data(c, t)
        return found is not None and found[0] is d

    def _split(self, c: Complex[MeshDatum], sub: Constraint) -> tuple[Complex[MeshDatum], int] | None:
        """Split the subsegment ``sub`` of version ``c``: the new version and the point, or None if it is gone."""
        T, P, geo = self.T, self.P, self.geo
        lo, hi, s = sub
        vu, vw = T.vertex(lo), T.vertex(hi)
        sides = [self.S.neighbour(c, (vu, vw)), self.S.neighbour(c, (vw, vu))]
        if sides[0] is None or constraint_of(sides[0][1], lo, hi) != s:
            return None
        # The side whose apex encroaches (else any domain side): Triangle's choice, which decides the shells.
        beside = sides[0]
        best = -1
        for side in sides:
            if side is None or side[0][2] < 0 or side[1][1] == EXTERIOR:
                continue
            rank = 1 if self._encroaches(side[0][0], side[0][1], side[0][2]) else 0
            if rank > best:
                best, beside = rank, side
        (x0, x1, apex), bdat = beside
        tu, tw = param_on_segment(P, geo, s, lo), param_on_segment(P, geo, s, hi)
        t_lo_first = tu < tw
        if not t_lo_first:
            tu, tw = tw, tu
        a, b = geo.ends[s]
        # Concentric shells (Ruppert, Shewchuk): around an end that is an input vertex where another segment meets
        # this one at an angle below 60°, where they keep the splits of both segments at equal distances.  Otherwise
        # (neither end, or both) Triangle's choice: the end where the triangle beside the subsegment has a second
        # constrained edge (two segments meet at that triangle's corner), else the midpoint.
        small_0, small_1 = self._small_angle_at(int(x0), s), self._small_angle_at(int(x1), s)
        if small_0 != small_1:
            acute_0, acute_1 = small_0, small_1
        else:
            acute_1 = constraint_of(bdat, x1, apex) >= 0 if bdat[2] else False
            acute_0 = not acute_1 and (constraint_of(bdat, apex, x0) >= 0 if bdat[2] else False)
        wanted = (tu + tw) / 2
        shell: tuple[int, int] | None = None
        if acute_0 or acute_1:
            o, other = (int(x1), int(x0)) if acute_1 else (int(x0), int(x1))
            (po, pt), e = P.integers(o, other)
            length = math.hypot(po[0] - pt[0], po[1] - pt[1]) * 2.0**e
            (pa, pb), e2 = P.integers(a, b)
            total = math.hypot(pa[0] - pb[0], pa[1] - pb[1]) * 2.0**e2
            if length > 0 and total > 0 and math.isfinite(length) and math.isfinite(total):
                k = math.floor(math.log2(length / 3.0)) + 1  # 1.5 · 2^k <= length < 3 · 2^k
                while length < 1.5 * 2.0**k:
                    k -= 1
                while length >= 3.0 * 2.0**k:
                    k += 1
                dt = Fraction(2.0**k / total)
                t_o = param_on_segment(P, geo, s, o)
                wanted = t_o + dt if t_o == tu else t_o - dt
                shell = (o, k)
        u, w = lo, hi
        try:
            t, x, y = split_parameter(P, a, b, *((lo, hi) if t_lo_first else (hi, lo)), tu, tw, wanted)
        except PrecisionLimitError as exc:
            if self.exact_segments:
                raise PrecisionLimitError(
                    f"splitting segment {s} between vertices {int(u)} and {int(w)}: {exc}; "
                    "without exact_segments=True split points are rounded to the nearest doubles there, as Triangle does"
                ) from None
            t, x, y = self._rounded_split(a, b, u, w, tu, tw, wanted)
            rounded = True
        else:
            rounded = False
        p = P.append(x, y)
        geo.on_segment[p] = (s, t)
        if shell is not None:
            geo.shell[p] = shell
        ins = T.insert(c, p, beside, split=(lo, hi, s))
        if rounded:
            # Off the segment by up to half an ulp, p might not see every edge of its cavity from inside (a
            # boundary edge at a hair's angle to the segment): then no valid mesh holds it, and we say so.
            for tri, _ in ins.created:
                if tri[2] >= 0 and tri[0] >= 0 and tri[1] >= 0 and P.orient2d_sign(tri[0], tri[1], tri[2]) <= 0:
                    raise PrecisionLimitError(
                        f"the split point of segment {s} between vertices {int(u)} and {int(w)}, rounded to the nearest "
                        "doubles, would make a flat or inverted triangle: the mesh is at the limit of double precision here"
                    )
        elif lo in geo.off_segment or hi in geo.off_segment:
            # Exactly on a piece that ends at a rounded point: on the segment itself only if the line allows.
            rounded = P.orient2d_sign(a, b, p) != 0
        if rounded:
            geo.off_segment.add(p)
            self.counts.rounded_splits += 1
            self.counts.rounded_segments.add(s)
        self.counts.segment_splits += 1
        self._examine(ins.version, ins.created)
        return ins.version, p

    def _small_angle_at(self, o: int, s: int) -> bool:
        """Whether input vertex ``o`` is an end of segment ``s`` where another segment meets it at an angle below 60°
        (exact; memoised): where concentric shells are needed."""
        geo = self.geo
        if o >= geo.n_input or geo.incident[o] < 2:
            return False
        key = (o, s)
        found = self._small.get(key)
        if found is None:
            a, b = geo.ends[s]
            far = b if a == o else a
            found = False
            for t, (c, d) in enumerate(geo.ends):
                if t == s or o not in (c, d) or c == d:
                    continue
                other = d if c == o else c
                (io, ip, iq), _ = self.P.integers(o, far, other)
                d1, d2 = (ip[0] - io[0], ip[1] - io[1]), (iq[0] - io[0], iq[1] - io[1])
                if not angle_at_least(d1[0] * d2[0] + d1[1] * d2[1], d1[0] ** 2 + d1[1] ** 2, d2[0] ** 2 + d2[1] ** 2, 60.0):
                    found = True
                    break
            self._small[key] = found
        return found

    def _rounded_split(
        self, a: int, b: int, u: int, w: int, tu: Fraction, tw: Fraction, wanted: Fraction
    ) -> tuple[Fraction, float, float]:
        """``exact_segments=False``: the point of segment ``ab`` at parameter ``wanted`` (clamped to the middle half of
        ``(tu, tw)``), rounded to the nearest doubles — off the segment by at most half an ulp per coordinate (Triangle's
        split points); :class:`PrecisionLimitError` if it rounds onto an end."""
        P = self.P
        delta = tw - tu
        t = min(max(wanted, tu + delta / 4), tw - delta / 4)
        ex, ey = point_at(P, a, b, t)
        x, y = float(ex), float(ey)
        for v in (u, w):
            if (x, y) == P.xy(v):
                raise PrecisionLimitError(
                    f"the split point of the subsegment between vertices {u} and {w} rounds onto vertex {v}: "
                    "the mesh is at the limit of double precision here"
                )
        return t, x, y

    def _split_triangle(
        self, c: Complex[MeshDatum], t: Tri, d: MeshDatum, sh: Shape
    ) -> tuple[Complex[MeshDatum], int] | None:
        """Try to split bad triangle ``t``: the new version and point, or None when undone or blocked (the
        subsegments to split instead are queued and ``t`` goes back to the queue)."""
        T, P = self.T, self.P
        x, y, off = steiner_point(P, sh.p, sh.q, sh.r, self.offconstant)
        p = P.append(x, y)
        where = T.walk_to(c, (t, d), p)
        if where[0] == "blocked":
            lo, hi, s = where[1]
            if s < 0:
                raise MeshError(f"internal: the Steiner point of triangle {t} lies outside the triangulation")
            self.counts.blocked += 1
            self._segs.append((lo, hi, s))
            self._push_bad(t, d, sh)
            return None
        ft, fd = where[1]
        for v in ft:
            if P.same(v, p):
                raise PrecisionLimitError(
                    f"the Steiner point of triangle {tuple(int(v) for v in t)} rounds onto vertex {int(v)}: "
                    "the mesh is at the limit of double precision here"
                )
        for u, w in ((ft[0], ft[1]), (ft[1], ft[2]), (ft[2], ft[0])):
            s = constraint_of(fd, u, w) if fd[2] else -1
            if s >= 0 and P.orient2d_sign(u, w, p) == 0:
                # On a subsegment: it encroaches it (strictly inside its diametral circle).
                self.counts.blocked += 1
                self._segs.append((*edge_key(u, w), s))
                self._push_bad(t, d, sh)
                return None
        ins = T.insert(c, p, (ft, fd))
        encroached = [
            (lo, hi, s) for tri, dat in ins.created for lo, hi, s in dat[2] if self._encroaches(lo, hi, p)
        ]
        if encroached:
            # The paper's undo: drop the new version and go on from c, which persistence kept.
            self.counts.undos += 1
            self._segs.extend(encroached)
            self._push_bad(t, d, sh)
            return None
        if off:
            self.counts.offcenters += 1
        else:
            self.counts.circumcenters += 1
        self._examine(ins.version, ins.created)
        return ins.version, p

    # -- the run ---------------------------------------------------------------------------

    def run(
        self, start: Complex[MeshDatum], *, max_steiner: int | None = None, progress: Callable[[int], Any] | None = None
    ) -> Refinement:
        """Refine from version ``start`` until no subsegment is encroached and no triangle is bad (or
        ``max_steiner`` points were added).  O(output · log) expected in practice."""
        versions = [start]
        inserted: list[int] = []
        c = start
        seen: set[tuple[int, int]] = set()
        for t, d in self.S.items(c):
            if d[1] == EXTERIOR:
                continue
            sh = self._is_bad(t, d)
            if sh is not None:
                self._push_bad(t, d, sh)
            for lo, hi, s in d[2]:
                if (lo, hi) not in seen and self._encroached(c, self.T.vertex(lo), self.T.vertex(hi)):
                    seen.add((lo, hi))
                    self._segs.append((lo, hi, s))
        while True:
            if max_steiner is not None and len(inserted) >= max_steiner:
                break
            step: tuple[Complex[MeshDatum], int] | None = None
            if self._segs:
                step = self._split(c, self._segs.popleft())
            elif self._bad:
                _, _, t, d, sh = heapq.heappop(self._bad)
                if not self._alive(c, t, d):
                    continue
                step = self._split_triangle(c, t, d, sh)
            else:
                break
            if step is not None:
                c, p = step
                versions.append(c)
                inserted.append(p)
                if progress is not None:
                    progress(1)
        counts = self.counts
        counts.insertions = len(inserted)
        self._exempt.clear()
        angle_ok = area_ok = True
        for t, d in self.S.items(c):
            if d[1] == EXTERIOR:
                continue
            if area_ok and self._area_bad(t, d[1]):
                area_ok = False
            sh = shape(self.P, t[0], t[1], t[2], self.bound)
            if not sh.good_angle:
                if self._exempt_edge(sh.p, sh.q):
                    self._exempt.add(d[0])
                else:
                    angle_ok = False
        counts.exempt = len(self._exempt)
        return Refinement(versions, inserted, counts, angle_ok, area_ok, set(self._exempt))
