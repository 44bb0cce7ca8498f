"""What a command checks before it computes: the files it reads and writes, and its backend.

Every check fails with one line naming the file or option
(:func:`persistri.impl.cli.errors.fail`); the outputs are then written all or
nothing (:meth:`Outputs.staged`).

Inputs (:func:`check_input`): the file exists (a broken symbolic link is named
as such), is not a directory, can be opened for reading, and has a known
extension.

Outputs (:class:`Outputs`): the extension is known, the path is not a directory
and is not given twice, its directory exists and can be written in (tried, by
creating and removing a file: permission bits do not tell the whole story on
every file system).  A missing *last* directory is created when the files are
written (``-o out/hull.ply`` makes ``out/`` when ``.`` exists); a deeper missing
path (``/no/such/dir/x.ply``) is an error, since it is more likely a typo than a
wish.  The files are written to hidden temporary files beside their targets and
renamed over them only once every one has been written: a failure leaves no
output file behind (and no half-written one in place of an older file).

O(1) each, apart from the writing.
"""

from __future__ import annotations

import errno
import os
import secrets
import tempfile
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Final

import click

from persistri.impl.cli.errors import error_line, fail

__all__ = ["FILE_OR_NAME", "FILE_PATH", "FileOrName", "FilePath", "PLOT_FORMATS", "check_backend", "check_column_count", "check_input", "check_output_dir", "parse_columns", "Outputs", "Staging"]

PLOT_FORMATS: Final = (".png", ".pdf", ".svg")
"""The formats ``--plot`` writes (matplotlib chooses by extension)."""


class FilePath(click.Path):
    """A file name option or argument, as a :class:`~pathlib.Path`; an empty name is refused.

    ``pathlib`` reads ``""`` as ``"."`` — the current directory — so ``-o ''``
    would be reported as "a directory" and an empty input would read the
    directory's files.  An empty (or blank) name is a mistake in the command
    line: click reports it as a bad option value, exit status 2.
    """

    def convert(
        self, value: str | os.PathLike[str], param: click.Parameter | None, ctx: click.Context | None
    ) -> str | bytes | os.PathLike[str]:
        """``value`` as a Path; fail on an empty or blank name."""
        if isinstance(value, str) and not value.strip():
            self.fail("an empty file name", param, ctx)
        return super().convert(value, param, ctx)


FILE_PATH: Final = FilePath(path_type=Path)
"""The type of every file option and argument of the commands."""


class FileOrName(click.types.StringParamType):
    """An input that is a file name or a word naming a built-in input (``jacksboro``, a gallery domain); an
    empty or blank one is refused as a bad argument, like an empty :class:`FilePath`."""

    name = "file or name"

    def convert(self, value: object, param: click.Parameter | None, ctx: click.Context | None) -> str:
        """``value`` as a string; fail on an empty or blank one."""
        text = super().convert(value, param, ctx)
        if not text.strip():
            self.fail("an empty file name", param, ctx)
        return text


FILE_OR_NAME: Final = FileOrName()
"""The type of the inputs that may also be a built-in name (``persistri terrain``, ``persistri mesh``)."""


def _extension(path: Path) -> str:
    """``path``'s extension for a message: the suffix, or what is missing."""
    return path.suffix.lower() or "(no extension)"


def _formats(formats: Sequence[str]) -> str:
    return ", ".join(formats)


def check_input(path: Path, formats: Sequence[str], *, kind: str, words: Sequence[str] = ()) -> None:
    """Fail unless ``path`` is a readable file with one of ``formats`` (``kind`` names them: "point", "grid").

    ``words`` are inputs that are not files (``jacksboro``); they pass.  ``-`` (standard input), a named pipe
    and ``/dev/stdin`` fed by a pipe are refused (:func:`~persistri.impl.file_errors.special_file`) before
    anything opens them: opening a pipe to test it would empty it.
    """
    if str(path).lower() in words:
        return
    if str(path) == "-" and not path.exists():
        fail(f"-: persistri does not read standard input; give the name of a {kind} file ({_formats(formats)})")
    from persistri.impl.file_errors import special_file

    special = special_file(path)
    if special is not None:
        fail(f"{path}: {special}")
    if path.is_symlink() and not path.exists():
        fail(f"{path}: a broken symbolic link (to {path.readlink()})")
    if not path.exists():
        fail(f"{path}: no such file")
    if path.is_dir():
        fail(f"{path}: a directory, not a file")
    suffix = path.suffix.lower()
    from persistri.impl.files import TEXT_FORMATS

    if suffix == ".gz" and Path(path.stem).suffix.lower() in set(formats) & set(TEXT_FORMATS):
        suffix = Path(path.stem).suffix.lower()  # points.xyz.gz: the text readers decompress it
    if suffix not in formats:
        also = f" or {', '.join(words)}" if words else ""
        from persistri.impl.file_errors import foreign_format

        fail(f"{path}: unknown {kind} format {_extension(path)}; use one of {_formats(formats)}{also}{foreign_format(path, formats)}")
    try:
        with path.open("rb"):
            pass
    except PermissionError:
        fail(f"{path}: cannot read it (permission denied)")
    except OSError as exc:
        fail(f"{path}: cannot read it ({exc.strerror or error_line(exc)})")


def parse_columns(ctx: click.Context, param: click.Parameter, value: str | None) -> list[str | int] | None:
    """``--columns``: comma-separated column numbers (from 0) or header names, in order (``2,3`` or ``lon,lat,h``).

    A click callback; a malformed list is a usage error naming the option. O(length).
    """
    if value is None:
        return None
    items = [item.strip() for item in value.split(",")]
    if not all(items):
        raise click.BadParameter(f"an empty column in {value!r}: give numbers (from 0) or header names, comma-separated")
    negative = [item for item in items if item.startswith("-") and item[1:].isdecimal()]
    if negative:
        raise click.BadParameter(f"column numbers count from 0, got {negative[0]}")
    return [int(item) if item.isdecimal() else item for item in items]


def check_column_count(columns: Sequence[str | int] | None, counts: Sequence[int], reads: str) -> None:
    """Fail with a usage error naming ``--columns`` unless it chooses one of ``counts`` columns (``reads``: "x,y,z")."""
    if columns is not None and len(columns) not in counts:
        want = " or ".join(str(c) for c in counts)
        shown = ",".join(str(c) for c in columns)
        raise click.BadParameter(f"{shown} names {len(columns)} columns; give {want} ({reads})", param_hint="--columns")


def check_backend(name: str, option: str = "--backend") -> None:
    """Fail unless the map backend ``name`` exists and loads (its optional package is installed);
    the line names ``option``, the option that gave it (``--backends`` for a list)."""
    from persistri.impl.maps import UnknownBackendError, backend

    try:
        backend(name)
    except UnknownBackendError as exc:
        fail(f"{option} {name}: {error_line(exc)}")


def check_output_dir(path: Path) -> None:
    """Fail unless ``path`` can be an output directory (``--out``): writable, or missing with an existing parent.

    The caller creates it when it writes (a missing parent is a typo, not a wish).
    """
    if path.exists() and not path.is_dir():
        fail(f"{path}: not a directory")
    if path.is_dir():
        _probe(path, path)
    elif path.parent.exists() and not path.parent.is_dir():
        fail(f"{path}: {path.parent} is not a directory")
    elif not path.parent.is_dir():
        fail(f"{path}: directory {path.parent} does not exist")
    else:
        _probe(path.parent, path)


def _probe(directory: Path, target: Path) -> None:
    """Fail unless a file can be created in ``directory`` (which exists)."""
    try:
        fd, name = tempfile.mkstemp(dir=directory, prefix=".persistri-probe-")
    except PermissionError:
        fail(f"{target}: cannot write in {directory} (permission denied)")
    except OSError as exc:
        fail(f"{target}: cannot write in {directory} ({exc.strerror or exc})")
    os.close(fd)
    os.unlink(name)


def _check_directory(directory: Path, target: Path) -> bool:
    """Fail unless files can be written in ``directory`` or it can be made (its parent exists); True if it must be made."""
    if directory.is_dir():
        _probe(directory, target)
        return False
    if directory.exists() or directory.is_symlink():
        fail(f"{target}: {directory} is not a directory")
    parent = directory.parent
    if not parent.is_dir():
        fail(f"{target}: directory {directory} does not exist")
    _probe(parent, target)
    return True


class Outputs:
    """The files (and directories) one command writes, checked as they are named, written at the end.

    ``outputs.file(path, formats, what="mesh")`` checks a file option (never one of
    the run's ``inputs``, which it would replace before or while they are read);
    ``with outputs.staged() as stage: write(stage(path))`` writes each file to
    a temporary path and, when the block ends without an exception, renames
    them all into place.  On an exception the temporary files (and directories
    made for them) are removed and the failure names the file being written.
    """

    def __init__(self, inputs: Sequence[Path | str | None] = ()) -> None:
        self._targets: set[Path] = set()
        self._make: set[Path] = set()
        # The input files of the run: an output that is one of them would replace what is being read
        # (`persistri hull cloud.ply -o cloud.ply` replaced the cloud by its hull).
        self._inputs = [Path(p) for p in inputs if p is not None and Path(p).is_file()]

    def file(self, path: Path | None, formats: Sequence[str], *, what: str) -> Path | None:
        """``path`` checked as an output of one of ``formats`` (``what`` names them: "mesh", "plot"); None passes."""
        if path is None:
            return None
        if path.is_dir():
            fail(f"{path}: a directory; give a file name")
        suffix = path.suffix.lower()
        if suffix not in formats:
            if path.name.lower() in formats:
                fail(f"{path}: a name that is only an extension; give a file name, such as mesh{path.name}")
            fail(f"{path}: unknown {what} format {_extension(path)}; use one of {_formats(formats)}")
        key = Path(os.path.abspath(path))
        if key in self._targets:
            fail(f"{path}: named as two outputs")
        if path.exists() and any(os.path.samefile(path, p) for p in self._inputs):
            fail(f"{path}: is an input of this run; name the output otherwise")
        if path.exists() and not os.access(path, os.W_OK):
            fail(f"{path}: exists and is read-only")
        if _check_directory(path.parent, path):
            self._make.add(path.parent)
        self._targets.add(key)
        return path

    @contextmanager
    def staged(self) -> Iterator[Staging]:
        """Yield a :class:`Staging`; rename its files into place when the block ends, or remove them on an exception."""
        staging = Staging(self._make)
        try:
            yield staging
            staging.commit()
        except BaseException as exc:
            staging.discard()
            current = staging.current
            if current is not None and isinstance(exc, Exception) and not isinstance(exc, click.ClickException):
                # An OSError would name the temporary file: say only why.
                reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else error_line(exc)
                fail(f"{current}: cannot write it ({reason})")
            raise


class Staging:
    """Temporary files standing for the outputs while they are written (:meth:`Outputs.staged`).

    ``staging(target)`` is the path to write ``target`` to: a hidden file in the
    same directory with the same extension (writers choose the format by it).
    A writer that puts companions beside it with the same stem (``mesh.ply``
    with a ``.prj``) gets them renamed too (``mesh.prj``).
    """

    def __init__(self, make: set[Path]) -> None:
        self._make = make
        self._made: list[Path] = []
        self._pending: list[tuple[Path, Path]] = []
        self.current: Path | None = None
        """The output being written (named by a failure)."""

    def __call__(self, target: Path) -> Path:
        directory = target.parent
        if directory in self._make and not directory.is_dir():
            directory.mkdir()
            self._made.append(directory)
        temp = directory / f".{target.stem}.partial-{secrets.token_hex(6)}{target.suffix}"
        self._pending.append((temp, target))
        self.current = target
        return temp

    def target(self, written: Path) -> Path:
        """The output a file a writer reports having written (a staged path or a companion of one) will become."""
        for temp, target in self._pending:
            if written.parent == temp.parent and written.stem == temp.stem:
                return target.with_suffix(written.suffix)
        return written

    def _files(self) -> list[tuple[Path, Path]]:
        """Each staged file and companion, with the output it becomes."""
        out = []
        for temp, target in self._pending:
            prefix = temp.stem + "."
            for name in sorted(os.listdir(temp.parent)):
                if name.startswith(prefix):
                    found = temp.parent / name
                    out.append((found, target.with_suffix(found.suffix)))
        return out

    def commit(self) -> None:
        files = self._files()
        # Every target first, so that one that cannot be replaced (made a directory or read-only since the
        # checks) leaves none of the others renamed into place: all or nothing.
        for _, target in files:
            self.current = target
            if target.is_dir():
                raise IsADirectoryError(errno.EISDIR, "it is a directory", str(target))
            if target.exists() and not os.access(target, os.W_OK):
                raise PermissionError(errno.EACCES, "it exists and is read-only", str(target))
        for temp, target in files:
            self.current = target
            os.replace(temp, target)
        self.current = None

    def discard(self) -> None:
        for temp, _ in self._files():
            temp.unlink(missing_ok=True)
        for directory in reversed(self._made):
            try:
                directory.rmdir()
            except OSError:  # someone else put a file there meanwhile: leave it
                pass
