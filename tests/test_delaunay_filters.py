"""The triangulator's written-out filters: the cavity's ``incircle`` and the walks' ``orient2d`` fast paths.

:func:`persistri.impl.terrain.cavity.insert_linked` and the walks of :mod:`persistri.impl.terrain.walk` write
the kernel's semi-static filter out in place (a call a test fewer); a determinant the static threshold does not
decide goes to the kernel's method.  They must be the proved functions' statements (so that they round as the
kernel's do), and decide as the methods do: a counted run, whose tests all go to the methods, makes the same
triangulation as an uncounted one, on inputs where the filters fail often.
"""

from __future__ import annotations

import ast
import inspect
import textwrap
from pathlib import Path

import numpy as np
import pytest
from numpy.typing import NDArray

import persistri.impl.geometry.filter as fp
import persistri.impl.terrain.cavity as cavity
from persistri.impl.stats import Stats
from persistri.impl.terrain.scattered import delaunay


def _stmts(fn: ast.FunctionDef) -> list[str]:
    nodes = sorted((n for n in ast.walk(fn) if isinstance(n, ast.stmt)), key=lambda n: (n.lineno, n.col_offset))
    return [ast.dump(n) for n in nodes]


def _function(module: str, name: str) -> ast.FunctionDef:
    tree = ast.parse(Path(cavity.__file__).parent.joinpath(module).read_text(encoding="utf-8"))
    found = [f for f in ast.walk(tree) if isinstance(f, ast.FunctionDef) and f.name == name]
    assert len(found) == 1, name
    return found[0]


def _filter(fn: object) -> list[str]:
    """The filter function's statements up to ``det`` (the permanent is the kernel's method's)."""
    tree = ast.parse(textwrap.dedent(inspect.getsource(fn))).body[0]  # type: ignore[arg-type]
    assert isinstance(tree, ast.FunctionDef)
    body = [ast.dump(s) for s in tree.body[1:-1]]  # after the docstring, before the return
    det = next(i for i, s in enumerate(body) if "id='det', ctx=Store()" in s)
    return body[: det + 1]


def _in_order(have: list[str], want: list[str]) -> bool:
    it = iter(have)
    return all(any(h == w for h in it) for w in want)


@pytest.mark.parametrize(
    ("module", "name", "filter_fn", "ordered"),
    [
        ("cavity.py", "insert_linked", fp.incircle_terms, True),
        ("walk.py", "walk", fp.orient2d_terms, True),
        ("walk.py", "walk_from_fan", fp.orient2d_terms, False),  # the scan's a − c parts read once, first
    ],
)
def test_the_written_out_filters_are_the_proved_functions(module: str, name: str, filter_fn: object, ordered: bool) -> None:
    want = _filter(filter_fn)
    have = _stmts(_function(module, name))
    assert all(w in have for w in want)
    if ordered:
        assert _in_order(have, want)


def _circle(n: int) -> NDArray[np.float64]:
    t = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    return np.c_[np.cos(t), np.sin(t)]


def _inputs() -> list[tuple[str, NDArray[np.float64]]]:
    rng = np.random.default_rng(3)
    grid = np.array([(i, j) for i in range(24) for j in range(24)], dtype=float)
    return [
        ("circle", _circle(160)),  # cocircular in floats: the filters fail for most cavity tests
        ("circle, 1e7 away", _circle(120) * 1e-3 + 1e7),
        ("grid", grid),  # exact floats: the threshold 0, every zero to SoS
        ("grid, ulps apart", grid * (1.0 + rng.integers(-2, 3, grid.shape) * 2.0**-52)),
        ("uniform, 1e7 away", rng.random((600, 2)) + 1e7),
    ]


@pytest.mark.parametrize(("name", "pts"), _inputs(), ids=[n for n, _ in _inputs()])
def test_the_written_out_filters_decide_as_the_kernels_methods(name: str, pts: NDArray[np.float64]) -> None:
    fast = delaunay(pts)
    counted = delaunay(pts, stats=Stats())  # every test by the kernel's methods (no records, no written-out filter)
    checked = delaunay(pts, check=True)  # the records' path, each step checked, the result verified exactly
    for other in (counted, checked):
        assert np.array_equal(fast.triangles, other.triangles)
        assert np.array_equal(fast.hull, other.hull)
