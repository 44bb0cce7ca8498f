"""A downstream consumer of persistri, typed the way user code is.

This file lives OUTSIDE the package on purpose: it imports the *installed*
package (the strict editable install) through its public names only —
``persistri`` and its public submodules ``persistri.maps``,
``persistri.conformance`` and ``persistri.spec``, never ``persistri.impl`` — and
must pass ``mypy tests/typing/consumer.py`` under the project's strict settings
(``make typecheck`` runs it).  ``assert_type`` pins the types mypy infers, so a
change that silently widens a signature to ``Any`` (or narrows it wrongly) makes
the type check fail, not just the run.

It also runs: ``python tests/typing/consumer.py`` prints nothing and exits 0,
its ``assert`` statements checking the results of the generic code below on
every backend that exists.
"""

from __future__ import annotations

import operator
import tempfile
from collections.abc import Iterable
from pathlib import Path
from typing import Any, TypeVar, assert_never, assert_type

import numpy as np
from numpy.typing import NDArray

import persistri
from persistri import Stats
from persistri.maps import ALMap, AssocListMap, HamtMap, HMap, RBMap, RedBlackMap, assoc_list, counted, hamt, red_black
from persistri.spec import NATURAL_ORDER, SOME, NotFound, Option, OrdKey, OrdMap, Order, valOf

K = TypeVar("K")
V = TypeVar("V")
M = TypeVar("M")


# -- generic code over any ORD_MAP structure -----------------------------------


def from_items(s: OrdMap[K, V, M], items: Iterable[tuple[K, V]]) -> M:
    """The map of ``items`` (later items win), built with structure ``s``."""
    m = s.empty()
    for k, v in items:
        m = s.insert(m, k, v)
    return m


def count(s: OrdMap[K, int, M], words: Iterable[K]) -> M:
    """How often each word occurs: ``insertWith (op +)`` over ``words``."""
    m = s.empty()
    for w in words:
        m = s.insertWith(operator.add, m, w, 1)
    return m


def get_or(s: OrdMap[K, V, M], m: M, k: K, default: V) -> V:
    """The value of ``k`` in ``m``, or ``default``: the ``Option`` convention read with ``match``."""
    found: Option[V] = s.find(m, k)
    match found:
        case (v,):
            return v
        case None:
            return default
        case _:
            assert_never(found)


def lookup_or_none(s: OrdMap[K, V, M], m: M, k: K) -> V | None:
    """``lookup``, with SML's ``NotFound`` caught as a ``KeyError`` subclass."""
    try:
        return s.lookup(m, k)
    except NotFound:
        return None


def total(s: OrdMap[K, int, M], m: M) -> int:
    """The sum of the values of ``m`` (``foldli``)."""
    return s.foldli(lambda _k, v, acc: acc + v, 0, m)


def pop_all(s: OrdMap[K, V, M], m: M) -> list[V]:
    """Remove every key in increasing order; the values in that order."""
    out: list[V] = []
    for k in s.listKeys(m):
        m, v = s.remove(m, k)
        out.append(v)
    assert s.isEmpty(m)
    return out


def is_sorted(order: OrdKey[K], keys: list[K]) -> bool:
    """Whether ``keys`` increase strictly under ``order`` (an ``ORD_KEY`` structure)."""
    return all(order.compare(a, b) is Order.LESS for a, b in zip(keys, keys[1:]))


def exercise(s: OrdMap[str, int, M]) -> None:
    """Run the generic code above with structure ``s`` and check its results."""
    words = "the cat saw the dog and the cat ran".split()
    counts = count(s, words)
    assert s.listItemsi(counts) == [("and", 1), ("cat", 2), ("dog", 1), ("ran", 1), ("saw", 1), ("the", 3)]
    assert s.numItems(counts) == 6
    assert total(s, counts) == len(words)
    assert is_sorted(s.Key, s.listKeys(counts))
    assert get_or(s, counts, "cat", 0) == 2
    assert get_or(s, counts, "cow", 0) == 0
    assert lookup_or_none(s, counts, "cow") is None
    assert s.find(counts, "the") == SOME(3)
    assert valOf(s.find(counts, "dog")) == 1
    # Persistence: removing from a later version leaves the earlier one intact.
    before = s.listItemsi(counts)
    values = pop_all(s, counts)
    assert values == [v for _, v in before]
    assert s.listItemsi(counts) == before
    m1 = from_items(s, [("b", 2), ("a", 1), ("b", 20)])
    m2 = s.insert(m1, "c", 3)
    assert s.listItemsi(m1) == [("a", 1), ("b", 20)]
    assert s.listItemsi(m2) == [("a", 1), ("b", 20), ("c", 3)]


# -- the concrete backends, at concrete types ----------------------------------

# The association-list structure: its class at concrete types, and the polymorphic constant.
al: AssocListMap[int, str] = AssocListMap()
al_map = from_items(al, [(2, "two"), (1, "one")])
assert_type(al_map, "ALMap[int, str]")
assert_type(al.find(al_map, 1), "Option[str]")
assert_type(al.remove(al_map, 1), "tuple[ALMap[int, str], str]")

# Ascription to the signature hides the representation (SML's opaque ascription).
al_sig: OrdMap[int, str, ALMap[int, str]] = al
assert_type(al_sig.listItemsi(al_map), list[tuple[int, str]])
assert al_sig.listItemsi(al_map) == [(1, "one"), (2, "two")]

# The red-black tree at concrete types.
rb = RedBlackMap[int, str]()
rb_map = from_items(rb, [(3, "three"), (1, "one"), (2, "two")])
assert_type(rb_map, "RBMap[int, str]")
assert_type(rb.find(rb_map, 1), "Option[str]")
rb_sig: OrdMap[int, str, RBMap[int, str]] = rb
rb_smaller, removed = rb_sig.remove(rb_map, 2)
assert_type(removed, str)
assert removed == "two" and rb_sig.listKeys(rb_smaller) == [1, 3] and rb_sig.listKeys(rb_map) == [1, 2, 3]
assert get_or(rb_sig, rb_smaller, 2, "none") == "none"

# The HAMT at concrete types (keys must be hashable as well as ordered).
hm = HamtMap[str, int]()
hm_map = count(hm, ["b", "a", "b"])
assert_type(hm_map, HMap[str, int])
assert_type(hm.lookup(hm_map, "b"), int)
hm_sig: OrdMap[str, int, HMap[str, int]] = hm
assert hm_sig.listItemsi(hm_map) == [("a", 1), ("b", 2)]

# Counting: the counted structure has the same type and the same results.
stats = Stats()
al_counted = counted(al_sig, stats)
assert_type(al_counted, "OrdMap[int, str, ALMap[int, str]]")
assert al_counted.find(al_map, 2) == ("two",)
assert stats.dict_ops == 1 and stats.key_comparisons == 2
assert counted(al_sig, None) is al_sig

# The natural order as an ORD_KEY structure.
assert_type(NATURAL_ORDER.compare(1, 2), Order)
assert NATURAL_ORDER.compare("b", "a") is Order.GREATER
assert -Order.LESS is Order.GREATER
key_order: OrdKey[int] = NATURAL_ORDER
assert is_sorted(key_order, [1, 2, 3]) and not is_sorted(key_order, [1, 1])

# SML's NotFound is a KeyError.
try:
    al.lookup(al_map, 3)
except KeyError as exc:
    assert isinstance(exc, NotFound)
else:
    raise AssertionError("lookup of an absent key must raise NotFound")

rb_counted = counted(rb_sig, stats)
assert_type(rb_counted, "OrdMap[int, str, RBMap[int, str]]")
before_ops = stats.dict_ops
assert rb_counted.inDomain(rb_map, 3) and stats.dict_ops == before_ops + 1

backends: list[OrdMap[str, int, Any]] = [assoc_list, red_black, hamt, counted(hamt, Stats())]
for b in backends:
    exercise(b)


# -- the public geometry: scipy.spatial's shape, typed ---------------------------------

IntcArray = NDArray[np.intc]
FloatArray = NDArray[np.float64]

assert_type(persistri.__version__, str)

cube = np.array([[x, y, z] for x in (0, 2) for y in (0, 2) for z in (0, 2)], dtype=np.float64)
hull = persistri.ConvexHull(cube, history=True, backend="red_black", seed=1)
assert_type(hull, "persistri.ConvexHull[persistri.HullHistory]")  # history=True: the history is there
assert_type(hull.points, FloatArray)
assert_type(hull.simplices, IntcArray)
assert_type(hull.vertices, IntcArray)
assert_type(hull.neighbors, IntcArray)
assert_type(hull.equations, FloatArray)
assert_type(hull.duplicates, IntcArray)
assert_type(hull.volume, float)
assert_type(hull.area, float)
assert_type(hull.nsimplex, int)
assert_type(hull.history, persistri.HullHistory)
assert_type(hull.result, persistri.Hull)
assert hull.volume == 8.0 and hull.area == 24.0 and hull.vertices.tolist() == list(range(8))
assert len(hull.history) == hull.result.insertions + 1  # the README's line, as written: no narrowing needed
assert_type(persistri.ConvexHull(cube).history, None)  # without history=True
keep = bool(len(cube))
maybe = persistri.ConvexHull(cube, history=keep)  # a bool the checker cannot read: narrow it yourself
assert_type(maybe.history, "persistri.HullHistory | None")
assert maybe.history is not None and len(maybe.history) >= 1
assert_type(hull.history.simplices(0), "NDArray[np.intp]")

# Persistence: a new hull, the old one unchanged.
taller = hull.add_points([[1.0, 1.0, 5.0]])
assert_type(taller, "persistri.ConvexHull[persistri.HullHistory]")  # the history continues
assert taller.volume == 12.0 and hull.volume == 8.0

# Points too many to load: a path (or a Dask/Zarr array), hulled chunk by chunk — here in this process.
with tempfile.TemporaryDirectory() as where:
    np.save(Path(where) / "cube.npy", cube)
    chunked = persistri.ConvexHull(Path(where) / "cube.npy", workers=1, chunk_rows=3)
    assert_type(chunked.vertex_points, FloatArray)
    assert chunked.chunked is not None and chunked.volume == hull.volume
    assert chunked.vertices.tolist() == hull.vertices.tolist()

# The functions under the classes, and their result types.
deep: persistri.Hull = persistri.convex_hull(cube)
assert_type(persistri.ConvexHull.from_hull(deep), persistri.ConvexHull)  # its history: either
report = persistri.verify_hull(cube, hull.simplices)
assert_type(report, persistri.HullReport)
assert_type(report.ok, bool)
assert report.ok

xy = np.array([[0, 0], [2, 0], [0, 2], [2, 2], [3, 1]], dtype=np.float64)
tri = persistri.Delaunay(xy)
assert_type(tri, "persistri.Delaunay[None]")  # no history kept
assert_type(persistri.Delaunay(xy, history=True).history, persistri.DelaunayHistory)
assert_type(tri.add_points([[1.0, 1.0]]).history, None)
assert_type(tri.simplices, IntcArray)
assert_type(tri.neighbors, IntcArray)
assert_type(tri.convex_hull, IntcArray)
assert_type(tri.coplanar, IntcArray)
assert_type(tri.vertex_neighbor_vertices, tuple[IntcArray, IntcArray])
assert_type(tri.find_simplex(xy), IntcArray)
assert_type(tri.result, persistri.DelaunayTriangulation)
assert tri.find_simplex([[-1.0, 0.0]]).tolist() == [-1]
assert_type(persistri.delaunay(xy), persistri.DelaunayTriangulation)

heights = np.zeros((5, 6))
heights[2, 3] = 7.0
tin = persistri.greedy_insertion(heights, max_points=5)
assert_type(tin, persistri.Tin)
assert tin.n_points == 5

# Quality meshes of planar domains (Ruppert's refinement, paper §1): Triangle's dictionary in, arrays out.
square = {"vertices": [[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]], "segments": [[0, 1], [1, 2], [2, 3], [3, 0]]}
domain = persistri.PSLG.from_dict(square)
assert_type(domain, persistri.PSLG)
mesh = persistri.triangulate(domain, min_angle=30, max_area=1.0)
assert_type(mesh, persistri.QualityMesh)
assert_type(mesh.vertices, FloatArray)
assert_type(mesh.triangles, "NDArray[np.intp]")
assert_type(mesh.segments, "NDArray[np.intp]")
assert_type(mesh.undos, int)
assert_type(mesh.min_angle_reached, bool)
finer = persistri.refine(mesh, min_angle=30, max_area=0.25)
assert_type(finer, persistri.QualityMesh)
assert finer.history[0] is mesh.complex and len(finer.triangles) > len(mesh.triangles)
mesh_report = persistri.verify_mesh(domain, finer.vertices, finer.triangles, min_angle=30, max_area=0.25)
assert_type(mesh_report, persistri.MeshReport)
assert mesh_report.ok and mesh_report.mesh_area == 16
with tempfile.TemporaryDirectory() as scratch:
    poly_path = Path(scratch) / "square.poly"
    poly_path.write_text("4 2 0 0\n0 0 0\n1 4 0\n2 4 4\n3 0 4\n4 0\n0 0 1\n1 1 2\n2 2 3\n3 3 0\n0\n", encoding="utf-8")
    from_file = persistri.read_poly(poly_path)
assert_type(from_file, persistri.PSLG)
assert from_file.vertices.tolist() == square["vertices"]
assert len(persistri.triangulate(from_file).triangles) == 2

counts = Stats()
persistri.ConvexHull(cube, stats=counts)
assert counts.dict_ops > 0

# The conformance suite, under its public name (the classes only: running it is the test suite's job).
suite: type[persistri.conformance.OrdMapConformance] = persistri.conformance.OrdMapConformance
missing = persistri.conformance.missing_operations(red_black)
assert_type(missing, list[str])
assert missing == [] and suite.__name__ == "OrdMapConformance"
