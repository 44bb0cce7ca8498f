"""``python -m persistri`` runs the ``persistri`` command, under that name."""

from __future__ import annotations

import subprocess
import sys


def test_python_dash_m_runs_the_command() -> None:
    out = subprocess.run([sys.executable, "-m", "persistri", "--help"], capture_output=True, text=True, check=True)
    assert out.stdout.startswith("Usage: persistri [OPTIONS] COMMAND")
    assert "hull" in out.stdout and "terrain" in out.stdout


def test_python_dash_m_fails_as_the_command_does() -> None:
    out = subprocess.run([sys.executable, "-m", "persistri", "hull", "/nonexistent/cloud.xyz"], capture_output=True, text=True)
    assert out.returncode == 2
    assert out.stderr.strip().splitlines() == ["persistri: /nonexistent/cloud.xyz: no such file"]
