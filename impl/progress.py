"""The progress bar of long algorithms (``progress=True``): rich, on stderr, erased when done."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["ProgressBar", "progress_callback"]


class ProgressBar:
    """A transient rich progress bar titled ``title``, advanced in batches of ``batch`` steps."""

    def __init__(self, title: str, total: int | None, *, batch: int = 256) -> None:
        from rich.console import Console
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

        console = Console(stderr=True)
        # Off a terminal rich draws nothing but a blank line when the bar ends: draw nothing at all.
        self._p = Progress(
            TextColumn(title),
            BarColumn(),
            MofNCompleteColumn(),
            TimeElapsedColumn(),
            transient=True,
            console=console,
            disable=not console.is_terminal,
        )
        self._task = self._p.add_task(title, total=total)
        self._p.start()
        self._batch = batch
        self._pending = 0

    def __call__(self, k: int) -> None:
        self._pending += k
        if self._pending >= self._batch:
            self._p.advance(self._task, self._pending)
            self._pending = 0

    def close(self) -> None:
        self._p.advance(self._task, self._pending)
        self._p.stop()


def progress_callback(
    progress: bool | Callable[[int], Any] | None, title: str, total: int | None, *, batch: int = 256
) -> Any:
    """``progress`` as a callable taking a step count: a :class:`ProgressBar` for True, None for False.

    A NumPy boolean counts as a bool; anything else that is not callable is a :class:`TypeError`
    naming its type (qualified by its module outside the builtins, so ``numpy.bool`` is not "bool")."""
    value: object = progress
    if type(value).__module__ == "numpy" and type(value).__name__ in ("bool", "bool_"):
        value = bool(value)
    if value is True:
        return ProgressBar(title, total, batch=batch)
    if value is False or value is None:
        return None
    if callable(value):
        return value
    kind = type(value)
    name = kind.__name__ if kind.__module__ == "builtins" else f"{kind.__module__}.{kind.__qualname__}"
    raise TypeError(f"progress must be a bool or a callable, not {name}")
