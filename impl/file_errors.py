"""The one error of persistri's file readers: :class:`InputFileError`, one line naming the file (and the line).

Shared by the point readers (:mod:`persistri.impl.files`), the text tables
(:mod:`persistri.impl.text_tables`) and the grid readers.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

__all__ = ["InputFileError", "quote", "widths", "os_error"]

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
