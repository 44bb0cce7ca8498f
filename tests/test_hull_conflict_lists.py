"""The stored form of conflict lists and the kernel's two partition paths around their thresholds.

The kernel's ``partition`` loops over the points below ``SCALAR_BELOW`` (``KERNEL_BATCH``
interpreted, ``COMPILED_BATCH`` in the compiled twin) and runs vectorised from there; the
bulldozer stores a list as a tuple below ``KERNEL_BATCH`` entries and as a read-only int32 array
from there, whatever form it arrives in — so both builds keep the same versions.
"""

from __future__ import annotations

import numpy as np
import pytest

from persistri.impl.geometry.kernel import COMPILED, COMPILED_BATCH, KERNEL_BATCH, SCALAR_BELOW
from persistri.impl.geometry.predicates import Predicates3
from persistri.impl.hull.conflicts import _freeze


def test_the_scalar_threshold_is_the_builds() -> None:
    assert SCALAR_BELOW == (COMPILED_BATCH if COMPILED else KERNEL_BATCH)
    assert COMPILED_BATCH >= KERNEL_BATCH


@pytest.mark.parametrize("m", [0, 1, KERNEL_BATCH - 1, KERNEL_BATCH, COMPILED_BATCH - 1, COMPILED_BATCH, 300])
def test_a_list_is_stored_by_its_length_alone(m: int) -> None:
    pts = list(range(7, 7 + m))
    for given in (pts, tuple(pts), np.array(pts, dtype=np.intp), np.array(pts, dtype=np.int32)):
        stored = _freeze(given)
        if m < KERNEL_BATCH:
            assert type(stored) is tuple and stored == tuple(pts)
        else:
            assert isinstance(stored, np.ndarray) and stored.dtype == np.int32 and not stored.flags.writeable
            assert stored.tolist() == pts


@pytest.mark.parametrize("m", [KERNEL_BATCH - 1, KERNEL_BATCH, (KERNEL_BATCH + COMPILED_BATCH) // 2, COMPILED_BATCH - 1, COMPILED_BATCH])
def test_partition_around_both_thresholds_matches_the_checked_signs(m: int) -> None:
    """The lists (or arrays) each side returns are those of the checked orient3d, in input order."""
    rng = np.random.default_rng(m)
    pts = rng.random((m + 3, 3))
    pred = Predicates3(pts)
    k = pred.kernel()
    qs = list(range(3, m + 3))
    want_minus = [q for q in qs if pred.orient3d(0, 1, 2, q) < 0]
    want_plus = [q for q in qs if pred.orient3d(0, 1, 2, q) > 0]
    for given in (qs, tuple(qs), np.array(qs, dtype=np.int32), np.array(qs, dtype=np.intp)):
        minus, plus = k.partition(0, 1, 2, given)
        assert list(map(int, minus)) == want_minus and list(map(int, plus)) == want_plus
        assert isinstance(minus, np.ndarray) == (m >= SCALAR_BELOW)


def test_of_validated_is_the_checked_constructor() -> None:
    rng = np.random.default_rng(4)
    pts = rng.random((200, 3)) * 1e3
    a, b = Predicates3(pts), Predicates3.of_validated(pts.copy())
    assert a.filter_scale == b.filter_scale and len(a) == len(b)
    qs = np.arange(3, 200)
    assert a.orient3d_batch(0, 1, 2, qs).tolist() == b.orient3d_batch(0, 1, 2, qs).tolist()
    assert a.with_centroid(0, 1, 2, 3).points.tobytes() == b.with_centroid(0, 1, 2, 3).points.tobytes()
