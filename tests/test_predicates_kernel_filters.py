"""The kernel's written-out filters are the proved ones: Orient3dKernel's scalar paths and split write the
filter expressions of :mod:`persistri.impl.geometry.filter` out in place (no call per test); their statements,
read from the source, must be those of the functions ``proofs/proof_predicates.py`` analyses, and the in-place
and vectorised forms must round bit for bit alike.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from filter_source_helpers import _contains_in_order, _contains_run, _filter_body
from persistri.impl.geometry import filter as fp


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
