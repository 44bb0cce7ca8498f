"""Planar straight-line graphs (PSLGs): the domains of quality meshing (Ruppert 1995; Triangle's input).

A :class:`PSLG` is what Shewchuk's Triangle reads from a ``.poly`` file, as
numpy arrays: vertices, segments between them, hole points (a hole is the
region around a hole point bounded by segments) and, optionally, region
points with an attribute and an area bound.  The domain it describes, as in
Triangle: the convex hull of the vertices, less every region reachable from
outside the hull or from a hole point without crossing a segment
("concavities and holes eaten away").  In terms of the segments' faces
(:mod:`~persistri.impl.mesh.faces`): the union of the bounded faces that hold
no hole point, with the segments and vertices between and on them.

:func:`as_pslg` builds a validated PSLG; :meth:`PSLG.from_dict` does the same
from a dictionary in the form ``triangle.triangulate`` takes, and
:meth:`PSLG.to_dict` gives that form back.  :func:`validate` and
:func:`validate_dict` are the same with the exact predicates they built over the
validated vertices (:class:`Validated`), which a mesher can start from.
:func:`~persistri.impl.mesh.domain_faces.domain_of` (importable from here)
computes the domain's faces, which are kept, and its exact area.

Every geometric decision is exact (:class:`~persistri.impl.geometry.growing.GrowingPredicates2`'s
true signs, integer arithmetic): inputs at UTM offsets are decided like small ones.
The paper (§1) motivates the application; the domain model is Triangle's.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Final, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.geometry.points import as_points, unique_rows
from persistri.impl.mesh.domain_faces import Domain, domain_of
from persistri.impl.mesh.errors import DomainError
from persistri.impl.mesh.segments import FEW_SEGMENTS, convex_hull, dedupe, point_text, refuse_crossings, split_at_vertices

__all__ = ["PSLG", "DomainError", "Domain", "Validated", "as_pslg", "domain_of", "validate", "validate_dict"]

_KEYS = ("vertices", "segments", "holes", "regions", "vertex_markers", "segment_markers", "vertex_attributes")

def _no_pairs() -> NDArray[np.intp]:
    return np.zeros((0, 2), dtype=np.intp)


def _no_points() -> NDArray[np.float64]:
    return np.zeros((0, 2), dtype=np.float64)


def _no_regions() -> NDArray[np.float64]:
    return np.zeros((0, 4), dtype=np.float64)


def counted(rows: NDArray[Any], one: str, many: str | None = None) -> str:
    """``"<n> <one>"`` or ``"<n> <many>"`` for an array of ``n`` rows (``many`` defaults to ``one + "s"``)."""
    n = int(rows.shape[0])
    return f"{n} {one}" if n == 1 else f"{n} {many or one + 's'}"


@dataclass(frozen=True, eq=False)
class PSLG:
    """A planar straight-line graph with holes and regions (Triangle's ``.poly`` contents).

    * ``vertices`` — ``(n, 2)`` float64, exact input coordinates;
    * ``segments`` — ``(m, 2)`` intp, pairs of vertex rows (order irrelevant);
    * ``holes`` — ``(h, 2)`` float64, one point strictly inside each hole;
    * ``regions`` — ``(r, 4)`` float64 rows ``(x, y, attribute, max_area)``
      (``max_area <= 0``: no bound), Triangle's regional attributes;
    * ``vertex_markers`` / ``segment_markers`` — ``(n,)`` / ``(m,)`` intp boundary markers
      (Triangle's; 0 when the file gives none);
    * ``vertex_attributes`` — ``(n, k)`` float64, Triangle's vertex attributes, or None;
    * ``notes`` — what :func:`as_pslg` repaired or noticed, one line each (merged
      duplicate vertices, split segments, vertices outside the domain);
    * ``vertex_map`` — for a PSLG from :func:`as_pslg`, the row of ``vertices`` each
      input vertex became (duplicates merge), else None;
    * ``segment_origin`` — for a PSLG from :func:`as_pslg`, the input row each segment comes
      from (a piece of it, where validation split it at a vertex; the first of repeated ones), or
      -1 for a convex hull edge that ``convex=True`` added; else None (the rows are the input's).
      Messages name segments by it (:class:`~persistri.impl.mesh.naming.InputNames`).
      :meth:`to_dict` leaves it out (Triangle's form has no such key): a PSLG read back
      from that dictionary has the hull edges as segments of its own, numbered as listed.

    A ``PSLG`` built directly is NOT validated; :func:`~persistri.impl.mesh.domain.as_pslg`
    builds a validated one (crossing segments, vertices on segment interiors, duplicates,
    holes outside the domain, NaN/inf are clear errors).
    """

    vertices: NDArray[np.float64]
    segments: NDArray[np.intp] = field(default_factory=_no_pairs)
    holes: NDArray[np.float64] = field(default_factory=_no_points)
    regions: NDArray[np.float64] = field(default_factory=_no_regions)
    vertex_markers: NDArray[np.intp] | None = None
    segment_markers: NDArray[np.intp] | None = None
    vertex_attributes: NDArray[np.float64] | None = None
    notes: tuple[str, ...] = ()
    vertex_map: NDArray[np.intp] | None = None
    segment_origin: NDArray[np.intp] | None = None

    def __repr__(self) -> str:
        return f"PSLG({counted(self.vertices, 'vertex', 'vertices')}, {counted(self.segments, 'segment')}, " + (
            f"{counted(self.holes, 'hole')}, {counted(self.regions, 'region')})"
        )

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], *, convex: bool = False, repair: bool = True) -> PSLG:
        """A validated PSLG from ``triangle.triangulate``'s input form (:func:`as_pslg` checks it).

        Keys: ``vertices`` (required), ``segments``, ``holes``, ``regions`` (rows of
        four), ``vertex_markers`` and ``segment_markers`` (``(k,)`` or ``(k, 1)``),
        ``vertex_attributes``.  Any other key is an error naming it.

        >>> PSLG.from_dict({'vertices': [[0, 0], [1, 0], [0, 1]], 'segments': [[0, 1], [1, 2], [2, 0]]})
        PSLG(3 vertices, 3 segments, 0 holes, 0 regions)
        """
        return validate_dict(data, convex=convex, repair=repair).pslg

    def to_dict(self) -> dict[str, NDArray[Any]]:
        """``triangle.triangulate``'s input form: its keys and dtypes, empty arrays left out.

        ``triangle.triangulate(pslg.to_dict(), 'pq30')`` meshes this domain with Triangle.
        """
        out: dict[str, NDArray[Any]] = {"vertices": np.array(self.vertices, dtype=np.float64)}
        if self.segments.size:
            out["segments"] = np.array(self.segments, dtype=np.intc)
        if self.holes.size:
            out["holes"] = np.array(self.holes, dtype=np.float64)
        if self.regions.size:
            out["regions"] = np.array(self.regions, dtype=np.float64)
        if self.vertex_markers is not None:
            out["vertex_markers"] = np.array(self.vertex_markers, dtype=np.intc).reshape(-1, 1)
        if self.segment_markers is not None and self.segments.size:
            out["segment_markers"] = np.array(self.segment_markers, dtype=np.intc).reshape(-1, 1)
        if self.vertex_attributes is not None and self.vertex_attributes.size:
            out["vertex_attributes"] = np.array(self.vertex_attributes, dtype=np.float64)
        return out


# -- input arrays ---------------------------------------------------------------------------


def _int_array(values: ArrayLike, what: str, width: int | None) -> NDArray[np.intp]:
    raw = np.asarray(values)
    if raw.size == 0:
        return np.zeros((0, width) if width else (0,), dtype=np.intp)
    if raw.dtype == object or raw.dtype.kind not in "iu":
        if raw.dtype.kind == "f" and np.all(np.isfinite(raw)) and np.all(raw == np.round(raw)):
            raw = raw.astype(np.int64)
        else:
            raise DomainError(f"{what} must be integers, got {raw.dtype}")
    if width is None:
        if raw.ndim == 2 and raw.shape[1] == 1:
            raw = raw[:, 0]
        if raw.ndim != 1:
            raise DomainError(f"{what} must be a (k,) or (k, 1) array, got shape {raw.shape}")
    elif raw.ndim != 2 or raw.shape[1] != width:
        raise DomainError(f"{what} must be a (k, {width}) array, got shape {raw.shape}")
    return raw.astype(np.intp)


COORDINATE_LIMIT: Final = 2.0**510
"""Coordinates are below this in magnitude (≈ 3.4·10^153): the refinement measures squared lengths, areas and
circumcentres in doubles (its choices; every decision is exact), and twice this squared is the largest double."""


def _real_rows(values: ArrayLike, what: str, width: int) -> NDArray[np.float64]:
    raw = np.asarray(values) if not isinstance(values, (str, bytes)) else values
    if isinstance(raw, np.ndarray) and raw.size == 0:
        return np.zeros((0, width), dtype=np.float64)
    try:
        out = as_points(values, width, what=what)
    except (TypeError, ValueError) as exc:
        raise DomainError(str(exc)) from None
    if out.size and float(np.abs(out).max()) >= COORDINATE_LIMIT:
        k = int(np.flatnonzero((np.abs(out) >= COORDINATE_LIMIT).any(axis=1))[0])
        raise DomainError(
            f"{what} row {k} {tuple(out[k].tolist())}: a coordinate of magnitude 2^510 (about 3.4e153) or more; "
            f"the mesh measures squared lengths in doubles: scale the domain down"
        )
    return out


# -- validation -------------------------------------------------------------------------------


class Validated(NamedTuple):
    """A validated PSLG and the exact predicates validation decided it with.

    ``predicates`` is a :class:`~persistri.impl.geometry.growing.GrowingPredicates2`
    over ``pslg.vertices`` (in order, nothing appended): what a mesher builds first,
    so :func:`~persistri.impl.mesh.api.triangulate` takes it over instead of making
    another.  It belongs to the caller, who may append to it.
    """

    pslg: PSLG
    predicates: GrowingPredicates2


def as_pslg(
    vertices: ArrayLike,
    segments: ArrayLike = (),
    holes: ArrayLike = (),
    regions: ArrayLike = (),
    *,
    vertex_markers: ArrayLike | None = None,
    segment_markers: ArrayLike | None = None,
    vertex_attributes: ArrayLike | None = None,
    convex: bool = False,
    repair: bool = True,
) -> PSLG:
    """A validated :class:`PSLG`, or :class:`DomainError` with one line naming what is wrong.

    Refused, always (vertex and segment numbers are input rows):

    * NaN or infinite coordinates, coordinates of magnitude :data:`COORDINATE_LIMIT` (2^510) or more,
      wrong shapes, non-integer or out-of-range segment indices;
    * a segment joining a vertex to itself, or two vertices at the same point;
    * two segments that cross without a shared vertex (their exact crossing point is
      not representable: split them yourself where you want the vertex);
    * a hole or region point on a segment or vertex, or outside every boundary: in
      the unbounded face and outside the convex hull of the vertices ("outside the
      domain"), or inside the hull but reachable from outside without crossing a
      segment ("not enclosed": its flood fill would eat everything);
    * an empty domain (every bounded face eaten by holes, or no closed boundary),
      and fewer than 3 non-collinear vertices.

    Repaired when ``repair`` (the default, as Triangle does) and refused otherwise:

    * **duplicate vertices** (exactly equal rows) are merged into the first; segments
      are renumbered (``vertex_map``);
    * **a vertex on a segment's interior** splits the segment there, so the segment
      is the union of its pieces, which is what it meant; collinear segments that
      overlap are split this way into pieces, and repeated pieces merged.

    Always merged: repeated segments (either orientation).  Each repair is one line
    of ``notes``, as is each input vertex outside the domain (it cannot be a mesh
    vertex).  ``convex=True`` adds the convex hull's edges as segments (Triangle's
    ``-c``), so that a set of points with no closed boundary is meshed over its hull.

    Cost: O((n + m) log n + k) exact tests, k the number of (segment, vertex) and
    (segment, segment) pairs whose bounding boxes overlap: a sweep in x, so near
    O(m log m) for boundaries of ordinary shape and O(m²) only for many long
    segments over one slab; plus the faces' nesting (:mod:`~persistri.impl.mesh.faces`).
    """
    return validate(
        vertices,
        segments,
        holes,
        regions,
        vertex_markers=vertex_markers,
        segment_markers=segment_markers,
        vertex_attributes=vertex_attributes,
        convex=convex,
        repair=repair,
    ).pslg


def validate_dict(data: Mapping[str, Any], *, convex: bool = False, repair: bool = True) -> Validated:
    """:meth:`PSLG.from_dict` with the predicates over the validated vertices (:class:`Validated`).

    Same keys, checks and errors as :meth:`PSLG.from_dict`.  Cost: :func:`as_pslg`'s.
    """
    if not isinstance(data, Mapping):
        raise DomainError(f"a PSLG dictionary must be a mapping, not {type(data).__name__}")
    unknown = sorted(set(map(str, data)) - set(_KEYS))
    if unknown:
        raise DomainError(f"unknown PSLG key {unknown[0]!r} (the keys are {', '.join(_KEYS)})")
    if "vertices" not in data:
        raise DomainError("a PSLG dictionary needs 'vertices'")
    return validate(
        data["vertices"],
        data.get("segments", ()),
        data.get("holes", ()),
        data.get("regions", ()),
        vertex_markers=data.get("vertex_markers"),
        segment_markers=data.get("segment_markers"),
        vertex_attributes=data.get("vertex_attributes"),
        convex=convex,
        repair=repair,
    )


def validate(
    vertices: ArrayLike,
    segments: ArrayLike = (),
    holes: ArrayLike = (),
    regions: ArrayLike = (),
    *,
    vertex_markers: ArrayLike | None = None,
    segment_markers: ArrayLike | None = None,
    vertex_attributes: ArrayLike | None = None,
    convex: bool = False,
    repair: bool = True,
) -> Validated:
    """:func:`as_pslg` with the predicates over the validated vertices (:class:`Validated`).

    Same arguments, checks, repairs and errors as :func:`as_pslg`.  Every
    orientation test is one of the returned predicates' true signs, most of
    them decided by its proved filter vectorised over all candidates at once
    (:func:`~persistri.impl.mesh.segments.orient_signs`).  Cost: :func:`as_pslg`'s.
    """
    pts = _real_rows(vertices, "vertices", 2)
    n_in = pts.shape[0]
    seg = _int_array(segments, "segments", 2)
    m_in = seg.shape[0]
    if m_in:
        if int(seg.min()) < 0 or int(seg.max()) >= n_in:
            k = int(np.flatnonzero((seg < 0).any(axis=1) | (seg >= n_in).any(axis=1))[0])
            raise DomainError(f"segment {k} {tuple(seg[k].tolist())}: a vertex index is outside 0..{n_in - 1}")
        loops = seg[:, 0] == seg[:, 1]
        if loops.any():
            k = int(np.flatnonzero(loops)[0])
            raise DomainError(f"segment {k} joins vertex {int(seg[k, 0])} to itself")
    hol = _real_rows(holes, "holes", 2)
    reg = _regions(regions)
    vmark = None if vertex_markers is None else _int_array(vertex_markers, "vertex_markers", None)
    if vmark is not None and vmark.shape[0] != n_in:
        raise DomainError(f"vertex_markers has {vmark.shape[0]} entries for {n_in} vertices")
    smark = None if segment_markers is None else _int_array(segment_markers, "segment_markers", None)
    if smark is not None and smark.shape[0] != m_in:
        raise DomainError(f"segment_markers has {smark.shape[0]} entries for {m_in} segments")
    vattr = None
    if vertex_attributes is not None:
        raw = np.asarray(vertex_attributes, dtype=np.float64)
        if raw.ndim == 1:
            raw = raw.reshape(-1, 1)
        if raw.ndim != 2 or raw.shape[0] != n_in:
            raise DomainError(f"vertex_attributes must be an ({n_in}, k) array, got shape {raw.shape}")
        vattr = np.ascontiguousarray(raw)
    notes: list[str] = []

    # Duplicate vertices: merged into the first occurrence (exact equality of doubles; as_points made -0.0 into 0.0
    # and refused NaN, so Python's float equality is the same).  Distinct rows, the usual case, are told by one set.
    uniq = None if len(set(map(tuple, pts.tolist()))) == n_in else unique_rows(pts)
    if uniq is None:
        verts = pts
        name = vertex_map = np.arange(n_in, dtype=np.intp)  # the input row each vertex is named by
    else:
        name = uniq.first
        verts = np.ascontiguousarray(pts[uniq.first])
        vertex_map = uniq.inverse.astype(np.intp)
    if uniq is not None and uniq.first.size < n_in:
        dup = np.flatnonzero(uniq.first[uniq.inverse] != np.arange(n_in))
        for i in dup.tolist():
            j = int(uniq.first[uniq.inverse[i]])
            msg = f"vertices {j} and {i} are the same point {point_text(pts[i])}"
            if not repair:
                raise DomainError(msg)
            notes.append(msg + f": vertex {i} merged into {j}")
    n = verts.shape[0]
    if uniq is not None and m_in:
        seg = uniq.inverse[seg]
        same = np.flatnonzero(seg[:, 0] == seg[:, 1])
        if same.size:
            k = int(same[0])
            a, b = (int(v) for v in segments_in_rows(segments)[k])
            raise DomainError(f"segment {k} ({a}–{b}) has both ends at the same point {point_text(pts[a])}")
    if uniq is not None and vmark is not None:
        vmark = vmark[uniq.first]
    if uniq is not None and vattr is not None:
        vattr = vattr[uniq.first]

    pred = GrowingPredicates2(verts)
    # Not all on one line: some vertex off the line of the first two (the first test decides, as a rule).
    if n < 3 or not any(pred.orient2d_sign(0, 1, k) for k in range(2, n)):
        if n < 3:
            some = "no vertices" if n == 0 else ("only 1 distinct vertex" if n == 1 else "only 2 distinct vertices")
            raise DomainError(f"{some}: a region needs at least 3 not on one line")
        raise DomainError(f"the {n} distinct vertices are collinear: they bound no region")

    origin = np.arange(seg.shape[0], dtype=np.intp)  # the input segment each current one comes from (-1: hull)
    marks = smark.copy() if smark is not None else None
    if convex:
        hull = convex_hull(verts, pred)
        extra = np.array([[hull[k], hull[(k + 1) % len(hull)]] for k in range(len(hull))], dtype=np.intp)
        seg = np.concatenate([seg, extra])
        origin = np.concatenate([origin, np.full(extra.shape[0], -1, dtype=np.intp)])
        if marks is not None:
            marks = np.concatenate([marks, np.zeros(extra.shape[0], dtype=np.intp)])

    seg, origin, marks = dedupe(seg, origin, marks, notes, name)
    columns = pred.filter_columns() if seg.shape[0] > FEW_SEGMENTS else None  # the vectorised paths' (segments.py)
    pieces = split_at_vertices(verts, seg, origin, marks, pred, notes, name, repair, columns)
    if pieces[0] is not seg:  # split: pieces of overlapping segments may repeat
        seg, origin, marks = dedupe(*pieces, notes, name)
    refuse_crossings(verts, seg, origin, name, pred, columns)

    result = PSLG(
        vertices=verts,
        segments=seg,
        holes=hol,
        regions=reg,
        vertex_markers=vmark,
        segment_markers=marks,
        vertex_attributes=vattr,
        notes=(),
        vertex_map=vertex_map,
        segment_origin=origin,
    )
    dom = domain_of(result)
    for v in np.flatnonzero(~dom.vertex_inside).tolist():
        notes.append(f"vertex {int(name[v])} at {point_text(verts[v])} lies outside the domain: it cannot be a mesh vertex")
    if not notes:
        return Validated(result, pred)  # nothing repaired or noticed: the PSLG checked is the one returned
    final = PSLG(
        vertices=result.vertices,
        segments=result.segments,
        holes=result.holes,
        regions=result.regions,
        vertex_markers=result.vertex_markers,
        segment_markers=result.segment_markers,
        vertex_attributes=result.vertex_attributes,
        notes=tuple(notes),
        vertex_map=result.vertex_map,
        segment_origin=result.segment_origin,
    )
    return Validated(final, pred)


def segments_in_rows(segments: ArrayLike) -> NDArray[np.intp]:
    """``segments`` as an ``(m, 2)`` index array (for messages naming input rows)."""
    return np.asarray(segments).reshape(-1, 2).astype(np.intp)


def _regions(regions: ArrayLike) -> NDArray[np.float64]:
    raw = np.asarray(regions)
    if raw.size == 0:
        return _no_regions()
    if raw.ndim != 2 or raw.shape[1] != 4:
        raise DomainError(f"regions must be an (r, 4) array of rows (x, y, attribute, max_area), got shape {raw.shape}")
    try:
        return as_points(raw, 4, what="regions")
    except (TypeError, ValueError) as exc:
        raise DomainError(str(exc)) from None
