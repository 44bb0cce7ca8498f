"""The laws of ``signature SIMPCOMP`` (paper Fig. 3), as executable code.

A complex is checked against a *model*: a ``dict`` from the oriented key of
each n-simplex it should hold to that simplex's datum.  The oriented key of a
simplex (:func:`oriented_key`) is its vertices in increasing order (by
``Vertex.compare``) together with the parity of the permutation that sorts
them, so two orders of one orientation have one key and the two orientations
of one vertex set have two.  The laws compute everything they expect —
induced faces, containment, orientation — from vertex positions and the
model, never from the structure under test.

Each ``law_*`` function raises :class:`LawViolation` (naming the law) when
the structure breaks it; an unexpected exception from the structure is
reported as a violation of the law being checked.  Laws that perform an
operation return the new version and its model, so a test can chain them and
keep every version for :func:`law_persistence`.  Every law that performs an
operation also rechecks that the version it was given still agrees with its
model (persistence: an operation never changes its argument).

Vertices must be hashable (the model is a ``dict``).  Costs are O(N) calls of
the structure for a model of N simplices (``law_agrees``), plus what each law
states.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterable, Mapping, Sequence
from itertools import combinations
from typing import Any, TypeVar

from persistri.spec.law import SignatureLawViolation, law_decorator, raised
from persistri.spec.order import Order
from persistri.spec.simpcomp import SIMPCOMP
from persistri.spec.simplex import SIMPLEX
from persistri.spec.simplex_laws import permutation_parity

__all__ = [
    "SIMPCOMP_LAWS",
    "LawViolation",
    "OrientedKey",
    "Model",
    "oriented_key",
    "representative",
    "law_new",
    "law_agrees",
    "law_add",
    "law_add_present",
    "law_rem",
    "law_rem_absent",
    "law_add_rem_inverse",
    "law_update",
    "law_find",
    "law_grep",
    "law_neighbour",
    "law_persistence",
    "law_bad_input",
    "law_invariants",
]

Vx = TypeVar("Vx")
Sx = TypeVar("Sx")
D = TypeVar("D")
Cx = TypeVar("Cx")

OrientedKey = tuple[tuple[Any, ...], int]
"""``(vertices in increasing order, parity of the sorting permutation)``: one per oriented simplex."""

Model = Mapping[OrientedKey, Any]
"""What a complex should hold: oriented key of each n-simplex → its datum."""

SIMPCOMP_LAWS: dict[str, str] = {
    "new": "new(n) is empty: dim = n, isEmpty, no vertices and no d-simplices for any d in 0..n",
    "agrees": "a complex agrees with its model: dim and isEmpty; simplices(c, n) reports each held n-simplex "
    "exactly once; data(c, s) = SOME x for every order of the held orientation and NONE for the other; "
    "vertices(c) are the vertices of the n-simplices, once each; simplices(c, d) for d < n reports each "
    "d-face of an n-simplex exactly once and nothing else",
    "add": "add(c, s, x) holds s with datum x (data of every order of s's orientation is SOME x, of the "
    "other NONE), every other simplex as before, and s is in find(c', f) for each induced face f of s",
    "add_present": "add of an n-simplex already held, in either orientation, raises a ValueError",
    "rem": "rem(c, s) of a held n-simplex (any order of its orientation) holds every other simplex as before "
    "and not s: no order of s has data, and no face of s finds it",
    "rem_absent": "rem of an n-simplex not held in that orientation raises a ValueError",
    "add_rem_inverse": "rem(add(c, s, x), s) holds exactly what c holds",
    "update": "update(c, s, f) gives s the datum f(x), calling f once, and changes nothing else",
    "find": "find(c, f) of an (n-1)-simplex f is the held n-simplices having f as an induced face "
    "with f's orientation, each once",
    "grep": "grep(c, d, s) is the d-simplices having s as a face, each once: for d = n and dim s = n-1 as find; "
    "for dim s = d-1 < n-1 each d-face reported has s as an induced face; otherwise vertex-set containment",
    "neighbour": "in a closed, consistently oriented complex each induced face e of a held n-simplex t gives "
    "find(c, e) = [t] and find(c, flip(e)) = exactly one other n-simplex",
    "persistence": "every version agrees with the model it had when it was made, after any later operation",
    "bad_input": "a call with bad input raises a ValueError or TypeError and leaves the complex as it was",
    "invariants": "the structure's own representation check (check(c) or _check(c), when it has one) "
    "accepts every complex its operations make",
    "determinism": "answers depend only on the versions and arguments given: the same operations replayed later, "
    "on the same or another instance, give the same answers, whatever was made or freed in between "
    "(no cache keyed by object identity, no hidden state)",
    "isolation": "instances share no mutable state: operations on one instance of the structure never change "
    "what the versions of another answer",
}
"""Every ``SIMPCOMP`` law: name → statement."""


class LawViolation(SignatureLawViolation):
    """A structure broke a ``SIMPCOMP`` law (a :class:`persistri.spec.law.LawViolation`)."""

    SIGNATURE = "SIMPCOMP"
    LAWS = SIMPCOMP_LAWS


_law = law_decorator(LawViolation)


# -- keys and models ----------------------------------------------------------------------


def _sorted_positions(S: SIMPLEX[Any, Any], vs: Sequence[Any]) -> list[int]:
    cmp = S.Vertex.compare

    def by_vertex(i: int, j: int) -> int:
        return int(cmp(vs[i], vs[j]).value)

    return sorted(range(len(vs)), key=functools.cmp_to_key(by_vertex))


def _key_of(S: SIMPLEX[Any, Any], vs: Sequence[Any]) -> OrientedKey:
    order = _sorted_positions(S, vs)
    return tuple(vs[i] for i in order), permutation_parity(order) if len(vs) >= 2 else 0


def oriented_key(S: SIMPLEX[Any, Any], s: Any) -> OrientedKey:
    """The oriented key of simplex ``s`` (module docstring): equal for two orders of one orientation."""
    return _key_of(S, list(S.vertices(s)))


def representative(S: SIMPLEX[Vx, Sx], key: OrientedKey) -> Sx:
    """An ordered simplex with oriented key ``key``: sorted vertices, the last two swapped for parity 1."""
    vs = list(key[0])
    if key[1] and len(vs) >= 2:
        vs[-1], vs[-2] = vs[-2], vs[-1]
    return S.simplex(vs)


def _induced(vs: Sequence[Any], i: int) -> list[Any]:
    rest = list(vs[:i]) + list(vs[i + 1 :])
    if i % 2 == 1 and len(rest) >= 2:
        rest[-1], rest[-2] = rest[-2], rest[-1]
    return rest


def _induced_keys(S: SIMPLEX[Any, Any], vs: Sequence[Any]) -> list[OrientedKey]:
    return [_key_of(S, _induced(vs, i)) for i in range(len(vs))]


def _has_face(S: SIMPLEX[Any, Any], t_key: OrientedKey, f_key: OrientedKey) -> bool:
    """Whether the simplex of ``t_key`` has the simplex of ``f_key`` as an induced face (orientation included)."""
    vs = list(t_key[0])
    if t_key[1] and len(vs) >= 2:
        vs[-1], vs[-2] = vs[-2], vs[-1]
    return f_key in _induced_keys(S, vs)


def _even_orders(vs: Sequence[Any]) -> list[list[Any]]:
    """A few orders of one orientation: itself and, from 3 vertices, the 3-cycles of the first three."""
    out = [list(vs)]
    if len(vs) >= 3:
        out.append([vs[1], vs[2], vs[0]] + list(vs[3:]))
        out.append([vs[2], vs[0], vs[1]] + list(vs[3:]))
    return out


def _odd_order(vs: Sequence[Any]) -> list[Any]:
    return [vs[1], vs[0]] + list(vs[2:])


def _keys(S: SIMPLEX[Any, Any], ss: Iterable[Any]) -> list[OrientedKey]:
    return [oriented_key(S, s) for s in ss]


def _same(a: object, b: object) -> bool:
    return a is b or a == b


def _show_keys(keys: Iterable[OrientedKey]) -> str:
    shown = sorted((repr(k[0]) + ("'" if k[1] else "")) for k in keys)
    return "{" + ", ".join(shown[:12]) + (", …" if len(shown) > 12 else "") + "}"


# -- laws ---------------------------------------------------------------------------------


@_law("new")
def law_new(C: SIMPCOMP[Vx, Sx, D, Cx], n: int) -> Cx:
    """``new(n)`` is an empty n-complex; returns it."""
    c = C.new(n)
    if C.dim(c) != n:
        raise LawViolation("new", f"dim(new({n})) = {C.dim(c)}")
    if not C.isEmpty(c):
        raise LawViolation("new", f"isEmpty(new({n})) is false")
    if list(C.vertices(c)):
        raise LawViolation("new", f"vertices(new({n})) = {list(C.vertices(c))!r}")
    for d in range(n + 1):
        if list(C.simplices(c, d)):
            raise LawViolation("new", f"simplices(new({n}), {d}) = {list(C.simplices(c, d))!r}")
    return c


def _agrees(C: SIMPCOMP[Any, Any, Any, Any], c: Any, n: int, model: Model, law: str, where: str) -> None:
    S = C.Simplex
    at = f" ({where})" if where else ""
    if C.dim(c) != n:
        raise LawViolation(law, f"dim(c) = {C.dim(c)}, expected {n}{at}")
    if C.isEmpty(c) != (not model):
        raise LawViolation(law, f"isEmpty(c) = {C.isEmpty(c)} but the model holds {len(model)} simplices{at}")
    tops = list(C.simplices(c, n))
    keys = _keys(S, tops)
    if len(set(keys)) != len(keys):
        raise LawViolation(law, f"simplices(c, {n}) reports a simplex twice: {tops!r}{at}")
    if set(keys) != set(model):
        raise LawViolation(
            law, f"simplices(c, {n}) = {_show_keys(keys)} but the model holds {_show_keys(model)}{at}"
        )
    for key, x in model.items():
        vs = list(S.vertices(representative(S, key)))
        for order in _even_orders(vs):
            got = C.data(c, S.simplex(order))
            if got is None or not _same(got[0], x):
                raise LawViolation(law, f"data(c, {S.simplex(order)!r}) = {got!r}, expected SOME {x!r}{at}")
        if n >= 1:
            odd = S.simplex(_odd_order(vs))
            got = C.data(c, odd)
            if got is not None:
                raise LawViolation(law, f"data(c, {odd!r}) = {got!r} for the unheld orientation{at}")
    verts = list(C.vertices(c))
    vkeys = [_key_of(S, [v])[0] for v in verts]
    expected_v = {(v,) for key in model for v in key[0]}
    if len(set(vkeys)) != len(vkeys) or set(vkeys) != expected_v:
        want = [v for (v,) in expected_v]
        raise LawViolation(law, f"vertices(c) = {verts!r}, expected {[want[i] for i in _sorted_positions(S, want)]!r}{at}")
    for d in range(n):
        faces = list(C.simplices(c, d))
        fsets = [frozenset(S.vertices(f)) for f in faces]
        if any(len(S.vertices(f)) != d + 1 for f in faces) or len(set(fsets)) != len(fsets):
            raise LawViolation(law, f"simplices(c, {d}) = {faces!r} is not a list of distinct {d}-simplices{at}")
        closure = {frozenset(sub) for key in model for sub in combinations(key[0], d + 1)}
        if set(fsets) != closure:
            missing = [sorted(s, key=repr) for s in closure - set(fsets)][:3]
            extra = [sorted(s, key=repr) for s in set(fsets) - closure][:3]
            raise LawViolation(law, f"simplices(c, {d}) misses faces {missing!r} and reports non-faces {extra!r}{at}")


@_law("agrees")
def law_agrees(C: SIMPCOMP[Vx, Sx, D, Cx], c: Cx, n: int, model: Model, where: str = "") -> None:
    """``c`` agrees with ``model`` (the statement of ``agrees``).  O(N · n) structure calls plus the face sets."""
    _agrees(C, c, n, model, "agrees", where)


def _unchanged(C: SIMPCOMP[Any, Any, Any, Any], c: Any, n: int, model: Model, call: str) -> None:
    """A persistence violation unless ``c`` still agrees with ``model`` after ``call``."""
    try:
        _agrees(C, c, n, model, "persistence", f"the version given to {call}, afterwards")
    except LawViolation:
        raise
    except Exception as exc:
        raise LawViolation("persistence", f"reading the version given to {call} raised {type(exc).__name__}: {exc}") from exc


@_law("add")
def law_add(
    C: SIMPCOMP[Vx, Sx, D, Cx], c: Cx, n: int, model: Model, s: Sx, x: D, *, recheck: bool = True
) -> tuple[Cx, dict[OrientedKey, Any]]:
    """``add(c, s, x)`` for an n-simplex ``s`` held in neither orientation; returns the new version and model."""
    S = C.Simplex
    key = oriented_key(S, s)
    c2 = C.add(c, s, x)
    model2 = dict(model)
    model2[key] = x
    _agrees(C, c2, n, model2, "add", f"after add(c, {s!r}, {x!r})")
    vs = list(S.vertices(s))
    for i in range(len(vs)):
        f = S.simplex(_induced(vs, i))
        found = _keys(S, C.find(c2, f))
        if key not in found:
            raise LawViolation("add", f"find(c', {f!r}) = {list(C.find(c2, f))!r} lacks the added {s!r}")
    if recheck:
        _unchanged(C, c, n, model, f"add(c, {s!r}, {x!r})")
    return c2, model2


def _raises_bad_input(call: Callable[[], object]) -> BaseException | None:
    try:
        call()
    except (ValueError, TypeError) as exc:
        return exc
    return None


@_law("add_present")
def law_add_present(C: SIMPCOMP[Vx, Sx, D, Cx], c: Cx, n: int, model: Model, s: Sx, x: D) -> None:
    """``add`` of ``s`` held in either orientation raises a ValueError; ``c`` is unchanged."""
    S = C.Simplex
    vs = list(S.vertices(s))
    held = oriented_key(S, s) in model or _key_of(S, _odd_order(vs)) in model
    if not held:
        raise ValueError(f"law_add_present: {s!r} is not held in either orientation")
    exc = _raises_bad_input(lambda: C.add(c, s, x))
    if not isinstance(exc, ValueError):
        raise LawViolation("add_present", f"add(c, {s!r}, {x!r}) of a held simplex did not raise a ValueError ({exc!r})")
    _unchanged(C, c, n, model, f"the refused add(c, {s!r}, _)")


@_law("rem")
def law_rem(
    C: SIMPCOMP[Vx, Sx, D, Cx], c: Cx, n: int, model: Model, s: Sx, *, recheck: bool = True
) -> tuple[Cx, dict[OrientedKey, Any]]:
    """``rem(c, s)`` of a held ``s``; returns the new version and model."""
    key = oriented_key(C.Simplex, s)
    if key not in model:
        raise ValueError(f"law_rem: {s!r} is not held")
    c2 = C.rem(c, s)
    model2 = dict(model)
    del model2[key]
    _agrees(C, c2, n, model2, "rem", f"after rem(c, {s!r})")
    S = C.Simplex
    vs = list(S.vertices(s))
    for i in range(len(vs)):  # every rotation (either orientation): a copy left under any vertex would answer
        order = vs[i:] + vs[:i]
        got = C.data(c2, S.simplex(order))
        if got is not None:
            raise LawViolation("rem", f"after rem(c, {s!r}), data(c', {S.simplex(order)!r}) = {got!r}")
        for f in (S.simplex(_induced(vs, j)) for j in range(len(vs))):
            if key in _keys(S, C.find(c2, f)):
                raise LawViolation("rem", f"after rem(c, {s!r}), find(c', {f!r}) still reports it")
    if recheck:
        _unchanged(C, c, n, model, f"rem(c, {s!r})")
    return c2, model2


@_law("rem_absent")
def law_rem_absent(C: SIMPCOMP[Vx, Sx, D, Cx], c: Cx, n: int, model: Model, s: Sx) -> None:
    """``rem`` of ``s`` not held in its orientation raises a ValueError; ``c`` is unchanged."""
    if oriented_key(C.Simplex, s) in model:
        raise ValueError(f"law_rem_absent: {s!r} is held")
    exc = _raises_bad_input(lambda: C.rem(c, s))
    if not isinstance(exc, ValueError):
        raise LawViolation("rem_absent", f"rem(c, {s!r}) of an absent simplex did not raise a ValueError ({exc!r})")
    _unchanged(C, c, n, model, f"the refused rem(c, {s!r})")


@_law("add_rem_inverse")
def law_add_rem_inverse(C: SIMPCOMP[Vx, Sx, D, Cx], c: Cx, n: int, model: Model, s: Sx, x: D) -> None:
    """``rem(add(c, s, x), s)`` agrees with ``model`` (``s`` held in neither orientation)."""
    c3 = C.rem(C.add(c, s, x), s)
    _agrees(C, c3, n, model, "add_rem_inverse", f"rem(add(c, {s!r}, {x!r}), {s!r})")


@_law("update")
def law_update(
    C: SIMPCOMP[Vx, Sx, D, Cx], c: Cx, n: int, model: Model, s: Sx, f: Callable[[D], D], *, recheck: bool = True
) -> tuple[Cx, dict[OrientedKey, Any]]:
    """``update(c, s, f)`` of a held ``s``: its datum becomes ``f(x)``, ``f`` called once; returns version and model."""
    key = oriented_key(C.Simplex, s)
    if key not in model:
        raise ValueError(f"law_update: {s!r} is not held")
    calls: list[D] = []

    def counting(x: D) -> D:
        calls.append(x)
        return f(x)

    c2 = C.update(c, s, counting)
    if len(calls) != 1 or not _same(calls[0], model[key]):
        raise LawViolation("update", f"update(c, {s!r}, f) called f on {calls!r}, expected once on {model[key]!r}")
    model2 = dict(model)
    model2[key] = f(model[key])
    _agrees(C, c2, n, model2, "update", f"after update(c, {s!r}, f)")
    if recheck:
        _unchanged(C, c, n, model, f"update(c, {s!r}, f)")
    return c2, model2


@_law("find")
def law_find(C: SIMPCOMP[Vx, Sx, D, Cx], c: Cx, n: int, model: Model, f: Sx) -> None:
    """``find(c, f)`` is exactly the held n-simplices with ``f`` as an induced face, each once."""
    S = C.Simplex
    fkey = oriented_key(S, f)
    got = list(C.find(c, f))
    keys = _keys(S, got)
    expected = {k for k in model if _has_face(S, k, fkey)}
    if len(set(keys)) != len(keys) or set(keys) != expected:
        raise LawViolation("find", f"find(c, {f!r}) = {got!r}, expected {_show_keys(expected)}")


@_law("grep")
def law_grep(C: SIMPCOMP[Vx, Sx, D, Cx], c: Cx, n: int, model: Model, d: int, s: Sx) -> None:
    """``grep(c, d, s)`` against the model (the statement of ``grep``)."""
    S = C.Simplex
    vs = list(S.vertices(s))
    k = len(vs) - 1
    sset = set(vs)
    got = list(C.grep(c, d, s))
    call = f"grep(c, {d}, {s!r}) = {got!r}"
    if k > d:
        if got:
            raise LawViolation("grep", f"{call}, but a {k}-simplex is a face of no {d}-simplex")
        return
    if d == n:
        keys = _keys(S, got)
        if k == n - 1:
            skey = oriented_key(S, s)
            expected = {t for t in model if _has_face(S, t, skey)}
        else:
            expected = {t for t in model if sset <= set(t[0])}
        if len(set(keys)) != len(keys) or set(keys) != expected:
            raise LawViolation("grep", f"{call}, expected {_show_keys(expected)}")
        return
    sets = [frozenset(S.vertices(t)) for t in got]
    expected_sets = {
        frozenset(sub) for t in model for sub in combinations(t[0], d + 1) if sset <= set(sub)
    }
    if len(set(sets)) != len(sets) or set(sets) != expected_sets:
        shown = sorted((list(_key_of(S, list(f))[0]) for f in expected_sets), key=repr)  # by compare: vertices need no <
        raise LawViolation("grep", f"{call}, expected the {d}-faces {shown!r}")
    if k == d - 1 and k >= 1:
        skey = oriented_key(S, s)
        for t in got:
            if skey not in _induced_keys(S, list(S.vertices(t))):
                raise LawViolation("grep", f"{call}: {t!r} does not have {s!r} as an induced face")


@_law("neighbour")
def law_neighbour(C: SIMPCOMP[Vx, Sx, D, Cx], c: Cx, n: int) -> None:
    """In a closed, consistently oriented n-complex (n ≥ 2), ``find`` gives each simplex's neighbours."""
    S = C.Simplex
    for t in C.simplices(c, n):
        tkey = oriented_key(S, t)
        vs = list(S.vertices(t))
        for i in range(len(vs)):
            e = S.simplex(_induced(vs, i))
            own = _keys(S, C.find(c, e))
            if own != [tkey]:
                raise LawViolation("neighbour", f"find(c, {e!r}) = {list(C.find(c, e))!r}, expected just {t!r}")
            back = S.flip(e)
            other = list(C.find(c, back))
            if len(other) != 1 or S.compare(other[0], t) is Order.EQUAL:
                raise LawViolation(
                    "neighbour", f"find(c, flip({e!r})) = {other!r}: the face {e!r} of {t!r} needs exactly one neighbour"
                )


@_law("persistence")
def law_persistence(C: SIMPCOMP[Vx, Sx, D, Cx], n: int, history: Sequence[tuple[Cx, Model]]) -> None:
    """Every ``(version, model)`` of ``history`` still agrees.  O(total size of the models)."""
    for i, (c, model) in enumerate(history):
        _agrees(C, c, n, model, "persistence", f"version {i} of {len(history)}")


def law_bad_input(C: SIMPCOMP[Vx, Sx, D, Cx], c: Cx, n: int, model: Model, call: Callable[[], object], what: str) -> None:
    """``call()`` — a call on ``c`` with bad input, described by ``what`` — raises a ValueError or TypeError,
    and ``c`` still agrees with ``model`` afterwards."""
    try:
        call()
    except (ValueError, TypeError):
        pass
    except Exception as exc:
        raise LawViolation("bad_input", f"{what} raised {type(exc).__name__}: {exc}, not a ValueError or TypeError") from exc
    else:
        raise LawViolation("bad_input", f"{what} did not raise")
    _unchanged(C, c, n, model, f"the refused {what}")


def law_invariants(check: Callable[[Cx], object], c: Cx, where: str = "") -> None:
    """The structure's representation check ``check`` accepts ``c`` (any exception it raises is a violation)."""
    try:
        check(c)
    except Exception as exc:
        at = f" ({where})" if where else ""
        raise LawViolation("invariants", f"the check rejected the complex{at}: {raised(exc)}") from exc
