"""Quality meshes of planar domains, every step a version: :func:`triangulate` and :func:`refine` (paper §1).

``triangulate(domain, min_angle=30)`` builds the constrained Delaunay
triangulation of a PSLG (:mod:`~persistri.impl.mesh.cdt`) and refines it
(:mod:`~persistri.impl.mesh.ruppert`); ``min_angle=0`` and no area bound give
the plain CDT.  The result, a :class:`QualityMesh`, holds numpy arrays in the
style of ``triangle.triangulate`` and its whole **history**: ``mesh.history[k]``
is the persistent complex after ``k`` insertions, sharing structure with the
others, and ``mesh.history.mesh(k)`` reads it back as arrays.

``refine(mesh, min_angle=…, max_area=…)`` continues from a mesh's last version
as *another future*: refining one CDT twice, with different bounds, gives two
meshes whose histories start at the same version, and every version of both
stays valid (no version is ever changed; the point set they draw their new
points from is append-only, so a point index means one point in every future).

>>> import numpy as np
>>> from persistri.impl.mesh.domain import as_pslg
>>> square = as_pslg([[0, 0], [4, 0], [4, 4], [0, 4]], [[0, 1], [1, 2], [2, 3], [3, 0]])
>>> cdt = triangulate(square)
>>> cdt.triangles.shape, len(cdt.history)
((2, 3), 1)
>>> fine = refine(cdt, min_angle=30, max_area=1.0)
>>> fine.min_angle_reached, fine.max_area_reached, len(fine.history) == fine.insertions + 1
(True, True, True)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from itertools import chain
from operator import itemgetter
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import NDArray

from persistri.impl.collector import collector_paused
from persistri.impl.complex.structure import Complex
from persistri.impl.complex.versions import Versions
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.flags import flag
from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.maps import backend as map_backend
from persistri.impl.mesh.cdt import SegmentGeometry, constrained_delaunay
from persistri.impl.mesh.domain import PSLG, validate, validate_dict
from persistri.impl.mesh.quality import AngleBound
from persistri.impl.mesh.record import Blocked, Counts, Undone
from persistri.impl.mesh.ruppert import Refiner
from persistri.impl.mesh.steiner import offcenter_constant
from persistri.impl.mesh.triangulation import EXTERIOR, MeshDatum, MeshTriangulation
from persistri.impl.progress import progress_callback

__all__ = ["QualityMesh", "MeshHistory", "MeshArrays", "triangulate", "refine"]

IntArray = NDArray[np.intp]


@dataclass(frozen=True, eq=False)
class MeshArrays:
    """One version read back as arrays (the :class:`QualityMesh` fields of the same names).

    ``points[k]`` is the point index (in the run's append-only point set) of output vertex ``k``.
    """

    vertices: NDArray[np.float64]
    triangles: IntArray
    segments: IntArray
    segment_of: IntArray
    regions: IntArray
    points: IntArray


@dataclass(frozen=True, eq=False)
class _Run:
    """What every future of one CDT shares: the triangulation (predicates, structure, vertices) and the segments."""

    T: MeshTriangulation
    geo: SegmentGeometry
    domain: PSLG


def _arrays(run: _Run, c: Complex[MeshDatum]) -> MeshArrays:
    """Version ``c`` as arrays: the input vertices first (rows kept), then the Steiner vertices present, by index."""
    items = run.T.S.items(c)
    n = run.geo.n_input
    # Every triangle's labels (ghosts' -1 too) and region in one pass each, as arrays (a vertex is an int).
    labels = np.fromiter(chain.from_iterable([t for t, _ in items]), dtype=np.intp, count=3 * len(items)).reshape(-1, 3)
    region_of = np.fromiter([d[1] for _, d in items], dtype=np.intp, count=len(items))
    # The input vertices (every row kept), then the Steiner points present, by index: a mask over the point set (the
    # ghosts' label -1 marks its extra last slot), not np.unique's hash and sort.
    present = np.zeros(len(run.T.pred) + 1, dtype=bool)
    present[labels] = True
    present[:n] = True
    points = np.flatnonzero(present[:-1])
    index = np.full(len(run.T.pred), -1, dtype=np.intp)
    index[points] = np.arange(points.size)
    inside = region_of != EXTERIOR
    segs: dict[tuple[int, int], int] = {}
    for _, d in items:
        if d[2]:
            for lo, hi, s in d[2]:
                segs[(lo, hi)] = s
    seg_rows = sorted(segs.items(), key=itemgetter(1, 0))  # by (segment, edge); the key made in C
    ns = len(seg_rows)
    return MeshArrays(
        vertices=np.array(run.T.pred.points[points], dtype=np.float64),
        triangles=index[labels[inside]],
        segments=index[np.fromiter(chain.from_iterable([k for k, _ in seg_rows]), dtype=np.intp, count=2 * ns).reshape(-1, 2)],
        segment_of=np.fromiter([s for _, s in seg_rows], dtype=np.intp, count=ns),
        regions=region_of[inside],
        points=points,
    )


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
    Points are indices in the run's point set, read with :meth:`point`.
    """

    def __init__(
        self,
        run: _Run,
        versions: list[Complex[MeshDatum]],
        inserted: list[int],
        deleted: list[tuple[int, ...]] | None = None,
        undone: tuple[Undone, ...] = (),
        blocked: tuple[Blocked, ...] = (),
    ) -> None:
        self._run = run
        self.versions: tuple[Complex[MeshDatum], ...] = tuple(versions)
        self.inserted: tuple[int, ...] = tuple(inserted)
        self.deleted: tuple[tuple[int, ...], ...] = tuple(deleted) if deleted is not None else ((),) * len(inserted)
        self.undone: tuple[Undone, ...] = undone
        self.blocked: tuple[Blocked, ...] = blocked


    @property
    def structure(self) -> TwoComplex[MeshDatum]:
        """The structure that reads the versions."""
        return self._run.T.S

    def mesh(self, k: int) -> MeshArrays:
        """Version ``k`` as arrays (domain triangles, counterclockwise; segments; regions). O(size)."""
        return _arrays(self._run, self.versions[k])

    def point(self, i: int) -> tuple[float, float]:
        """The coordinates of point ``i`` of the run's point set (kept, dropped or an input vertex). O(1)."""
        return self._run.T.pred.xy(i)


@dataclass(frozen=True, eq=False)
class QualityMesh:
    """A mesh of a planar domain and the history that made it (module docstring).

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
    _run: _Run
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


def _as_domain(domain: PSLG | Mapping[str, Any]) -> tuple[PSLG, GrowingPredicates2 | None]:
    """The validated domain, and the predicates its validation made over its vertices (None: it was valid already)."""
    if isinstance(domain, PSLG):
        if domain.vertex_map is not None:
            return domain, None
        return validate(domain.vertices, domain.segments, domain.holes, domain.regions)
    if isinstance(domain, Mapping):
        return validate_dict(domain)
    raise TypeError(f"domain must be a PSLG or a dictionary of arrays, not {type(domain).__name__}")


def _area(max_area: float | None) -> Fraction | None:
    if max_area is None:
        return None
    if isinstance(max_area, bool) or not isinstance(max_area, (int, float)):
        raise TypeError(f"max_area must be a positive real number or None, not {type(max_area).__name__}")
    if not (math.isfinite(max_area) and max_area > 0):
        raise ValueError(f"max_area must be a positive finite number, got {max_area!r}")
    return Fraction(float(max_area))


def _finish(
    run: _Run,
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
) -> QualityMesh:
    history = MeshHistory(run, versions, inserted, deleted, undone, blocked)
    arr = _arrays(run, versions[-1])
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


def _refine_run(
    run: _Run,
    start: Complex[MeshDatum],
    min_angle: float,
    max_area: float | None,
    *,
    region_areas: bool,
    offcenters: bool,
    max_steiner: int | None,
    progress: bool | Callable[[int], Any],
    check: bool,
    encroachment: str,
    exact_segments: bool,
) -> QualityMesh:
    bound = AngleBound.of(min_angle)
    area = _area(max_area)
    _refinement_options(
        max_steiner, encroachment, check=check, offcenters=offcenters, exact_segments=exact_segments,
        region_areas=region_areas,
    )
    regs = run.domain.regions if region_areas else run.domain.regions[:0]
    region_area = {r + 1: Fraction(float(regs[r, 3])) for r in range(regs.shape[0]) if regs[r, 3] > 0}
    refiner = Refiner(
        run.T,
        run.geo,
        bound,
        area,
        region_area,
        offcenter_constant(bound.degrees) if offcenters else 0.0,
        lens=encroachment == "lens",
        exact_segments=bool(exact_segments),
    )
    bar = progress_callback(progress, "refining", None, batch=64)
    try:
        with collector_paused():
            result = refiner.run(start, max_steiner=max_steiner, progress=bar)
    finally:
        if bar is not None and hasattr(bar, "close"):
            bar.close()
    mesh = _finish(
        run,
        result.versions,
        result.inserted,
        result.counts,
        result.angle_reached,
        bound.degrees,
        max_area,
        result.area_reached,
        exact_segments,
        result.deleted,
        result.undone,
        result.blocked,
    )
    if check:
        _check(mesh)
    return mesh


def _check(mesh: QualityMesh) -> None:
    """``check=True``: the independent exact checker, with exact segments unless split points were rounded."""
    from persistri.impl.mesh.verify import verify_mesh  # the independent checker: imported only when asked for

    report = verify_mesh(
        mesh.domain,
        mesh.vertices,
        mesh.triangles,
        min_angle=mesh.min_angle or None,
        max_area=mesh.max_area,
        exact_segments=mesh.exact_segments or mesh.rounded_splits == 0,
    )
    if not report.ok:
        first = report.problems[0]
        raise AssertionError(f"check=True: the mesh fails the exact checker ({len(report.problems)} problems; first: {first})")


def _refinement_options(max_steiner: object, encroachment: object, **flags: object) -> None:
    """Raise :class:`ValueError` for a ``max_steiner`` or ``encroachment`` that :func:`triangulate` and
    :func:`refine` do not take, and :class:`TypeError` for a yes/no argument (``flags``, by name) that is
    not a bool (:func:`~persistri.impl.flags.flag`). O(1)."""
    for name, value in flags.items():
        flag(name, value)
    if max_steiner is not None and (isinstance(max_steiner, bool) or not isinstance(max_steiner, int) or max_steiner < 0):
        raise ValueError(f"max_steiner must be a nonnegative integer or None, got {max_steiner!r}")
    if encroachment not in ("lens", "circle"):
        raise ValueError(f"encroachment must be 'lens' (Chew's, Triangle's default) or 'circle' (Ruppert's), not {encroachment!r}")


def triangulate(
    domain: PSLG | Mapping[str, Any],
    *,
    min_angle: float = 0.0,
    max_area: float | None = None,
    region_areas: bool = False,
    backend: str = "red_black",
    check: bool = False,
    progress: bool | Callable[[int], Any] = False,
    offcenters: bool = True,
    max_steiner: int | None = None,
    encroachment: str = "lens",
    exact_segments: bool = False,
) -> QualityMesh:
    """A quality mesh of ``domain`` (a :class:`PSLG`, or ``triangle.triangulate``'s dictionary): module docstring.

    * ``min_angle`` — the smallest angle wanted, degrees in ``[0, 60)`` (0: none;
      20.7 is the bound Ruppert's theory guarantees; Triangle's users ask 20–34);
    * ``max_area`` — the largest triangle area wanted (None: none);
    * ``region_areas`` — also the area bounds of ``domain``'s regions
      (``domain.regions[:, 3] > 0``), each inside its region: Triangle's ``-a``
      without a number.  Off by default, as in Triangle, so that a ``.poly`` with
      regional bounds meshed at ``min_angle=0`` is its constrained Delaunay triangulation;
    * ``backend`` — the ``ORD_MAP`` backend of the complex;
    * ``check`` — run the independent exact checker on the result (:mod:`~persistri.impl.mesh.verify`);
    * ``progress`` — a progress bar (or a callable taking step counts);
    * ``offcenters`` — Üngör's off-centres (fewer triangles) or circumcentres only;
    * ``max_steiner`` — stop after this many Steiner points (Triangle's ``-S``);
    * ``encroachment`` — ``"lens"`` (Chew's algorithm, Triangle's default: diametral
      lenses, and free vertices deleted from a subsegment's diametral circle before it
      is split; fewer triangles) or ``"circle"`` (Ruppert's diametral circles, no
      deletion: Triangle's ``-D``);
    * ``exact_segments`` — False (the default): a split point lies exactly on its segment
      wherever a double does near the wanted place (on a segment at a small input angle
      ``α``: within ``min(α²/4, 2^-12)`` of its distance from the apex,
      :func:`~persistri.impl.mesh.splitting.placement_tolerances`); on a subsegment where
      none does (ends given to the
      centimetre at UTM offsets, say) it is rounded to the nearest doubles, as Triangle's
      are, counted in ``rounded_splits`` and said in ``notes``; such a mesh passes
      ``verify_mesh(..., exact_segments=False)``, and one with ``rounded_splits == 0``
      passes with ``exact_segments=True``.  True (strict): a subsegment on which no
      double lies is a :class:`~persistri.impl.mesh.steiner.PrecisionLimitError`.

    With ``min_angle=0`` and no area bound the result is the constrained
    Delaunay triangulation (history of one version).  Errors, one line each:
    :class:`~persistri.impl.mesh.domain.DomainError` for a bad domain,
    :class:`ValueError` for bad bounds, :class:`~persistri.impl.mesh.steiner.PrecisionLimitError`
    when a new point would need more precision than doubles have (in strict mode, also
    a split on a subsegment with no double on it).  Expected
    O(n log n) for the CDT, then O(lg n) complex work per insertion.
    """
    _refinement_options(  # checked even when no refinement runs
        max_steiner, encroachment, check=check, offcenters=offcenters, exact_segments=exact_segments,
        region_areas=region_areas,
    )
    pslg, pred = _as_domain(domain)
    bound = AngleBound.of(min_angle)
    _area(max_area)
    if pred is None:
        pred = GrowingPredicates2(pslg.vertices)
    structure: TwoComplex[MeshDatum] = TwoComplex(map_backend(backend))
    T = MeshTriangulation(pred, structure)
    with collector_paused():
        cdt, geo = constrained_delaunay(T, pslg)
    run = _Run(T, geo, pslg)
    if bound.degrees == 0.0 and max_area is None and not (region_areas and bool(np.any(pslg.regions[:, 3] > 0))):
        mesh = _finish(run, [cdt], [], Counts(), True, 0.0, None, True, bool(exact_segments))
        if check:
            _check(mesh)
        return mesh
    return _refine_run(
        run,
        cdt,
        bound.degrees,
        max_area,
        region_areas=region_areas,
        offcenters=offcenters,
        max_steiner=max_steiner,
        progress=progress,
        check=check,
        encroachment=encroachment,
        exact_segments=exact_segments,
    )


def refine(
    mesh: QualityMesh,
    *,
    min_angle: float,
    max_area: float | None = None,
    region_areas: bool = False,
    offcenters: bool = True,
    max_steiner: int | None = None,
    progress: bool | Callable[[int], Any] = False,
    check: bool = False,
    encroachment: str = "lens",
    exact_segments: bool = False,
) -> QualityMesh:
    """Refine ``mesh`` further, from its last version, as a new future (module docstring); ``mesh`` is unchanged.

    The new mesh's ``history[0]`` is ``mesh``'s last version.  Arguments as
    :func:`triangulate`.
    """
    if not isinstance(mesh, QualityMesh):
        raise TypeError(f"refine takes a QualityMesh (from triangulate), not {type(mesh).__name__}")
    return _refine_run(
        mesh._run,
        mesh.complex,
        min_angle,
        max_area,
        region_areas=region_areas,
        offcenters=offcenters,
        max_steiner=max_steiner,
        progress=progress,
        check=check,
        encroachment=encroachment,
        exact_segments=exact_segments,
    )
