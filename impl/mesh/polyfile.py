"""Shewchuk's Triangle file formats: ``.node``, ``.poly``, ``.ele`` and ``.edge``, read and written.

The formats, as Triangle documents and reads them:

* **comments and blank lines** — everything from ``#`` to the end of a line is a
  comment; blank lines are skipped; fields are separated by blanks.
* ``.node`` — a header ``<# of vertices> <dimension (2)> <# of attributes> <# of
  boundary markers (0 or 1)>`` (the last three default to 2, 0, 0), then one line per
  vertex: ``<vertex #> <x> <y> [attributes] [boundary marker]``.  Vertices are
  numbered consecutively from 0 or 1; the first vertex's number fixes the numbering
  of every file of the mesh.  A missing attribute or marker is 0 (as Triangle).
* ``.poly`` — a ``.node`` section (whose count may be 0: the vertices are then in
  the ``.node`` file of the same name beside it, as Triangle writes them), then
  ``<# of segments> <# of boundary markers>`` and ``<segment #> <endpoint> <endpoint>
  [boundary marker]`` lines, then ``<# of holes>`` and ``<hole #> <x> <y>`` lines, and
  optionally ``<# of regions>`` and ``<region #> <x> <y> <attribute> <maximum area>``
  lines.  As in Triangle, a region line with one number after ``x y`` uses it as both
  the attribute and the area bound.
* ``.ele`` — ``<# of triangles> <nodes per triangle (3)> <# of attributes>``, then
  ``<triangle #> <node> <node> <node> ... [attributes]``: the first three nodes are the
  corners, counterclockwise; further nodes (``-o2``'s six-node triangles) are skipped.
* ``.edge`` — ``<# of edges> <# of boundary markers>``, then ``<edge #> <endpoint>
  <endpoint> [boundary marker]`` (Voronoi rays, with endpoint -1, are not read).

Numbers are parsed by numpy (``np.loadtxt`` on the comment-stripped lines of a
section); indices and markers must be integers written in decimal.  Every
malformed file raises :class:`PolyFileError` with one line: the file, the line
number and what is wrong.  Numbers in the record's own numbering (segment,
hole, triangle numbers) are not checked, as Triangle ignores them; vertex
numbers are.  Writers print every float with Python's shortest round-tripping
``repr``, so a write followed by a read gives back the same doubles.

Cost: O(size of the file), in numpy for the numbers.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from persistri.impl.mesh.domain import PSLG, DomainError, as_pslg

__all__ = [
    "PolyFileError",
    "NodeData",
    "EleData",
    "EdgeData",
    "read_node",
    "read_poly",
    "read_ele",
    "read_edge",
    "read_mesh",
    "write_node",
    "write_poly",
    "write_ele",
    "write_edge",
]

PathLike = str | os.PathLike[str]


class PolyFileError(ValueError):
    """A Triangle file is malformed; the message is ``file:line: what is wrong``."""


@dataclass(frozen=True, eq=False)
class NodeData:
    """A ``.node`` file: ``vertices`` ``(n, 2)``, ``attributes`` ``(n, k)`` or None, ``markers`` ``(n,)`` or None.

    ``first_number`` is the number of the first vertex (0 or 1): every index in
    the mesh's other files counts from it.
    """

    vertices: NDArray[np.float64]
    attributes: NDArray[np.float64] | None
    markers: NDArray[np.intp] | None
    first_number: int


@dataclass(frozen=True, eq=False)
class EleData:
    """An ``.ele`` file: ``triangles`` ``(t, 3)`` of 0-based vertex rows (counterclockwise corners) and ``attributes``."""

    triangles: NDArray[np.intp]
    attributes: NDArray[np.float64] | None
    nodes_per_triangle: int


@dataclass(frozen=True, eq=False)
class EdgeData:
    """An ``.edge`` file: ``edges`` ``(e, 2)`` of 0-based vertex rows and their ``markers`` (or None)."""

    edges: NDArray[np.intp]
    markers: NDArray[np.intp] | None


# -- reading ------------------------------------------------------------------------------


class _Records:
    """The non-blank, comment-stripped lines of a file, each with its line number, read in order."""

    def __init__(self, path: PathLike) -> None:
        self.path = os.fspath(path)
        try:
            text = Path(path).read_text(encoding="utf-8", errors="replace")
        except OSError as exc:
            raise PolyFileError(f"{self.path}: cannot read: {exc.strerror or exc}") from None
        self.lines: list[tuple[int, str]] = []
        for number, line in enumerate(text.splitlines(), start=1):
            body = line.split("#", 1)[0].strip()
            if body:
                self.lines.append((number, body))
        self.pos = 0
        self.last = len(text.splitlines())

    def error(self, line: int, message: str) -> PolyFileError:
        return PolyFileError(f"{self.path}:{line}: {message}")

    def more(self) -> bool:
        return self.pos < len(self.lines)

    def header(self, what: str, names: tuple[str, ...], defaults: tuple[int, ...]) -> tuple[int, list[int]]:
        """The next line as a header of integers: ``names[0]`` required, the rest defaulting."""
        if not self.more():
            raise PolyFileError(f"{self.path}:{self.last}: the file ends where the {what} line was expected")
        number, body = self.lines[self.pos]
        self.pos += 1
        fields = body.split()
        values: list[int] = []
        for k, name in enumerate(names):
            if k >= len(fields):
                values.append(defaults[k - 1])
                continue
            try:
                values.append(int(fields[k]))
            except ValueError:
                raise self.error(number, f"the {what} line: {name} must be an integer, found {fields[k]!r}") from None
            if values[-1] < 0:
                raise self.error(number, f"the {what} line: {name} must not be negative, found {values[-1]}")
        return number, values

    def block(
        self,
        count: int,
        what: str,
        required: tuple[str, ...],
        optional: tuple[str, ...],
        integer: tuple[int, ...],
        *,
        repeat_last: bool = False,
    ) -> tuple[NDArray[np.float64], list[int]]:
        """``count`` records of the ``required`` and ``optional`` numbers (missing optional ones are 0).

        ``repeat_last``: a missing first optional number repeats the last required one
        (Triangle's regions).  Columns in ``integer`` must hold integers.  Returns the
        numbers and the line number of each record.
        """
        width = len(required) + len(optional)
        names = required + optional
        if self.pos + count > len(self.lines):
            have = len(self.lines) - self.pos
            raise PolyFileError(f"{self.path}:{self.last}: the file ends after {have} of the {count} {what} lines")
        rows = self.lines[self.pos : self.pos + count]
        self.pos += count
        text: list[str] = []
        for number, body in rows:
            fields = body.split()
            if len(fields) < len(required):
                raise self.error(
                    number,
                    f"a {what} line needs {len(required)} numbers ({', '.join(required)}), found {len(fields)}",
                )
            if len(fields) < width:
                pad = fields[len(required) - 1] if repeat_last and len(fields) == len(required) else "0"
                fields = fields + [pad] + ["0"] * (width - len(fields) - 1)
            text.append(" ".join(fields[:width]))
        lines = [n for n, _ in rows]
        if count == 0:
            return np.zeros((0, width), dtype=np.float64), lines
        try:
            data = np.loadtxt(text, dtype=np.float64, ndmin=2, comments=None)
        except ValueError:
            for (number, _), record in zip(rows, text):
                try:
                    np.loadtxt([record], dtype=np.float64, ndmin=2, comments=None)
                except ValueError:
                    token = next((f for f in record.split() if not _is_number(f)), record)
                    raise self.error(number, f"{token!r} is not a number (in a {what} line)") from None
            raise  # pragma: no cover - loadtxt failed on the whole but on no single line
        finite = np.isfinite(data)
        if not finite.all():
            k = int(np.argmax(~finite.all(axis=1)))
            raise self.error(lines[k], f"a {what} line has a value that is not finite: {text[k]!r}")
        for col in integer:
            column = data[:, col]
            wrong = np.flatnonzero((column != np.round(column)) | (np.abs(column) > 2**31))
            if wrong.size:
                k = int(wrong[0])
                field = names[col]
                raise self.error(lines[k], f"{field} {text[k].split()[col]!r} is not an integer (in a {what} line)")
        return data, lines

    def finish(self, what: str) -> None:
        if self.more():
            number, body = self.lines[self.pos]
            raise self.error(number, f"unexpected content after the {what}: {body!r}")


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _read_vertices(rec: _Records, *, allow_zero: bool) -> NodeData | None:
    line, (n, dim, nattr, nmark) = rec.header(
        "vertex count", ("the number of vertices", "the dimension", "the number of attributes", "the number of boundary markers"), (2, 0, 0)
    )
    if dim != 2:
        raise rec.error(line, f"the dimension must be 2, found {dim}")
    if nmark not in (0, 1):
        raise rec.error(line, f"the number of boundary markers must be 0 or 1, found {nmark}")
    if n == 0 and allow_zero:
        return None
    if n < 3:
        raise rec.error(line, f"a mesh needs at least 3 vertices, the file lists {n}")
    required = ("vertex number", "x", "y")
    optional = ("attribute",) * nattr + ("marker",) * nmark
    data, lines = rec.block(n, "vertex", required, optional, (0,) + ((3 + nattr,) if nmark else ()))
    numbers = data[:, 0].astype(np.int64)
    first = int(numbers[0])
    if first not in (0, 1):
        raise rec.error(lines[0], f"vertices must be numbered from 0 or 1, the first is numbered {first}")
    wrong = np.flatnonzero(numbers != first + np.arange(n))
    if wrong.size:
        k = int(wrong[0])
        raise rec.error(lines[k], f"vertices must be numbered consecutively: vertex {int(numbers[k])} where {first + k} was expected")
    vertices = np.ascontiguousarray(data[:, 1:3])
    attributes = np.ascontiguousarray(data[:, 3 : 3 + nattr]) if nattr else None
    markers = data[:, 3 + nattr].astype(np.intp) if nmark else None
    return NodeData(vertices, attributes, markers, first)


def read_node(path: PathLike) -> NodeData:
    """Read a ``.node`` file (the module docstring gives the format). O(file)."""
    rec = _Records(path)
    node = _read_vertices(rec, allow_zero=False)
    assert node is not None
    return node


def _indices(
    rec: _Records, data: NDArray[np.float64], lines: list[int], cols: tuple[int, ...], first: int, n: int, what: str
) -> NDArray[np.intp]:
    idx = data[:, list(cols)].astype(np.int64) - first
    bad = np.flatnonzero(((idx < 0) | (idx >= n)).any(axis=1))
    if bad.size:
        k = int(bad[0])
        shown = (idx[k] + first).tolist()
        raise rec.error(lines[k], f"{what} refers to vertex {shown}, but the vertices are numbered {first}..{first + n - 1}")
    return idx.astype(np.intp)


def _first_number(path: Path, default_from: NDArray[np.float64]) -> int:
    node = path.with_suffix(".node")
    if node.exists():
        try:
            with node.open(encoding="utf-8", errors="replace") as fh:
                records = [line.split("#", 1)[0].split() for line in fh]
            body = [r for r in records if r]
            if len(body) > 1 and body[1][0].lstrip("+-").isdigit():
                return int(body[1][0])
        except OSError:
            pass
    return 0 if default_from.size and default_from.min() == 0 else 1


def read_poly(path: PathLike, *, validate: bool = True, convex: bool = False) -> PSLG:
    """Read a ``.poly`` file as a :class:`PSLG` (with the ``.node`` beside it when it lists 0 vertices).

    ``validate`` (default): the result is checked by :func:`~persistri.impl.mesh.domain.as_pslg`
    (which may merge duplicates and split segments, see its ``notes``); a
    domain error is raised as :class:`PolyFileError` naming the file.  With
    ``validate=False`` the file's contents are returned as they are.  O(file).
    """
    p = Path(path)
    rec = _Records(p)
    node = _read_vertices(rec, allow_zero=True)
    if node is None:
        beside = p.with_suffix(".node")
        if not beside.exists():
            raise PolyFileError(f"{p}:{rec.lines[0][0]}: the .poly lists 0 vertices, so they must be in {beside}, which does not exist")
        node = read_node(beside)
    n, first = node.vertices.shape[0], node.first_number
    _, (m, smark) = rec.header("segment count", ("the number of segments", "the number of boundary markers"), (0,))
    data, lines = rec.block(
        m, "segment", ("segment number", "endpoint", "endpoint"), ("marker",) * smark, (0, 1, 2) + ((3,) if smark else ())
    )
    segments = _indices(rec, data, lines, (1, 2), first, n, "a segment")
    seg_markers = data[:, 3].astype(np.intp) if smark else None
    _, (h,) = rec.header("hole count", ("the number of holes",), ())
    hdata, _ = rec.block(h, "hole", ("hole number", "x", "y"), (), (0,))
    holes = np.ascontiguousarray(hdata[:, 1:3])
    regions = np.zeros((0, 4), dtype=np.float64)
    if rec.more():
        _, (r,) = rec.header("region count", ("the number of regions",), ())
        rdata, _ = rec.block(r, "region", ("region number", "x", "y", "attribute"), ("maximum area",), (0,), repeat_last=True)
        regions = np.ascontiguousarray(rdata[:, 1:5])
    rec.finish("regions" if regions.size else "holes")
    if not validate:
        return PSLG(
            vertices=node.vertices,
            segments=segments,
            holes=holes,
            regions=regions,
            vertex_markers=node.markers,
            segment_markers=seg_markers,
            vertex_attributes=node.attributes,
        )
    try:
        return as_pslg(
            node.vertices,
            segments,
            holes,
            regions,
            vertex_markers=node.markers,
            segment_markers=seg_markers,
            vertex_attributes=node.attributes,
            convex=convex,
        )
    except DomainError as exc:
        counted = "" if first == 0 else f" (rows counted from 0; the file numbers from {first})"
        raise PolyFileError(f"{p}: {exc}{counted}") from None


def read_ele(path: PathLike, *, first_number: int | None = None, n_vertices: int | None = None) -> EleData:
    """Read an ``.ele`` file; indices become 0-based rows.

    ``first_number`` is the vertices' numbering base; by default, the first
    vertex number of the ``.node`` file beside it, else 0 if some triangle uses
    vertex 0, else 1.  ``n_vertices`` (if known) range-checks the indices. O(file).
    """
    p = Path(path)
    rec = _Records(p)
    line, (t, nodes, nattr) = rec.header("triangle count", ("the number of triangles", "the nodes per triangle", "the number of attributes"), (3, 0))
    if nodes < 3:
        raise rec.error(line, f"a triangle has at least 3 nodes, the file says {nodes}")
    required = ("triangle number", "node", "node", "node")
    optional = ("node",) * (nodes - 3) + ("attribute",) * nattr
    data, lines = rec.block(t, "triangle", required, optional, tuple(range(1 + nodes)))
    rec.finish("triangles")
    corners = data[:, 1:4]
    first = first_number if first_number is not None else _first_number(p, corners)
    n = n_vertices if n_vertices is not None else (int(corners.max()) - first + 1 if t else 0)
    triangles = _indices(rec, data, lines, (1, 2, 3), first, max(n, 0), "a triangle")
    attributes = np.ascontiguousarray(data[:, 1 + nodes :]) if nattr else None
    return EleData(triangles, attributes, nodes)


def read_edge(path: PathLike, *, first_number: int | None = None, n_vertices: int | None = None) -> EdgeData:
    """Read an ``.edge`` file; indices become 0-based rows (``first_number`` as :func:`read_ele`). O(file)."""
    p = Path(path)
    rec = _Records(p)
    _, (e, emark) = rec.header("edge count", ("the number of edges", "the number of boundary markers"), (0,))
    if emark not in (0, 1):
        raise rec.error(rec.lines[0][0], f"the number of boundary markers must be 0 or 1, found {emark}")
    data, lines = rec.block(e, "edge", ("edge number", "endpoint", "endpoint"), ("marker",) * emark, (0, 1, 2) + ((3,) if emark else ()))
    rec.finish("edges")
    ray = np.flatnonzero((data[:, 1:3] == -1).any(axis=1))
    if ray.size:
        raise rec.error(lines[int(ray[0])], "an infinite Voronoi ray (endpoint -1): .v.edge files are not read")
    ends = data[:, 1:3]
    first = first_number if first_number is not None else _first_number(p, ends)
    n = n_vertices if n_vertices is not None else (int(ends.max()) - first + 1 if e else 0)
    edges = _indices(rec, data, lines, (1, 2), first, max(n, 0), "an edge")
    return EdgeData(edges, data[:, 3].astype(np.intp) if emark else None)


def read_mesh(path: PathLike) -> tuple[NodeData, EleData]:
    """A Triangle mesh: ``stem.node`` and ``stem.ele`` (``path`` may be the stem or either file). O(files)."""
    p = Path(path)
    stem = p.with_suffix("") if p.suffix in (".node", ".ele") else p
    node = read_node(stem.with_name(stem.name + ".node"))
    ele = read_ele(stem.with_name(stem.name + ".ele"), first_number=node.first_number, n_vertices=node.vertices.shape[0])
    return node, ele


# -- writing ------------------------------------------------------------------------------


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
    _write(p, f"a PSLG: {verts.shape[0]} vertices, {m} segments, {holes.shape[0]} holes, {regions.shape[0]} regions", lines)


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
