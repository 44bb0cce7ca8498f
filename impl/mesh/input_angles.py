"""The input's angles as Ruppert's refinement asks about them, each answer memoised for the run (Shewchuk, Triangle).

Small input angles (below 60°) are where Ruppert's guarantee needs help:
segments there are split on concentric shells, a triangle whose short edge
joins two split points equidistant from the apex of such an angle is exempt
from the angle bound (Triangle's ``testtriangle`` rule), and split points are
placed within a tolerance that keeps the shells paired
(:mod:`persistri.impl.mesh.splitting`).  :class:`InputAngles` answers these
questions for one run of :class:`~persistri.impl.mesh.ruppert.Refiner`,
exactly, each once: they depend on the input and on split points that never
change once made.  docs/meshing.md, "Termination and small input angles", has the argument.
"""

from __future__ import annotations

from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.angles import angle_at_least
from persistri.impl.mesh.cdt import SegmentGeometry
from persistri.impl.mesh.quality import equidistant
from persistri.impl.mesh.splitting import placement_tolerances, small_angle_at

__all__ = ["InputAngles"]


class InputAngles:
    """The memoised small-angle, exemption and placement tests of one refinement over ``P`` and ``geo``.  O(1)
    per question after its first answer."""

    def __init__(self, P: GrowingPredicates2, geo: SegmentGeometry) -> None:
        self.P = P
        self.geo = geo
        self._n_input = geo.n_input
        self._small: dict[tuple[int, int], bool] = {}
        self._sharp: dict[tuple[int, int, int], bool] = {}
        self._placement: dict[int, tuple[tuple[int, float], ...]] = {}
        self._exempt: dict[tuple[int, int], bool] = {}

    def exempt_edge(self, p: int, q: int) -> bool:
        """Whether edge ``pq`` joins two split points on different segments, equidistant from their common endpoint.

        Memoised: the answer depends on ``p`` and ``q`` alone (their segments and shells are recorded when they are
        made, before any triangle of theirs is judged, and never change)."""
        on = self.geo.on_segment
        sp, sq = on.get(p), on.get(q)
        if sp is None or sq is None or sp[0] == sq[0]:
            return False
        key = (p, q)  # vertices are ints: equal to their labels and hashed alike
        found = self._exempt.get(key)
        if found is None:
            found = self._exempt[key] = self._exempt_split_points(p, q, sp[0], sq[0])
        return found

    def _exempt_split_points(self, p: int, q: int, s1: int, s2: int) -> bool:
        """:meth:`exempt_edge` for split points ``p`` on segment ``s1`` and ``q`` on segment ``s2 != s1``."""
        ends_p, ends_q = self.geo.ends[s1], self.geo.ends[s2]
        for o in ends_p:
            if o not in ends_q:
                continue
            # Only at a small input angle (below 60°): elsewhere Ruppert's argument needs no exemption.
            if not self._sharp_pair(o, s1, s2):
                continue
            shp, shq = self.geo.shell.get(p), self.geo.shell.get(q)
            if shp is not None and shp == shq and shp[0] == o:
                return True
            # Triangle's test, decided exactly (float stage first): squared distances within a factor 1.001.
            if equidistant(self.P, o, p, q):
                return True
        return False

    def _sharp_pair(self, o: int, s1: int, s2: int) -> bool:
        """Whether segments ``s1`` and ``s2``, both ending at input vertex ``o``, meet there at less than 60° (exact;
        memoised: a property of the input)."""
        key = (int(o), s1, s2)
        found = self._sharp.get(key)
        if found is None:
            e1, e2 = self.geo.ends[s1], self.geo.ends[s2]
            far1, far2 = e1[1] if e1[0] == o else e1[0], e2[1] if e2[0] == o else e2[0]
            (io, ip, iq), _ = self.P.integers(o, far1, far2)
            d1, d2 = (ip[0] - io[0], ip[1] - io[1]), (iq[0] - io[0], iq[1] - io[1])
            found = not angle_at_least(d1[0] * d2[0] + d1[1] * d2[1], d1[0] ** 2 + d1[1] ** 2, d2[0] ** 2 + d2[1] ** 2, 60.0)
            self._sharp[key] = found
        return found

    def small_angle(self, o: int, s: int) -> bool:
        """:func:`~persistri.impl.mesh.splitting.small_angle_at`, memoised (a Steiner vertex is no input vertex:
        False at once)."""
        if o >= self._n_input:
            return False
        key = (int(o), s)
        found = self._small.get(key)
        if found is None:
            found = self._small[key] = small_angle_at(self.P, self.geo, int(o), s)
        return found

    def tolerances(self, s: int) -> tuple[tuple[int, float], ...]:
        """:func:`~persistri.impl.mesh.splitting.placement_tolerances` of segment ``s``, memoised."""
        found = self._placement.get(s)
        if found is None:
            found = self._placement[s] = placement_tolerances(self.P, self.geo, s, small=self.small_angle)
        return found
