"""The maps the map benchmark measures (:mod:`persistri.impl.bench.maps`): its subjects and their timed loops.

A *subject* (:class:`MapSubject`) is one map: Python's ``dict`` (the baseline
of the ratios), a persistri backend, a persistri adapter over a third-party
map, or that third-party map itself.  Each loads a :class:`Driver`: the three
loops the benchmark times (insert every key, find every key, remove every
key) written against the map's own calling convention, so that what is timed
is the map and the loop, nothing else.  :data:`SUBJECTS` lists them in table
order; the benchmark's module docstring says what each measures.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Final, Literal

from persistri.impl.maps import backend

__all__ = ["ADAPTED", "ASSOC_LIST_MAX_N", "SUBJECTS", "Driver", "Kind", "MapSubject", "ord_map_driver"]

Kind = Literal["baseline", "persistri", "adapter", "peer"]
"""What a subject is: the ``dict`` baseline, a persistri backend, a persistri adapter, or a third-party map."""

ASSOC_LIST_MAX_N: Final = 10_000
"""Largest ``n`` the association list is measured at: its operations are O(n) each, O(n²) per loop."""

# -- drivers: the three timed loops of each subject ---------------------------------------


@dataclass(frozen=True, slots=True)
class Driver:
    """The timed loops of one subject, over its own map type (opaque here)."""

    insert_all: Callable[[Sequence[int]], Any]
    """Build a map from empty by inserting ``k ↦ k`` for each key in order; return it."""
    find_all: Callable[[Any, Sequence[int]], None]
    """Look up each key in the map."""
    remove_all: Callable[[Any, Sequence[int]], Any]
    """Remove each key from the map in order; return the final map."""
    size: Callable[[Any], int]
    """The number of items of a map (untimed check)."""
    for_removal: Callable[[Any], Any]
    """The map ``remove_all`` starts from, given the built one: itself if persistent, a copy if mutable."""


def _itself(m: Any) -> Any:
    return m


def ord_map_driver(structure: Any) -> Driver:
    """The loops through the ORD_MAP operations of ``structure`` (a persistri backend or adapter)."""
    empty, insert, find, remove = structure.empty, structure.insert, structure.find, structure.remove

    def insert_all(keys: Sequence[int]) -> Any:
        m = empty()
        for k in keys:
            m = insert(m, k, k)
        return m

    def find_all(m: Any, keys: Sequence[int]) -> None:
        for k in keys:
            find(m, k)

    def remove_all(m: Any, keys: Sequence[int]) -> Any:
        for k in keys:
            m, _ = remove(m, k)
        return m

    return Driver(insert_all, find_all, remove_all, structure.numItems, _itself)


def _dict_driver() -> Driver:
    """The loops over Python's ``dict`` (mutated in place, so removal starts from a copy)."""

    def insert_all(keys: Sequence[int]) -> dict[int, int]:
        d: dict[int, int] = {}
        for k in keys:
            d[k] = k
        return d

    def find_all(d: dict[int, int], keys: Sequence[int]) -> None:
        for k in keys:
            d[k]

    def remove_all(d: dict[int, int], keys: Sequence[int]) -> dict[int, int]:
        for k in keys:
            del d[k]
        return d

    return Driver(insert_all, find_all, remove_all, len, dict)


def _method_driver(empty: Callable[[], Any], set_: str, get: str, delete: str) -> Driver:
    """The loops over a third-party persistent map through its own methods (``m = m.set(k, v)`` …)."""
    cls = type(empty())
    set_f, get_f, delete_f = getattr(cls, set_), getattr(cls, get), getattr(cls, delete)

    def insert_all(keys: Sequence[int]) -> Any:
        m = empty()
        for k in keys:
            m = set_f(m, k, k)
        return m

    def find_all(m: Any, keys: Sequence[int]) -> None:
        for k in keys:
            get_f(m, k)

    def remove_all(m: Any, keys: Sequence[int]) -> Any:
        for k in keys:
            m = delete_f(m, k)
        return m

    return Driver(insert_all, find_all, remove_all, len, _itself)


def _library_map(module: str, attr: str) -> Callable[[], Any]:
    """The empty-map constructor ``module.attr``, imported now (ImportError if missing).

    Imported by name because immutables' pure-Python ``immutables.map`` has no
    type annotations: the benchmark only calls it, so ``Any`` loses nothing.
    """
    factory: Callable[[], Any] = getattr(importlib.import_module(module), attr)
    return factory


@dataclass(frozen=True, slots=True)
class MapSubject:
    """One map the benchmark measures: its name, kind, a one-line description, and how to load it."""

    name: str
    kind: Kind
    description: str
    load: Callable[[], Driver]
    """Import what the subject needs and return its loops; raises if it is not available."""
    max_n: int | None = None
    """Largest key count it is measured at (``None``: no limit)."""
    skip_note: str = ""
    """Shown instead of figures above ``max_n``; ``{limit}`` stands for the limit."""
    compare_with: str | None = None
    """For an adapter, the library map it wraps: its note gives the adapter's overhead over it."""


SUBJECTS: Final[tuple[MapSubject, ...]] = (
    MapSubject("dict", "baseline", "Python dict (mutable C hash table): d[k]=v, d[k], del d[k]", _dict_driver),
    MapSubject(
        "red_black",
        "persistri",
        "persistri red-black tree (Okasaki insert, functional delete), pure Python",
        lambda: ord_map_driver(backend("red_black")),
    ),
    MapSubject(
        "hamt", "persistri", "persistri hash array mapped trie (Bagwell), pure Python", lambda: ord_map_driver(backend("hamt"))
    ),
    MapSubject(
        "assoc_list",
        "persistri",
        "persistri sorted association list (teaching baseline), pure Python",
        lambda: ord_map_driver(backend("assoc_list")),
        max_n=ASSOC_LIST_MAX_N,
        skip_note=(
            "measured up to {limit} keys only: O(n) per operation (n/2 cells visited, and "
            "copied by insert and remove, on average), so each figure grows linearly with n"
        ),
    ),
    MapSubject(
        "immutables",
        "adapter",
        "persistri ORD_MAP adapter over immutables.Map",
        lambda: ord_map_driver(backend("immutables")),
        compare_with="immutables.Map",
    ),
    MapSubject(
        "pyrsistent",
        "adapter",
        "persistri ORD_MAP adapter over pyrsistent.pmap",
        lambda: ord_map_driver(backend("pyrsistent")),
        compare_with="pyrsistent.pmap",
    ),
    MapSubject(
        "immutables.Map",
        "peer",
        "immutables.Map, C HAMT: .set/.get/.delete",
        lambda: _method_driver(_library_map("immutables", "Map"), "set", "get", "delete"),
    ),
    MapSubject(
        "immutables.map.Map",
        "peer",
        "immutables' pure-Python HAMT: .set/.get/.delete",
        lambda: _method_driver(_library_map("immutables.map", "Map"), "set", "get", "delete"),
    ),
    MapSubject(
        "pyrsistent.pmap",
        "peer",
        "pyrsistent.pmap, hash table over a persistent vector: .set/.get/.remove",
        lambda: _method_driver(_library_map("pyrsistent", "pmap"), "set", "get", "remove"),
    ),
)
"""Every subject, in table order; ``dict`` first, as the baseline of the ratios."""

ADAPTED: Final[dict[str, str]] = {s.name: s.compare_with for s in SUBJECTS if s.compare_with is not None}
"""Adapter name → the name of the library map it wraps (both are subjects)."""
