"""Cross-check with an independent peer, ``gudhi.SimplexTree``, on random 2- and 3-complexes.

gudhi stores unoriented simplices closed under faces.  For the same top
simplices (each in a random orientation), our complex and gudhi's tree must
have the same simplices in every dimension, and ``grep(c, d, s)`` must be
gudhi's cofaces of ``s`` of codimension ``d − dim s`` (``s`` itself for
codimension 0) — as vertex sets, since gudhi has no orientation.  The
orientation-sensitive case ``d = n, dim s = n − 1`` (``find``) is compared with
gudhi's cofaces restricted by the orientation computed here.
"""

from __future__ import annotations

from itertools import combinations
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from complex_helpers import STRUCTURES, fresh
from persistri.impl.complex.simplex import canonical, tuple_simplex

gudhi = pytest.importorskip("gudhi")

S = tuple_simplex
CHOICES = [sid for sid, _ in STRUCTURES if sid in ("red_black", "hamt", "red_black-functor")] or [STRUCTURES[0][0]]


def as_set(s: Any) -> frozenset[int]:
    return frozenset(int(v) for v in s)


@pytest.mark.parametrize("sid", CHOICES)
@pytest.mark.parametrize("n", [2, 3])
@settings(max_examples=max(4, settings.default.max_examples // 4))
@given(data=st.data())
def test_same_simplices_and_cofaces_as_gudhi(sid: str, n: int, data: st.DataObject) -> None:
    make = dict(STRUCTURES)[sid]
    C = make(n)
    pool = fresh(data.draw(st.integers(n + 1, n + 5), label="vertices"))
    candidates = list(combinations(pool, n + 1))
    chosen = data.draw(st.lists(st.sampled_from(candidates), min_size=1, max_size=12, unique=True), label="tops")
    flips = data.draw(st.lists(st.booleans(), min_size=len(chosen), max_size=len(chosen)), label="orientations")
    c = C.new(n)
    tree = gudhi.SimplexTree()
    tops = []
    for t, f in zip(chosen, flips):
        t = S.flip(t) if f else t
        c = C.add(c, t, None)
        tree.insert([int(v) for v in t])
        tops.append(t)

    by_dim: dict[int, set[frozenset[int]]] = {d: set() for d in range(n + 1)}
    for simplex, _ in tree.get_simplices():
        by_dim[len(simplex) - 1].add(frozenset(simplex))
    for d in range(n + 1):
        ours = [as_set(s) for s in C.simplices(c, d)]
        assert len(ours) == len(set(ours)) and set(ours) == by_dim[d], f"dimension {d}"

    for k in range(n + 1):
        for s in by_dim[k]:
            face = tuple(sorted((v for v in pool if int(v) in s), key=int))
            for d in range(k, n + 1):
                got = [as_set(t) for t in C.grep(c, d, face)]
                assert len(got) == len(set(got)), f"grep reports a simplex twice: {face}, {d}"
                if d == k:
                    expected = {s}
                else:
                    expected = {frozenset(t) for t, _ in tree.get_cofaces(sorted(s), d - k)}
                if d == n and k == n - 1:
                    # find: only the n-simplices having `face` with its orientation
                    expected = {
                        as_set(t)
                        for t in tops
                        if as_set(t) in expected
                        and any(canonical(f) == canonical(face) for f in S.faces(t))
                    }
                assert set(got) == expected, f"grep(c, {d}, {face})"
