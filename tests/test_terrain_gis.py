"""Terrain files a GIS user can open: world orientation, compressed GeoTIFF, the CRS, compact meshes.

Every check reads the written files back (meshio for .ply/.obj/.off/.stl, numpy for .npz)
and recomputes what it asserts from them.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path
from typing import Any

import meshio
import numpy as np
import pytest
from click.testing import CliRunner

from persistri.impl.cli.main import main
from persistri.impl.files import compact_mesh
from persistri.impl.terrain.crs import Crs, crs_from_geokeys
from persistri.impl.terrain.export import tin_arrays, write_tin
from persistri.impl.terrain.greedy import greedy_insertion
from persistri.impl.terrain.esri_grid import write_asc
from persistri.impl.terrain.grids import GridTransform, read_grid

tifffile = pytest.importorskip("tifffile")
pytest.importorskip("imagecodecs")
pyproj = pytest.importorskip("pyproj")

MESH_SUFFIXES = (".ply", ".obj", ".off", ".stl")
UTM14N_WKT = (
    'PROJCS["WGS_1984_UTM_Zone_14N",GEOGCS["GCS_WGS_1984",DATUM["D_WGS_1984",SPHEROID["WGS_1984",6378137.0,'
    '298.257223563]],PRIMEM["Greenwich",0.0],UNIT["Degree",0.0174532925199433]],PROJECTION["Transverse_Mercator"],'
    'PARAMETER["False_Easting",500000.0],PARAMETER["False_Northing",0.0],PARAMETER["Central_Meridian",-99.0],'
    'PARAMETER["Scale_Factor",0.9996],PARAMETER["Latitude_Of_Origin",0.0],UNIT["Meter",1.0]]'
)


def run(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, list(args))
    return result.exit_code, result.output


def one_error_line(text: str, pattern: str) -> None:
    lines = [ln for ln in text.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("persistri: "), text
    assert re.search(pattern, lines[0]), lines[0]


def terrain(rows: int = 14, cols: int = 19, seed: int = 0) -> np.ndarray:
    """A rough height field with no symmetry, so that every orientation mistake shows."""
    rng = np.random.default_rng(seed)
    return np.cumsum(np.cumsum(rng.normal(size=(rows, cols)), axis=0), axis=1).round(2)


def geokey_directory(*keys: tuple[int, int], citation: str | None = None) -> list[tuple[Any, ...]]:
    """GeoTIFF tags for tifffile's ``extratags``: the GeoKeyDirectory (short keys) and, if given, a citation.

    Each key is ``(GeoKey id, value)``; the citation is PCSCitationGeoKey (3073) in GeoAsciiParams.
    """
    entries = [(1024, 0, 1, 1), (1025, 0, 1, 1)]  # GTModelType Projected, GTRasterType PixelIsArea
    entries += [(k, 0, 1, v) for k, v in keys]
    tags: list[tuple[Any, ...]] = []
    if citation is not None:
        text = citation + "|"
        entries.append((3073, 34737, len(text), 0))
        tags.append((34737, "s", 0, text, False))
    entries.sort()
    flat = [1, 1, 0, len(entries)] + [v for e in entries for v in e]
    return [(34735, "H", len(flat), tuple(flat)), *tags]


def tie_and_scale(x0: float = 500000.0, y0: float = 4000000.0, cell: float = 30.0) -> list[tuple[Any, ...]]:
    return [
        (33550, "d", 3, (cell, cell, 0.0)),  # ModelPixelScale
        (33922, "d", 6, (0.0, 0.0, 0.0, x0, y0, 0.0)),  # ModelTiepoint: corner of pixel (0, 0)
    ]


def model_transformation(a: float, d: float, e: float, f: float) -> list[tuple[Any, ...]]:
    """ModelTransformation x = a·col + d, y = e·row + f (pixel corners), no rotation."""
    return [(34264, "d", 16, (a, 0.0, 0.0, d, 0.0, e, 0.0, f, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0))]


def up_normals(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """The z component of each triangle's normal (twice its signed area in (x, y)), from a file's arrays."""
    p = np.asarray(points, dtype=np.float64)
    a, b, c = p[triangles[:, 0]], p[triangles[:, 1]], p[triangles[:, 2]]
    out: np.ndarray = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    return out


def read_back(path: Path) -> tuple[np.ndarray, np.ndarray]:
    if path.suffix == ".npz":
        data = np.load(path)
        return data["vertices"], data["triangles"]
    mesh = meshio.read(path)
    return np.asarray(mesh.points), np.asarray(mesh.cells_dict["triangle"])


# -- 1. orientation in world coordinates -----------------------------------------------------------


@pytest.mark.parametrize(
    "transform",
    [
        (500000.0, 4000000.0, 30.0, -30.0),  # north-up: the determinant is negative
        (500000.0, 4000000.0, 30.0, 30.0),  # south-up
        (500000.0, 4000000.0, -30.0, 30.0),  # east-left, row 0 south: negative determinant
        (500000.0, 4000000.0, -30.0, -30.0),  # rotated half a turn: positive determinant
        (-84.4, 36.7, 1 / 1200, -1 / 1200),  # degrees, north-up (jacksboro's kind)
    ],
)
def test_world_triangles_are_counterclockwise_from_above(transform: tuple[float, ...]) -> None:
    h = terrain()
    tin = greedy_insertion(h, max_points=40, transform=transform)
    v, t = tin.world_vertices(), tin.world_triangles()
    assert bool(np.all(up_normals(v, t) > 0))
    assert bool(np.all(up_normals(tin.vertices, tin.triangles) > 0))  # grid coordinates stay counterclockwise
    # The same triangles as vertex sets, only their order may change.
    assert {frozenset(r) for r in t.tolist()} == {frozenset(r) for r in tin.triangles.tolist()}
    tf = GridTransform(transform[0], transform[1], transform[2], transform[3])
    assert tf.mirrors == (transform[2] * transform[3] < 0)
    assert np.array_equal(t, tin.triangles) != tf.mirrors


def geotiff(path: Path, h: np.ndarray, tags: list[tuple[Any, ...]], **kw: Any) -> Path:
    tifffile.imwrite(path, h.astype(np.float32), extratags=tags, **kw)
    return path


@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")  # meshio's STL reader sizing an ASCII file
@pytest.mark.parametrize("suffix", [*MESH_SUFFIXES, ".npz"])
@pytest.mark.parametrize("layout", ["asc north-up", "tif north-up", "tif south-up"])
def test_cli_world_meshes_have_normals_up(tmp_path: Path, suffix: str, layout: str) -> None:
    h = terrain()
    if layout == "asc north-up":
        src = write_asc(tmp_path / "g.asc", h, x0=1000.0, y0=2000.0, cellsize=5.0)
    elif layout == "tif north-up":
        src = geotiff(tmp_path / "g.tif", h, tie_and_scale() + geokey_directory((3072, 32614)))
    else:  # row 0 is the southernmost: y grows with the row
        src = geotiff(tmp_path / "g.tif", h, model_transformation(30.0, 500000.0, 30.0, 3990000.0) + geokey_directory((3072, 32614)))
    out = tmp_path / f"tin{suffix}"
    code, text = run("terrain", str(src), "--max-points", "50", "--world", "-o", str(out), "--quiet")
    assert code == 0, text
    points, triangles = read_back(out)
    assert len(triangles) >= 50
    assert bool(np.all(up_normals(points, triangles) > 0)), f"{int(np.sum(up_normals(points, triangles) <= 0))} triangles face down"
    # The vertices are where the transform puts them: the npz says which grid sample each one is.
    npz = tmp_path / "same.npz"
    assert run("terrain", str(src), "--max-points", "50", "--world", "-o", str(npz), "--quiet")[0] == 0
    data = np.load(npz)
    g = read_grid(src)
    assert g.transform is not None
    rows, cols = np.divmod(data["samples"], h.shape[1])
    assert np.allclose(data["vertices"][:, 0], g.transform.x0 + cols * g.transform.dx, rtol=0, atol=1e-9 * abs(g.transform.x0))
    assert np.allclose(data["vertices"][:, 1], g.transform.y0 + rows * g.transform.dy, rtol=0, atol=1e-9 * abs(g.transform.y0))
    assert np.array_equal(data["vertices"][:, 2], g.heights[rows, cols])
    if suffix != ".stl":  # STL stores each triangle's own corners; the others share vertices
        assert len(points) == len(data["vertices"])


def test_south_up_geotiff_transform(tmp_path: Path) -> None:
    h = terrain(5, 6)
    src = geotiff(tmp_path / "s.tif", h, model_transformation(30.0, 500000.0, 30.0, 3990000.0))
    tf = read_grid(src).transform
    assert tf == GridTransform(500015.0, 3990015.0, 30.0, 30.0)  # pixel-is-area: centres half a cell in
    assert tf is not None and not tf.mirrors
    rotated = geotiff(tmp_path / "r.tif", h, [(34264, "d", 16, (30.0, 5.0, 0, 0, 5.0, -30.0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1.0))])
    with pytest.raises(ValueError, match="rotated or sheared"):
        read_grid(rotated)


# -- 2. compressed GeoTIFF -------------------------------------------------------------------------

CODECS = [
    ("lzw", None, np.float32, None),
    ("lzw", 2, np.int16, None),  # horizontal differencing, as GDAL writes integer DEMs
    ("deflate", None, np.float32, None),
    ("deflate", 3, np.float32, (16, 16)),  # floating-point predictor, tiled
    ("deflate", 2, np.uint16, (32, 16)),
    ("zstd", None, np.float64, (16, 32)),
    ("packbits", None, np.int32, None),
    ("lzma", 3, np.float32, None),
]


@pytest.mark.parametrize(("compression", "predictor", "dtype", "tile"), CODECS)
def test_compressed_geotiff_reads_exactly(tmp_path: Path, compression: str, predictor: int | None, dtype: Any, tile: Any) -> None:
    h = (terrain(37, 41) * 10).astype(dtype)
    path = tmp_path / "c.tif"
    kw: dict[str, Any] = {"compression": compression, "extratags": tie_and_scale() + geokey_directory((3072, 32614))}
    if predictor is not None:
        kw["predictor"] = predictor
    if tile is not None:
        kw["tile"] = tile
    else:
        kw["rowsperstrip"] = 5  # several strips
    tifffile.imwrite(path, h, **kw)
    with tifffile.TiffFile(path) as tif:
        page = tif.pages[0]
        assert page.compression.name.lower().endswith(compression) or compression == "deflate"
        assert page.is_tiled == (tile is not None)
    g = read_grid(path)
    assert np.array_equal(g.heights, h.astype(np.float64))
    assert g.transform == GridTransform(500015.0, 3999985.0, 30.0, -30.0, Crs(32614))
    np.save(tmp_path / "plain.npy", h)
    a, b = tmp_path / "from_tif.npz", tmp_path / "from_npy.npz"
    assert run("terrain", str(path), "--max-points", "30", "-o", str(a), "--quiet")[0] == 0
    assert run("terrain", str(tmp_path / "plain.npy"), "--max-points", "30", "-o", str(b), "--quiet")[0] == 0
    for name in ("vertices", "triangles", "samples"):
        assert np.array_equal(np.load(a)[name], np.load(b)[name])


def test_undecodable_compression_names_file_and_codec(tmp_path: Path) -> None:
    path = geotiff(tmp_path / "odd.tif", terrain(6, 7), tie_and_scale())
    with tifffile.TiffFile(path, mode="r+") as tif:
        tif.pages[0].tags["Compression"].overwrite(60001)  # no codec has this number
    code, text = run("terrain", str(path), "--max-points", "10")
    assert code != 0
    one_error_line(text, r"odd\.tif: cannot decode its 60001 compression")


def test_missing_decoder_says_what_to_install(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "lzw.tif"
    tifffile.imwrite(path, terrain(6, 7).astype(np.float32), compression="lzw")

    def refuse(*args: Any, **kwargs: Any) -> Any:
        raise ValueError("<COMPRESSION.LZW: 5> requires the 'imagecodecs' package")

    monkeypatch.setattr(tifffile.TiffPage, "asarray", refuse)  # what tifffile says without imagecodecs
    code, text = run("terrain", str(path), "--max-points", "10")
    assert code != 0
    one_error_line(text, r"lzw\.tif: cannot decode its LZW compression .*pip install 'persistri\[geotiff\]'")


def test_multi_band_tiff_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "rgb.tif"
    tifffile.imwrite(path, np.zeros((6, 7, 3), np.uint8))
    code, text = run("terrain", str(path), "--max-points", "10")
    assert code != 0
    one_error_line(text, r"rgb\.tif: expected one band of heights, got 3 samples per pixel")


# -- 3. the CRS ------------------------------------------------------------------------------------


def test_geokeys_to_crs() -> None:
    assert crs_from_geokeys({"ProjectedCSTypeGeoKey": 32614}) == Crs(32614)
    assert crs_from_geokeys({"GeographicTypeGeoKey": 4326}) == Crs(4326)
    # A projected raster's geographic key is only its datum: the projected one wins, user-defined means none.
    assert crs_from_geokeys({"ProjectedCSTypeGeoKey": 26915, "GeographicTypeGeoKey": 4269}) == Crs(26915)
    assert crs_from_geokeys({"ProjectedCSTypeGeoKey": 32767, "GeographicTypeGeoKey": 4269}) is None
    assert crs_from_geokeys({}) is None
    cited = crs_from_geokeys({"PCSCitationGeoKey": f"ESRI PE String = {UTM14N_WKT}"})
    assert cited == Crs(wkt=UTM14N_WKT)
    with pytest.raises(ValueError, match="EPSG code or a WKT"):
        Crs()
    with pytest.raises(ValueError, match="not a WKT"):
        Crs(wkt="Projection UTM")


def test_geotiff_epsg_to_npz_and_prj(tmp_path: Path) -> None:
    src = geotiff(tmp_path / "utm.tif", terrain(), tie_and_scale() + geokey_directory((3072, 32614), citation="UTM 14N"))
    g = read_grid(src)
    assert g.crs == Crs(32614)  # a citation that is no WKT is only a name
    code, text = run("terrain", str(src), "--max-points", "30", "--world", "-o", str(tmp_path / "t.npz"))
    assert code == 0, text
    data = np.load(tmp_path / "t.npz")
    assert str(data["crs"]) == "EPSG:32614" and "crs_wkt" not in data.files
    assert bool(data["world"]) and np.array_equal(data["grid_shape"], [14, 19])
    assert not (tmp_path / "t.prj").exists()  # the .npz holds its CRS itself
    code, text = run("terrain", str(src), "--max-points", "30", "--world", "-o", str(tmp_path / "t.ply"))
    assert code == 0, text
    assert "CRS EPSG:32614" in text and "t.prj" in text
    wkt = (tmp_path / "t.prj").read_text()
    assert wkt.startswith('PROJCS["WGS_1984_UTM_Zone_14N"')
    assert pyproj.CRS.from_wkt(wkt).to_epsg() == 32614


def test_geotiff_geographic_and_citation_wkt(tmp_path: Path) -> None:
    tags = tie_and_scale(-99.5, 36.5, 1 / 1200) + geokey_directory((2048, 4326), citation=f"ESRI PE String = {UTM14N_WKT}")
    src = geotiff(tmp_path / "g.tif", terrain(), tags)
    assert read_grid(src).crs == Crs(4326, UTM14N_WKT)
    out = tmp_path / "g.obj"
    assert run("terrain", str(src), "--max-points", "20", "--world", "-o", str(out), "--quiet")[0] == 0
    assert (tmp_path / "g.prj").read_text().strip() == UTM14N_WKT  # the file's own WKT, verbatim
    assert run("terrain", str(src), "--max-points", "20", "--world", "-o", str(tmp_path / "g.npz"), "--quiet")[0] == 0
    data = np.load(tmp_path / "g.npz")
    assert str(data["crs"]) == "EPSG:4326" and str(data["crs_wkt"]) == UTM14N_WKT


def test_asc_with_and_without_prj(tmp_path: Path) -> None:
    h = terrain()
    src = write_asc(tmp_path / "dem.asc", h, x0=500000.0, y0=4000000.0, cellsize=10.0)
    assert read_grid(src).crs is None
    assert run("terrain", str(src), "--max-points", "20", "--world", "-o", str(tmp_path / "a.ply"), "--quiet")[0] == 0
    assert not (tmp_path / "a.prj").exists()  # no CRS, no sidecar
    assert run("terrain", str(src), "--max-points", "20", "--world", "-o", str(tmp_path / "a.npz"), "--quiet")[0] == 0
    assert "crs" not in np.load(tmp_path / "a.npz").files and "transform" in np.load(tmp_path / "a.npz").files
    (tmp_path / "dem.prj").write_text(UTM14N_WKT)
    assert read_grid(src).crs == Crs(wkt=UTM14N_WKT)
    code, text = run("terrain", str(src), "--max-points", "20", "--world", "-o", str(tmp_path / "b.stl"))
    assert code == 0, text
    assert "WKT 'WGS_1984_UTM_Zone_14N'" in text
    assert (tmp_path / "b.prj").read_text().strip() == UTM14N_WKT
    # Grid coordinates are not in the CRS: no sidecar, but the .npz keeps the transform and CRS to get there.
    assert run("terrain", str(src), "--max-points", "20", "-o", str(tmp_path / "c.ply"), "--quiet")[0] == 0
    assert not (tmp_path / "c.prj").exists()
    assert run("terrain", str(src), "--max-points", "20", "-o", str(tmp_path / "c.npz"), "--quiet")[0] == 0
    data = np.load(tmp_path / "c.npz")
    assert not bool(data["world"]) and str(data["crs"]) == UTM14N_WKT
    read = read_grid(src).transform
    assert read is not None and data["transform"].tolist() == [read.x0, read.y0, read.dx, read.dy]


def test_a_mesh_named_like_its_asc_leaves_the_input_prj_as_it_is(tmp_path: Path) -> None:
    # dem.asc meshed to dem.ply: the sidecar due beside the mesh is dem.prj, the input's own; it already holds the
    # CRS, so it is not rewritten (it was, stripped and with a newline added: an input file changed by a run).
    src = write_asc(tmp_path / "dem.asc", terrain(), x0=500000.0, y0=4000000.0, cellsize=10.0)
    own = "  " + UTM14N_WKT + "\r\n\r\n"
    (tmp_path / "dem.prj").write_bytes(own.encode())
    code, text = run("terrain", str(src), "--max-points", "20", "--world", "-o", str(tmp_path / "dem.ply"), "--quiet")
    assert code == 0, text
    assert (tmp_path / "dem.prj").read_bytes() == own.encode()
    assert (tmp_path / "dem.ply").is_file()
    # A .prj beside the output that holds another CRS is replaced, as before.
    (tmp_path / "other.prj").write_text('PROJCS["something else"]')
    assert run("terrain", str(src), "--max-points", "20", "--world", "-o", str(tmp_path / "other.ply"), "--quiet")[0] == 0
    assert (tmp_path / "other.prj").read_text().strip() == UTM14N_WKT


def test_prj_that_is_not_wkt_is_one_line(tmp_path: Path) -> None:
    src = write_asc(tmp_path / "dem.asc", terrain(), cellsize=10.0)
    (tmp_path / "dem.prj").write_text("Projection    UTM\nZone          14\nDatum         WGS84\n")
    code, text = run("terrain", str(src), "--max-points", "20")
    assert code != 0
    one_error_line(text, r"dem\.prj: not a WKT coordinate system")


def test_epsg_without_pyproj_fails_before_the_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    src = geotiff(tmp_path / "utm.tif", terrain(), tie_and_scale() + geokey_directory((3072, 32614)))
    monkeypatch.setitem(sys.modules, "pyproj", None)  # import pyproj now raises ImportError
    out = tmp_path / "t.ply"
    code, text = run("terrain", str(src), "--max-points", "20", "--world", "-o", str(out))
    assert code != 0
    one_error_line(text, r"EPSG:32614 as the WKT of a \.prj file needs pyproj")
    assert not out.exists() and not (tmp_path / "t.prj").exists()
    assert run("terrain", str(src), "--max-points", "20", "--world", "-o", str(tmp_path / "t.npz"), "--quiet")[0] == 0


# -- 4. compact meshes -----------------------------------------------------------------------------


def test_compact_mesh_keeps_order_and_renumbers() -> None:
    pts = np.arange(18, dtype=np.float64).reshape(6, 3)
    tri = np.array([[5, 1, 3], [3, 1, 4]])
    used_pts, new_tri, used = compact_mesh(pts, tri)
    assert used.tolist() == [1, 3, 4, 5]
    assert np.array_equal(used[new_tri], tri) and np.array_equal(used_pts, pts[used])


def test_tin_npz_maps_vertices_to_grid_samples(tmp_path: Path) -> None:
    h = terrain()
    tin = greedy_insertion(h, max_error=1.0, transform=(0.0, 0.0, 1.0, -1.0))
    arrays = tin_arrays(tin)
    rows, cols = np.divmod(arrays["samples"], h.shape[1])
    assert np.array_equal(arrays["vertices"], np.column_stack([cols, rows, h[rows, cols]]).astype(np.float64))
    assert np.unique(arrays["triangles"]).size == len(arrays["vertices"])
    written = write_tin(tmp_path / "w.off", tin, world=True)
    assert written == [tmp_path / "w.off"]  # georeferenced, but no CRS: no sidecar
    with pytest.raises(ValueError, match="unknown mesh format"):
        write_tin(tmp_path / "w.vtk", tin)


def test_hull_and_delaunay_mesh_files_hold_only_used_points(tmp_path: Path) -> None:
    rng = np.random.default_rng(5)
    cloud = rng.random((300, 3))
    np.save(tmp_path / "cloud.npy", cloud)
    assert run("hull", str(tmp_path / "cloud.npy"), "-o", str(tmp_path / "h.ply"), "--quiet")[0] == 0
    assert run("hull", str(tmp_path / "cloud.npy"), "-o", str(tmp_path / "h.npz"), "--quiet")[0] == 0
    mesh = meshio.read(tmp_path / "h.ply")
    data = np.load(tmp_path / "h.npz")
    assert np.array_equal(data["points"], cloud)  # the .npz keeps the input and the hull's vertex indices
    assert np.array_equal(mesh.points, cloud[data["vertices"]])
    assert np.array_equal(data["vertices"][mesh.cells_dict["triangle"]], data["simplices"])
    flat = np.vstack([rng.random((60, 2)), [[0.5, 0.5]] * 3])  # duplicates: merged, not meshed
    np.save(tmp_path / "flat.npy", flat)
    assert run("delaunay", str(tmp_path / "flat.npy"), "-o", str(tmp_path / "d.obj"), "--quiet")[0] == 0
    mesh = meshio.read(tmp_path / "d.obj")
    assert len(mesh.points) == np.unique(mesh.cells_dict["triangle"]).size == 61
