"""Keys that no total order can place (a NaN, sets under inclusion) are refused, never taken for another key.

Python's ``<`` says neither ``nan < 1.0`` nor ``1.0 < nan``, so a search by ``<`` alone finds ``nan`` "equal"
to whatever key it meets first: an ordered map would replace, find or remove that key instead (a wrong
answer, silently).  Every backend refuses such a key with a ValueError naming it; a hashing backend,
which could store a NaN apart, refuses it too, so that the backends stay interchangeable.
"""

from __future__ import annotations

from typing import Any

import pytest

import persistri.maps as maps
from persistri.spec.ord_map import NotFound

NAN = float("nan")
BACKENDS = [b for b in maps.BACKENDS if b != "int_trie"]
"""Every backend whose keys may be floats: the integer trie refuses any key that is not an int, a NaN included
(``tests/test_int_trie.py``)."""


def _filled(S: Any) -> Any:
    m = S.empty()
    for k in (1.0, 2.0, 3.0):
        m = S.insert(m, k, str(k))
    return m


OPERATIONS = {
    "insert": lambda S, m, k: S.insert(m, k, "x"),
    "insertWith": lambda S, m, k: S.insertWith(lambda a, b: a, m, k, "x"),
    "find": lambda S, m, k: S.find(m, k),
    "lookup": lambda S, m, k: S.lookup(m, k),
    "inDomain": lambda S, m, k: S.inDomain(m, k),
    "remove": lambda S, m, k: S.remove(m, k),
}


HASHING = {"hamt"}
"""Backends that find keys by hash: a NaN looked up is simply absent there (a right answer); stored, it is refused."""

ABSENT = {"find": None, "inDomain": False}


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("operation", sorted(OPERATIONS))
def test_a_nan_key_is_refused_and_the_map_kept(backend: str, operation: str) -> None:
    S = maps.backend(backend)
    m = _filled(S)
    if backend in HASHING and operation in ABSENT:
        assert OPERATIONS[operation](S, m, NAN) is ABSENT[operation]
    elif backend in HASHING and operation in {"lookup", "remove"}:
        with pytest.raises(NotFound):
            OPERATIONS[operation](S, m, NAN)
    else:
        with pytest.raises(ValueError, match=rf"{backend}: key.* nan .*totally ordered"):
            OPERATIONS[operation](S, m, NAN)
    assert S.listItemsi(m) == [(1.0, "1.0"), (2.0, "2.0"), (3.0, "3.0")]


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_nan_key_is_refused_by_an_empty_map(backend: str) -> None:
    S = maps.backend(backend)
    with pytest.raises(ValueError, match="not equal to itself"):
        S.insert(S.empty(), NAN, 0)
    with pytest.raises(ValueError, match="not equal to itself"):
        S.singleton(NAN, 0)


@pytest.mark.parametrize("backend", ["assoc_list", "red_black", "red_black_arena"])
def test_sets_under_inclusion_are_not_taken_for_one_key(backend: str) -> None:
    S = maps.backend(backend)
    m = S.insert(S.empty(), frozenset({1}), 1)
    with pytest.raises(ValueError, match=r"neither '<' nor '=='"):
        S.insert(m, frozenset({2}), 2)
    assert S.listItemsi(m) == [(frozenset({1}), 1)]


@pytest.mark.parametrize("backend", ["red_black", "red_black_arena"])
def test_adjust_many_refuses_a_single_nan(backend: str) -> None:
    S = maps.backend(backend)
    with pytest.raises(ValueError):
        S.adjust_many(lambda a, b: b, _filled(S), [(NAN, "x")])


@pytest.mark.parametrize("backend", ["hamt", "immutables", "pyrsistent"])
@pytest.mark.parametrize(
    "keys",
    [(frozenset({1}), frozenset({2})), ((NAN,), (1.0,)), ((1.0,), (float("nan"),), (float("nan"),))],
    ids=["sets", "nan-in-tuple", "two-nans-in-tuples"],
)
def test_a_hashing_map_never_lists_keys_that_do_not_order(backend: str, keys: tuple[Any, ...]) -> None:
    """A hashing backend stores such keys apart (it never compares on insert); its listing, which must be
    strictly increasing by ``<``, refuses them as the ordered backends refuse them on insert."""
    pytest.importorskip(backend) if backend != "hamt" else None
    S = maps.backend(backend)
    m = S.empty()
    for i, k in enumerate(keys):
        m = S.insert(m, k, i)
    for listing in (S.listItemsi, S.listKeys, lambda m: S.foldli(lambda k, v, a: a, None, m)):
        with pytest.raises(ValueError, match=rf"{backend}: keys .* are neither '<' nor '=='"):
            listing(m)
