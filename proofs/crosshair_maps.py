"""CrossHair contract checks of the pure map operations and of ``Order`` / ``Option``.

Each public function below carries a PEP 316 contract in its docstring
(``pre:`` bounds the input size, ``post: __return__`` states the law) and is
checked by ``crosshair check --analysis_kind=PEP316`` (``python -m proofs`` runs
it with a bounded time; ``proofs/README.md`` says what that establishes and what
it cannot).  CrossHair runs a function on *symbolic* inputs — an integer, a
list of integers of symbolic length — and asks an SMT solver for inputs that
would take each branch, looking for one that makes a postcondition false or
raises an exception the contract does not allow.

The map laws are the ``ORD_MAP`` laws of :mod:`persistri.spec.ord_map`, checked
on every pure backend (one contracted function per law and backend, so that each
is a separate CrossHair condition with its own time budget).  A map is built by
inserting ``keys[i] ↦ i`` in order, so a key's value is the position of its
*last* occurrence: "a later insert replaces an earlier one" is part of every
law.  The expectations are computed from the key list alone (``sorted``,
``set``, positions), never from another map implementation.

The functions return ``bool`` and the laws are stated in the ``post:`` line;
helpers whose names begin with ``_`` carry no contract and are not checked on
their own.

**Budgets.**  CrossHair's search is bounded by CPU time per condition, set by
its own directive ``# crosshair: per_condition_timeout=SECONDS``: 4 s by
default (this module's top level), 8 s for the ``listItemsi`` laws and 16 s for
the laws that remove (``remove``, persistence, ``_check``), whose
counterexamples are deepest.  Two deliberately broken deletion rebalancings in
a copy of the red-black tree (shown by 4–5 keys and one removal) were missed
by the invariant law in 8 s but found by the ``remove`` law, which also runs
``_check``, within 16 s (``proofs/README.md`` lists these experiments).  The
order and option laws are settled over all paths in well under a second.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from persistri.impl.maps.assoc_list import assoc_list
from persistri.impl.maps.hamt import hamt
from persistri.impl.maps.red_black import red_black
from persistri.spec.option import NONE, SOME, isSome, valOf
from persistri.spec.ord_map import NotFound
from persistri.spec.order import NATURAL_ORDER, Order

__all__: list[str] = []  # nothing here is for import; CrossHair finds the contracts itself

# CPU seconds per condition (see the module docstring); a function may raise its own.
# crosshair: per_condition_timeout=4


# -- the laws, for any structure ---------------------------------------------------


class LawRaised(Exception):
    """A map operation raised an exception where the law says it must not.

    The message names the original exception; it is formatted while CrossHair
    still traces, because CrossHair 0.0.112 cannot format an exception whose
    arguments hold symbolic values (``NotFound(k)``) after the call has returned:
    it stops with ``CrossHairInternal`` instead of reporting the counterexample.
    """


def _holds(law: Callable[..., bool], *args: Any) -> bool:
    """``law(*args)``, with any exception it raises re-raised as :class:`LawRaised`."""
    try:
        return law(*args)
    except Exception as exc:  # CrossHair's own control flow uses BaseException, never caught here
        raise LawRaised(f"{type(exc).__name__}: {exc}") from None


def _int_key(k: int) -> Any:
    """Plain integer keys."""
    return k


class _Clash:
    """An integer key whose hash keeps only ``k % 4``, in bits 10–11.

    Distinct keys with equal ``k % 4`` have equal hashes (the HAMT's collision
    nodes), and keys with different hashes share the first two trie levels
    (slot 0 at depths 0 and 1) before they part at depth 2.  Order and
    equality are those of ``k``, so ``_Clash`` is monotone in ``k``.
    """

    __slots__ = ("k",)

    def __init__(self, k: int) -> None:
        self.k = k

    def __eq__(self, other: object) -> bool:
        return isinstance(other, _Clash) and self.k == other.k

    def __lt__(self, other: _Clash) -> bool:
        return self.k < other.k

    def __hash__(self) -> int:
        return (self.k % 4) << 10

    def __repr__(self) -> str:
        return f"_Clash({self.k!r})"


def _last(keys: list[int], k: int) -> int:
    """The position of the last occurrence of ``k`` in ``keys`` (``k`` must occur)."""
    pos = -1
    for i, x in enumerate(keys):
        if x == k:
            pos = i
    assert pos >= 0
    return pos


def _build(s: Any, keys: list[int], key: Callable[[int], Any]) -> Any:
    """The map ``{key(keys[i]) ↦ i}`` made by inserting in order: later occurrences win."""
    m = s.empty()
    for i, k in enumerate(keys):
        m = s.insert(m, key(k), i)
    return m


def _insert_find(s: Any, keys: list[int], k: int, v: int) -> bool:
    """``find(insert(m, k, v), k) == SOME v``; ``lookup`` and ``inDomain`` agree."""
    m = s.insert(_build(s, keys, _int_key), k, v)
    return bool(s.find(m, k) == (v,) and s.lookup(m, k) == v and s.inDomain(m, k))


def _insert_other(s: Any, keys: list[int], k: int, j: int, v: int) -> bool:
    """For ``j != k``: ``find(insert(m, k, v), j) == find(m, j)``."""
    m = _build(s, keys, _int_key)
    return bool(s.find(s.insert(m, k, v), j) == s.find(m, j))


def _insert_with(s: Any, keys: list[int], k: int, v: int) -> bool:
    """``insertWith f (m, k, v)`` stores ``f(old, v)`` when ``k ↦ old`` is present, else ``v``.

    ``f`` is subtraction, which is not symmetric, so swapped arguments are caught.
    """
    m = s.insertWith(lambda old, new: old - new, _build(s, keys, _int_key), k, v)
    expected = _last(keys, k) - v if k in keys else v
    return bool(s.find(m, k) == (expected,) and s.numItems(m) == len(set([*keys, k])))


def _items(s: Any, keys: list[int], key: Callable[[int], Any] = _int_key) -> bool:
    """``listItemsi`` is sorted and holds each key once with its last value; counts agree.

    ``listKeys``, ``numItems``, ``isEmpty`` and ``foldli`` are checked against it.
    """
    m = _build(s, keys, key)
    distinct = sorted(set(keys))
    expected = [(key(k), _last(keys, k)) for k in distinct]
    folded = s.foldli(lambda k, v, acc: [*acc, (k, v)], [], m)
    return bool(
        s.listItemsi(m) == expected
        and s.listKeys(m) == [key(k) for k in distinct]
        and folded == expected
        and s.numItems(m) == len(distinct)
        and s.isEmpty(m) == (len(keys) == 0)
    )


def _remove(s: Any, keys: list[int], k: int, key: Callable[[int], Any] = _int_key) -> bool:
    """``remove(m, k)`` returns ``(m without k, its value)`` satisfying ``_check``; an absent key raises ``NotFound``."""
    m = _build(s, keys, key)
    before = s.listItemsi(m)
    if k not in keys:
        try:
            s.remove(m, key(k))
        except NotFound:
            pass
        else:
            return False
        try:
            s.lookup(m, key(k))
        except NotFound:
            return s.find(m, key(k)) is NONE and s.listItemsi(m) == before
        return False
    m2, v = s.remove(m, key(k))
    s._check(m2)  # the representation invariant after the removal, too
    return bool(
        v == _last(keys, k)
        and s.find(m2, key(k)) is NONE
        and s.numItems(m2) == s.numItems(m) - 1
        and s.listItemsi(m2) == [item for item in before if item[0] != key(k)]
    )


def _versions(
    s: Any, keys: list[int], dels: list[int], key: Callable[[int], Any]
) -> tuple[list[Any], list[list[tuple[Any, int]]]]:
    """Every version made by inserting ``keys`` then removing the present keys of ``dels``,
    each with the items it had when it was made."""
    versions = [s.empty()]
    seen: list[list[tuple[Any, int]]] = [[]]
    for i, k in enumerate(keys):
        versions.append(s.insert(versions[-1], key(k), i))
        seen.append(s.listItemsi(versions[-1]))
    for k in dels:
        if s.inDomain(versions[-1], key(k)):
            versions.append(s.remove(versions[-1], key(k))[0])
            seen.append(s.listItemsi(versions[-1]))
    return versions, seen


def _persistence(s: Any, keys: list[int], dels: list[int], key: Callable[[int], Any] = _int_key) -> bool:
    """After all later inserts and removes, every earlier version still has its items."""
    versions, seen = _versions(s, keys, dels, key)
    return all(s.listItemsi(m) == items for m, items in zip(versions, seen))


def _invariant(s: Any, keys: list[int], dels: list[int], key: Callable[[int], Any] = _int_key) -> bool:
    """The backend's representation invariant (``_check``) holds in every version."""
    versions, _ = _versions(s, keys, dels, key)
    for m in versions:
        s._check(m)  # raises AssertionError when an invariant is broken
    return True


# -- the association list ----------------------------------------------------------


def assoc_list_insert_find(keys: list[int], k: int, v: int) -> bool:
    """``find(insert(m, k, v), k) == SOME v`` on the association list.

    pre: len(keys) <= 6
    post: __return__
    """
    return _holds(_insert_find, assoc_list, keys, k, v)


def assoc_list_insert_other(keys: list[int], k: int, j: int, v: int) -> bool:
    """Inserting ``k`` leaves every other key ``j`` as it was, on the association list.

    pre: len(keys) <= 6 and j != k
    post: __return__
    """
    return _holds(_insert_other, assoc_list, keys, k, j, v)


def assoc_list_insert_with(keys: list[int], k: int, v: int) -> bool:
    """``insertWith`` combines old and new values in that order, on the association list.

    pre: len(keys) <= 6
    post: __return__
    """
    return _holds(_insert_with, assoc_list, keys, k, v)


def assoc_list_items(keys: list[int]) -> bool:
    """``listItemsi`` = sorted distinct keys with their last values, on the association list.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=8
    return _holds(_items, assoc_list, keys)


def assoc_list_remove(keys: list[int], k: int) -> bool:
    """The ``remove`` laws (present and absent keys) on the association list.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return _holds(_remove, assoc_list, keys, k)


def assoc_list_persistence(keys: list[int], dels: list[int]) -> bool:
    """Every version of the association list is unchanged by later operations.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return _holds(_persistence, assoc_list, keys, dels)


def assoc_list_invariant(keys: list[int], dels: list[int]) -> bool:
    """The association list's ``_check`` holds after every insert and remove.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return _holds(_invariant, assoc_list, keys, dels)


# -- the red-black tree ------------------------------------------------------------


def red_black_insert_find(keys: list[int], k: int, v: int) -> bool:
    """``find(insert(m, k, v), k) == SOME v`` on the red-black tree.

    pre: len(keys) <= 6
    post: __return__
    """
    return _holds(_insert_find, red_black, keys, k, v)


def red_black_insert_other(keys: list[int], k: int, j: int, v: int) -> bool:
    """Inserting ``k`` leaves every other key ``j`` as it was, on the red-black tree.

    pre: len(keys) <= 6 and j != k
    post: __return__
    """
    return _holds(_insert_other, red_black, keys, k, j, v)


def red_black_insert_with(keys: list[int], k: int, v: int) -> bool:
    """``insertWith`` combines old and new values in that order, on the red-black tree.

    pre: len(keys) <= 6
    post: __return__
    """
    return _holds(_insert_with, red_black, keys, k, v)


def red_black_items(keys: list[int]) -> bool:
    """``listItemsi`` = sorted distinct keys with their last values, on the red-black tree.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=8
    return _holds(_items, red_black, keys)


def red_black_remove(keys: list[int], k: int) -> bool:
    """The ``remove`` laws (present and absent keys) on the red-black tree.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return _holds(_remove, red_black, keys, k)


def red_black_persistence(keys: list[int], dels: list[int]) -> bool:
    """Every version of the red-black tree is unchanged by later operations.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return _holds(_persistence, red_black, keys, dels)


def red_black_invariant(keys: list[int], dels: list[int]) -> bool:
    """The red-black tree's ``_check`` holds after every insert and remove.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return _holds(_invariant, red_black, keys, dels)


# -- the HAMT ----------------------------------------------------------------------


def hamt_insert_find(keys: list[int], k: int, v: int) -> bool:
    """``find(insert(m, k, v), k) == SOME v`` on the HAMT.

    pre: len(keys) <= 6
    post: __return__
    """
    return _holds(_insert_find, hamt, keys, k, v)


def hamt_insert_other(keys: list[int], k: int, j: int, v: int) -> bool:
    """Inserting ``k`` leaves every other key ``j`` as it was, on the HAMT.

    pre: len(keys) <= 6 and j != k
    post: __return__
    """
    return _holds(_insert_other, hamt, keys, k, j, v)


def hamt_insert_with(keys: list[int], k: int, v: int) -> bool:
    """``insertWith`` combines old and new values in that order, on the HAMT.

    pre: len(keys) <= 6
    post: __return__
    """
    return _holds(_insert_with, hamt, keys, k, v)


def hamt_items(keys: list[int]) -> bool:
    """``listItemsi`` = sorted distinct keys with their last values, on the HAMT.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=8
    return _holds(_items, hamt, keys)


def hamt_remove(keys: list[int], k: int) -> bool:
    """The ``remove`` laws (present and absent keys) on the HAMT.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return _holds(_remove, hamt, keys, k)


def hamt_persistence(keys: list[int], dels: list[int]) -> bool:
    """Every version of the HAMT is unchanged by later operations.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return _holds(_persistence, hamt, keys, dels)


def hamt_invariant(keys: list[int], dels: list[int]) -> bool:
    """The HAMT's ``_check`` holds after every insert and remove.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return _holds(_invariant, hamt, keys, dels)


# -- the HAMT with colliding hashes ------------------------------------------------
#
# Integer keys hash to themselves, so the checks above rarely reach the HAMT's
# deeper levels or its collision nodes; ``_Clash`` keys reach both on every path.


def hamt_clash_items(keys: list[int]) -> bool:
    """The ``listItemsi`` law on the HAMT, with colliding and prefix-sharing hashes.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=8
    return _holds(_items, hamt, keys, _Clash)


def hamt_clash_remove(keys: list[int], k: int) -> bool:
    """The ``remove`` laws on the HAMT, with colliding and prefix-sharing hashes.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return _holds(_remove, hamt, keys, k, _Clash)


def hamt_clash_persistence(keys: list[int], dels: list[int]) -> bool:
    """Persistence of the HAMT, with colliding and prefix-sharing hashes.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return _holds(_persistence, hamt, keys, dels, _Clash)


def hamt_clash_invariant(keys: list[int], dels: list[int]) -> bool:
    """The HAMT's ``_check`` (collision nodes, canonical form) in every version, with colliding hashes.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return _holds(_invariant, hamt, keys, dels, _Clash)


# -- the order on keys and the option convention -----------------------------------


def compare_reflexive(a: int) -> bool:
    """``NATURAL_ORDER.compare(a, a) is EQUAL``.

    post: __return__
    """
    return NATURAL_ORDER.compare(a, a) is Order.EQUAL


def compare_antisymmetric(a: int, b: int) -> bool:
    """``compare(a, b) == -compare(b, a)``.

    post: __return__
    """
    return NATURAL_ORDER.compare(a, b) == -NATURAL_ORDER.compare(b, a)


def compare_matches_lt(a: int, b: int) -> bool:
    """``compare`` agrees with ``<`` and ``==`` on integers.

    post: __return__
    """
    expected = Order.LESS if a < b else Order.EQUAL if a == b else Order.GREATER
    return NATURAL_ORDER.compare(a, b) is expected


def compare_transitive(a: int, b: int, c: int) -> bool:
    """``compare(a, b) is LESS`` and ``compare(b, c) is LESS`` imply ``compare(a, c) is LESS``.

    post: __return__
    """
    less = Order.LESS
    c_ab, c_bc, c_ac = NATURAL_ORDER.compare(a, b), NATURAL_ORDER.compare(b, c), NATURAL_ORDER.compare(a, c)
    return not (c_ab is less and c_bc is less) or c_ac is less


def compare_str_antisymmetric(a: str, b: str) -> bool:
    """``compare`` is antisymmetric on strings too (any type ordered by ``<``).

    pre: len(a) <= 3 and len(b) <= 3
    post: __return__
    """
    return NATURAL_ORDER.compare(a, b) == -NATURAL_ORDER.compare(b, a)


def order_negation(o: Order) -> bool:
    """``-(-o) is o``, and ``-o`` differs from ``o`` unless ``o`` is ``EQUAL``.

    post: __return__
    """
    return -(-o) is o and ((-o is o) == (o is Order.EQUAL))


def option_some(x: int) -> bool:
    """``valOf(SOME x) == x`` and ``isSome(SOME x)``; ``SOME x`` is never ``NONE``.

    post: __return__
    """
    o = SOME(x)
    return valOf(o) == x and isSome(o) and o is not NONE


def option_none() -> bool:
    """``isSome NONE`` is false and ``valOf NONE`` raises ``ValueError`` (SML's ``Option``).

    post: __return__
    """
    if isSome(NONE):
        return False
    try:
        valOf(NONE)
    except ValueError:
        return True
    return False
