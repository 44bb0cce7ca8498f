"""The hull kernel's vectorised determinant: ``negated_plane_side_dets`` is minus the proved
``filter.plane_side_det_into``, bit for bit up to the sign of a zero, and the vectorised partition runs its
statements in place, in order (read from the source, as ``test_predicates_kernel_filters.py`` reads the scalar
paths).
"""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from persistri.impl.geometry import filter as fp
from persistri.impl.geometry.kernel import negated_plane_side_dets

# The vectorised partition's names for negated_plane_side_dets' arguments.
_RENAMED = {"gx": "qx", "gy": "qy", "gz": "qz", "ax_0d": "ax", "ay_0d": "ay", "az_0d": "az", "nx_0d": "nx", "ny_0d": "ny", "nz_0d": "nz"}


class _Rename(ast.NodeTransformer):
    def visit_Name(self, node: ast.Name) -> ast.Name:
        return ast.Name(id=_RENAMED.get(node.id, node.id), ctx=node.ctx)


def _dumps(stmts: list[ast.stmt]) -> list[str]:
    return [ast.dump(_Rename().visit(s)) for s in stmts]


def _function(tree: ast.AST, name: str) -> ast.FunctionDef:
    (fn,) = [f for f in ast.walk(tree) if isinstance(f, ast.FunctionDef) and f.name == name]
    return fn


def test_the_vectorised_partition_runs_the_negated_determinants_statements() -> None:
    """The partition's mask path writes ``negated_plane_side_dets`` out in place: the same statements, in one run."""
    tree = ast.parse(Path(fp.__file__).with_name("kernel_vector.py").read_text(encoding="utf-8"))
    body = _function(tree, "negated_plane_side_dets").body[1:]  # after the docstring
    assert isinstance(body[-1], ast.Return)
    want = _dumps(body[:-1])
    assert len(want) == 8
    partition = _function(_function(tree, "make_vectorised"), "wide")  # the partition of long lists
    runs = 0
    for node in ast.walk(partition):
        block = getattr(node, "body", None)
        if isinstance(block, list) and block and isinstance(block[0], ast.stmt):
            got = _dumps(block)
            runs += sum(got[i : i + len(want)] == want for i in range(len(got)))
    assert runs == 1


_coord = st.floats(allow_nan=False, allow_infinity=False, min_value=-1e75, max_value=1e75)


@settings(max_examples=300, deadline=None)
@given(
    plane=st.tuples(*[_coord] * 6),
    qs=st.lists(st.tuples(_coord, _coord, _coord), min_size=1, max_size=40),
    zero_d=st.booleans(),
)
def test_the_negated_determinants_are_the_proved_ones_negated(
    plane: tuple[float, float, float, float, float, float], qs: list[tuple[float, float, float]], zero_d: bool
) -> None:
    """Each entry is ``-plane_side_det_into``'s, the same double (a zero of either sign aside), with the plane's
    numbers as floats or as 0-d arrays; so each side's comparison with a threshold ``t >= 0`` agrees."""
    ax, ay, az, nx, ny, nz = plane
    q = np.array(qs, dtype=np.float64)
    det = fp.plane_side_det_into(nx, ny, nz, ax, ay, az, q[:, 0].copy(), q[:, 1].copy(), q[:, 2].copy())
    args = [np.asarray(v) for v in (ax, ay, az, nx, ny, nz)] if zero_d else [ax, ay, az, nx, ny, nz]
    neg = negated_plane_side_dets(q[:, 0].copy(), q[:, 1].copy(), q[:, 2].copy(), *args)
    assert np.array_equal(neg, -det)
    nonzero = det != 0
    assert np.array_equal(np.signbit(neg[nonzero]), ~np.signbit(det[nonzero]))
    for t in (0.0, 1e-300, float(np.abs(det).min()), float(np.median(np.abs(det)))):
        assert np.array_equal(neg > t, det < -t)
        assert np.array_equal(neg < -t, det > t)


def test_the_negated_determinants_at_exact_zeros_and_ties() -> None:
    """Points on the plane (exact zeros) and rounding ties: the same decisions either way."""
    ax, ay, az = 1.0, 2.0, 3.0
    nx, ny, nz = 1.0, -1.0, 0.5
    q = np.array([[1.0, 2.0, 3.0], [2.0, 3.0, 3.0], [1.0 + 2**-52, 2.0, 3.0], [0.5, 1.5, 2.0], [3.0, 1.0, -1.0]])
    det = fp.plane_side_det_into(nx, ny, nz, ax, ay, az, q[:, 0].copy(), q[:, 1].copy(), q[:, 2].copy())
    neg = negated_plane_side_dets(q[:, 0].copy(), q[:, 1].copy(), q[:, 2].copy(), ax, ay, az, nx, ny, nz)
    assert np.array_equal(neg, -det)
    assert (det == 0).sum() >= 2
    assert np.array_equal(neg > 0.0, det < -0.0) and np.array_equal(neg < -0.0, det > 0.0)
