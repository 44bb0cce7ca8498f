"""A face datum packed in one int (runs keeping their history): exact round trips, the same hulls and lists."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from persistri.impl.geometry.kernel import KERNEL_BATCH
from persistri.impl.hull.api import convex_hull
from persistri.impl.hull.conflicts import _freeze
from persistri.impl.hull.distributions import generate
from persistri.impl.hull.extend import extend_hull
from persistri.impl.hull.packed import ID_MASK, SHORT_MAX, conflict_list, face_id, pack_face, pack_points, points_of, unpack_points


def _lists() -> list[np.ndarray]:
    rng = np.random.default_rng(3)
    runs = np.concatenate([np.arange(s, s + k) for s, k in zip(rng.integers(0, 2**20, 40), rng.integers(1, 400, 40))])
    return [
        np.array([5], dtype=np.int32),
        np.arange(1000, dtype=np.int32),  # one run of 1000: lengths escape
        np.array([0, 2**31 - 1, 0, 2**31 - 1], dtype=np.int32),  # extreme gaps both ways
        np.sort(rng.choice(2**31 - 1, 300, replace=False)).astype(np.int32),  # sparse: every gap escapes
        rng.permutation(2000).astype(np.int32),  # unsorted
        runs.astype(np.int32),  # joined increasing parts, as the bulldozer makes them
        np.array([7, 8, 9, 3, 4, 5, 100, 101, 90], dtype=np.int32),
        np.array([500, 372, 373, 501, 629, 1000, 1001, 1002], dtype=np.int32),  # gaps of -128, +127, +128
    ]


@pytest.mark.parametrize("pts", _lists(), ids=lambda a: f"n{a.size}")
def test_pack_points_round_trip(pts: np.ndarray) -> None:
    back = unpack_points(pack_points(pts))
    assert back.dtype == np.int32 and not back.flags.writeable
    assert np.array_equal(back, pts)


def test_runs_cost_a_byte_or_two() -> None:
    # 1000 consecutive points: one run, its length an escape; far below 4 bytes a point.
    assert len(pack_points(np.arange(1000, dtype=np.int32))) < 40
    # 100 runs of 5 with gaps of 3: two int8 per run.
    pts = np.concatenate([np.arange(s, s + 5) for s in range(0, 800, 8)]).astype(np.int32)
    assert len(pack_points(pts)) == 12 + 100 + 12 + 100
    # Gaps of 200 (an int16 escape: two bytes more) and -128 (the escape mark itself, escaped).
    pts = np.array([1000, 1201, 1202, 1075, 1076], dtype=np.int32)
    assert np.array_equal(unpack_points(pack_points(pts)), pts)
    assert len(pack_points(pts)) == 12 + 3 * 2 + 3 + 12 + 3  # the first point (1000) escapes too


@pytest.mark.parametrize("fid", [0, 1, 255, 256, 123456, ID_MASK])
@pytest.mark.parametrize("n", [0, 1, 2, KERNEL_BATCH - 1, KERNEL_BATCH, 5 * KERNEL_BATCH])
def test_pack_face_round_trip(fid: int, n: int) -> None:
    pts = list(range(0, 3 * n, 3))
    pts[n // 2 :] = pts[n // 2 :][::-1]  # not sorted
    if n:
        pts[-1] = 0  # a last point 0: its high bytes are zero
    conflict = _freeze(pts)
    d = pack_face(fid, conflict)
    assert type(d) is int and face_id(d) == fid
    got = conflict_list(d)
    assert type(got) is type(conflict)  # tuple below KERNEL_BATCH, else an int32 array
    assert list(np.asarray(got).tolist()) == pts
    # What the bulldozer reads (an int32 array when short) has the same points, and packs back to the same int.
    fast = points_of(d)
    assert list(np.asarray(fast).tolist()) == pts
    assert pack_face(fid, fast) == d and pack_face(fid, list(pts) if n < KERNEL_BATCH else conflict) == d
    tup = (fid, conflict)
    assert face_id(tup) == fid and conflict_list(tup) is conflict


@pytest.mark.parametrize("pts", [(0, 65535, 7), (0, 65536, 7), (2**31 - 1, 5), (70000, 4, 2**20)])
def test_short_lists_near_and_far(pts: tuple[int, ...]) -> None:
    # Near or far apart, up to the largest int32: the same list, four bytes a point after the id and one-byte count.
    d = pack_face(9, pts)
    assert conflict_list(d) == pts and list(points_of(d)) == list(pts) and face_id(d) == 9
    assert d.bit_length() <= 40 + 32 * len(pts)


@pytest.mark.parametrize("n", [SHORT_MAX, SHORT_MAX + 1, 300])
def test_a_short_list_longer_than_its_count_byte_is_run_coded(n: int) -> None:
    # The bulldozer's short lists are below KERNEL_BATCH; a longer tuple is still packed exactly, as a long list.
    pts = tuple(range(5, 5 + 2 * n, 2))
    d = pack_face(77, pts)
    got = conflict_list(d)
    assert face_id(d) == 77 and np.asarray(got).tolist() == list(pts) == np.asarray(points_of(d)).tolist()
    assert type(got) is (tuple if n <= SHORT_MAX else np.ndarray)


def test_pack_face_id_range() -> None:
    with pytest.raises(OverflowError):
        pack_face(ID_MASK + 1, ())
    with pytest.raises(OverflowError):
        pack_face(-1, ())


def _faces(S: Any, version: Any) -> dict[int, tuple[tuple[int, ...], list[int], str]]:
    out = {}
    for tri, d in S.items(version):
        lst = conflict_list(d)
        out[face_id(d)] = (tuple(map(int, tri)), np.asarray(lst).tolist(), type(lst).__name__)
    return out


@pytest.mark.parametrize("dist", ["InBall", "OnSphere", "BordHeavy"])
def test_history_packs_the_same_faces(dist: str) -> None:
    pts = generate(dist, 3000, seed=4)
    plain = convex_hull(pts, seed=4, history=True)
    S = plain.structure
    assert all(type(d) is int for _, d in S.items(plain.history[1]))
    # The same run without history: its final version's faces, ids and lists; every version's pending points
    # are those the run had at that step (the lists of a packed history decode to the usual forms).
    one = convex_hull(pts, seed=4)
    assert np.array_equal(one.simplices, plain.simplices)
    assert np.array_equal(one.bulldozed_faces, plain.bulldozed_faces)
    assert _faces(S, one.bulldozed) == _faces(S, plain.bulldozed)
    # An early version holds long lists (packed by runs): every point outside it is pending exactly once.
    first = _faces(S, plain.history[0])
    assert any(kind == "ndarray" for _, _, kind in first.values())
    counts = np.bincount(np.concatenate([np.asarray(lst, dtype=np.intp) for _, lst, _ in first.values()]), minlength=3000)
    assert counts.max() == 1 and counts.sum() == plain.history.pending(0).size


def test_checked_and_counted_history_runs() -> None:
    from persistri.impl.stats import Stats

    pts = generate("InBall", 1500, seed=2)
    a, b = Stats(), Stats()
    convex_hull(pts, seed=2, stats=a, stepwise=True)
    convex_hull(pts, seed=2, stats=b, stepwise=True, history=True)
    assert a.as_dict() == b.as_dict() and a.as_dict()["plane_side_tests"] > 0
    # check=True verifies every insertion of a packed run (the walk, the tents' lists, the final hull).
    checked = convex_hull(pts, seed=2, history=True, check=True, stepwise=True)
    assert np.array_equal(checked.simplices, convex_hull(pts, seed=2).simplices)


def test_extend_a_packed_history() -> None:
    pts = generate("InBall", 1500, seed=5)
    old = convex_hull(pts, seed=5, history=True)
    more = generate("InBall", 800, seed=6) * 1.1
    got = extend_hull(old, more, check=True)
    ref = extend_hull(convex_hull(pts, seed=5), more)
    assert np.array_equal(got.simplices, ref.simplices)
    assert got.history is not None and len(got.history) == len(old.history) + got.insertions - old.insertions
