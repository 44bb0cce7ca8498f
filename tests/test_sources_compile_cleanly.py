"""Every module of the package compiles without a warning (an invalid escape sequence in a docstring, say).

Python 3.11 reports those as a DeprecationWarning once, when the module is first compiled, and a cached
``.pyc`` hides it afterwards; compiling the sources here catches them every run.  (3.12 makes them
SyntaxWarnings, and a later version errors.)
"""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SOURCES = sorted(p for top in ("api", "impl", "spec", "tools", "proofs") for p in (ROOT / top).rglob("*.py"))


def test_the_sources_are_found() -> None:
    assert len(SOURCES) > 150 and any(p.name == "bulldozer.py" for p in SOURCES)


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(ROOT)))
def test_a_module_compiles_without_warnings(path: Path) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        compile(path.read_text(encoding="utf-8"), str(path), "exec", dont_inherit=True)
