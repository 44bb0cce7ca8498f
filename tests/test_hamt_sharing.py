"""What HAMT versions share (:mod:`persistri.impl.maps.hamt`): path copying and the one full nodemap.

An update copies only the path to its key: every other entry of the root is the
same object in the old and the new version, and the old version reads as before.
Every nodemap with all 16 slots set is the module's ``_FULL`` object itself
(``find`` tests it by identity), however the node came about: by insertions,
deletions and reinsertions, or by unpickling and copying a map.
"""

from __future__ import annotations

import copy as copy_module
import pickle
import random

from persistri.impl.maps.hamt import HMap, hamt
from persistri.impl.maps.hamt_nodes import _FULL

from hamt_helpers import build, combine, nodes


# -- persistence by path copying ----------------------------------------------------


def test_structural_sharing() -> None:
    """An insert copies only the path to its key: every other entry of the root is the same object."""
    rng = random.Random(7)
    keys = list(range(5000))
    rng.shuffle(keys)
    m = build([(k, k) for k in keys])
    m2 = hamt.insert(m, 12345, 0)
    old, new = m.root, m2.root
    assert old[1] is new[1] is _FULL and len(old) == len(new) == 18  # the two bitmaps and 16 children
    changed = [j for j in range(len(old)) if old[j] is not new[j]]
    assert changed == [2 + (12345 & 15)]
    m3, _ = hamt.remove(m2, 12345)
    assert m3 == m and m3.root[2 + (12345 & 15)] is not m.root[2 + (12345 & 15)]
    hamt._check(m)
    # insertWith on a present key shares just as much, and leaves the old version alone.
    m4 = hamt.insertWith(combine, m, 777, 1)
    assert [j for j in range(18) if m4.root[j] is not m.root[j]] == [2 + (777 & 15)]
    assert hamt.find(m4, 777) == (777 * 31 + 1,) and hamt.find(m, 777) == (777,)


# -- the full nodemap, one shared object -------------------------------------------------


def test_full_nodes_share_the_full_bitmap() -> None:
    """Every nodemap with all 16 slots set, however it came about, is ``_FULL`` itself."""
    rng = random.Random(5)
    keys = list(range(3000))
    rng.shuffle(keys)
    m = build([(k, k) for k in keys])
    full = [node for _, node in nodes(m) if node[1] == _FULL]
    assert len(full) == 1 + 16 and all(node[1] is _FULL for node in full)  # the root and its 16 children
    for k in keys[:2000]:
        m, _ = hamt.remove(m, k)
    for k in keys[:2000]:
        m = hamt.insertWith(combine, m, k, k)
    hamt._check(m)
    assert all(node[1] is _FULL for _, node in nodes(m) if node[1] == _FULL)


def test_pickle_round_trip_keeps_full_nodes_shared() -> None:
    """Unpickled ints are new objects: the map rebuilds its full nodemaps as ``_FULL`` (``_check`` holds)."""
    m = build([(k, str(k)) for k in range(3000)] + [(-1, "a"), (-2, "b")])
    for copy in (pickle.loads(pickle.dumps(m)), copy_module.deepcopy(m), copy_module.copy(m)):
        assert type(copy) is HMap and copy == m
        hamt._check(copy)
        assert copy.root[1] is _FULL
        assert hamt.find(copy, 2999) == ("2999",) and hamt.find(copy, -2) == ("b",)
    assert pickle.loads(pickle.dumps(hamt.empty())) == hamt.empty()
