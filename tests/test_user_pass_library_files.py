"""The file readers used as a library: the caller's mistakes and the system's refusals, each in one line.

``read_points(path, columns=…)`` takes the accepted *widths* (``(2, 3)``), not column numbers (``fields``):
an empty sequence used to end in an IndexError from the message builder, and ``(0, 1)`` or ``("x",)`` in a
message blaming the file ("expected 0 or 1 numbers").  ``read_npy`` is public too, and let a missing file
or a directory through as the system's own ``FileNotFoundError`` / ``IsADirectoryError``.  ``write_mesh``
wrote a triangle holding index -1 as one ending at the last point (a wrong mesh, silently), failed deep in
NumPy on an index past the end, and crashed inside meshio (leaving half a file) on planar points as .obj/.stl.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from persistri.impl.files import InputFileError, read_npy, read_points, write_mesh


@pytest.fixture
def csv(tmp_path: Path) -> Path:
    path = tmp_path / "points.csv"
    path.write_text("0,0,0\n1,0,0\n0,1,0\n")
    return path


def test_accepted_widths_read_the_file(csv: Path) -> None:
    assert read_points(csv, columns=(2, 3)).shape == (3, 3)
    assert read_points(csv, columns=[np.int64(3)]).shape == (3, 3)
    with pytest.raises(InputFileError, match=r"points.csv: line 1: expected 2 numbers, got 3"):
        read_points(csv, columns=(2,))


@pytest.mark.parametrize(
    ("columns", "error", "message"),
    [
        ((), ValueError, r"at least one accepted width \(None accepts any\)"),
        ((0, 1), ValueError, r"each at least 1, got 0: to pick columns, use fields"),
        ((-1,), ValueError, r"each at least 1, got -1"),
        (("x",), TypeError, r"integers\), not str 'x': to pick columns, use fields"),
        ((True,), TypeError, r"not bool True"),
        ((2.0,), TypeError, r"not float 2.0"),
        ("3", TypeError, r"a sequence of accepted widths such as \(2, 3\), not str"),
        (3, TypeError, r"not int"),
    ],
)
def test_a_wrong_columns_argument_is_the_callers_error(csv: Path, columns: object, error: type, message: str) -> None:
    with pytest.raises(error, match=message) as info:
        read_points(csv, columns=columns)  # type: ignore[arg-type]
    assert not isinstance(info.value, InputFileError)  # the file is fine


def test_read_npy_names_a_missing_file_and_a_directory(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match=r"^\S*missing.npy: no such file$"):
        read_npy(tmp_path / "missing.npy")
    (tmp_path / "dir.npy").mkdir()
    with pytest.raises(InputFileError, match=r"^\S*dir.npy: a directory, not a file$"):
        read_npy(tmp_path / "dir.npy")
    np.save(tmp_path / "ok.npy", np.zeros((2, 3)))
    assert read_npy(tmp_path / "ok.npy", mmap=True).shape == (2, 3)


POINTS = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [5.0, 5.0, 5.0]])


@pytest.mark.parametrize(
    ("triangles", "error", "message"),
    [
        ([[0, 1, -1]], ValueError, r"triangle 0 \[0, 1, -1\]: a point index is outside 0..3"),
        ([[0, 1, 2], [0, 1, 7]], ValueError, r"triangle 1 \[0, 1, 7\]: a point index is outside 0..3"),
        ([[0.0, 1.0, 2.0]], TypeError, r"integer indices into the points, not float64"),
        ([[0, 1]], ValueError, r"an \(m, 3\) array of point indices, got shape \(1, 2\)"),
    ],
)
@pytest.mark.parametrize("suffix", [".ply", ".npz"])
def test_write_mesh_refuses_bad_triangles_before_writing(
    tmp_path: Path, suffix: str, triangles: object, error: type, message: str
) -> None:
    out = tmp_path / f"mesh{suffix}"
    with pytest.raises(error, match=message):
        write_mesh(out, POINTS, np.asarray(triangles))
    assert not out.exists()


def test_write_mesh_refuses_points_of_the_wrong_shape(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"mesh points must be an \(n, 2\) or \(n, 3\) array, got shape \(4, 4\)"):
        write_mesh(tmp_path / "m.ply", np.zeros((4, 4)), [[0, 1, 2]])
    with pytest.raises(TypeError, match=r"mesh points must be real numbers"):
        write_mesh(tmp_path / "m.ply", np.full((3, 3), "a"), [[0, 1, 2]])


@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")  # meshio reading the STL back
@pytest.mark.parametrize("suffix", [".ply", ".obj", ".off", ".stl"])
def test_write_mesh_puts_planar_points_at_z_0(tmp_path: Path, suffix: str, capfd: pytest.CaptureFixture[str]) -> None:
    import meshio

    out = write_mesh(tmp_path / f"m{suffix}", POINTS[:, :2], [[0, 1, 2]])
    mesh = meshio.read(out)
    assert np.array_equal(mesh.points, POINTS[:3])
    assert mesh.cells_dict["triangle"].tolist() == [[0, 1, 2]]
    assert capfd.readouterr().out == ""  # no meshio warning about padding
