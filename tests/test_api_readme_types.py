"""The README's Python examples type-check as written under ``mypy --strict``, as a user's code would.

The README is the first code a user copies; a line such as
``len(hull.history)`` that needs narrowing before ``mypy --strict`` accepts it
would fail in their project, not here.  Every ``>>>`` session of the README is
made one module (the sessions continue each other) and checked with the
project's settings; a second test proves the check fails on a line that does
not type-check.
"""

from __future__ import annotations

import os
import re
import shutil
import tempfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CACHE_DIR = ROOT / ".mypy_cache" / "readme_types" / os.environ.get("PYTEST_XDIST_WORKER", "main")
"""mypy's cache for this check, apart from the package's own (one per pytest-xdist worker)."""


def readme_sessions(text: str) -> str:
    """The source of every ``>>>`` session of ``text``, in order: prompts kept, expected output dropped."""
    lines = []
    for block in re.findall(r"```python\n(.*?)```", text, flags=re.S):
        code = [line[4:] for line in block.splitlines() if line.startswith((">>> ", "... "))]
        lines += code
    return "\n".join(lines) + "\n"


def mypy_errors(source: str) -> list[str]:
    """mypy's errors on ``source`` as a module of its own: ``--strict`` and the project's settings."""
    from mypy import api  # imported here so that collecting this module stays cheap

    seed = ROOT / ".mypy_cache" / "check_rejections" / "main"  # what `make typecheck` leaves: persistri checked
    if not CACHE_DIR.exists() and seed.is_dir():  # mypy revalidates every entry it reads from a copy
        try:
            shutil.copytree(seed, CACHE_DIR)
        except OSError:
            shutil.rmtree(CACHE_DIR, ignore_errors=True)
    CACHE_DIR.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="persistri-readme-") as tmp:
        path = Path(tmp) / "readme_example.py"
        path.write_text(source, encoding="utf-8")
        stdout, stderr, status = api.run(
            ["--strict", "--config-file", str(ROOT / "pyproject.toml"), "--cache-dir", str(CACHE_DIR),
             "--no-error-summary", "--show-error-codes", "--no-pretty", "--no-color-output", str(path)]
        )
    assert status in (0, 1), f"mypy crashed or was misconfigured (exit status {status}):\n{stdout}{stderr}"
    return [line for line in stdout.splitlines() if ": error:" in line]


@pytest.mark.skipif(bool(os.environ.get("PERSISTRI_TWIN")), reason="types are the same for the compiled twin")
def test_the_readme_examples_type_check_as_written() -> None:
    source = readme_sessions((ROOT / "README.md").read_text(encoding="utf-8"))
    assert "len(hull.history)" in source  # the line that needed narrowing before
    errors = mypy_errors(source)
    assert errors == [], "\n".join(errors)


@pytest.mark.skipif(bool(os.environ.get("PERSISTRI_TWIN")), reason="types are the same for the compiled twin")
def test_the_check_reports_a_line_that_needs_narrowing() -> None:
    source = "import numpy as np\nimport persistri\nflag = bool(np.random.default_rng(0).integers(2))\n"
    source += "hull = persistri.ConvexHull(np.eye(4, 3), history=flag)\nprint(len(hull.history))\n"
    errors = mypy_errors(source)
    assert len(errors) == 1 and ":5:" in errors[0] and "[arg-type]" in errors[0], errors
