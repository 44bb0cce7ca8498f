"""Greedy insertion (paper §5): known answers, hypothesis grids verified exactly, pydelatin, history, bad input."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numpy.typing import NDArray

from persistri.impl.complex.checks import check_closed_surface
from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.stats import Stats
from persistri.impl.terrain.check import TerrainCheckError, mesh_errors, verify_tin
from persistri.impl.terrain.greedy import Tin, greedy_insertion
from persistri.impl.terrain.grids import GridTransform, jacksboro


def assert_sound(tin: Tin, heights: NDArray[np.float64]) -> None:
    """The exact verification, plus the conventions of ``Tin`` checked directly."""
    verify_tin(tin, heights).raise_if_failed()
    check_closed_surface(tin.complex)
    rows, cols = heights.shape
    v = tin.vertices
    assert np.array_equal(v[:, 0], tin.samples % cols)  # x = column
    assert np.array_equal(v[:, 1], tin.samples // cols)  # y = row, no flip
    assert np.array_equal(v[:, 2], heights.ravel()[tin.samples])
    assert tin.samples[:4].tolist() == [0, cols - 1, rows * cols - 1, (rows - 1) * cols]
    pred = Predicates2(v[:, :2])
    assert all(pred.orient2d_sign(int(a), int(b), int(c)) > 0 for a, b, c in tin.triangles)


# -- known answers -------------------------------------------------------------------------


@pytest.mark.parametrize(
    "heights",
    [
        np.zeros((5, 7)),
        np.full((9, 4), 3.25),
        np.fromfunction(lambda r, c: 2 * r - 3 * c + 1, (11, 13)),
        np.fromfunction(lambda r, c: 0.5 * r + 0.25 * c, (6, 30)),
    ],
    ids=["zero", "constant", "integer-plane", "dyadic-plane"],
)
def test_a_plane_needs_only_the_four_corners(heights: NDArray[np.float64]) -> None:
    tin = greedy_insertion(heights, max_error=0.0, check=True)
    assert tin.n_points == 4 and tin.triangles.shape == (2, 3)
    assert tin.max_error == 0.0 and tin.rms_error == 0.0
    # Asking for more points adds none: the mesh is already exact.
    assert greedy_insertion(heights, max_points=50).n_points == 4


@pytest.mark.parametrize(("row", "col"), [(4, 5), (1, 1), (0, 3), (6, 0), (7, 9)])
def test_a_single_spike_is_inserted_first(row: int, col: int) -> None:
    heights = np.zeros((8, 11))
    heights[row, col] = 10.0
    tin = greedy_insertion(heights, max_points=5, check=True)
    assert tin.samples[4] == row * 11 + col
    assert tin.vertices[4].tolist() == [col, row, 10.0]
    full = greedy_insertion(heights, max_error=0.0, check=True)
    assert full.max_error == 0.0
    assert full.samples[4] == row * 11 + col


def test_a_spike_on_the_boundary_splits_the_hull_edge_without_a_flat_triangle() -> None:
    heights = np.zeros((6, 9))
    heights[0, 4] = 5.0  # on the bottom edge (y = 0)
    tin = greedy_insertion(heights, max_points=5, check=True)
    assert tin.samples[4] == 4
    assert len(tin.triangles) == 3  # the rectangle's fan from the split point: no zero-area triangle


def test_max_error_stops_at_the_first_mesh_within_it() -> None:
    rng = np.random.default_rng(3)
    heights = rng.normal(size=(20, 25))
    tin = greedy_insertion(heights, max_error=0.5, check=True)
    assert tin.max_error <= 0.5
    assert tin.history is not None
    assert all(e > 0.5 for e in tin.history.max_errors[:-1])


def test_two_by_two_grid() -> None:
    heights = np.array([[0.0, 1.0], [2.0, 5.0]])
    tin = greedy_insertion(heights, max_error=0, check=True)
    assert tin.n_points == 4 and len(tin.triangles) == 2 and tin.max_error == 0.0


# -- hypothesis grids -----------------------------------------------------------------------


@st.composite
def grids(draw: st.DrawFn) -> NDArray[np.float64]:
    rows = draw(st.integers(2, 13))
    cols = draw(st.integers(2, 13))
    kind = draw(st.sampled_from(["constant", "planar", "random", "plateaus", "integer"]))
    if kind == "constant":
        return np.full((rows, cols), draw(st.integers(-5, 5)) / 4)
    if kind == "planar":
        a, b, c = (draw(st.integers(-8, 8)) for _ in range(3))
        return np.fromfunction(lambda r, q: a * r + b * q + c, (rows, cols)) / 8
    if kind == "random":
        values = draw(st.lists(st.floats(-1e3, 1e3, allow_nan=False, width=32), min_size=rows * cols, max_size=rows * cols))
        return np.array(values, dtype=np.float64).reshape(rows, cols)
    if kind == "plateaus":
        levels = draw(st.lists(st.integers(0, 3), min_size=4, max_size=4))
        r0, c0 = draw(st.integers(0, rows)), draw(st.integers(0, cols))
        h = np.empty((rows, cols))
        h[:r0, :c0], h[:r0, c0:], h[r0:, :c0], h[r0:, c0:] = levels
        return h * 10.0
    values = draw(st.lists(st.integers(-3, 3), min_size=rows * cols, max_size=rows * cols))
    return np.array(values, dtype=np.float64).reshape(rows, cols)


@given(grids(), st.one_of(st.none(), st.integers(4, 40)))
def test_hypothesis_grids_are_verified_exactly(heights: NDArray[np.float64], k: int | None) -> None:
    tin = greedy_insertion(heights, max_error=None if k is not None else 0.0, max_points=k, check=True)
    assert_sound(tin, heights)
    if k is None:
        assert tin.max_error == 0.0
    else:
        assert tin.n_points <= k
        assert tin.n_points == k or tin.max_error == 0.0


@given(grids())
def test_planar_grids_need_four_points_and_full_refinement_interpolates(heights: NDArray[np.float64]) -> None:
    tin = greedy_insertion(heights, max_error=0.0)
    rows, cols = heights.shape
    r = np.arange(rows)[:, None]
    c = np.arange(cols)[None, :]
    # A grid whose heights are exactly one plane is meshed by its corners.
    A = np.column_stack([np.ones(rows * cols), np.repeat(np.arange(rows), cols), np.tile(np.arange(cols), rows)])
    coef = np.linalg.lstsq(A, heights.ravel(), rcond=None)[0]
    if np.array_equal(coef[0] + coef[1] * r + coef[2] * c, heights):
        assert tin.n_points == 4
    err, cover = mesh_errors(heights, tin.vertices, tin.triangles)
    assert bool(np.all(cover >= 1))
    assert float(np.max(err)) == pytest.approx(0.0, abs=1e-9 * max(1.0, float(np.ptp(heights))))


# -- against pydelatin ------------------------------------------------------------------------


def _pydelatin_error(crop: NDArray[np.float64], k: int) -> tuple[int, float]:
    from pydelatin import Delatin

    d = Delatin(crop.astype(np.float32), max_points=k, max_error=0.0)
    v = np.asarray(d.vertices, dtype=np.float64).copy()
    # pydelatin puts row 0 at the top: its y is (rows - 1 - row).
    v[:, 1] = crop.shape[0] - 1 - v[:, 1]
    err, cover = mesh_errors(crop, v, d.triangles)
    assert bool(np.all(cover >= 1))
    return len(v), float(np.max(err))


@pytest.mark.parametrize("k", [50, 150, 400])
def test_within_five_percent_of_pydelatin_at_equal_vertex_counts(k: int) -> None:
    crop = jacksboro().heights[100:170, 150:240]
    n, theirs = _pydelatin_error(crop, k)
    tin = greedy_insertion(crop, max_points=n)
    assert tin.n_points == n
    assert tin.max_error <= 1.05 * theirs, (tin.max_error, theirs)


def test_pydelatin_row_convention_is_a_flip() -> None:
    from pydelatin import Delatin

    h = np.zeros((5, 7))
    h[0, 2] = 9.0
    d = Delatin(h.astype(np.float32), max_error=0.0)
    peak = [v for v in np.asarray(d.vertices).tolist() if v[2] == 9.0]
    assert peak == [[2.0, 4.0, 9.0]]  # row 0 comes out at y = rows - 1
    tin = greedy_insertion(h, max_points=5)
    assert tin.vertices[4].tolist() == [2.0, 0.0, 9.0]


# -- history ---------------------------------------------------------------------------------


def test_history_levels_equal_fresh_runs() -> None:
    rng = np.random.default_rng(7)
    heights = np.cumsum(np.cumsum(rng.normal(size=(24, 31)), axis=0), axis=1)
    tin = greedy_insertion(heights, max_points=200, check=True)
    h = tin.history
    assert h is not None and len(h) == 197 and list(h.points)[:2] == [4, 5]
    for k in (4, 5, 17, 64, 199, 200):
        old = h.at(points=k)
        fresh = greedy_insertion(heights, max_points=k)
        assert np.array_equal(old.vertices, fresh.vertices)
        assert np.array_equal(old.triangles, fresh.triangles)
        assert old.max_error == fresh.max_error and old.rms_error == fresh.rms_error
        assert np.array_equal(old.vertices, tin.vertices[:k])  # levels are prefixes
    for e in (float(h.max_errors[10]), float(h.max_errors[120]) * 1.01, 1e9):
        old = h.at(error=e)
        fresh = greedy_insertion(heights, max_error=e)
        assert np.array_equal(old.triangles, fresh.triangles) and old.n_points == fresh.n_points
        assert old.max_error <= e
    verify_tin(h.at(points=80), heights).raise_if_failed()
    assert tin.max_error == h.max_errors[-1]


def test_best_level_within_a_budget() -> None:
    heights = jacksboro().heights[100:160, 150:230]
    tin = greedy_insertion(heights, max_points=400)
    h = tin.history
    assert h is not None
    errors = np.asarray(h.max_errors)
    assert bool(np.any(errors[1:] > errors[:-1]))  # the greedy error is not monotone here
    for k in (50, 200, 400, 10_000):
        best = h.best(k)
        j = min(k, 400) - 4
        assert best.max_error == errors[: j + 1].min() <= h.at(points=min(k, 400)).max_error
        assert best.n_points == 4 + int(np.argmin(errors[: j + 1])) <= k
    with pytest.raises(ValueError, match="4 to 400 points"):
        h.best(3)


def test_history_errors_and_no_history() -> None:
    heights = np.random.default_rng(1).normal(size=(10, 10))
    tin = greedy_insertion(heights, max_points=30)
    h = tin.history
    assert h is not None
    with pytest.raises(ValueError, match="4 to 30 points"):
        h.at(points=31)
    with pytest.raises(ValueError, match="4 to 30 points"):
        h.at(points=3)
    with pytest.raises(ValueError, match="never reached"):
        h.at(error=0.0)
    with pytest.raises(ValueError, match="exactly one"):
        h.at()
    with pytest.raises(ValueError, match="exactly one"):
        h.at(points=5, error=1.0)
    with pytest.raises(TypeError):
        h.at(points=5.0)  # type: ignore[arg-type]
    bare = greedy_insertion(heights, max_points=30, history=False)
    assert bare.history is None
    assert np.array_equal(bare.triangles, tin.triangles) and bare.max_error == tin.max_error


def test_old_versions_survive_later_insertions() -> None:
    heights = np.random.default_rng(2).normal(size=(12, 12))
    tin = greedy_insertion(heights, max_points=60)
    h = tin.history
    assert h is not None
    S = h.structure
    snapshot = sorted((t, d[0], d[1].tolist()) for t, d in S.items(h.versions[10]))
    greedy_insertion(heights, max_points=80)  # other runs do not disturb it either
    assert sorted((t, d[0], d[1].tolist()) for t, d in S.items(h.versions[10])) == snapshot
    assert all(not d[1].flags.writeable for _, d in S.items(h.versions[10]))


# -- options ---------------------------------------------------------------------------------


@pytest.mark.parametrize("backend", ["hamt", "assoc_list", "immutables"])
def test_backends_agree(backend: str) -> None:
    heights = np.random.default_rng(4).integers(0, 9, size=(9, 12)).astype(float)
    ref = greedy_insertion(heights, max_error=0.0)
    other = greedy_insertion(heights, max_error=0.0, backend=backend, check=True)
    assert np.array_equal(ref.vertices, other.vertices) and np.array_equal(ref.triangles, other.triangles)


def test_stats_count_the_work_and_change_nothing() -> None:
    heights = np.random.default_rng(5).normal(size=(15, 15))
    stats = Stats()
    counted = greedy_insertion(heights, max_points=40, stats=stats)
    plain = greedy_insertion(heights, max_points=40)
    assert np.array_equal(counted.triangles, plain.triangles)
    assert counted.stats is stats
    assert stats.key_comparisons > 0 and stats.dict_ops > 0 and stats.plane_side_tests > 0 and stats.flops > 0
    assert stats.faces_created - stats.faces_deleted == len(plain.triangles) + 4 + _hull_splits(plain)


def _hull_splits(tin: Tin) -> int:
    """Ghost triangles beyond the rectangle's four: one per vertex on the rectangle's sides, not a corner."""
    rows, cols = tin.shape
    x, y = tin.vertices[:, 0], tin.vertices[:, 1]
    on = (x == 0) | (x == cols - 1) | (y == 0) | (y == rows - 1)
    return int(on.sum()) - 4


def test_transform_gives_world_coordinates() -> None:
    heights = np.arange(12.0).reshape(3, 4) ** 2
    tin = greedy_insertion(heights, max_points=6, transform=((500.0, 4000.0), (2.0, -2.0)))
    assert tin.transform == GridTransform(500.0, 4000.0, 2.0, -2.0)
    w = tin.world_vertices()
    assert np.array_equal(w[:, 0], 500.0 + 2.0 * tin.vertices[:, 0])
    assert np.array_equal(w[:, 1], 4000.0 - 2.0 * tin.vertices[:, 1])
    assert np.array_equal(w[:, 2], tin.vertices[:, 2])
    assert greedy_insertion(heights, max_points=6, transform=(1, 2, 3, 4)).transform == GridTransform(1, 2, 3, 4)
    assert np.array_equal(greedy_insertion(heights, max_points=6).world_vertices(), tin.vertices)


def test_progress_callable_counts_insertions() -> None:
    seen: list[int] = []
    tin = greedy_insertion(np.random.default_rng(0).normal(size=(8, 8)), max_points=20, progress=seen.append)
    assert sum(seen) == tin.n_points - 4


def test_verification_detects_a_wrong_error() -> None:
    heights = np.random.default_rng(6).normal(size=(8, 9))
    tin = greedy_insertion(heights, max_points=15)
    import dataclasses

    bad = dataclasses.replace(tin, max_error=tin.max_error + 1.0)
    report = verify_tin(bad, heights)
    assert not report.ok and "maximum error" in report.failures[0]
    with pytest.raises(TerrainCheckError):
        report.raise_if_failed()
    flipped = dataclasses.replace(tin, triangles=tin.triangles[:, ::-1].copy())
    assert any("counterclockwise" in f for f in verify_tin(flipped, heights).failures)


# -- bad input -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("heights", "kind", "message"),
    [
        (np.zeros((0, 5)), ValueError, "at least 2 rows and 2 columns"),
        (np.zeros((1, 5)), ValueError, "at least 2 rows and 2 columns"),
        (np.zeros((5, 1)), ValueError, "at least 2 rows and 2 columns"),
        (np.zeros(5), ValueError, "2D array"),
        ([[1.0, 2.0], [3.0]], ValueError, "rectangular"),
        ("heights", TypeError, "2D array of real numbers"),
        (np.array([["a", "b"], ["c", "d"]]), TypeError, "real numbers"),
        (np.array([[1.0, np.inf], [0.0, 0.0]]), ValueError, "infinite"),
        (np.array([[1.0, 1e300], [0.0, 0.0]]), ValueError, r"cell \(row 0, col 1\) is 1e\+300, beyond"),
        (np.array([[1.0, np.nan], [np.nan, 0.0]]), ValueError, r"2 no-data cells \(NaN\), the first at \(row 0, col 1\)"),
        (np.where(np.arange(2500).reshape(50, 50) < 1234, np.nan, 1.0), ValueError, r"1,234 no-data cells \(NaN\), the first at \(row 0, col 0\)"),
        (np.full((3, 3), np.nan), ValueError, "every cell is no-data"),
    ],
)
def test_bad_grids_are_refused_clearly(heights: object, kind: type[Exception], message: str) -> None:
    with pytest.raises(kind, match=message):
        greedy_insertion(heights, max_points=10)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("kwargs", "kind", "message"),
    [
        ({}, ValueError, "max_error, max_points or both"),
        ({"max_points": 3}, ValueError, "at least 4"),
        ({"max_points": 10.5}, TypeError, "integer"),
        ({"max_points": True}, TypeError, "integer"),
        ({"max_error": -1.0}, ValueError, ">= 0"),
        ({"max_error": float("nan")}, ValueError, ">= 0"),
        ({"max_error": "1"}, TypeError, "number"),
        ({"max_error": 1.0, "backend": "btree"}, ValueError, "unknown map backend"),
        ({"max_error": 1.0, "progress": 3}, TypeError, "progress"),
        ({"max_error": 1.0, "transform": (1, 2, 3)}, ValueError, "4 numbers"),
        ({"max_error": 1.0, "transform": (1, 2, 0, 4)}, ValueError, "zero cell size"),
        ({"max_error": 1.0, "transform": "x"}, TypeError, "transform"),
        ({"max_error": 1.0, "history": 1}, TypeError, "history"),
    ],
)
def test_bad_options_are_refused_clearly(kwargs: dict[str, object], kind: type[Exception], message: str) -> None:
    with pytest.raises(kind, match=message):
        greedy_insertion(np.zeros((3, 3)), **kwargs)  # type: ignore[arg-type]


def test_nodata_rules() -> None:
    h = np.array([[1.0, 2.0, 3.0], [4.0, np.nan, 6.0], [7.0, 8.0, np.nan]])
    with pytest.raises(ValueError, match="nodata='fill'"):
        greedy_insertion(h, max_error=0)
    filled = greedy_insertion(h, max_error=0, nodata="fill", check=True)
    assert set(filled.vertices[:, 2].tolist()) <= {1.0, 2.0, 3.0, 4.0, 6.0, 7.0, 8.0}
    low = greedy_insertion(h, max_error=0, nodata="min", check=True)
    assert low.vertices[2].tolist() == [2.0, 2.0, 1.0]  # the corner (row 2, col 2) took the lowest height
    fixed = greedy_insertion(h, max_error=0, nodata=-5, check=True)
    assert fixed.vertices[2].tolist() == [2.0, 2.0, -5.0]
    with pytest.raises(ValueError, match="nodata must be one of"):
        greedy_insertion(h, max_error=0, nodata="zero")
    with pytest.raises(TypeError, match="nodata must be one of"):
        greedy_insertion(h, max_error=0, nodata=None)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="finite"):
        greedy_insertion(h, max_error=0, nodata=float("inf"))


@pytest.mark.parametrize("size", [5, 128, 129, 700, 5000])
def test_queue_chooses_the_first_sample_of_largest_error(size: int) -> None:
    """GreedyRun._queue, on a list (up to 128 samples) or by numpy over the whole fan (above), queues for each
    triangle with samples the first of its samples of largest error, when that error is positive: ties (few
    distinct errors), zero errors, triangles without samples and one-sample triangles included."""
    from persistri.impl.complex.two_complex import TwoComplex
    from persistri.impl.maps import backend as map_backend
    from persistri.impl.terrain.greedy_run import GreedyRun

    z = np.zeros(100 * 100)
    run = GreedyRun(z, (100, 100), TwoComplex(map_backend("red_black"), None), None, False)
    keys = run.keys
    rng = np.random.default_rng(size)
    checked = 0
    for trial in range(40):
        k = int(rng.integers(1, 9))
        cuts = np.sort(rng.integers(0, size + 1, k - 1))
        counts = np.diff(np.concatenate(([0], cuts, [size]))).tolist()
        if trial % 3 == 0 and k > 1:  # empty triangles between full ones
            counts[int(rng.integers(1, k))] += counts[0]
            counts[0] = 0
        assert sum(counts) == size
        err = rng.integers(0, 4, size).astype(np.float64) / 3.0  # few distinct values: ties everywhere
        if trial % 5 == 0:
            err[: size // 2] = 0.0
        samples = rng.permutation(z.size)[:size].astype(np.int32)
        tids = [1000 + 7 * i for i in range(k)]
        expected = []
        start = 0
        for tid, cnt in zip(tids, counts):
            if cnt:
                part = err[start : start + cnt]
                first = start + int(np.flatnonzero(part == part.max())[0])
                if err[first] > 0.0:
                    expected.append((float(err[first]), tid, int(samples[first])))
            start += cnt
        run.heap = []
        run._queue(tids, counts, samples, err)
        got = sorted((keys.error(key), keys.tid(key), keys.sample(key)) for key in run.heap)
        assert got == sorted(expected)
        checked += len(expected)
    assert checked > 40


@pytest.mark.parametrize("seed", [0, 1])
def test_small_fan_errors_queue_what_numpy_queues(seed: int) -> None:
    """GreedyRun._queue_small (Python floats, one loop) pushes exactly the keys that fan_plane_errors then
    _queue push, insertion after insertion (ties included: a grid of few distinct heights)."""
    from persistri.impl.complex.two_complex import TwoComplex
    from persistri.impl.maps import backend as map_backend
    from persistri.impl.terrain.greedy_run import _GATHER_HEIGHTS, GreedyRun
    from persistri.impl.terrain.plane_errors import fan_plane_errors

    sizes = []
    rng = np.random.default_rng(seed)
    heights = np.round(rng.normal(size=(31, 37)).cumsum(axis=0) * 3.0) / 4.0
    z = np.ascontiguousarray(heights).ravel()
    run = GreedyRun(z, heights.shape, TwoComplex(map_backend("red_black"), None), None, False)
    compared = 0
    for _ in range(300):
        if run.current_error() == 0.0:
            break
        ins = run.step()
        samples = ins.samples
        if samples is None or not samples.size:
            continue
        # The fan's gradients, as _assess computes them.
        cols = heights.shape[1]
        yp, xp = divmod(ins.point, cols)
        zp = float(z[ins.point])
        gxs, gys = [], []
        ring = [int(v) for v in ins.rays]
        for a, b in zip(ring, ring[1:]):
            (ya, xa), (yb, xb) = divmod(a, cols), divmod(b, cols)
            dx1, dy1, dz1 = xa - xp, ya - yp, float(z[a]) - zp
            dx2, dy2, dz2 = xb - xp, yb - yp, float(z[b]) - zp
            det = float(dx1 * dy2 - dx2 * dy1)
            gxs.append((dz1 * dy2 - dz2 * dy1) / det)
            gys.append((dx1 * dz2 - dx2 * dz1) / det)
        tids = [tid for tid, _ in ins.created]
        saved = list(run.heap)
        run.heap = []
        run._queue_small(tids, ins.counts, samples, float(xp), float(yp), zp, gxs, gys)
        small = run.heap
        run.heap = []
        err = fan_plane_errors(run.pred.coordinates, z, float(xp), float(yp), zp, gxs, gys, ins.fan_index, samples)
        run._queue(tids, ins.counts, samples, err)
        assert sorted(small) == sorted(run.heap)
        compared += len(small)
        sizes.append(samples.size)
        run.heap = saved
    assert compared > 100
    # Both ways of reading the heights were compared: gathered (large fans) and one at a time.
    assert min(sizes) < _GATHER_HEIGHTS <= max(sizes)
