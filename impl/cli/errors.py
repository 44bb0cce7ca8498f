"""The command line's error contract: every failure is one line on stderr and exit status 2.

The line is ``persistri: <file>: <what is wrong>`` (``persistri: points.csv:
line 7: expected 3 numbers, got 2``), or ``persistri: <what is wrong>`` when no
file is involved.  No traceback, no ``Aborted!``, no usage text: those are for
mistakes in the command line itself (an unknown option, a bad option value),
which click reports in its usual form, also with status 2.

One mechanism serves every command: :class:`PersistriGroup`, the class of the
``persistri`` group, turns any exception escaping a sub-command into a
:class:`CliError`, and :func:`about` names the input file in errors raised while
computing on it.  A bug in persistri itself is also one line (``internal
error: …``); ``PERSISTRI_DEBUG=1`` lets its traceback through.  A package that
cannot be imported (an incomplete installation) is named, with the ``pip install``
that brings it, not called a bug.

When the reader of the output goes away (``persistri … | head``) the command
stops quietly with status 1 (click's handling of a closed pipe), not with an
error line.

Commands with results that are not failures keep their documented statuses:
``persistri conformance`` exits 1 when a law fails and ``bench``/``demo`` exit 1
when a measured structure fails.
"""

from __future__ import annotations

import os
import zipfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Any, Final, NoReturn

import click

__all__ = ["EXIT_FAILURE", "CliError", "PersistriGroup", "about", "error_line", "fail", "one_line"]

EXIT_FAILURE: Final = 2
"""The exit status of every failure (bad input, unwritable output, failed check)."""

_DEBUG_VARIABLE: Final = "PERSISTRI_DEBUG"


class CliError(click.ClickException):
    """A failure the command line reports as the single line ``persistri: <message>``, exit status 2."""

    exit_code = EXIT_FAILURE

    def show(self, file: IO[Any] | None = None) -> None:
        """Print the one line on stderr (click's ``Error:`` prefix and usage text are not used); a control
        character in it (a file name may hold a newline) is printed escaped, so it stays one line."""
        click.echo(f"persistri: {one_line(self.format_message())}", err=True)


def one_line(text: str) -> str:
    """``text`` with each control character escaped (``\\n``, ``\\x1b``): a file name may hold a newline,
    and a summary or an error naming it must stay one line. O(len(text))."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def fail(message: str) -> NoReturn:
    """Stop the command with the one-line ``message`` (name the file first: ``f"{path}: …"``)."""
    raise CliError(message)


def error_line(exc: BaseException) -> str:
    """An exception as one readable line.

    An :class:`OSError` becomes ``<file>: <reason>`` (not ``[Errno 2] …: '<file>'``);
    a message of several lines keeps its first two, joined.
    """
    if isinstance(exc, OSError) and exc.strerror:
        reason = exc.strerror[0].lower() + exc.strerror[1:]
        return f"{exc.filename}: {reason}" if exc.filename is not None else reason
    lines = [ln.strip() for ln in str(exc).strip().splitlines() if ln.strip()]
    if not lines:
        return type(exc).__name__
    return lines[0] if len(lines) == 1 else f"{lines[0]} {lines[1]}"


def _data_errors() -> tuple[type[BaseException], ...]:
    """What bad input or a failed check raises (the other exceptions are bugs)."""
    from persistri.impl.experiments.dems import DemUnavailableError
    from persistri.impl.hull.errors import BulldozerCheckError
    from persistri.impl.hull.verify import HullVerificationError
    from persistri.impl.terrain.check import TerrainCheckError
    from persistri.impl.terrain.delaunay import TriangulationCheckError

    return (
        ValueError,
        TypeError,
        OSError,
        EOFError,  # click would print "Aborted!" for it
        zipfile.BadZipFile,  # a damaged .npz
        DemUnavailableError,
        BulldozerCheckError,
        HullVerificationError,
        TerrainCheckError,
        TriangulationCheckError,
    )


def _missing_package(exc: Exception) -> str | None:
    """The top-level name of the package ``exc`` found missing, when it is not persistri's own (a module of
    persistri that cannot be imported is a bug; a package that cannot is an incomplete installation)."""
    if isinstance(exc, ModuleNotFoundError) and exc.name:
        top = exc.name.split(".")[0]
        if top != "persistri":
            return top
    return None


def _as_cli_error(exc: Exception) -> CliError:
    if isinstance(exc, _data_errors()):
        return CliError(error_line(exc))
    package = _missing_package(exc)
    if package is not None:
        return CliError(
            f"{package} is not installed, and this command needs it ({error_line(exc)}): pip install {package} "
            f"(pip install 'persistri[dev]' installs every peer)"
        )
    return CliError(
        f"internal error: {type(exc).__name__}: {error_line(exc)} "
        f"(a bug in persistri; {_DEBUG_VARIABLE}=1 shows the traceback)"
    )


@contextmanager
def about(name: str | Path | None) -> Iterator[None]:
    """Errors raised inside the block name the file ``name``: ``<name>: <message>``.

    For the computation on an input (``no 3D convex hull: all points are
    coplanar`` becomes ``points.csv: no 3D convex hull: …``); a message that
    already names the file is kept as it is.  ``None`` (a generated input)
    adds nothing.
    """
    try:
        yield
    except (click.ClickException, click.exceptions.Exit, click.Abort, BrokenPipeError):
        raise
    except Exception as exc:
        if os.environ.get(_DEBUG_VARIABLE):
            raise
        message = _as_cli_error(exc).message
        if name is not None and str(name) not in message and not message.startswith("internal error") and _missing_package(exc) is None:
            message = f"{name}: {message}"
        raise CliError(message) from None


class PersistriGroup(click.Group):
    """A click group whose sub-commands (and their sub-groups) fail with one line and status 2."""

    def invoke(self, ctx: click.Context) -> Any:
        """Run the sub-command; an exception escaping it becomes a :class:`CliError`."""
        try:
            return super().invoke(ctx)
        except (click.ClickException, click.exceptions.Exit, click.Abort, BrokenPipeError):
            # A closed pipe (``persistri … | head``) is not a failure to report: click's own handler
            # silences the rest of the output and exits with status 1, as other tools do.
            raise
        except Exception as exc:
            if os.environ.get(_DEBUG_VARIABLE):
                raise
            raise _as_cli_error(exc) from None
