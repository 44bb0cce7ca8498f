"""Naming the domain's segments and vertices in messages as the user wrote them (Triangle's input; paper §1).

Validation (:func:`~persistri.impl.mesh.domain.as_pslg`) renumbers what it is
given: duplicate vertices merge into the first (``PSLG.vertex_map``), segments
split at the vertices on them, repeated ones merge, and ``convex=True`` (a
``.node`` file, Triangle's ``-c``) adds the convex hull's edges as segments
(``PSLG.segment_origin``).  A message from the refinement or the checker that
said "segment 15" by the validated row could name a segment the user never
wrote; :class:`InputNames` says instead

* for a segment (or a piece of one) of the input: ``segment k between (x, y) and (x', y')``,
  ``k`` its row in the input (counted from 0, as the vertex rows are), the points the ends of the
  part meant (the whole segment, or the piece of it validation made);
* for an added hull edge: ``the convex hull edge (x, y)–(x', y') (a .node file, or convex=True, is
  meshed as its convex hull)``;
* for a vertex of the domain: its input row (the first of merged duplicates).

Costs: :meth:`InputNames.of` O(n + m); every name O(1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["HULL_EDGE", "InputNames"]

_FEW = 1024
"""Up to this many vertices :meth:`InputNames.of` tells an identity ``vertex_map`` by one comparison of lists."""

HULL_EDGE = -1
"""``PSLG.segment_origin``'s value for a convex hull edge that ``convex=True`` added."""


@dataclass(frozen=True)
class InputNames:
    """The input row of each validated segment (:data:`HULL_EDGE` for an added hull edge) and vertex.

    ``segment_origin`` / ``vertex_row``: None means the rows are the input's, as given."""

    segment_origin: tuple[int, ...] | None = None
    vertex_row: tuple[int, ...] | None = None

    @classmethod
    def of(cls, segment_origin: NDArray[np.intp] | None, vertex_map: NDArray[np.intp] | None) -> InputNames:
        """From a PSLG's ``segment_origin`` and ``vertex_map`` (input row → validated row). O(n)."""
        rows: tuple[int, ...] | None = None
        # The identity (no merges: the rows as given), told by one comparison of lists when there are few.
        if vertex_map is not None and vertex_map.size and (vertex_map.size > _FEW or vertex_map.tolist() != list(range(vertex_map.size))):
            vm = np.asarray(vertex_map, dtype=np.intp)
            first = np.full(int(vm.max()) + 1, -1, dtype=np.intp)
            first[vm[::-1]] = np.arange(vm.size - 1, -1, -1, dtype=np.intp)  # the last write wins: the first row
            if not np.array_equal(first, np.arange(first.size)):
                rows = tuple(first.tolist())
        origin = None if segment_origin is None else tuple(segment_origin.tolist())  # Python ints
        if origin is not None and origin == tuple(range(len(origin))):
            origin = None
        return cls(origin, rows)

    @classmethod
    def through(
        cls,
        first: tuple[NDArray[np.intp] | None, NDArray[np.intp] | None],
        then: tuple[NDArray[np.intp] | None, NDArray[np.intp] | None],
    ) -> InputNames:
        """Names across two validations: ``then`` = (``segment_origin``, ``vertex_map``) of a PSLG validated from
        one whose own are ``first`` (the checker re-validates the domain it is given).  O(n + m)."""
        origin, vmap = then
        if first[0] is not None and origin is not None:
            origin = np.where(origin >= 0, first[0][np.maximum(origin, 0)], HULL_EDGE).astype(np.intp)
        if first[1] is not None and vmap is not None:
            vmap = vmap[first[1]]
        return cls.of(origin, vmap)

    def vertex(self, v: int) -> int:
        """The input row of domain vertex ``v``. O(1)."""
        rows = self.vertex_row
        return int(v) if rows is None or not 0 <= v < len(rows) else rows[v]

    def is_hull_edge(self, s: int) -> bool:
        """Whether segment ``s`` is a convex hull edge that validation added. O(1)."""
        return self.segment_origin is not None and self.segment_origin[s] == HULL_EDGE

    def segment(self, s: int, a: str, b: str) -> str:
        """Segment ``s`` with ends at ``a`` and ``b`` (texts of points), as the module docstring says. O(1)."""
        if self.is_hull_edge(s):
            return f"the convex hull edge {a}–{b} (a .node file, or convex=True, is meshed as its convex hull)"
        o = s if self.segment_origin is None else self.segment_origin[s]
        return f"segment {o} between {a} and {b}"
