"""The one exception every executable law raises: :class:`LawViolation`.

Each signature's laws (:mod:`persistri.spec.simplex_laws`,
:mod:`persistri.spec.simpcomp_laws`, …) are plain functions that return
``None`` when the law holds and raise :class:`LawViolation` when it does not.
The exception names the law and states it, so a failing conformance run says
*which* promise of the signature a structure broke, not just that an
``assert`` failed somewhere.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping
from typing import Any, ClassVar, ParamSpec, TypeVar

__all__ = ["LawViolation", "SignatureLawViolation", "law_decorator"]

P = ParamSpec("P")
R = TypeVar("R")


class LawViolation(AssertionError):
    """A structure broke a law of its signature.

    ``law`` is the law's short name (e.g. ``"flip-involution"``), ``statement``
    the law itself in words, ``detail`` what was observed.  A subclass of
    :class:`AssertionError`, so test runners report it as a failed check.
    """

    law: str
    statement: str
    detail: str

    def __init__(self, law: str, statement: str, detail: str = "") -> None:
        self.law = law
        self.statement = statement
        self.detail = detail
        message = f"law {law!r} violated: {statement}"
        if detail:
            message += f"\n  observed: {detail}"
        super().__init__(message)


class SignatureLawViolation(LawViolation):
    """The violation of one signature's laws: subclasses name the signature and its table of laws.

    ``SignatureLawViolation(law, detail)`` looks the statement up in ``LAWS``, so
    a misspelt law name is a :class:`ValueError`, not a silent message.
    """

    SIGNATURE: ClassVar[str]
    """The signature's SML name, e.g. ``"ORD_MAP"``."""
    LAWS: ClassVar[Mapping[str, str]]
    """Every law of the signature: name → statement."""

    def __init__(self, law: str, detail: str = "") -> None:
        try:
            statement = self.LAWS[law]
        except KeyError:
            raise ValueError(f"unknown {self.SIGNATURE} law {law!r}; known laws: {', '.join(self.LAWS)}") from None
        super().__init__(law, statement, detail)

    def __reduce__(self) -> tuple[Any, ...]:
        return (type(self), (self.law, self.detail))


def law_decorator(
    violation: type[SignatureLawViolation],
) -> Callable[[str], Callable[[Callable[P, R]], Callable[P, R]]]:
    """A decorator factory ``law(name)``: a law function that lets an unexpected exception escape
    reports it as a violation of law ``name`` (a crashing structure breaks the law it was tested on)."""

    def law(name: str) -> Callable[[Callable[P, R]], Callable[P, R]]:
        def decorate(fn: Callable[P, R]) -> Callable[P, R]:
            @functools.wraps(fn)
            def checked(*args: P.args, **kwargs: P.kwargs) -> R:
                try:
                    return fn(*args, **kwargs)
                except LawViolation:
                    raise
                except Exception as exc:
                    raise violation(name, f"the structure raised {type(exc).__name__}: {exc}") from exc

            return checked

        return decorate

    return law
