"""The consoles every command prints through: rich on a terminal, unbroken plain lines in a pipe or a file.

rich asks a terminal for its width; when the stream is a pipe or a file it
assumes 80 columns and folds every longer line, and squeezes every wider table,
to fit them.  Output piped into ``less``, ``grep`` or a file then has its
tables truncated and its messages broken mid-path.  The consoles made here keep
rich's behaviour on a terminal; anywhere else

* lines are never folded (rich's *soft wrap*) and tables take their natural
  width, unless the ``COLUMNS`` environment variable asks for a width (tables
  then fit it; plain lines are still not folded);
* no colour or cursor codes are written (rich's own rule off a terminal, which
  also honours ``NO_COLOR``; ``FORCE_COLOR`` makes rich treat the stream as a terminal).

On a terminal and off it, rich's *markup* is off: text in square brackets is
printed as it is, so a file named ``survey[final].csv`` is not shown as
``survey.csv`` (nor ``a[/b]`` refused as bad markup) in a summary or a table title.

Every command makes its consoles with :func:`make_console` (or the two
shorthands) when it runs, so that the stream it checks is the one in use then.
"""

from __future__ import annotations

import os
from typing import Final, TextIO

from rich.console import Console

__all__ = ["UNBOUNDED_WIDTH", "MIN_WIDTH", "make_console", "stdout_console", "stderr_console", "text_console", "pipe_width"]

UNBOUNDED_WIDTH: Final = 10_000
"""The width a console off a terminal lays out in when ``COLUMNS`` is unset: wider than any table
persistri prints, so tables keep their natural width (a rich table does not pad itself to the console)."""


MIN_WIDTH: Final = 40
"""The narrowest width tables are laid out in: below it rich squeezes every column to nothing and a table shows
no values (``COLUMNS=5``); the table is then wider than the screen, and readable."""


def pipe_width() -> int:
    """The width for output that is not a terminal: ``COLUMNS`` when it is a positive integer (at least
    :data:`MIN_WIDTH`), else :data:`UNBOUNDED_WIDTH`."""
    columns = os.environ.get("COLUMNS", "").strip()
    return max(int(columns), MIN_WIDTH) if columns.isdigit() and int(columns) > 0 else UNBOUNDED_WIDTH


def make_console(*, stderr: bool = False) -> Console:
    """A rich console on stdout (or stderr): rich's defaults on a terminal; off one, unwrapped plain text (module docstring)."""
    console = Console(stderr=stderr, markup=False)
    if console.is_terminal:
        return console if console.width >= MIN_WIDTH else Console(stderr=stderr, markup=False, width=MIN_WIDTH)
    return Console(stderr=stderr, width=pipe_width(), soft_wrap=True, markup=False)


def stdout_console() -> Console:
    """:func:`make_console` on stdout: where results (tables, summaries) go."""
    return make_console()


def stderr_console() -> Console:
    """:func:`make_console` on stderr: where progress and notes go."""
    return make_console(stderr=True)


def text_console(file: TextIO, width: int | None = None) -> Console:
    """A console writing plain text (no colour or control codes) to ``file``, for reports saved as ``.txt``.

    ``width`` bounds the tables (default: unbounded, as in a pipe); lines are never folded.
    """
    return Console(
        file=file,
        width=UNBOUNDED_WIDTH if width is None else width,
        soft_wrap=True,
        markup=False,
        color_system=None,
        force_terminal=False,
        force_jupyter=False,
        force_interactive=False,
    )


def count_noun(n: int, noun: str) -> str:
    """``n`` and ``noun``, plural unless n is 1 (``1 triangle``, ``2 vertices``), for the lines people read."""
    plural = "vertices" if noun == "vertex" else noun + "s"
    return f"{n:,} {noun if n == 1 else plural}"
