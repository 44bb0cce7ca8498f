"""The refinement's edge index (persistri.impl.mesh.edges): always the version the run stands at.

The refiner reads its current version through a mutable index of its triangles by directed edge, kept in step with
each step it adopts.  These tests compare the index with the version's own triangles after every step of whole runs
(deletions, rounded split points, undos), compare every conflict search made through the index with the same search
made through the complex, and run the refinement with the triangulation's internal checks on (the split points known
to lie on their subsegment's line tested anyway): the same meshes.
"""

from __future__ import annotations

from typing import Any

import pytest

from persistri.impl.mesh import api
from persistri.impl.mesh.api import triangulate
from persistri.impl.mesh.edges import advance, edge_reader, index_of
from persistri.impl.mesh.gallery import gallery_domain
from persistri.impl.mesh.ruppert import Refiner
from persistri.impl.mesh.triangulation import MeshTriangulation

# Deletions (fan, comb), rounded split points (needle, fan, utm-tile), undos (all), a hull (utm-tile, circle).
RUNS = [("fan", 20.0), ("comb", 30.0), ("needle", 30.0), ("utm-tile", 33.0), ("circle", 30.0), ("square-hole", 33.0)]


def _fingerprint(m: api.QualityMesh) -> tuple[Any, ...]:
    return (
        m.vertices.tobytes(),
        m.triangles.tobytes(),
        m.segments.tobytes(),
        m.history.inserted,
        m.history.deleted,
        tuple(repr(u) for u in m.history.undone),
        tuple(repr(b) for b in m.history.blocked),
        (m.insertions, m.undos, m.deletions, m.rounded_splits, m.rounding_retries, m.exempt),
    )


def _is_deletion(step: Any) -> bool:
    """A step of Chew's rule: a star replaced by triangles on its link (an insertion's fan has a new vertex)."""
    return {v for t, _ in step.created for v in t} <= {v for t, _ in step.removed for v in t}


@pytest.mark.parametrize("name,angle", RUNS)
def test_index_is_the_current_version_after_every_step(name: str, angle: float, monkeypatch: pytest.MonkeyPatch) -> None:
    """After an insertion, the index is its version's; after each of Chew's deletions, which make no version of their
    own (the split after them makes one for the whole step), the version the run stands at with the deletions since
    done on its index."""
    adopted = deletions = 0
    since: list[Any] = []
    original = Refiner._adopt

    def checked(self: Refiner, step: Any, apexes: bool = True) -> None:
        nonlocal adopted, deletions
        original(self, step, apexes)
        expected = index_of(self.S.items(step.version))
        if _is_deletion(step):
            since.append(step)
            for d in since:
                advance(expected, d.removed, d.created)
            deletions += 1
        else:
            since.clear()
        assert self._edges == expected
        adopted += 1

    monkeypatch.setattr(Refiner, "_adopt", checked)
    m = triangulate(gallery_domain(name).pslg, min_angle=angle)
    assert adopted >= m.insertions + m.deletions > 0
    assert deletions == m.deletions


@pytest.mark.parametrize("name,angle", RUNS)
def test_conflict_searches_through_the_index_equal_those_through_the_complex(
    name: str, angle: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    searched = ahead = 0
    original = MeshTriangulation.cavity

    def both(self: MeshTriangulation, c: Any, p: int, start: Any, split: Any = None, index: Any = None, on_line: bool = False) -> Any:
        nonlocal searched, ahead
        got = original(self, c, p, start, split, index, on_line)
        read = c
        if index is not None:
            # After Chew's deletions the index is ahead of c (the split makes one version for both): the complex
            # searched is c with the index's triangles instead of its own, made here.
            own = dict(self.S.items(c))
            indexed = dict(((u, w, x), d) for (u, w), (x, d) in index.items() if u == min(u, w, x))
            if own != indexed:
                ahead += 1
                read = self.S.replace(c, [t for t in own if t not in indexed], [td for td in indexed.items() if td[0] not in own])
        plain = original(self, read, p, start, split)
        assert got.triangles == plain.triangles and list(got.triangles) == list(plain.triangles)
        assert got.boundary == plain.boundary and got.beyond == plain.beyond
        searched += index is not None
        return got

    monkeypatch.setattr(MeshTriangulation, "cavity", both)
    m = triangulate(gallery_domain(name).pslg, min_angle=angle)
    assert searched >= m.insertions > 0
    assert (ahead > 0) == (m.deletions > 0)


@pytest.mark.parametrize("name,angle", RUNS)
def test_checked_triangulation_gives_the_same_mesh(name: str, angle: float, monkeypatch: pytest.MonkeyPatch) -> None:
    plain = triangulate(gallery_domain(name).pslg, min_angle=angle)

    def checked(pred: Any, structure: Any) -> MeshTriangulation:
        return MeshTriangulation(pred, structure, check=True)

    monkeypatch.setattr(api, "MeshTriangulation", checked)
    again = triangulate(gallery_domain(name).pslg, min_angle=angle)
    assert _fingerprint(again) == _fingerprint(plain)


def test_advance_and_reader_agree_with_the_versions() -> None:
    m = triangulate(gallery_domain("l-shape").pslg, min_angle=30, max_area=0.05)
    S = m.history.structure
    index = index_of(S.items(m.history[0]))
    for k in range(1, len(m.history)):
        before, after = S.items(m.history[k - 1]), S.items(m.history[k])
        gone = [item for item in before if item not in after]
        made = [item for item in after if item not in before]
        advance(index, gone, made)
        assert index == index_of(after)
        get = edge_reader(S, m.history[k])
        assert all(get(e) == rec for e, rec in index.items())
    with pytest.raises(KeyError):
        advance(index, [((10**6, 10**6 + 1, 10**6 + 2), (0, 0, ()))], [])


@pytest.mark.parametrize("name,angle", RUNS)
def test_a_bad_triangles_split_leaves_no_encroached_subsegment_untested(
    name: str, angle: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A bad triangle's split adopts its fan without testing the apexes of the fan's subsegment edges (``apexes``
    False): each is the new point, which the undo test found to encroach none of them.  Tested here for every such
    step of the runs: none is encroached, and the queue of subsegments gets nothing the test would have added."""
    skipped = 0
    original = Refiner._adopt

    def checked(self: Refiner, step: Any, apexes: bool = True) -> None:
        nonlocal skipped
        if not apexes:
            for (a, b, c), d in step.created:
                if d[1] == -1:  # exterior: never examined
                    continue
                for lo, hi, _ in d[2]:
                    apex = a if a not in (lo, hi) else b if b not in (lo, hi) else c
                    assert not self.tests.encroaches(lo, hi, apex)
                    skipped += 1
        original(self, step, apexes)

    monkeypatch.setattr(Refiner, "_adopt", checked)
    m = triangulate(gallery_domain(name).pslg, min_angle=angle)
    if name in ("utm-tile", "comb", "square-hole"):  # circumcentres beside subsegments
        assert m.circumcenters + m.offcenters > 0 and skipped > 0
