"""Reading point sets and writing triangle meshes, by file extension.

Point inputs (:func:`read_points`):

* ``.npy`` — an ``(n, d)`` array of reals (integers must be exact in float64;
  object arrays are never unpickled);
* ``.csv`` / ``.xyz`` / ``.txt`` (or gzip-compressed, ``.xyz.gz``) — text, one point per line, by the rules of
  :mod:`persistri.impl.text_tables` (delimiters, header lines, ``#`` comments);
  columns are chosen by number or by the header's names (``fields``); without a
  choice a header naming ``x`` and ``y`` (and ``z``) among other columns picks
  those (``id,x,y`` → ``x, y``), else every column is read;
* ``.ply`` — the vertices of a PLY file, through meshio (an integer of an ASCII PLY that its
  property's type would round, ``9007199254740993`` as a ``double``, is refused naming its line;
  :mod:`persistri.impl.ply_points`).

Mesh outputs (:func:`write_mesh`): ``.ply``, ``.obj``, ``.off``, ``.stl`` through
meshio, and ``.npz`` holding named arrays.

Every failure is an :class:`InputFileError` (a :class:`ValueError`) whose text is
one line naming the file and, for text, the line of the file (counting headers,
comments and blank lines, from 1): ``points.csv: line 7: expected 3 numbers, got 2``.
"""

from __future__ import annotations

import numbers
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from persistri.impl.file_errors import InputFileError, foreign_format, os_error, quote, special_file, widths
from persistri.impl.geometry.points import as_points
from persistri.impl.ply_points import ply_fields, read_ply
from persistri.impl.text_tables import Fields, read_text, read_text_table, text_of

__all__ = [
    "rounded_integer",
    "rounded_note",
    "POINT_FORMATS",
    "TEXT_FORMATS",
    "MESH_FORMATS",
    "InputFileError",
    "read_points",
    "read_npy",
    "read_text_table",
    "write_mesh",
    "compact_mesh",
    "unit_normals",
]

TEXT_FORMATS = (".csv", ".xyz", ".txt")
"""Text point formats: one point per line."""

POINT_FORMATS = (".npy", *TEXT_FORMATS, ".ply")
"""The extensions :func:`read_points` reads."""

MESH_FORMATS = (".ply", ".obj", ".off", ".stl", ".npz")
"""The extensions :func:`write_mesh` writes."""

_NPY_MAGIC = b"\x93NUMPY"


# -- binary ----------------------------------------------------------------------------------


def read_npy(path: str | Path, *, mmap: bool = False) -> NDArray[Any]:
    """The array of a ``.npy`` file of real numbers, its header checked before the data is read.

    ``mmap`` — map the file read-only instead of reading it (``np.load(mmap_mode="r")``:
    rows are read when used, so a file larger than memory can be cut into chunks).
    Raises :class:`InputFileError` for an empty, truncated or foreign file (a
    ``.npz`` archive, anything without the NumPy header), and for an array of
    Python objects (never unpickled), strings, complex numbers or records.
    or a file the system will not let us read (missing, a directory, no permission).
    Shared by the point and the grid readers; the shape is theirs to check.
    """
    path = Path(path)
    try:
        return _read_npy(path, mmap)
    except OSError as exc:  # missing, a directory, unreadable: one line, as read_points says it
        raise os_error(path, exc) from None


def _read_npy(path: Path, mmap: bool) -> NDArray[Any]:
    """:func:`read_npy` with the system's errors left to it (``OSError``)."""
    with path.open("rb") as fh:
        magic = fh.read(len(_NPY_MAGIC))
        if not magic:
            raise InputFileError(path, "the file is empty")
        if magic.startswith(b"PK"):
            raise InputFileError(path, "a .npz archive, not a .npy array")
        if magic != _NPY_MAGIC:
            raise InputFileError(path, "not a .npy file (no NumPy header)")
        fh.seek(0)
        try:
            version = np.lib.format.read_magic(fh)
            if version == (1, 0):
                shape, _, dtype = np.lib.format.read_array_header_1_0(fh)
            elif version == (2, 0):
                shape, _, dtype = np.lib.format.read_array_header_2_0(fh)
            else:  # 3.0 exists only for structured arrays with non-Latin-1 field names
                raise InputFileError(path, f"a .npy file of format {version[0]}.{version[1]}: not an array of real numbers")
            offset = fh.tell()
        except (ValueError, EOFError) as exc:
            raise InputFileError(path, f"a damaged .npy header ({str(exc).splitlines()[0]})") from None
    if dtype.hasobject:
        raise InputFileError(path, "holds Python objects (a pickled array); persistri never unpickles: save numbers")
    if dtype.fields is not None:  # a record per row (PDAL, a laspy point record): the columns are not ours to guess
        names = list(dtype.names or ())
        shown = ", ".join(names[:6]) + (", …" if len(names) > 6 else "")
        first = names[:3] if len(names) >= 3 else names
        stack = ", ".join(f"a[{n!r}]" for n in first)
        raise InputFileError(
            path,
            f"a structured array (a record per row, fields {shown}), not an array of numbers: save the numbers "
            f"as a plain array, e.g. np.column_stack([{stack}])",
        )
    if dtype.kind not in "biuf":
        raise InputFileError(path, f"holds {dtype} values, not real numbers")
    expected = int(np.prod(shape, dtype=np.int64)) * dtype.itemsize
    held = path.stat().st_size - offset
    if held < expected:
        raise InputFileError(path, f"truncated: the header announces {shape} {dtype} ({expected:,} bytes), the file holds {held:,}")
    try:
        arr: NDArray[Any] = np.load(path, allow_pickle=False, mmap_mode="r" if mmap else None)
    except (ValueError, EOFError, OSError) as exc:
        raise InputFileError(path, f"cannot read .npy ({str(exc).splitlines()[0]})") from None
    return arr


def _check_shape(path: Path, shape: tuple[int, ...], columns: Sequence[int] | None) -> None:
    if len(shape) != 2:
        want = f"(n, {widths(columns)})" if columns is not None else "(n, d)"
        raise InputFileError(path, f"expected an array of shape {want}, got shape {shape}")
    if shape[0] == 0:
        raise InputFileError(path, f"no points: the array has shape {shape}")
    if columns is not None and shape[1] not in columns:
        raise InputFileError(path, f"expected {widths(columns)} columns, got shape {shape}")


def _select_array(path: Path, raw: NDArray[Any], fields: Fields) -> NDArray[Any]:
    """The columns ``fields`` (numbers only: arrays have no header) of a 2-D array."""
    if any(isinstance(f, str) for f in fields):
        raise InputFileError(path, "has no header to name columns by: choose them by number (from 0)")
    picked = [int(f) for f in fields]
    if raw.ndim != 2:
        raise InputFileError(path, f"expected an array of shape (n, d), got shape {raw.shape}")
    bad = [f for f in picked if not 0 <= f < raw.shape[1]]
    if bad:
        raise InputFileError(path, f"no column {bad[0]}: the array has {raw.shape[1]} (numbered from 0)")
    if len(set(picked)) != len(picked):
        raise InputFileError(path, f"a column is selected twice: {', '.join(map(str, picked))}")
    return raw[:, picked]


# -- the entry point -------------------------------------------------------------------------


def read_points(path: str | Path, columns: Sequence[int] | None = None, fields: Fields | None = None) -> NDArray[np.float64]:
    """The points stored in ``path``: a non-empty ``(n, d)`` float64 array of finite, exact values.

    ``columns`` lists the accepted widths ``d`` (``(3,)`` for a hull,
    ``(2, 3)`` for a Delaunay triangulation); None accepts any.  ``fields``
    selects the columns, in order: 0-based numbers, or names from a text file's
    header line (any case; other columns may then hold anything, such as dates).
    Without it a text file whose last header line names ``x`` and ``y`` (and
    ``z``) among other columns gives those; otherwise every column.  Raises
    :class:`InputFileError` (one line naming the file; the line of a text
    file, the row of an array counting from 0) for a missing or unreadable
    file, an unknown extension, binary or non-UTF-8 text, a file with no
    points, a bad or ragged row, the wrong number of columns, a NaN or
    infinite coordinate, an integer float64 cannot hold exactly, or a pipe
    (a FIFO: its readers open a file more than once).
    O(n) (a text file with a bad row is parsed about twice more to find it).
    """
    _check_columns(columns)
    p = Path(path)
    suffix = p.suffix.lower()
    if p.is_symlink() and not p.exists():
        raise InputFileError(p, f"a broken symbolic link (to {p.readlink()})")
    if suffix == ".gz":  # points.xyz.gz: text is read through gzip (text_tables), nothing else is
        suffix = Path(p.stem).suffix.lower()
        if suffix not in TEXT_FORMATS:
            raise InputFileError(p, f"a gzip-compressed {suffix or 'file'}: persistri decompresses text only ({', '.join(t + '.gz' for t in TEXT_FORMATS)}); decompress it first")
    if suffix not in POINT_FORMATS:
        raise InputFileError(p, f"unknown point format {suffix or '(no extension)'}; use one of {', '.join(POINT_FORMATS)}{foreign_format(p)}")
    special = special_file(p)
    if special is not None:  # a pipe: the readers open their file more than once, and would block for ever
        raise InputFileError(p, special)
    try:
        if suffix in TEXT_FORMATS:
            arr, lines = read_text(p, columns, fields=fields)
            _refuse_rounded_integers(p, arr, lines)
            bad = ~np.isfinite(arr).all(axis=1)
            if bad.any():
                row = int(np.argmax(bad))
                shown = ", ".join(repr(float(v)) for v in arr[row])
                raise InputFileError(p, f"a coordinate is not finite ({shown}){_overflow_note(p, int(lines[row]))}", line=int(lines[row]))
            out: NDArray[np.float64] = arr + 0.0  # -0.0 becomes 0.0
            return out
        raw = read_npy(p) if suffix == ".npy" else read_ply(p)
    except OSError as exc:
        raise os_error(p, exc) from None
    if fields is not None:
        if suffix == ".ply":
            fields = ply_fields(p, fields)
        raw = _select_array(p, raw, fields)
    _check_shape(p, raw.shape, columns)
    try:
        return as_points(raw, raw.shape[1], what=str(p))
    except (TypeError, ValueError) as exc:  # a non-finite or inexact row, named by as_points (from 0)
        raise InputFileError(p, str(exc).splitlines()[0].removeprefix(f"{p}: ")) from None


_INTEGER_TOKEN = re.compile(r"(?<![\w.])[-+]?\d{16,}(?![\w.])")
"""An integer of 16 digits or more standing alone in a line of text (not part of a decimal or an exponent)."""


def rounded_integer(text: str, values: NDArray[np.float64]) -> str | None:
    """The first integer written in ``text`` (16 digits or more, standing alone) that a double cannot hold
    and whose double is among ``values`` (the numbers read from ``text``): the token its reading rounded,
    or None.  Only the values of 2^53 or more are looked up, so a file without one costs one vectorised
    comparison. O(len(values)), and O(len(text)) when some value is that large.
    """
    with np.errstate(invalid="ignore"):
        big = values[np.abs(values) >= 2.0**53]
    if big.size == 0:
        return None
    read = set(big.tolist())
    for token in _INTEGER_TOKEN.findall(text):
        exact = int(token)
        if float(exact) != exact and float(exact) in read:
            return str(token)
    return None


def rounded_note(token: str) -> str:
    """The end of the error for an integer a double would round: what it is, and what reading it would do."""
    return (
        f"{token} is not exactly representable as float64 (an integer beyond 2^53 that is not a double; "
        f"reading it would round it to {float(int(token)):.17g}, and persistri never rounds its input)"
    )


def _refuse_rounded_integers(path: Path, arr: NDArray[np.float64], lines: NDArray[Any]) -> None:
    """Raise :class:`InputFileError` for the first integer of a text file that its double rounded
    (``9007199254740993`` read as 2^53): a coordinate of 2^53 or more is looked up on its line, and an
    integer written there that a double cannot hold and whose rounding is that coordinate is named.
    Decimals (``0.1``) are read as the nearest double, as every reader of decimal text does; an integer
    is a number the writer meant exactly.  O(n) vectorised, and O(line) for each row with such a coordinate.
    """
    with np.errstate(invalid="ignore"):
        big = (np.abs(arr) >= 2.0**53).any(axis=1)
    if not big.any():
        return
    text = text_of(path).replace("\r\n", "\n").replace("\r", "\n").split("\n")
    for row in np.flatnonzero(big).tolist():
        line = int(lines[row])
        token = rounded_integer(text[line - 1], arr[row])
        if token is not None:
            raise InputFileError(path, rounded_note(token), line=line)


def _check_columns(columns: object) -> None:
    """The caller's ``columns`` (accepted widths, not column numbers: those are ``fields``): None or a
    non-empty sequence of integers >= 1; a :class:`TypeError` or :class:`ValueError` otherwise.  O(len)."""
    if columns is None:
        return
    if isinstance(columns, (str, bytes)) or not isinstance(columns, Sequence):
        raise TypeError(f"columns must be a sequence of accepted widths such as (2, 3), not {type(columns).__name__}")
    if not columns:
        raise ValueError("columns must list at least one accepted width (None accepts any)")
    for c in columns:
        if isinstance(c, bool) or not isinstance(c, numbers.Integral):
            raise TypeError(f"columns lists accepted widths (integers), not {type(c).__name__} {c!r}: to pick columns, use fields")
        if c < 1:
            raise ValueError(f"columns lists accepted widths, each at least 1, got {c}: to pick columns, use fields")


def _overflow_note(path: Path, line: int) -> str:
    """Where line ``line`` of ``path`` spells no inf or nan, its infinity is a number too large for a double
    (``1e400``): say so, with the line as written.  Read again on this error path only; O(file)."""
    text = text_of(path).replace("\r\n", "\n").replace("\r", "\n").split("\n")[line - 1]
    if re.search(r"inf|nan", text, re.IGNORECASE):
        return ""
    return f": a number beyond the largest double (about 1.8e308) in {quote(text.strip())}"


def compact_mesh(
    points: NDArray[Any], triangles: NDArray[Any]
) -> tuple[NDArray[np.float64], NDArray[np.intp], NDArray[np.intp]]:
    """The mesh on the points its triangles use: ``(used points, renumbered triangles, used)``. O(n + m).

    ``used`` holds the indices into ``points`` of the kept points, ascending (so
    their relative order is kept): ``points[used]`` are the new points and
    ``used[new_triangles]`` equals ``triangles``.
    """
    pts = np.asarray(points, dtype=np.float64)
    tri = np.asarray(triangles, dtype=np.intp).reshape(-1, 3)
    used: NDArray[np.intp] = np.unique(tri).astype(np.intp)
    renumber = np.full(pts.shape[0], -1, dtype=np.intp)
    renumber[used] = np.arange(used.size, dtype=np.intp)
    return pts[used], renumber[tri], used


def write_mesh(
    path: str | Path,
    points: NDArray[Any],
    triangles: NDArray[Any],
    *,
    npz_arrays: dict[str, Any] | None = None,
) -> Path:
    """Write the triangle mesh ``(points, triangles)`` to ``path`` by its extension.

    ``.npz`` stores ``npz_arrays`` (the caller names the arrays, e.g. ``points``,
    ``simplices`` and ``vertices`` for a hull); the other formats store the
    triangles and only the points they use (:func:`compact_mesh`: a viewer would
    show an unused point as a stray dot), through meshio; planar ``(n, 2)`` points get
    z = 0 there.  The directory must exist (the command line
    checks and creates it before computing: :mod:`persistri.impl.cli.checks`).
    Raises :class:`ValueError` (naming the file) for an unknown extension, and
    :class:`TypeError` / :class:`ValueError` for points that are not ``(n, 2)``
    or ``(n, 3)`` reals, or triangles that are not ``(m, 3)`` integer indices
    into them (a negative index would wrap around to another point), before
    anything is written.  O(n + m).
    """
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in MESH_FORMATS:
        raise ValueError(f"{p}: unknown mesh format {suffix!r}; use one of {', '.join(MESH_FORMATS)}")
    pts, tris = _mesh_arrays(points, triangles)
    if suffix == ".npz":
        arrays = npz_arrays if npz_arrays is not None else {"points": points, "triangles": triangles}
        np.savez(p, **arrays)
        return p
    import meshio

    if pts.shape[1] == 2:
        pts = np.column_stack([pts, np.zeros(pts.shape[0])])
    used_points, renumbered, _ = compact_mesh(pts, tris)
    tri = renumbered.astype(np.int64)
    if tri.size == 0 or int(tri.max()) < 2**31:
        tri = tri.astype(np.int32)  # PLY has no 64-bit integers: meshio would warn and cast anyway
    cell_data = {"facet_normals": [unit_normals(used_points, tri)]} if suffix == ".stl" else None
    meshio.write(p, meshio.Mesh(used_points, [("triangle", tri)], cell_data=cell_data))
    return p


def _mesh_arrays(points: object, triangles: object) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    """``(points, triangles)`` of :func:`write_mesh` as float64 ``(n, 2 | 3)`` and intp ``(m, 3)`` arrays,
    each index in ``0 .. n - 1``; a :class:`TypeError` or :class:`ValueError` naming what is wrong.  O(n + m)."""
    pts = np.asarray(points)
    if pts.dtype.kind not in "biuf":
        raise TypeError(f"mesh points must be real numbers, not {pts.dtype}")
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise ValueError(f"mesh points must be an (n, 2) or (n, 3) array, got shape {pts.shape}")
    tri = np.asarray(triangles)
    if tri.size == 0:
        tri = tri.reshape(0, 3).astype(np.intp)
    if tri.dtype.kind not in "iu":
        raise TypeError(f"triangles must be integer indices into the points, not {tri.dtype}")
    if tri.ndim != 2 or tri.shape[1] != 3:
        raise ValueError(f"triangles must be an (m, 3) array of point indices, got shape {tri.shape}")
    bad = (tri < 0) | (tri >= pts.shape[0])
    if bad.any():
        row = int(np.argmax(bad.any(axis=1)))
        raise ValueError(f"triangle {row} {tri[row].tolist()}: a point index is outside 0..{pts.shape[0] - 1}")
    return pts.astype(np.float64), tri.astype(np.intp)


def unit_normals(points: NDArray[np.float64], triangles: NDArray[Any]) -> NDArray[np.float64]:
    """The unit normal of each triangle (right-hand rule), for every finite input. O(m).

    Each triangle is first scaled by a power of two (exact) so that its largest
    coordinate is about 1, and its edge vectors again so that the longer is: the
    cross product then neither overflows (coordinates near ±1e308) nor underflows
    (subnormal ones), where meshio's own formula would warn and write NaN.  A
    triangle whose cross product still rounds to zero gets the zero vector.
    """
    corners = np.asarray(points, dtype=np.float64)[np.asarray(triangles, dtype=np.intp).reshape(-1, 3)]
    if corners.size == 0:
        return np.zeros((0, 3))

    def normalised(v: NDArray[np.float64]) -> NDArray[np.float64]:
        largest = np.max(np.abs(v.reshape(v.shape[0], -1)), axis=1)
        exponent = np.frexp(largest)[1]
        scaled: NDArray[np.float64] = np.ldexp(v, -exponent.reshape((-1,) + (1,) * (v.ndim - 1)))
        return scaled

    a, b, c = np.moveaxis(normalised(corners), 1, 0)
    edges = normalised(np.stack([b - a, c - a], axis=1))
    n = np.cross(edges[:, 0], edges[:, 1])
    length = np.sqrt(np.einsum("ij,ij->i", n, n))
    out: NDArray[np.float64] = np.divide(n, length[:, None], out=np.zeros_like(n), where=length[:, None] > 0)
    return out
