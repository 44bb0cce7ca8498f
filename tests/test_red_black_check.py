"""The red-black map's ``_check`` (:mod:`persistri.impl.maps.red_black`) rejects broken trees, naming the rule.

Hand-built trees each break one invariant: a red root, a red node with a red
child, unequal black heights, search order (also where only an ancestor above
the parent sees it), a wrong stored size, a colour that is not ``RED`` or
``BLACK``, a node that is not a 5-tuple; valid hand-built trees pass.
"""

from __future__ import annotations

from typing import Any

import pytest

from persistri.impl.maps.red_black import BLACK, RED, RBMap, Tree, red_black

S = red_black


# -- _check rejects broken trees ---------------------------------------------------------


def leaf(k: int, colour: bool = RED) -> Tree[int, str]:
    return (colour, None, k, str(k), None)


VALID: RBMap[int, str] = (3, (BLACK, leaf(1), 2, "2", leaf(3)))


@pytest.mark.parametrize(
    ("m", "message"),
    [
        ((1, leaf(1)), "root is not black"),
        ((4, (BLACK, (RED, leaf(1), 2, "2", None), 3, "3", leaf(4))), "red node 2 has a red child 1"),
        ((2, (BLACK, leaf(1, BLACK), 2, "2", None)), "unequal black heights"),
        ((3, (BLACK, leaf(5), 3, "3", leaf(4))), "5 in the left subtree of 3"),
        # 7 is in order with its parent 1 but not with the root 5: a local check would miss it.
        (
            (4, (BLACK, (BLACK, None, 1, "1", leaf(7)), 5, "5", leaf(9, BLACK))),
            "7 in the left subtree of 5",
        ),
        ((3, (BLACK, leaf(2), 2, "2", leaf(3))), "2 in the left subtree of 2"),
        ((4, VALID[1]), "stored size 4 but 3 nodes"),
        ((3, (BLACK, ("red", None, 1, "1", None), 2, "2", leaf(3))), "colour 'red'"),
        ((3, (BLACK, (RED, None, 1), 2, "2", leaf(3))), "5-tuple"),
    ],
)
def test_check_detects_broken_trees(m: Any, message: str) -> None:
    with pytest.raises(AssertionError, match=message):
        S._check(m)


def test_check_accepts_valid_hand_built_trees() -> None:
    S._check(VALID)
    S._check(S.empty())
    S._check((4, (BLACK, (BLACK, None, 1, "1", leaf(3)), 5, "5", leaf(9, BLACK))))
