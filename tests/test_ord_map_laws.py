"""Each ``ORD_MAP`` law function holds on a correct map and names itself on a map that breaks it.

The broken maps here are the association list with one operation replaced
(:func:`patched`), so that each law is shown to *fail* for the defect it is
about; the suite-level tests (:mod:`test_conformance_rejects_broken`) show the
hypothesis tests find such defects on their own.
"""

from __future__ import annotations

import pickle
from collections.abc import Callable
from typing import Any

import pytest

from broken_maps import bad_check, mutating
from persistri.impl.maps.assoc_list import assoc_list
from persistri.spec.law import LawViolation as SharedLawViolation
from persistri.spec.ord_map import NotFound, OrdMap
from persistri.spec.ord_map_laws import (
    ORD_MAP_LAWS,
    LawViolation,
    law_empty,
    law_find_insert,
    law_find_insert_other,
    law_foldli,
    law_inDomain,
    law_insertWith,
    law_invariants,
    law_isEmpty,
    law_key_order,
    law_listItemsi,
    law_listKeys,
    law_lookup,
    law_numItems_insert,
    law_persistence,
    law_remove,
    law_remove_absent,
    law_singleton,
)
from persistri.spec.order import Order


class Patched:
    """The association list with some operations replaced (keyword arguments name them)."""

    def __init__(self, **ops: Callable[..., Any]) -> None:
        self._ops = ops

    def __getattr__(self, name: str) -> Any:
        if name in self._ops:
            return self._ops[name]
        return getattr(assoc_list, name)


def build(s: Any, *items: tuple[Any, Any]) -> Any:
    m = s.empty()
    for k, v in items:
        m = assoc_list.insert(m, k, v)
    return m


M3 = build(assoc_list, (1, "a"), (2, "b"), (3, "c"))


def violated(law: str, call: Callable[[], object]) -> LawViolation:
    with pytest.raises(LawViolation) as info:
        call()
    assert info.value.law == law, str(info.value)
    assert info.value.statement == ORD_MAP_LAWS[law]
    return info.value


class _Cmp:
    def __init__(self, compare: Callable[[Any, Any], Any]) -> None:
        self.compare = compare


def test_every_law_holds_on_the_association_list() -> None:
    s: OrdMap[int, str, Any] = assoc_list
    law_key_order(s, [3, 1, 2, 1, -7])
    law_empty(s, [0, 1])
    law_singleton(s, 1, "a", [0, 2])
    law_find_insert(s, M3, 2, "z")
    law_find_insert(s, M3, 9, "z")
    law_find_insert_other(s, M3, 2, "z", [0, 1, 2, 3, 4])
    for k in (0, 1, 3):
        law_lookup(s, M3, k)
        law_inDomain(s, M3, k)
    law_insertWith(s, lambda old, new: old + new, M3, 2, "z", [1, 3])
    law_insertWith(s, lambda old, new: old + new, M3, 7, "z", [1, 3])
    law_numItems_insert(s, M3, 2, "z")
    law_numItems_insert(s, M3, 5, "z")
    assert law_remove(s, M3, 2)[1] == "b"
    law_remove_absent(s, M3, 5)
    law_listItemsi(s, M3, [0, 2, 5])
    law_listKeys(s, M3)
    law_foldli(s, M3)
    law_isEmpty(s, M3)
    law_isEmpty(s, s.empty())
    law_persistence(s, [(s.empty(), {}), (M3, {1: "a", 2: "b", 3: "c"})], [0, 4])
    law_invariants(s, M3)


def test_key_order_catches_each_defect() -> None:
    assert "reflexive" in violated("key_order", lambda: law_key_order(Patched(Key=_Cmp(lambda a, b: Order.LESS)), [1])).detail
    assert "not an Order" in violated("key_order", lambda: law_key_order(Patched(Key=_Cmp(lambda a, b: 0)), [1])).detail
    coarse = _Cmp(lambda a, b: Order.EQUAL if a // 2 == b // 2 else (Order.LESS if a < b else Order.GREATER))
    assert "!=" in violated("key_order", lambda: law_key_order(Patched(Key=coarse), [2, 3])).detail
    lopsided = _Cmp(lambda a, b: Order.EQUAL if a == b else Order.LESS)
    assert "antisymmetric" in violated("key_order", lambda: law_key_order(Patched(Key=lopsided), [1, 2])).detail

    def rock_paper_scissors(a: int, b: int) -> Order:
        if a == b:
            return Order.EQUAL
        return Order.LESS if (b - a) % 3 == 1 else Order.GREATER

    cyclic = _Cmp(rock_paper_scissors)
    assert "transitive" in violated("key_order", lambda: law_key_order(Patched(Key=cyclic), [0, 1, 2])).detail


def test_empty_and_singleton_catch_defects() -> None:
    violated("empty", lambda: law_empty(Patched(empty=lambda: assoc_list.singleton(0, 0))))
    violated("empty", lambda: law_empty(Patched(isEmpty=lambda m: 0), []))
    violated("singleton", lambda: law_singleton(Patched(singleton=lambda k, v: assoc_list.singleton(k, None)), 1, "a"))
    violated("singleton", lambda: law_singleton(Patched(singleton=lambda k, v: assoc_list.singleton(k + 1, v)), 1, "a"))


def test_find_insert_catches_lost_values_and_non_options() -> None:
    violated("find_insert", lambda: law_find_insert(Patched(insert=lambda m, k, v: m), M3, 9, "z"))
    bare = violated("find_insert", lambda: law_find_insert(Patched(find=lambda m, k: assoc_list.lookup(m, k)), M3, 2, "z"))
    assert "not an option" in bare.detail
    # SOME None must be (None,), never a bare None.
    violated("find_insert", lambda: law_find_insert(Patched(find=lambda m, k: None), M3, 2, None))


def test_find_insert_other_catches_an_insert_that_loses_keys() -> None:
    forgetful = Patched(insert=lambda m, k, v: assoc_list.singleton(k, v))
    assert "j = 1" in violated("find_insert_other", lambda: law_find_insert_other(forgetful, M3, 2, "z", [1, 2, 3])).detail


def test_lookup_and_inDomain_catch_defects() -> None:
    violated("lookup", lambda: law_lookup(Patched(lookup=lambda m, k: None), M3, 9))
    # A plain KeyError is not NotFound: reported under the law, with the exception.
    wrong_exc = Patched(lookup=lambda m, k: {}[k])
    assert "KeyError" in violated("lookup", lambda: law_lookup(wrong_exc, M3, 9)).detail
    violated("lookup", lambda: law_lookup(Patched(lookup=lambda m, k: "other"), M3, 1))
    violated("inDomain", lambda: law_inDomain(Patched(inDomain=lambda m, k: 1), M3, 1))
    violated("inDomain", lambda: law_inDomain(Patched(inDomain=lambda m, k: True), M3, 9))


def test_insertWith_catches_swapped_arguments_extra_calls_and_lost_keys() -> None:
    swapped = Patched(insertWith=lambda f, m, k, v: assoc_list.insertWith(lambda a, b: f(b, a), m, k, v))
    cat: Callable[[str, str], str] = lambda old, new: old + new
    violated("insertWith", lambda: law_insertWith(swapped, cat, M3, 2, "z"))
    eager = Patched(insertWith=lambda f, m, k, v: assoc_list.insert(m, k, f(v, v)))
    violated("insertWith", lambda: law_insertWith(eager, cat, M3, 9, "z"))
    forgetful = Patched(insertWith=lambda f, m, k, v: assoc_list.singleton(k, v))
    violated("insertWith", lambda: law_insertWith(forgetful, cat, M3, 9, "z", [1]))


def test_numItems_insert_catches_miscounting() -> None:
    plus_one = Patched(numItems=lambda m: assoc_list.numItems(m) + (1 if assoc_list.inDomain(m, 2) else 0))
    violated("numItems_insert", lambda: law_numItems_insert(plus_one, build(assoc_list, (1, "a")), 2, "z"))
    law_numItems_insert(plus_one, build(assoc_list, (1, "a")), 3, "z")  # the defect only shows with key 2


def test_remove_and_remove_absent_catch_defects() -> None:
    def lossy(m: Any, k: Any) -> Any:
        m2, v = assoc_list.remove(m, k)
        return assoc_list.remove(m2, 3)[0] if k != 3 and assoc_list.inDomain(m2, 3) else m2, v

    assert "lost [3]" in violated("remove", lambda: law_remove(Patched(remove=lossy), M3, 1)).detail
    violated("remove", lambda: law_remove(Patched(remove=lambda m, k: (assoc_list.remove(m, k)[0], "?")), M3, 1))
    violated("remove", lambda: law_remove(Patched(remove=lambda m, k: (m, assoc_list.lookup(m, k))), M3, 1))
    violated("remove", lambda: law_remove(assoc_list, M3, 9))  # the key must be present
    violated("remove_absent", lambda: law_remove_absent(Patched(remove=lambda m, k: (m, None)), M3, 9))
    violated("remove_absent", lambda: law_remove_absent(assoc_list, M3, 1))  # the key must be absent


def test_listing_laws_catch_defects() -> None:
    rev = Patched(listItemsi=lambda m: assoc_list.listItemsi(m)[::-1])
    violated("listItemsi", lambda: law_listItemsi(rev, M3))
    short = Patched(listItemsi=lambda m: assoc_list.listItemsi(m)[1:])
    violated("listItemsi", lambda: law_listItemsi(short, M3))
    hidden = Patched(find=lambda m, k: None if k == 9 else assoc_list.find(m, k))
    violated("listItemsi", lambda: law_listItemsi(hidden, build(assoc_list, (9, "x"))))
    violated("listKeys", lambda: law_listKeys(Patched(listKeys=lambda m: [3, 1, 2]), M3))
    violated("foldli", lambda: law_foldli(Patched(foldli=_fold_rev), M3))
    violated("foldli", lambda: law_foldli(Patched(foldli=_fold_no_acc), M3))
    violated("isEmpty", lambda: law_isEmpty(Patched(isEmpty=lambda m: False), assoc_list.empty()))


def _fold_rev(f: Callable[[Any, Any, Any], Any], init: Any, m: Any) -> Any:
    acc = init
    for k, v in reversed(assoc_list.listItemsi(m)):
        acc = f(k, v, acc)
    return acc


def _fold_no_acc(f: Callable[[Any, Any, Any], Any], init: Any, m: Any) -> Any:
    acc = init
    for k, v in assoc_list.listItemsi(m):
        acc = f(k, v, init)  # the defect: every call gets init
    return acc


def test_persistence_catches_a_mutated_version_and_operand_checks_report_it() -> None:
    m0 = mutating.empty()
    m1 = mutating.insert(m0, 1, "a")
    detail = violated("persistence", lambda: law_persistence(mutating, [(m0, {}), (m1, {1: "a"})])).detail
    assert "version 0" in detail
    # A law that performs the insert itself notices its operand change.
    violated("persistence", lambda: law_find_insert(mutating, mutating.empty(), 1, "a"))


def test_invariants_catches_a_failing_check_and_ignores_structures_without_one() -> None:
    m = bad_check.insert(bad_check.insert(bad_check.empty(), 2, "b"), 1, "a")
    assert "out of order" in violated("invariants", lambda: law_invariants(bad_check, m, "after two inserts")).detail
    law_invariants(object(), m)  # no _check: nothing to check


def test_law_violation_is_shared_named_and_picklable() -> None:
    e = LawViolation("remove", "observed this")
    assert isinstance(e, SharedLawViolation) and isinstance(e, AssertionError)
    assert e.law == "remove" and e.statement == ORD_MAP_LAWS["remove"] and e.detail == "observed this"
    again = pickle.loads(pickle.dumps(e))
    assert (again.law, again.statement, again.detail) == (e.law, e.statement, e.detail)
    with pytest.raises(ValueError, match="unknown ORD_MAP law"):
        LawViolation("no-such-law", "x")


def test_notfound_from_remove_of_present_key_is_reported_under_remove() -> None:
    def refuses(m: Any, k: Any) -> Any:
        raise NotFound(k)

    assert "raised NotFound" in violated("remove", lambda: law_remove(Patched(remove=refuses), M3, 1)).detail
