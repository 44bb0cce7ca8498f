"""Futures of one version as Dask tasks (:mod:`persistri.impl.scale.futures`) equal the same calls in turn."""

from __future__ import annotations

import pickle
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest
from distributed import Client

from persistri.impl.hull.api import convex_hull
from persistri.impl.hull.distributions import generate
from persistri.impl.hull.extend import extend_hull
from persistri.impl.mesh.api import QualityMesh, refine, triangulate
from persistri.impl.mesh.gallery import gallery_domain
from persistri.impl.scale.cluster import connect
from persistri.impl.scale.futures import extend_many, futures, refine_many


@pytest.fixture(scope="module")
def client() -> Iterator[Client]:
    with connect(workers=2) as c:
        assert c is not None
        yield c


def arrays(m: QualityMesh) -> list[Any]:
    return [m.vertices, m.triangles, m.segments, m.segment_of, m.regions]


def counts(m: QualityMesh) -> tuple[Any, ...]:
    return (
        m.insertions, m.segment_splits, m.circumcenters, m.offcenters, m.undos, m.deletions, m.blocked, m.exempt,
        m.rounded_splits, m.rounding_retries, m.min_angle_reached, m.max_area_reached, len(m.history), m.notes,
    )


BOUNDS: list[dict[str, Any]] = [
    {"min_angle": 30},
    {"min_angle": 20, "max_area": 0.002},
    {"min_angle": 33, "max_area": 0.02, "offcenters": False},
    {"min_angle": 25, "encroachment": "circle"},
]


def test_refinements_on_two_workers_equal_the_sequential_ones(client: Client, monkeypatch: pytest.MonkeyPatch) -> None:
    cdt = triangulate(gallery_domain("circle").pslg)
    before = [a.copy() for a in arrays(cdt)]
    sequential = [refine(cdt, **b) for b in BOUNDS]
    pickled = 0
    dumps = pickle.dumps

    def counting(obj: Any, *args: Any, **kwargs: Any) -> bytes:
        nonlocal pickled
        pickled += obj is cdt
        return dumps(obj, *args, **kwargs)

    monkeypatch.setattr(pickle, "dumps", counting)  # the module futures_module pickles with
    parallel = refine_many(cdt, BOUNDS, client=client)
    monkeypatch.undo()
    assert pickled == 1  # the version is pickled once, for every future
    assert len(parallel) == len(BOUNDS)
    for s, p in zip(sequential, parallel, strict=True):
        for a, b in zip(arrays(s), arrays(p), strict=True):
            assert a.dtype == b.dtype and np.array_equal(a, b)
        assert counts(s) == counts(p)
        assert p.history.mesh(0).triangles.tolist() == cdt.triangles.tolist()  # each future starts at the version
        assert len(p.history) > 1
    # The version is unchanged, its later futures too, and every past version of a future still reads back.
    assert all(np.array_equal(a, b) for a, b in zip(before, arrays(cdt), strict=True))
    mid = parallel[1].history.mesh(len(parallel[1].history) // 2)
    assert mid.triangles.shape[1] == 3 and 0 < len(mid.triangles) < len(parallel[1].triangles)


def test_in_process_the_futures_share_the_version_itself() -> None:
    cdt = triangulate(gallery_domain("l-shape").pslg)
    got = refine_many(cdt, BOUNDS[:2])
    assert got[0].history[0] is got[1].history[0] is cdt.complex
    assert [counts(m) for m in got] == [counts(refine(cdt, **b)) for b in BOUNDS[:2]]


def test_bad_bounds_are_errors_before_anything_runs(client: Client) -> None:
    cdt = triangulate(gallery_domain("square-hole").pslg)
    with pytest.raises(TypeError, match=r"bounds\[1\]: unknown refine option 'min_angel'"):
        refine_many(cdt, [{"min_angle": 20}, {"min_angel": 20}], client=client)
    with pytest.raises(TypeError, match=r"bounds\[0\]: min_angle is required"):
        refine_many(cdt, [{"max_area": 1.0}], client=client)
    with pytest.raises(TypeError, match="takes a QualityMesh"):
        refine_many(cdt.complex, [{"min_angle": 20}])  # type: ignore[arg-type]


def test_a_failing_future_raises_its_own_error(client: Client) -> None:
    cdt = triangulate(gallery_domain("square-hole").pslg)
    with pytest.raises(ValueError) as here:
        refine(cdt, min_angle=80)
    with pytest.raises(ValueError) as there:
        refine_many(cdt, [{"min_angle": 20}, {"min_angle": 80}], client=client)
    assert str(there.value) == str(here.value)


def test_hull_extensions_on_two_workers(client: Client) -> None:
    hull = convex_hull(generate("InBall", 3_000, 1), history=True)
    more = [generate("BordHeavy", 500, s) * 1.2 for s in range(3)] + [np.round(generate("OnSphere", 200, 9), 1)]
    sequential = [extend_hull(hull, p) for p in more]
    parallel = extend_many(hull, more, client=client)
    for s, p in zip(sequential, parallel, strict=True):
        assert np.array_equal(s.simplices, p.simplices) and np.array_equal(s.vertices, p.vertices)
        assert s.duplicates == p.duplicates and s.insertions == p.insertions
        assert p.history is not None and len(p.history) == len(s.history or ())


def test_futures_of_any_module_level_function(client: Client) -> None:
    pts = generate("InBall", 2_000, 3)
    got = futures(convex_hull, pts, [{"seed": 1}, {"seed": 2, "labels": "input"}], client=client)
    assert all(np.array_equal(g.simplices, convex_hull(pts).simplices) for g in got)
