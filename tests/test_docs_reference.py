"""The API reference (docs/reference/*.md) documents every module of the package.

A module added without a ``::: module`` line would be invisible to the reader of the
docs (mkdocs does not complain about what it was never asked to render), so this
test lists the package's modules from the source tree and asks for each one.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
HALVES = {"api": "persistri", "spec": "persistri.spec", "impl": "persistri.impl"}
PRIVATE_PUBLIC_API = {"persistri._arrays", "persistri._hull", "persistri._hull_chunked", "persistri._delaunay"}
"""The public package's private modules: documented through the names they define (``::: persistri.ConvexHull``)."""


def package_modules() -> set[str]:
    """Every module of the distribution, by dotted name (``__init__``/``__main__`` stand for their package)."""
    names: set[str] = set()
    for folder, prefix in HALVES.items():
        for path in (ROOT / folder).rglob("*.py"):
            if path.name in ("__init__.py", "__main__.py"):
                continue
            rel = path.relative_to(ROOT / folder).with_suffix("")
            names.add(".".join([prefix, *rel.parts]))
    return names - PRIVATE_PUBLIC_API


def documented_modules() -> set[str]:
    text = "\n".join(p.read_text() for p in (ROOT / "docs" / "reference").glob("*.md"))
    return set(re.findall(r"^::: (\S+)", text, flags=re.MULTILINE))


def test_every_module_has_a_reference_entry() -> None:
    missing = sorted(package_modules() - documented_modules())
    assert not missing, f"add a '::: name' line to a page of docs/reference/ for: {', '.join(missing)}"


def test_every_reference_entry_names_a_module_or_public_name() -> None:
    import importlib

    import persistri

    stale = []
    for name in sorted(documented_modules()):
        module, _, attr = name.rpartition(".")
        try:
            importlib.import_module(name)
        except ImportError:
            if not (module and hasattr(importlib.import_module(module), attr)):
                stale.append(name)
    assert persistri.__name__ == "persistri" and not stale, f"reference entries naming nothing: {stale}"
