"""The segment clean-up's two ways of finding candidates give the same answers (impl/mesh/segments.py).

Up to :data:`~persistri.impl.mesh.segments.FEW_SEGMENTS` segments, :func:`split_at_vertices`,
:func:`refuse_crossings` and :func:`dedupe` loop over Python lists; above it they sweep with numpy.
Both must find the same vertices on each segment in the same order, and the same first crossing
(so the same message): here every random degenerate graph is run both ways, with the threshold
moved, and the validated domains compared field by field.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh import segments
from persistri.impl.mesh.domain import PSLG, DomainError


def _graphs(seed: int, count: int) -> list[dict[str, Any]]:
    """Random small graphs on grids: vertices on segments, overlaps, crossings, duplicates, at several scales."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        g = int(rng.integers(2, 7))
        n = int(rng.integers(3, 14))
        scale = float(rng.choice([1.0, 0.5, 1e-3, 2.0**-300, 1e6, 3.0]))
        V = rng.integers(0, g, size=(n, 2)).astype(float) * scale + float(rng.choice([0.0, 5e5, -7.0]))
        m = int(rng.integers(1, 16))
        S = rng.integers(0, n, size=(m, 2))
        S = S[S[:, 0] != S[:, 1]]
        box = [[0, 0], [g, 0], [g, g], [0, g]]
        V = np.vstack([np.array(box, dtype=float) * scale, V])
        S = np.vstack([[[0, 1], [1, 2], [2, 3], [3, 0]], S + 4]) if S.size else np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
        out.append({"vertices": V, "segments": S})
    return out


def _outcome(d: dict[str, Any]) -> Any:
    try:
        p = PSLG.from_dict(d)
    except DomainError as exc:
        return f"DomainError: {exc}"
    return (p.vertices.tolist(), p.segments.tolist(), p.segment_origin.tolist() if p.segment_origin is not None else None, p.notes)


@pytest.mark.parametrize("seed", [0, 1])
def test_few_and_many_paths_validate_alike(seed: int, monkeypatch: pytest.MonkeyPatch) -> None:
    """Every graph validated with the loops and with the sweep (the threshold at -1): the same PSLG or message."""
    graphs = _graphs(seed, 150)
    few = [_outcome(d) for d in graphs]
    monkeypatch.setattr(segments, "FEW_SEGMENTS", -1)
    many = [_outcome(d) for d in graphs]
    assert few == many
    errors = sum(isinstance(o, str) for o in few)
    assert 0 < errors < len(few)  # crossings and repairs both exercised
    assert any("cross at" in o for o in few if isinstance(o, str))
    assert any(not isinstance(o, str) and o[3] for o in few)  # some split or merged, with notes


def test_vertices_on_segments_in_the_same_order() -> None:
    """The two candidate searches, called directly on random graphs with many collinear triples."""
    rng = np.random.default_rng(5)
    for _ in range(200):
        n = int(rng.integers(3, 20))
        V = rng.integers(0, 5, size=(n, 2)).astype(float)
        V = np.unique(V, axis=0)
        if V.shape[0] < 3:
            continue
        S = rng.integers(0, V.shape[0], size=(int(rng.integers(1, 12)), 2))
        S = S[S[:, 0] != S[:, 1]]
        if not S.size:
            continue
        pred = GrowingPredicates2(V)
        few = segments._vertices_on_few(V, S, pred)
        many = segments._vertices_on_many(V, S, pred, None)
        assert few == many
        # every pair the vectorised sweep keeps is one the loops keep, in the same order (the sweep's filter sets
        # aside only pairs that cannot cross)
        kept_few = list(segments._crossing_candidates_few(V, S))
        kept_many = list(segments._crossing_candidates_many(V, S, pred, None))
        it = iter(kept_few)
        assert all(pair in it for pair in kept_many)
