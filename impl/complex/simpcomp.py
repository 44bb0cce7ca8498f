"""Choosing a complex: one dimension (:func:`complex_structure`) or all of them (:class:`SimpComp`).

The paper's ``SIMPCOMP`` has ``new : int -> 'a complex``: one structure makes
complexes of every dimension.  :class:`SimpComp` is that structure: it builds,
per dimension n, the representation persistri uses and sends each operation to
the structure of its complex's dimension (one dictionary lookup of dispatch).

=====  =======================================================================
n      representation (``specialised=True``, the default)
=====  =======================================================================
1      :class:`~persistri.impl.complex.one_complex.OneComplex`
2      :class:`~persistri.impl.complex.two_complex.TwoComplex` (paper §4)
≥ 3    :class:`~persistri.impl.complex.bootstrap.Bootstrap` over the (n−1) one
=====  =======================================================================

With ``specialised=False`` the 2-complex is the functor applied to the
1-complex too: the paper's generic construction, slower, kept for teaching and
as a cross-check.  Code that works in one dimension (the convex hull) should
take the structure of that dimension from :func:`complex_structure` (or, for
2-complexes, :func:`two_complex`) and skip the dispatch.

The backend name ``"ephemeral"`` (:data:`~persistri.impl.complex.ephemeral.EPHEMERAL`)
selects the NOT persistent baseline
:class:`~persistri.impl.complex.ephemeral.EphemeralTwoComplex` — dimension 2,
specialised, only; it exists to measure what persistence costs.

>>> from persistri.impl.complex.vertex import VertexState, int_vertex
>>> C = complex_structure(2, "assoc_list")
>>> _, (a, b, c) = int_vertex.new_many(VertexState.initial(), ["p", "q", "r"])
>>> t = C.add(C.new(2), (a, b, c), "datum")
>>> C.find(t, (b, c)), C.data(t, (c, a, b))
([(v1, v2, v0)], ('datum',))
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from typing import Any, Generic, TypeVar

from persistri.impl.complex.bootstrap import Bootstrap
from persistri.impl.complex.ephemeral import EPHEMERAL, EphemeralTwoComplex
from persistri.impl.complex.errors import DimensionError, ForeignComplexError
from persistri.impl.complex.one_complex import OneComplex
from persistri.impl.complex.simplex import Simplex, TupleSimplex, tuple_simplex
from persistri.impl.complex.structure import Complex, ComplexStructure
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.complex.vertex import IntVertex, Vertex, VertexState
from persistri.impl.maps import backend as backend_named
from persistri.impl.stats import Stats
from persistri.spec.option import Option
from persistri.spec.simpcomp import SIMPCOMP
from persistri.spec.simplex import SIMPLEX
from persistri.spec.vertex import VERTEX

__all__ = ["complex_structure", "two_complex", "SimpComp", "MAX_DIM"]

D = TypeVar("D")

MAX_DIM = 16
"""The largest dimension :class:`SimpComp` builds (far beyond any use; 1–4 are tested)."""

_Simplex = Simplex  # inside SimpComp, ``Simplex`` is the signature's sub-structure


def _resolve(backend: Any) -> Any:
    """The ``ORD_MAP`` structure ``backend`` names, or ``backend`` itself when it is one; a :class:`TypeError`
    naming what it lacks otherwise (``backend=3`` used to fail deep inside, as "'int' object has no attribute
    'insert'")."""
    if isinstance(backend, str):
        return backend_named(backend)
    lacking = [op for op in ("empty", "insert", "find", "remove") if not callable(getattr(backend, op, None))]
    if lacking:
        raise TypeError(
            f"backend must be a map backend's name or an ORD_MAP structure, not {type(backend).__name__} "
            f"(it has no {', '.join(lacking)})"
        )
    return backend


def complex_structure(
    n: int, backend: Any = "red_black", *, stats: Stats | None = None, specialised: bool = True
) -> ComplexStructure[Any]:
    """The ``SIMPCOMP`` structure of n-complexes over ``backend`` (an ``ORD_MAP`` structure or its registry name).

    ``stats`` is attached at every level (the inner complexes of the functor
    report to it too).  See the module docstring for the representations;
    ``backend="ephemeral"`` is the NOT persistent baseline (n = 2, specialised).
    """
    if isinstance(n, bool) or not isinstance(n, int):
        raise TypeError(f"complex_structure: dimension must be an int, got {type(n).__name__}")
    if not 1 <= n <= MAX_DIM:
        raise DimensionError(f"complex_structure: dimension {n} is outside 1..{MAX_DIM}")
    if isinstance(backend, str) and backend == EPHEMERAL:
        if n != 2 or not specialised:
            raise ValueError(
                f"complex_structure: the ephemeral baseline is the specialised 2-complex only "
                f"(asked for n={n}, specialised={specialised})"
            )
        return EphemeralTwoComplex(stats)
    b = _resolve(backend)
    structure: ComplexStructure[Any] = OneComplex(b, stats)
    for k in range(2, n + 1):
        if k == 2 and specialised:
            structure = TwoComplex(b, stats)
        else:
            structure = Bootstrap(structure, b, stats)
    return structure


def two_complex(backend: Any = "red_black", stats: Stats | None = None) -> TwoComplex[Any]:
    """The specialised 2-complex (paper §4) over ``backend`` — an ``ORD_MAP`` structure or its registry
    name — or, for ``backend="ephemeral"``, the NOT persistent baseline over a ``dict``.

    What the 2-complex algorithms (the convex hull) build on.  Raises
    :class:`~persistri.impl.maps.UnknownBackendError` for an unknown name.
    """
    if isinstance(backend, str) and backend == EPHEMERAL:
        return EphemeralTwoComplex(stats)
    return TwoComplex(_resolve(backend), stats)


class SimpComp(Generic[D]):
    """``structure SimpComp : SIMPCOMP`` of every dimension over one backend (see the module docstring).

    Each operation costs what the structure of its complex's dimension costs,
    plus one dispatch.  ``dim``, ``new`` and the dispatch are O(1).
    """

    def __init__(self, backend: Any = "red_black", stats: Stats | None = None, *, specialised: bool = True) -> None:
        self._backend = _resolve(backend)
        self._stats = stats
        self._specialised = specialised
        self._by_dim: dict[int, ComplexStructure[D]] = {}

    @property
    def Simplex(self) -> TupleSimplex:
        """``structure Simplex : SIMPLEX``: :data:`~persistri.impl.complex.simplex.tuple_simplex`."""
        return tuple_simplex

    def structure(self, n: int) -> ComplexStructure[D]:
        """The structure of n-complexes this one dispatches to (built once)."""
        s = self._by_dim.get(n)
        if s is None:
            s = complex_structure(n, self._backend, stats=self._stats, specialised=self._specialised)
            self._by_dim[n] = s
        return s

    def _of(self, c: Complex[D], what: str) -> ComplexStructure[D]:
        try:
            n = c.family.n
        except AttributeError:
            raise ForeignComplexError(f"{what}: expected a complex, got {type(c).__name__}") from None
        return self.structure(n)

    def dim(self, c: Complex[D], /) -> int:
        """``dim c``: the dimension of ``c``."""
        return self._of(c, "dim").dim(c)

    def new(self, n: int, /) -> Complex[D]:
        """``new n``: the empty n-complex (1 ≤ n ≤ :data:`MAX_DIM`)."""
        if isinstance(n, bool) or not isinstance(n, int):
            raise TypeError(f"new: dimension must be an int, got {type(n).__name__}")
        if not 1 <= n <= MAX_DIM:
            raise DimensionError(f"new: dimension {n} is outside 1..{MAX_DIM}")
        return self.structure(n).new(n)

    def isEmpty(self, c: Complex[D], /) -> bool:
        """``isEmpty c``."""
        return self._of(c, "isEmpty").isEmpty(c)

    def vertices(self, c: Complex[D], /) -> Sequence[Vertex]:
        """``vertices c``."""
        return self._of(c, "vertices").vertices(c)

    def simplices(self, c: Complex[D], d: int, /) -> Sequence[_Simplex]:
        """``simplices c d``."""
        return self._of(c, "simplices").simplices(c, d)

    def data(self, c: Complex[D], s: _Simplex, /) -> Option[D]:
        """``data (c, s)``."""
        return self._of(c, "data").data(c, s)

    def grep(self, c: Complex[D], d: int, s: _Simplex, /) -> Sequence[_Simplex]:
        """``grep c (d, s)``."""
        return self._of(c, "grep").grep(c, d, s)

    def find(self, c: Complex[D], s: _Simplex, /) -> Sequence[_Simplex]:
        """``find (c, s)``."""
        return self._of(c, "find").find(c, s)

    def findi(self, c: Complex[D], s: _Simplex, /) -> Sequence[tuple[_Simplex, D]]:
        """``find`` with each simplex's datum (persistri's addition)."""
        return self._of(c, "findi").findi(c, s)

    def neighbour(self, c: Complex[D], s: _Simplex, /) -> tuple[_Simplex, D] | None:
        """The first simplex ``findi`` gives with its datum, or None (persistri's addition; see ``TwoComplex.neighbour``)."""
        return self._of(c, "neighbour").neighbour(c, s)

    def items(self, c: Complex[D], /) -> Sequence[tuple[_Simplex, D]]:
        """Each n-simplex once with its datum (persistri's addition)."""
        return self._of(c, "items").items(c)

    def iter_items(self, c: Complex[D], /) -> Iterator[tuple[_Simplex, D]]:
        """``items`` one at a time, without a list of them all (persistri's addition)."""
        return self._of(c, "items").iter_items(c)

    def add(self, c: Complex[D], s: _Simplex, x: D, /) -> Complex[D]:
        """``add (c, s, x)``."""
        return self._of(c, "add").add(c, s, x)

    def rem(self, c: Complex[D], s: _Simplex, /) -> Complex[D]:
        """``rem (c, s)``."""
        return self._of(c, "rem").rem(c, s)

    def update(self, c: Complex[D], s: _Simplex, f: Callable[[D], D], /) -> Complex[D]:
        """``update (c, s, f)``."""
        return self._of(c, "update").update(c, s, f)

    def replace(
        self, c: Complex[D], removed: Sequence[_Simplex], added: Sequence[tuple[_Simplex, D]], /
    ) -> Complex[D]:
        """``replace (c, removed, added)``: the ``rem`` of each removed simplex, then the ``add`` of each added one."""
        return self._of(c, "replace").replace(c, removed, added)

    def check(self, c: Complex[D], /) -> None:
        """The representation check of ``c``'s structure (RepresentationError / OrientationError)."""
        self._of(c, "check").check(c)

    def __repr__(self) -> str:
        name = getattr(self._backend, "name", None) or repr(self._backend)
        return f"<SimpComp over {name}{'' if self._specialised else ', unspecialised'}>"


# -- static conformance: mypy checks that each structure matches its signature ------------


def _is_simpcomp(s: ComplexStructure[D]) -> SIMPCOMP[Vertex, _Simplex, D, Complex[D]]:
    return s


def _is_simpcomp_all(s: SimpComp[D]) -> SIMPCOMP[Vertex, _Simplex, D, Complex[D]]:
    return s


def _is_simplex(s: TupleSimplex) -> SIMPLEX[Vertex, _Simplex]:
    return s


def _is_vertex(v: IntVertex) -> VERTEX[Vertex, VertexState, Any]:
    return v
