"""The negative type tests of ``tests/typing/check_rejections.py``, run by pytest.

One mypy run type-checks every snippet (a correct minimal ``ORD_MAP`` backend
that must be accepted; the same backend with an operation missing or a wrong
signature, and ``str`` keys given to ``int``-keyed maps, that must be rejected
with the stated error code and message).  A second test proves the checker
itself can fail: expectations that are false are reported, not passed.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

_SCRIPT = Path(__file__).resolve().parent / "typing" / "check_rejections.py"


def _load() -> ModuleType:
    spec = importlib.util.spec_from_file_location("persistri_check_rejections", _SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    # dataclasses resolves annotations through sys.modules while the module executes.
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


check_rejections = _load()


def test_wrong_backends_are_rejected_and_the_right_one_accepted() -> None:
    problems = check_rejections.run_checks()
    assert problems == [], "\n".join(problems)


def test_the_checker_reports_violated_expectations() -> None:
    c = check_rejections
    good, missing_remove = c.SNIPPETS[0], c.SNIPPETS[1]
    assert good.code is None and missing_remove.note_lines == ("remove",)
    wrong = (
        # An accepted backend claimed to be rejected.
        c.Snippet(name="claims_reject", why="W1", source=good.source, code="assignment"),
        # A rejected backend claimed to be accepted.
        c.Snippet(name="claims_accept", why="W2", source=missing_remove.source),
        # The right code but the wrong missing member.
        c.Snippet(
            name="wrong_member", why="W3", source=missing_remove.source, code="assignment", note_lines=("find",)
        ),
        # The wrong error code.
        c.Snippet(name="wrong_code", why="W4", source=missing_remove.source, code="arg-type"),
    )
    problems = c.run_checks(wrong)
    for tag in ("W1", "W2", "W3", "W4"):
        assert any(p.startswith(f"{tag}:") for p in problems), (tag, problems)
    assert any("ACCEPTED" in p for p in problems if p.startswith("W1:"))
    assert any("'find'" in p for p in problems if p.startswith("W3:"))
    assert any("[arg-type]" in p for p in problems if p.startswith("W4:"))
