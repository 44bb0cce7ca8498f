"""Placeholder for `persistri conformance` (being written)."""

from __future__ import annotations

import click


@click.group()
def conformance() -> None:
    """Not yet available."""
