"""Point sets in row chunks, each readable where it is used: on a worker, never all at once on the client.

A :class:`PointSource` is an ``(n, 3)`` point set cut into consecutive row
ranges (:class:`Block`); the rows keep their numbers in the whole input, which is
how every result of :mod:`persistri.impl.scale.hull` names points.  What a block
holds is small and picklable, so a task can carry it to a worker that reads the
rows itself:

* a memory-mapped ``.npy`` file — the path and the row range
  (:class:`NpyRows`: the worker maps the file and copies its rows; a file larger
  than memory is never loaded whole);
* a directory of ``.npy`` files — one after another in file-name order (name them
  with zero-padded numbers), each file cut like a single one;
* a Zarr array (an array object, or the path of a store holding one) — its row
  range (:class:`ZarrRows`: the worker reads the chunks it covers);
* a Dask array — its blocks (Dask computes each where the task runs);
* an array in memory — views of its rows (the client sends each block once).

Only the headers are read here (shape and dtype, checked at once: one clear
error for a file that is not an ``(n, 3)`` numeric array).  The rows are
validated when read, by :func:`read_block`, with the error naming the row in the
whole input, as :func:`persistri.impl.geometry.points.as_points` names it for one
array.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from persistri.impl.geometry.points import as_points

__all__ = ["Block", "NpyRows", "PointSource", "ZarrRows", "DEFAULT_CHUNK_ROWS", "points_source", "read_block"]

DEFAULT_CHUNK_ROWS = 1 << 18
"""Rows per block when none is given (262,144 points, 6 MiB of float64): a chunk hull of a few seconds."""


@dataclass(frozen=True)
class NpyRows:
    """Rows ``start:stop`` of the ``.npy`` file ``path``, read through a memory map."""

    path: str
    start: int
    stop: int

    def read(self) -> NDArray[Any]:
        """The rows, copied out of the map (the map itself is closed with the array). O(rows)."""
        mapped = np.load(self.path, mmap_mode="r", allow_pickle=False)
        return np.array(mapped[self.start : self.stop])


@dataclass(frozen=True)
class ZarrRows:
    """Rows ``start:stop`` of a Zarr array: the array object (Zarr arrays pickle as their store and path)."""

    array: Any
    start: int
    stop: int

    def read(self) -> NDArray[Any]:
        """The rows, read from the chunks of the array that hold them. O(rows)."""
        return np.asarray(self.array[self.start : self.stop])


@dataclass(frozen=True)
class Block:
    """Rows ``start:stop`` of the whole input and how to read them (``data``).

    ``data`` is an array (the rows themselves), a reader (:class:`NpyRows`,
    :class:`ZarrRows`) or a ``dask.delayed`` block of a Dask array.
    """

    start: int
    stop: int
    data: Any

    def __len__(self) -> int:
        return self.stop - self.start


@dataclass(frozen=True)
class PointSource:
    """An ``(n, 3)`` point set as consecutive blocks covering rows ``0 … n - 1``.

    ``name`` says what it is (for messages and reports); ``what`` is how errors about
    its rows begin (``points``, or the file: ``pts.npy: row 7 is not finite: …``).
    """

    n: int
    blocks: tuple[Block, ...]
    name: str
    what: str = "points"


def _rows(n: int, chunk_rows: int) -> list[tuple[int, int]]:
    """``0 … n`` cut into ranges of ``chunk_rows`` (the last one shorter); one empty range for n = 0."""
    if n == 0:
        return [(0, 0)]
    return [(a, min(a + chunk_rows, n)) for a in range(0, n, chunk_rows)]


def _check_header(what: str, shape: tuple[int, ...], dtype: np.dtype[Any]) -> None:
    if dtype.kind not in "biuf":
        raise TypeError(f"{what}: points must be real numbers, not {dtype}")
    if len(shape) != 2 or shape[1] != 3:
        raise ValueError(f"{what}: points must be an (n, 3) array, got shape {shape}")


def _npy_header(path: Path) -> tuple[tuple[int, ...], np.dtype[Any]]:
    """The shape and dtype of the ``.npy`` file ``path``, its header checked (:func:`~persistri.impl.files.read_npy`)."""
    from persistri.impl.files import read_npy

    mapped = read_npy(path, mmap=True)
    return mapped.shape, mapped.dtype


def _is_zarr_store(path: Path) -> bool:
    return (path / "zarr.json").is_file() or (path / ".zarray").is_file()


def points_source(points: Any, chunk_rows: int | None = None) -> PointSource:
    """``points`` as a :class:`PointSource` of blocks of ``chunk_rows`` rows (:data:`DEFAULT_CHUNK_ROWS`).

    ``points``: a :class:`PointSource` (returned as it is); a path (``str`` or :class:`~pathlib.Path`) of a ``.npy`` file, of
    a directory of ``.npy`` files or of a Zarr store; a Zarr array; a Dask array
    (cut along its own row chunks unless ``chunk_rows`` is given); or any array
    of shape ``(n, 3)``.  Raises :class:`ValueError`/:class:`TypeError` (one line)
    for a missing path, a file of another shape or a non-numeric dtype,
    :class:`ValueError` for ``chunk_rows < 1``.  O(number of blocks); no row is read.
    """
    if isinstance(points, PointSource):
        return points
    if chunk_rows is not None and (isinstance(chunk_rows, bool) or chunk_rows < 1):
        raise ValueError(f"chunk size must be at least 1 row, got {chunk_rows}")
    size = chunk_rows or DEFAULT_CHUNK_ROWS
    if isinstance(points, (str, Path)):
        return _path_source(Path(points), size)
    module = type(points).__module__
    if module.startswith("zarr"):
        _check_header("zarr array", tuple(points.shape), np.dtype(points.dtype))
        n = int(points.shape[0])
        blocks = tuple(Block(a, b, ZarrRows(points, a, b)) for a, b in _rows(n, size))
        return PointSource(n, blocks, f"zarr array of {n:,} points")
    if module.startswith("dask"):
        return _dask_source(points, chunk_rows)
    arr = np.asarray(points)
    if arr.dtype == object or arr.ndim != 2 or arr.shape[1] != 3:
        as_points(arr, 3)  # its own one-line error for ragged, non-numeric or mis-shaped input
    n = int(arr.shape[0])
    return PointSource(n, tuple(Block(a, b, arr[a:b]) for a, b in _rows(n, size)), f"array of {n:,} points")


def _path_source(path: Path, size: int) -> PointSource:
    if not path.exists():
        raise FileNotFoundError(2, "No such file or directory", str(path))
    if path.is_dir():
        if _is_zarr_store(path):
            import zarr

            array = zarr.open_array(store=str(path), mode="r")
            source = points_source(array, size)
            return PointSource(source.n, source.blocks, f"{path} (zarr, {source.n:,} points)", str(path))
        files = sorted(p for p in path.iterdir() if p.suffix.lower() == ".npy" and p.is_file())
        if not files:
            raise ValueError(f"{path}: a directory of points must hold .npy files (or be a Zarr store); it holds none")
        blocks: list[Block] = []
        offset = 0
        for f in files:
            shape, dtype = _npy_header(f)
            _check_header(str(f), shape, dtype)
            for a, b in _rows(int(shape[0]), size):
                if b > a:
                    blocks.append(Block(offset + a, offset + b, NpyRows(str(f), a, b)))
            offset += int(shape[0])
        if not blocks:
            blocks.append(Block(0, 0, np.zeros((0, 3))))
        return PointSource(offset, tuple(blocks), f"{path} ({len(files)} .npy files, {offset:,} points)", str(path))
    if path.suffix.lower() != ".npy":
        raise ValueError(f"{path}: chunked input must be a .npy file, a directory of .npy files or a Zarr store")
    shape, dtype = _npy_header(path)
    _check_header(str(path), shape, dtype)
    n = int(shape[0])
    rows = tuple(Block(a, b, NpyRows(str(path), a, b)) for a, b in _rows(n, size))
    return PointSource(n, rows, f"{path} ({n:,} points)", str(path))


def _dask_source(x: Any, chunk_rows: int | None) -> PointSource:
    _check_header("dask array", tuple(int(s) for s in x.shape), np.dtype(x.dtype))
    if any(np.isnan(c) for c in x.chunks[0]):
        raise ValueError("dask array: its row chunks must have known sizes (call compute_chunk_sizes() first)")
    x = x.rechunk({0: chunk_rows or x.chunks[0], 1: 3})
    delayed = x.to_delayed().ravel()
    blocks: list[Block] = []
    offset = 0
    for rows, d in zip(x.chunks[0], delayed, strict=True):
        blocks.append(Block(offset, offset + int(rows), d))
        offset += int(rows)
    n = int(x.shape[0])
    if not blocks:
        blocks.append(Block(0, 0, np.zeros((0, 3))))
    return PointSource(n, tuple(blocks), f"dask array of {n:,} points")


_ROW = re.compile(r"\brow (\d+)\b")


def read_block(data: Any, start: int, what: str = "points") -> NDArray[np.float64]:
    """The rows of a block as validated float64 (:func:`~persistri.impl.geometry.points.as_points`).

    ``data`` is what :attr:`Block.data` holds, already computed when it was a
    Dask block; ``start`` its first row in the whole input, which the error for a
    NaN, infinite or inexact coordinate names (``points: row 1234567 is not
    finite: …``, ``what`` first).  O(rows).
    """
    raw = data.read() if isinstance(data, (NpyRows, ZarrRows)) else data
    try:
        return as_points(raw, 3, what=what)
    except ValueError as exc:
        message = _ROW.sub(lambda m: f"row {int(m[1]) + start}", str(exc), count=1)
        raise ValueError(message) from None
