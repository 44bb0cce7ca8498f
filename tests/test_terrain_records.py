"""The greedy terrain on the triangulator's neighbour records (``Triangulator.adj``, paper §5).

A greedy run's cavity searches read the records instead of the complex's maps, and its queue tells a live
triangle by its record; a counted run keeps no records (it counts the paper's look-ups).  The records must be
the current version's triangles and neighbours after every insertion, and a run must make the same meshes,
errors and levels with and without them.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.typing import NDArray

from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.maps import backend as map_backend
from persistri.impl.stats import Stats
from persistri.impl.terrain.errors import TriangulationCheckError
from persistri.impl.terrain.greedy import greedy_insertion
from persistri.impl.terrain.greedy_run import GreedyRun


def _terrain(rows: int, cols: int, seed: int) -> NDArray[np.float64]:
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:rows, 0:cols]
    out: NDArray[np.float64] = np.sin(x / 5.0) * 10 + np.cos(y / 7.0) * 8 + rng.integers(0, 4, (rows, cols)).astype(float)
    return out


def test_a_greedy_runs_records_are_its_current_versions_after_every_insertion() -> None:
    heights = _terrain(40, 50, 3)
    run = GreedyRun(heights.ravel().copy(), heights.shape, TwoComplex(map_backend("red_black"), None), None, False)
    T = run.T
    adj = T.adj
    assert adj is not None
    for k in range(250):
        run.current_error()
        run.step()
        if k % 25 and k != 249:
            continue
        items = T.S.items(T.complex)
        data = {int(d[0]): (t, d) for t, d in items}
        live = {i: R for i, R in enumerate(adj) if R is not None}
        assert len(adj) == T._next_id and set(live) == set(data) and T.live == len(data)
        edges = {}
        for t, d in items:
            a, b, c = t
            edges[(int(a), int(b))] = edges[(int(b), int(c))] = edges[(int(c), int(a))] = int(d[0])
        for i, R in live.items():
            tri, d = R[0], R[1]
            ct = data[i][0]
            assert tri in (ct, (ct[1], ct[2], ct[0]), (ct[2], ct[0], ct[1])) and data[i][1] is d
            for j in range(3):
                u, w = int(tri[j]), int(tri[(j + 1) % 3])
                assert edges[(w, u)] == int(R[2 + j])  # the record's edge j faces the triangle holding (w, u)
        # The queue's top, once current_error has popped the dead entries, is a triangle of the complex.
        run.current_error()
        assert run.keys.tid(run.heap[0]) in data


def test_a_greedy_run_is_the_same_with_and_without_records() -> None:
    # A counted run keeps no records: the same meshes, errors, insertion order and levels as an uncounted one.
    heights = _terrain(45, 38, 11)
    plain = greedy_insertion(heights, max_points=400)
    counted = greedy_insertion(heights, max_points=400, stats=Stats())
    assert plain.history is not None and counted.history is not None
    for a, b in ((plain, counted), (plain.history.at(points=150), counted.history.at(points=150))):
        assert np.array_equal(a.triangles, b.triangles) and np.array_equal(a.vertices, b.vertices)
        assert (a.max_error, a.rms_error) == (b.max_error, b.rms_error)
    assert np.array_equal(plain.history.max_errors, counted.history.max_errors)
    assert np.array_equal(plain.history.inserted, counted.history.inserted)


def test_a_counted_greedy_run_keeps_no_records() -> None:
    heights = _terrain(20, 20, 1)
    counted = GreedyRun(heights.ravel().copy(), heights.shape, TwoComplex(map_backend("red_black"), Stats()), Stats(), False)
    assert counted.T.adj is None
    run = GreedyRun(heights.ravel().copy(), heights.shape, TwoComplex(map_backend("red_black"), None), None, False)
    assert run.T.adj is not None and run.T.live == 6  # two triangles and four ghosts


def test_a_checked_greedy_run_catches_a_wrong_record() -> None:
    # check=True compares each answer of the records with the complex's: a datum equal to the complex's but not
    # its object is caught at the first look-up that reads it.
    heights = _terrain(30, 30, 5)
    run = GreedyRun(heights.ravel().copy(), heights.shape, TwoComplex(map_backend("red_black"), None), None, True)
    for _ in range(40):
        run.current_error()
        run.step()
    adj = run.T.adj
    assert adj is not None
    for R in adj:
        if R is not None:
            d = R[1]
            R[1] = (d[0], d[1])
    run.current_error()
    with pytest.raises(TriangulationCheckError, match="indexed neighbour"):
        run.step()


def test_the_queue_reads_liveness_from_the_records_when_it_is_rebuilt() -> None:
    # Past a quarter of the live triangles in dead entries, the queue is rebuilt without them: every entry left
    # names a triangle with a record, and the run's top error is the same as without the rebuild.
    heights = _terrain(60, 60, 8)
    run = GreedyRun(heights.ravel().copy(), heights.shape, TwoComplex(map_backend("red_black"), None), None, False)
    for _ in range(400):
        run.current_error()
        run.step()
    adj = run.T.adj
    assert adj is not None
    tm, ts = run.keys.id_mask, run.keys.id_shift
    dead = [key for key in run.heap if adj[(key >> ts) & tm] is None]
    assert dead  # 400 insertions have killed triangles whose entries have not surfaced yet
    top = run.current_error()
    # Force a rebuild: pad the queue with copies of a dead entry beyond the bound.
    run.heap.extend(dead[:1] * (run.T.live + (run.T.live >> 2) + 1025))
    assert run.current_error() == top
    assert all(adj[(key >> ts) & tm] is not None for key in run.heap)
