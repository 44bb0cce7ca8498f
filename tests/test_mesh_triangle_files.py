"""Every example file bundled with Triangle (the ``triangle`` package's ``data/``) meshes, or fails for a stated reason.

Each ``.node`` (the convex hull of its points, as Triangle meshes one) and
``.poly`` file is meshed at the angle bounds Triangle's users ask for — 0 (the
constrained Delaunay triangulation), 20°, 30° and 33° — and, for the small
ones, with an area bound too, and every mesh must pass the exact checker with
its bounds.  The files that cannot be meshed must fail with the one-line reason
that is true of them, checked here independently:

* ``box.poly`` encloses no region (one side of its outer box is a segment; its
  hole eats the rest): Triangle meshes it only with ``-c``, and so does
  persistri with ``convex=True``;
* ``spiral.q.1.node``, ``spiral.r.1.node`` (Triangle's own outputs read back)
  and ``greenland.node`` hold an input vertex less than an ulp from a convex
  hull edge it is not on: any positive angle bound needs edges shorter than the
  spacing of doubles there (Triangle itself fails or loops on them).

Slow cases (:data:`SLOW`: ``la`` but at 20°, the largest at 33°, all of
``greenland``, 0.3–9 s each) carry the ``slow`` mark and run only with
``PERSISTRI_SLOW_MESH=1``.
"""

from __future__ import annotations

import math
import os
import re
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

from persistri.impl.mesh.api import refine, triangulate
from persistri.impl.mesh.domain import PSLG
from persistri.impl.mesh.polyfile import PolyFileError
from persistri.impl.mesh.steiner import PrecisionLimitError
from persistri.impl.mesh.verify import verify_mesh

triangle = pytest.importorskip("triangle")

DATA = Path(triangle.__file__).parent / "data"
FILES = sorted(p.name for p in DATA.iterdir() if p.suffix in (".node", ".poly"))
ANGLES = (0.0, 20.0, 30.0, 33.0)

UNENCLOSED = {"box.poly"}
"""Files whose segments enclose no region."""

CROWDED = {"spiral.q.1.node": 16, "spiral.r.1.node": 16, "greenland.node": 12008}
"""Files with an input vertex (row) less than an ulp from a segment it is not on."""

SLOW = (
    {(name, a) for name in ("la.poly", "la.1.poly") for a in (0.0, 30.0, 33.0)}
    | {(name, 33.0) for name in ("la.1.node", "dots.node", "dots.1.v.node")}
    | {("greenland.node", a) for a in ANGLES}
)
"""Cases of a second or more (or several tenths on the largest files; their 20° case runs)."""

slow_mesh = [
    pytest.mark.slow,
    pytest.mark.skipif(not os.environ.get("PERSISTRI_SLOW_MESH"), reason="seconds per case: PERSISTRI_SLOW_MESH=1"),
]


def _domain(name: str, *, convex: bool = False) -> PSLG:
    from persistri.impl.cli.mesh import read_domain

    return read_domain(str(DATA / name), convex=convex)


def _cases() -> list[object]:
    return [
        pytest.param(name, angle, marks=slow_mesh if (name, angle) in SLOW else (), id=f"{name}-q{angle:g}")
        for name in FILES
        for angle in ANGLES
    ]


def _check(domain: PSLG, mesh: object, min_angle: float, max_area: float | None) -> None:
    from persistri.impl.mesh.api import QualityMesh

    assert isinstance(mesh, QualityMesh)
    report = verify_mesh(
        domain,
        mesh.vertices,
        mesh.triangles,
        min_angle=min_angle or None,
        max_area=max_area,
        exact_segments=mesh.rounded_splits == 0,
        region_areas=True,
    )
    assert report.ok, report.problems[:3]
    assert mesh.min_angle_reached and mesh.max_area_reached


def _ulp_distance(domain: PSLG, v: int) -> float:
    """The exact distance from input vertex ``v`` to the nearest segment it is not on, in ulps of the largest
    coordinate magnitude involved (a float of an exact rational)."""
    x, y = (Fraction(c) for c in domain.vertices[v])
    best = math.inf
    for a, b in domain.segments.tolist():
        if v in (a, b):
            continue
        (ax, ay), (bx, by) = (tuple(Fraction(c) for c in domain.vertices[i]) for i in (a, b))
        dx, dy, wx, wy = bx - ax, by - ay, x - ax, y - ay
        along, length2 = wx * dx + wy * dy, dx * dx + dy * dy
        if not 0 < along < length2:
            continue
        cross = dx * wy - dy * wx
        if cross == 0:
            continue
        d = math.sqrt(cross * cross / length2)
        ulp = math.ulp(max(abs(float(c)) for c in (x, y, ax, ay, bx, by)))
        best = min(best, d / ulp)
    return best


@pytest.mark.parametrize("name, angle", _cases())
def test_bundled_file_meshes_or_fails_for_its_reason(name: str, angle: float) -> None:
    if name in UNENCLOSED:
        with pytest.raises(PolyFileError, match=r"is every boundary closed\?"):
            _domain(name)
        hull = _domain(name, convex=True)  # Triangle's -c
        _check(hull, triangulate(hull, min_angle=angle), angle, None)
        return
    domain = _domain(name)
    if name in CROWDED and angle > 0:
        v = CROWDED[name]
        with pytest.raises(PrecisionLimitError) as info:
            triangulate(domain, min_angle=angle)
        message = str(info.value)
        x, y = (float(c) for c in domain.vertices[v])
        assert f"input vertex {v} at ({x!r}, {y!r})" in message and "units in the last place" in message
        assert "\n" not in message
        _names_the_hull_edge(domain, message)
        # The reason is true: that vertex is off every segment but within the tolerance band of one.
        shown = re.search(r"\(([\d.e+-]+) units in the last place\)", message)
        assert shown is not None and _ulp_distance(domain, v) < 2
        assert math.isclose(float(shown.group(1)), _ulp_distance(domain, v), rel_tol=0.05)
        return
    mesh = triangulate(domain, min_angle=angle, region_areas=True)  # Triangle's -a: the regions' own bounds too
    _check(domain, mesh, angle, None)


def _names_the_hull_edge(domain: PSLG, message: str) -> None:
    """A .node file has no segments: the message names the convex hull edge (added by validation) as such, with
    its ends, and no segment number."""
    named = re.search(
        r"from the convex hull edge \((\S+), (\S+)\)–\((\S+), (\S+)\) \(a \.node file, or convex=True, is meshed as its "
        r"convex hull\), without being on it",
        message,
    )
    assert named is not None, message
    assert not re.search(r"segment \d", message), message
    ax, ay, bx, by = (float(c) for c in named.groups())
    rows = {(float(x), float(y)): k for k, (x, y) in enumerate(domain.vertices.tolist())}
    ends = {rows[(ax, ay)], rows[(bx, by)]}
    assert domain.segment_origin is not None
    hull = [set(e) for e, o in zip(domain.segments.tolist(), domain.segment_origin.tolist()) if o == -1]
    assert ends in hull and len(hull) == domain.segments.shape[0]


def test_greenland_names_the_convex_hull_edge_not_a_segment() -> None:
    # Triangle's greenland.node at 20° (as `persistri mesh greenland.node --min-angle 20`): its row 12008 lies 0.16
    # ulp from an edge of the convex hull, which the file never lists; the message named it "segment 15".
    domain = _domain("greenland.node")
    with pytest.raises(PrecisionLimitError) as info:
        triangulate(domain, min_angle=20)
    message = str(info.value)
    x, y = (float(c) for c in domain.vertices[12008])
    assert message.startswith(f"input vertex 12008 at ({x!r}, {y!r}) lies "), message
    assert "the convex hull edge (105.4610209809, 39.6536736603)–(106.5, 40.0) (a .node file" in message, message
    _names_the_hull_edge(domain, message)


LARGE = ("la", "dots", "box.4", "double_hex.2", "double_hex3.1", "square_circle_hole")
SMALL = [name for name in FILES if name not in UNENCLOSED and name not in CROWDED and not name.startswith(LARGE)]
"""The files of a few dozen vertices, where an area bound of 1/64 of the domain refines."""


@pytest.mark.parametrize("name", SMALL)
def test_bundled_file_with_an_area_bound(name: str) -> None:
    # A future of the CDT with an area bound of 1/64 of the domain: as fine as the file's scale asks.
    domain = _domain(name)
    cdt = triangulate(domain)
    area = float(verify_mesh(domain, cdt.vertices, cdt.triangles).domain_area) / 64
    mesh = refine(cdt, min_angle=30, max_area=area)
    _check(domain, mesh, 30.0, area)
    assert len(mesh.triangles) >= 64
    assert mesh.history[0] is cdt.complex  # another future of the same version
    assert np.array_equal(cdt.history.mesh(0).triangles, cdt.triangles)
