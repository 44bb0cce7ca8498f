"""The source distribution is the whole source tree: its tests can run from the unpacked sdist.

setuptools alone ships ``tests/test*.py`` without the helpers they import
(``conftest.py``, ``mesh_helpers.py``, ...) nor the docs, proofs and ``tools/`` they
read; ``MANIFEST.in`` grafts those folders whole.  Built offline from a copy of
the checkout (a build in the checkout would write its ``persistri.egg-info``).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tarfile
import tomllib
from pathlib import Path

import pytest

_REPO = Path(__file__).resolve().parents[1]
_IGNORED = shutil.ignore_patterns("__pycache__", "*.py[cod]", "*.so", "*.pyd", ".hypothesis")
_READ_BY_TESTS = ("tests", "docs", "proofs", "tools")


@pytest.mark.skipif(bool(os.environ.get("PERSISTRI_TWIN")), reason="packaging is the same for the compiled twin")
def test_the_sdist_holds_the_tests_and_everything_they_read(tmp_path: Path) -> None:
    src = tmp_path / "src"
    src.mkdir()
    with (_REPO / "pyproject.toml").open("rb") as fh:
        project = tomllib.load(fh)
    packages = sorted({d.split("/")[0] for d in project["tool"]["setuptools"]["package-dir"].values()})
    for name in [*packages, *_READ_BY_TESTS]:
        shutil.copytree(_REPO / name, src / name, ignore=_IGNORED)
    for name in ("pyproject.toml", "README.md", "LICENSE", "MANIFEST.in", "Makefile", "mkdocs.yml"):
        shutil.copy2(_REPO / name, src / name)
    out = tmp_path / "dist"
    code = f"from setuptools import build_meta; print(build_meta.build_sdist({str(out)!r}))"
    built = subprocess.run([sys.executable, "-c", code], cwd=src, capture_output=True, text=True, timeout=600, check=False)
    assert built.returncode == 0, built.stderr[-2000:]
    name = built.stdout.strip().splitlines()[-1]
    with tarfile.open(out / name) as tar:
        top = name.removesuffix(".tar.gz")
        shipped = {m.name.removeprefix(top + "/") for m in tar.getmembers() if m.isfile()}
    wanted = {p.relative_to(src).as_posix() for folder in _READ_BY_TESTS for p in (src / folder).rglob("*") if p.is_file()}
    wanted |= {"Makefile", "mkdocs.yml", "README.md", "LICENSE", "pyproject.toml"}
    missing = sorted(wanted - shipped)
    assert not missing, f"{len(missing)} files of the source tree are not in the sdist, e.g. {missing[:5]}"
    assert {"tests/conftest.py", "tests/mesh_helpers.py", "docs/tutorial.md", "tools/compiled_twin.py"} <= shipped
    assert not any("__pycache__" in s or s.endswith(".pyc") for s in shipped)
