"""CrossHair contract checks of the pure map operations: the ``ORD_MAP`` laws on each backend.

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
the laws' bodies are in :mod:`proofs.map_laws` (no contract there).  The laws of
``Order`` and ``Option`` are in :mod:`proofs.crosshair_order`.

**Budgets.**  CrossHair's search is bounded by CPU time per condition, set by
its own directive ``# crosshair: per_condition_timeout=SECONDS``: 4 s by
default (this module's top level), 8 s for the ``listItemsi`` laws and 16 s for
the laws that remove (``remove``, persistence, ``_check``), whose
counterexamples are deepest.  Two deliberately broken deletion rebalancings in
a copy of the red-black tree (shown by 4–5 keys and one removal) were missed
by the invariant law in 8 s but found by the ``remove`` law, which also runs
``_check``, within 16 s (``proofs/README.md`` lists these experiments).
"""

from __future__ import annotations

from persistri.impl.maps.assoc_list import assoc_list
from persistri.impl.maps.hamt import hamt
from persistri.impl.maps.red_black import red_black
from proofs.map_laws import (
    Clash,
    holds,
    insert_find,
    insert_other,
    insert_with,
    invariant,
    items,
    persistence,
    remove,
)

__all__: list[str] = []  # nothing here is for import; CrossHair finds the contracts itself

# CPU seconds per condition (see the module docstring); a function may raise its own.
# crosshair: per_condition_timeout=4


# -- the association list ----------------------------------------------------------


def assoc_list_insert_find(keys: list[int], k: int, v: int) -> bool:
    """``find(insert(m, k, v), k) == SOME v`` on the association list.

    pre: len(keys) <= 6
    post: __return__
    """
    return holds(insert_find, assoc_list, keys, k, v)


def assoc_list_insert_other(keys: list[int], k: int, j: int, v: int) -> bool:
    """Inserting ``k`` leaves every other key ``j`` as it was, on the association list.

    pre: len(keys) <= 6 and j != k
    post: __return__
    """
    return holds(insert_other, assoc_list, keys, k, j, v)


def assoc_list_insert_with(keys: list[int], k: int, v: int) -> bool:
    """``insertWith`` combines old and new values in that order, on the association list.

    pre: len(keys) <= 6
    post: __return__
    """
    return holds(insert_with, assoc_list, keys, k, v)


def assoc_list_items(keys: list[int]) -> bool:
    """``listItemsi`` = sorted distinct keys with their last values, on the association list.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=8
    return holds(items, assoc_list, keys)


def assoc_list_remove(keys: list[int], k: int) -> bool:
    """The ``remove`` laws (present and absent keys) on the association list.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return holds(remove, assoc_list, keys, k)


def assoc_list_persistence(keys: list[int], dels: list[int]) -> bool:
    """Every version of the association list is unchanged by later operations.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return holds(persistence, assoc_list, keys, dels)


def assoc_list_invariant(keys: list[int], dels: list[int]) -> bool:
    """The association list's ``_check`` holds after every insert and remove.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return holds(invariant, assoc_list, keys, dels)


# -- the red-black tree ------------------------------------------------------------


def red_black_insert_find(keys: list[int], k: int, v: int) -> bool:
    """``find(insert(m, k, v), k) == SOME v`` on the red-black tree.

    pre: len(keys) <= 6
    post: __return__
    """
    return holds(insert_find, red_black, keys, k, v)


def red_black_insert_other(keys: list[int], k: int, j: int, v: int) -> bool:
    """Inserting ``k`` leaves every other key ``j`` as it was, on the red-black tree.

    pre: len(keys) <= 6 and j != k
    post: __return__
    """
    return holds(insert_other, red_black, keys, k, j, v)


def red_black_insert_with(keys: list[int], k: int, v: int) -> bool:
    """``insertWith`` combines old and new values in that order, on the red-black tree.

    pre: len(keys) <= 6
    post: __return__
    """
    return holds(insert_with, red_black, keys, k, v)


def red_black_items(keys: list[int]) -> bool:
    """``listItemsi`` = sorted distinct keys with their last values, on the red-black tree.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=8
    return holds(items, red_black, keys)


def red_black_remove(keys: list[int], k: int) -> bool:
    """The ``remove`` laws (present and absent keys) on the red-black tree.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return holds(remove, red_black, keys, k)


def red_black_persistence(keys: list[int], dels: list[int]) -> bool:
    """Every version of the red-black tree is unchanged by later operations.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return holds(persistence, red_black, keys, dels)


def red_black_invariant(keys: list[int], dels: list[int]) -> bool:
    """The red-black tree's ``_check`` holds after every insert and remove.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return holds(invariant, red_black, keys, dels)


# -- the HAMT ----------------------------------------------------------------------


def hamt_insert_find(keys: list[int], k: int, v: int) -> bool:
    """``find(insert(m, k, v), k) == SOME v`` on the HAMT.

    pre: len(keys) <= 6
    post: __return__
    """
    return holds(insert_find, hamt, keys, k, v)


def hamt_insert_other(keys: list[int], k: int, j: int, v: int) -> bool:
    """Inserting ``k`` leaves every other key ``j`` as it was, on the HAMT.

    pre: len(keys) <= 6 and j != k
    post: __return__
    """
    return holds(insert_other, hamt, keys, k, j, v)


def hamt_insert_with(keys: list[int], k: int, v: int) -> bool:
    """``insertWith`` combines old and new values in that order, on the HAMT.

    pre: len(keys) <= 6
    post: __return__
    """
    return holds(insert_with, hamt, keys, k, v)


def hamt_items(keys: list[int]) -> bool:
    """``listItemsi`` = sorted distinct keys with their last values, on the HAMT.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=8
    return holds(items, hamt, keys)


def hamt_remove(keys: list[int], k: int) -> bool:
    """The ``remove`` laws (present and absent keys) on the HAMT.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return holds(remove, hamt, keys, k)


def hamt_persistence(keys: list[int], dels: list[int]) -> bool:
    """Every version of the HAMT is unchanged by later operations.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return holds(persistence, hamt, keys, dels)


def hamt_invariant(keys: list[int], dels: list[int]) -> bool:
    """The HAMT's ``_check`` holds after every insert and remove.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return holds(invariant, hamt, keys, dels)


# -- the HAMT with colliding hashes ------------------------------------------------
#
# Integer keys hash to themselves, so the checks above rarely reach the HAMT's
# deeper levels or its collision nodes; ``Clash`` keys reach both on every path.


def hamt_clash_items(keys: list[int]) -> bool:
    """The ``listItemsi`` law on the HAMT, with colliding and prefix-sharing hashes.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=8
    return holds(items, hamt, keys, Clash)


def hamt_clash_remove(keys: list[int], k: int) -> bool:
    """The ``remove`` laws on the HAMT, with colliding and prefix-sharing hashes.

    pre: len(keys) <= 6
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return holds(remove, hamt, keys, k, Clash)


def hamt_clash_persistence(keys: list[int], dels: list[int]) -> bool:
    """Persistence of the HAMT, with colliding and prefix-sharing hashes.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return holds(persistence, hamt, keys, dels, Clash)


def hamt_clash_invariant(keys: list[int], dels: list[int]) -> bool:
    """The HAMT's ``_check`` (collision nodes, canonical form) in every version, with colliding hashes.

    pre: len(keys) <= 5 and len(dels) <= 3
    post: __return__
    """
    # crosshair: per_condition_timeout=16
    return holds(invariant, hamt, keys, dels, Clash)
