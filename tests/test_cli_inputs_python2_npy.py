"""A ``.npy`` written by Python 2 (numpy's own test data has some): read as any other, without numpy's warning.

numpy reads such a file correctly but warns on every read, in two lines that name
its source; the commands' contract is one line (a summary, or one error naming
the file).  The file is written here byte by byte: a version 1.0 header whose
shape has Python 2's long integers (``4L``).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest


def write_python2_npy(path: Path, data: np.ndarray) -> None:
    shape = "(" + "".join(f"{n}L, " for n in data.shape).rstrip(" ") + ")"
    header = f"{{'descr': '<f8', 'fortran_order': False, 'shape': {shape}, }}"
    header += " " * (-(len(header) + 11) % 16) + "\n"
    path.write_bytes(b"\x93NUMPY\x01\x00" + len(header).to_bytes(2, "little") + header.encode("latin1")
                     + data.astype("<f8").tobytes())


def run(*args: str) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONWARNINGS",)}
    return subprocess.run([sys.executable, "-m", "persistri", *args], capture_output=True, text=True, env=env,
                          timeout=300, check=False)


def test_a_python2_npy_is_hulled_with_one_line(tmp_path: Path) -> None:
    pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0.2, 0.2, 0.2]], dtype=float)
    path = tmp_path / "py2.npy"
    write_python2_npy(path, pts)
    with pytest.warns(UserWarning, match="created on Python 2"):  # numpy reads it, and warns
        assert np.array_equal(np.load(path), pts)
    done = run("hull", str(path))
    assert done.returncode == 0, done.stderr
    assert done.stderr.count("\n") == 1 and "Warning" not in done.stderr, done.stderr
    assert "4 faces, 4 vertices" in done.stderr


def test_a_python2_npy_of_the_wrong_shape_is_one_line_naming_it(tmp_path: Path) -> None:
    path = tmp_path / "flat.npy"
    write_python2_npy(path, np.array([1.0, 2.0]))
    done = run("hull", str(path))
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1 and done.stderr.startswith(f"persistri: {path}: expected an array of shape (n, 3)"), done.stderr
