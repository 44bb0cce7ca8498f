"""The command line's failure contract as test helpers, shared by ``test_cli_inputs*.py``.

A failure is exit status 2 and exactly one non-empty line on stderr,
``persistri: …``, naming the file: no traceback, no warning, no usage text
(``persistri.impl.cli.errors``).  :func:`forbid` replaces a compute function by
one whose call ends the test, to show that a check came before any computation.
"""

from __future__ import annotations

import os
import re
import warnings
from pathlib import Path

import pytest
from click.testing import CliRunner, Result

from persistri.impl.cli.main import main

IS_ROOT = hasattr(os, "geteuid") and os.geteuid() == 0
"""Root reads and writes through permission bits: chmod cases are replaced, not dropped (see the cases)."""

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


class Computed(BaseException):
    """A command computed although its input or output was bad.

    Not an :class:`Exception`, so that no handler of the command line turns it
    into a one-line message: it ends the test where it is raised.
    """


def forbid(monkeypatch: pytest.MonkeyPatch, target: str) -> None:
    """Replace ``module:attribute`` by a function that fails the test when called."""
    module, attr = target.split(":")

    def called(*args: object, **kwargs: object) -> None:
        raise Computed(f"{target} was called")

    monkeypatch.setattr(f"{module}.{attr}", called)


def files_under(root: Path) -> set[str]:
    """Every path under ``root`` (hidden files included), relative."""
    return {str(p.relative_to(root)) for p in root.rglob("*")}


def invoke(args: list[str]) -> tuple[Result, list[str]]:
    """Run ``persistri ARGS`` in-process; the result and the warnings raised meanwhile."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = CliRunner().invoke(main, args)
    return result, [f"{w.category.__name__}: {w.message}" for w in caught]


def assert_one_line_failure(result: Result, caught: list[str], name: str, pattern: str) -> str:
    """Exit 2, one non-empty stderr line ``persistri: …`` naming ``name`` and matching ``pattern``; no noise."""
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert result.exit_code == 2, (result.exit_code, result.output, result.exception)
    assert len(lines) == 1, result.stderr
    line = lines[0]
    assert line.startswith("persistri: "), line
    assert name in line, line
    assert re.search(pattern, line), (pattern, line)
    assert "Traceback" not in result.output and "Aborted" not in result.output
    assert "Usage:" not in result.output
    assert not caught, caught
    return line


