"""The unvalidated fast path of orient3d (Orient3dKernel) and the setup shortcuts: same answers as the checked API."""

from __future__ import annotations

import ast
import inspect
import textwrap
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray
from test_predicates import point_sets

from persistri.impl.geometry import filter as fp
from persistri.impl.geometry.filter import FLOPS_ORIENT3D, FLOPS_PLANE, FLOPS_PLANE_SIDE
from persistri.impl.geometry.points import unique_rows
from persistri.impl.geometry.kernel import KERNEL_BATCH, MASK_BELOW, SCALAR_BELOW
from persistri.impl.geometry.predicates import Predicates3
from persistri.impl.stats import Stats


def _split(p: Predicates3, a: int, b: int, c: int, qs: list[int]) -> tuple[list[int], list[int]]:
    """The reference: the checked scalar test, point by point, order kept."""
    signs = [p.orient3d(a, b, c, q) for q in qs]
    return [q for q, s in zip(qs, signs) if s < 0], [q for q, s in zip(qs, signs) if s > 0]


def _lists(pair: tuple[object, object]) -> tuple[list[int], list[int]]:
    minus, plus = pair
    return [int(q) for q in minus], [int(q) for q in plus]  # type: ignore[attr-defined]  # list or array


@settings(max_examples=60)
@given(point_sets(min_size=5, max_size=9), st.data())
def test_kernel_agrees_with_the_checked_predicates(pts: NDArray[np.float64], data: st.DataObject) -> None:
    """Degenerate sets (grids, planes, lines, duplicates, extreme scales): the filter fails, exact and SoS decide."""
    p = Predicates3(pts)
    n = len(p)
    k = p.kernel()
    a, b, c = data.draw(st.permutations(range(n)))[:3]
    rest = [q for q in range(n) if q not in (a, b, c)]
    for q in rest:
        assert k.orient3d(a, b, c, q) == p.orient3d(a, b, c, q)
    expected = _split(p, a, b, c, rest)
    assert _lists(k.partition(a, b, c, rest)) == expected
    assert _lists(k.partition(a, b, c, tuple(rest))) == expected
    assert _lists(k.partition(a, b, c, np.array(rest, dtype=np.intp))) == expected


def _grid_with_planes() -> NDArray[np.float64]:
    """A 6×6×6 integer grid: most plane-side tests through grid points are exact zeros (SoS decides)."""
    g = np.arange(6, dtype=float)
    return np.array([[x, y, z] for x in g for y in g for z in g])


def _point_set(kind: str, rng: np.random.Generator, n: int) -> NDArray[np.float64]:
    """``n`` random points in the unit cube, the 6×6×6 grid, or ``n`` grid points of step 1e-3 offset by 1e9."""
    if kind == "random":
        return rng.random((n, 3))
    if kind == "grid":
        return _grid_with_planes()
    return rng.integers(-50, 50, size=(n, 3)).astype(float) * 1e-3 + 1e9


@pytest.mark.parametrize("kind", ["random", "grid", "offset"])
def test_partition_vectorised_path_agrees(kind: str) -> None:
    rng = np.random.default_rng(3)
    pts = _point_set(kind, rng, 400)
    p = Predicates3(pts)
    k = p.kernel()
    n = len(p)
    for a, b, c in ((0, 1, 2), (0, 7, 42), (5, 36, 200)):
        qs = [q for q in rng.permutation(n).tolist() if q not in (a, b, c)]
        assert len(qs) >= KERNEL_BATCH  # the vectorised path
        minus, plus = k.partition(a, b, c, np.array(qs, dtype=np.intp))
        assert isinstance(minus, np.ndarray) and isinstance(plus, np.ndarray)
        assert _lists((minus, plus)) == _split(p, a, b, c, qs)
        assert k.signs(a, b, c, np.array(qs, dtype=np.intp)).tolist() == [p.orient3d(a, b, c, q) for q in qs]
        small = qs[: KERNEL_BATCH - 1]
        got = k.partition(a, b, c, small)
        assert isinstance(got[0], list)
        assert _lists(got) == _split(p, a, b, c, small)



@pytest.mark.parametrize("kind", ["random", "offset"])
def test_partition_by_masks_and_by_index_lists_agree(kind: str) -> None:
    """Below :data:`MASK_BELOW` points the vectorised partition gathers each side by its boolean mask, from there
    on through index lists: either way the checked predicates' lists, in the order given, of the type given."""
    rng = np.random.default_rng(11)
    p = Predicates3(_point_set(kind, rng, 1600))
    k = p.kernel()
    n = len(p)
    for a, b, c in ((0, 1, 2), (3, 500, 900)):
        qs = [q for q in rng.permutation(n).tolist() if q not in (a, b, c)]
        for m in (SCALAR_BELOW, MASK_BELOW - 1, MASK_BELOW, len(qs)):
            part = qs[:m]
            expected = _split(p, a, b, c, part)
            for dtype in (np.int32, np.intp):
                minus, plus = k.partition(a, b, c, np.array(part, dtype=dtype))
                assert isinstance(minus, np.ndarray) and isinstance(plus, np.ndarray)
                assert minus.dtype == plus.dtype == np.dtype(dtype)
                assert _lists((minus, plus)) == expected

def test_partition_with_the_exact_centroid_and_empty_input() -> None:
    """A needle tetrahedron: the float centroid is not inside, the exact one has no float copy (NaN row)."""
    third = 1 / 3
    rng = np.random.default_rng(2)
    pts = np.vstack([[[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0], [third, third, third + 2.0**-52]], rng.random((100, 3)) - 0.2])
    base = Predicates3(pts)
    c = base.with_centroid(0, 1, 2, 3)
    assert not c.centre_is_float
    k = c.kernel()
    centre = len(c) - 1
    qs = list(range(4, centre))
    assert len(qs) >= KERNEL_BATCH
    for arg in (qs, np.array(qs, dtype=np.intp), qs[:5]):
        q_list = [int(q) for q in arg]
        assert _lists(k.partition(centre, 0, 1, arg)) == _split(c, centre, 0, 1, q_list)
        assert _lists(k.partition(0, 1, centre, arg)) == _split(c, 0, 1, centre, q_list)
    assert [k.orient3d(centre, 0, 1, q) for q in qs] == [c.orient3d(centre, 0, 1, q) for q in qs]
    assert k.signs(centre, 0, 1, np.array(qs)).tolist() == [c.orient3d(centre, 0, 1, q) for q in qs]
    assert k.signs(0, 1, 2, np.zeros(0, dtype=np.intp)).tolist() == []
    assert _lists(k.partition(0, 1, 2, [])) == ([], [])
    assert _lists(k.partition(0, 1, 2, np.zeros(0, dtype=np.intp))) == ([], [])


def test_wide_dynamic_range_falls_back_to_the_checked_path() -> None:
    """Grains too far apart for one filter scale: the kernel uses the per-test grain checks, same signs."""
    pts = np.array([[1e300, 0.0, 0.0], [0.0, 1e-300, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0],
                    [2.0**-1000, 3.0, 1e300], [-1e300, 1e-300, 5.0], [7.0, -2.0**-1000, 1.0]] * 6, dtype=float)
    pts = pts + np.arange(pts.shape[0])[:, None] * np.array([[0.0, 0.0, 1.0]])
    p = Predicates3(pts)
    assert p.filter_scale[1] is False
    k = p.kernel()
    qs = list(range(3, len(p)))
    assert _lists(k.partition(0, 1, 2, qs)) == _split(p, 0, 1, 2, qs)
    assert _lists(k.partition(0, 1, 2, np.array(qs))) == _split(p, 0, 1, 2, qs)
    assert [k.orient3d(0, 1, 2, q) for q in qs] == [p.orient3d(0, 1, 2, q) for q in qs]
    assert k.signs(0, 1, 2, np.array(qs)).tolist() == [p.orient3d(0, 1, 2, q) for q in qs]


def test_kernel_counts_like_the_checked_predicates() -> None:
    rng = np.random.default_rng(5)
    stats = Stats()
    p = Predicates3(rng.random((300, 3)), stats=stats)
    k = p.kernel()
    k.orient3d(0, 1, 2, 3)
    assert (stats.plane_side_tests, stats.flops, stats.filter_failures) == (1, FLOPS_ORIENT3D, 0)
    for m in (5, 200):
        stats.reset()
        k.partition(0, 1, 2, list(range(3, 3 + m)))
        assert (stats.plane_side_tests, stats.flops) == (m, FLOPS_PLANE + m * FLOPS_PLANE_SIDE)
    # The grid: exact zeros everywhere on the plane z = 0, each one a filter failure.
    stats = Stats()
    g = Predicates3(_grid_with_planes(), stats=stats)
    a, b, c = 0, 1, 6  # (0,0,0), (0,0,1), (0,1,0): the plane x = 0
    qs = [q for q in range(216) if q not in (a, b, c)]
    g.kernel().partition(a, b, c, qs)
    assert stats.filter_failures == sum(1 for q in qs if g.points[q, 0] == 0.0) > 0


@settings(max_examples=40)
@given(st.integers(4, 40), st.integers(0, 2**32 - 1), st.sampled_from([1.0, 1e-5, 1e5, 2.0**-200]),
       st.sampled_from([0.0, 3.0, 1e9]))
def test_centroid_shortcut_builds_what_the_full_setup_builds(n: int, seed: int, scale: float, offset: float) -> None:
    """with_centroid appends the float centroid without redoing the setup when the filter scale stays: same object."""
    rng = np.random.default_rng(seed)
    pts = rng.random((n, 3)) * scale + offset
    p = Predicates3(pts)
    if p.orient3d_sign(0, 1, 2, 3) == 0:
        return
    guess = ((pts[0] + pts[1]) + (pts[2] + pts[3])) * 0.25 + 0.0
    fast = p._with_row(guess)
    full = Predicates3.__new__(Predicates3)
    full._setup(np.vstack([pts, guess[None, :]]), exact_rows=n + 1, extra=0, stats=None)
    if fast is None:
        assert full.filter_scale != p.filter_scale or not full.filter_scale[1]
        return
    for attr in ("_n", "_dim", "_shift", "_span", "_scale", "_uniform"):
        assert getattr(fast, attr) == getattr(full, attr), attr
    # Rows are made on first use: the same floats once made, whichever were made before.
    assert [fast._row(i) for i in range(n + 1)] == [full._row(i) for i in range(n + 1)]
    assert fast._grain is None and full._grain is None  # uniform sets keep no per-point grains
    assert all(np.array_equal(x, y) for x, y in zip(fast._cols, full._cols))
    assert np.array_equal(fast.points, full.points)


def test_unique_rows_on_real_valued_data_with_planted_duplicates() -> None:
    """Distinct first coordinates take a shortcut; any repeat goes through the full lexicographic sort."""
    rng = np.random.default_rng(11)
    pts = rng.random((500, 3))
    u = unique_rows(pts)
    assert u.first.tolist() == list(range(500)) and u.inverse.tolist() == list(range(500))
    dup = np.vstack([pts, pts[[3, 3, 17]], pts[[17]] * np.array([[1.0, 1.0, 2.0]])])
    u = unique_rows(dup)
    assert u.first.tolist() == list(range(500)) + [503]
    assert u.inverse[500:].tolist() == [3, 3, 17, 500]
    assert np.array_equal(dup[u.first][u.inverse], dup)


# -- the kernel's written-out filters are the proved ones ------------------------------------------


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


def _kernel_function(name: str) -> ast.FunctionDef:
    # The kernel's source files, beside filter.py (inspect cannot read the compiled twin's functions): the
    # scalar paths are closures of Orient3dKernel.__init__ (kernel.py) and of make_split (kernel_split.py).
    found = []
    for module, factory in (("kernel.py", "__init__"), ("kernel_split.py", "make_split")):
        tree = ast.parse(Path(fp.__file__).with_name(module).read_text(encoding="utf-8"))
        (outer,) = [f for f in ast.walk(tree) if isinstance(f, ast.FunctionDef) and f.name == factory]
        found += [f for f in ast.walk(outer) if isinstance(f, ast.FunctionDef) and f.name == name]
    assert len(found) == 1, name
    return found[0]


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


@pytest.mark.parametrize(
    ("kernel_fn", "filter_fn"),
    [("orient3d", fp.orient3d_terms), ("partition", fp.plane_terms), ("partition", fp.plane_side_det)],
)
def test_the_kernels_written_out_filter_is_the_proved_function(kernel_fn: str, filter_fn: Callable[..., Any]) -> None:
    """The kernel's scalar paths write the filter expressions out in place (no call per test): they must be
    the statements of the functions ``proofs/proof_predicates.py`` analyses, in the same order, so that
    they round exactly alike — any edit to one without the other fails here."""
    run, returned = _filter_body(filter_fn)
    fn = _kernel_function(kernel_fn)
    assert _contains_in_order(fn, run), f"Orient3dKernel.{kernel_fn} does not contain the body of filter.{filter_fn.__name__}"
    read = {n.id for n in ast.walk(fn) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load)}
    assert set(returned) <= read, "the kernel reads the values the filter function returns, by the same names"


def test_the_partitions_own_threshold_completes_the_proved_function() -> None:
    """The partition's fallback for a point the semi-static threshold leaves undecided computes the
    differences and the permanent as ``plane_side_terms`` does (its determinant is ``plane_side_det``,
    bitwise the same, checked below): together the kernel's scalar path is the proved function."""
    terms_body, returned = _filter_body(fp.plane_side_terms)
    assert returned == ["det", "permanent"]
    assert _contains_run(_kernel_function("partition"), terms_body[:3] + terms_body[-1:])


_finite = st.floats(allow_nan=False, allow_infinity=False, min_value=-1e75, max_value=1e75)  # every result finite (no NaN to compare)


@settings(max_examples=200)
@given(st.lists(_finite, min_size=9, max_size=9), st.lists(st.tuples(_finite, _finite, _finite), min_size=1, max_size=20))
def test_the_in_place_plane_side_is_the_proved_function_bit_for_bit(
    abc: list[float], qs: list[tuple[float, float, float]]
) -> None:
    """``plane_side_terms_into`` (the vectorised partition's form) computes in its input buffers: its
    results must be bitwise those of ``plane_side_terms``, the function the filter constant is proved for."""
    ax, ay, az, bx, by, bz, cx, cy, cz = abc
    with np.errstate(all="ignore"):
        terms = fp.plane_terms(ax, ay, az, bx, by, bz, cx, cy, cz)
        q = np.array(qs, dtype=np.float64)
        det, perm = fp.plane_side_terms(*terms, ax, ay, az, q[:, 0], q[:, 1], q[:, 2])
        det2, perm2 = fp.plane_side_terms_into(*terms, ax, ay, az, q[:, 0].copy(), q[:, 1].copy(), q[:, 2].copy())
    assert det.tobytes() == det2.tobytes()
    assert perm.tobytes() == perm2.tobytes()
    # And each entry is what the scalar expression gives for that point alone (Python floats).
    for i, (qx, qy, qz) in enumerate(qs):
        with np.errstate(all="ignore"):
            d, p = fp.plane_side_terms(*terms, ax, ay, az, qx, qy, qz)
        assert np.float64(d).tobytes() == det2[i].tobytes() and np.float64(p).tobytes() == perm2[i].tobytes()


_coord = st.one_of(
    _finite,
    st.floats(allow_nan=False, allow_infinity=False, min_value=-4.0, max_value=4.0),
    st.sampled_from([0.0, 1.0, -1.0, 2.0**-30, 1.0 + 2.0**-52, 3.0 * 2.0**60]),
)


@settings(max_examples=300)
@given(st.lists(_coord, min_size=9, max_size=9), st.lists(st.tuples(_coord, _coord, _coord), min_size=1, max_size=12))
def test_the_semi_static_thresholds_bound_every_tests_own_threshold(
    abc: list[float], qs: list[tuple[float, float, float]]
) -> None:
    """The box thresholds of a point set are at least the own computed threshold
    ``fl(ERRBOUND · permanent)`` of every test among its points — the threshold the filter constants are
    proved for (rounding is monotone) — for orient3d and for the prepared-plane test alike.  So whatever
    they decide, the proved filters decide alike."""
    ax, ay, az, bx, by, bz, cx, cy, cz = abc
    every = np.array([(ax, ay, az), (bx, by, bz), (cx, cy, cz), *qs], dtype=np.float64)
    lo, hi = every.min(axis=0).tolist(), every.max(axis=0).tolist()
    with np.errstate(all="ignore"):
        sides = (hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2])
        o3_static = fp.orient3d_box_threshold(*sides)
        side_static = fp.plane_side_box_threshold(*sides)
        nx, ny, nz, px, py, pz = fp.plane_terms(ax, ay, az, bx, by, bz, cx, cy, cz)
        for qx, qy, qz in qs:
            det, permanent = fp.plane_side_terms(nx, ny, nz, px, py, pz, ax, ay, az, qx, qy, qz)
            assert det == fp.plane_side_det(nx, ny, nz, ax, ay, az, qx, qy, qz) or det != det
            own = fp.ERRBOUND_PLANE_SIDE * permanent
            if own == own:  # NaN (from inf - inf) decides nothing either way
                assert own <= side_static or side_static != side_static, (own, side_static)
            _, permanent = fp.orient3d_terms(ax, ay, az, bx, by, bz, cx, cy, cz, qx, qy, qz)
            own = fp.ERRBOUND_ORIENT3D * permanent
            if own == own:
                assert own <= o3_static or o3_static != o3_static, (own, o3_static)


@settings(max_examples=100)
@given(st.lists(_finite, min_size=9, max_size=9), st.lists(st.tuples(_finite, _finite, _finite), min_size=1, max_size=20))
def test_the_in_place_determinant_is_the_proved_one_bit_for_bit(
    abc: list[float], qs: list[tuple[float, float, float]]
) -> None:
    """``plane_side_det`` (the kernel's scalar loop) and ``plane_side_det_into`` (its vectorised stage) give
    bitwise the det of ``plane_side_terms``, the function the filter constant is proved for."""
    ax, ay, az, bx, by, bz, cx, cy, cz = abc
    with np.errstate(all="ignore"):
        nx, ny, nz, px, py, pz = fp.plane_terms(ax, ay, az, bx, by, bz, cx, cy, cz)
        q = np.array(qs, dtype=np.float64)
        det, _ = fp.plane_side_terms(nx, ny, nz, px, py, pz, ax, ay, az, q[:, 0], q[:, 1], q[:, 2])
        det2 = fp.plane_side_det_into(nx, ny, nz, ax, ay, az, q[:, 0].copy(), q[:, 1].copy(), q[:, 2].copy())
        det3 = [fp.plane_side_det(nx, ny, nz, ax, ay, az, qx, qy, qz) for qx, qy, qz in qs]
        # The kernel passes the plane's numbers as 0-d arrays: the same float64 operands.
        zero_d = [np.asarray(v) for v in (nx, ny, nz, ax, ay, az)]
        det4 = fp.plane_side_det_into(*zero_d, q[:, 0].copy(), q[:, 1].copy(), q[:, 2].copy())
    assert det.tobytes() == det2.tobytes() == np.array(det3, dtype=np.float64).tobytes() == det4.tobytes()


@pytest.mark.parametrize("kind", ["random", "grid", "offset"])
def test_counted_and_uncounted_partitions_agree(kind: str) -> None:
    """Uncounted, the partition tests against the semi-static threshold first; counted, every point against
    its own: the same exact answers (the grid's exact zeros included), at every size."""
    p = Predicates3(_point_set(kind, np.random.default_rng(5), 300))
    k = p.kernel()
    for a, b, c in ((0, 1, 2), (0, 7, 42), (5, 36, 200)):
        qs = [q for q in range(len(p)) if q not in (a, b, c)]
        for part in (qs[:5], qs):
            p.stats = None
            fast = _lists(k.partition(a, b, c, part))
            p.stats = Stats()
            counted = _lists(k.partition(a, b, c, np.array(part, dtype=np.intp)))
            assert fast == counted == _split(p, a, b, c, part)


def test_rows_are_made_on_first_use_and_are_the_scaled_copy() -> None:
    """Predicates3 makes a point's tuple of floats (the scalar tests' operands) when a test first reads it,
    with its block; the kernel's scalar paths and the checked API make them alike, to the same floats."""
    rng = np.random.default_rng(8)
    pts = rng.random((200, 3)) * 3.0 - 1.0
    p = Predicates3(pts)
    assert not any(p._rows)  # nothing made yet
    k = p.kernel()
    assert k.orient3d(150, 3, 77, 199) == p.orient3d(150, 3, 77, 199)
    made = [i for i, r in enumerate(p._rows) if r]
    assert 0 < len(made) < 200 and {150, 3, 77, 199} <= set(made)
    assert _lists(k.partition(120, 5, 60, [180, 181, 40])) == _split(p, 120, 5, 60, [180, 181, 40])
    shift, _ = p.filter_scale
    for i in range(200):
        assert p._row(i) == tuple(np.ldexp(pts[i], shift).tolist())


# -- split: three partitions in one pass ----------------------------------------------------------------


def _split_reference(
    p: Predicates3, a: int, b: int, c: int, qs: list[int], lo: tuple[int, int, int] | None, hi: tuple[int, int, int] | None
) -> tuple[list[int], list[int], list[int], list[int]]:
    """What ``split`` stands for: the checked test by (a, b, c), then each side by its own plane (or whole)."""
    minus, plus = _split(p, a, b, c, qs)
    mm, mp = _split(p, *lo, minus) if lo is not None else (minus, [])
    pm, pp = _split(p, *hi, plus) if hi is not None else (plus, [])
    return mm, mp, pm, pp


def _four(got: tuple[object, object, object, object]) -> tuple[list[int], ...]:
    return tuple([int(q) for q in part] for part in got)  # type: ignore[attr-defined]  # list, tuple or array


@pytest.mark.parametrize("kind", ["random", "grid", "offset"])
def test_split_is_the_three_partitions_it_stands_for(kind: str) -> None:
    """The same lists in the same order as the partitions (the grid's exact zeros decided by SoS), short
    (one pass) and long (the partitions themselves), with either second plane absent, counted or not —
    and counted alike: the same tests, flops and filter failures as the three partition calls."""
    rng = np.random.default_rng(11)
    p = Predicates3(_point_set(kind, rng, 300))
    k = p.kernel()
    planes = ((0, 1, 2), (0, 7, 42), (5, 36, 200), (3, 9, 27))
    for a, b, c in planes[:3]:
        used = {i for plane in planes for i in plane}  # no point is tested against a plane through it
        rest = [q for q in rng.permutation(len(p)).tolist() if q not in used]
        for lo, hi in ((planes[3], planes[1]), (None, planes[3]), (planes[2], None), (None, None)):
            for part in (rest[:1], rest[:9], rest[: KERNEL_BATCH - 1], rest):
                want = _split_reference(p, a, b, c, part, lo, hi)
                p.stats = None
                assert _four(k.split(a, b, c, part, lo, hi)) == want
                assert _four(k.split(a, b, c, tuple(part), lo, hi)) == want
                assert _four(k.split(a, b, c, np.array(part, dtype=np.intp), lo, hi)) == want
                p.stats = fused = Stats()
                assert _four(k.split(a, b, c, part, lo, hi)) == want
                p.stats = separate = Stats()
                minus, plus = k.partition(a, b, c, part)
                if lo is not None:
                    k.partition(*lo, minus)
                if hi is not None:
                    k.partition(*hi, plus)
                assert fused.as_dict() == separate.as_dict()
    p.stats = None
    assert k.split(0, 1, 2, [], planes[3], None) == ((), (), (), ())


def test_split_on_the_checked_path() -> None:
    """A point set with per-test grain checks: split is the checked partitions, composed."""
    pts = np.array([[1e300, 0.0, 0.0], [0.0, 1e-300, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0],
                    [2.0**-1000, 3.0, 1e300], [-1e300, 1e-300, 5.0], [7.0, -2.0**-1000, 1.0]] * 6, dtype=float)
    pts = pts + np.arange(pts.shape[0])[:, None] * np.array([[0.0, 0.0, 1.0]])
    p = Predicates3(pts)
    assert p.filter_scale[1] is False
    k = p.kernel()
    qs = list(range(6, len(p)))
    assert _four(k.split(0, 1, 2, qs, (3, 4, 5), (1, 3, 5))) == _split_reference(p, 0, 1, 2, qs, (3, 4, 5), (1, 3, 5))


class _Unsuffix(ast.NodeTransformer):
    """Names with ``suffix`` read without it: split's second-level planes are the first plane's statements."""

    def __init__(self, suffix: str) -> None:
        self.suffix = suffix

    def visit_Name(self, node: ast.Name) -> ast.Name:
        if node.id.endswith(self.suffix):
            return ast.Name(id=node.id[: -len(self.suffix)], ctx=node.ctx)
        return node


@pytest.mark.parametrize("suffix", ["", "_lo", "_hi"])
def test_splits_written_out_filters_are_the_proved_functions(suffix: str) -> None:
    """split writes the plane's terms and each point's determinant out for its three planes (the second
    and third with names suffixed ``_lo`` and ``_hi``): each must be the proved functions' statements in
    order; ``settle`` (a point the semi-static stage leaves undecided) completes them with the plane's
    permanents and the point's own threshold, as ``partition`` does."""
    fn = _kernel_function("split")
    if suffix:
        renamed = _Unsuffix(suffix).visit(ast.parse(ast.unparse(fn)).body[0])
        assert isinstance(renamed, ast.FunctionDef)
        fn = renamed
    plane, _ = _filter_body(fp.plane_terms)
    det, _ = _filter_body(fp.plane_side_det)
    assert _contains_in_order(fn, plane[:-3]), f"split's plane{suffix} is not filter.plane_terms"
    assert _contains_in_order(fn, det), f"split's determinant{suffix} is not filter.plane_side_det"
    settle = _kernel_function("settle")
    terms_body, _ = _filter_body(fp.plane_side_terms)
    assert _contains_in_order(settle, plane[-3:])
    assert _contains_run(settle, terms_body[:3] + terms_body[-1:])
