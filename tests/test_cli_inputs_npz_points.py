"""A ``.npz`` given where points are read: refused, with the archive's arrays named and the line that saves one.

scipy users keep points in archives (``np.savez(path, points=..., labels=...)``);
which array holds the points is not persistri's to guess, but the message says
how to make the ``.npy`` it reads.  Where no ``.npy`` is read (a domain for
``persistri mesh``), the message gives no such advice.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from cli_contract import invoke

from persistri.impl.files import InputFileError, read_points


def test_the_reader_names_the_arrays(tmp_path: Path) -> None:
    np.savez(tmp_path / "several.npz", points=np.zeros((4, 3)), labels=np.arange(4))
    with pytest.raises(InputFileError) as caught:
        read_points(tmp_path / "several.npz", (3,))
    message = str(caught.value)
    assert "unknown point format .npz" in message and "its arrays points, labels" in message, message
    assert "np.save('points.npy', np.load('several.npz')['points'])" in message, message


@pytest.mark.parametrize("command", ["hull", "delaunay"])
def test_the_command_names_the_arrays(tmp_path: Path, command: str) -> None:
    np.savez(tmp_path / "one.npz", xyz=np.zeros((4, 3)))
    result, caught = invoke([command, str(tmp_path / "one.npz"), "-o", str(tmp_path / "out.ply")])
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert result.exit_code == 2 and len(lines) == 1 and not caught, result.stderr
    assert "(its array xyz)" in lines[0] and "np.load('one.npz')['xyz']" in lines[0], lines[0]


def test_no_zip_gets_the_advice_without_names(tmp_path: Path) -> None:
    (tmp_path / "junk.npz").write_text("not a zip")
    with pytest.raises(InputFileError, match=r"a NumPy archive: save the array to read alone with np.save \(a .npy\)$"):
        read_points(tmp_path / "junk.npz")


def test_a_domain_is_not_advised_to_be_an_npy(tmp_path: Path) -> None:
    np.savez(tmp_path / "d.npz", vertices=np.zeros((4, 2)))
    result, _ = invoke(["mesh", str(tmp_path / "d.npz")])
    assert result.exit_code == 2 and "unknown domain format .npz" in result.stderr, result.stderr
    assert "np.save" not in result.stderr
