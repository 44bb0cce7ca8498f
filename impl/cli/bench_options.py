"""Options and progress display shared by the ``persistri bench`` sub-commands.

:func:`parse_sizes` reads the size lists every benchmark takes (``--sizes
1000,1e5``); :func:`progress_bar` draws the transient bar a benchmark feeds
while it measures.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from contextlib import contextmanager

import click
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

from persistri.impl.bench.maps import ProgressCallback

__all__ = ["parse_sizes", "progress_bar", "sizes_option"]


_COUNTED: dict[tuple[str, str], str] = {
    ("complex", "sizes"): "triangle count",
    ("hull", "sizes"): "point count",
    ("delaunay", "sizes"): "point count",
    ("terrain", "sizes"): "vertex count",
    ("scale", "worker_counts"): "worker count",
}
"""What each sub-command's list counts, for the message naming a bad item (default: key count, as in ``bench maps``)."""


def parse_sizes(text: str, what: str = "key count") -> tuple[int, ...]:
    """``"1000,100_000,1e6"`` → ``(1000, 100000, 1000000)``: positive integers separated by commas.

    Raises :class:`click.BadParameter` naming the bad item and ``what`` the
    integers count (``'x' is not a point count``).
    """
    sizes: list[int] = []
    for item in text.split(","):
        item = item.strip()
        try:
            value = float(item) if "e" in item.lower() else int(item)
        except ValueError:
            raise click.BadParameter(f"{item!r} is not a {what} (give integers separated by commas)") from None
        if not math.isfinite(value) or value != int(value) or int(value) < 1:  # 1e400 is inf: no integer
            raise click.BadParameter(f"{item!r} is not a positive integer")
        sizes.append(int(value))
    return tuple(sizes)


def sizes_option(ctx: click.Context, param: click.Parameter, value: str) -> tuple[int, ...]:
    """A click callback: the option's text through :func:`parse_sizes`, the message in the command's words."""
    return parse_sizes(value, _COUNTED.get((ctx.info_name or "", param.name or ""), "key count"))


@contextmanager
def progress_bar(console: Console, title: str) -> Iterator[ProgressCallback]:
    """A rich progress bar on ``console`` for the duration of the block, fed by the callback it yields.

    The bar is transient (erased when done) and drawn only when ``console`` is
    a terminal (off one, rich would leave a blank line).
    """
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
    with Progress(*columns, console=console, transient=True, disable=not console.is_terminal) as progress:
        task = progress.add_task(title, total=None)

        def update(done: int, total: int, what: str) -> None:
            progress.update(task, completed=done, total=total, description=f"{title}: {what}")

        yield update
