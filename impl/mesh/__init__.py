"""Quality meshes of planar domains: constrained Delaunay triangulation and Ruppert's refinement.

The paper's motivating application (§1): Ruppert's Delaunay refinement, in which a
circumcenter whose insertion would encroach a boundary segment is *undone* by
returning to the previous persistent version, not repaired.

* :mod:`~persistri.impl.mesh.domain` — planar straight-line graphs (:class:`PSLG`): vertices,
  segments, holes, regions; validation;
"""
