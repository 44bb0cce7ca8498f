"""Placeholder for `persistri bench` (being written)."""

from __future__ import annotations

import click


@click.group()
def bench() -> None:
    """Not yet available."""
