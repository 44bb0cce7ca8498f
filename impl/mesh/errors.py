"""The exceptions of quality meshing: what is wrong with a domain, said in one line."""

from __future__ import annotations

__all__ = ["DomainError"]


class DomainError(ValueError):
    """A PSLG is not a valid domain; the one-line message names the offending element.

    Also importable from :mod:`persistri.impl.mesh.domain`, which raises it.
    """
