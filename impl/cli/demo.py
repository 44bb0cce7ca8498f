"""Placeholder for `persistri demo` (being written)."""

from __future__ import annotations

import click


@click.group()
def demo() -> None:
    """Not yet available."""
