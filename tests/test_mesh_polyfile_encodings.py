"""Triangle files as editors and mistakes save them: UTF-8 with a byte order mark, UTF-16 ("Unicode" on
Windows), and a binary file given by mistake (an archive renamed .poly), which is refused as such instead
of echoing its bytes as a bad number."""

from __future__ import annotations

import codecs
from pathlib import Path

import numpy as np
import pytest

from persistri.impl.mesh.polyfile import PolyFileError, read_poly

SQUARE = "# a unit square\n4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n"


@pytest.mark.parametrize(
    ("name", "data"),
    [("bom.poly", codecs.BOM_UTF8 + SQUARE.encode()), ("le.poly", SQUARE.encode("utf-16")), ("be.poly", codecs.BOM_UTF16_BE + SQUARE.encode("utf-16-be"))],
)
def test_an_encoded_file_reads_as_the_plain_one(tmp_path: Path, name: str, data: bytes) -> None:
    (tmp_path / "plain.poly").write_text(SQUARE)
    (tmp_path / name).write_bytes(data)
    plain, other = read_poly(tmp_path / "plain.poly"), read_poly(tmp_path / name)
    assert np.array_equal(plain.vertices, other.vertices) and np.array_equal(plain.segments, other.segments)


def test_a_binary_file_is_refused_as_binary(tmp_path: Path) -> None:
    path = tmp_path / "domain.poly"
    np.savez(tmp_path / "a.npz", v=np.zeros((4, 2)))
    path.write_bytes((tmp_path / "a.npz").read_bytes())
    with pytest.raises(PolyFileError, match=r": not a Triangle file: binary data \(a NUL byte at offset \d+\)$"):
        read_poly(path)
