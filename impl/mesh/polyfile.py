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

import codecs
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from persistri.impl.file_errors import shown
from persistri.impl.files import rounded_integer, rounded_note
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
            data = Path(path).read_bytes()
        except OSError as exc:
            raise PolyFileError(f"{self.path}: cannot read: {exc.strerror or exc}") from None
        if data.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):  # saved as "Unicode" by a Windows editor
            text = data.decode("utf-16", errors="replace")
        elif b"\x00" in data[:8192]:  # Triangle's files are text: a NUL byte is an archive, an image, a .npy ...
            raise PolyFileError(f"{self.path}: not a Triangle file: binary data (a NUL byte at offset {data.index(0)})")
        else:
            text = data.decode("utf-8-sig", errors="replace")  # a byte order mark is not part of the first number
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
            if not self.lines:
                raise PolyFileError(f"{self.path}: the file is empty (or only comments): its first line is the {what}")
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
                raise self.error(number, f"the {what} line: {name} must be an integer, found {shown(fields[k])}") from None
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
                    raise self.error(number, f"{shown(token)} is not a number (in a {what} line)") from None
            raise  # pragma: no cover - loadtxt failed on the whole but on no single line
        finite = np.isfinite(data)
        if not finite.all():
            k = int(np.argmax(~finite.all(axis=1)))
            raise self.error(lines[k], f"a {what} line has a value that is not finite: {shown(text[k])}")
        for col in integer:
            column = data[:, col]
            wrong = np.flatnonzero((column != np.round(column)) | (np.abs(column) > 2**31))
            if wrong.size:
                k = int(wrong[0])
                field = names[col]
                raise self.error(lines[k], f"{field} {shown(text[k].split()[col])} is not an integer (in a {what} line)")
        return data, lines

    def finish(self, what: str) -> None:
        if self.more():
            number, body = self.lines[self.pos]
            raise self.error(number, f"unexpected content after the {what}: {shown(body)}")


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
    with np.errstate(invalid="ignore"):
        big = np.flatnonzero((np.abs(vertices) >= 2.0**53).any(axis=1))
    for k in big.tolist():  # a coordinate its double may have rounded (9007199254740993 read as 2^53)
        body = dict(rec.lines).get(int(lines[k]), "")
        token = rounded_integer(body, vertices[k])
        if token is not None:
            raise rec.error(int(lines[k]), f"vertex {int(numbers[k])}: {rounded_note(token)}")
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
        wrong = next(v for v in shown if not first <= v < first + n)
        raise rec.error(
            lines[k],
            f"{what} ({' '.join(map(str, shown))}) refers to vertex {wrong}, but the vertices are numbered {first}..{first + n - 1}",
        )
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

    A ``.node`` file (vertices only) is read as the domain Triangle meshes for it: the
    convex hull of its points (``convex`` implied; ``validate=False`` then returns the
    points with no segments).

    ``validate`` (default): the result is checked by :func:`~persistri.impl.mesh.domain.as_pslg`
    (which may merge duplicates and split segments, see its ``notes``); a
    domain error is raised as :class:`PolyFileError` naming the file.  With
    ``validate=False`` the file's contents are returned as they are.  O(file).
    """
    p = Path(path)
    if p.suffix.lower() == ".node":
        # Vertices only: the domain is their convex hull, as Triangle meshes a .node file (and `persistri mesh` does).
        node: NodeData | None = read_node(p)
        assert node is not None
        first, convex = node.first_number, True
        segments = np.zeros((0, 2), dtype=np.intp)
        seg_markers: NDArray[np.intp] | None = None
        holes = np.zeros((0, 2), dtype=np.float64)
        regions = np.zeros((0, 4), dtype=np.float64)
    else:
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
        names_row = re.search(r"\b(vertex|vertices|segment|segments|hole|region|row) \d", str(exc))
        counted = "" if first == 0 or not names_row else f" (rows counted from 0; the file numbers from {first})"
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


# The writers live in their own module; their names stay importable from here.
from persistri.impl.mesh.polyfile_write import write_edge, write_ele, write_node, write_poly  # noqa: E402
