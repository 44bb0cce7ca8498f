"""The HAMT's ``_check`` (:mod:`persistri.impl.maps.hamt`) catches broken tries, naming what is wrong.

Hand-built tries each break one rule of the layout or of canonical form
(bitmap sizes, slots the hash does not select, leaves that should be pulled up,
unsorted or single-key collision nodes, wrong stored sizes, nodes below the
last level), and a real trie is broken by flipping one bit of a bitmap or by a
full nodemap that is an equal int but not the shared ``_FULL``.
"""

from __future__ import annotations

from typing import Any

import pytest

from persistri.impl.maps.hamt import HMap, hamt
from persistri.impl.maps.hamt_nodes import _BIT, _FULL

from hamt_helpers import P, build, leaves


# -- _check catches broken tries ------------------------------------------------------


def broken(size: int, root: Any) -> HMap[Any, Any]:
    return HMap(size, root)


def _chain(levels: int, bottom: tuple[Any, ...]) -> tuple[Any, ...]:
    """``bottom`` under ``levels`` single-child nodes whose one child sits in slot 15 (a root in slot 14)."""
    node = bottom
    for _ in range(levels):
        node = (0, _BIT[15], node)
    return (0, _BIT[14], node)


@pytest.mark.parametrize(
    ("m", "message"),
    [
        (broken(1, (0b11, 0, 1, "a")), r"holds 2 item\(s\), not 4"),
        (broken(1, (0b100, 0, 1, "a")), "hash selects slot 1"),
        (broken(1, (1 << 16, 0, 1, "a")), "16-bit"),
        (broken(1, (0b1, 0b1, 0, "a", (0b1, 0, 0, "a"))), "both leaf and child"),
        (broken(1, (0, 0b1, (0b1, 0, 0, "a"))), "single leaf"),
        (broken(0, (0, 0b1, (0, 0))), "empty non-root node"),
        (broken(2, (0, 0b1, (0, 0b1, (0, 0, 0, 0, "a", P, "b")))), "single collision node"),
        (broken(1, (0, 0b1, (0, 0, 0, 0, "a"))), "not ≥ 2"),
        (broken(2, (0, 0b1, (0, 0, 0, P, "b", 0, "a"))), "before"),
        (broken(2, (0, 0b1, (0, 0, 0, 0, "a", 0, "b"))), "before"),
        (broken(2, (0, 0b1, (0, 0, 0, 0, "a", 1, "b"))), "is in the collision node of hash 0"),
        (broken(2, (0, 0b10, (0, 0, 0, 0, "a", P, "b"))), "collision node of hash 0 sits in slot 1"),
        (broken(2, (0, 0b1, (0, 0, 0, 0, "a", P))), "malformed"),
        (broken(3, (0b11, 0, 0, "a", 1, "b")), "stored size 3"),
        (broken(1, (0b11, 0, 0, "a", 1)), r"holds 3 item\(s\), not 4"),
        (broken(1, [0b1, 0, 0, "a"]), "not a bitmap node"),
        (broken(1, (0, 0b1, 7)), "is not a node"),
        (broken(2, _chain(16, (0b11, 0, 0, "a", 1, "b"))), "below the 16 levels"),
    ],
)
def test_check_detects_broken_tries(m: HMap[Any, Any], message: str) -> None:
    with pytest.raises(AssertionError, match=message):
        hamt._check(m)


def test_check_detects_flipped_bitmap_in_real_trie() -> None:
    m = build([(k, k) for k in range(200)])
    hamt._check(m)
    assert m.root[1] is _FULL
    child = m.root[2]  # the level-1 node under slot 0: the keys 0, 16, …, 192 as leaves
    assert child[1] == 0 and [k for k, _ in leaves(child)] == list(range(0, 200, 16))
    for bad in ((child[0] ^ 1, *child[1:]), (child[0] ^ (1 << 15), *child[1:]), (child[0], 0b1, *child[2:])):
        bad_root = (m.root[0], m.root[1], bad, *m.root[3:])
        with pytest.raises(AssertionError):
            hamt._check(HMap(m.size, bad_root))
    # A full nodemap must be the shared _FULL object (find tests it by identity).
    copied = int(str(_FULL))
    assert copied == _FULL and copied is not _FULL
    with pytest.raises(AssertionError, match="full nodemap that is not _FULL"):
        hamt._check(HMap(m.size, (m.root[0], copied, *m.root[2:])))
