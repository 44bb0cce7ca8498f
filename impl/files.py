"""Reading point sets and writing triangle meshes, by file extension.

Point inputs: ``.npy`` (an array), ``.csv`` / ``.xyz`` / ``.txt`` (one point per
line, comma- or whitespace-separated, ``#`` comments and one optional header line),
``.ply`` (the vertices of a PLY file, through meshio).  Mesh outputs: ``.ply``,
``.obj``, ``.off``, ``.stl`` through meshio, and ``.npz`` holding named arrays.
Every failure is a :class:`ValueError` with one readable line.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["POINT_FORMATS", "MESH_FORMATS", "read_points", "write_mesh", "compact_mesh"]

POINT_FORMATS = (".npy", ".csv", ".xyz", ".txt", ".ply")
MESH_FORMATS = (".ply", ".obj", ".off", ".stl", ".npz")


def _read_text(path: Path) -> NDArray[Any]:
    lines = [ln.strip() for ln in path.read_text().splitlines()]
    rows = [ln for ln in lines if ln and not ln.startswith("#")]
    if not rows:
        raise ValueError(f"{path}: no points in the file")
    sep = "," if "," in rows[0] else None

    def parse(line: str) -> list[float]:
        return [float(tok) for tok in line.split(sep)]

    try:
        first = parse(rows[0])
    except ValueError:
        rows = rows[1:]  # a header line
        if not rows:
            raise ValueError(f"{path}: no points in the file") from None
    parsed: list[list[float]] = []
    for number, line in enumerate(rows, start=1):
        try:
            parsed.append(parse(line))
        except ValueError:
            raise ValueError(f"{path}: point {number} is not a row of numbers: {line!r}") from None
    widths = {len(r) for r in parsed}
    if len(widths) != 1:
        raise ValueError(f"{path}: rows have different numbers of coordinates {sorted(widths)}")
    del first
    return np.array(parsed, dtype=np.float64)


def read_points(path: str | Path) -> NDArray[Any]:
    """The point array stored in ``path`` (validation of shape and values is the caller's)."""
    p = Path(path)
    suffix = p.suffix.lower()
    if not p.exists():
        raise ValueError(f"{p}: no such file")
    if suffix == ".npy":
        try:
            arr: NDArray[Any] = np.load(p, allow_pickle=False)
        except ValueError as exc:
            raise ValueError(f"{p}: not a numeric .npy array ({exc})") from None
        return arr
    if suffix in (".csv", ".xyz", ".txt"):
        return _read_text(p)
    if suffix == ".ply":
        import meshio

        try:
            mesh = meshio.read(p)
        except Exception as exc:  # meshio raises many types for malformed files
            raise ValueError(f"{p}: cannot read PLY ({exc})") from None
        pts: NDArray[Any] = np.asarray(mesh.points, dtype=np.float64)
        return pts
    raise ValueError(f"{p}: unknown point format {suffix!r}; use one of {', '.join(POINT_FORMATS)}")


def compact_mesh(
    points: NDArray[Any], triangles: NDArray[Any]
) -> tuple[NDArray[np.float64], NDArray[np.intp], NDArray[np.intp]]:
    """The mesh on the points its triangles use: ``(used points, renumbered triangles, used)``. O(n + m).

    ``used`` holds the indices into ``points`` of the kept points, ascending (so
    their relative order is kept): ``points[used]`` are the new points and
    ``used[new_triangles]`` equals ``triangles``.
    """
    pts = np.asarray(points, dtype=np.float64)
    tri = np.asarray(triangles, dtype=np.intp).reshape(-1, 3)
    used: NDArray[np.intp] = np.unique(tri).astype(np.intp)
    renumber = np.full(pts.shape[0], -1, dtype=np.intp)
    renumber[used] = np.arange(used.size, dtype=np.intp)
    return pts[used], renumber[tri], used


def write_mesh(
    path: str | Path,
    points: NDArray[Any],
    triangles: NDArray[Any],
    *,
    npz_arrays: dict[str, Any] | None = None,
) -> Path:
    """Write the triangle mesh ``(points, triangles)`` to ``path`` by its extension.

    ``.npz`` stores ``npz_arrays`` (the caller names the arrays, e.g. ``points``,
    ``simplices`` and ``vertices`` for a hull); the other formats store the
    triangles and only the points they use (:func:`compact_mesh`: a viewer would
    show an unused point as a stray dot), through meshio.
    """
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in MESH_FORMATS:
        raise ValueError(f"{p}: unknown mesh format {suffix!r}; use one of {', '.join(MESH_FORMATS)}")
    if p.parent and not p.parent.exists():
        p.parent.mkdir(parents=True, exist_ok=True)
    if suffix == ".npz":
        arrays = npz_arrays if npz_arrays is not None else {"points": points, "triangles": triangles}
        np.savez(p, **arrays)
        return p
    import meshio

    used_points, renumbered, _ = compact_mesh(points, triangles)
    tri = renumbered.astype(np.int64)
    if tri.size == 0 or int(tri.max()) < 2**31:
        tri = tri.astype(np.int32)  # PLY has no 64-bit integers: meshio would warn and cast anyway
    meshio.write(p, meshio.Mesh(used_points, [("triangle", tri)]))
    return p
