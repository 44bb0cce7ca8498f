"""The HAMT map (:mod:`persistri.impl.maps.hamt`) with colliding hashes: collision nodes and deep tries.

Keys whose whole hash collides share a collision node, kept in key order and
turned back into a leaf when one key is left; a different hash in the same slot
pushes the collision node one level down, and deleting it moves it back up.
Keys whose hashes share a long prefix make chains of single-child nodes down to
the last level (depth 15 of 64-bit hashes in 4-bit slices), which deletions
collapse again.  ``NotFound`` is raised wherever an absent key's search ends.
"""

from __future__ import annotations

import pytest

from persistri.impl.maps.hamt import hamt
from persistri.impl.maps.hamt_nodes import _BIT
from persistri.spec.ord_map import NotFound

from hamt_helpers import (
    P,
    HKey,
    build,
    children,
    collision_keys,
    collision_nodes,
    combine,
    depth,
    is_collision,
    key_maker,
    leaves,
    nodes,
    signed64,
)


# -- collisions -----------------------------------------------------------------


def test_python_int_collisions() -> None:
    """``-1`` and ``-2`` hash alike, as do ``0, P, 2P, -P``: they share collision nodes."""
    assert hash(-1) == hash(-2) and hash(0) == hash(P) == hash(2 * P) == hash(-P)
    m = build([(-1, "a"), (-2, "b"), (0, "z"), (P, "p"), (2 * P, "pp"), (-P, "-p"), (5, "five")])
    hamt._check(m)
    sizes = sorted(len(collision_keys(c)) for c in collision_nodes(m))
    assert sizes == [2, 4]
    assert hamt.find(m, -1) == ("a",) and hamt.find(m, -2) == ("b",)
    assert hamt.find(m, P) == ("p",) and hamt.find(m, 3 * P) is None
    assert hamt.listKeys(m) == [-P, -2, -1, 0, 5, P, 2 * P]
    # Each collision node keeps its keys in increasing order, whatever the insertion order.
    assert build([(2 * P, 1), (-P, 1), (P, 1), (0, 1)]) == build([(0, 1), (P, 1), (-P, 1), (2 * P, 1)])
    # Removing down to one key turns the collision node back into a leaf.
    m2, v = hamt.remove(m, -2)
    assert v == "b"
    hamt._check(m2)
    assert sorted(len(collision_keys(c)) for c in collision_nodes(m2)) == [4]
    assert hamt.find(m2, -1) == ("a",) and hamt.find(m2, -2) is None
    # The old version still has both.
    assert hamt.find(m, -2) == ("b",)


def test_collision_node_meets_a_different_hash() -> None:
    """A key whose hash differs from a collision node's, in the same slot, pushes both one level down."""
    a, b = HKey(1, 0), HKey(2, 0)
    c = HKey(3, 1 << 5)  # same level-0 slot (0), different level-1 slot
    m = build([(a, "a"), (b, "b")])
    assert m.root[:2] == (0, 1) and is_collision(m.root[2])
    m2 = hamt.insert(m, c, "c")
    hamt._check(m2)
    assert m2.root[:2] == (0, 1) and not is_collision(m2.root[2]) and depth(m2) == 1
    assert len(children(m2.root[2])) == 1 and leaves(m2.root[2]) == [(c, "c")]
    assert [hamt.find(m2, k) for k in (a, b, c)] == [("a",), ("b",), ("c",)]
    m3, _ = hamt.remove(m2, c)
    assert m3 == m  # the collision node moves back up into the root


def test_insert_with_in_collision_node() -> None:
    a, b = HKey(1, 9), HKey(2, 9)
    m = build([(a, 10), (b, 20)])
    m = hamt.insertWith(combine, m, HKey(2, 9), 1)
    m = hamt.insertWith(combine, m, HKey(3, 9), 4)
    hamt._check(m)
    assert hamt.listItemsi(m) == [(a, 10), (b, 20 * 31 + 1), (HKey(3, 9), 4)]


def test_remove_not_found_everywhere() -> None:
    """NotFound (a KeyError) from an empty slot, another leaf, a foreign collision node, an absent colliding key."""
    m = build([(HKey(1, 0), 1), (HKey(2, 0), 2), (HKey(3, 1), 3)])
    for absent in (HKey(4, 2), HKey(4, 1), HKey(4, 32), HKey(4, 0)):
        with pytest.raises(NotFound):
            hamt.remove(m, absent)
        with pytest.raises(KeyError):
            hamt.lookup(m, absent)
        assert hamt.find(m, absent) is None
    with pytest.raises(NotFound):
        hamt.remove(hamt.empty(), 0)


# -- deep tries -------------------------------------------------------------------


def test_deep_trie_ints() -> None:
    """``0`` and ``2**60`` agree on hash bits 0–59: a chain of single-child nodes, parting at depth 15."""
    m = build([(0, "a"), (1 << 60, "b")])
    hamt._check(m)
    assert depth(m) == 15
    assert all(node[:2] == (0, 1) and len(node) == 3 for d, node in nodes(m) if d < 15)
    assert [leaves(node) for d, node in nodes(m) if d == 15] == [[(0, "a"), (1 << 60, "b")]]
    m2, _ = hamt.remove(m, 0)
    hamt._check(m2)
    assert depth(m2) == 0 and m2 == hamt.singleton(1 << 60, "b")


def test_deep_trie_sign_bit() -> None:
    """Hashes differing only in bit 63 (the sign) part at the last level."""
    a, b = HKey(0, 5), HKey(1, signed64((1 << 63) + 5))
    assert hash(b) < 0
    m = build([(a, 0), (b, 1)])
    hamt._check(m)
    assert depth(m) == 15 and not collision_nodes(m)
    c = HKey(2, 5)  # same full hash as a: a collision node at the bottom
    m2 = hamt.insert(m, c, 2)
    hamt._check(m2)
    assert depth(m2) == 15 and len(collision_nodes(m2)) == 1
    m3, _ = hamt.remove(m2, b)
    hamt._check(m3)
    # The collision node rises to the root.
    assert depth(m3) == 0 and m3.root[:2] == (0, _BIT[5]) and collision_keys(m3.root[2]) == [a, c]


def test_many_deep_keys() -> None:
    key = key_maker("shared-58-bits")
    m = build([(key(n), n) for n in range(64)])
    hamt._check(m)
    assert depth(m) == 15
    for n in range(0, 64, 2):
        m, _ = hamt.remove(m, key(n))
        hamt._check(m)
    assert m == build([(key(n), n) for n in range(1, 64, 2)])
