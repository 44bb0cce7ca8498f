"""The one error of persistri's file readers: :class:`InputFileError`, one line naming the file (and the line).

Shared by the point readers (:mod:`persistri.impl.files`), the text tables
(:mod:`persistri.impl.text_tables`) and the grid readers.
"""

from __future__ import annotations

import stat
import zipfile
from collections.abc import Sequence
from pathlib import Path

__all__ = ["InputFileError", "foreign_format", "quote", "shown", "widths", "os_error", "special_file"]

_SHOWN = 40  # characters of a bad line or field quoted in a message


class InputFileError(ValueError):
    """A file that cannot be used as input; ``str()`` is one line, ``"<path>: <what is wrong>"``.

    ``path`` is the file as the caller named it; ``line`` the 1-based line of a
    text file the problem is on, when there is one.
    """

    def __init__(self, path: str | Path, message: str, *, line: int | None = None) -> None:
        where = f"{path}: line {line}: " if line is not None else f"{path}: "
        super().__init__(where + message)
        self.path = str(path)
        self.line = line


def quote(text: str) -> str:
    """``text`` stripped, in double quotes, cut to 40 characters with an ellipsis."""
    text = text.strip()
    return '"' + (text if len(text) <= _SHOWN else text[: _SHOWN - 1] + "…") + '"'


def shown(text: str) -> str:
    """``repr(text)``, its text cut to 40 characters with an ellipsis: a bad token as a message may echo it.

    A field of a file can be megabytes long (a line without its newlines); a message
    quotes at most its first 39 characters and "…", so it stays one readable line.
    """
    return repr(text if len(text) <= _SHOWN else text[: _SHOWN - 1] + "…")


def widths(columns: Sequence[int]) -> str:
    """``(3,)`` → ``"3"``, ``(2, 3)`` → ``"2 or 3"``."""
    names = [str(c) for c in columns]
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " or " + names[-1]


def os_error(p: Path, exc: OSError) -> InputFileError:
    """The one-line error for a file the system would not let us read."""
    if isinstance(exc, FileNotFoundError):
        return InputFileError(p, "no such file")
    if isinstance(exc, IsADirectoryError):
        return InputFileError(p, "a directory, not a file")
    if isinstance(exc, PermissionError):
        return InputFileError(p, "cannot read it (permission denied)")
    return InputFileError(p, f"cannot read it ({exc.strerror or exc})")


_FOREIGN: dict[str, str] = {
    ".las": "a LAS point cloud: convert it, e.g. `pdal translate cloud.las cloud.ply`, or save laspy's x, y, z with np.save",
    ".laz": "a compressed LAS point cloud: convert it, e.g. `pdal translate cloud.laz cloud.ply`",
    ".xlsx": "a spreadsheet: save the sheet as CSV",
    ".xls": "a spreadsheet: save the sheet as CSV",
    ".ods": "a spreadsheet: save the sheet as CSV",
    ".node": "a Triangle .node file: `persistri mesh FILE --min-angle 0` triangulates its vertices",
    ".poly": "a Triangle .poly file: `persistri mesh FILE` meshes it",
    ".zip": "a zip archive: extract the file first",
    ".gz": "gzip is decompressed only around text, .csv.gz, .xyz.gz, .txt.gz: decompress this file first",
    ".bz2": "bzip2-compressed: decompress it first",
    ".xz": "xz-compressed: decompress it first",
    ".hgt": "an SRTM tile: convert it to GeoTIFF first, e.g. `gdal_translate N45E006.hgt dem.tif`",
    ".jpg": "a JPEG, whose lossy compression changes heights: use a 16-bit grayscale PNG or a GeoTIFF",
    ".jpeg": "a JPEG, whose lossy compression changes heights: use a 16-bit grayscale PNG or a GeoTIFF",
}


def foreign_format(path: str | Path, reads: Sequence[str] = (".npy",)) -> str:
    """What to do with ``path`` whose extension persistri does not read, when it is a well-known format; else "".

    Appended to the "unknown format" messages of the readers and of the command line: ``"; a LAS point
    cloud: convert it, ..."``.  ``reads``: the extensions the reader takes; a ``.npz`` is advised to be saved
    as a ``.npy`` only where ``.npy`` is among them.  O(1) (a ``.npz``: O(its arrays), their names read).
    """
    if Path(path).suffix.lower() == ".npz" and ".npy" in reads:
        return f"; {_npz_advice(Path(path))}"
    advice = _FOREIGN.get(Path(path).suffix.lower())
    return f"; {advice}" if advice else ""


def _npz_advice(path: Path) -> str:
    """What to do with a NumPy archive where one array is read: save that array alone, named by the archive's first.

    Reads the zip's directory only (never an array); a file that is no zip gets the advice without names.
    """
    try:
        with zipfile.ZipFile(path) as archive:
            names = [n.removesuffix(".npy") for n in archive.namelist()]
    except (OSError, zipfile.BadZipFile):
        names = []
    if not names:
        return "a NumPy archive: save the array to read alone with np.save (a .npy)"
    listed = ", ".join(n if len(n) <= 40 else n[:39] + "…" for n in names[:6]) + (", …" if len(names) > 6 else "")
    first = names[0] if len(names[0]) <= 40 else "NAME"
    noun = "array" if len(names) == 1 else "arrays"
    return (f"a NumPy archive (its {noun} {listed}): save the array to read alone, "
            f"e.g. np.save({first + '.npy'!r}, np.load({path.name!r})[{first!r}])")


def special_file(path: Path) -> str | None:
    """What ``path`` is when it exists and is neither a regular file nor a directory — a pipe (a FIFO,
    ``/dev/stdin`` fed by a pipe), a socket, a device — as the end of a one-line error; None otherwise.

    persistri's readers open their input more than once (a header checked before the data is read, a line
    read again to name an error): a pipe would be emptied by the first reading and block the next for
    ever, so such inputs are refused before anything opens them.  One ``stat``, which never blocks. O(1).
    """
    try:
        mode = path.stat().st_mode
    except (OSError, ValueError):  # missing, a broken link, an unreadable directory: the callers' own errors
        return None
    if stat.S_ISREG(mode) or stat.S_ISDIR(mode):
        return None
    what = (
        "a pipe (FIFO)" if stat.S_ISFIFO(mode) else "a socket" if stat.S_ISSOCK(mode)
        else "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else "not a regular file"
    )
    return (
        f"{what}, not a regular file: persistri reads its input more than once, which a pipe cannot give; "
        "save the data to a file and name that"
    )
