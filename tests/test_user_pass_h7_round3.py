"""A new user's third pass (H7, 2026-11-28, round 3): files of other programs, each case failed before its fix.

Wrong answers first: a no-data cell kept as a height, a region's number written where Triangle
writes its attribute.  Then valid files refused with a misleading line.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from persistri.impl.terrain.grids import read_grid


def _geotiff(path: Path, heights: np.ndarray, nodata: str) -> Path:
    tifffile = pytest.importorskip("tifffile")
    tifffile.imwrite(
        path,
        heights,
        extratags=[
            (33550, "d", 3, (10.0, 10.0, 0.0)),  # ModelPixelScale
            (33922, "d", 6, (0.0, 0.0, 0.0, 500000.0, 4000000.0, 0.0)),  # ModelTiepoint
            (42113, "s", 0, nodata, False),  # GDAL_NODATA
        ],
        photometric="minisblack",
    )
    return path


@pytest.mark.parametrize(
    ("dtype", "fill", "tag"),
    [
        # float32's lowest value, its tag as numpy and rasterio print a float32: as a double it is another number.
        (np.float32, float(np.finfo(np.float32).min), str(np.finfo(np.float32).min)),
        (np.float32, -9999.9, "-9999.9"),  # float32(-9999.9) == -9999.900390625 as a double
        (np.float32, 1e20, "1e+20"),
        (np.float64, -9999.9, "-9999.9"),  # a double band: the tag's double itself
        (np.int16, -32768, "-32768.0"),
    ],
)
def test_geotiff_nodata_is_compared_in_the_band_type(tmp_path: Path, dtype: type, fill: float, tag: str) -> None:
    # Before: the tag was compared as a double with the cells widened to doubles, so a float32 band's
    # no-data cells (float32(-3.4028235e+38) is not the double -3.4028235e+38) became heights of -3.4e38,
    # and `persistri terrain` meshed them as vertices.
    heights = np.arange(30, dtype=np.float64).reshape(5, 6).astype(dtype)
    heights[1, 2] = fill
    heights[4, 5] = fill
    g = read_grid(_geotiff(tmp_path / "dem.tif", heights, tag))
    assert np.isnan(g.heights).sum() == 2 and np.isnan(g.heights[1, 2]) and np.isnan(g.heights[4, 5])
    assert np.nanmax(np.abs(g.heights)) == 28.0  # 29 was the no-data cell (4, 5)


def test_geotiff_nodata_that_the_band_cannot_hold_matches_nothing(tmp_path: Path) -> None:
    ints = np.arange(30, dtype=np.int16).reshape(5, 6)
    assert not np.isnan(read_grid(_geotiff(tmp_path / "a.tif", ints, "3.5")).heights).any()  # not integral
    assert not np.isnan(read_grid(_geotiff(tmp_path / "b.tif", ints, "70000")).heights).any()  # beyond int16
    floats = np.arange(30, dtype=np.float32).reshape(5, 6)
    assert not np.isnan(read_grid(_geotiff(tmp_path / "c.tif", floats, "1e300")).heights).any()  # beyond float32
    assert np.isnan(read_grid(_geotiff(tmp_path / "d.tif", floats, "7")).heights).sum() == 1


def test_tiled_terrain_reads_the_same_nodata_cells(tmp_path: Path) -> None:
    # `persistri terrain dem.tif --tile` reads its windows through another reader, which had the same comparison.
    pytest.importorskip("zarr")
    from persistri.impl.scale.terrain_source import open_dem

    heights = np.arange(30, dtype=np.float32).reshape(5, 6)
    heights[1, 2] = np.finfo(np.float32).min
    path = _geotiff(tmp_path / "dem.tif", heights, str(np.finfo(np.float32).min))
    window = open_dem(path).source.read(0, 5, 0, 6)
    assert np.array_equal(np.isnan(window), np.isnan(read_grid(path).heights)) and np.isnan(window).sum() == 1


_TWO_REGIONS = """# two regions, a wall between them, Triangle's regional attributes 7 and -2.5
6 2 0 0
1 0 0
2 10 0
3 10 10
4 0 10
5 5 0
6 5 10
7 0
1 1 5
2 5 2
3 2 3
4 3 6
5 6 4
6 4 1
7 5 6
0
2
1 1 1 7 0
2 9 1 -2.5 0
"""


@pytest.mark.parametrize("min_angle", ["0", "25"])
def test_mesh_ele_carries_the_regional_attribute_as_triangle_does(tmp_path: Path, min_angle: str) -> None:
    # Before: the .ele's attribute column held each triangle's region number (1, 2), where Triangle's -A
    # writes the region's attribute (7, -2.5): a side-by-side comparison with Triangle's output disagreed.
    from cli_contract import invoke

    from persistri.impl.mesh.polyfile import read_mesh

    (tmp_path / "two.poly").write_text(_TWO_REGIONS)
    result, _ = invoke(["mesh", str(tmp_path / "two.poly"), "--min-angle", min_angle, "-o", str(tmp_path / "out.ele"), "--quiet"])
    assert result.exit_code == 0, result.output
    node, ele = read_mesh(tmp_path / "out.ele")
    assert ele.attributes is not None
    centroid_x = node.vertices[ele.triangles].mean(axis=1)[:, 0]
    assert np.array_equal(ele.attributes[:, 0], np.where(centroid_x < 5, 7.0, -2.5))
    triangle = pytest.importorskip("triangle")
    from persistri.impl.mesh.polyfile import read_poly

    d = read_poly(tmp_path / "two.poly")
    theirs = triangle.triangulate({"vertices": d.vertices, "segments": d.segments, "regions": d.regions}, "pA")
    assert set(theirs["triangle_attributes"][:, 0]) == set(ele.attributes[:, 0]) == {7.0, -2.5}


_POINTS = [(0.25, 0.5, 0.75), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (1.5, 2.5, 3.5)]


@pytest.mark.parametrize(
    ("name", "row", "header"),
    [
        # columns aligned with spaces and a tab: the tab was taken for the delimiter, every line for a header
        # ("no points: 5 lines of text and no row of numbers").
        ("aligned.xyz", "   {}    {}\t {}  ", ""),
        ("aligned_tab_first.txt", "{}\t   {}   {}", ""),
        # a delimiter ending every row (some exporters): "an empty field" without a header line.
        ("trailing.csv", "{},{},{},", ""),
        ("trailing_semicolon.csv", "{};{};{};", ""),
        ("trailing_crlf.csv", "{},{},{},\r", ""),
        # a blank after the delimiter, before a quoted field: '""0.5"" is not a number'.
        ("quoted_spaced.csv", '"{}", "{}", "{}"', '"x", "y", "z"\n'),
        ("quoted_leading.csv", '  "{}","{}","{}"', ""),
    ],
)
def test_valid_text_points_are_read(tmp_path: Path, name: str, row: str, header: str) -> None:
    from persistri.impl.files import read_points

    path = tmp_path / name
    path.write_text(header + "".join(row.format(*p) + "\n" for p in _POINTS), newline="")
    assert np.array_equal(read_points(path), np.array(_POINTS))


def test_a_trailing_delimiter_on_some_rows_only_is_still_an_empty_field(tmp_path: Path) -> None:
    from persistri.impl.files import InputFileError, read_points

    path = tmp_path / "ragged.csv"
    path.write_text("0,0,0,\n1,0,0\n0,1,0,\n0,0,1,\n")
    with pytest.raises(InputFileError, match=r"line 1: an empty field"):
        read_points(path)


def test_a_tab_separated_file_with_an_empty_field_is_still_named(tmp_path: Path) -> None:
    from persistri.impl.files import InputFileError, read_points

    path = tmp_path / "tabs.txt"
    path.write_text("0\t0\t0\n1\t\t0\n")
    with pytest.raises(InputFileError, match=r"line 2: an empty field"):
        read_points(path)


def test_no_row_of_numbers_shows_the_first_line(tmp_path: Path) -> None:
    # Was "no points: 3 lines of text and no row of numbers": it did not say what was read, nor what is accepted.
    from persistri.impl.files import InputFileError, read_points

    path = tmp_path / "pipes.txt"
    path.write_text("0|0|0\n1|0|0\n0|1|0\n")
    with pytest.raises(InputFileError, match=r"3 lines of text and no row of numbers separated by commas, semicolons, tabs or spaces \(line 1: \"0\|0\|0\"\)"):
        read_points(path)


def _xyz_text() -> str:
    return "x,y,z\r\n" + "".join(f"{a},{b},{c}\r\n" for a, b, c in _POINTS)


@pytest.mark.parametrize("encoding", ["utf-16", "utf-16-le", "utf-16-be"])
def test_utf16_text_with_its_mark_is_read(tmp_path: Path, encoding: str) -> None:
    # Windows PowerShell 5's `Out-File` and `>` write UTF-16 with a byte-order mark: was refused ("save it as UTF-8").
    from persistri.impl.files import read_points

    path = tmp_path / "points.csv"
    mark = {"utf-16": b"", "utf-16-le": b"\xff\xfe", "utf-16-be": b"\xfe\xff"}[encoding]
    path.write_bytes(mark + _xyz_text().encode(encoding))
    assert np.array_equal(read_points(path), np.array(_POINTS))


def test_gzip_text_points_and_grids_are_read(tmp_path: Path) -> None:
    # Was "unknown point format .gz" from the command and the library alike.
    import gzip

    from cli_contract import invoke

    from persistri.impl.files import InputFileError, read_points

    (tmp_path / "points.xyz.gz").write_bytes(gzip.compress(_xyz_text().encode()))
    assert np.array_equal(read_points(tmp_path / "points.xyz.gz"), np.array(_POINTS))
    result, _ = invoke(["hull", str(tmp_path / "points.xyz.gz"), "-o", str(tmp_path / "h.npz")])
    assert result.exit_code == 0, result.output
    (tmp_path / "points.xyz").write_text(_xyz_text())
    plain, _ = invoke(["hull", str(tmp_path / "points.xyz"), "-o", str(tmp_path / "plain.npz")])
    assert np.array_equal(np.load(tmp_path / "h.npz")["simplices"], np.load(tmp_path / "plain.npz")["simplices"])
    (tmp_path / "heights.csv.gz").write_bytes(gzip.compress(b"1,2,3\n4,5,6\n7,8,10\n"))
    assert np.array_equal(read_grid(tmp_path / "heights.csv.gz").heights, [[1, 2, 3], [4, 5, 6], [7, 8, 10]])
    result, _ = invoke(["terrain", str(tmp_path / "heights.csv.gz"), "--max-points", "4", "-o", str(tmp_path / "t.npz")])
    assert result.exit_code == 0, result.output
    # a truncated stream, a line beyond a double's range (read again on the error path, through gzip too)
    (tmp_path / "cut.xyz.gz").write_bytes(gzip.compress(_xyz_text().encode())[:25])
    with pytest.raises(InputFileError, match=r"cut\.xyz\.gz: a damaged gzip file"):
        read_points(tmp_path / "cut.xyz.gz")
    (tmp_path / "big.xyz.gz").write_bytes(gzip.compress(b"0 0 0\n1e400 0 0\n0 1 0\n0 0 1\n"))
    with pytest.raises(InputFileError, match=r"line 2: .*beyond the largest double .* \"1e400 0 0\""):
        read_points(tmp_path / "big.xyz.gz")
    (tmp_path / "p.npy.gz").write_bytes(gzip.compress(b"\x93NUMPY"))
    with pytest.raises(InputFileError, match=r"a gzip-compressed \.npy: .*decompress it first"):
        read_points(tmp_path / "p.npy.gz")


@pytest.mark.parametrize("separator", ["\t", " "])
def test_decimal_commas_between_tabs_are_named(tmp_path: Path, separator: str) -> None:
    # German Excel's "Text (tab-delimited)": the comma was taken for the delimiter, and the line said '"5\t1" is not a number'.
    from persistri.impl.files import InputFileError, read_points

    path = tmp_path / "points.txt"
    path.write_text("".join(separator.join(f"{v:.1f}".replace(".", ",") for v in p) + "\n" for p in _POINTS))
    with pytest.raises(InputFileError, match=r"line 1: numbers with decimal commas \(\"0,2\"\) separated by tabs or spaces: .*decimal points"):
        read_points(path)


def test_a_structured_npy_says_how_to_save_the_numbers(tmp_path: Path) -> None:
    # Was "holds [('x', '<f8'), ('y', '<f8'), ('z', '<f8'), ('intensity', '<u2')] values, not real numbers": the
    # fields are real numbers, what is wrong is the record layout (PDAL's arrays, a point record).
    from persistri.impl.files import InputFileError, read_points

    records = np.zeros(4, dtype=[("x", "f8"), ("y", "f8"), ("z", "f8"), ("intensity", "u2")])
    np.save(tmp_path / "cloud.npy", records)
    with pytest.raises(InputFileError, match=r"a structured array \(a record per row, fields x, y, z, intensity\), .*np\.column_stack\(\[a\['x'\], a\['y'\], a\['z'\]\]\)"):
        read_points(tmp_path / "cloud.npy")
    with pytest.raises(ValueError, match=r"a structured array"):
        read_grid(tmp_path / "cloud.npy")


def test_a_binary_ply_cut_short_is_named_truncated(tmp_path: Path) -> None:
    # Was "cannot read PLY (buffer size must be a multiple of element size)", numpy's words.
    from persistri.impl.files import InputFileError, read_points

    header = b"ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float intensity\nproperty double x\nproperty double y\nproperty double z\nend_header\n"
    body = np.zeros(5, dtype=[("i", "<f4"), ("x", "<f8"), ("y", "<f8"), ("z", "<f8")])
    body["x"], body["y"], body["z"] = np.array(_POINTS).T
    (tmp_path / "whole.ply").write_bytes(header + body.tobytes())
    assert np.array_equal(read_points(tmp_path / "whole.ply"), np.array(_POINTS))
    (tmp_path / "cut.ply").write_bytes(header + body.tobytes()[:-7])
    with pytest.raises(InputFileError, match=r"cut\.ply: truncated: the PLY header announces 5 vertices of 28 bytes, the file holds 133 bytes"):
        read_points(tmp_path / "cut.ply")


def test_a_grayscale_png_heightmap_is_a_grid(tmp_path: Path) -> None:
    # Was "unknown grid format .png": the heightmaps of games and terrain editors are 8- or 16-bit grayscale PNGs.
    from cli_contract import invoke
    from PIL import Image

    heights = (np.arange(12 * 9, dtype=np.uint32).reshape(12, 9) * 601 % 65536).astype(np.uint16)
    Image.fromarray(heights).save(tmp_path / "h16.png")
    Image.fromarray((heights // 256).astype(np.uint8)).save(tmp_path / "h8.png")
    assert np.array_equal(read_grid(tmp_path / "h16.png").heights, heights)
    assert np.array_equal(read_grid(tmp_path / "h8.png").heights, heights // 256)
    result, _ = invoke(["terrain", str(tmp_path / "h16.png"), "--max-error", "0", "-o", str(tmp_path / "t.npz")])
    assert result.exit_code == 0, result.output
    assert float(np.load(tmp_path / "t.npz")["max_error"]) == 0.0
    Image.fromarray(np.stack([heights // 256] * 3, axis=-1).astype(np.uint8)).save(tmp_path / "rgb.png")
    with pytest.raises(ValueError, match=r"rgb\.png: an image of mode RGB .*one grayscale band"):
        read_grid(tmp_path / "rgb.png")
    (tmp_path / "cut.png").write_bytes((tmp_path / "h16.png").read_bytes()[:60])
    with pytest.raises(ValueError, match=r"cut\.png: cannot read PNG"):
        read_grid(tmp_path / "cut.png")


def test_an_esri_grid_names_its_first_field_that_is_no_number(tmp_path: Path) -> None:
    # Was "the grid holds something that is not a number": which line, which field?
    header = "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
    (tmp_path / "commas.asc").write_text(header + "1,2,3\n4,5,6\n")
    with pytest.raises(ValueError, match=r"commas\.asc: line 6: '1,2,3' is not a number \(fields are separated by blanks"):
        read_grid(tmp_path / "commas.asc")
    (tmp_path / "word.asc").write_text(header + "1 2 3\n4 n/a 6\n")
    with pytest.raises(ValueError, match=r"word\.asc: line 7: 'n/a' is not a number$"):
        read_grid(tmp_path / "word.asc")


def test_a_header_without_x_y_says_how_to_choose_columns(tmp_path: Path) -> None:
    # The README's `persistri delaunay survey.csv` on the survey.csv of `hull ... --columns east,north,height`:
    # was 'line 2: "2024-01-01" is not a number', with no word of --columns.
    from cli_contract import assert_one_line_failure, invoke

    from persistri.impl.files import InputFileError, read_points

    path = tmp_path / "survey.csv"
    path.write_text("id,date,east,north,height\n1,2024-01-01,5.5,4.25,101.5\n2,2024-01-01,10,0,99\n3,2024-01-02,0,10,98\n")
    result, caught = invoke(["delaunay", str(path), "-o", str(tmp_path / "tin.npz")])
    assert_one_line_failure(result, caught, "survey.csv", r"line 2: \"2024-01-01\" is not a number; choose the columns by the header's names \(id, date, east, north, height\): --columns")
    wide = tmp_path / "wide.csv"
    wide.write_text("id,east,north,height,q\n1,0,0,0,1\n2,1,0,0,1\n3,0,1,0,1\n4,0,0,1,1\n")
    with pytest.raises(InputFileError, match=r"line 2: expected 3 numbers, got 5; choose the columns by the header's names \(id, east, north, height, q\)"):
        read_points(wide, columns=(3,))
    assert read_points(wide, columns=(3,), fields=["east", "north", "height"]).shape == (4, 3)
    # a header that names no more columns than a point has: nothing to choose, no hint
    narrow = tmp_path / "narrow.csv"
    narrow.write_text('easting,northing,elevation\n"1,000.5",2,3\n0,1,0\n0,0,1\n1,1,1\n')
    with pytest.raises(InputFileError, match=r"line 2: \"1,000\.5\" is not a number$"):
        read_points(narrow, columns=(3,))


@pytest.mark.parametrize(
    ("command", "name", "advice"),
    [
        ("hull", "cloud.las", r"a LAS point cloud: convert it, e\.g\. `pdal translate"),
        ("delaunay", "survey.xlsx", r"a spreadsheet: save the sheet as CSV"),
        ("delaunay", "dots.node", r"a Triangle \.node file: `persistri mesh FILE --min-angle 0`"),
        ("terrain", "N45E006.hgt", r"an SRTM tile: convert it to GeoTIFF first"),
        ("hull", "points.npy.gz", r"gzip is decompressed only around text"),
    ],
)
def test_a_known_foreign_format_says_what_to_do(tmp_path: Path, command: str, name: str, advice: str) -> None:
    # Was only "unknown point format .las; use one of ...": the formats a user brings most often get a way forward.
    from cli_contract import assert_one_line_failure, invoke

    (tmp_path / name).write_bytes(b"\x00" * 16)
    args = [command, str(tmp_path / name), "-o", str(tmp_path / "out.npz")] + (["--max-points", "5"] if command == "terrain" else [])
    result, caught = invoke(args)
    assert_one_line_failure(result, caught, name, r"unknown (point|grid) format \.\w+; use one of .*; " + advice)


def test_an_output_that_is_the_input_is_refused(tmp_path: Path) -> None:
    # `persistri hull cloud.ply -o cloud.ply` replaced the 30-point cloud by its 17-vertex hull; `terrain dem.npz
    # -o dem.npz` replaced the grid by the mesh; `terrain h.png --plot h.png` the heightmap by its picture.
    from cli_contract import assert_one_line_failure, invoke
    from PIL import Image

    cloud = tmp_path / "cloud.ply"
    text = "ply\nformat ascii 1.0\nelement vertex 5\nproperty double x\nproperty double y\nproperty double z\nend_header\n"
    cloud.write_text(text + "".join(f"{a} {b} {c}\n" for a, b, c in _POINTS))
    before = cloud.read_bytes()
    np.savez(tmp_path / "dem.npz", heights=np.arange(20.0).reshape(4, 5) ** 2)
    Image.fromarray(np.arange(20, dtype=np.uint8).reshape(4, 5)).save(tmp_path / "h.png")
    (tmp_path / "alias.ply").symlink_to(cloud)
    for args, name in [
        (["hull", str(cloud), "-o", str(cloud)], "cloud.ply"),
        (["hull", str(cloud), "-o", str(tmp_path / "alias.ply")], "alias.ply"),
        (["delaunay", str(cloud), "-o", str(tmp_path / "." / "cloud.ply")], "cloud.ply"),
        (["terrain", str(tmp_path / "dem.npz"), "--max-points", "5", "-o", str(tmp_path / "dem.npz")], "dem.npz"),
        (["terrain", str(tmp_path / "h.png"), "--max-points", "5", "--plot", str(tmp_path / "h.png")], "h.png"),
    ]:
        result, caught = invoke(args)
        assert_one_line_failure(result, caught, name, r"is an input of this run; name the output otherwise")
    assert cloud.read_bytes() == before
    assert set(np.load(tmp_path / "dem.npz")) == {"heights"}
    assert np.array_equal(read_grid(tmp_path / "h.png").heights, np.arange(20).reshape(4, 5))


def test_text_that_is_not_utf8_says_how_to_save_it(tmp_path: Path) -> None:
    # Was "not UTF-8 text (byte 0xf6 at offset 21)": which line, and what to do?
    from persistri.impl.files import InputFileError, read_points

    path = tmp_path / "survey.csv"
    path.write_bytes("x,y,z\n0,0,0\n# H\xf6he in m\n1,0,0\n".encode("latin-1"))
    with pytest.raises(InputFileError, match=r"not UTF-8 text \(byte 0xf6 at offset 15, line 3; Latin-1 or Windows-1252.*\): save it as UTF-8$"):
        read_points(path)
