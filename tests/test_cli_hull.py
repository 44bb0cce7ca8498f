"""``persistri hull``: files in, meshes out, one readable line on bad input."""

from __future__ import annotations

import re
from pathlib import Path

import meshio
import numpy as np
import pytest
from click.testing import CliRunner

from persistri.impl.cli.main import main
from persistri.impl.hull.distributions import generate
from persistri.impl.hull.verify import verify_hull


def run(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, ["hull", *args])
    return result.exit_code, result.output


def test_generated_distribution_to_npz_with_check_and_stats(tmp_path: Path) -> None:
    out = tmp_path / "h.npz"
    code, text = run("--dist", "BordHeavy", "-n", "300", "-o", str(out), "--check", "--stats", "--quiet")
    assert code == 0, text
    assert "plane side tests" in text
    data = np.load(out)
    assert set(data.files) == {"points", "simplices", "vertices"}
    assert np.array_equal(data["points"], generate("BordHeavy", 300, 0))
    assert verify_hull(data["points"], data["simplices"]).ok
    assert np.array_equal(np.unique(data["simplices"]), data["vertices"])


@pytest.mark.parametrize("suffix", [".ply", ".obj", ".off"])
def test_point_files_to_mesh_formats(tmp_path: Path, suffix: str) -> None:
    pts = generate("InBall", 200, 3)
    src = tmp_path / "pts.csv"
    np.savetxt(src, pts, delimiter=",", header="x,y,z")
    out = tmp_path / f"hull{suffix}"
    code, text = run(str(src), "-o", str(out), "--quiet", "--plot", str(tmp_path / "h.png"))
    assert code == 0, text
    mesh = meshio.read(out)
    assert mesh.cells[0].data.shape[1] == 3
    assert (tmp_path / "h.png").stat().st_size > 1000


def test_npy_and_xyz_inputs(tmp_path: Path) -> None:
    pts = generate("OnSphere", 100, 1)
    np.save(tmp_path / "p.npy", pts)
    np.savetxt(tmp_path / "p.xyz", pts)
    a = run(str(tmp_path / "p.npy"), "-o", str(tmp_path / "a.npz"), "--quiet")
    b = run(str(tmp_path / "p.xyz"), "-o", str(tmp_path / "b.npz"), "--quiet")
    assert a[0] == b[0] == 0
    assert np.array_equal(np.load(tmp_path / "a.npz")["simplices"], np.load(tmp_path / "b.npz")["simplices"])


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("0,0,0\n1,0,0\n0,1,0\n0,0,nan\n", r"bad\.csv: line 4: a coordinate is not finite \(0\.0, 0\.0, nan\)"),
        ("0,0,0\n1,1,1\n2,2,2\n3,3,3\n", r"bad\.csv: .*collinear"),
        ("0,0\n1,0\n", r"bad\.csv: line 1: expected 3 numbers, got 2"),
        ("a,b,c\n1,2,x\n", r'bad\.csv: line 2: "x" is not a number'),
    ],
)
def test_bad_files_exit_2_with_one_line(tmp_path: Path, content: str, message: str) -> None:
    src = tmp_path / "bad.csv"
    src.write_text(content)
    result = CliRunner().invoke(main, ["hull", str(src), "-o", str(tmp_path / "x.npz"), "--quiet"])
    assert result.exit_code == 2
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("persistri: "), result.output
    assert re.search(message, lines[0]), lines[0]
    assert not (tmp_path / "x.npz").exists()


@pytest.mark.parametrize(
    "args",
    [
        ("--dist", "InBall", "-n", "50", "--backend", "btree"),
        ("--dist", "InBall", "-n", "50", "-o", "out.xyz"),
        ("missing.npy",),
    ],
)
def test_bad_options_exit_2_with_one_line(args: tuple[str, ...]) -> None:
    result = CliRunner().invoke(main, ["hull", *args, "--quiet"])
    assert result.exit_code == 2
    assert len([ln for ln in result.output.splitlines() if ln.strip()]) == 1, result.output
