"""What a refinement run did and kept: its counts, its versions, and the points it tried and dropped (paper §1).

The paper's point about Ruppert's refinement is that its undo is a *return to
an older version*: a circumcentre that would encroach a subsegment is not
repaired away, the refinement simply goes on from the version before it, which
persistence kept.  The run records it.  Each :class:`Undone` names the version
the point was tried on (and that the run went on from), the point, the bad
triangle it was meant to split, the subsegments it encroached, and the
versions in which those subsegments were split instead (with the free
vertices Chew's rule deleted there).  A :class:`Blocked` point — one that a
segment separated from its triangle, so that it was never inserted — is
recorded the same way.  :class:`~persistri.impl.mesh.api.MeshHistory` hands
them out as ``history.undone`` and ``history.blocked``.

Point and vertex numbers are indices in the run's append-only point set (the
labels of the complex's vertices; :attr:`~persistri.impl.mesh.api.MeshArrays.points`
maps a version's output rows to them); version numbers index the history.
Building the record costs O(1) per dropped point and per split during the run; the records themselves
(:meth:`DropLog.records`) are made when they are first read, O(records).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from persistri.impl.complex.structure import Complex
from persistri.impl.mesh.triangulation import Constraint, MeshDatum

__all__ = ["Counts", "Refinement", "Undone", "Blocked", "DropLog"]

Triangle3 = tuple[int, int, int]
"""A triangle as three point indices, counterclockwise."""


@dataclass
class Counts:
    """What a refinement did.

    * ``insertions`` — accepted insertions (= new versions), ``segment_splits +
      circumcenters + offcenters``;
    * ``undos`` — insertions made and then dropped because the new point
      encroached a subsegment (the paper's undo by persistence);
    * ``blocked`` — circumcentres or off-centres not inserted because a segment
      stood between them and their triangle (the segment was split instead);
    * ``deletions`` — free vertices deleted from a subsegment's diametral circle
      before it was split (Chew's rule, with lenses);
    * ``exempt`` — bad-angle triangles left alone at small input angles;
    * ``rounded_splits`` — split points not exactly on their input segment (``exact_segments=False``,
      the default): rounded to the nearest doubles where no double lies on the subsegment (or none near
      enough the place a small input angle needs), or on a
      piece of the chain that ends at such a point; ``rounded_segments`` — the input segments they split;
      ``rounding_retries`` — rounded split points inserted and dropped because their version was not a valid
      mesh (a flat or inverted triangle), before a nearby double that makes one.
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
    deletions: int = 0
    rounding_retries: int = 0


@dataclass(frozen=True, slots=True)
class Undone:
    """An insertion made and dropped: the refinement returned to ``history[version]``, which it was made from.

    * ``version`` — the version the point was inserted into, and the one the run went on from;
    * ``point``, ``xy`` — the point (index in the run's point set) and its coordinates;
    * ``triangle`` — the bad triangle of ``history[version]`` it was to split; ``offcenter`` — whether it was
      that triangle's off-centre (else its circumcentre);
    * ``encroached`` — the subsegments ``(lo, hi, segment)`` of ``history[version]`` on its cavity's boundary
      whose diametral lens (or circle, with ``encroachment="circle"``) holds it, exactly;
    * ``cavity`` — the finite triangles of ``history[version]`` its insertion replaced;
    * ``split_at`` — per encroached subsegment, the version whose insertion split it (the first version in which
      it is no longer a subsegment), or None if the run stopped first (``max_steiner``);
    * ``deleted`` — the free vertices Chew's rule deleted in those splits (usually none).
    """

    version: int
    point: int
    xy: tuple[float, float]
    triangle: Triangle3
    offcenter: bool
    encroached: tuple[Constraint, ...]
    cavity: tuple[Triangle3, ...]
    split_at: tuple[int | None, ...]
    deleted: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class Blocked:
    """A point never inserted: a segment lay between it and its bad triangle in ``history[version]`` (or it lay on one).

    ``segment`` is the subsegment ``(lo, hi, segment)`` split instead (``segment`` the input segment's index);
    ``split_at`` the version whose insertion split it (None if the run stopped first); the other fields as in
    :class:`Undone`.
    """

    version: int
    point: int
    xy: tuple[float, float]
    triangle: Triangle3
    offcenter: bool
    segment: Constraint
    split_at: int | None


class DropLog:
    """The record being built during a run: dropped points now, the versions that split their subsegments later.

    A run hands in what it has at hand (its vertices, its cavity); :meth:`records` turns it into the records, as
    point indices, once, when they are first read (``history.undone``): a run whose records nobody reads never
    builds them."""

    def __init__(self) -> None:
        self._undone: list[
            tuple[int, int, tuple[float, float], Sequence[int], bool, Sequence[Constraint], Mapping[int, tuple[Sequence[int], MeshDatum]]]
        ] = []
        self._blocked: list[tuple[int, int, tuple[float, float], Triangle3, bool, Constraint]] = []
        self._waiting: dict[tuple[int, int], list[tuple[bool, int]]] = {}
        self._split: dict[tuple[int, int], tuple[int, tuple[int, ...]]] = {}
        self._records: tuple[tuple[Undone, ...], tuple[Blocked, ...]] | None = None

    def undone(
        self,
        version: int,
        point: int,
        xy: tuple[float, float],
        triangle: Sequence[int],
        offcenter: bool,
        encroached: Sequence[Constraint],
        cavity: Mapping[int, tuple[Sequence[int], MeshDatum]],
    ) -> None:
        """Record an undone insertion: ``triangle`` its bad triangle, ``encroached`` the subsegments it encroached
        (``(lo, hi, segment)``), ``cavity`` its cavity's triangles with their data by id (ghosts among them), each
        kept as given (not changed afterwards) and read as point indices by :meth:`records`. O(len(encroached))."""
        k = len(self._undone)
        self._undone.append((version, point, xy, triangle, offcenter, encroached, cavity))
        for lo, hi, _ in encroached:
            self._waiting.setdefault((lo, hi), []).append((True, k))

    def blocked(
        self, version: int, point: int, xy: tuple[float, float], triangle: Triangle3, offcenter: bool, segment: Constraint
    ) -> None:
        """Record a blocked point. O(1)."""
        k = len(self._blocked)
        self._blocked.append((version, point, xy, triangle, offcenter, segment))
        self._waiting.setdefault((segment[0], segment[1]), []).append((False, k))

    def split(self, lo: int, hi: int, version: int, deleted: tuple[int, ...]) -> None:
        """The subsegment ``{lo, hi}`` was split, making ``version`` (``deleted``: Chew's deletions in that step). O(1)."""
        if (lo, hi) in self._waiting:
            self._split[(lo, hi)] = (version, deleted)

    def records(self) -> tuple[tuple[Undone, ...], tuple[Blocked, ...]]:
        """The finished records (made on the first call, once the run has ended). O(records)."""
        if self._records is not None:
            return self._records
        undone = []
        for version, point, xy, triangle, off, raw, cavity in self._undone:
            encroached = tuple((int(lo), int(hi), s) for lo, hi, s in raw)
            at = [self._split.get((lo, hi)) for lo, hi, _ in encroached]
            deleted = tuple(dict.fromkeys(v for found in at if found is not None for v in found[1]))
            finite = tuple((int(a), int(b), int(e)) for (a, b, e), _ in cavity.values() if min(a, b, e) >= 0)
            tri = (int(triangle[0]), int(triangle[1]), int(triangle[2]))
            undone.append(
                Undone(version, point, xy, tri, off, encroached, finite, tuple(f[0] if f else None for f in at), deleted)
            )
        blocked = []
        for version, point, xy, triangle3, off, segment in self._blocked:
            found = self._split.get((segment[0], segment[1]))
            blocked.append(Blocked(version, point, xy, triangle3, off, segment, found[0] if found else None))
        self._records = (tuple(undone), tuple(blocked))
        return self._records


@dataclass
class Refinement:
    """The result of a run: ``versions[k]`` is the mesh after ``k`` steps (``versions[0]`` the start);
    ``inserted[k - 1]`` the point inserted to make version ``k`` and ``deleted[k - 1]`` the free vertices deleted
    in that step (before a split); ``angle_reached`` / ``area_reached`` whether every domain triangle of the last
    version meets the angle bound (exempt ones excepted) / the area bounds, decided exactly (False only when
    ``max_steiner`` stopped the run); ``undone`` / ``blocked`` the points tried and dropped."""

    versions: list[Complex[MeshDatum]]
    inserted: list[int]
    counts: Counts
    angle_reached: bool
    area_reached: bool
    exempt: set[int] = field(default_factory=set)
    """Ids of the last version's exempt triangles."""
    deleted: list[tuple[int, ...]] = field(default_factory=list)
    log: DropLog = field(default_factory=DropLog)
    """The run's record of the points it dropped (:attr:`undone`, :attr:`blocked`)."""

    @property
    def undone(self) -> tuple[Undone, ...]:
        """The insertions undone (:meth:`DropLog.records`)."""
        return self.log.records()[0]

    @property
    def blocked(self) -> tuple[Blocked, ...]:
        """The points blocked by a segment (:meth:`DropLog.records`)."""
        return self.log.records()[1]
