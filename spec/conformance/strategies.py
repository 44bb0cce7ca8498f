"""The keys, values and maps the ``ORD_MAP`` conformance suite generates (hypothesis strategies).

Keys come in *kinds*; one map only ever holds keys of one kind, so that its
keys are always mutually ordered:

* ``"int"`` — Python integers: mostly small (so that inserts overwrite and
  removes hit), sometimes arbitrary; with ``hashing`` also the integers whose
  Python hashes collide (``hash(-1) == hash(-2)``, ``hash(0) == hash(2**61 - 1)``,
  ``hash(1) == hash(2**61)``);
* ``"CollidingKey"`` (only with ``hashing``) — :class:`CollidingKey`, ordered by
  one field and hashed by a coarse function of it, so that many distinct keys
  share one full hash (a HAMT's collision nodes).

The structure under test must order both kinds by Python's ``<``/``==`` or by
its own ``Key.compare`` consistently with ``==``; ``law_key_order`` checks it.
Values include ``None`` (``find`` must then return ``(None,)``) and 1-tuples
(which must not be confused with the option that holds them).
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any, Literal

from hypothesis import strategies as st

from persistri.spec.ord_map import NotFound
from persistri.spec.ord_map_laws import LawViolation

__all__ = [
    "COLLIDING_INTS",
    "CollidingKey",
    "KeyKind",
    "key_kinds",
    "keys",
    "small_keys",
    "values",
    "fresh_key",
    "MapCase",
    "map_cases",
]

COLLIDING_INTS: tuple[int, ...] = (-1, -2, 0, 2**61 - 1, -(2**61 - 1), 1, 2**61)
"""Python integers whose hashes collide in pairs and triples (CPython hashes ints modulo 2**61 − 1, and -1 as -2)."""

KeyKind = Literal["int", "CollidingKey"]


@dataclass(frozen=True, order=True)
class CollidingKey:
    """A key ordered (and compared) by ``rank`` whose hash is that of the coarse ``rank >> 3``.

    Eight consecutive ranks share one hash, so distinct keys collide on the
    *full* hash, not just on a few bits of it.
    """

    rank: int

    def __hash__(self) -> int:
        return hash(self.rank >> 3)


def key_kinds(hashing: bool) -> tuple[KeyKind, ...]:
    """The key kinds in use: only ``"int"`` without ``hashing``."""
    return ("int", "CollidingKey") if hashing else ("int",)


@functools.cache
def _ints(hashing: bool) -> st.SearchStrategy[int]:
    small = st.integers(-12, 12)
    if hashing:
        return st.one_of(small, st.sampled_from(COLLIDING_INTS), st.integers())
    return st.one_of(small, st.integers())


@functools.cache
def keys(kind: KeyKind, hashing: bool) -> st.SearchStrategy[Any]:
    """Keys of one kind (see the module docstring); shrinks towards small integers.

    Strategies are cached: building one per draw would revalidate it every time.
    """
    if kind == "int":
        return _ints(hashing)
    return st.builds(CollidingKey, _ints(hashing))


@functools.cache
def small_keys(kind: KeyKind, hashing: bool) -> st.SearchStrategy[Any]:
    """Keys of one kind from a small range (plus the colliding integers): programs of a few steps revisit them."""
    ints = st.integers(-6, 6)
    if hashing:
        ints = st.one_of(ints, st.sampled_from(COLLIDING_INTS))
    return ints if kind == "int" else st.builds(CollidingKey, ints)


@functools.cache
def values() -> st.SearchStrategy[Any]:
    """Stored values: ``None``, small integers, short strings and 1-tuples (one cached strategy)."""
    return st.one_of(st.none(), st.integers(-3, 3), st.text(max_size=2), st.tuples(st.integers(0, 2)))


def fresh_key(kind: KeyKind, used: Iterable[Any]) -> Any:
    """A key of ``kind`` greater than every key in ``used`` (so certainly absent from them)."""
    us = list(used)
    if kind == "int":
        return max(us, default=0) + 1
    return CollidingKey(max((u.rank for u in us), default=0) + 1)


@dataclass(frozen=True)
class MapCase:
    """One law's input: the map made by inserting ``items`` in order into ``empty()``, then removing
    ``removed``; a key and a value to apply the law to; and some ``probes`` (other keys to look at).
    """

    kind: KeyKind
    items: tuple[tuple[Any, Any], ...]
    removed: tuple[Any, ...]
    key: Any
    value: Any
    probes: tuple[Any, ...]
    model: dict[Any, Any] = field(repr=False, compare=False, hash=False)
    """The items the map should hold (Python's ``dict`` as the model)."""

    def build(self, s: Any, after: Callable[[Any], None] | None = None) -> Any:
        """The map, built with ``s``'s operations; ``after(m)`` is called on every intermediate version."""
        m = s.empty()
        for k, v in self.items:
            m = s.insert(m, k, v)
            if after is not None:
                after(m)
        for k in self.removed:
            try:
                m, _ = s.remove(m, k)
            except NotFound as exc:
                raise LawViolation(
                    "remove",
                    f"while building the case's map: remove of {k!r}, inserted and not yet removed, raised NotFound",
                ) from exc
            if after is not None:
                after(m)
        return m


@functools.cache
def _kinds(hashing: bool) -> st.SearchStrategy[KeyKind]:
    return st.sampled_from(key_kinds(hashing))


@functools.cache
def _item_lists(kind: KeyKind, hashing: bool, min_size: int, max_size: int) -> st.SearchStrategy[list[tuple[Any, Any]]]:
    return st.lists(st.tuples(keys(kind, hashing), values()), min_size=min_size, max_size=max_size)


@functools.cache
def _probe_lists(kind: KeyKind, hashing: bool) -> st.SearchStrategy[list[Any]]:
    return st.lists(keys(kind, hashing), max_size=5)


@st.composite
def map_cases(
    draw: st.DrawFn,
    hashing: bool,
    key_mode: Literal["present", "absent", "any"] = "any",
    max_items: int = 24,
) -> MapCase:
    """A :class:`MapCase` whose ``key`` is present in the map, absent from it, or either (``key_mode``)."""
    kind = draw(_kinds(hashing))
    ks = keys(kind, hashing)
    items = draw(_item_lists(kind, hashing, 1 if key_mode == "present" else 0, max_items))
    model: dict[Any, Any] = {}
    for k, v in items:
        model[k] = v
    distinct = sorted(model)
    keep = 1 if key_mode == "present" else 0
    removed: list[Any] = []
    if len(distinct) > keep:
        removed = draw(st.lists(st.sampled_from(distinct), unique=True, max_size=len(distinct) - keep))
    for k in removed:
        del model[k]
    present = sorted(model)
    pick_present = key_mode == "present" or (key_mode == "any" and len(present) > 0 and draw(st.booleans()))
    if pick_present:
        key = draw(st.sampled_from(present))
    else:
        key = draw(ks)
        if key in model:
            key = fresh_key(kind, [*model, *removed])
    probes = draw(_probe_lists(kind, hashing))
    return MapCase(kind, tuple(items), tuple(removed), key, draw(values()), tuple(probes), model)
