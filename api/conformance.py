"""persistri.conformance — the conformance suite, for authors of their own persistent maps and complexes.

The same objects as :mod:`persistri.spec.conformance` (where they are documented),
under a shorter name::

    from persistri.conformance import OrdMapConformance

    class TestMyMap(OrdMapConformance):
        structure = MyMap()

The suite needs pytest and hypothesis (``pip install 'persistri[conformance]'``).
Importing this module does not import them; the first name used from it does,
and says what to install when they are missing.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from persistri.spec.conformance import *  # noqa: F403  - the suite's own __all__, checked by mypy

    __all__: list[str]
else:

    def __getattr__(name: str) -> object:
        """Every name (``__all__`` included) from :mod:`persistri.spec.conformance`, imported on first use."""
        if name.startswith("__") and name != "__all__":
            raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
        value = getattr(importlib.import_module("persistri.spec.conformance"), name)
        globals()[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(importlib.import_module("persistri.spec.conformance").__all__)
