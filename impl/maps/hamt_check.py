"""The HAMT's representation invariants, checked exactly: what ``HamtMap._check`` asserts.

:func:`check` walks a whole map (O(n · depth)) and asserts, with a message
naming the broken invariant, every rule of the node layout and of the
canonical form stated in :mod:`persistri.impl.maps.hamt`.  The conformance
suite runs it on every map a test makes (the ``invariants`` law).
"""

from __future__ import annotations

from typing import Any

from persistri.impl.maps.hamt_nodes import _BITS, _CKEYS, _ENTRIES, _FULL, _LEVELS, _MASK, _WIDTH, HMap, _Node

__all__ = ["check"]


def check(m: HMap[Any, Any]) -> None:
    """Assert every representation invariant, with a message naming the broken one.

    Bitmaps are disjoint 16-bit naturals, a full nodemap is the shared
    ``_FULL`` object, and a node's length is 2 + its children + twice its
    leaves; every key sits in the slot its hash bits select at each level;
    a collision node holds ≥ 2 keys, all of its hash, in strictly increasing
    order, in the slot its hash selects; no node is empty and no node holds
    a single leaf or a single collision node, except the root; the stored
    size is the real count; no key occurs twice.  O(n · depth).
    """
    assert isinstance(m, tuple) and len(m) == 2, f"hamt: a map is (size, root), got {m!r}"
    size, root = m
    keys: list[Any] = []
    # (node, depth, slots on the path to it); the root has depth 0 and no slots.
    stack: list[tuple[Any, int, tuple[int, ...]]] = [(root, 0, ())]
    while stack:
        node, depth, slots = stack.pop()
        where = f"node at slots {list(slots)}"
        assert isinstance(node, tuple) and len(node) >= 2, f"hamt: {where} is not a bitmap node: {node!r}"
        datamap, nodemap = node[0], node[1]
        for name, bits in (("datamap", datamap), ("nodemap", nodemap)):
            assert isinstance(bits, int) and 0 <= bits <= _FULL, (
                f"hamt: {where} has {name} {bits!r}, not a {_WIDTH}-bit natural number"
            )
        assert not datamap & nodemap, (
            f"hamt: {where} has slots both leaf and child: datamap {datamap:#06x}, nodemap {nodemap:#06x}"
        )
        assert nodemap != _FULL or nodemap is _FULL, f"hamt: {where} has a full nodemap that is not _FULL"
        children, leaves = nodemap.bit_count(), datamap.bit_count()
        assert len(node) == _ENTRIES + children + 2 * leaves, (
            f"hamt: {where} has {children} child bit(s) and {leaves} leaf bit(s) "
            f"but holds {len(node) - _ENTRIES} item(s), not {children + 2 * leaves}"
        )
        assert depth < _LEVELS, f"hamt: {where} is at depth {depth}, below the {_LEVELS} levels of a hash"
        if slots:
            assert children + leaves > 0, f"hamt: {where} is an empty non-root node"
            if children + leaves == 1:
                assert leaves == 0, f"hamt: {where} is a non-root node holding a single leaf (it belongs in its parent)"
                only = node[_ENTRIES]  # no leaves: the child
                assert not (isinstance(only, tuple) and len(only) > 2 and only[0] == only[1] == 0), (
                    f"hamt: {where} is a non-root node holding a single collision node (it belongs in its parent)"
                )
        d = _ENTRIES
        c = _ENTRIES + 2 * leaves
        for slot in range(_WIDTH):
            here = (*slots, slot)
            if nodemap >> slot & 1:
                child = node[c]
                c += 1
                assert isinstance(child, tuple) and len(child) >= 2, (
                    f"hamt: the child at slots {list(here)} is not a node: {child!r}"
                )
                if child[0] == 0 and child[1] == 0 and len(child) > 2:
                    keys.extend(_check_collision(child, here))
                else:
                    stack.append((child, depth + 1, here))
            elif datamap >> slot & 1:
                key = node[d]
                d += 2
                _check_slots(hash(key), here, f"key {key!r}")
                keys.append(key)
    assert len(keys) == size, f"hamt: stored size {size} but the trie holds {len(keys)} keys"
    assert len(set(keys)) == len(keys), "hamt: a key occurs twice in the trie"


def _check_collision(cnode: _Node, slots: tuple[int, ...]) -> list[Any]:
    """Assert the invariants of the collision node at ``slots``; its keys."""
    where = f"collision node at slots {list(slots)}"
    assert len(cnode) % 2 == 1, f"hamt: {where} has a malformed tuple {cnode!r}"
    assert len(cnode) >= _CKEYS + 4, f"hamt: {where} holds {(len(cnode) - _CKEYS) // 2} key(s), not ≥ 2"
    ch = cnode[2]
    assert isinstance(ch, int), f"hamt: {where} has hash {ch!r}, not an int"
    _check_slots(ch, slots, f"collision node of hash {ch!r}")
    ckeys = list(cnode[_CKEYS::2])
    for ck in ckeys:
        assert hash(ck) == ch, f"hamt: key {ck!r} (hash {hash(ck)}) is in the collision node of hash {ch}"
    for a, b in zip(ckeys, ckeys[1:]):
        assert a < b, f"hamt: {where} has {a!r} before {b!r}"
    return ckeys


def _check_slots(h: int, slots: tuple[int, ...], what: str) -> None:
    """Assert that hash ``h`` selects ``slots`` level by level (the path an entry sits on)."""
    for depth, slot in enumerate(slots):
        want = (h >> (_BITS * depth)) & _MASK
        assert want == slot, (
            f"hamt: {what} sits in slot {slot} at depth {depth} but its hash selects slot {want} "
            f"(path {list(slots)})"
        )
