"""What every persistri complex shares: the complex value, its family, and the SIMPCOMP boundary.

A *complex value* (:class:`Complex`) is an immutable record of three things:

* ``family`` — which representation made it (:class:`Family`: the kind, the
  dimension n, the ``ORD_MAP`` backend, and for the bootstrapping functor the
  family of the (n−1)-complexes inside).  A structure refuses values of another
  family with :class:`~persistri.impl.complex.errors.ForeignComplexError`;
* ``rep`` — the representation: a persistent map of the backend, from vertices
  to what each representation stores per vertex;
* ``lineage`` — the vertex lineage of its simplices, adopted from the first
  simplex added (``None`` while nothing was ever added).

:class:`ComplexStructure` is the base of the three representations
(:mod:`~persistri.impl.complex.one_complex`, :mod:`~persistri.impl.complex.two_complex`,
:mod:`~persistri.impl.complex.bootstrap`).  It implements the public
``SIMPCOMP`` operations (paper Fig. 3) once: it validates the arguments — the
complex's family, the simplex's vertices, lineage, distinctness and
dimension — and then calls the representation's *internal* operations, which
work on bare ``rep`` maps and trust their arguments.  The functor calls the
internal operations of the (n−1)-complex it is built on, so the boundary is
checked once per call, not once per level.

Orientation semantics (the laws are in :mod:`persistri.spec.simpcomp_laws`):

* top simplices are oriented: any order of the stored orientation finds them;
* ``find(c, f)``: the n-simplices having the (n−1)-simplex ``f`` as a face with
  ``f``'s orientation, i.e. those of the class of ``join(x, f)`` for some x;
* ``grep(c, d, s)``: when ``dim s = d − 1`` orientation matters: for ``d = n`` it
  is ``find``, for ``d < n`` every d-face ``{x} ∪ s`` is reported as
  ``join(x, s)``.  Otherwise it is vertex-set containment;
* faces of dimension d < n (``simplices`` and ``grep``) are reported once each, in
  increasing vertex order, except as just said.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Sequence
from itertools import combinations
from typing import Any, Generic, NamedTuple, TypeAlias, TypeVar

from persistri.impl.complex.errors import DimensionError, ForeignComplexError
from persistri.impl.complex.simplex import Simplex, TupleSimplex, check_simplex, tuple_simplex
from persistri.impl.complex.vertex import Lineage, Vertex
from persistri.impl.maps.counted import counted
from persistri.impl.stats import Stats
from persistri.spec.option import Option

__all__ = ["Complex", "Family", "ComplexStructure", "grep_in_star", "same_datum"]

D = TypeVar("D")

_Simplex: TypeAlias = Simplex
# Inside ComplexStructure the name ``Simplex`` is the SIMPCOMP signature's sub-structure.


class Family:
    """The representation a complex value belongs to: kind, dimension, backend (and the inner family).

    Two families are equal when they describe the same representation (the same
    structure class) over the *same* backend object; structures with and without a :class:`Stats`
    attached share one family, so their values are interchangeable.
    ``plain`` is the uncounted structure of the family (the invariant checks
    read values through it).
    """

    __slots__ = ("kind", "n", "backend", "sub", "plain")

    kind: str
    n: int
    backend: Any
    sub: Family | None
    plain: ComplexStructure[Any]

    def __init__(self, kind: str, n: int, backend: Any, sub: Family | None, plain: ComplexStructure[Any]) -> None:
        self.kind = kind
        self.n = n
        self.backend = backend
        self.sub = sub
        self.plain = plain

    def __eq__(self, other: object) -> bool:
        if self is other:
            return True
        if not isinstance(other, Family):
            return NotImplemented
        return (
            self.kind == other.kind
            and self.n == other.n
            and self.backend is other.backend
            and type(self.plain) is type(other.plain)
            and self.sub == other.sub
        )

    def __hash__(self) -> int:
        return hash((self.kind, self.n, id(self.backend)))

    def __repr__(self) -> str:
        inner = "" if self.sub is None else f" over {self.sub!r}"
        name = getattr(self.backend, "name", None) or repr(self.backend)
        return f"{self.n}-complex[{self.kind}{inner}; {name}]"


class Complex(NamedTuple, Generic[D]):
    """A persistent n-complex value: ``(family, rep, lineage)``; see the module docstring.

    Immutable.  ``==`` is identity: two complexes with the same simplices may
    have differently shaped maps, so compare contents with the structure's
    ``items`` (or :func:`persistri.spec.simpcomp_laws.observe`) instead.
    ``D`` is the type of the data on the n-simplices.
    """

    family: Family
    rep: Any
    lineage: Lineage | None

    def __eq__(self, other: object) -> bool:
        return self is other

    def __ne__(self, other: object) -> bool:
        return self is not other

    def __hash__(self) -> int:
        return id(self)

    def __repr__(self) -> str:
        return f"<{self.family!r}, lineage {self.lineage!r}>"


_new_complex = tuple.__new__
"""Build a :class:`Complex` without NamedTuple's Python-level ``__new__`` (the hot path)."""


class ComplexStructure(Generic[D]):
    """Base of the ``SIMPCOMP`` structures: the validated public operations over internal ones.

    Subclasses set ``n``, ``kind`` and ``family`` and implement the internal
    operations (names with one underscore), which take and return ``rep`` maps:

    ``_empty()``, ``_is_empty(rep)``, ``_vertices(rep)``, ``_data(rep, s)``,
    ``_find(rep, f)``, ``_star(rep, v)`` (the n-simplices containing ``v``),
    ``_items(rep)`` (each n-simplex once with its datum), ``_add(rep, s, x)``,
    ``_rem(rep, s)``, ``_update(rep, s, f)`` and ``_check_rep(rep)``.

    Complexities are stated for the red-black backend (O(lg n) per map
    operation); each subclass states its own per-vertex costs.
    """

    n: int
    kind: str
    family: Family
    _raw: Any
    _m: Any
    _stats: Stats | None

    def _init_maps(self, backend: Any, stats: Stats | None) -> None:
        self._raw = backend
        self._m = counted(backend, stats)
        self._stats = stats

    # -- the SIMPCOMP signature ----------------------------------------------------

    @property
    def Simplex(self) -> TupleSimplex:
        """``structure Simplex : SIMPLEX``: :data:`~persistri.impl.complex.simplex.tuple_simplex`."""
        return tuple_simplex

    @property
    def stats(self) -> Stats | None:
        """The :class:`Stats` this structure reports to, or None (uncounted)."""
        return self._stats

    def _open(self, c: Complex[D], what: str) -> tuple[Any, Lineage | None]:
        """The ``rep`` and lineage of ``c``, after checking that this structure made it."""
        try:
            fam = c.family
            rep = c.rep
            lin = c.lineage
        except AttributeError:
            raise ForeignComplexError(f"{what}: expected a complex, got {type(c).__name__}") from None
        if fam is not self.family and fam != self.family:
            mine, theirs = repr(self.family), repr(fam)
            if mine == theirs:  # same names, other objects: e.g. a backend instance made apart from persistri.maps'
                theirs += " built on other backend objects (another instance, or one unpickled without its module's)"
            raise ForeignComplexError(f"{what}: a value of {theirs} given to a structure of {mine}")
        return rep, lin

    def _arg(self, s: Any, k: int, lin: Lineage | None, what: str) -> tuple[_Simplex, Lineage | None]:
        """``s`` validated as a k-simplex of lineage ``lin`` (any one lineage if None)."""
        t, slin = check_simplex(s, what, lin)
        if len(t) != k + 1:
            raise DimensionError(
                f"{what}: {t!r} is a {len(t) - 1}-simplex; this {self.n}-complex needs a {k}-simplex here"
            )
        return t, slin

    def dim(self, c: Complex[D], /) -> int:
        """``dim c``: n.  O(1)."""
        self._open(c, "dim")
        return self.n

    def new(self, n: int, /) -> Complex[D]:
        """``new n``: the empty n-complex; ``n`` must be this structure's dimension.  O(1)."""
        if n != self.n:
            raise DimensionError(f"new: this structure makes {self.n}-complexes, not {n}-complexes")
        return _new_complex(Complex, (self.family, self._empty(), None))

    def isEmpty(self, c: Complex[D], /) -> bool:
        """``isEmpty c``: whether ``c`` has no simplices.  O(1)."""
        rep, _ = self._open(c, "isEmpty")
        return self._is_empty(rep)

    def vertices(self, c: Complex[D], /) -> Sequence[Vertex]:
        """``vertices c``: the vertices of ``c``, each once, in the backend's ``listKeys`` order.  O(V)."""
        rep, _ = self._open(c, "vertices")
        return self._vertices(rep)

    def simplices(self, c: Complex[D], d: int, /) -> Sequence[_Simplex]:
        """``simplices c d``: the d-simplices, each once: for d = n in their stored orientation,
        for d < n in increasing vertex order.  O(N) for N n-simplices."""
        rep, _ = self._open(c, "simplices")
        if not 0 <= d <= self.n:
            raise DimensionError(f"simplices: dimension {d} is outside 0..{self.n}")
        if d == self.n:
            return [t for t, _ in self._items(rep)]
        if d == 0:
            return [(v,) for v in self._vertices(rep)]
        faces: set[_Simplex] = set()
        for t, _ in self._items(rep):
            for f in combinations(sorted(t), d + 1):
                faces.add(f)
        return sorted(faces)

    def items(self, c: Complex[D], /) -> Sequence[tuple[_Simplex, D]]:
        """Each n-simplex once, with its datum (persistri's addition to SIMPCOMP).  O(N)."""
        rep, _ = self._open(c, "items")
        return list(self._items(rep))

    def iter_items(self, c: Complex[D], /) -> Iterator[tuple[_Simplex, D]]:
        """``items`` one at a time, in the same order, without a list of them all (persistri's addition).

        For reading a large final complex into arrays: the list ``items``
        builds holds a pair and a simplex tuple per n-simplex at once.  O(1) to
        start, O(N) in all.
        """
        rep, _ = self._open(c, "items")
        return iter(self._items(rep))

    def data(self, c: Complex[D], s: _Simplex, /) -> Option[D]:
        """``data (c, s)``: ``(x,)`` if the n-simplex ``s`` is held in this orientation with datum x, else None."""
        rep, lin = self._open(c, "data")
        s, _ = self._arg(s, self.n, lin, "data")
        return self._data(rep, s)

    def find(self, c: Complex[D], s: _Simplex, /) -> Sequence[_Simplex]:
        """``find (c, s)``: the n-simplices having the (n−1)-simplex ``s`` as a face with its orientation."""
        rep, lin = self._open(c, "find")
        s, _ = self._arg(s, self.n - 1, lin, "find")
        return self._find(rep, s)

    def findi(self, c: Complex[D], s: _Simplex, /) -> Sequence[tuple[_Simplex, D]]:
        """``find`` with the datum of each n-simplex found (persistri's addition; saves a ``data`` per result)."""
        rep, lin = self._open(c, "findi")
        s, _ = self._arg(s, self.n - 1, lin, "findi")
        out: list[tuple[_Simplex, D]] = []
        for t in self._find(rep, s):
            x = self._data(rep, t)
            assert x is not None
            out.append((t, x[0]))
        return out

    def neighbour(self, c: Complex[D], s: _Simplex, /) -> tuple[_Simplex, D] | None:
        """The first n-simplex ``findi(c, s)`` would give, with its datum, or None if it gives none.

        persistri's addition (the walk across a face: on a closed oriented
        surface the one triangle holding a directed edge).  Same validation and
        errors as ``findi``; the 2-complex does it with one lookup and a scan
        that stops at the hit (:meth:`~persistri.impl.complex.two_complex.TwoComplex.neighbour`).
        """
        rep, lin = self._open(c, "neighbour")
        s, _ = self._arg(s, self.n - 1, lin, "neighbour")
        for t in self._find(rep, s):
            x = self._data(rep, t)
            assert x is not None
            return t, x[0]
        return None

    def grep(self, c: Complex[D], d: int, s: _Simplex, /) -> Sequence[_Simplex]:
        """``grep c (d, s)``: the d-simplices having ``s`` as a face (see the module docstring).

        O(the star of ``s[0]``): the n-simplices around one vertex of ``s``.
        """
        rep, lin = self._open(c, "grep")
        n = self.n
        if not 0 <= d <= n:
            raise DimensionError(f"grep: dimension {d} is outside 0..{n}")
        s, _ = check_simplex(s, "grep", lin)
        k = len(s) - 1
        if not 0 <= k <= n:
            raise DimensionError(f"grep: {s!r} is a {k}-simplex; a face of this {n}-complex has dimension 0..{n}")
        if k > d:
            return []
        if d == n and k == n - 1:
            return list(self._find(rep, s))
        return grep_in_star(self._star(rep, s[0]), n, d, s)

    def add(self, c: Complex[D], s: _Simplex, x: D, /) -> Complex[D]:
        """``add (c, s, x)``: ``c`` with the n-simplex ``s`` carrying ``x``; ``c`` is unchanged.

        Raises DimensionError, RepeatedVertexError, ForeignVertexError,
        DuplicateSimplexError or OppositeOrientationError.
        """
        rep, lin = self._open(c, "add")
        s, slin = self._arg(s, self.n, lin, "add")
        rep = self._add(rep, s, x)
        if self._stats is not None:
            self._stats.faces_created += 1
        return _new_complex(Complex, (self.family, rep, slin))

    def rem(self, c: Complex[D], s: _Simplex, /) -> Complex[D]:
        """``rem (c, s)``: ``c`` without the n-simplex ``s`` (in this orientation); AbsentSimplexError if absent."""
        rep, lin = self._open(c, "rem")
        s, _ = self._arg(s, self.n, lin, "rem")
        rep = self._rem(rep, s)
        if self._stats is not None:
            self._stats.faces_deleted += 1
        return _new_complex(Complex, (self.family, rep, lin))

    def update(self, c: Complex[D], s: _Simplex, f: Callable[[D], D], /) -> Complex[D]:
        """``update (c, s, f)``: ``c`` with the datum x of ``s`` replaced by ``f(x)`` (``f`` called once)."""
        rep, lin = self._open(c, "update")
        s, _ = self._arg(s, self.n, lin, "update")
        return _new_complex(Complex, (self.family, self._update(rep, s, f), lin))

    def replace(
        self, c: Complex[D], removed: Sequence[_Simplex], added: Sequence[tuple[_Simplex, D]], /
    ) -> Complex[D]:
        """``c`` without the n-simplices ``removed`` and with ``added`` (``(simplex, datum)`` pairs).

        persistri's addition to the paper's signature: the fold ``rem`` of each
        removed simplex in turn, then ``add`` of each added one, so it raises
        what the first failing ``rem`` or ``add`` raises (``c`` is unchanged).
        Here it *is* that fold; the specialised 2-complex does the same change
        with one map operation per vertex touched
        (:meth:`~persistri.impl.complex.two_complex.TwoComplex.replace`).
        O((|removed| + |added|) · cost of rem/add).
        """
        return self._replace_fold(c, removed, added)

    def _replace_fold(self, c: Complex[D], removed: Iterable[_Simplex], added: Iterable[tuple[_Simplex, D]]) -> Complex[D]:
        """:meth:`replace` as the fold of ``rem`` and ``add`` (the definition, and every error path)."""
        self._open(c, "replace")  # even when there is nothing to fold
        out = c
        for s in removed:
            out = self.rem(out, s)
        for item in added:
            if type(item) is not tuple or len(item) != 2:
                raise TypeError(f"replace: added must hold (simplex, datum) pairs, got {item!r}")
            out = self.add(out, item[0], item[1])
        return out

    def check(self, c: Complex[D], /) -> None:
        """Assert the representation invariants of ``c`` (RepresentationError / OrientationError)."""
        rep, _ = self._open(c, "check")
        self._check_rep(rep)

    # -- internal operations (subclasses) -------------------------------------------

    def _empty(self) -> Any:
        return self._raw.empty()

    def _is_empty(self, rep: Any) -> bool:
        return bool(self._raw.isEmpty(rep))

    def _vertices(self, rep: Any) -> list[Vertex]:
        return list(self._m.listKeys(rep))

    def _data(self, rep: Any, s: _Simplex) -> Option[D]:
        raise NotImplementedError

    def _find(self, rep: Any, f: _Simplex) -> Sequence[_Simplex]:
        raise NotImplementedError

    def _star(self, rep: Any, v: Vertex) -> Sequence[_Simplex]:
        raise NotImplementedError

    def _items(self, rep: Any) -> Iterable[tuple[_Simplex, D]]:
        raise NotImplementedError

    def _add(self, rep: Any, s: _Simplex, x: D) -> Any:
        raise NotImplementedError

    def _rem(self, rep: Any, s: _Simplex) -> Any:
        raise NotImplementedError

    def _update(self, rep: Any, s: _Simplex, f: Callable[[D], D]) -> Any:
        raise NotImplementedError

    def _check_rep(self, rep: Any) -> None:
        raise NotImplementedError

    def __repr__(self) -> str:
        counted_note = "" if self._stats is None else ", counted"
        return f"<{type(self).__name__} {self.family!r}{counted_note}>"


def grep_in_star(star: Iterable[Simplex], n: int, d: int, s: Simplex) -> list[Simplex]:
    """``grep`` for every case but ``d = n, dim s = n − 1`` (which is ``find``), from the star of ``s[0]``.

    ``star`` holds the n-simplices containing ``s[0]``.  For ``d = n`` the
    result is those containing all of ``s``; for ``d < n``, their d-faces
    containing ``s``, once each: as ``join(x, s)`` when ``dim s = d − 1``, else
    in increasing vertex order.  O(|star| · C(n+1, d+1)).
    """
    sset = set(s)
    if d == n:
        return [t for t in star if sset.issubset(t)]
    k = len(s) - 1
    found: dict[frozenset[Vertex], Simplex] = {}
    for t in star:
        if not sset.issubset(t):
            continue
        others = sorted(v for v in t if v not in sset)
        for extra in combinations(others, d - k):
            key = frozenset(extra)
            if key in found:
                continue
            if d - k == 1:
                found[key] = (extra[0],) + s
            else:
                found[key] = tuple(sorted(s + extra))
    return list(found.values())


def same_datum(x: Any, y: Any) -> bool:
    """Whether two stored copies of a datum agree: identity, or ``==`` when that is a plain truth value."""
    if x is y:
        return True
    try:
        return bool(x == y)
    except Exception:  # data need not define == sensibly (numpy arrays): then only identity counts
        return False
