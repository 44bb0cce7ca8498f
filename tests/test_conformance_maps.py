"""Every persistri map backend passes the ``ORD_MAP`` conformance suite (as an outsider would run it).

One subclass of :class:`~persistri.spec.conformance.OrdMapConformance` per entry
of :data:`persistri.impl.maps.BACKENDS`.  A backend whose module does not exist
(yet) is skipped, and only then: a module that exists but fails to import is an
error.
"""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path
from typing import Any

import pytest

from persistri.impl.maps import BACKENDS, backend
from persistri.spec.conformance import ORD_MAP_OPERATIONS, ORD_MAP_TESTS, OrdMapConformance, missing_operations
from persistri.spec.ord_map import OrdMap


def _module_exists(name: str) -> bool:
    return importlib.util.find_spec(BACKENDS[name].split(":")[0]) is not None


def _load(name: str) -> Any:
    """The backend's structure, or None when its module does not exist."""
    return backend(name) if _module_exists(name) else None


def _needs(name: str) -> pytest.MarkDecorator:
    return pytest.mark.skipif(not _module_exists(name), reason=f"{BACKENDS[name]} does not exist yet")


# The backends kept pure Python in the compiled twin: their suites run once, on the interpreted build
# (``build_independent``, tests/conftest.py).  ``test_the_uncompiled_backends_are_not_in_the_twin`` keeps
# this list true to ``tools/compiled_twin.py``.
UNCOMPILED = ("assoc_list", "hamt", "immutables", "pyrsistent")
_uncompiled = pytest.mark.build_independent


@_uncompiled
@_needs("assoc_list")
class TestAssocList(OrdMapConformance):
    structure = _load("assoc_list")
    # O(n) per operation: 10^5 sequential keys would be ~5·10^9 cell visits per workload.
    workload_size = 2_000


@_needs("red_black")
class TestRedBlack(OrdMapConformance):
    structure = _load("red_black")


@_uncompiled
@_needs("hamt")
class TestHamt(OrdMapConformance):
    structure = _load("hamt")


@_needs("red_black_arena")
class TestRedBlackArena(OrdMapConformance):
    structure = _load("red_black_arena")


@_uncompiled
@_needs("immutables")
class TestImmutables(OrdMapConformance):
    structure = _load("immutables")


@_uncompiled
@_needs("pyrsistent")
class TestPyrsistent(OrdMapConformance):
    structure = _load("pyrsistent")


@_needs("int_trie")
class TestIntTrie(OrdMapConformance):
    structure = _load("int_trie")
    hashing = False  # integer keys only: the colliding keys of the hashing kind are not integers


def test_every_backend_has_a_conformance_class() -> None:
    covered = {"assoc_list", "red_black", "hamt", "red_black_arena", "immutables", "pyrsistent", "int_trie"}
    assert covered == set(BACKENDS)


def test_base_class_has_one_method_per_suite_test() -> None:
    methods = {n for n in vars(OrdMapConformance) if n.startswith("test_")}
    assert methods == {f"test_{t.name}" for t in ORD_MAP_TESTS}


def test_the_operation_list_is_the_protocol() -> None:
    members = [n for n in vars(OrdMap) if not n.startswith("_")]
    assert list(ORD_MAP_OPERATIONS) == members


class _Odd:
    """An object with every kind of defect missing_operations looks for."""

    empty = 3  # not callable

    @property
    def Key(self) -> object:
        return object()  # no compare

    @property
    def find(self) -> object:
        raise RuntimeError("a property that raises is unusable")


def test_missing_operations() -> None:
    assert missing_operations(backend("assoc_list")) == []
    assert missing_operations(_Odd()) == [
        "Key.compare", "empty", "isEmpty", "singleton", "insert", "insertWith", "find", "lookup",
        "inDomain", "remove", "numItems", "listItemsi", "listKeys", "foldli",
    ]
    assert missing_operations(object()) == list(ORD_MAP_OPERATIONS)


def test_the_uncompiled_backends_are_not_in_the_twin() -> None:
    """The classes left to the interpreted run are those of :data:`UNCOMPILED`, and no module of theirs
    (the backend's module or one named after it) is compiled by ``tools/compiled_twin.py``."""
    marked = {
        name
        for name, cls in globals().items()
        if name.startswith("Test") and any(m.name == "build_independent" for m in getattr(cls, "pytestmark", []))
    }
    assert marked == {"TestAssocList", "TestHamt", "TestImmutables", "TestPyrsistent"}
    source = (Path(__file__).resolve().parents[1] / "tools" / "compiled_twin.py").read_text(encoding="utf-8")
    compiled = re.findall(r'"persistri/([a-z_/]+)\.py"', source)
    assert "impl/maps/red_black_tree" in compiled  # the list was found
    for name in UNCOMPILED:
        module = BACKENDS[name].split(":")[0].removeprefix("persistri.").replace(".", "/")
        assert not [path for path in compiled if path.startswith(module)], (name, module)
