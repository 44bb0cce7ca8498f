"""A griffe extension: persistri's reST-flavoured docstrings, rewritten as Markdown for mkdocstrings.

persistri's docstrings are written to read well in ``help()`` and in source:
Sphinx roles (``:class:`~persistri.impl.stats.Stats```), reST simple tables
(rows between lines of ``=====``), ``::`` literal blocks, underlined section
titles and bare ``>>>`` examples.  mkdocstrings renders docstrings as Markdown,
where those constructs come out as noise.  This extension rewrites each
docstring once, when griffe loads it, so that the API reference reads as the
source does:

* a role becomes inline code (``~`` keeps the last dotted component, as Sphinx does);
* a simple table becomes a Markdown table (a row with a blank first cell, or a blank second cell in a wider table, continues the row above);
* ``text::`` becomes ``text:`` (the indented block after it is already code in Markdown), and
  an indented block *not* introduced by ``::`` (a quotation in reST, code in Markdown)
  loses its double backticks;
* an underlined title becomes a bold line (no stray entries in the page's table of contents);
* a paragraph of ``>>>`` lines becomes a ``pycon`` code block.

Nothing here changes what a docstring says; the doctests are run from the
sources by pytest, not from the rendered pages.
"""

from __future__ import annotations

import re
from typing import Any

import griffe

__all__ = ["RestToMarkdown", "rest_to_markdown"]

_ROLE = re.compile(r":(?:py:)?(?:class|func|meth|mod|data|attr|exc|obj|const|term|ref|type):`(~?)([^`]+)`")
_BORDER = re.compile(r"^\s*=+(?:\s+=+)+\s*$")
_UNDERLINE = re.compile(r"^\s*([-=~^])\1{2,}\s*$")


def _role(match: re.Match[str]) -> str:
    tilde, target = match.group(1), match.group(2)
    if tilde:
        target = target.rsplit(".", 1)[-1]
    return f"`{target}`"


def _columns(border: str) -> list[tuple[int, int]]:
    """The character spans of a simple table's columns, from a border line (the last runs to the line end)."""
    spans = [(m.start(), m.end()) for m in re.finditer(r"=+", border)]
    return [(a, spans[k + 1][0] if k + 1 < len(spans) else 10_000) for k, (a, _) in enumerate(spans)]


def _cells(line: str, cols: list[tuple[int, int]]) -> list[str]:
    return [line[a:b].strip() for a, b in cols]


def _cell(text: str) -> str:
    """A table cell's text as Markdown: roles to code, pipes outside code spans escaped."""
    parts = re.split(r"(`+[^`]*`+)", _ROLE.sub(_role, text))
    return "".join(part if part.startswith("`") else part.replace("|", "\\|") for part in parts)


def _table(rows: list[str], indent: str) -> list[str]:
    """A reST simple table (its lines, borders included) as a Markdown table."""
    cols = _columns(rows[0])
    borders = [k for k, r in enumerate(rows) if _BORDER.match(r)]
    header: list[str] = []
    body_from = 1
    if len(borders) >= 3:
        header = [" ".join(c) for c in zip(*[_cells(r, cols) for r in rows[1 : borders[1]]])]
        body_from = borders[1] + 1
    body: list[list[str]] = []
    for r in rows[body_from : borders[-1]]:
        cells = _cells(r, cols)
        if body and (not cells[0] or (len(cells) > 2 and not cells[1])):
            # A blank first column continues the row above (reST's rule for multi-line rows);
            # so does a blank second one in a wider table (a wrapped name beside no value).
            body[-1] = [f"{a} {b}".strip() for a, b in zip(body[-1], cells)]
        else:
            body.append(cells)
    if not header:
        header = [" "] * len(cols)
    out = [indent + "| " + " | ".join(_cell(h) for h in header) + " |"]
    out.append(indent + "|" + "|".join("---" for _ in cols) + "|")
    out.extend(indent + "| " + " | ".join(_cell(c) for c in row) + " |" for row in body)
    return out


def _tables(lines: list[str]) -> list[str]:
    """Each reST simple table (from its top border to its last border) as a Markdown table."""
    out: list[str] = []
    i = 0
    while i < len(lines):
        if _BORDER.match(lines[i]) and len(lines[i].strip()) > 3:
            # The table ends at the last border line before a blank line (or the end).
            j = i + 1
            last = i
            while j < len(lines) and lines[j].strip():
                if _BORDER.match(lines[j]):
                    last = j
                j += 1
            if last > i:
                indent = lines[i][: len(lines[i]) - len(lines[i].lstrip())]
                if out and out[-1].strip():
                    out.append("")
                out.extend(_table(lines[i : last + 1], indent))
                out.extend(lines[last + 1 : j])
                i = j
                continue
        out.append(lines[i])
        i += 1
    return out


def _blocks(lines: list[str]) -> list[str]:
    """Doctest paragraphs to ``pycon`` fences, underlined titles to bold, ``::`` to ``:``."""
    out: list[str] = []
    i = 0
    fenced = False
    literal = False  # whether the last paragraph ended with "::" (its indented block is code)
    quoting = False  # inside an indented block that reST reads as a quotation, Markdown as code
    while i < len(lines):
        line = lines[i]
        stripped = line.strip()
        indented = line.startswith("    ")
        if not stripped:
            pass
        elif not indented:
            literal = stripped.endswith("::")
            quoting = False
        elif not out or not out[-1].strip():
            quoting = quoting or not literal
        if quoting and indented:
            # Markdown will show this block as code: drop reST's inline-literal markup inside it.
            out.append(line.replace("``", ""))
            i += 1
            continue
        if stripped.startswith("```"):
            fenced = not fenced
            out.append(line)
            i += 1
            continue
        if fenced:
            out.append(line)
            i += 1
            continue
        starts_paragraph = not out or not out[-1].strip()
        if stripped.startswith(">>>") and starts_paragraph:
            indent = line[: len(line) - len(line.lstrip())]
            out.append(f"{indent}```pycon")
            while i < len(lines) and lines[i].strip():
                out.append(lines[i])
                i += 1
            out.append(f"{indent}```")
            continue
        if (
            stripped
            and i + 1 < len(lines)
            and _UNDERLINE.match(lines[i + 1])
            and len(lines[i + 1].strip()) >= len(stripped)
            and starts_paragraph
        ):
            out.append(f"**{stripped}**")
            out.append("")
            i += 2
            continue
        if stripped == "::":
            i += 1
            continue
        if stripped.endswith("::"):
            line = line.rstrip()[:-1]
        out.append(line)
        i += 1
    return out


def rest_to_markdown(text: str) -> str:
    """``text`` (a docstring) with the reST constructs listed in the module docstring rewritten as Markdown."""
    lines = text.splitlines()
    lines = _tables(lines)
    lines = _blocks(lines)
    # Roles are rewritten outside code fences only (an example keeps its literal text).
    out: list[str] = []
    fenced = False
    for line in lines:
        if line.strip().startswith("```"):
            fenced = not fenced
        out.append(line if fenced else _ROLE.sub(_role, line))
    return "\n".join(out)


class RestToMarkdown(griffe.Extension):
    """Rewrite every docstring griffe loads (see the module docstring)."""

    def on_instance(self, *, node: Any, obj: griffe.Object, agent: Any, **kwargs: Any) -> None:
        """Called once per loaded object: rewrite its docstring in place."""
        if obj.docstring is not None:
            obj.docstring.value = rest_to_markdown(obj.docstring.value)
