"""Rows of numbers from text files: delimiters, header lines, comments, and the choice of columns.

The text rules of persistri's point and grid files (:mod:`persistri.impl.files`):
numbers separated by commas, semicolons, tabs or spaces (the delimiter is the
first of ``;`` ``,`` tab found on the first data line, else whitespace — also for
columns aligned with spaces and tabs mixed; a delimiter that ends every row,
``1,2,3,``, is dropped; a number with a decimal comma, ``0,5``, is named as
such, never read nor skipped), any
number of leading header lines (lines whose first — or first chosen — field is
not a number, e.g. ``x,y,z``), ``#`` comments (whole lines or after the numbers),
blank lines, Windows line ends, a UTF-8 byte-order mark (or UTF-16 text with its
byte-order mark; a gzip-compressed file is decompressed first) and fields in double
quotes (``"1","2","3"`` or ``"1", "2", "3"``, as spreadsheets export them), read by
:func:`numpy.loadtxt`.  Columns are chosen by number or by the header's names
(:data:`Fields`); without a choice a header naming ``x`` and ``y`` (and ``z``)
among other columns picks those (:data:`XY_NAMES`).  A bad row is found by
halving (:func:`_first_bad`) and reported with its line number in the file.
"""

from __future__ import annotations

import gzip
import re
import zlib
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from persistri.impl.file_errors import InputFileError, os_error, quote, widths

__all__ = ["Fields", "XY_NAMES", "read_text", "read_text_table", "text_of"]


def _decode(path: Path, raw: bytes) -> str:
    """The text of a point file: UTF-8, or UTF-16 after its byte-order mark (as Windows PowerShell writes
    files), a gzip stream decompressed first; binary files are refused by name."""
    if raw[:2] == b"\x1f\x8b":  # gzip's magic number: points.xyz.gz
        try:
            raw = gzip.decompress(raw)
        except (OSError, EOFError, zlib.error) as exc:
            raise InputFileError(path, f"a damaged gzip file ({str(exc) or type(exc).__name__})") from None
    if raw[:2] in (b"\xff\xfe", b"\xfe\xff"):
        try:
            return raw.decode("utf-16")
        except UnicodeDecodeError as exc:
            raise InputFileError(path, f"not UTF-16 text after its byte-order mark (at offset {exc.start})") from None
    nul = raw.find(b"\x00")
    if nul >= 0:
        raise InputFileError(path, f"a binary file, not text (a NUL byte at offset {nul})")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw.count(b"\n", 0, exc.start) + 1
        raise InputFileError(
            path,
            f"not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start}, line {line}; Latin-1 or "
            "Windows-1252, as older spreadsheets save?): save it as UTF-8",
        ) from None


def text_of(path: Path) -> str:
    """The text of the file ``path`` by the rules of :func:`_decode` (UTF-8 or UTF-16 with its mark, gzip). O(size)."""
    return _decode(path, path.read_bytes())


_DECIMAL_COMMA = re.compile(r"\s*[+-]?\d*,\d+\s*")
"""A number written with a decimal comma (``0,5``, ``-12,25``): not read, but named as what it is."""


def _delimiter(line: str) -> str | None:
    """The field separator of a data line: the first of semicolon, comma, tab it holds; None = whitespace.

    A semicolon first: a file separated by semicolons is one whose numbers may hold commas (decimal commas,
    ``0,5;1;2``, as spreadsheets write them where the comma is the decimal sign), which are then named as such.
    """
    data = line.split("#", 1)[0]  # a comment after the numbers may hold any of them
    found = next((d for d in (";", ",", "\t") if d in data), None)
    if found == "\t" and any(len(field.split()) > 1 for field in data.split("\t")):
        return None  # columns aligned with spaces and tabs mixed ("1.5   2.5\t 3"): whitespace separates them
    return found


def _normalised(lines: list[str], delimiter: str | None, quoted: bool) -> list[str]:
    """Data lines as :func:`numpy.loadtxt` reads them: blanks before a quoted field dropped (``"1", "2"``), and
    a delimiter that ends every line (``1,2,3,``, as some exporters write rows) removed.

    ``quoted`` — whether the file holds a double quote at all.  O(total length) where a rule applies; a
    file of plain rows is returned as it is after a look at its first line.
    """
    if delimiter is None:
        return lines
    out = [re.sub(rf'(^|{re.escape(delimiter)})\s+"', r'\1"', line) for line in lines] if quoted else lines
    if out and out[0].split("#", 1)[0].rstrip().endswith(delimiter):
        bodies = [line.split("#", 1)[0].rstrip() for line in out]
        if all(body.endswith(delimiter) for body in bodies):
            out = [body[: -len(delimiter)] for body in bodies]
    return out


def _loadtxt(lines: Sequence[str], delimiter: str | None, usecols: Sequence[int] | None = None) -> NDArray[np.float64]:
    arr: NDArray[np.float64] = np.loadtxt(
        lines, delimiter=delimiter, comments="#", ndmin=2, dtype=np.float64, usecols=usecols, quotechar='"'
    )
    return arr


def _is_header(line: str, usecols: Sequence[int] | None = None) -> bool:
    """A header line: its first field is not a number (``x,y,z``; ``survey 2024``), as numpy's type detection sees it.

    A line that starts with a number is data, to be reported if it is bad
    (``1,2,x`` is not silently skipped as a header; ``nan,0,0`` is data too).
    With ``usecols`` the first *selected* field decides (a date in an unused
    first column does not make every line a header).
    """
    # Quotes are dropped first: a spreadsheet's "1","2","3" is data, its "x","y","z" a header.
    bare = line.replace('"', "")
    fields = np.genfromtxt([bare], delimiter=_delimiter(bare), comments="#", dtype=None, encoding="utf-8")
    names = fields.dtype.names
    # One dtype for every field when they agree (a plain array), else a record of one per field.
    kinds = [fields.dtype[k].kind for k in range(len(names))] if names else [fields.dtype.kind] * max(fields.size, 1)
    at = 0 if usecols is None else usecols[0]
    if at < len(kinds) and kinds[at] in "US":
        # a number with a decimal comma (0,5 in a file separated by semicolons) is data, to be named as bad
        parts = bare.split(_delimiter(bare))
        return not (at < len(parts) and _DECIMAL_COMMA.fullmatch(parts[at]) is not None)
    return False


def _names(line: str, delimiter: str | None) -> list[str]:
    """The fields of a header line, stripped of blanks and quotes, lower-cased (``"X", y`` → ``["x", "y"]``)."""
    return [f.strip().strip("\"'").strip().lower() for f in line.split(delimiter)]


def _what_is_wrong(line: str, delimiter: str | None, width: int, usecols: Sequence[int] | None = None) -> str:
    """Why one data line is not a row of ``width`` numbers (the line alone, parsed again)."""
    try:
        alone = _loadtxt([line], delimiter, usecols)
    except ValueError as exc:
        tokens = line.split("#", 1)[0].split()
        if delimiter == "," and len(tokens) > 1 and all(_DECIMAL_COMMA.fullmatch(t) for t in tokens):
            # "0,5<TAB>1,5": decimal commas between tabs or spaces, which the comma's role as delimiter splits apart
            return f"numbers with decimal commas ({quote(tokens[0])}) separated by tabs or spaces: persistri reads decimal points, 0.5"
        field = re.search(r"could not convert string '(.*)' to", str(exc))
        if field is None:
            if usecols is not None and "invalid column index" in str(exc):
                return f"no column {max(usecols)}: the line has {len(line.split(delimiter))} fields (numbered from 0)"
            return f"not a row of numbers: {quote(line)}"
        if not field.group(1).strip():
            return f"an empty field: {quote(line)}"
        if _DECIMAL_COMMA.fullmatch(field.group(1)):
            return f"{quote(field.group(1))} is not a number (a decimal comma: persistri reads decimal points, 0.5)"
        return f"{quote(field.group(1))} is not a number"
    return f"expected {width} numbers, got {alone.shape[1]}"


def _first_bad(lines: Sequence[str], delimiter: str | None, width: int, usecols: Sequence[int] | None = None) -> int:
    """The index of the first line that is not a row of ``width`` numbers (one exists).

    Halves the range that holds it, parsing the first half alone each time:
    O(total length) over all the steps, and only on the error path.
    """

    def good(chunk: Sequence[str]) -> bool:
        try:
            return bool(_loadtxt(chunk, delimiter, usecols).shape[1] == width)
        except ValueError:
            return False

    lo, hi = 0, len(lines)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if good(lines[lo:mid]):
            lo = mid
        else:
            hi = mid
    return lo


Fields = Sequence[str | int]
"""A selection of columns of a text file: 0-based numbers or names from its header line (any case)."""

XY_NAMES = ("x", "y", "z")
"""Header names that select columns by default (``id,x,y`` reads ``x, y``; ``x,y,z,intensity`` reads ``x, y, z``)."""


def _header_line(lines: Sequence[str], content: Sequence[int], delimiter: str | None, names: Sequence[str]) -> int | None:
    """The index in ``content`` of the first line (of the first 100) whose fields include every one of ``names``."""
    for k, i in enumerate(content[:100]):
        if set(names) <= set(_names(lines[i], delimiter)):
            return k
    return None


def _named_xyz(lines: Sequence[str], content: Sequence[int]) -> list[str | int] | None:
    """The columns a header line naming ``x`` and ``y`` picks (:data:`XY_NAMES`), or None to read every column.

    Only a header with as many fields as the last line of the file (a data
    line) describes the columns; one that names exactly the columns in order
    (``x,y,z``) needs no choice. O(header lines).
    """
    delimiter = _delimiter(lines[content[-1]])
    k = _header_line(lines, content, delimiter, ("x", "y"))
    if k is None:
        return None
    header = _names(lines[content[k]], delimiter)
    named = [header.index(n) for n in XY_NAMES if n in header]
    if len(lines[content[-1]].split(delimiter)) != len(header) or named == list(range(len(header))):
        return None
    return [n for n in XY_NAMES if n in header]


def _select(
    path: Path, lines: Sequence[str], content: Sequence[int], delimiter: str | None, fields: Fields
) -> tuple[list[int], int]:
    """The 0-based columns ``fields`` names and how many leading content lines the header takes (0 without names)."""
    named = [f.strip().lower() for f in fields if isinstance(f, str)]
    at = 0
    if named:
        k = _header_line(lines, content, delimiter, named)
        if k is None:
            # The header meant is the first line naming any of them, else the first line.
            k = next((j for j, i in enumerate(content[:100]) if set(named) & set(_names(lines[i], delimiter))), 0)
            if not _is_header(lines[content[k]]):
                raise InputFileError(path, "has no header line to name columns by (its first line is data): choose them by number (from 0)")
            header = _names(lines[content[k]], delimiter)
            missing = [f for f in fields if isinstance(f, str) and f.strip().lower() not in header]
            listed = ", ".join(repr(f) for f in missing)
            shown = quote(", ".join(header))[1:-1]
            raise InputFileError(path, f"no column{'s' if len(missing) > 1 else ''} {listed} in the header ({shown})")
        header = _names(lines[content[k]], delimiter)
        at = k + 1
    usecols: list[int] = []
    for f in fields:
        if isinstance(f, str):
            usecols.append(header.index(f.strip().lower()))
        elif f < 0:
            raise InputFileError(path, f"column numbers count from 0, got {f}")
        else:
            usecols.append(f)
    if len(set(usecols)) != len(usecols):
        raise InputFileError(path, f"a column is selected twice: {', '.join(str(f) for f in fields)}")
    return usecols, at


def _named_rows(lines: list[str], content: list[int]) -> str:
    """Why a file whose every line starts with text holds no points, when its rows are names then numbers
    (``name,lon,lat,elev`` / ``p1,5.1,40.2,12``): the header names the columns to choose; else "". O(1) lines."""
    if len(content) < 2:
        return ""
    row = lines[content[1]].replace('"', "")
    delimiter = _delimiter(row)
    named = _names(lines[content[0]], delimiter)
    fields = [f.strip() for f in row.split(delimiter)]
    numeric = 0
    for f in fields[1:]:
        try:
            float(f)
            numeric += 1
        except ValueError:
            pass
    if re.fullmatch(r"[+-]?\d{1,3}(,\d{3})+(\.\d*)?", fields[0]):
        return f"{quote(fields[0])} is not a number (a thousands separator? persistri reads {fields[0].replace(',', '')})"
    if len(named) < 2 or numeric < 2:
        return ""
    return (
        f"{quote(fields[0])} is not a number, nor is the first field of any line; choose the columns by the "
        f"header's names ({quote(', '.join(named))[1:-1]}): --columns, or fields= in Python"
    )


def read_text(
    path: Path, columns: Sequence[int] | None, what: str = "points", fields: Fields | None = None
) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    """The rows of a text file of numbers and, for each, its 1-based line number in the file (``what`` names its content).

    ``fields`` selects columns (:data:`Fields`); without it a last header line
    that names ``x`` and ``y`` (and maybe ``z``) among other columns selects
    those (:data:`XY_NAMES`), else every column is read.
    """
    text = text_of(path)
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    content = [i for i, ln in enumerate(lines) if ln.strip() and not ln.lstrip().startswith("#")]
    if not content:
        raise InputFileError(path, f"no {what}: the file is empty" if not text.strip() else f"no {what}: only comments")
    usecols: list[int] | None = None
    headers = 0
    if fields is None:
        fields = _named_xyz(lines, content)
    if fields is not None:
        usecols, headers = _select(path, lines, content, _delimiter(lines[content[-1]]), fields)
    while headers < len(content) and _is_header(lines[content[headers]], usecols):
        headers += 1
    if headers == len(content):
        if usecols is not None:
            raise InputFileError(path, f"no {what}: column {usecols[0]} holds no number on any line")
        shown = "a header line" if headers == 1 else f"{headers} lines of text"
        opening = lines[content[0]].strip()
        named_rows = _named_rows(lines, content)
        if named_rows:
            raise InputFileError(path, named_rows, line=content[1] + 1)
        raise InputFileError(
            path,
            f"no {what}: {shown} and no row of numbers separated by commas, semicolons, tabs or spaces "
            f"(line {content[0] + 1}: {quote(opening)})",
        )
    numbers = content[headers:]
    delimiter = _delimiter(lines[numbers[0]])
    data = _normalised([lines[i] for i in numbers], delimiter, '"' in text)
    first = numbers[0] + 1
    # Every column is read: where a header names them, say how to choose (survey.csv: id, date, east, north, height).
    hint = ""
    named = _names(lines[content[headers - 1]], delimiter) if usecols is None and headers else []
    if len(named) > max(columns or (3,)):  # more columns than a point has: some are to be left out
        hint = f"; choose the columns by the header's names ({quote(', '.join(named))[1:-1]}): --columns, or fields= in Python"
    try:
        width = _loadtxt(data[:1], delimiter, usecols).shape[1]
    except ValueError:
        why = _what_is_wrong(data[0], delimiter, 0, usecols)
        raise InputFileError(path, why + (hint if why.endswith("is not a number") else ""), line=first) from None
    if columns is not None and width not in columns:
        raise InputFileError(path, f"expected {widths(columns)} numbers, got {width}{hint}", line=first)
    try:
        arr = _loadtxt(data, delimiter, usecols)
    except ValueError:
        bad = _first_bad(data, delimiter, width, usecols)
        raise InputFileError(path, _what_is_wrong(data[bad], delimiter, width, usecols), line=numbers[bad] + 1) from None
    line_numbers: NDArray[np.intp] = np.asarray(numbers, dtype=np.intp) + 1
    return arr, line_numbers


def read_text_table(path: str | Path, what: str) -> NDArray[np.float64]:
    """The rows of numbers of a text file, all of one width (``what`` names the content in messages).

    The same text rules as the point files (delimiters, headers, comments, line
    ends; module docstring).  NaN and infinities are returned as read: the
    caller decides what they mean.  Raises :class:`InputFileError` naming the
    file, and the line, for an unreadable or empty file, a bad field or a
    ragged row.  O(size).
    """
    p = Path(path)
    try:
        return read_text(p, None, what)[0]
    except OSError as exc:
        raise os_error(p, exc) from None
