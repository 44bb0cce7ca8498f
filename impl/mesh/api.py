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

The result's classes are :mod:`~persistri.impl.mesh.result` (:class:`QualityMesh`,
:class:`MeshHistory`), the read-out of a version :mod:`~persistri.impl.mesh.readout`
(:class:`MeshArrays`) and the checks of the arguments :mod:`~persistri.impl.mesh.options`;
all are importable from here.

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

from collections.abc import Callable, Mapping
from fractions import Fraction
from typing import Any

import numpy as np

from persistri.impl.collector import collector_paused
from persistri.impl.complex.structure import Complex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.maps import backend as map_backend
from persistri.impl.mesh.cdt import constrained_delaunay
from persistri.impl.mesh.domain import PSLG
from persistri.impl.mesh.options import area_bound, as_domain, refinement_options
from persistri.impl.mesh.quality import AngleBound
from persistri.impl.mesh.readout import MeshArrays, Run
from persistri.impl.mesh.record import Counts
from persistri.impl.mesh.result import MeshHistory, QualityMesh, finish, smallest_angle
from persistri.impl.mesh.ruppert import Refiner
from persistri.impl.mesh.steiner import offcenter_constant
from persistri.impl.mesh.triangulation import MeshDatum, MeshTriangulation
from persistri.impl.progress import progress_callback

__all__ = ["QualityMesh", "MeshHistory", "MeshArrays", "triangulate", "refine", "smallest_angle"]


def _refine_run(
    run: Run,
    start: Complex[MeshDatum],
    bound: AngleBound,
    area: Fraction | None,
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
    """Refine ``start`` of ``run`` under arguments already checked (``area`` is ``max_area`` exactly)."""
    regs = run.domain.regions
    region_area = {r + 1: Fraction(float(regs[r, 3])) for r in range(regs.shape[0]) if regs[r, 3] > 0} if region_areas else {}
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
    mesh = finish(
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
        log=result.log,
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


def triangulate(
    domain: PSLG | Mapping[str, Any],
    *,
    min_angle: float = 0.0,
    max_area: float | None = None,
    region_areas: bool = False,
    backend: str = "int_trie",
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
    * ``backend`` — the ``ORD_MAP`` backend of the complex (the mesh's vertex ids are dense from 0:
      the integer trie, ``persistri.impl.maps.int_trie``, by default);
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
    refinement_options(  # checked even when no refinement runs
        max_steiner, encroachment, check=check, offcenters=offcenters, exact_segments=exact_segments,
        region_areas=region_areas,
    )
    pslg, pred = as_domain(domain)
    bound = AngleBound.of(min_angle)
    area = area_bound(max_area)
    if pred is None:
        pred = GrowingPredicates2(pslg.vertices)
    structure: TwoComplex[MeshDatum] = TwoComplex(map_backend(backend))
    T = MeshTriangulation(pred, structure)
    with collector_paused():
        cdt, geo = constrained_delaunay(T, pslg)
    run = Run(T, geo, pslg)
    if bound.degrees == 0.0 and max_area is None and not (region_areas and bool(np.any(pslg.regions[:, 3] > 0))):
        mesh = finish(run, [cdt], [], Counts(), True, 0.0, None, True, bool(exact_segments))
        if check:
            _check(mesh)
        return mesh
    return _refine_run(
        run,
        cdt,
        bound,
        area,
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
    bound = AngleBound.of(min_angle)
    area = area_bound(max_area)
    refinement_options(
        max_steiner, encroachment, check=check, offcenters=offcenters, exact_segments=exact_segments,
        region_areas=region_areas,
    )
    return _refine_run(
        mesh._run,
        mesh.complex,
        bound,
        area,
        max_area,
        region_areas=region_areas,
        offcenters=offcenters,
        max_steiner=max_steiner,
        progress=progress,
        check=check,
        encroachment=encroachment,
        exact_segments=exact_segments,
    )
