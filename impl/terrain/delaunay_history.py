"""``DelaunayHistory``: every version of a scattered Delaunay run, oldest first (time travel, paper §1 and §5).

The incremental Delaunay triangulation makes one version of the persistent
complex per inserted point; a run started with ``history=True``
(:func:`persistri.impl.terrain.scattered.delaunay`) keeps them all.  Keeping
them costs only what each insertion changed — the new triangles and the
O(lg n) map nodes on the paths to the vertices whose stars changed — never a
copy: every triangle, datum, vertex list and subtree an insertion left alone is
the same object in the version before and after it.

``versions[0]`` is the first triangle (with its three ghosts); ``versions[k]``
is the triangulation after ``k`` further insertions.  ``inserted`` names the
points as input rows: ``inserted[0:3]`` are the first triangle's corners and
``inserted[k + 2]`` the point whose insertion made ``versions[k]``, so version
``k`` is the Delaunay triangulation of exactly the rows ``inserted[: k + 3]``
(every distinct point is a vertex: nothing is ever deleted).  A run continued
by :func:`~persistri.impl.terrain.extend_delaunay.extend_delaunay` continues
its history too.

>>> import numpy as np
>>> from persistri.impl.terrain.scattered import delaunay
>>> h = delaunay(np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [2.0, 2.0]]), history=True).history
>>> len(h), h.simplices(0).shape, h.simplices(1).shape
(2, (1, 3), (2, 3))
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import chain
from operator import itemgetter

import numpy as np
from numpy.typing import NDArray

from persistri.impl.complex.structure import Complex
from persistri.impl.complex.versions import Versions
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.terrain.insertion import TriDatum, canonical_triangles

__all__ = ["DelaunayHistory", "read_labels"]

IntArray = NDArray[np.intp]


def read_labels(structure: TwoComplex[TriDatum], c: Complex[TriDatum]) -> IntArray:
    """Every triangle of version ``c`` (ghosts included) as a ``(m, 3)`` array of vertex labels, read from the complex. O(m)."""
    read: IntArray = np.fromiter(
        chain.from_iterable(map(itemgetter(0), structure.iter_items(c))), dtype=np.intp
    ).reshape(-1, 3)
    return read


@dataclass(frozen=True, eq=False)
class DelaunayHistory(Versions[TriDatum]):
    """Every version of a scattered Delaunay run, oldest first (module docstring).

    * ``structure`` — the structure that reads the versions;
    * ``versions`` — the complexes, ``versions[k]`` after ``k`` insertions past the first triangle;
    * ``inserted`` — input rows: the first triangle's three, then one per later version;
    * ``labels`` — the input row of each vertex label (``-1`` at ``infinite``);
    * ``infinite`` — the label of the symbolic vertex at infinity (the ghosts' apex).
    """

    structure: TwoComplex[TriDatum]
    versions: tuple[Complex[TriDatum], ...]
    inserted: tuple[int, ...]
    labels: IntArray
    infinite: int


    def simplices(self, k: int) -> IntArray:
        """The triangles of version ``k`` as input rows, counterclockwise, canonical (each rotated to start
        at its smallest row, rows sorted: the form of :attr:`DelaunayTriangulation.triangles`). O(m log m)."""
        every = read_labels(self.structure, self[k])
        finite = every[~(every == self.infinite).any(axis=1)]
        return canonical_triangles(self.labels[finite])

    def vertices(self, k: int) -> IntArray:
        """The sorted input rows that are vertices of version ``k``: ``sorted(inserted[: k + 3])``. O(m log m)."""
        return np.unique(self.simplices(k))

    def continued(self, versions: list[Complex[TriDatum]], inserted: list[int], labels: IntArray) -> DelaunayHistory:
        """This history followed by ``versions`` (made by inserting the rows ``inserted``), read with ``labels``
        (this history's labels extended by the new points'). O(len(self) + len(versions)): the complexes are shared."""
        return DelaunayHistory(self.structure, self.versions + tuple(versions), self.inserted + tuple(inserted), labels, self.infinite)
