"""What :func:`~persistri.impl.mesh.api.triangulate` and :func:`~persistri.impl.mesh.api.refine` return (paper §1).

A :class:`QualityMesh` holds the last version of a refinement read back as numpy
arrays, in the style of ``triangle.triangulate``, the counts of what the
refinement did, and the whole :class:`MeshHistory`: every version, oldest first,
each a persistent complex sharing structure with the others (O(lg n) map nodes
per changed vertex, not a copy each), with the points each step inserted and
deleted and the points the run tried and dropped
(:mod:`~persistri.impl.mesh.record`).  :func:`finish` makes one from a run's
outcome; :func:`smallest_angle` is the floating-point angle report.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.complex.versions import Versions
from persistri.impl.mesh.domain import PSLG
from persistri.impl.mesh.readout import IntArray, MeshArrays, Run, mesh_arrays
from persistri.impl.mesh.record import Blocked, Counts, DropLog, Undone
from persistri.impl.mesh.triangulation import MeshDatum

__all__ = ["MeshHistory", "QualityMesh", "finish", "smallest_angle"]


class MeshHistory(Versions[MeshDatum]):
    """Every version of one refinement, oldest first: ``history[k]`` is the complex after ``k`` insertions.

    ``history[0]`` is the version the run started from (the CDT, or the mesh
    :func:`refine` continued); ``inserted[k - 1]`` the point index inserted to
    make version ``k``, and ``deleted[k - 1]`` the free vertices deleted in the same
    step, before a segment split (Chew's rule; usually none); :meth:`mesh` reads a
    version back as arrays.  The versions share structure: keeping all of them
    costs O(lg n) map nodes per changed vertex, not a copy each.

    The points the run tried and dropped are recorded too
    (:mod:`~persistri.impl.mesh.record`): ``undone`` — each insertion undone by
    returning to the version it was made from (:class:`~persistri.impl.mesh.record.Undone`:
    that version, the point, the subsegments it encroached and the versions that
    split them instead), one per :attr:`QualityMesh.undos`; ``blocked`` — each
    point a segment kept from its triangle (:class:`~persistri.impl.mesh.record.Blocked`).
    Points are indices in the run's point set, read with :meth:`point`.  Both are made from the run's log when
    first read (a run whose records nobody reads never builds them).
    """

    undone: tuple[Undone, ...]
    blocked: tuple[Blocked, ...]

    def __init__(
        self,
        run: Run,
        versions: list[Complex[MeshDatum]],
        inserted: list[int],
        deleted: list[tuple[int, ...]] | None = None,
        undone: tuple[Undone, ...] = (),
        blocked: tuple[Blocked, ...] = (),
        log: DropLog | None = None,
    ) -> None:
        self._run = run
        self.versions: tuple[Complex[MeshDatum], ...] = tuple(versions)
        self.inserted: tuple[int, ...] = tuple(inserted)
        self.deleted: tuple[tuple[int, ...], ...] = tuple(deleted) if deleted is not None else ((),) * len(inserted)
        if log is None:
            self.undone = undone
            self.blocked = blocked
        else:
            self._log = log  # undone and blocked are read from it when first asked for (__getattr__)

    def __getattr__(self, name: str) -> Any:
        # Only for attributes not set: undone and blocked of a history made with a log, made on the first read (each
        # set alone stays as set).
        log = self.__dict__.get("_log")
        if log is None or name not in ("undone", "blocked"):
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        undone, blocked = log.records()
        self.__dict__.setdefault("undone", undone)
        self.__dict__.setdefault("blocked", blocked)
        return self.__dict__[name]

    @property
    def structure(self) -> TwoComplex[MeshDatum]:
        """The structure that reads the versions."""
        return self._run.T.S

    def mesh(self, k: int) -> MeshArrays:
        """Version ``k`` as arrays (domain triangles, counterclockwise; segments; regions). O(size)."""
        return mesh_arrays(self._run, self.versions[k])

    def point(self, i: int) -> tuple[float, float]:
        """The coordinates of point ``i`` of the run's point set (kept, dropped or an input vertex). O(1)."""
        return self._run.T.pred.xy(i)


@dataclass(frozen=True, eq=False)
class QualityMesh:
    """A mesh of a planar domain and the history that made it (:mod:`~persistri.impl.mesh.api`).

    * ``vertices`` — ``(N, 2)`` float64: the domain's vertices first, in their rows,
      then the Steiner points (every one lies exactly where it is: split points
      exactly on their segment);
    * ``triangles`` — ``(T, 3)`` rows of ``vertices``, counterclockwise, the domain's
      triangles only (holes and concavities eaten away);
    * ``segments`` — ``(S, 2)``: the mesh edges that lie on input segments, and
      ``segment_of`` — the input segment of each;
    * ``regions`` — ``(T,)``: the region of each triangle (0: none; ``r + 1``: the
      region of ``domain.regions[r]``);
    * ``insertions``, ``segment_splits``, ``circumcenters``, ``offcenters`` — what the
      refinement inserted; ``undos`` — circumcentres inserted and then dropped
      by returning to the previous version (they encroached a subsegment);
      ``deletions`` — circumcentres deleted later, from the diametral circle of a
      subsegment about to be split (Chew's rule, with lenses: Triangle's default);
      ``blocked`` — ones not inserted (a segment lay between); ``exempt`` —
      triangles left below the angle bound at small input angles; ``rounded_splits`` —
      split points rounded to the nearest doubles because no double lies exactly on
      their subsegment, or none near enough the place a small input angle needs the split
      at (:func:`~persistri.impl.mesh.splitting.placement_tolerances`) (never with
      ``exact_segments=True``; such a mesh passes
      ``verify_mesh(..., exact_segments=False)``, one with none passes with ``True``);
      ``rounding_retries`` — rounded split points whose version was not a valid mesh (a
      flat or inverted triangle near a vertex close to the segment), dropped for the next
      nearby double (:func:`~persistri.impl.mesh.splitting.rounded_candidates`);
    * ``min_angle`` / ``max_area`` — the bounds asked; ``min_angle_reached`` /
      ``max_area_reached`` — whether every domain triangle meets them (exempt
      ones excepted for the angle), decided exactly;
    * ``history`` — every version (:class:`MeshHistory`); ``domain`` the PSLG;
    * ``notes`` — one line per thing a user should know about the result (rounded
      split points: how many, on which segments).
    """

    vertices: NDArray[np.float64]
    triangles: IntArray
    segments: IntArray
    segment_of: IntArray
    regions: IntArray
    domain: PSLG
    history: MeshHistory
    min_angle: float
    max_area: float | None
    min_angle_reached: bool
    max_area_reached: bool
    insertions: int
    segment_splits: int
    circumcenters: int
    offcenters: int
    undos: int
    blocked: int
    exempt: int
    rounded_splits: int
    exact_segments: bool
    _run: Run
    notes: tuple[str, ...] = ()
    deletions: int = 0
    rounding_retries: int = 0
    points: IntArray | None = None
    """The index in the run's point set of each row of ``vertices`` (``history.mesh(-1).points``)."""

    @property
    def complex(self) -> Complex[MeshDatum]:
        """The last version."""
        return self.history[-1]

    def smallest_angle(self) -> float:
        """The smallest angle over the domain's triangles, in degrees (floating point: for reports). O(T)."""
        return smallest_angle(self.vertices, self.triangles)


def smallest_angle(vertices: NDArray[np.float64], triangles: IntArray) -> float:
    """The smallest interior angle of ``triangles`` in degrees, in floating point (reports only; 60 for none)."""
    if triangles.size == 0:
        return 60.0
    p = vertices[triangles]
    best = 180.0
    for k in range(3):
        a, b, c = p[:, k], p[:, (k + 1) % 3], p[:, (k + 2) % 3]
        u, w = b - a, c - a
        # scaled by a power of two (exact) to a largest component in [0.5, 1): near 1e-300 the products
        # below underflow to 0 and arctan2(0, ±0) reads 0° or 180° (angles do not depend on scale)
        shift = np.frexp(np.maximum(np.abs(u).max(axis=1), np.abs(w).max(axis=1)))[1][:, None]
        u, w = np.ldexp(u, -shift), np.ldexp(w, -shift)
        cross = np.abs(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0])
        dot = (u * w).sum(axis=1)
        best = min(best, float(np.degrees(np.arctan2(cross, dot)).min()))
    return best


def finish(
    run: Run,
    versions: list[Complex[MeshDatum]],
    inserted: list[int],
    counts: Counts,
    reached: bool,
    min_angle: float,
    max_area: float | None,
    area_reached: bool,
    exact_segments: bool = False,
    deleted: list[tuple[int, ...]] | None = None,
    undone: tuple[Undone, ...] = (),
    blocked: tuple[Blocked, ...] = (),
    log: DropLog | None = None,
) -> QualityMesh:
    """The :class:`QualityMesh` of a run's versions and counts: the last version read back, the history, the notes.

    O(size of the last version) for the read-out (:func:`~persistri.impl.mesh.readout.mesh_arrays`).
    """
    history = MeshHistory(run, versions, inserted, deleted, undone, blocked, log)
    arr = mesh_arrays(run, versions[-1])
    notes: list[str] = []
    if counts.rounded_splits:
        segs = sorted(counts.rounded_segments)
        notes.append(
            f"{counts.rounded_splits} split point{'s' if counts.rounded_splits > 1 else ''} within an ulp of "
            f"segment{'s' if len(segs) > 1 else ''} {', '.join(map(str, segs))}, not on it: no double lies exactly "
            "there (or none near enough the place a small input angle needs), so they were rounded to the nearest "
            "doubles (check with verify_mesh(..., exact_segments=False))"
        )
    return QualityMesh(
        vertices=arr.vertices,
        triangles=arr.triangles,
        segments=arr.segments,
        segment_of=arr.segment_of,
        regions=arr.regions,
        domain=run.domain,
        history=history,
        min_angle=min_angle,
        max_area=max_area,
        min_angle_reached=reached,
        max_area_reached=area_reached,
        insertions=counts.insertions,
        segment_splits=counts.segment_splits,
        circumcenters=counts.circumcenters,
        offcenters=counts.offcenters,
        undos=counts.undos,
        blocked=counts.blocked,
        exempt=counts.exempt,
        rounded_splits=counts.rounded_splits,
        exact_segments=exact_segments,
        _run=run,
        notes=tuple(notes),
        deletions=counts.deletions,
        rounding_retries=counts.rounding_retries,
        points=arr.points,
    )
