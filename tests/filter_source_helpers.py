"""Reading filter expressions from source: a written-out filter must be the proved function's statements.

The kernels write the filter expressions of :mod:`persistri.impl.geometry.filter`
out in place; these helpers compare statements as ASTs (``ast.dump``), so that
formatting differs freely and any change to an expression shows.
"""

from __future__ import annotations

import ast
import inspect
import textwrap
from collections.abc import Callable, Iterator
from typing import Any


class _Unalias(ast.NodeTransformer):
    """``_abs`` (filter.py's typed alias of the builtin) read as ``abs``, as the kernel writes it."""

    def visit_Name(self, node: ast.Name) -> ast.Name:
        return ast.Name(id="abs", ctx=node.ctx) if node.id == "_abs" else node


def _dumps(stmts: list[ast.stmt]) -> list[str]:
    return [ast.dump(_Unalias().visit(s)) for s in stmts]


def _filter_body(fn: Callable[..., Any]) -> tuple[list[str], list[str]]:
    """A filter function's statements (docstring and ``return`` left out) and the names it returns."""
    tree = ast.parse(textwrap.dedent(inspect.getsource(fn))).body[0]
    assert isinstance(tree, ast.FunctionDef)
    body = tree.body[1:]  # after the docstring
    ret = body[-1]
    assert isinstance(ret, ast.Return) and isinstance(ret.value, (ast.Tuple, ast.Name))
    values = ret.value.elts if isinstance(ret.value, ast.Tuple) else [ret.value]
    names = [e.id for e in values if isinstance(e, ast.Name)]
    assert len(names) == len(values), f"{fn.__name__} must return named values"
    return _dumps(body[:-1]), names


def _blocks(node: ast.AST) -> Iterator[list[ast.stmt]]:
    """Every statement list under ``node`` (function bodies, loop bodies, branches)."""
    for child in ast.walk(node):
        for field in ("body", "orelse"):
            block = getattr(child, field, None)
            if isinstance(block, list) and block and isinstance(block[0], ast.stmt):
                yield block


def _contains_in_order(fn: ast.FunctionDef, stmts: list[str]) -> bool:
    """The statements occur in ``fn`` in this order (a subsequence of its statements in source order,
    branches included): the kernel may test a semi-static threshold between them."""
    nodes = sorted((n for n in ast.walk(fn) if isinstance(n, ast.stmt)), key=lambda n: (n.lineno, n.col_offset))
    dumps = iter(_dumps(nodes))
    return all(any(d == want for d in dumps) for want in stmts)


def _contains_run(fn: ast.FunctionDef, run: list[str]) -> bool:
    for block in _blocks(fn):
        dumps = _dumps(block)
        for i in range(len(dumps) - len(run) + 1):
            if dumps[i : i + len(run)] == run:
                return True
    return False
