"""CrossHair contract checks of ``Order`` (the key order of ``ORD_KEY``) and ``Option`` (SML's ``'a option``).

Checked by ``crosshair check --analysis_kind=PEP316`` as :mod:`proofs.crosshair_maps`
is (``python -m proofs``): each function's ``post: __return__`` states one law of
:mod:`persistri.spec.order` or :mod:`persistri.spec.option`.  These laws have few
paths and are settled over all of them in well under a second.
"""

from __future__ import annotations

from persistri.spec.option import NONE, SOME, isSome, valOf
from persistri.spec.order import NATURAL_ORDER, Order

__all__: list[str] = []  # nothing here is for import; CrossHair finds the contracts itself

# CPU seconds per condition.
# crosshair: per_condition_timeout=4


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
