"""Reading the vertices of a PLY file as points: the ``.ply`` input of :func:`persistri.impl.files.read_points`.

The header is read and checked here before meshio reads the data (meshio's ``read`` prints and exits
the process on a file that is no PLY, and its ASCII reader silently returns fewer vertices than
announced); the vertices must have x, y, z properties (in ASCII PLY, as the first three).  An integer
of an ASCII PLY that its property's type would round (``9007199254740993`` as a ``double``,
``16777217`` as a ``float``) is refused naming its line: persistri never rounds its input.
Every failure is an :class:`~persistri.impl.file_errors.InputFileError`.  O(n) for n vertices.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from persistri.impl.file_errors import InputFileError, shown
from persistri.impl.text_tables import Fields

__all__ = ["read_ply", "ply_fields"]


_PLY_SIZES: dict[str, int] = {
    **dict.fromkeys(("char", "uchar", "int8", "uint8"), 1),
    **dict.fromkeys(("short", "ushort", "int16", "uint16"), 2),
    **dict.fromkeys(("int", "uint", "float", "int32", "uint32", "float32"), 4),
    **dict.fromkeys(("double", "float64"), 8),
}
"""Bytes of each PLY scalar type (PLY 1.0's names and their sized aliases)."""


def _ply_vertex_header(path: Path) -> tuple[int, list[str], int | None]:
    """The vertex count and the vertex properties' names that the PLY header of ``path`` announces, and for an
    ASCII file the line (from 1) of the first vertex (each element of an ASCII PLY takes one line).

    Checked here, before meshio reads the data: meshio's ``read`` prints and exits the process on a
    file that is no PLY, its ASCII reader silently returns fewer vertices than announced (a truncated
    file would be hulled as if complete) and needs x, y, z as the first three properties.
    O(header lines).
    """
    with path.open("rb") as fh:
        if fh.readline(16).strip() != b"ply":
            raise InputFileError(path, "not a PLY file (its first line is not 'ply')")
        count: int | None = None
        names: list[str] = []
        element = ""
        ascii_ = False
        elements = 0
        first = False  # whether the vertex element comes first (its data then starts the body)
        lines = 1  # the header's lines read so far
        before = 0  # the lines of the elements before the vertex element (ASCII)
        record: int | None = 0  # bytes of one vertex of a binary file (None: a list property, no fixed size)
        for _ in range(100_000):
            raw = fh.readline(4096)
            if not raw:
                raise InputFileError(path, "a damaged PLY header (no end_header line)")
            lines += 1
            words = raw.decode("latin-1").split()
            if words == ["end_header"]:
                break
            if words[:2] == ["format", "ascii"]:
                ascii_ = True
            elif words[:1] == ["element"]:
                element = words[1] if len(words) > 1 else ""
                elements += 1
                if count is None and element != "vertex" and len(words) == 3 and words[2].isdecimal():
                    before += int(words[2])
                if element == "vertex":
                    if len(words) != 3 or not words[2].isdecimal():
                        raise InputFileError(path, f"a damaged PLY header (line {shown(raw.decode('latin-1').strip())})")
                    count = int(words[2])
                    first = elements == 1
            elif words[:1] == ["property"] and element == "vertex":
                names.append(words[-1])
                size = _PLY_SIZES.get(words[1]) if len(words) == 3 else None
                record = None if record is None or size is None else record + size
        else:
            raise InputFileError(path, "a damaged PLY header (no end_header line)")
        data_start = fh.tell()
    if count is None:
        raise InputFileError(path, "no points: the PLY file has no vertex element")
    if count == 0:
        raise InputFileError(path, "no points: the PLY header announces 0 vertices")
    if not ascii_ and first and record:
        held = path.stat().st_size - data_start
        if held < count * record:  # a binary file cut short: numpy's reader would say only "buffer size must be …"
            raise InputFileError(path, f"truncated: the PLY header announces {count:,} vertices of {record} bytes, the file holds {held:,} bytes of data")
    if (names[:3] != ["x", "y", "z"]) if ascii_ else not {"x", "y", "z"} <= set(names):
        listed = ", ".join(n if len(n) <= 40 else n[:39] + "…" for n in names[:8]) + (", …" if len(names) > 8 else "")
        where = " as the first three (in ASCII PLY)" if ascii_ else ""
        raise InputFileError(path, f"PLY vertices with the properties {listed or 'none'}: persistri reads x, y, z{where}")
    return count, names, (lines + before + 1 if ascii_ else None)


def read_ply(path: Path) -> NDArray[Any]:
    """The vertices of the PLY file ``path`` as meshio reads them (``(n, k)``, the file's type), its header
    checked first and, for an ASCII file, no integer rounded by its property's type.
    Raises :class:`InputFileError` (one line naming the file; the line of an ASCII file) for a file that is no
    PLY, a damaged or truncated one, vertices without x, y, z, or a rounded integer; ``OSError`` is the caller's.
    O(n).
    """
    from meshio import ply

    count, _, first_line = _ply_vertex_header(path)
    try:
        mesh = ply.read(path)  # not meshio.read: it prints and exits on a ReadError
    except Exception as exc:  # meshio raises many types for malformed files
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise InputFileError(path, f"cannot read PLY ({first})") from None
    pts: NDArray[Any] = np.asarray(mesh.points)
    if pts.ndim != 2 or pts.shape[0] != count:
        raise InputFileError(path, f"truncated: the PLY header announces {count:,} vertices, the file holds {len(pts):,}")
    if first_line is not None:
        _refuse_rounded_ply(path, pts, first_line)
    return pts


_INTEGER_WORD = re.compile(r"[-+]?\d+")


def _refuse_rounded_ply(path: Path, pts: NDArray[Any], first_line: int) -> None:
    """Raise :class:`InputFileError` for the first integer x, y or z of an ASCII PLY (vertex ``i`` on line
    ``first_line + i``) that reading it in its property's type rounded: ``9007199254740993`` as a ``double`` is
    2^53, ``16777217`` as a ``float`` is 2^24.  Only rows with a coordinate at or beyond the type's exact
    integers (2^53, 2^24) are looked up on their line, so other files cost one vectorised comparison.
    """
    if pts.dtype.kind != "f" or pts.shape[1] < 3:
        return
    with np.errstate(invalid="ignore"):
        big = (np.abs(pts[:, :3]) >= 2.0 ** (np.finfo(pts.dtype).nmant + 1)).any(axis=1)
    if not big.any():
        return
    text = path.read_bytes().decode("latin-1").replace("\r\n", "\n").replace("\r", "\n").split("\n")
    for row in np.flatnonzero(big).tolist():
        line = first_line + row
        for word, value in zip(text[line - 1].split()[:3], pts[row, :3].tolist()):
            if _INTEGER_WORD.fullmatch(word) and int(word) != value:
                kind = "float64" if pts.dtype == np.float64 else f"{pts.dtype}, its PLY property's type"
                hint = "" if pts.dtype == np.float64 else " (declare the property double)"
                raise InputFileError(
                    path,
                    f"{word} is not exactly representable as {kind}: reading it would round it to {value:.17g}, and "
                    f"persistri never rounds its input{hint}",
                    line=line,
                )


def ply_fields(path: Path, fields: Fields) -> list[int]:
    """``fields`` for a PLY file's vertices, read as x, y, z: a name (any case) becomes its column number."""
    out = []
    for f in fields:
        if isinstance(f, str):
            if f.lower() not in ("x", "y", "z"):
                raise InputFileError(path, f"no column {f!r}: PLY vertices are read as x, y, z")
            out.append("xyz".index(f.lower()))
        else:
            out.append(int(f))
    return out
