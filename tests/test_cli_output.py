"""Output to a pipe or a file: lines are not folded, tables not squeezed, no colour codes (:mod:`persistri.impl.cli.console`).

The commands run as subprocesses of the installed ``persistri`` script, so
their stdout and stderr are real pipes (what ``persistri … | cat`` sees); rich
alone would fold everything at 80 columns there.
"""

from __future__ import annotations

import io
import os
import platform
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from persistri.impl.cli.console import MIN_WIDTH, UNBOUNDED_WIDTH, make_console, pipe_width, text_console

PERSISTRI = str(Path(sys.executable).with_name("persistri"))

def _persistri(args: list[str], cwd: Path, columns: str | None = None) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k not in ("COLUMNS", "FORCE_COLOR", "TTY_COMPATIBLE")}
    if columns is not None:
        env["COLUMNS"] = columns
    result = subprocess.run([PERSISTRI, *args], cwd=cwd, env=env, capture_output=True, text=True, timeout=300, check=False)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "\x1b" not in result.stdout + result.stderr  # no colour or cursor codes off a terminal
    return result


def _table_lines(text: str) -> list[str]:
    """The lines of the first table in ``text``."""
    lines = text.splitlines()
    top = next(i for i, line in enumerate(lines) if line.startswith("┏"))
    bottom = next(i for i, line in enumerate(lines) if i > top and line.startswith("└"))
    return lines[top : bottom + 1]


def test_bench_table_keeps_its_natural_width_in_a_pipe(tmp_path: Path) -> None:
    result = _persistri(["bench", "maps", "--sizes", "40", "--repeat", "1"], tmp_path)
    lines = _table_lines(result.stdout)
    widths = {len(line) for line in lines}
    assert len(lines) > 10 and len(widths) == 1 and widths.pop() > 100  # one unsqueezed table, wider than 80
    row = next(line for line in lines if " red_black " in line)
    assert "persistri" in row and "×" in row  # every column present: name, kind, µs and ratios
    # The caption is one line, not folded to the table's width.
    caption = [line for line in result.stdout.splitlines() if "best of 1 run(s)" in line]
    assert len(caption) == 1 and caption[0].rstrip().endswith(f"on {platform.machine()} {platform.system()}")
    assert result.stderr == ""  # no progress bar, not even the blank line it would leave


def test_columns_bounds_the_tables_but_folds_no_line(tmp_path: Path) -> None:
    result = _persistri(["bench", "maps", "--sizes", "40", "--repeat", "1"], tmp_path, columns="90")
    lines = _table_lines(result.stdout)
    assert lines and max(len(line) for line in lines) <= 90  # the table fits the width asked for
    caption = [line for line in result.stdout.splitlines() if "best of 1 run(s)" in line]
    assert len(caption) == 1 and len(caption[0]) > 90  # a plain line is still not folded


def test_hull_message_and_stats_are_not_folded(tmp_path: Path) -> None:
    deep = tmp_path / ("a_directory_with_a_long_name_" * 4) / "and_another_level"
    deep.mkdir(parents=True)
    points = deep / "points.npy"
    np.save(points, np.random.default_rng(1).standard_normal((200, 3)))
    result = _persistri(["hull", str(points), "--stats", "-o", str(tmp_path / "hull.ply")], tmp_path)
    said = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(said) == 1 and len(said[0]) > 120  # the whole message, on one line
    assert said[0].startswith(f"hull of {points}: ") and said[0].endswith("duplicate rows merged")
    stats = _table_lines(result.stdout)
    assert any("key comparisons" in line for line in stats) and len({len(line) for line in stats}) == 1


def test_a_narrow_columns_still_shows_the_values(tmp_path: Path) -> None:
    # COLUMNS=5 printed a stats table of empty cells: every row "│ │ │".
    result = _persistri(["hull", "--dist", "InBall", "-n", "200", "--stats"], tmp_path, columns="5")
    stats = _table_lines(result.stdout)
    assert any(re.search(r"key comparisons +│ +[1-9][\d,]* │", line) for line in stats), stats


def test_the_factory(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("COLUMNS", raising=False)
    monkeypatch.delenv("FORCE_COLOR", raising=False)
    monkeypatch.delenv("TTY_COMPATIBLE", raising=False)
    out, err = io.StringIO(), io.StringIO()  # not terminals
    monkeypatch.setattr(sys, "stdout", out)
    monkeypatch.setattr(sys, "stderr", err)
    for stderr in (False, True):
        console = make_console(stderr=stderr)
        assert not console.is_terminal and console.soft_wrap and console.width == UNBOUNDED_WIDTH
        assert console.color_system is None
        console.print("x" * 300, "[bold]y[/bold]")
    # No markup: square brackets are text (a file named survey[final].csv, persistri[geotiff]), and no codes.
    assert out.getvalue() == err.getvalue() == "x" * 300 + " [bold]y[/bold]\n"
    for value, width in (
        ("132", 132),
        ("", UNBOUNDED_WIDTH),
        ("wide", UNBOUNDED_WIDTH),
        ("0", UNBOUNDED_WIDTH),
        ("5", MIN_WIDTH),  # rich would squeeze every column to nothing
    ):
        monkeypatch.setenv("COLUMNS", value)
        assert pipe_width() == width
        assert make_console().width == width
    buffer = io.StringIO()
    text_console(buffer).print("[bold]z[/bold] " + "w" * 200)
    assert buffer.getvalue() == "[bold]z[/bold] " + "w" * 200 + "\n"


@pytest.mark.parametrize("args", [["delaunay", "--help"], ["mesh", "square-hole", "--stats"]])
def test_a_closed_pipe_stops_quietly(tmp_path: Path, args: list[str]) -> None:
    # `persistri … | head`: the reader goes away before the output is written.  Not an error line
    # ("persistri: broken pipe", status 2, as before): click's handling, status 1 and nothing more.
    process = subprocess.Popen([PERSISTRI, *args], cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    assert process.stdout is not None and process.stderr is not None
    process.stdout.close()
    err = process.stderr.read().decode()
    assert process.wait(timeout=300) == 1
    assert "persistri:" not in err and "Traceback" not in err and "Exception ignored" not in err


@pytest.mark.parametrize(
    "args, name",
    [
        (["hull", "--dist", "inball", "-n", "50", "-o", ""], "'-o' / '--output'"),
        (["hull", ""], "'INPUT'"),
        (["delaunay", " "], "'INPUT'"),
        (["mesh", "", "--min-angle", "20"], "'INPUT'"),
        (["terrain", "jacksboro", "--max-error", "5", "--plot", ""], "'--plot'"),
    ],
)
def test_an_empty_file_name_is_a_bad_argument(tmp_path: Path, args: list[str], name: str) -> None:
    # pathlib reads "" as "." (the current directory): without the check, `-o ''` was ". : a directory" and an
    # empty INPUT read the directory.
    result = subprocess.run([PERSISTRI, *args], cwd=tmp_path, capture_output=True, text=True, timeout=300, check=False)
    assert result.returncode == 2
    assert f"Invalid value for {name}: an empty file name" in result.stderr
    assert not list(tmp_path.iterdir())
