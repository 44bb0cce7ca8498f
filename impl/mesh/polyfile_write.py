"""Writing Triangle's files: ``.node``, ``.poly``, ``.ele`` and ``.edge`` (the formats :mod:`.polyfile` reads).

Every float is printed with Python's shortest round-tripping ``repr``, so a write
followed by a read (:mod:`persistri.impl.mesh.polyfile`) gives back the same
doubles; numbering starts at ``first_number`` (0 or 1, Triangle's two
conventions).  The names are importable from :mod:`persistri.impl.mesh.polyfile`
too.  Cost: O(size of the file).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.mesh.domain import PSLG, counted

__all__ = ["write_node", "write_poly", "write_ele", "write_edge"]

PathLike = str | os.PathLike[str]


def _rows(*columns: NDArray[Any]) -> list[str]:
    """One line per row: integers as such, floats as their shortest round-tripping repr."""
    cols = [c.reshape(c.shape[0], -1) for c in columns if c is not None]
    parts = [c.tolist() for c in cols]
    return ["  ".join(" ".join(repr(v) if isinstance(v, float) else str(v) for v in block[i]) for block in parts) for i in range(cols[0].shape[0])]


def _numbered(first: int, n: int) -> NDArray[np.int64]:
    return np.arange(first, first + n, dtype=np.int64)


def _check_first(first_number: int) -> None:
    if first_number not in (0, 1):
        raise ValueError(f"first_number must be 0 or 1, got {first_number}")


def _vertex_lines(vertices: NDArray[np.float64], attributes: NDArray[np.float64] | None, markers: NDArray[np.intp] | None, first: int) -> list[str]:
    n = vertices.shape[0]
    nattr = 0 if attributes is None else attributes.reshape(n, -1).shape[1]
    head = f"{n}  2  {nattr}  {0 if markers is None else 1}"
    cols: list[NDArray[Any]] = [_numbered(first, n), vertices.astype(np.float64)]
    if attributes is not None and nattr:
        cols.append(attributes.reshape(n, -1).astype(np.float64))
    if markers is not None:
        cols.append(np.asarray(markers).reshape(n).astype(np.int64))
    return [head] + _rows(*cols)


def _write(path: PathLike, what: str, lines: list[str]) -> None:
    Path(path).write_text(f"# {what}, written by persistri\n" + "\n".join(lines) + "\n", encoding="utf-8")


def _as_real(values: ArrayLike, width: int | None, what: str) -> NDArray[np.float64]:
    arr = np.asarray(values, dtype=np.float64)
    if arr.ndim != 2 or (width is not None and arr.shape[1] != width):
        raise ValueError(f"{what} must be an (n, {width if width else 'k'}) array, got shape {arr.shape}")
    return arr


def write_node(
    path: PathLike,
    vertices: ArrayLike,
    *,
    attributes: ArrayLike | None = None,
    markers: ArrayLike | None = None,
    first_number: int = 1,
) -> None:
    """Write a ``.node`` file (shortest round-tripping floats). O(n)."""
    _check_first(first_number)
    v = _as_real(vertices, 2, "vertices")
    attr = None if attributes is None else _as_real(np.asarray(attributes, dtype=np.float64).reshape(v.shape[0], -1), None, "attributes")
    mark = None if markers is None else np.asarray(markers).reshape(-1).astype(np.intp)
    _write(path, f"{v.shape[0]} vertices", _vertex_lines(v, attr, mark, first_number))


def write_poly(path: PathLike, pslg: PSLG, *, first_number: int = 1, node_file: bool = False) -> None:
    """Write a PSLG as a ``.poly`` file; ``node_file=True`` puts the vertices in the ``.node`` beside it (as Triangle). O(n + m)."""
    _check_first(first_number)
    p = Path(path)
    verts = pslg.vertices
    if node_file:
        write_node(p.with_suffix(".node"), verts, attributes=pslg.vertex_attributes, markers=pslg.vertex_markers, first_number=first_number)
        nattr = 0 if pslg.vertex_attributes is None else pslg.vertex_attributes.shape[1]
        lines = [f"0  2  {nattr}  {0 if pslg.vertex_markers is None else 1}"]
    else:
        lines = _vertex_lines(verts, pslg.vertex_attributes, pslg.vertex_markers, first_number)
    seg = np.asarray(pslg.segments, dtype=np.int64).reshape(-1, 2)
    m = seg.shape[0]
    smark = pslg.segment_markers
    lines.append(f"{m}  {0 if smark is None else 1}")
    if m:
        cols: list[NDArray[Any]] = [_numbered(first_number, m), seg + first_number]
        if smark is not None:
            cols.append(np.asarray(smark).reshape(m).astype(np.int64))
        lines += _rows(*cols)
    holes = np.asarray(pslg.holes, dtype=np.float64).reshape(-1, 2)
    lines.append(f"{holes.shape[0]}")
    if holes.shape[0]:
        lines += _rows(_numbered(first_number, holes.shape[0]), holes)
    regions = np.asarray(pslg.regions, dtype=np.float64).reshape(-1, 4)
    if regions.shape[0]:
        lines.append(f"{regions.shape[0]}")
        lines += _rows(_numbered(first_number, regions.shape[0]), regions)
    what = ", ".join(
        (counted(verts, "vertex", "vertices"), counted(seg, "segment"), counted(holes, "hole"), counted(regions, "region"))
    )
    _write(p, f"a PSLG: {what}", lines)


def write_ele(path: PathLike, triangles: ArrayLike, *, attributes: ArrayLike | None = None, first_number: int = 1) -> None:
    """Write an ``.ele`` file from ``(t, 3)`` 0-based vertex rows (counterclockwise, as Triangle expects). O(t)."""
    _check_first(first_number)
    tri = np.asarray(triangles)
    if tri.ndim != 2 or tri.shape[1] != 3 or (tri.size and tri.dtype.kind not in "iu"):
        raise ValueError(f"triangles must be a (t, 3) integer array, got shape {tri.shape} of {tri.dtype}")
    t = tri.shape[0]
    attr = None if attributes is None else np.asarray(attributes, dtype=np.float64).reshape(t, -1)
    lines = [f"{t}  3  {0 if attr is None else attr.shape[1]}"]
    if t:
        cols: list[NDArray[Any]] = [_numbered(first_number, t), tri.astype(np.int64) + first_number]
        if attr is not None:
            cols.append(attr)
        lines += _rows(*cols)
    _write(path, f"{t} triangles", lines)


def write_edge(path: PathLike, edges: ArrayLike, *, markers: ArrayLike | None = None, first_number: int = 1) -> None:
    """Write an ``.edge`` file from ``(e, 2)`` 0-based vertex rows. O(e)."""
    _check_first(first_number)
    ed = np.asarray(edges)
    if ed.ndim != 2 or ed.shape[1] != 2 or (ed.size and ed.dtype.kind not in "iu"):
        raise ValueError(f"edges must be an (e, 2) integer array, got shape {ed.shape} of {ed.dtype}")
    e = ed.shape[0]
    mark = None if markers is None else np.asarray(markers).reshape(e).astype(np.int64)
    lines = [f"{e}  {0 if mark is None else 1}"]
    if e:
        cols: list[NDArray[Any]] = [_numbered(first_number, e), ed.astype(np.int64) + first_number]
        if mark is not None:
            cols.append(mark)
        lines += _rows(*cols)
    _write(path, f"{e} edges", lines)
