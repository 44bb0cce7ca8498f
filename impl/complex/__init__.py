"""Persistent simplicial complexes (paper §2): vertices, simplices and the complex functor.

=====================================  ===============================================================
module                                  what
=====================================  ===============================================================
:mod:`.vertex`                          :class:`Vertex`, :class:`VertexState`, ``int_vertex`` (VERTEX)
:mod:`.simplex`                         tuples of vertices, ``tuple_simplex`` (SIMPLEX)
:mod:`.structure`                       the complex value :class:`Complex` and the validated boundary
:mod:`.one_complex`                     the special 1-complex
:mod:`.two_complex`                     the specialised 2-complex of the algorithms (paper §4)
:mod:`.bootstrap`                       the functor: n-complex from (n−1)-complex
:mod:`.simpcomp`                        :func:`complex_structure` (one dimension), :class:`SimpComp` (all)
:mod:`.ephemeral`                       the NOT persistent baseline over a ``dict`` (benchmarks only)
:mod:`.trace`                           record SIMPCOMP operations, replay them on any complex
:mod:`.checks`                          executable invariants: ``check_complex``, ``check_closed_surface``
:mod:`.errors`                          every exception of the layer
=====================================  ===============================================================
"""

from persistri.impl.complex.bootstrap import Bootstrap
from persistri.impl.complex.checks import SurfaceReport, check_closed_surface, check_complex
from persistri.impl.complex.one_complex import OneComplex
from persistri.impl.complex.ephemeral import EphemeralTwoComplex
from persistri.impl.complex.simpcomp import SimpComp, complex_structure, two_complex
from persistri.impl.complex.simplex import Simplex, TupleSimplex, canonical, tuple_simplex
from persistri.impl.complex.structure import Complex, ComplexStructure, Family
from persistri.impl.complex.trace import Trace, TracingTwoComplex, load_trace, replay, save_trace
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.complex.vertex import IntVertex, Lineage, Vertex, VertexState, int_vertex

__all__ = [
    "Vertex",
    "VertexState",
    "Lineage",
    "IntVertex",
    "int_vertex",
    "Simplex",
    "TupleSimplex",
    "tuple_simplex",
    "canonical",
    "Complex",
    "ComplexStructure",
    "Family",
    "OneComplex",
    "TwoComplex",
    "Bootstrap",
    "SimpComp",
    "complex_structure",
    "two_complex",
    "EphemeralTwoComplex",
    "Trace",
    "TracingTwoComplex",
    "replay",
    "save_trace",
    "load_trace",
    "check_complex",
    "check_closed_surface",
    "SurfaceReport",
]
