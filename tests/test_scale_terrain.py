"""Tiled terrain (:mod:`persistri.impl.scale.terrain`): watertight seams, the error bound at every sample, the same
mesh on one worker or two, and DEMs read in windows.

The cluster is a real :class:`distributed.LocalCluster` of two worker processes (module-scoped).
The meshes are checked independently of how they were built: exact integer
orientation, edges, areas and — on integer heights — exact vertical errors at
every sample of the grid.
"""

from __future__ import annotations

from collections.abc import Iterator
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.scale.terrain import TiledTin, tiled_terrain, write_tile_meshes
from persistri.impl.scale.terrain_seams import Tiling, seam_vertices
from persistri.impl.scale.terrain_nodata import NodataRule, filled_window
from persistri.impl.scale.terrain_source import NpySource, open_dem
from persistri.impl.scale.terrain_tile import mesh_tile
from persistri.impl.terrain.check import ERROR_RTOL, verify_triangulation
from persistri.impl.terrain.synthetic import synthetic_dem

distributed = pytest.importorskip("distributed")
tifffile = pytest.importorskip("tifffile")
zarr = pytest.importorskip("zarr")

BOUND = Fraction(25, 2)  # max_error 12.5: a half-integer, so integer heights meet it exactly at some samples


@pytest.fixture(scope="module")
def client() -> Iterator[Any]:
    from persistri.impl.scale.cluster import connect

    with connect(workers=2) as c:  # a LocalCluster of two worker processes
        yield c


def integer_dem(rows: int = 131, cols: int = 157, seed: int = 4) -> np.ndarray:
    """Integer heights (metres, 0–600) of a rough fBm terrain: exact arithmetic decides every error."""
    g = synthetic_dem(max(rows, cols), seed=seed, relief=600.0).heights[:rows, :cols]
    return np.round(g).astype(np.int64)


# -- an independent check of a stitched mesh -----------------------------------------------------------


def check_mesh(tin: TiledTin, heights: np.ndarray, bound: Fraction) -> dict[str, int]:
    """Assert that ``tin`` triangulates the grid's rectangle watertight, counterclockwise, within ``bound`` exactly.

    Integer heights only (every quantity below is an integer).  Returns counts for the caller's assertions.
    """
    rows, cols = heights.shape
    v = tin.vertices
    x, y = v[:, 0].astype(np.int64), v[:, 1].astype(np.int64)
    assert np.array_equal(y * cols + x, tin.samples)
    assert np.array_equal(v[:, 2], heights[y, x].astype(np.float64))
    t = tin.triangles
    a, b, c = t[:, 0], t[:, 1], t[:, 2]
    area2 = (x[b] - x[a]) * (y[c] - y[a]) - (y[b] - y[a]) * (x[c] - x[a])
    assert bool(np.all(area2 > 0)), "every triangle strictly counterclockwise"
    assert int(area2.sum()) == 2 * (rows - 1) * (cols - 1), "the triangles' areas add up to the rectangle's"
    # Edges: each directed edge once; an edge without its reverse lies on the rim.
    directed = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    keys = directed[:, 0].astype(np.int64) * len(v) + directed[:, 1]
    assert np.unique(keys).size == keys.size, "a directed edge is used twice"
    reverse = directed[:, 1].astype(np.int64) * len(v) + directed[:, 0]
    has_twin = np.isin(reverse, keys)
    rim = directed[~has_twin]
    u, w = rim[:, 0], rim[:, 1]
    on_side = ((y[u] == 0) & (y[w] == 0)) | ((y[u] == rows - 1) & (y[w] == rows - 1)) | (
        (x[u] == 0) & (x[w] == 0)) | ((x[u] == cols - 1) & (x[w] == cols - 1))
    assert bool(np.all(on_side)), "every edge with one triangle lies on the grid's rim"
    assert int(np.sum(np.abs(x[w] - x[u]) + np.abs(y[w] - y[u]))) == 2 * (rows - 1) + 2 * (cols - 1)
    # Seams: an edge along an inner border line has a triangle on each side.
    seam_edges = 0
    for r in tin.tiling.row_lines[1:-1]:
        along = (y[directed[:, 0]] == r) & (y[directed[:, 1]] == r)
        seam_edges += int(along.sum())
        assert bool(np.all(has_twin[along])), f"a seam edge on row {r} has one triangle"
    for col in tin.tiling.col_lines[1:-1]:
        along = (x[directed[:, 0]] == col) & (x[directed[:, 1]] == col)
        seam_edges += int(along.sum())
        assert bool(np.all(has_twin[along])), f"a seam edge on column {col} has one triangle"
    # Euler: a disc has V - E + F = 1.
    edges = (keys.size + int((~has_twin).sum())) // 2
    assert len(v) - edges + len(t) == 1
    # The vertical error at every sample, exactly: |z·2A − Σ w_i z_i| ≤ bound·2A over every triangle holding it.
    z = heights.astype(np.int64)
    covered = np.zeros((rows, cols), dtype=bool)
    num, den = bound.numerator, bound.denominator
    worst = Fraction(0)
    for (i, j, k), twice in zip(t.tolist(), area2.tolist()):
        xs, ys = (x[i], x[j], x[k]), (y[i], y[j], y[k])
        gx, gy = np.meshgrid(np.arange(min(xs), max(xs) + 1), np.arange(min(ys), max(ys) + 1))
        wa = (xs[1] - gx) * (ys[2] - gy) - (ys[1] - gy) * (xs[2] - gx)
        wb = (xs[2] - gx) * (ys[0] - gy) - (ys[2] - gy) * (xs[0] - gx)
        wc = (xs[0] - gx) * (ys[1] - gy) - (ys[0] - gy) * (xs[1] - gx)
        inside = (wa >= 0) & (wb >= 0) & (wc >= 0)
        assert bool(np.all((wa + wb + wc) == twice))
        px, py = gx[inside], gy[inside]
        dev = np.abs(z[py, px] * twice - (wa[inside] * z[ys[0], xs[0]] + wb[inside] * z[ys[1], xs[1]] + wc[inside] * z[ys[2], xs[2]]))
        assert bool(np.all(dev * den <= num * twice)), "a sample farther than the bound from the mesh"
        if dev.size:
            worst = max(worst, Fraction(int(dev.max()), twice))
        covered[py, px] = True
    assert bool(covered.all()), "every sample lies in some triangle"
    assert tin.max_error <= float(bound)
    assert abs(tin.max_error - float(worst)) <= ERROR_RTOL * max(1.0, float(np.ptp(heights)))
    return {"seam_edges": seam_edges}


# -- the stitched mesh ---------------------------------------------------------------------------------


def test_the_stitched_mesh_is_watertight_and_within_the_bound_everywhere() -> None:
    h = integer_dem()
    tin = tiled_terrain(h, max_error=float(BOUND), tile=40)
    assert tin.tiling.shape == (4, 4)  # 131 rows: lines 0, 39, 78, 117, 130; 157 columns: 0, 39, 78, 117, 156
    counts = check_mesh(tin, h, BOUND)
    assert counts["seam_edges"] > 0
    assert 4 < tin.n_points < h.size // 4


def test_one_worker_and_two_give_identical_arrays(client: Any) -> None:
    h = integer_dem(97, 121, seed=7)
    alone = tiled_terrain(h, max_error=7.5, tile=33)
    shared = tiled_terrain(h, max_error=7.5, tile=33, client=client)
    for name in ("vertices", "triangles", "samples"):
        assert np.array_equal(getattr(alone, name), getattr(shared, name)), name
    assert (alone.max_error, alone.rms_error) == (shared.max_error, shared.rms_error)
    assert len(client.scheduler_info()["workers"]) == 2
    check_mesh(shared, h, Fraction(15, 2))


def test_float_heights_stay_within_the_bound_on_the_cluster(client: Any, tmp_path: Path) -> None:
    h = synthetic_dem(120, seed=11, relief=300.0).heights[:101, :117]
    path = tmp_path / "dem.npy"
    np.save(path, h)
    tin = tiled_terrain(str(path), max_error=4.0, tile=30, client=client)
    assert tin.max_error <= 4.0
    # Errors recomputed over the whole grid by matplotlib's linear interpolation: a third route.
    from matplotlib.tri import LinearTriInterpolator, Triangulation

    tri = Triangulation(tin.vertices[:, 0], tin.vertices[:, 1], tin.triangles)
    gy, gx = np.mgrid[0 : h.shape[0], 0 : h.shape[1]]
    fitted = LinearTriInterpolator(tri, tin.vertices[:, 2])(gx.astype(float), gy.astype(float))
    assert not np.ma.is_masked(fitted) or not bool(np.ma.getmaskarray(fitted).any())
    err = np.abs(np.asarray(fitted) - h)
    assert float(err.max()) <= 4.0 * (1 + ERROR_RTOL)  # another float route: agreement to the project's tolerance
    assert abs(float(err.max()) - tin.max_error) <= ERROR_RTOL * 300.0
    rms = float(np.sqrt(np.mean(err**2)))
    assert abs(rms - tin.rms_error) <= ERROR_RTOL * 300.0


def test_a_single_tile_and_an_exact_mesh() -> None:
    h = integer_dem(20, 23, seed=2)
    tin = tiled_terrain(h, max_error=0.0, tile=64)
    assert tin.tiling.shape == (1, 1)
    check_mesh(tin, h, Fraction(0))
    plane = np.add.outer(3 * np.arange(30), 2 * np.arange(41))
    flat = tiled_terrain(plane, max_error=0.0, tile=11)
    assert flat.max_error == 0.0
    # A plane needs only the tile corners: 3 × 4 tiles, 4 × 5 corners.
    assert flat.n_points == len(flat.tiling.row_lines) * len(flat.tiling.col_lines) == 20
    check_mesh(flat, plane, Fraction(0))


def test_thin_last_tiles_and_two_row_grids() -> None:
    h = integer_dem(42, 44, seed=5)  # tile 21: lines 0, 20, 40, 41 — a last tile of two rows
    tin = tiled_terrain(h, max_error=3.5, tile=21)
    assert tin.tiling.row_lines == (0, 20, 40, 41)
    check_mesh(tin, h, Fraction(7, 2))
    strip = integer_dem(2, 50, seed=6)
    check_mesh(tiled_terrain(strip, max_error=1.5, tile=9), strip, Fraction(3, 2))


# -- one tile ------------------------------------------------------------------------------------------


def test_a_tile_is_the_delaunay_triangulation_of_its_vertices_with_the_seams_as_boundary() -> None:
    z = synthetic_dem(40, seed=9).heights[:33, :37]
    e = 25.0
    top, bottom = seam_vertices(z[0], e).vertices, seam_vertices(z[-1], e).vertices
    left, right = seam_vertices(z[:, 0], e).vertices, seam_vertices(z[:, -1], e).vertices
    mesh = mesh_tile(z, top, right, bottom, left, e)
    h, w = z.shape
    xy = np.column_stack([np.tile(np.arange(w), h), np.repeat(np.arange(h), w)]).astype(float)
    boundary = ([int(c) for c in top[:-1]] + [int(r) * w + w - 1 for r in right[:-1]]
                + [(h - 1) * w + int(c) for c in bottom[::-1][:-1]] + [int(r) * w for r in left[::-1][:-1]])
    report = verify_triangulation(Predicates2(xy), mesh.triangles, vertices=mesh.vertices, boundary=boundary)
    assert report.ok, report.failures
    assert mesh.max_error <= e and mesh.interior == (h - 2) * (w - 2)


def test_seams_must_run_from_end_to_end() -> None:
    z = np.zeros((5, 6))
    ok = np.array([0, 5])
    with pytest.raises(ValueError, match="top seam"):
        mesh_tile(z, np.array([1, 5]), np.array([0, 4]), ok, np.array([0, 4]), 1.0)


# -- seams: Douglas–Peucker, exact ----------------------------------------------------------------------


def greedy_1d(z: list[int], e: Fraction) -> list[int]:
    """1D greedy insertion in exact arithmetic: insert the worst sample (first of ties) while it exceeds ``e``."""
    keep = [0, len(z) - 1]
    while True:
        worst, at = Fraction(-1), -1
        for a, b in zip(keep, keep[1:]):
            for t in range(a + 1, b):
                err = abs(z[t] - z[a] - Fraction((z[b] - z[a]) * (t - a), b - a))
                if err > worst:
                    worst, at = err, t
        if worst <= e:
            return keep
        keep = sorted(keep + [at])


@given(st.lists(st.integers(-50, 50), min_size=2, max_size=40), st.integers(0, 40))
def test_seams_are_one_dimensional_greedy_insertion_to_the_bound(z: list[int], quarters: int) -> None:
    e = Fraction(quarters, 4)
    seam = seam_vertices(np.array(z, dtype=np.float64), float(e))
    assert seam.vertices.tolist() == greedy_1d(z, e)
    assert seam.max_error <= float(e)


@given(st.lists(st.floats(-1e6, 1e6), min_size=3, max_size=30), st.floats(0, 10))
def test_seams_hold_the_bound_exactly_on_floats(z: list[float], e: float) -> None:
    seam = seam_vertices(np.array(z), e)
    keep = seam.vertices.tolist()
    for a, b in zip(keep, keep[1:]):
        for t in range(a + 1, b):
            exact = abs(Fraction(z[t]) - Fraction(z[a]) - (Fraction(z[b]) - Fraction(z[a])) * Fraction(t - a, b - a))
            assert exact <= Fraction(e)


def test_tilings() -> None:
    t = Tiling.of((10, 7), 4)
    assert t.row_lines == (0, 3, 6, 9) and t.col_lines == (0, 3, 6)
    assert Tiling.of((5, 5), 100).shape == (1, 1)
    with pytest.raises(ValueError, match="at least 3"):
        Tiling.of((10, 10), 2)


# -- DEMs read in windows ---------------------------------------------------------------------------------


def test_every_lazy_format_gives_the_array_s_mesh(tmp_path: Path, client: Any) -> None:
    import dask.array as da

    h = integer_dem(70, 83, seed=12).astype(np.float32)
    np.save(tmp_path / "dem.npy", h)
    tifffile.imwrite(tmp_path / "dem.tif", h, tile=(32, 32), compression="zlib")
    tifffile.imwrite(tmp_path / "strips.tif", h, rowsperstrip=7)
    zarr.create_array(str(tmp_path / "dem.zarr"), data=h, chunks=(20, 20))
    group = zarr.open_group(str(tmp_path / "group.zarr"), mode="w")
    group.create_array("elevation", data=h, chunks=(16, 16))
    reference = tiled_terrain(h, max_error=6.5, tile=25)
    sources: list[Any] = [str(tmp_path / n) for n in ("dem.npy", "dem.tif", "strips.tif", "dem.zarr", "group.zarr")]
    sources.append(da.from_array(h, chunks=(30, 30)))
    for source in sources:
        for run_on in (None, client):
            got = tiled_terrain(source, max_error=6.5, tile=25, client=run_on)
            assert np.array_equal(got.vertices, reference.vertices), source
            assert np.array_equal(got.triangles, reference.triangles), source


def test_a_geotiff_keeps_its_transform_crs_and_nodata(tmp_path: Path) -> None:
    from persistri.impl.terrain.grids import read_grid

    h = integer_dem(40, 50, seed=3).astype(np.float32)
    h[10:13, 20:24] = -9999.0
    tags = [
        (33550, "d", 3, (30.0, 30.0, 0.0)),
        (33922, "d", 6, (0.0, 0.0, 0.0, 500000.0, 4000000.0, 0.0)),
        (34735, "H", 16, (1, 1, 0, 3, 1024, 0, 1, 1, 1025, 0, 1, 1, 3072, 0, 1, 32614)),
        (42113, "s", 0, "-9999", False),
    ]
    path = tmp_path / "dem.tif"
    tifffile.imwrite(path, h, extratags=tags, tile=(16, 16))
    dem = open_dem(str(path))
    whole = read_grid(path)
    assert dem.transform == whole.transform and dem.transform is not None and dem.transform.crs is not None
    window = dem.source.read(5, 20, 15, 30)
    assert np.array_equal(np.isnan(window), np.isnan(whole.heights[5:20, 15:30]))
    assert np.array_equal(np.nan_to_num(window), np.nan_to_num(whole.heights[5:20, 15:30]))
    with pytest.raises(ValueError, match=r"12 no-data cells \(NaN\), the first at \(row 10, col 20\)"):
        tiled_terrain(str(path), max_error=2.5, tile=17)
    tin = tiled_terrain(str(path), max_error=2.5, tile=17, nodata="min")
    assert tin.crs is not None and tin.crs.name == "EPSG:32614"
    low = float(np.min(h[h != -9999.0]))
    inside = (tin.vertices[:, 1] >= 10) & (tin.vertices[:, 1] <= 12) & (tin.vertices[:, 0] >= 20) & (tin.vertices[:, 0] <= 23)
    assert bool(np.all(tin.vertices[inside, 2] == low))


def test_fill_agrees_across_windows_and_picks_the_nearest_valid_cell(tmp_path: Path) -> None:
    rng = np.random.default_rng(1)
    h = rng.integers(0, 100, size=(30, 34)).astype(np.float64)
    h[8:19, 5:16] = np.nan  # a hole across the seams of 9-sample tiles
    h[0, 30:] = np.nan
    path = tmp_path / "holes.npy"
    np.save(path, h)
    src = NpySource(str(path), h.shape)
    rule = NodataRule("fill", reach=12)
    whole = filled_window(src, 0, 29, 0, 33, rule)
    valid = np.argwhere(~np.isnan(h))
    for r, c in np.argwhere(np.isnan(h)).tolist():
        d2 = ((valid - [r, c]) ** 2).sum(axis=1)
        nearest = valid[d2 == d2.min()]
        first = min(map(tuple, nearest.tolist()))  # the smallest (row, col) among the nearest
        assert whole[r, c] == h[first], (r, c)
    for r0, r1, c0, c1 in ((8, 16, 0, 8), (16, 24, 8, 16), (10, 10, 3, 20), (0, 29, 12, 12)):
        assert np.array_equal(filled_window(src, r0, r1, c0, c1, rule), whole[r0 : r1 + 1, c0 : c1 + 1])
    tin = tiled_terrain(str(path), max_error=20.0, tile=9, nodata="fill", fill_reach=12)
    check_mesh(tin, whole.astype(np.int64), Fraction(20))
    with pytest.raises(ValueError, match=r"no-data cell \(row 11, col 8\) has no valid cell within 3 cells"):
        tiled_terrain(str(path), max_error=20.0, tile=9, nodata="fill", fill_reach=3)


def test_bad_grids_fail_before_any_meshing(tmp_path: Path) -> None:
    h = np.zeros((20, 20))
    h[3, 4] = np.inf
    with pytest.raises(ValueError, match=r"cell \(row 3, col 4\) is infinite"):
        tiled_terrain(h, max_error=1.0, tile=8)
    with pytest.raises(ValueError, match="every cell is no-data"):
        tiled_terrain(np.full((5, 5), np.nan), max_error=1.0, tile=8, nodata="fill")
    with pytest.raises(ValueError, match="at least 2 rows"):
        tiled_terrain(np.zeros((1, 9)), max_error=1.0)
    with pytest.raises(ValueError, match="max_error must be a finite number"):
        tiled_terrain(np.zeros((9, 9)), max_error=-1.0)
    bad = tmp_path / "x.npy"
    bad.write_bytes(b"not numpy")
    with pytest.raises(ValueError, match="no NumPy header"):
        tiled_terrain(str(bad), max_error=1.0)


def test_tile_meshes_are_written_beside_the_whole(tmp_path: Path) -> None:
    h = integer_dem(50, 61, seed=8)
    tin = tiled_terrain(h, max_error=5.5, tile=21, keep_tiles=True)
    written = write_tile_meshes(tmp_path / "tiles", tin)
    assert len(written) == len(tin.tiling) == 9
    total = 0
    for path in written:
        data = np.load(path)
        assert set(data.files) >= {"vertices", "triangles", "samples", "max_error", "rms_error", "grid_shape"}
        assert float(data["max_error"]) <= 5.5
        total += len(data["triangles"])
    assert total == len(tin.triangles)
    with pytest.raises(ValueError, match="kept no tile meshes"):
        write_tile_meshes(tmp_path / "none", tiled_terrain(h, max_error=5.5, tile=21))
