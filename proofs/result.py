"""What every check of ``proofs/`` returns, and where the checks live.

A :class:`Result` is the outcome of one proof (:mod:`proofs.runner`) or one
CrossHair contract (:mod:`proofs.contracts`); the runner prints one line per
result and fails when any is not ``ok``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

__all__ = ["PROOFS_DIR", "Result"]

PROOFS_DIR = Path(__file__).resolve().parent
"""The ``proofs/`` directory."""


@dataclass(frozen=True)
class Result:
    """The outcome of one proof or contract: its qualified name, whether it held, and why not."""

    name: str
    ok: bool
    seconds: float | None
    detail: str = ""
