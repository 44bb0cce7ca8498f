"""The triangulator's unvalidated 2D kernel (Delaunay2Kernel): the checked predicates' signs, its exact-float path, its filters."""

from __future__ import annotations

import ast
import inspect
import itertools
import textwrap
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray
from test_predicates_2d import CIRCLE, planar_sets
from filter_source_helpers import _contains_in_order, _dumps, _filter_body

from persistri.impl.geometry import filter as fp
from persistri.impl.geometry.growing import dot_terms
from persistri.impl.geometry.kernel2d import INCIRCLE_EXACT_SPAN, ORIENT2D_EXACT_SPAN, exact_float_spans
from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.geometry.sos import ORIENT3D_SOS
from persistri.impl.stats import Stats


def _agree(pts: NDArray[np.float64], quads: int = 400, seed: int = 0) -> None:
    """Every orient2d triple and a sample of incircle quadruples: the kernel's signs are the checked ones."""
    p = Predicates2(pts)
    k = p.kernel()
    n = len(p)
    for a, b, c in itertools.permutations(range(min(n, 7)), 3):
        assert k.orient2d(a, b, c) == k.orient2d_uncounted(a, b, c) == p.orient2d(a, b, c)
        assert k.orient2d_sign(a, b, c) == p.orient2d_sign(a, b, c)
    rng = np.random.default_rng(seed)
    for _ in range(quads):
        a, b, c, d = (int(i) for i in rng.choice(n, size=4, replace=False))
        assert k.incircle(a, b, c, d) == k.incircle_uncounted(a, b, c, d) == p.incircle(a, b, c, d), (a, b, c, d)


@settings(max_examples=80)
@given(planar_sets(min_size=4, max_size=8))
def test_kernel_agrees_with_the_checked_predicates(pts: NDArray[np.float64]) -> None:
    """Grids, circles, lines, duplicates, extreme scales and offsets: zeros, SoS, filters and fallbacks alike."""
    from persistri.impl.geometry.points import unique_rows

    distinct = pts[unique_rows(pts).first]
    if len(distinct) >= 4:
        _agree(distinct, quads=120)


@pytest.mark.parametrize(
    ("name", "pts", "exact"),
    [
        ("grid", np.array([[x, y] for y in range(12) for x in range(9)], dtype=float), True),
        ("circle", np.array(CIRCLE + [(0, 0), (1, 1)], dtype=float), True),
        ("half-grid offset", np.array([[x, y] for y in range(6) for x in range(6)], dtype=float) * 0.5 + 1024.0, True),
        ("random", np.random.default_rng(1).random((60, 2)), False),
        ("offset decimals", np.array([[x, y] for y in range(6) for x in range(6)], dtype=float) * 0.1 + 1e6, False),
    ],
)
def test_kernel_paths(name: str, pts: NDArray[np.float64], exact: bool) -> None:
    """The exact-float path on grid-like sets (cocircular squares everywhere), the filters elsewhere: one answer."""
    assert Predicates2(pts).kernel().exact_floats is exact
    _agree(pts, quads=3000)


def test_exact_float_spans_at_the_bound() -> None:
    """Fewer than 2^12 grains across: exact incircle; 2^12 or more: not (and orient2d likewise at 2^26)."""
    below = np.array([[0.0, 0.0], [INCIRCLE_EXACT_SPAN - 1.0, 1.0], [3.0, 2.0]])
    at = np.array([[0.0, 0.0], [float(INCIRCLE_EXACT_SPAN), 1.0], [3.0, 2.0]])
    assert exact_float_spans(Predicates2(below)) == (True, True)
    assert exact_float_spans(Predicates2(at)) == (True, False)
    assert exact_float_spans(Predicates2(at * 2.0**-30 + 7.0)) == (True, False)  # the grain follows the scale
    assert exact_float_spans(Predicates2(below * 2.0**-30 + 7.0)) == (True, True)
    wide = np.array([[0.0, 0.0], [float(ORIENT2D_EXACT_SPAN), 1.0], [3.0, 2.0]])
    assert exact_float_spans(Predicates2(wide)) == (False, False)


def test_the_exact_float_bounds_hold() -> None:
    """The module docstring's arithmetic: every intermediate integer of the determinants stays below 2^53."""
    s = INCIRCLE_EXACT_SPAN
    assert s * s <= 2**53 and 2 * s * s <= 2**53 and 4 * s**4 <= 2**53 and 12 * s**4 <= 2**53
    t = ORIENT2D_EXACT_SPAN
    assert t * t <= 2**53 and 2 * t * t <= 2**53
    # And a worst case of the grid: the extreme determinant is computed exactly (compared with integers).
    rng = np.random.default_rng(5)
    for _ in range(2000):
        q = rng.integers(0, s, size=(4, 2))
        ((ax, ay), (bx, by), (cx, cy), (dx, dy)) = q.tolist()
        det, _ = fp.incircle_terms(*(float(v) for v in (ax, ay, bx, by, cx, cy, dx, dy)))
        exact = fp.incircle_terms(ax, ay, bx, by, cx, cy, dx, dy)[0]  # the same expression on Python ints
        assert det == exact


def test_the_sos_shortcut_is_the_first_term_of_lambda4() -> None:
    """The kernel's shortcut for an incircle zero reads the first term of Λ4 as orient2d of the three largest indices."""
    assert ORIENT3D_SOS[1] == (1, (1, 2, 3), (0, 1, 3))


def test_cocircular_zeros_go_to_sos_in_every_order() -> None:
    """Twelve cocircular integer points (and their collinear triples): every ordered quadruple agrees."""
    pts = np.array(CIRCLE + [(0, 0), (5, 5), (-5, -5)], dtype=float)
    p = Predicates2(pts)
    k = p.kernel()
    assert k.exact_floats
    for quad in itertools.permutations([0, 2, 5, 8, 12, 13], 4):
        assert k.incircle(*quad) == p.incircle(*quad)


@pytest.mark.parametrize(
    "pts",
    [
        [[0.0, 0.0], [1e-300, 1.0], [1e300, 2.0], [3.0, 1e-200], [5.0, 7.0], [-1e300, 1e-300], [2.0, 2.0]],
        [[0.1, 0.2], [1e200, 3e-100], [2.5, 1e-250], [7.0, 8.0], [1e-5, 1e5], [0.0, 0.0], [1e-250, 0.0]],
    ],
)
def test_a_set_needing_grain_checks_gets_the_checked_signs(pts: list[list[float]]) -> None:
    """No uniform filter scale (``filter_scale[1]`` False): the kernel's thresholds are infinite, so no float
    decides, and every test answers what the checked predicate answers (true zeros and SoS included)."""
    p = Predicates2(np.array(pts, dtype=float))
    assert p.filter_scale[1] is False and not p.kernel().exact_floats
    k = p.kernel()
    for a, b, c in itertools.permutations(range(len(pts)), 3):
        assert k.orient2d(a, b, c) == p.orient2d(a, b, c)
        assert k.orient2d_sign(a, b, c) == p.orient2d_sign(a, b, c)
    for a, b, c, d in itertools.permutations(range(len(pts)), 4):
        assert k.incircle(a, b, c, d) == p.incircle(a, b, c, d), (a, b, c, d)


def test_counted_runs_count_as_the_checked_predicates() -> None:
    pts = np.array([[x, y] for y in range(5) for x in range(5)], dtype=float)
    s1, s2 = Stats(), Stats()
    p1, p2 = Predicates2(pts, stats=s1), Predicates2(pts, stats=s2)
    k = p1.kernel()
    for a, b, c, d in itertools.permutations(range(0, 25, 4), 4):
        assert k.incircle(a, b, c, d) == p2.incircle(a, b, c, d)
        assert k.orient2d(a, b, c) == p2.orient2d(a, b, c)
        assert k.orient2d_sign(a, b, d) == p2.orient2d_sign(a, b, d)
    assert s1 == s2 and s1.plane_side_tests > 0


# -- the written-out filters are the proved functions ------------------------------------------


def _kernel2d_function(name: str) -> ast.FunctionDef:
    tree = ast.parse(Path(fp.__file__).with_name("kernel2d.py").read_text(encoding="utf-8"))
    found = [f for f in ast.walk(tree) if isinstance(f, ast.FunctionDef) and f.name == name]
    assert len(found) == 1, name
    return found[0]


@pytest.mark.parametrize(
    ("kernel_fn", "filter_fn"),
    [
        ("incircle_uncounted", fp.incircle_terms),
        ("orient2d_uncounted", fp.orient2d_terms),
        ("orient2d_sign", fp.orient2d_terms),
    ],
)
def test_the_kernels_written_out_filter_is_the_proved_function(kernel_fn: str, filter_fn: object) -> None:
    """The kernel writes the filter expressions out in place: the same statements in the same order as the
    functions proofs/proof_predicates.py analyses, so that they round alike (the permanent of orient2d is
    completed only when the box threshold does not decide: ``abs(detleft) + abs(detright)``, the proved
    function's last statement).  ``incircle`` and ``orient2d`` are the ``_uncounted`` bodies behind the
    counting check."""
    run, _ = _filter_body(filter_fn)  # type: ignore[arg-type]
    if kernel_fn != "incircle_uncounted":
        run = run[:-1]
        completed = ast.dump(ast.parse("thr = o2_errbound * (abs(detleft) + abs(detright))").body[0])
        assert completed in _dumps([n for n in ast.walk(_kernel2d_function(kernel_fn)) if isinstance(n, ast.stmt)])
    assert _contains_in_order(_kernel2d_function(kernel_fn), run)


_coord = st.one_of(
    st.floats(allow_nan=False, allow_infinity=False, min_value=-1e75, max_value=1e75),
    st.floats(allow_nan=False, allow_infinity=False, min_value=-4.0, max_value=4.0),
    st.sampled_from([0.0, 1.0, -1.0, 2.0**-30, 1.0 + 2.0**-52, 3.0 * 2.0**60]),
)


@settings(max_examples=300)
@given(st.lists(st.tuples(_coord, _coord), min_size=4, max_size=10))
def test_the_box_thresholds_bound_every_tests_own_threshold(pts: list[tuple[float, float]]) -> None:
    """The semi-static thresholds of a point set are at least every test's own ``fl(ERRBOUND · permanent)``."""
    every = np.array(pts, dtype=np.float64)
    lo, hi = every.min(axis=0).tolist(), every.max(axis=0).tolist()
    with np.errstate(all="ignore"):
        dx, dy = hi[0] - lo[0], hi[1] - lo[1]
        o2 = fp.orient2d_box_threshold(dx, dy)
        ic = fp.incircle_box_threshold(dx, dy)
        for (ax, ay), (bx, by), (cx, cy), (qx, qy) in itertools.islice(itertools.permutations(pts, 4), 60):
            _, perm = fp.orient2d_terms(ax, ay, bx, by, cx, cy)
            own = fp.ERRBOUND_ORIENT2D * perm
            if own == own:
                assert own <= o2 or o2 != o2, (own, o2)
            _, perm = fp.incircle_terms(ax, ay, bx, by, cx, cy, qx, qy)
            own = fp.ERRBOUND_INCIRCLE * perm
            if own == own:
                assert own <= ic or ic != ic, (own, ic)



@pytest.mark.parametrize(
    ("growing_fn", "filter_fn"),
    [("orient2d_sign", fp.orient2d_terms), ("incircle_sign", fp.incircle_terms), ("dot_sign", dot_terms)],
)
def test_the_growing_predicates_written_out_filters_are_the_proved_functions(growing_fn: str, filter_fn: object) -> None:
    """GrowingPredicates2 (the quality mesh's) writes its filters out as the 2D kernel does: the proved
    function's statements in order, and its permanent (the value of the statement before its ``return``)
    inside the threshold, so that they round alike."""
    tree = ast.parse(Path(fp.__file__).with_name("growing.py").read_text(encoding="utf-8"))
    found = [f for f in ast.walk(tree) if isinstance(f, ast.FunctionDef) and f.name == growing_fn]
    assert len(found) == 1, growing_fn
    run, _ = _filter_body(filter_fn)  # type: ignore[arg-type]
    assert _contains_in_order(found[0], run[:-1])
    fn = ast.parse(textwrap.dedent(inspect.getsource(filter_fn))).body[0]  # type: ignore[arg-type]
    assert isinstance(fn, ast.FunctionDef) and isinstance(fn.body[-2], ast.Assign)
    permanent = ast.dump(ast.parse(ast.unparse(fn.body[-2].value).replace("_abs(", "abs("), mode="eval").body)
    assert any(ast.dump(n) == permanent for n in ast.walk(found[0]) if isinstance(n, ast.expr))
