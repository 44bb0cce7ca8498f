"""Negative type tests: mypy must REJECT a wrong ``ORD_MAP`` backend, and for the right reason.

``python tests/typing/check_rejections.py`` writes small snippet modules to a
temporary directory, type-checks them all in ONE ``mypy.api.run`` (``--strict``,
the project's ``[tool.mypy]`` settings from ``pyproject.toml``, a shared cache
directory) and checks, snippet by snippet, that

* (c) a correct minimal backend (:data:`GOOD_BACKEND`), ascribed to
  ``OrdMap[int, str, Pairs]``, is ACCEPTED with no error at all;
* (a) the same backend with one ``ORD_MAP`` operation deleted is REJECTED at the
  ascription, with error code ``assignment`` and mypy's note naming the missing
  protocol member;
* (b) the same backend with one wrong signature (``find`` returning
  ``str | None`` instead of the ``Option`` 1-tuple; ``remove`` returning only the
  map) is REJECTED at the ascription, with mypy's note naming the conflicting
  member and the expected signature;
* (d) a ``str`` key passed to a map typed ``OrdMap[int, str, M]`` is REJECTED
  with error code ``arg-type``, both in generic code and at the real backends;
* (e) a misspelt public name (``persistri.ConvexHul``) is REJECTED (``attr-defined``:
  the lazy module ``__getattr__`` must not make every name ``Any``), and so is a
  wrong use of a public attribute's type.

Because each defective snippet is derived from the accepted one by a single
textual edit, a rejection can only come from that edit.  Every snippet must
produce exactly the expected errors, on exactly the marked lines: an
unexpected error anywhere is a failure too.

Exit status 0 means every expectation held; otherwise a readable report of
each violated expectation is printed and the exit status is 1.
:func:`run_checks` is the same check for pytest (``tests/test_typing_rejections.py``).
"""

from __future__ import annotations

import os
import re
import shutil
import sys
import tempfile
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
"""The repository root (the directory holding ``pyproject.toml``)."""

CACHE_DIR = ROOT / ".mypy_cache" / "check_rejections" / os.environ.get("PYTEST_XDIST_WORKER", "main")
"""mypy's cache for these snippets, kept apart from the package's own cache (one per pytest-xdist worker,
so that two concurrent mypy runs never share a cache)."""

MARK = "# reject"
"""The comment that marks the line on which a snippet must be rejected."""


@dataclass(frozen=True)
class Snippet:
    """A module to type-check, and what mypy must say about it.

    ``code`` is the error code mypy must report on the line marked :data:`MARK`;
    every string of ``messages`` must occur in mypy's messages (errors and notes)
    for that line, and every string of ``note_lines`` must be one of those notes
    exactly (e.g. the name of a missing protocol member).  ``code=None`` means
    the snippet must be accepted.
    """

    name: str
    why: str
    source: str
    code: str | None = None
    messages: tuple[str, ...] = ()
    note_lines: tuple[str, ...] = ()


GOOD_BACKEND = '''
from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeAlias, TypeVar

from persistri.spec import NATURAL_ORDER, NotFound, Option, OrdKey, OrdMap

B = TypeVar("B")

Pairs: TypeAlias = tuple[tuple[int, str], ...]
"""A map: a sorted tuple of (key, value) pairs."""


class PairsMap:
    """A minimal, correct ORD_MAP structure from int to str (sorted tuples, copied on update)."""

    @property
    def Key(self) -> OrdKey[int]:
        return NATURAL_ORDER

    def empty(self) -> Pairs:
        return ()

    def isEmpty(self, m: Pairs, /) -> bool:
        return not m

    def singleton(self, k: int, v: str, /) -> Pairs:
        return ((k, v),)

    def insert(self, m: Pairs, k: int, v: str, /) -> Pairs:
        return tuple(sorted({**dict(m), k: v}.items()))

    def insertWith(self, f: Callable[[str, str], str], m: Pairs, k: int, v: str, /) -> Pairs:
        d = dict(m)
        return tuple(sorted({**d, k: f(d[k], v) if k in d else v}.items()))

    def find(self, m: Pairs, k: int, /) -> Option[str]:
        d = dict(m)
        return (d[k],) if k in d else None

    def lookup(self, m: Pairs, k: int, /) -> str:
        d = dict(m)
        if k not in d:
            raise NotFound(k)
        return d[k]

    def inDomain(self, m: Pairs, k: int, /) -> bool:
        return k in dict(m)

    def remove(self, m: Pairs, k: int, /) -> tuple[Pairs, str]:
        v = self.lookup(m, k)
        return tuple(p for p in m if p[0] != k), v

    def numItems(self, m: Pairs, /) -> int:
        return len(m)

    def listItemsi(self, m: Pairs, /) -> list[tuple[int, str]]:
        return list(m)

    def listKeys(self, m: Pairs, /) -> list[int]:
        return [k for k, _ in m]

    def foldli(self, f: Callable[[int, str, B], B], init: B, m: Pairs, /) -> B:
        acc = init
        for k, v in m:
            acc = f(k, v, acc)
        return acc


structure: OrdMap[int, str, Pairs] = PairsMap()  # reject
'''
"""(c): the backend every defective snippet is one edit away from."""


def _edit(old: str, new: str) -> str:
    """:data:`GOOD_BACKEND` with the one occurrence of ``old`` replaced by ``new``."""
    assert GOOD_BACKEND.count(old) == 1, f"snippet edit {old!r} must match exactly once"
    return GOOD_BACKEND.replace(old, new)


_REMOVE_DEF = '''    def remove(self, m: Pairs, k: int, /) -> tuple[Pairs, str]:
        v = self.lookup(m, k)
        return tuple(p for p in m if p[0] != k), v
'''

_ASSIGN = "Incompatible types in assignment"
_VAR = 'variable has type "OrdMap[int, str, tuple[tuple[int, str], ...]]"'

SNIPPETS: tuple[Snippet, ...] = (
    Snippet(
        name="good_backend",
        why="(c) a correct minimal backend is accepted",
        source=GOOD_BACKEND,
    ),
    Snippet(
        name="missing_remove",
        why="(a) a backend without `remove` is rejected",
        source=_edit(_REMOVE_DEF, ""),
        code="assignment",
        messages=(_ASSIGN, _VAR, '"PairsMap" is missing following "OrdMap" protocol member'),
        note_lines=("remove",),
    ),
    Snippet(
        name="missing_foldli",
        why="(a) a backend without `foldli` is rejected",
        source=_edit("    def foldli(", "    def _not_foldli("),
        code="assignment",
        messages=(_ASSIGN, _VAR, '"PairsMap" is missing following "OrdMap" protocol member'),
        note_lines=("foldli",),
    ),
    Snippet(
        name="find_returns_bare_value",
        why="(b) `find` returning `str | None` (not the Option 1-tuple) is rejected",
        source=_edit(
            """    def find(self, m: Pairs, k: int, /) -> Option[str]:
        d = dict(m)
        return (d[k],) if k in d else None""",
            """    def find(self, m: Pairs, k: int, /) -> str | None:
        return dict(m).get(k)""",
        ),
        code="assignment",
        messages=(
            _ASSIGN,
            _VAR,
            'Following member(s) of "PairsMap" have conflicts',
            "def find(self, tuple[tuple[int, str], ...], int, /) -> tuple[str] | None",
            "def find(self, tuple[tuple[int, str], ...], int, /) -> str | None",
        ),
    ),
    Snippet(
        name="remove_returns_only_map",
        why="(b) `remove` returning only the map (not `(map, value)`) is rejected",
        source=_edit(
            _REMOVE_DEF,
            """    def remove(self, m: Pairs, k: int, /) -> Pairs:
        return tuple(p for p in m if p[0] != k)
""",
        ),
        code="assignment",
        messages=(
            _ASSIGN,
            _VAR,
            'Following member(s) of "PairsMap" have conflicts',
            "-> tuple[tuple[tuple[int, str], ...], str]",
            "def remove(self, tuple[tuple[int, str], ...], int, /) -> tuple[tuple[int, str], ...]",
        ),
    ),
    Snippet(
        name="str_key_generic",
        why="(d) a str key passed to a map typed OrdMap[int, str, M] is rejected (generic code)",
        source='''
from typing import TypeVar

from persistri.spec import OrdMap

M = TypeVar("M")


def add_word(s: OrdMap[int, str, M], m: M) -> M:
    return s.insert(m, "one", "1")  # reject
''',
        code="arg-type",
        messages=('Argument 2 to "insert" of "OrdMap" has incompatible type "str"; expected "int"',),
    ),
    Snippet(
        name="str_key_assoc_list",
        why="(d) a str key passed to the association list ascribed OrdMap[int, str, ALMap[int, str]] is rejected",
        source='''
from persistri.maps import ALMap, assoc_list
from persistri.spec import OrdMap

s: OrdMap[int, str, ALMap[int, str]] = assoc_list
m = s.insert(s.empty(), 1, "one")
found = s.find(m, "one")  # reject
''',
        code="arg-type",
        messages=('Argument 2 to "find" of "OrdMap" has incompatible type "str"; expected "int"',),
    ),
    *(
        Snippet(
            name=f"str_key_{cls.lower()}",
            why=f"(d) a str key passed to {cls}[int, str] is rejected",
            source=f'''
from {module} import {cls}

s = {cls}[int, str]()
m = s.insert(s.empty(), 1, "one")
m2 = s.insert(m, "two", "2")  # reject
''',
            code="arg-type",
            messages=(f'Argument 2 to "insert" of "{cls}" has incompatible type "str"; expected "int"',),
        )
        for module, cls in (("persistri.maps", "RedBlackMap"), ("persistri.maps", "HamtMap"))
    ),
    Snippet(
        name="misspelt_public_name",
        why="(e) a misspelt public name is rejected: the lazy module __getattr__ is hidden from mypy, not Any",
        source='''
import persistri

hull = persistri.ConvexHul([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])  # reject
''',
        code="attr-defined",
        messages=('Module has no attribute "ConvexHul"',),
    ),
    Snippet(
        name="public_attribute_type",
        why="(e) the public API's attributes are typed: a hull's volume is not a str",
        source='''
import persistri

hull = persistri.ConvexHull([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
volume: str = hull.volume  # reject
''',
        code="assignment",
        messages=(_ASSIGN, 'expression has type "float", variable has type "str"'),
    ),
)
"""Every snippet, accepted or rejected (see the module docstring)."""


_LINE = re.compile(r"^(?P<path>.+?):(?P<line>\d+): (?P<kind>error|note): (?P<msg>.*?)(?:  \[(?P<code>[a-z-]+)\])?$")


@dataclass
class _Reported:
    errors: list[tuple[str | None, str]] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


def _python_version() -> str:
    with open(ROOT / "pyproject.toml", "rb") as f:
        version = tomllib.load(f)["tool"]["mypy"]["python_version"]
    assert isinstance(version, str)
    return version


def _seed_cache() -> None:
    """Start a pytest-xdist worker's empty cache as a copy of the one ``make typecheck`` leaves (``main``).

    The snippets import persistri, so a cold cache type-checks the whole package again (about a CPU minute);
    mypy revalidates every entry it reads, so a copy is never trusted beyond what it checks itself.
    """
    main = CACHE_DIR.parent / "main"
    if CACHE_DIR.exists() or CACHE_DIR == main or not main.is_dir():
        return
    try:
        shutil.copytree(main, CACHE_DIR)
    except OSError:  # a copy half made is removed: mypy then starts cold, as without one
        shutil.rmtree(CACHE_DIR, ignore_errors=True)


def run_checks(snippets: tuple[Snippet, ...] | None = None) -> list[str]:
    """Type-check every snippet in one mypy run; the violated expectations (empty: all good)."""
    from mypy import api  # imported here so that importing this module stays cheap

    if snippets is None:
        snippets = SNIPPETS
    _seed_cache()
    CACHE_DIR.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="persistri-rejections-") as tmp:
        paths: dict[str, Snippet] = {}
        for snip in snippets:
            path = Path(tmp) / f"snippet_{snip.name}.py"
            path.write_text(snip.source, encoding="utf-8")
            paths[path.name] = snip
        stdout, stderr, status = api.run(
            [
                "--strict",
                "--config-file",
                str(ROOT / "pyproject.toml"),
                "--python-version",
                _python_version(),
                "--cache-dir",
                str(CACHE_DIR),
                "--no-error-summary",
                "--show-error-codes",
                "--no-pretty",
                "--no-color-output",
                *(str(Path(tmp) / name) for name in paths),
            ]
        )
        if status not in (0, 1):
            return [f"mypy crashed or was misconfigured (exit status {status}):\n{stdout}{stderr}"]
        reported: dict[tuple[str, int], _Reported] = {}
        unparsed: list[str] = []
        for raw in stdout.splitlines():
            match = _LINE.match(raw)
            if match is None:
                unparsed.append(raw)
                continue
            key = (Path(match["path"]).name, int(match["line"]))
            rep = reported.setdefault(key, _Reported())
            if match["kind"] == "error":
                rep.errors.append((match["code"], match["msg"]))
            else:
                rep.notes.append(match["msg"].strip())
        problems = [f"unparsed mypy output: {line}" for line in unparsed]
        for fname, snip in paths.items():
            problems.extend(_judge(fname, snip, reported))
    return problems


def _judge(fname: str, snip: Snippet, reported: dict[tuple[str, int], _Reported]) -> list[str]:
    """The violated expectations of one snippet."""
    marked = [i for i, line in enumerate(snip.source.splitlines(), start=1) if line.rstrip().endswith(MARK)]
    assert len(marked) == 1, f"snippet {snip.name} must mark exactly one line with {MARK!r}"
    target = marked[0]
    problems: list[str] = []
    for (f, line), other in sorted(reported.items(), key=lambda item: item[0]):
        if f != fname or not other.errors:
            continue
        if snip.code is None or line != target:
            shown = "; ".join(f"[{c}] {m}" for c, m in other.errors)
            problems.append(f"{snip.why}: unexpected error at line {line}: {shown}")
    if snip.code is None:
        return problems
    rep = reported.get((fname, target))
    if rep is None or not rep.errors:
        problems.append(f"{snip.why}: mypy ACCEPTED line {target}, it must reject it with [{snip.code}]")
        return problems
    codes = [c for c, _ in rep.errors]
    if snip.code not in codes:
        problems.append(f"{snip.why}: expected error code [{snip.code}] at line {target}, got {codes}")
    said = "\n".join([m for _, m in rep.errors] + rep.notes)
    for text in snip.messages:
        if text not in said:
            problems.append(f"{snip.why}: mypy's messages at line {target} do not contain {text!r}; they were:\n{said}")
    for note in snip.note_lines:
        if note not in rep.notes:
            problems.append(f"{snip.why}: mypy did not note {note!r} at line {target}; its notes were: {rep.notes}")
    return problems


def main() -> int:
    """Run every check; print a report; 0 when all expectations held."""
    snippets = SNIPPETS
    problems = run_checks(snippets)
    if problems:
        print(f"check_rejections: {len(problems)} expectation(s) violated:", file=sys.stderr)
        for p in problems:
            print(f"  - {p}", file=sys.stderr)
        return 1
    print(f"check_rejections: ok ({len(snippets)} snippets: 1 accepted, {len(snippets) - 1} rejected as expected)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
