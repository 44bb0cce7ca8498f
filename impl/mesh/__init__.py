"""Quality meshes of planar domains: constrained Delaunay triangulation and Ruppert's refinement.

The paper's motivating application (§1): Ruppert's Delaunay refinement, in which a
circumcenter whose insertion would encroach a boundary segment is *undone* by
returning to the previous persistent version, not repaired.

The domain and the check:

* :mod:`~persistri.impl.mesh.domain` — planar straight-line graphs (:class:`PSLG`): vertices,
  segments, holes, regions; validation (:func:`as_pslg`), the dict form, the domain's faces;
* :mod:`~persistri.impl.mesh.segments` — segment sets made clean: repeats merged, splits at
  vertices, crossings refused (exact);
* :mod:`~persistri.impl.mesh.errors` — :class:`DomainError`;
* :mod:`~persistri.impl.mesh.faces` — the faces of a PSLG's segments, traced exactly, and
  exact point location;
* :mod:`~persistri.impl.mesh.polyfile` — Triangle's ``.node``, ``.poly``, ``.ele``, ``.edge`` files;
* :mod:`~persistri.impl.mesh.verify` — :func:`verify_mesh`, the exact, independent mesh checker;
* :mod:`~persistri.impl.mesh.chains` — input segments as chains of mesh edges, exactly or within rounding;
* :mod:`~persistri.impl.mesh.angles` — angles against a bound in degrees, exactly; Ruppert's exemption;
* :mod:`~persistri.impl.mesh.gallery` — the bench's deterministic domains.

The mesher:

* :mod:`~persistri.impl.mesh.triangulation` — the triangulation as a persistent 2-complex;
* :mod:`~persistri.impl.mesh.cdt` — the constrained Delaunay triangulation of a PSLG;
* :mod:`~persistri.impl.mesh.steiner` — Steiner points as doubles: split points, circumcentres;
* :mod:`~persistri.impl.mesh.quality` — triangle quality against the bounds, exactly;
* :mod:`~persistri.impl.mesh.quality_filter` — the refinement's quality tests, float stage first;
* :mod:`~persistri.impl.mesh.ruppert` — Ruppert's refinement with undo by persistence;
* :mod:`~persistri.impl.mesh.api` — :func:`triangulate` and :func:`refine`, every step a version;
* :mod:`~persistri.impl.mesh.result` — what they return: :class:`QualityMesh`, :class:`MeshHistory`;
* :mod:`~persistri.impl.mesh.readout` — a version read back as arrays;
* :mod:`~persistri.impl.mesh.options` — their arguments, checked.
"""
