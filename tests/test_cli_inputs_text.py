"""The text reader (``persistri.impl.files``): every variation reads the points of the ``.npy``; bad rows by line.

And what a shell user sees, in real processes: one line, no traceback, and no
warning for coordinates near ±1e308 or subnormal.
"""

from __future__ import annotations

import itertools
import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from cli_contract import invoke

from persistri.impl.files import read_points

# -- text files read like the .npy ------------------------------------------------------------------


def _numbers() -> np.ndarray:
    rng = np.random.default_rng(11)
    return np.vstack([rng.random((40, 3)) * 2 - 1, [[1e-300, -2.5, 1e300], [0.1, 0.2, 0.3]]])


def _rows(points: np.ndarray, sep: str) -> list[str]:
    return [sep.join(repr(float(v)) for v in row) for row in points]


def _variants(points: np.ndarray) -> Iterator[tuple[str, bytes]]:
    rows = _rows(points, ",")
    yield "plain", ("\n".join(rows) + "\n").encode()
    yield "header", ("x,y,z\n" + "\n".join(rows) + "\n").encode()
    yield "two headers", ("survey 2024\nx,y,z\n" + "\n".join(rows)).encode()
    yield "quoted header", ('"x","y","z"\n' + "\n".join(rows) + "\n").encode()
    yield "semicolons", ("x;y;z\n" + "\n".join(_rows(points, ";")) + "\n").encode()
    yield "tabs", ("x\ty\tz\n" + "\n".join(_rows(points, "\t")) + "\n").encode()
    yield "spaces", ("\n".join("  " + r + "  " for r in _rows(points, "   ")) + "\n").encode()
    yield "comments", ("# exported\nx,y,z\n# units: m\n" + "\n".join(r + " # ok" for r in rows) + "\n# end\n").encode()
    yield "blank lines", ("\n\nx,y,z\n\n" + "\n\n".join(rows) + "\n\n\n").encode()
    yield "crlf", ("x,y,z\r\n" + "\r\n".join(rows) + "\r\n").encode()
    yield "bom", b"\xef\xbb\xbf" + ("x,y,z\n" + "\n".join(rows) + "\n").encode()
    yield "bom crlf comments", b"\xef\xbb\xbf" + ("# a\r\nx;y;z\r\n\r\n" + "\r\n".join(_rows(points, ";")) + "\r\n").encode()


VARIANTS = [pytest.param(name, content, id=name) for name, content in _variants(_numbers())]


@pytest.mark.parametrize(("name", "content"), VARIANTS)
@pytest.mark.parametrize("suffix", [".csv", ".txt", ".xyz"])
def test_text_variants_read_the_same_points_as_the_npy(tmp_path: Path, name: str, content: bytes, suffix: str) -> None:
    src = tmp_path / f"points{suffix}"
    src.write_bytes(content)
    np.save(tmp_path / "points.npy", _numbers())
    assert np.array_equal(read_points(src, (3,)), read_points(tmp_path / "points.npy", (3,)))


@pytest.mark.parametrize(("name", "content"), VARIANTS[:1] + VARIANTS[-2:])
def test_the_hull_of_a_text_file_is_the_hull_of_the_npy(tmp_path: Path, name: str, content: bytes) -> None:
    (tmp_path / "p.csv").write_bytes(content)
    np.save(tmp_path / "p.npy", _numbers())
    for src in ("p.csv", "p.npy"):
        result, caught = invoke(["hull", str(tmp_path / src), "-o", str(tmp_path / f"{src}.npz"), "--quiet"])
        assert result.exit_code == 0 and not caught, (result.output, caught)
    with np.load(tmp_path / "p.csv.npz") as a, np.load(tmp_path / "p.npy.npz") as b:
        assert np.array_equal(a["points"], b["points"]) and np.array_equal(a["simplices"], b["simplices"])


@pytest.mark.parametrize(
    ("content", "line", "what"),
    [
        ("x,y,z\n0,0,0\n\n# c\n1,2\n", 5, "expected 3 numbers, got 2"),
        ("# c\nx y z\n1 2 3\n4 5 six\n", 4, '"six" is not a number'),
        ("1;2;3\n4;5;6;\n", 2, 'an empty field: "4;5;6;"'),
        ("1,2,3\n4 5 6\n", 2, '"4 5 6" is not a number'),
        ("1,2,x\n3,4,5\n", 1, '"x" is not a number'),
        ("\r\n".join(["a,b,c"] + ["1,2,3"] * 5000 + ["1,2,inf"]) + "\r\n", 5002, r"a coordinate is not finite \(1\.0, 2\.0, inf\)"),
        ("\n".join(["a,b,c"] + ["1,2,3"] * 3000 + ["1,2"] + ["1,2,3"] * 3000), 3002, "expected 3 numbers, got 2"),
    ],
)
def test_a_bad_row_is_named_by_its_line_in_the_file(tmp_path: Path, content: str, line: int, what: str) -> None:
    src = tmp_path / "rows.csv"
    src.write_text(content, newline="")
    with pytest.raises(ValueError, match=f"^{re.escape(str(src))}: line {line}: {what}"):
        read_points(src, (3,))


# -- real processes: what a shell user sees ---------------------------------------------------------


def _persistri() -> list[str]:
    script = Path(sys.executable).with_name("persistri")
    return [str(script)] if script.exists() else [sys.executable, "-c", "from persistri.impl.cli.main import main; main()"]


@pytest.mark.parametrize(
    ("files", "argv", "name"),
    [
        ({"points.csv": b"x,y,z\n0,0,0\n1,0,0\n0,1,0\n0,0,1\n"}, ["hull", "points.csv", "-o", "no/such/dir/x.ply"], "x.ply"),
        ({"empty.npy": b""}, ["hull", "empty.npy"], "empty.npy"),
        ({"junk.npy": bytes(range(256)) * 3}, ["terrain", "junk.npy", "--max-points", "9"], "junk.npy"),
        ({"rows.csv": b"1,2,3\n4,5\n"}, ["delaunay", "rows.csv"], "rows.csv"),
    ],
)
def test_in_a_real_process_one_line_and_no_traceback(tmp_path: Path, files: dict[str, bytes], argv: list[str], name: str) -> None:
    for file, content in files.items():
        (tmp_path / file).write_bytes(content)
    run = subprocess.run([*_persistri(), *argv], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert run.returncode == 2, run.stderr
    assert run.stderr.count("\n") == 1 and run.stderr.startswith("persistri: ") and name in run.stderr, run.stderr
    assert run.stdout == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(files)


def test_in_a_real_process_extreme_coordinates_print_no_warning(tmp_path: Path) -> None:
    """Coordinates near ±1e308 and subnormal ones: correct answers, and nothing on stderr (warnings would print there)."""
    big = np.finfo(np.float64).max
    cube = np.array(list(itertools.product([-big, big], repeat=3)))
    np.save(tmp_path / "huge.npy", np.vstack([np.random.default_rng(5).random((30, 3)) * 2 - 1, cube]))
    np.save(tmp_path / "tiny.npy", np.random.default_rng(6).integers(-4, 5, (40, 3)) * 5e-324)
    np.save(tmp_path / "huge2.npy", np.vstack([np.random.default_rng(5).random((30, 2)), cube[::2, :2]]))
    np.save(tmp_path / "tiny2.npy", np.unique(np.random.default_rng(6).integers(-4, 5, (40, 2)) * 5e-324, axis=0))
    np.save(tmp_path / "relief.npy", np.random.default_rng(8).integers(-3, 4, (12, 13)) * 5e-324)
    np.save(tmp_path / "alps.npy", np.random.default_rng(9).random((12, 13)) * 2e250 - 1e250)
    runs = [
        ["hull", "huge.npy", "--check", "-o", "a.stl", "--plot", "a.png"],
        ["hull", "tiny.npy", "--check", "-o", "b.stl", "--plot", "b.png"],
        ["delaunay", "huge2.npy", "--check", "-o", "c.ply", "--plot", "c.png"],
        ["delaunay", "tiny2.npy", "--check", "-o", "d.stl", "--plot", "d.png"],
        ["terrain", "relief.npy", "--max-points", "30", "--check", "-o", "e.stl", "--plot", "e.png"],
        ["terrain", "alps.npy", "--max-points", "30", "--check", "-o", "f.npz", "--plot", "f.png"],
    ]
    for argv in runs:
        run = subprocess.run([*_persistri(), *argv, "--quiet"], cwd=tmp_path, capture_output=True, text=True, timeout=300)
        assert run.returncode == 0 and run.stderr == "", (argv, run.stderr)
    hull = [ln for ln in (tmp_path / "a.stl").read_text().splitlines() if "facet normal" in ln]
    assert len(hull) == 12 and not any("nan" in ln or "inf" in ln for ln in hull)  # the cube's 12 triangles
    rms = float(np.load(tmp_path / "f.npz")["rms_error"])
    assert 0 < rms < np.inf
