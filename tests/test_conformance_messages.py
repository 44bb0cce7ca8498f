"""The conformance suite's own messages, as an outsider reads them: constructors that fail, counts in words."""

from __future__ import annotations

import pytest

from persistri.impl.maps import red_black
from persistri.spec.conformance.ord_map_config import NotAnOrdMap, as_structure
from persistri.spec.conformance.simpcomp_config import NotASimpComp, as_simpcomp
from persistri.spec.ord_map_laws_base import LawViolation, _unchanged


class Boom:
    def __init__(self) -> None:
        raise RuntimeError("boom")


class NeedsArgs:
    def __init__(self, size: int) -> None:
        self.size = size


@pytest.mark.parametrize(("check", "error"), [(as_structure, NotAnOrdMap), (as_simpcomp, NotASimpComp)])
def test_a_constructor_that_raises_is_named_with_its_exception(check: object, error: type[Exception]) -> None:
    with pytest.raises(error, match=r"Boom'>\(\) raised RuntimeError: boom \(a structure class is instantiated"):
        check(Boom)  # type: ignore[operator]
    with pytest.raises(error, match="cannot be instantiated with no arguments: .*missing 1 required"):
        check(NeedsArgs)  # type: ignore[operator]


def test_a_changed_operand_is_counted_in_words() -> None:
    S = red_black.RedBlackMap[int, str]()
    two = S.insert(S.singleton(1, "a"), 2, "b")
    with pytest.raises(LawViolation, match=r"before it m had 1 item \{1: 'a'\}, after it m has 2 items"):
        _unchanged(S, two, ([(1, "a")], 1), lambda: "insert(m, 2, 'b')")
