"""The file readers used as a library: the system's refusals, each in one line naming the file.

``read_npy`` is public, and let a missing file or a directory through as the system's own
``FileNotFoundError`` / ``IsADirectoryError``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from persistri.impl.files import InputFileError, read_npy


def test_read_npy_names_a_missing_file_and_a_directory(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match=r"^\S*missing.npy: no such file$"):
        read_npy(tmp_path / "missing.npy")
    (tmp_path / "dir.npy").mkdir()
    with pytest.raises(InputFileError, match=r"^\S*dir.npy: a directory, not a file$"):
        read_npy(tmp_path / "dir.npy")
    np.save(tmp_path / "ok.npy", np.zeros((2, 3)))
    assert read_npy(tmp_path / "ok.npy", mmap=True).shape == (2, 3)
