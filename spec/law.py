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
import traceback
from collections.abc import Callable, Mapping
from typing import Any, ClassVar, ParamSpec, TypeVar

__all__ = ["LawViolation", "SignatureLawViolation", "law_decorator", "raised"]

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


def raised(exc: BaseException) -> str:
    """What ``exc`` says, for a message: ``"KeyError: 0"``; an exception with no message (a bare ``assert`` in a
    structure's ``_check``) names the line that raised it instead, ``"AssertionError at treap.py:109 (assert
    len(items) == m[1])"``, which is all there is to go on. O(depth of the traceback).
    """
    text = str(exc)
    if text:
        return f"{type(exc).__name__}: {text}"
    frames = traceback.extract_tb(exc.__traceback__)
    if not frames:
        return f"{type(exc).__name__} (no message)"
    last = frames[-1]
    source = f" ({last.line.strip()})" if last.line else ""
    return f"{type(exc).__name__} at {last.filename}:{last.lineno}{source}"


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
                    raise violation(name, f"the structure raised {raised(exc)}") from exc

            return checked

        return decorate

    return law
