"""The docs' two helper scripts: the reST → Markdown docstring rewriter and the checks behind the figures.

``docs/griffe_rst.py`` must turn each reST construct persistri's docstrings use
into its Markdown equivalent (and leave the rest alone); ``docs/figures.py``
must refuse to draw a picture whose content disagrees with the run or with the
paper — so its checks are tested here on corrupted inputs, not only on the
good run that ``make docs`` draws.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"


def _load(name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(f"persistri_docs_{name}", DOCS / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses resolve their module while the class is built
    spec.loader.exec_module(module)
    return module


rst = _load("griffe_rst")
figures = _load("figures")


# -- griffe_rst ------------------------------------------------------------------------


def test_roles_become_code_and_tilde_keeps_the_last_name() -> None:
    text = "See :class:`~persistri.impl.stats.Stats`, :func:`persistri.impl.hull.api.convex_hull` and :mod:`.red_black`."
    assert rst.rest_to_markdown(text) == "See `Stats`, `persistri.impl.hull.api.convex_hull` and `.red_black`."


def test_a_simple_table_becomes_a_markdown_table_with_its_continuation_rows() -> None:
    text = "\n".join(
        [
            "Costs:",
            "",
            "=========  ======  ===========",
            "operation  time    notes",
            "=========  ======  ===========",
            "find       O(1)    one lookup",
            "insert     O(n)    copies the",
            "                   prefix",
            "listItems,  O(n)   sorted",
            "foldli             order",
            "=========  ======  ===========",
            "",
            "After.",
        ]
    )
    assert rst.rest_to_markdown(text).splitlines() == [
        "Costs:",
        "",
        "| operation | time | notes |",
        "|---|---|---|",
        "| find | O(1) | one lookup |",
        "| insert | O(n) | copies the prefix |",
        "| listItems, foldli | O(n) | sorted order |",
        "",
        "After.",
    ]


def test_pipes_in_table_cells_are_escaped_outside_code_only() -> None:
    text = "\n".join(["=====  ==========", "SML    Python", "=====  ==========", "opt    ``V | None``", "a|b    x", "=====  =========="])
    rows = rst.rest_to_markdown(text).splitlines()
    assert rows[2] == "| opt | ``V | None`` |"
    assert rows[3] == "| a\\|b | x |"


def test_doctest_paragraphs_are_fenced_and_literal_blocks_lose_their_double_colon() -> None:
    text = "Use it like this::\n\n    x = 1\n\nor::\n\n    y = 2\n\n>>> 1 + 1\n2\n\nDone."
    assert rst.rest_to_markdown(text) == "Use it like this:\n\n    x = 1\n\nor:\n\n    y = 2\n\n```pycon\n>>> 1 + 1\n2\n```\n\nDone."


def test_underlined_titles_become_bold_and_quoted_blocks_lose_inline_literals() -> None:
    text = "Representation\n--------------\n\nstored as:\n\n    under a: ``(b, c)``\n\nthen ``code`` stays."
    assert rst.rest_to_markdown(text) == "**Representation**\n\n\nstored as:\n\n    under a: (b, c)\n\nthen ``code`` stays."


def test_markdown_without_rest_is_unchanged() -> None:
    text = "A *plain* docstring with `code`, a list:\n\n* one\n* two\n\nand an example:\n\n```python\nx = 1\n```"
    assert rst.rest_to_markdown(text) == text


# -- figures ------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def run() -> Any:
    """The run the hull pictures are drawn from: (points, history, predicates with the centre)."""
    return figures.hull_run()


def test_every_insertion_of_the_drawn_run_passes_the_checks(run: Any) -> None:
    _, history, pred = run
    for k in range(1, len(history)):
        ins = figures.insertion(history, pred, k)
        graph = figures.walking_graph(ins)
        assert graph.order[0] == ins.associated and sorted(graph.order) == ins.lit
        assert len(graph.to_horizon) == len(ins.horizon) == len(ins.tent)


def _largest(run: Any) -> Any:
    _, history, pred = run
    steps = [figures.insertion(history, pred, k) for k in range(1, len(history))]
    return max((s for s in steps if len(s.lit) >= 6), key=lambda s: len(s.moved))


def test_a_wrong_associated_face_is_refused(run: Any) -> None:
    ins = _largest(run)
    other = next(t for t in ins.lit if t != ins.associated)
    with pytest.raises(figures.FigureCheckError, match="associated face|in-degree"):
        figures.walking_graph(dataclasses.replace(ins, associated=other))


class _Misread:
    """A history whose point ``k`` is replaced by ``p``: versions k−1 → k paired with the wrong point."""

    def __init__(self, history: Any, k: int, p: int) -> None:
        self._history = history
        self.structure = history.structure
        self.inserted = list(history.inserted)
        self.inserted[k] = p

    def __getitem__(self, j: int) -> Any:
        return self._history[j]


def test_an_insertion_paired_with_the_wrong_point_is_refused(run: Any) -> None:
    _, history, pred = run
    # The point of insertion 7, still outside version 5, paired with versions 5 → 6.
    with pytest.raises(figures.FigureCheckError, match="the faces p sees are not the faces removed"):
        figures.insertion(_Misread(history, 6, history.inserted[7]), pred, 6)
