"""The ``ORD_MAP`` laws as plain functions over a structure, for the CrossHair contracts.

:mod:`proofs.crosshair_maps` checks each law on each pure backend through one
contracted function per law and backend; the laws themselves live here, with
no contract, so that CrossHair checks them only through those functions (and
``tests/crosshair_fixtures/broken_laws.py`` runs them on deliberately broken
maps).  Each law takes the structure ``s`` (an ``ORD_MAP`` of
:mod:`persistri.spec.ord_map`) and a key list; a map is built by inserting
``keys[i] ↦ i`` in order, so a key's value is the position of its *last*
occurrence.  Expectations are computed from the key list alone (``sorted``,
``set``, positions), never from another map implementation.  Every law
returns ``bool``; :func:`holds` turns an exception raised inside a law into
:class:`LawRaised`, which CrossHair reports as a counterexample.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from persistri.spec.option import NONE
from persistri.spec.ord_map import NotFound

__all__ = [
    "LawRaised",
    "holds",
    "int_key",
    "Clash",
    "last",
    "build",
    "insert_find",
    "insert_other",
    "insert_with",
    "items",
    "remove",
    "every_version",
    "persistence",
    "invariant",
]


class LawRaised(Exception):
    """A map operation raised an exception where the law says it must not.

    The message names the original exception; it is formatted while CrossHair
    still traces, because CrossHair 0.0.112 cannot format an exception whose
    arguments hold symbolic values (``NotFound(k)``) after the call has returned:
    it stops with ``CrossHairInternal`` instead of reporting the counterexample.
    """


def holds(law: Callable[..., bool], *args: Any) -> bool:
    """``law(*args)``, with any exception it raises re-raised as :class:`LawRaised`."""
    try:
        return law(*args)
    except Exception as exc:  # CrossHair's own control flow uses BaseException, never caught here
        raise LawRaised(f"{type(exc).__name__}: {exc}") from None


def int_key(k: int) -> Any:
    """Plain integer keys."""
    return k


class Clash:
    """An integer key whose hash keeps only ``k % 4``, in bits 10–11.

    Distinct keys with equal ``k % 4`` have equal hashes (the HAMT's collision
    nodes), and keys with different hashes share the first two trie levels
    (slot 0 at depths 0 and 1) before they part at depth 2.  Order and
    equality are those of ``k``, so ``Clash`` is monotone in ``k``.
    """

    __slots__ = ("k",)

    def __init__(self, k: int) -> None:
        self.k = k

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Clash) and self.k == other.k

    def __lt__(self, other: Clash) -> bool:
        return self.k < other.k

    def __hash__(self) -> int:
        return (self.k % 4) << 10

    def __repr__(self) -> str:
        return f"Clash({self.k!r})"


def last(keys: list[int], k: int) -> int:
    """The position of the last occurrence of ``k`` in ``keys`` (``k`` must occur)."""
    pos = -1
    for i, x in enumerate(keys):
        if x == k:
            pos = i
    assert pos >= 0
    return pos


def build(s: Any, keys: list[int], key: Callable[[int], Any]) -> Any:
    """The map ``{key(keys[i]) ↦ i}`` made by inserting in order: later occurrences win."""
    m = s.empty()
    for i, k in enumerate(keys):
        m = s.insert(m, key(k), i)
    return m


def insert_find(s: Any, keys: list[int], k: int, v: int) -> bool:
    """``find(insert(m, k, v), k) == SOME v``; ``lookup`` and ``inDomain`` agree."""
    m = s.insert(build(s, keys, int_key), k, v)
    return bool(s.find(m, k) == (v,) and s.lookup(m, k) == v and s.inDomain(m, k))


def insert_other(s: Any, keys: list[int], k: int, j: int, v: int) -> bool:
    """For ``j != k``: ``find(insert(m, k, v), j) == find(m, j)``."""
    m = build(s, keys, int_key)
    return bool(s.find(s.insert(m, k, v), j) == s.find(m, j))


def insert_with(s: Any, keys: list[int], k: int, v: int) -> bool:
    """``insertWith f (m, k, v)`` stores ``f(old, v)`` when ``k ↦ old`` is present, else ``v``.

    ``f`` is subtraction, which is not symmetric, so swapped arguments are caught.
    """
    m = s.insertWith(lambda old, new: old - new, build(s, keys, int_key), k, v)
    expected = last(keys, k) - v if k in keys else v
    return bool(s.find(m, k) == (expected,) and s.numItems(m) == len(set([*keys, k])))


def items(s: Any, keys: list[int], key: Callable[[int], Any] = int_key) -> bool:
    """``listItemsi`` is sorted and holds each key once with its last value; counts agree.

    ``listKeys``, ``numItems``, ``isEmpty`` and ``foldli`` are checked against it.
    """
    m = build(s, keys, key)
    distinct = sorted(set(keys))
    expected = [(key(k), last(keys, k)) for k in distinct]
    folded = s.foldli(lambda k, v, acc: [*acc, (k, v)], [], m)
    return bool(
        s.listItemsi(m) == expected
        and s.listKeys(m) == [key(k) for k in distinct]
        and folded == expected
        and s.numItems(m) == len(distinct)
        and s.isEmpty(m) == (len(keys) == 0)
    )


def remove(s: Any, keys: list[int], k: int, key: Callable[[int], Any] = int_key) -> bool:
    """``remove(m, k)`` returns ``(m without k, its value)`` satisfying ``_check``; an absent key raises ``NotFound``."""
    m = build(s, keys, key)
    before = s.listItemsi(m)
    if k not in keys:
        try:
            s.remove(m, key(k))
        except NotFound:
            pass
        else:
            return False
        try:
            s.lookup(m, key(k))
        except NotFound:
            return s.find(m, key(k)) is NONE and s.listItemsi(m) == before
        return False
    m2, v = s.remove(m, key(k))
    s._check(m2)  # the representation invariant after the removal, too
    return bool(
        v == last(keys, k)
        and s.find(m2, key(k)) is NONE
        and s.numItems(m2) == s.numItems(m) - 1
        and s.listItemsi(m2) == [item for item in before if item[0] != key(k)]
    )


def every_version(
    s: Any, keys: list[int], dels: list[int], key: Callable[[int], Any]
) -> tuple[list[Any], list[list[tuple[Any, int]]]]:
    """Every version made by inserting ``keys`` then removing the present keys of ``dels``,
    each with the items it had when it was made."""
    versions = [s.empty()]
    seen: list[list[tuple[Any, int]]] = [[]]
    for i, k in enumerate(keys):
        versions.append(s.insert(versions[-1], key(k), i))
        seen.append(s.listItemsi(versions[-1]))
    for k in dels:
        if s.inDomain(versions[-1], key(k)):
            versions.append(s.remove(versions[-1], key(k))[0])
            seen.append(s.listItemsi(versions[-1]))
    return versions, seen


def persistence(s: Any, keys: list[int], dels: list[int], key: Callable[[int], Any] = int_key) -> bool:
    """After all later inserts and removes, every earlier version still has its items."""
    versions, seen = every_version(s, keys, dels, key)
    return all(s.listItemsi(m) == had for m, had in zip(versions, seen))


def invariant(s: Any, keys: list[int], dels: list[int], key: Callable[[int], Any] = int_key) -> bool:
    """The backend's representation invariant (``_check``) holds in every version."""
    versions, _ = every_version(s, keys, dels, key)
    for m in versions:
        s._check(m)  # raises AssertionError when an invariant is broken
    return True
