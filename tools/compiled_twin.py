"""Build persistri's compiled twin: the same source, with its innermost modules compiled by mypyc.

    python tools/compiled_twin.py DIR

copies the package (``api/``, the top-level ``persistri`` with its public names, and
``impl/`` and ``spec/`` inside it) to ``DIR/persistri/`` and compiles
:data:`MODULES` there with mypyc (which ships with mypy, a dev dependency), so
that ``PYTHONPATH=DIR`` runs persistri with those modules as C extensions and
every other module interpreted, from the same source.  ``make test`` runs the
test suite on the twin too; ``docs/performance.md`` says what it is for and what
it measures.  The twin is rebuilt only when a source file changed since the
last build (a hash of them is kept in ``DIR/.sources``).

Exit status: 0 when the twin is built (or already up to date), 2 when this
machine has no C compiler or no Python headers (nothing is built: the twin is
optional, and the interpreted package needs neither), 1 on any other failure
(a mypyc or compiler error is a defect of the source, not of the machine).
"""

from __future__ import annotations

import hashlib
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

MODULES = (
    "persistri/impl/geometry/kernel.py",
    "persistri/impl/geometry/kernel_split.py",
    "persistri/impl/geometry/kernel_vector.py",
    "persistri/impl/hull/bulldozer.py",
    "persistri/impl/hull/insertion.py",
    "persistri/impl/hull/conflicts.py",
    "persistri/impl/hull/packed.py",
    "persistri/impl/maps/red_black_tree.py",
    "persistri/impl/maps/red_black_adjust.py",
    "persistri/impl/maps/red_black_adjust_insert.py",
    "persistri/impl/maps/red_black_arena_tree.py",
    "persistri/impl/maps/red_black_arena_delete.py",
    "persistri/impl/maps/red_black_arena_adjust.py",
    "persistri/impl/maps/int_trie_nodes.py",
    "persistri/impl/complex/vertex_lists.py",
    "persistri/impl/complex/vertex_changes.py",
    "persistri/impl/complex/replace.py",
    "persistri/impl/complex/neighbours.py",
    "persistri/impl/geometry/kernel2d.py",
    "persistri/impl/terrain/delaunay.py",
    "persistri/impl/terrain/cavity.py",
    "persistri/impl/terrain/insertion.py",
    "persistri/impl/terrain/walk.py",
    "persistri/impl/terrain/sectors.py",
    "persistri/impl/terrain/greedy_run.py",
    "persistri/impl/terrain/plane_errors.py",
)
"""The modules compiled: the bulldozer's insertion loop and its conflict-list helpers (and the packed face
data of a run that keeps its history), the predicate
kernel it calls (and its split and vectorised paths), and the inner functions of the persistent structures it changes — the red-black
tree's node algorithms, its batched update (with the fused insertion of ``replace``'s new vertex), the
same two for the arena red-black tree (the backend for keeping histories, ``red_black_arena``), the
2-complex's list functions and ``replace``'s grouping by vertex, its walks' edge lookups and ``replace``'s
compiled entry for the algorithms (``replace_trusted``) — where a hull run spends most of its interpreted time
(docs/performance.md); and for the terrain and the scattered Delaunay, the 2D kernel, the triangulator
and its cavity search, the sector test, the greedy run's loop and its error measure.  The structures' public operations
(``red_black.py``, ``two_complex.py``) and ``greedy_insertion`` (``terrain/greedy.py``) stay
interpreted: they raise the signature's errors for ill-typed arguments, where mypyc's entry
checks would raise its own.  The compiled ones type their nodes, entries and lists as tuples of any
length so that mypyc keeps them boxed: each stays the one object that older versions share
(mypyc would store a fixed-length tuple unboxed and box a new copy on the way out)."""


NO_TOOLCHAIN = 2

MYPY_CONFIG = """\
[mypy]
follow_imports = skip

[mypy-persistri.*,numpy.*]
follow_imports = normal
"""
"""The type checker's configuration for the build (``DIR/mypy.ini``).  mypyc keeps the body of every
function it analyses (mypy's ``preserve_asts``), so it type-checks the bodies of every installed
package that persistri imports anywhere — Dask, Bokeh, Hypothesis, Matplotlib, … — as plain mypy
never does: five minutes where mypy takes fifteen seconds.  The compiled modules need the types of
persistri and numpy only, so nothing else is followed; the C that mypyc writes is the same."""

PARTS = ("api", "impl", "spec")
"""The source folders of the package: ``api/`` is ``persistri`` itself, ``impl/`` and ``spec/`` its halves."""


def _sources() -> list[Path]:
    return sorted(p for part in PARTS for p in (ROOT / part).rglob("*") if p.is_file() and "__pycache__" not in p.parts)


def _fingerprint() -> str:
    digest = hashlib.sha256()
    for path in _sources():
        digest.update(str(path.relative_to(ROOT)).encode())
        digest.update(path.read_bytes())
    digest.update("\n".join(MODULES).encode())
    digest.update(MYPY_CONFIG.encode())
    digest.update(sys.version.encode())
    return digest.hexdigest()


def _toolchain() -> str | None:
    """Why this machine cannot compile a C extension for this Python, or None if it can: the C compiler
    Python's own build used (``CC``) must be on it, and Python's headers."""
    cc = (sysconfig.get_config_var("CC") or "cc").split()[0]
    if shutil.which(cc) is None:
        return f"no C compiler ({cc})"
    if not (Path(sysconfig.get_paths()["include"]) / "Python.h").exists():
        return "no Python headers (Python.h)"
    return None


def _check(out: Path) -> None:
    """Each module of :data:`MODULES` imports from the twin as an extension module."""
    names = [m.removesuffix(".py").replace("/", ".") for m in MODULES]
    probe = "import importlib, sys\n" + "".join(
        f"m = importlib.import_module({n!r}); assert m.__file__.endswith('.so'), m.__file__\n" for n in names
    )
    subprocess.run([sys.executable, "-c", probe], cwd=out, check=True, env={"PYTHONPATH": str(out), "PATH": ""})


def build(out: Path) -> int:
    stamp = out / ".sources"
    fingerprint = _fingerprint()
    if stamp.exists() and stamp.read_text() == fingerprint:
        print(f"compiled twin: {out} is up to date")
        return 0
    missing = _toolchain()
    if missing is not None:
        print(f"compiled twin: not built, this machine has {missing} (persistri itself needs neither)")
        return NO_TOOLCHAIN
    if out.exists():
        shutil.rmtree(out)
    package = out / "persistri"
    ignore = shutil.ignore_patterns("__pycache__")
    # The whole package, its own __init__ (api/) included, as the installed layout maps it: on PYTHONPATH
    # the twin's persistri shadows the installed one entirely, never half from each.
    shutil.copytree(ROOT / "api", package, ignore=ignore)
    shutil.copytree(ROOT / "impl", package / "impl", ignore=ignore)
    shutil.copytree(ROOT / "spec", package / "spec", ignore=ignore)
    (out / "mypy.ini").write_text(MYPY_CONFIG)
    print(f"compiled twin: compiling {len(MODULES)} modules with mypyc (about half a minute) …", flush=True)
    log = out / "mypyc.log"
    with log.open("w") as sink:
        done = subprocess.run([sys.executable, "-m", "mypyc", *MODULES], cwd=out, stdout=sink, stderr=subprocess.STDOUT)
    if done.returncode != 0:
        sys.stdout.write(log.read_text()[-4000:])
        print(f"compiled twin: mypyc failed (exit {done.returncode}); the full log is {log}")
        return 1
    _check(out)
    stamp.write_text(fingerprint)
    print(f"compiled twin: built in {out}")
    return 0


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print(__doc__)
        return 1
    return build(Path(argv[0]).resolve())


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
