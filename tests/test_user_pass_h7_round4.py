"""H7's fourth new-user pass: an installed wheel, scipy.spatial side by side, the conformance suite from outside.

Each test fails without the fix it names (the conformance suite's own are in
``test_conformance_rejects_broken.py``).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.spatial import Delaunay as QhullDelaunay

import persistri
from broken_maps import BareAssertCheckMap
from outside_complex import LowGrepOneOrientation, VerticesDropTheLast, outside_complex
from persistri.spec.conformance import SIMPCOMP_TESTS, run_conformance, run_simpcomp_conformance
from persistri.spec.law import raised


@pytest.mark.parametrize("size", [1e-160, 1e-120, 1e-80, 1e-60])
def test_lifted_planes_of_tiny_inputs_are_finite_and_agree_with_scipy(size: float) -> None:
    # The cross product of two edge vectors of size 1e-80 squares to 1e-320 and its norm underflowed: the
    # normals, equations and plane_distance were NaN where scipy's are numbers.
    rng = np.random.default_rng(3)
    pts = rng.random((30, 2)) * size
    tri, ref = persistri.Delaunay(pts), QhullDelaunay(pts)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow, underflow-to-NaN or division by zero on the way
        eq = tri.equations
        queries = (rng.random((20, 2)) * 0.8 + 0.1) * size
        dist = tri.plane_distance(queries)
    assert np.isfinite(eq).all() and np.allclose(np.linalg.norm(eq[:, :3], axis=1), 1.0)
    assert (eq[:, 2] < 0).all()
    # The same triangles as Qhull's (random points), and the same side of every lifted plane.
    index = {tuple(sorted(t)): i for i, t in enumerate(ref.simplices.tolist())}
    order = [index[tuple(sorted(t))] for t in tri.simplices.tolist()]
    want = ref.plane_distance(queries)[:, order]
    clear = np.abs(want) > 1e-9 * np.abs(want).max()
    assert (np.sign(dist)[clear] == np.sign(want)[clear]).all()
    # Inside a triangle's circumcircle (its centroid) is below its plane.
    a, b, c = (pts[tri.simplices[:, k]] for k in range(3))
    assert (np.diagonal(tri.plane_distance((a + b + c) / 3)) > 0).all()


def test_a_check_that_fails_a_bare_assert_is_named_by_its_line() -> None:
    # An AssertionError without a message printed as "_check(m) raised AssertionError: " and nothing more.
    report = run_conformance(BareAssertCheckMap(), tests=("invariants",), max_examples=30, derandomize=True)
    (failure,) = report.failures
    assert failure.law == "invariants"
    assert "raised AssertionError at " in failure.detail, failure.detail
    assert "broken_maps.py:" in failure.detail and "(assert self.numItems(m) < 3)" in failure.detail


def test_exceptions_are_described_with_their_message_or_their_line() -> None:
    assert raised(KeyError(0)) == "KeyError: 0"
    try:
        exec(compile("x = 1\nassert x == 3", "<user code>", "exec"))  # not rewritten by pytest: no message
    except AssertionError as exc:
        assert raised(exc) == "AssertionError at <user code>:2"
    else:
        raise AssertionError("the assert did not fail")
    assert raised(AssertionError()) == "AssertionError (no message)"


@pytest.mark.build_independent
def test_an_outside_complex_whose_vertices_compare_by_identity_conforms() -> None:
    # Each determinism session makes its vertices afresh; answers holding them were compared with ==, so a
    # correct complex whose vertices have identity equality failed determinism ("find(version 1, …) answered
    # (<…object at 0x7fc3…>, …) …, and (<…object at 0x7fc3…>, …)").  Vertices are now compared by place.
    report = run_simpcomp_conformance(
        outside_complex, state=lambda: 0, dims=(2, 3), max_examples=10, workload_size=20, stateful_steps=6,
        derandomize=True, name="outside complex",
    )
    assert report.ok, report.format()
    assert report.count("passed") == len(SIMPCOMP_TESTS) - 1  # invariants skipped: no check(c)


@pytest.mark.build_independent
@pytest.mark.parametrize(
    ("broken", "test", "seen"),
    [(LowGrepOneOrientation(), "grep", "expected the 2-faces [["), (VerticesDropTheLast(), "agrees", "vertices(c) = [")],
)
def test_a_broken_outside_complex_is_named_by_its_law_not_by_a_crash_of_the_message(broken: object, test: str, seen: str) -> None:
    # The laws sorted the expected vertices with Python's < to print them: vertices ordered by compare alone
    # made the message itself raise TypeError, reported as "the structure raised TypeError: '<' not supported".
    report = run_simpcomp_conformance(
        broken, state=lambda: 0, dims=(3,), max_examples=20, workload_size=10, stateful_steps=4,
        derandomize=True, tests=(test,),
    )
    (failure,) = report.failures
    assert failure.law == test and seen in failure.detail, failure.detail
    assert "TypeError" not in failure.detail
