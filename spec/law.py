"""The one exception every executable law raises: :class:`LawViolation`.

Each signature's laws (:mod:`persistri.spec.simplex_laws`,
:mod:`persistri.spec.simpcomp_laws`, …) are plain functions that return
``None`` when the law holds and raise :class:`LawViolation` when it does not.
The exception names the law and states it, so a failing conformance run says
*which* promise of the signature a structure broke, not just that an
``assert`` failed somewhere.
"""

from __future__ import annotations

__all__ = ["LawViolation"]


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
