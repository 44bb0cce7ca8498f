"""persistri — *Persistent Triangulations* (Blelloch et al., JFP 2001), exact and fully typed.

The public names, in the shape of :mod:`scipy.spatial`::

    import persistri
    hull = persistri.ConvexHull(points, history=True)     # exact 3D hull, every version kept
    bigger = hull.add_points(more)                         # a NEW hull; hull is unchanged
    tri = persistri.Delaunay(xy)                           # exact 2D Delaunay triangulation
    tri.find_simplex(queries)                              # exact point location, -1 outside
    more = tri.add_points(xy2)                             # a NEW triangulation; tri is unchanged
    mesh = persistri.triangulate(persistri.read_poly("domain.poly"), min_angle=30)   # Ruppert, exact
    persistri.verify_mesh(mesh.domain, mesh.vertices, mesh.triangles, min_angle=30).ok

==========================  ==================================================================
name                        what
==========================  ==================================================================
``ConvexHull``              the exact 3D convex hull, scipy's attributes, persistent versions
``Delaunay``                the exact 2D Delaunay triangulation, scipy's attributes
``convex_hull``             the function under ``ConvexHull``, returning the full :class:`Hull`
``delaunay``                the function under ``Delaunay``, returning a ``DelaunayTriangulation``
``verify_hull``             an exact, independent check of any hull (persistri's, Qhull's, …)
``greedy_insertion``        terrain meshing of a height grid, every level of detail kept (§5)
``triangulate``             a quality mesh of a planar domain: Ruppert's refinement, every step a
                            version, a circumcentre that encroaches undone by persistence (§1)
``refine``                  refine a mesh further, as another future of the same version
``PSLG``                    a planar domain (vertices, segments, holes, regions), as Triangle's
``read_poly``               a domain from Triangle's ``.poly`` file
``verify_mesh``             an exact, independent check of any mesh (persistri's, Triangle's, …)
``Hull``, ``HullHistory``,  the result types of the functions above, for annotations
``DelaunayTriangulation``,
``DelaunayHistory``,
``Tin``, ``HullReport``,
``QualityMesh``,
``MeshReport``
``Stats``                   operation counters (the paper's §4 measures) to pass as ``stats=``
``maps``                    the persistent ``ORD_MAP`` backends (:mod:`persistri.maps`)
``conformance``             the conformance suite for your own backends (``persistri[conformance]``)
``spec``                    the paper's signatures as Protocols, and their laws
``__version__``             the installed version
==========================  ==================================================================

Importing ``persistri`` is cheap: every name is loaded on first use (PEP 562), so
``import persistri`` imports neither numpy nor anything else heavy.  The
implementation stays importable under :mod:`persistri.impl` (the modules the
documentation's essays are about); these names are the stable surface.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from persistri import conformance as conformance
    from persistri import maps as maps
    from persistri import spec as spec
    from persistri._delaunay import Delaunay as Delaunay
    from persistri._hull import ConvexHull as ConvexHull
    from persistri.impl.hull.api import Hull as Hull
    from persistri.impl.hull.api import HullHistory as HullHistory
    from persistri.impl.hull.api import convex_hull as convex_hull
    from persistri.impl.hull.verify import HullReport as HullReport
    from persistri.impl.hull.verify import verify_hull as verify_hull
    from persistri.impl.mesh.api import QualityMesh as QualityMesh
    from persistri.impl.mesh.api import refine as refine
    from persistri.impl.mesh.api import triangulate as triangulate
    from persistri.impl.mesh.domain import PSLG as PSLG
    from persistri.impl.mesh.polyfile import read_poly as read_poly
    from persistri.impl.mesh.verify import MeshReport as MeshReport
    from persistri.impl.mesh.verify import verify_mesh as verify_mesh
    from persistri.impl.stats import Stats as Stats
    from persistri.impl.terrain.greedy import Tin as Tin
    from persistri.impl.terrain.greedy import greedy_insertion as greedy_insertion
    from persistri.impl.terrain.delaunay_history import DelaunayHistory as DelaunayHistory
    from persistri.impl.terrain.scattered import DelaunayTriangulation as DelaunayTriangulation
    from persistri.impl.terrain.scattered import delaunay as delaunay

    __version__: str

_NAMES: dict[str, str] = {
    "ConvexHull": "persistri._hull",
    "Delaunay": "persistri._delaunay",
    "convex_hull": "persistri.impl.hull.api",
    "Hull": "persistri.impl.hull.api",
    "HullHistory": "persistri.impl.hull.api",
    "delaunay": "persistri.impl.terrain.scattered",
    "DelaunayTriangulation": "persistri.impl.terrain.scattered",
    "DelaunayHistory": "persistri.impl.terrain.delaunay_history",
    "verify_hull": "persistri.impl.hull.verify",
    "HullReport": "persistri.impl.hull.verify",
    "greedy_insertion": "persistri.impl.terrain.greedy",
    "Tin": "persistri.impl.terrain.greedy",
    "Stats": "persistri.impl.stats",
    "triangulate": "persistri.impl.mesh.api",
    "refine": "persistri.impl.mesh.api",
    "QualityMesh": "persistri.impl.mesh.api",
    "PSLG": "persistri.impl.mesh.domain",
    "read_poly": "persistri.impl.mesh.polyfile",
    "verify_mesh": "persistri.impl.mesh.verify",
    "MeshReport": "persistri.impl.mesh.verify",
}
"""Each lazy public name → the module that defines it."""

_SUBMODULES: tuple[str, ...] = ("maps", "conformance", "spec")
"""Public subpackages, imported on first access (``persistri.impl`` is importable too, but not advertised)."""

__all__ = [
    "ConvexHull",
    "Delaunay",
    "convex_hull",
    "delaunay",
    "verify_hull",
    "greedy_insertion",
    "triangulate",
    "refine",
    "PSLG",
    "read_poly",
    "verify_mesh",
    "Hull",
    "HullHistory",
    "DelaunayTriangulation",
    "DelaunayHistory",
    "Tin",
    "HullReport",
    "QualityMesh",
    "MeshReport",
    "Stats",
    "maps",
    "conformance",
    "spec",
    "__version__",
]


def _version() -> str:
    """The installed distribution's version; ``"0+unknown"`` when persistri runs from a tree that was never installed."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("persistri")
    except PackageNotFoundError:
        return "0+unknown"


if not TYPE_CHECKING:
    # Only at run time: mypy reads the imports above instead, so that a misspelt name is an error, not Any.

    def __getattr__(name: str) -> object:
        """Load a public name on first use (PEP 562) and keep it, so the next access is a plain lookup."""
        if name == "__version__":
            value: object = _version()
        elif name in _SUBMODULES:
            value = importlib.import_module(f"{__name__}.{name}")
        elif name in _NAMES:
            value = getattr(importlib.import_module(_NAMES[name]), name)
        else:
            raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
        globals()[name] = value
        return value


def __dir__() -> list[str]:
    """The public names (:data:`__all__`), loaded or not."""
    return sorted(__all__)
