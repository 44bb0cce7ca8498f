"""Traces (impl/complex/trace.py): recording a bulldozer run and replaying it on every 2-complex,
branching histories, every operation, files, and the errors."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from broken_complexes import OrientationBlindFind
from complex_helpers import BACKEND_NAMES, build, fresh, icosahedron
from persistri.impl.complex import complex_structure
from persistri.impl.complex.errors import AbsentSimplexError, DuplicateSimplexError, StaleVersionError
from persistri.impl.complex.simpcomp import two_complex
from persistri.impl.complex.trace import (
    OPERATIONS,
    Replay,
    ReplayMismatch,
    Trace,
    TraceError,
    TraceFormatError,
    TracingTwoComplex,
    UntrackedVersionError,
    load_trace,
    replay,
    save_trace,
)
from persistri.impl.hull.api import convex_hull
from persistri.impl.hull.distributions import on_sphere
from persistri.impl.maps.assoc_list import assoc_list


def label_sets(C: Any, c: Any) -> list[tuple[int, ...]]:
    """The triangles of ``c`` as label tuples rotated to their smallest label (orientation kept)."""
    out = []
    for t, _ in C.items(c):
        labels = [int(v) for v in t]
        i = labels.index(min(labels))
        out.append(tuple(labels[i:] + labels[:i]))
    return sorted(out)


@pytest.fixture(scope="module", params=[False, True], ids=["replace", "stepwise"])
def hull_trace(request: pytest.FixtureRequest) -> tuple[Trace, list[tuple[int, ...]]]:
    """A recorded bulldozer run: one ``replace`` per insertion, or (stepwise) the paper's rem and add per face."""
    pts = on_sphere(400, seed=11)
    rec = TracingTwoComplex(two_complex("red_black"))
    hull = convex_hull(pts, structure=rec, seed=4, stepwise=request.param)
    trace = rec.stop()
    assert np.array_equal(hull.simplices, convex_hull(pts, seed=4).simplices)  # recording changes nothing
    return trace, label_sets(rec.inner, hull.complex)


def test_a_bulldozer_run_is_recorded(hull_trace: tuple[Trace, list[tuple[int, ...]]]) -> None:
    trace, final = hull_trace
    counts = dict.fromkeys(["rem", "replace", "replace.add", "replace.rem"], 0) | trace.counts()
    # The bulldozer's operations: one new, the tetrahedron's four adds, then per insertion findi of the
    # walk and either one replace (its parts recorded before it) or rems and adds (net +2 triangles per
    # inserted point).
    assert counts["new"] == 1
    added = counts["add"] + counts["replace.add"]
    removed = counts["rem"] + counts["replace.rem"]
    assert added - removed == len(final)
    assert counts["findi"] > added > 0
    assert trace.versions == 1 + counts["add"] + counts["rem"] + counts["replace"]
    insertions = len(trace.labels()) - 4
    if counts["replace"]:
        assert counts["add"] == 4 and counts["rem"] == 0 and counts["replace"] == insertions
    else:
        assert counts["replace.add"] == 0
    assert len(final) == 2 * len(trace.labels()) - 4  # a triangulated sphere: F = 2V - 4


REPLAY_TARGETS = [*BACKEND_NAMES, "ephemeral", "functor"]


@pytest.mark.parametrize("target", REPLAY_TARGETS)
def test_replay_reproduces_the_final_hull_on_every_2_complex(
    hull_trace: tuple[Trace, list[tuple[int, ...]]], target: str
) -> None:
    trace, final = hull_trace
    if target == "functor":
        S = complex_structure(2, "red_black", specialised=False)
    else:
        S = two_complex(target)
    c = replay(trace, S, verify=True)  # every query's result checked against the recording
    assert label_sets(S, c) == final
    S.check(c)


def test_branching_histories_are_recorded_and_replayed() -> None:
    k, tris = icosahedron()
    vs = fresh(k)
    rec = TracingTwoComplex(two_complex("hamt"))
    base = build(rec, vs, tris[:10])
    left = rec.add(base, tuple(vs[j] for j in tris[10]), "L")
    right = rec.rem(base, tuple(vs[j] for j in tris[0]))  # an operation on an older version
    right = rec.add(right, tuple(vs[j] for j in tris[11]), "R")
    rec.data(left, tuple(vs[j] for j in tris[11]))  # absent on this branch
    rec.data(right, tuple(vs[j] for j in tris[11]))
    trace = rec.stop()
    srcs = [e[1] for e in trace.events() if e[0] in ("add", "rem")]
    assert srcs[-3:] == [10, 10, 12]  # both branches start at version 10
    assert [e[4] for e in trace.events() if e[0] == "data"] == [0, 1]
    S = two_complex("red_black")
    assert label_sets(S, replay(trace, S)) == label_sets(rec.inner, right)
    # The ephemeral baseline cannot go back to version 10.
    with pytest.raises(StaleVersionError):
        replay(trace, two_complex("ephemeral"))


def test_every_operation_is_recorded_and_replayed() -> None:
    a, b, c, d = fresh(4)
    rec = TracingTwoComplex(two_complex("red_black"))
    k = rec.new(2)
    k = rec.add(k, (a, b, c), 1)
    k = rec.add(k, (a, c, d), 2)
    k = rec.update(k, (a, b, c), lambda x: x + 10)
    assert rec.data(k, (b, c, a)) == (11,)
    assert rec.dim(k) == 2 and rec.isEmpty(k) is False
    assert len(rec.vertices(k)) == 4 and len(rec.simplices(k, 1)) == 5 and len(rec.items(k)) == 2
    assert rec.find(k, (a, c)) == [(a, c, d)] and rec.findi(k, (c, a)) == [((c, a, b), 11)]
    assert len(rec.grep(k, 2, (a,))) == 2 and len(rec.grep(k, 1, (c,))) == 3
    k = rec.rem(k, (c, d, a))
    with pytest.raises(DuplicateSimplexError):
        rec.add(k, (a, b, c), 0)  # refused: not recorded
    k = rec.replace(k, [(b, c, a)], [((a, c, b), 7), ((a, d, c), 8)])  # 3 parts, then the replace: 4 events
    with pytest.raises(AbsentSimplexError):
        rec.replace(k, [(a, b, c)], [])  # refused: not recorded
    trace = rec.stop()
    assert set(trace.counts()) == set(OPERATIONS)
    assert len(trace) == 19
    assert trace.event(18) == ("replace", 4, (), 3, 5)
    S = two_complex("assoc_list")
    last = replay(trace, S)
    # Data: the index of the event that stored each (the replace.add parts are events 16 and 17).
    assert sorted((tuple(map(int, t)), x) for t, x in S.items(last)) == [((a, c, b), 16), ((a, d, c), 17)]
    # After stop() the structure forwards without recording.
    assert rec.data(k, (a, c, b)) == (7,) and not rec.recording and len(rec.trace()) == 19


def test_a_replay_that_diverges_is_caught() -> None:
    k, tris = icosahedron()
    vs = fresh(k)
    rec = TracingTwoComplex(two_complex("red_black"))
    c = build(rec, vs, tris)
    for t in rec.inner.items(c):
        rec.find(c, t[0][:2])
    trace = rec.stop()
    with pytest.raises(ReplayMismatch, match=r"event \d+: find"):
        replay(trace, OrientationBlindFind(assoc_list))
    replay(trace, OrientationBlindFind(assoc_list), verify=False)  # without verify the divergence goes unseen


def test_untracked_versions_are_refused() -> None:
    a, b, c, d, e = fresh(5)
    rec = TracingTwoComplex(two_complex("red_black"), window=2)
    k0 = rec.new(2)
    k1 = rec.add(k0, (a, b, c), 0)
    k2 = rec.add(k1, (a, c, d), 0)
    rec.add(k2, (a, d, e), 0)
    with pytest.raises(UntrackedVersionError, match="window"):
        rec.data(k0, (a, b, c))  # older than the last two versions
    rec.data(k2, (a, b, c))
    with pytest.raises(UntrackedVersionError):
        rec.data(rec.inner.new(2), (a, b, c))  # not made through the recorder
    with pytest.raises(ValueError):
        TracingTwoComplex(two_complex("red_black"), window=0)
    with pytest.raises(TypeError):
        TracingTwoComplex(assoc_list)  # type: ignore[arg-type]


def test_replay_refuses_a_structure_of_another_dimension(hull_trace: tuple[Trace, list[tuple[int, ...]]]) -> None:
    trace, _ = hull_trace
    with pytest.raises(TraceError, match="2-complexes"):
        replay(trace, complex_structure(3, "red_black"))
    with pytest.raises(TypeError):
        replay(trace, "red_black")  # type: ignore[arg-type]


@pytest.mark.parametrize("suffix", [".npz", ".json"])
def test_files_round_trip(hull_trace: tuple[Trace, list[tuple[int, ...]]], tmp_path: Path, suffix: str) -> None:
    trace, final = hull_trace
    path = save_trace(trace, tmp_path / f"hull{suffix}")
    back = load_trace(path)
    assert back.n == trace.n
    for field in ("op", "src", "simplex", "arg", "result"):
        assert np.array_equal(getattr(back, field), getattr(trace, field)), field
    S = two_complex("hamt")
    assert label_sets(S, Replay(back).run(S)) == final


def test_malformed_files_are_refused(hull_trace: tuple[Trace, list[tuple[int, ...]]], tmp_path: Path) -> None:
    trace, _ = hull_trace
    with pytest.raises(TraceFormatError, match=".npz or .json"):
        save_trace(trace, tmp_path / "t.txt")
    with pytest.raises(TraceFormatError, match=".npz or .json"):
        load_trace(tmp_path / "t.csv")
    (tmp_path / "junk.npz").write_bytes(b"not a zip")
    with pytest.raises(TraceFormatError, match="readable"):
        load_trace(tmp_path / "junk.npz")
    np.savez(tmp_path / "other.npz", x=np.zeros(3))
    with pytest.raises(TraceFormatError, match="missing"):
        load_trace(tmp_path / "other.npz")
    good = json.loads(save_trace(trace, tmp_path / "t.json").read_text())
    bad_cases = [
        ({**good, "format": "something else"}, "not a persistri trace"),
        ({**good, "format_version": 99}, "version"),
        ({**good, "events": [["fly", -1, [], 2, 0]]}, "event 0"),
        ({**good, "events": [["add", 0, [1, 2, 3], 0, 0]]}, "reads version 0"),
        ({**good, "events": [["new", -1, [], 2, 5]]}, "should make version 0"),
        ({**good, "n": 0}, "positive"),
    ]
    for doc, message in bad_cases:
        (tmp_path / "bad.json").write_text(json.dumps(doc))
        with pytest.raises(TraceFormatError, match=message):
            load_trace(tmp_path / "bad.json")
    (tmp_path / "broken.json").write_text("{")
    with pytest.raises(TraceFormatError, match="readable"):
        load_trace(tmp_path / "broken.json")


def test_trace_arrays_are_validated() -> None:
    z = np.zeros(1, dtype=np.int64)
    with pytest.raises(TraceFormatError, match="shape"):
        Trace(2, np.zeros(1, dtype=np.uint8), np.array([-1]), np.zeros((1, 2), dtype=np.int64), z, z)
    with pytest.raises(TraceFormatError, match="integers"):
        Trace(2, np.zeros(1, dtype=np.uint8), np.array([-1.0]), np.full((1, 3), -1), z, z)
    with pytest.raises(TraceError, match="no new event"):
        empty = np.zeros(0, dtype=np.int64)
        replay(Trace(2, np.zeros(0, dtype=np.uint8), empty, np.zeros((0, 3), dtype=np.int64), empty, empty), two_complex())
