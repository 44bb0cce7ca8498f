"""Inputs by unusual names: spaces and non-ASCII letters are plain files; ``-``, a FIFO and a piped
``/dev/stdin`` are refused in one line before anything opens them (the readers open a file more than once,
so a pipe would be emptied by the first opening and block the second for ever)."""

from __future__ import annotations

import os
import threading
from pathlib import Path

import numpy as np
import pytest
from cli_contract import assert_one_line_failure, invoke

from persistri.impl.files import InputFileError, read_points
from persistri.impl.terrain.grids import read_grid

fifo = pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes on this system")


class _Unblocking:
    """A watchdog for a test on the FIFO ``path``: from 5 s on, every second until stopped (60 s at most), it
    opens it for writing and closes it (without blocking: that fails unless a reader waits), so code that
    opens it to read gets an empty file and the test fails instead of hanging the suite."""

    def __init__(self, path: Path) -> None:
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._run, args=(path,), daemon=True)
        self.thread.start()

    def _run(self, path: Path) -> None:
        if self.stop.wait(5.0):
            return
        for _ in range(55):
            try:
                os.close(os.open(path, os.O_WRONLY | os.O_NONBLOCK))
            except OSError:
                pass
            if self.stop.wait(1.0):
                return

    def cancel(self) -> None:
        self.stop.set()


def _points(path: Path) -> Path:
    np.savetxt(path, np.random.default_rng(0).random((30, 3)), delimiter=",")
    return path


@pytest.mark.parametrize("name", ["my points.csv", "Höhen Ünïcode 点.csv", "-leading dash.csv"])
def test_names_with_spaces_and_unicode_are_read(tmp_path: Path, name: str) -> None:
    path = _points(tmp_path / name)
    for command in ("hull", "delaunay"):
        result, caught = invoke([command, "--", str(path)])
        assert result.exit_code == 0, result.output
        assert name in result.stdout + result.stderr and not caught
    grid = tmp_path / name.replace(".csv", " grid.csv")
    np.savetxt(grid, np.random.default_rng(1).random((5, 6)), delimiter=",")
    result, _ = invoke(["terrain", str(grid), "--max-points", "8"])
    assert result.exit_code == 0 and grid.name in result.stdout + result.stderr, result.output


@pytest.mark.parametrize("command", [["hull"], ["delaunay"], ["terrain", "--max-points", "5"]])
def test_a_dash_is_not_standard_input(command: list[str]) -> None:
    result, caught = invoke([*command, "-"])
    assert_one_line_failure(result, caught, "-", r"-: persistri does not read standard input; give the name of a")


@fifo
@pytest.mark.parametrize(("command", "name"), [(["hull"], "p.csv"), (["delaunay"], "p.npy"), (["terrain", "--max-points", "5"], "g.csv")])
def test_a_fifo_is_refused_before_it_is_opened(tmp_path: Path, command: list[str], name: str) -> None:
    """The FIFO has no writer: opening it to read would block, so the test hangs if anything opens it."""
    path = tmp_path / name
    os.mkfifo(path)
    watchdog = _Unblocking(path)
    result, caught = invoke([*command, str(path)])
    watchdog.cancel()
    assert_one_line_failure(result, caught, name, r"a pipe \(FIFO\), not a regular file: persistri reads its input more than once")


@fifo
def test_the_readers_refuse_a_fifo_before_opening_it(tmp_path: Path) -> None:
    for name, read in (("p.npy", read_points), ("g.npy", read_grid)):
        path = tmp_path / name
        os.mkfifo(path)
        watchdog = _Unblocking(path)
        with pytest.raises(ValueError, match=rf"{name}: a pipe \(FIFO\), not a regular file"):
            read(path)
        watchdog.cancel()
    with pytest.raises(InputFileError):
        read_points(tmp_path / "p.npy")


@fifo
def test_a_fed_fifo_is_refused_and_its_writer_not_left_hanging(tmp_path: Path) -> None:
    """Before: hull opened the FIFO to check it (emptying it) and then blocked for ever opening it again."""
    path = tmp_path / "fed.csv"
    os.mkfifo(path)
    writer = threading.Thread(target=lambda: path.write_text("0,0,0\n1,0,0\n0,1,0\n0,0,1\n"), daemon=True)
    writer.start()
    watchdog = _Unblocking(path)
    result, caught = invoke(["hull", str(path)])
    watchdog.cancel()
    assert_one_line_failure(result, caught, "fed.csv", r"a pipe \(FIFO\)")
    with path.open("r") as fh:  # release the writer, which waits for a reader
        fh.read()
    writer.join(5)
    assert not writer.is_alive()
