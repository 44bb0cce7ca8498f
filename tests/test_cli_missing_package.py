"""A package the command needs that cannot be imported is named, with the ``pip install`` that brings it.

Simulated by a module of that name, first on the path, that raises what a missing one raises: the
command must say which package is missing, in one line, and not call it a bug in persistri.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest


@pytest.mark.parametrize(
    "argv",
    [
        ["bench", "hull", "--sizes", "100", "--dists", "InBall"],
        ["bench", "delaunay", "--sizes", "100"],
        ["hull", "--dist", "InBall", "-n", "100", "--check"],
    ],
)
def test_a_missing_package_is_named_not_called_a_bug(tmp_path: Path, argv: list[str]) -> None:
    (tmp_path / "scipy.py").write_text("raise ModuleNotFoundError(\"No module named 'scipy'\", name='scipy')\n")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), os.environ.get("PYTHONPATH", "")])}
    env.pop("PERSISTRI_DEBUG", None)
    done = subprocess.run(
        [sys.executable, "-m", "persistri", *argv], capture_output=True, text=True, env=env, cwd=tmp_path, timeout=600
    )
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1, done.stderr
    assert lines[0].startswith("persistri: scipy is not installed, and this command needs it (No module named 'scipy')")
    assert "pip install scipy" in lines[0] and "bug" not in lines[0]
