"""Deliberately FALSE contracts: CrossHair must find a counterexample for each ``false_*``.

``tests/test_crosshair_catches.py`` runs the proofs runner's CrossHair step on
this file.  It shows that the pipeline that checks ``proofs/crosshair_maps.py``
really reports broken laws, through the same helpers (``holds`` and the law
functions) applied to two deliberately broken association lists, and that it
passes a true contract checked in the same run.  Not under ``proofs/``, so
``python -m proofs`` never runs it.
"""

from __future__ import annotations

from typing import Any

from persistri.impl.maps.assoc_list import ALMap, AssocListMap
from persistri.spec.order import NATURAL_ORDER, Order
from proofs.map_laws import holds, invariant, remove


class _LeakyRemove(AssocListMap[Any, Any]):
    """``remove`` that forgets to decrement the stored count."""

    def remove(self, m: ALMap[Any, Any], k: Any, /) -> tuple[ALMap[Any, Any], Any]:
        (n, cells), v = super().remove(m, k)
        return (n + 1, cells), v


class _FrontInsert(AssocListMap[Any, Any]):
    """``insert`` of a new key puts it in front once the map has two items: keys end up unsorted."""

    def insert(self, m: ALMap[Any, Any], k: Any, v: Any, /) -> ALMap[Any, Any]:
        if m[0] >= 2 and not self.inDomain(m, k):
            return (m[0] + 1, (k, v, m[1]))
        return super().insert(m, k, v)


def false_compare_never_equal(a: int, b: int) -> bool:
    """False: ``compare`` does return EQUAL (when ``a == b``).

    post: __return__
    """
    return NATURAL_ORDER.compare(a, b) is not Order.EQUAL


def false_leaky_remove(keys: list[int], k: int) -> bool:
    """False: the remove laws on an association list whose ``remove`` keeps the old count.

    pre: len(keys) <= 6
    post: __return__
    """
    return holds(remove, _LeakyRemove(), keys, k)


def false_front_insert_invariant(keys: list[int], dels: list[int]) -> bool:
    """False: ``_check`` (keys sorted) on an association list that inserts new keys in front.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    return holds(invariant, _FrontInsert(), keys, dels)


def true_compare_antisymmetric(a: int, b: int) -> bool:
    """True (the control): ``compare(a, b) == -compare(b, a)``.

    post: __return__
    """
    return NATURAL_ORDER.compare(a, b) == -NATURAL_ORDER.compare(b, a)
