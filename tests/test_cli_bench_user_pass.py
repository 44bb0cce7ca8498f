"""``persistri bench`` as a new user runs it: bad flag values are one readable line, before any work."""

from __future__ import annotations

import pytest
from click.testing import CliRunner

from persistri.impl.bench import mesh as bench_mesh
from persistri.impl.cli.main import main


def test_bench_mesh_refuses_an_angle_where_triangle_may_never_finish(monkeypatch: pytest.MonkeyPatch) -> None:
    """Triangle runs for ever on the square with a hole at 40° (its documentation: above 34° it may never
    finish); the bound is refused up front, naming the limit, and nothing is measured."""

    def never(*args: object, **kwargs: object) -> None:
        raise AssertionError("the bench ran: the angle was not refused")

    monkeypatch.setattr(bench_mesh, "run_mesh_bench", never)
    result = CliRunner().invoke(main, ["bench", "mesh", "--angles", "20,40", "--domains", "square-hole"])
    assert result.exit_code == 2, result.output
    assert "Invalid value for '--angles': 40° is above 34°, where Shewchuk's Triangle (the peer) may never finish" in result.output
    assert "persistri mesh --min-angle takes bounds up to 60°" in result.output
    assert "Traceback" not in result.output
