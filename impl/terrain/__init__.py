"""Terrain meshing and scattered-point Delaunay triangulation on the persistent complex (paper §5).

=====================  ====================================================================
module                 what
=====================  ====================================================================
:mod:`.delaunay`       the incremental Delaunay triangulation (Bowyer–Watson with ghosts)
:mod:`.greedy`         Garland–Heckbert greedy insertion: ``greedy_insertion``, ``Tin``, history
:mod:`.scattered`      ``delaunay``: exact Delaunay triangulation of arbitrary 2D points
:mod:`.grids`          height grids: validation, no-data rules, transforms, file readers
:mod:`.geotiff`        GeoTIFF height grids (compressed, tiled): heights, transform, CRS, no-data
:mod:`.crs`            the coordinate reference system a grid file states (EPSG code, WKT)
:mod:`.export`         terrain meshes to files: world orientation, used vertices only, CRS
:mod:`.check`          exact verification (``check=True``) and independent error measurement
:mod:`.plot`           the triangulation over a shaded relief (paper Figs. 9–10)
=====================  ====================================================================
"""
