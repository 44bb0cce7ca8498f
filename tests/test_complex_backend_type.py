"""A backend that is neither a backend's name nor an ORD_MAP structure: a TypeError saying so, not an
AttributeError from deep inside the complex (``'int' object has no attribute 'insert'``)."""

from __future__ import annotations

import numpy as np
import pytest

import persistri


@pytest.mark.parametrize("backend", [3, None, object()])
def test_a_backend_that_is_no_map_is_refused_by_name(backend: object) -> None:
    pts = np.random.default_rng(0).random((20, 3))
    with pytest.raises(TypeError, match=r"^backend must be a map backend's name or an ORD_MAP structure, not \w+"):
        persistri.ConvexHull(pts, backend=backend)  # type: ignore[call-overload]
    with pytest.raises(TypeError, match="backend must be"):
        persistri.convex_hull(pts, backend=backend)  # type: ignore[arg-type]
