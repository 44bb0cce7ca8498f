"""``persistri terrain`` and ``persistri delaunay``; the grid readers (.npy, .npz, .asc, GeoTIFF, jacksboro)."""

from __future__ import annotations

import re
from pathlib import Path

import meshio
import numpy as np
import pytest
from click.testing import CliRunner

from persistri.impl.cli.main import main
from persistri.impl.geometry.predicates import Predicates2
from persistri.impl.terrain.check import verify_triangulation
from persistri.impl.terrain.greedy import greedy_insertion
from persistri.impl.terrain.esri_grid import write_asc
from persistri.impl.terrain.grids import GridTransform, as_heights, jacksboro, read_grid

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def run(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, list(args))
    return result.exit_code, result.output


def one_error_line(text: str, pattern: str) -> None:
    lines = [ln for ln in text.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("persistri: "), text
    assert re.search(pattern, lines[0]), lines[0]


def grid(rows: int = 12, cols: int = 17, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.cumsum(rng.normal(size=(rows, cols)), axis=1).round(2)


# -- persistri terrain -------------------------------------------------------------------------


def test_npy_to_npz_matches_the_api(tmp_path: Path) -> None:
    h = grid()
    np.save(tmp_path / "g.npy", h)
    out = tmp_path / "mesh.npz"
    code, text = run("terrain", str(tmp_path / "g.npy"), "--max-points", "40", "-o", str(out), "--check", "--quiet")
    assert code == 0, text
    data = np.load(out)
    assert {"vertices", "triangles", "max_error"} <= set(data.files)
    tin = greedy_insertion(h, max_points=40)
    assert np.array_equal(data["vertices"], tin.vertices)
    assert np.array_equal(data["triangles"], tin.triangles)
    assert float(data["max_error"]) == tin.max_error


# meshio's STL reader first tries the binary layout, multiplying the ASCII file's bytes 80-84 as a uint32 count
# (an overflow warning of the reader's, not of persistri's writer).
@pytest.mark.filterwarnings("ignore:overflow encountered in scalar multiply:RuntimeWarning")
@pytest.mark.parametrize("suffix", [".ply", ".obj", ".stl"])
def test_mesh_formats_and_plot(tmp_path: Path, suffix: str) -> None:
    np.save(tmp_path / "g.npy", grid())
    out = tmp_path / f"mesh{suffix}"
    png = tmp_path / "mesh.png"
    code, text = run("terrain", str(tmp_path / "g.npy"), "--max-error", "0.5", "-o", str(out), "--plot", str(png))
    assert code == 0, text
    assert "max error" in text
    mesh = meshio.read(out)
    tris = mesh.cells[0].data
    assert tris.shape[1] == 3 and len(mesh.points) >= 4
    # Counterclockwise in (x, y): every normal points up (+z).
    p = np.asarray(mesh.points)
    a, b, c = p[tris[:, 0]], p[tris[:, 1]], p[tris[:, 2]]
    assert bool(np.all(np.cross(b - a, c - a)[:, 2] > 0))
    assert png.read_bytes().startswith(PNG_MAGIC)


def test_jacksboro_with_stats_and_world_coordinates(tmp_path: Path) -> None:
    out = tmp_path / "j.npz"
    code, text = run("terrain", "jacksboro", "--max-points", "60", "--world", "--stats", "-o", str(out), "--quiet")
    assert code == 0, text
    assert "key comparisons" in text and "plane side tests" in text
    v = np.load(out)["vertices"]
    assert v.shape == (60, 3)
    assert -84.5 < v[:, 0].min() and v[:, 0].max() < -84.0  # longitudes
    assert 36.4 < v[:, 1].min() and v[:, 1].max() < 36.8  # latitudes


def test_asc_with_nodata(tmp_path: Path) -> None:
    h = grid(9, 11)
    h[3, 4] = np.nan
    src = write_asc(tmp_path / "g.asc", h, x0=1000.0, y0=2000.0, cellsize=5.0)
    code, text = run("terrain", str(src), "--max-error", "0", "-o", str(tmp_path / "m.npz"), "--quiet")
    assert code == 2
    one_error_line(text, r"g\.asc: 1 no-data cell \(NaN\), the first at \(row 3, col 4\); .*--nodata fill")
    code, text = run("terrain", str(src), "--max-error", "0", "--nodata", "fill", "-o", str(tmp_path / "m.npz"), "--quiet")
    assert code == 0, text
    code, text = run("terrain", str(src), "--max-error", "0", "--nodata", "-7.5", "-o", str(tmp_path / "n.npz"), "--quiet")
    assert code == 0, text
    v = np.load(tmp_path / "n.npz")["vertices"]
    assert [3 * 11 + 4] == [int(r * 11 + c) for c, r, z in v.tolist() if z == -7.5]


@pytest.mark.parametrize(
    ("args", "pattern"),
    [
        (("terrain", "missing.npy", "--max-points", "10"), "missing.npy: no such file"),
        (("terrain", "g.xyz", "--max-points", "10"), "g.xyz: unknown grid format"),
        (("terrain", "jacksboro", "--max-points", "10", "-o", "m.vtk"), "m.vtk: unknown mesh format"),
        (("terrain", "jacksboro", "--max-points", "10", "--backend", "btree"), "--backend btree: unknown map backend"),
        (("terrain", "row.npy", "--max-points", "10"), "row.npy: .*at least 2 rows and 2 columns"),
        (("terrain", "row.npy", "--max-points", "10", "--world"), "row.npy: .*(at least 2 rows|georeferencing)"),
    ],
)
def test_bad_terrain_input_is_one_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, args: tuple[str, ...], pattern: str) -> None:
    monkeypatch.chdir(tmp_path)
    np.save(tmp_path / "row.npy", np.zeros((1, 8)))
    (tmp_path / "g.xyz").write_text("0 0 0\n")
    code, text = run(*args)
    assert code == 2
    one_error_line(text, pattern)


@pytest.mark.parametrize(
    "args",
    [
        ("terrain", "jacksboro"),
        ("terrain", "jacksboro", "--max-points", "3"),
        ("terrain", "jacksboro", "--max-error", "-1"),
        ("terrain", "jacksboro", "--max-error", "1", "--nodata", "sometimes"),
    ],
)
def test_usage_errors(args: tuple[str, ...]) -> None:
    code, text = run(*args)
    assert code == 2, text


# -- persistri delaunay ------------------------------------------------------------------------


def test_delaunay_csv_to_npz_exact(tmp_path: Path) -> None:
    pts = np.random.default_rng(1).random((120, 2)) * 10 + np.array([5e5, 4e6])
    pts = np.vstack([pts, pts[:3]])  # three duplicate rows
    src = tmp_path / "tile.csv"
    np.savetxt(src, pts, delimiter=",", header="x,y", fmt="%.17g")
    out = tmp_path / "tile.npz"
    code, text = run("delaunay", str(src), "-o", str(out), "--check", "--plot", str(tmp_path / "t.png"))
    assert code == 0, text
    assert "3 duplicate rows merged (row 120 = row 0" in " ".join(text.split())
    data = np.load(out)
    assert {"points", "triangles", "hull"} <= set(data.files)
    assert np.array_equal(data["points"], pts)
    tri = data["triangles"]
    assert np.unique(tri).size == 120
    verify_triangulation(Predicates2(pts), tri, vertices=np.arange(120)).raise_if_failed()
    assert (tmp_path / "t.png").read_bytes().startswith(PNG_MAGIC)


def test_delaunay_xyz_to_ply_carries_z(tmp_path: Path) -> None:
    pts = np.random.default_rng(2).random((40, 3))
    np.save(tmp_path / "p.npy", pts)
    code, text = run("delaunay", str(tmp_path / "p.npy"), "-o", str(tmp_path / "p.ply"), "--quiet", "--stats")
    assert code == 0, text
    mesh = meshio.read(tmp_path / "p.ply")
    assert np.allclose(mesh.points, pts)


@pytest.mark.parametrize(
    ("content", "pattern"),
    [
        ("0,0\n1,1\n2,2\n3,3\n", r"bad\.csv: .*collinear"),
        ("0,0\n1,0\n", r"bad\.csv: 2 distinct points"),
        ("0,0,0,0\n1,0,0,0\n0,1,0,0\n", r"bad\.csv: line 1: expected 2 or 3 numbers, got 4"),
        ("0,0\n1,nan\n0,1\n", r"bad\.csv: line 2: a coordinate is not finite \(1\.0, nan\)"),
        ("a,b\n1,x\n", r'bad\.csv: line 2: "x" is not a number'),
    ],
)
def test_bad_delaunay_input_is_one_line(tmp_path: Path, content: str, pattern: str) -> None:
    src = tmp_path / "bad.csv"
    src.write_text(content)
    code, text = run("delaunay", str(src), "-o", str(tmp_path / "x.npz"), "--quiet")
    assert code == 2
    one_error_line(text, pattern)


# -- grid readers -------------------------------------------------------------------------------


def test_jacksboro_is_the_344_by_403_dem() -> None:
    g = jacksboro()
    assert g.heights.shape == (344, 403)
    assert g.transform is not None and g.transform.dy < 0 < g.transform.dx
    assert float(g.heights.min()) > 0 and np.array_equal(g.heights, np.round(g.heights))


def test_asc_round_trip_and_transform(tmp_path: Path) -> None:
    h = grid(5, 6)
    g = read_grid(write_asc(tmp_path / "g.asc", h, x0=100.0, y0=200.0, cellsize=10.0))
    assert np.array_equal(g.heights, h)  # first data row is row 0: no flip
    # Cell centres: column 0 at x 105; the last row (southernmost) at y 205, row 0 at 205 + 4 * 10.
    assert g.transform == GridTransform(105.0, 245.0, 10.0, -10.0)


def test_asc_header_errors(tmp_path: Path) -> None:
    bad = tmp_path / "bad.asc"
    bad.write_text("ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 5\n")
    with pytest.raises(ValueError, match="2 rows × 3 columns but the file holds 5 values"):
        read_grid(bad)
    bad.write_text("ncols 2\n1 2\n")
    with pytest.raises(ValueError, match="no nrows"):
        read_grid(bad)


def test_npz_by_name_or_only_array(tmp_path: Path) -> None:
    h = grid(4, 5)
    np.savez(tmp_path / "a.npz", heights=h, other=np.arange(3))
    assert np.array_equal(read_grid(tmp_path / "a.npz").heights, h)
    np.savez(tmp_path / "b.npz", dem2=h)
    assert np.array_equal(read_grid(tmp_path / "b.npz").heights, h)
    np.savez(tmp_path / "c.npz", p=h, q=h)
    with pytest.raises(ValueError, match="cannot tell which array"):
        read_grid(tmp_path / "c.npz")


def test_geotiff_with_georeferencing_and_nodata(tmp_path: Path) -> None:
    tifffile = pytest.importorskip("tifffile")
    h = grid(7, 9).astype(np.float32)
    h[2, 3] = -9999.0
    path = tmp_path / "g.tif"
    tifffile.imwrite(
        path,
        h,
        extratags=[
            (33550, "d", 3, (30.0, 30.0, 0.0)),  # ModelPixelScale
            (33922, "d", 6, (0.0, 0.0, 0.0, 500000.0, 4000000.0, 0.0)),  # ModelTiepoint: corner of pixel (0, 0)
            (42113, "s", 0, "-9999", False),  # GDAL_NODATA
        ],
    )
    g = read_grid(path)
    assert np.isnan(g.heights[2, 3]) and int(np.isnan(g.heights).sum()) == 1
    assert g.transform == GridTransform(500015.0, 3999985.0, 30.0, -30.0)  # pixel-is-area: centres half a cell in
    tin = greedy_insertion(g.heights, max_error=0.0, nodata="fill", transform=g.transform, check=True)
    assert tin.max_error == 0.0


def test_as_heights_accepts_integers_and_refuses_objects() -> None:
    assert as_heights(np.arange(6, dtype=np.int16).reshape(2, 3)).dtype == np.float64
    with pytest.raises(ValueError, match="exactly representable"):
        as_heights(np.array([[2**60 + 1, 1], [0, 0]], dtype=np.int64))
    with pytest.raises(ValueError, match="rectangular"):
        as_heights(np.array([[1, 2], [3]], dtype=object))


# -- persistri bench terrain ----------------------------------------------------------------------


def test_bench_terrain_json_small_sizes(tmp_path: Path) -> None:
    import json

    np.save(tmp_path / "g.npy", jacksboro().heights[:60, :70])
    result = CliRunner().invoke(
        main, ["bench", "terrain", "--sizes", "12,30", "--memory", "--json", "--grid", str(tmp_path / "g.npy")]
    )
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert doc["shape"] == [60, 70]
    records = doc["records"]
    assert [r["target"] for r in records] == [12, 30]
    for r in records:
        assert r["points"] == r["target"]  # pydelatin stops at exactly max_points here
        assert r["persistri_error"] <= 1.05 * r["pydelatin_error"]
        assert r["persistri_best_error"] <= r["persistri_error"]
        assert r["pydelatin_s"] > 0 and r["persistri_s"] > 0
        assert 0 < r["key_comparisons"] and 0 < r["plane_side_tests"] <= r["flops"]
    assert records[0]["key_comparisons"] < records[1]["key_comparisons"]
    m = doc["memory"]
    assert m["points"] == 30 and m["versions"] == 27
    assert m["history_kept"] > m["final_only_kept"] > 0


def test_bench_terrain_table_on_jacksboro_and_bad_sizes() -> None:
    result = CliRunner().invoke(main, ["bench", "terrain", "--sizes", "8"])
    assert result.exit_code == 0, result.output
    text = " ".join(result.stdout.split())
    assert "Greedy insertion on jacksboro 344×403 (red_black backend; persistri " in text
    assert "recomputed over every sample" in text
    bad = CliRunner().invoke(main, ["bench", "terrain", "--sizes", "two"])
    assert bad.exit_code == 2
    missing = CliRunner().invoke(main, ["bench", "terrain", "--sizes", "8", "--grid", "nope.npy"])
    assert missing.exit_code == 2 and missing.stderr == "persistri: nope.npy: no such file\n"
