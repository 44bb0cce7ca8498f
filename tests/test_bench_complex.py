"""``persistri bench complex`` at tiny sizes: the workloads, the records, skipping, failures, the CLI.

Never timing: only shapes, counts, statuses and the baseline's own ratio (1 by definition).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from persistri.impl.bench import complex as bench_complex
from persistri.impl.bench.complex import (
    RECORD_FIELDS,
    SUBJECTS,
    ComplexSubject,
    hull_trace,
    run_complex_bench,
    sphere_trace,
    walk,
)
from persistri.impl.bench.complex_report import complex_text
from persistri.impl.cli.main import main
from persistri.impl.complex.checks import check_closed_surface
from persistri.impl.complex.simpcomp import two_complex
from persistri.impl.complex.trace import Replay, replay, save_trace
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.maps import UnknownBackendError, backend
from persistri.impl.maps.red_black import red_black

NAMES = [s.name for s in SUBJECTS]


def available(name: str) -> bool:
    if name == "ephemeral":
        return True
    try:
        backend(name)
    except UnknownBackendError:
        return False
    return True


def invoke(*args: str) -> Any:
    return CliRunner().invoke(main, ["bench", "complex", *args], catch_exceptions=False)


@pytest.mark.parametrize("triangles", [4, 5, 30, 200])
def test_the_sphere_workload_grows_a_closed_sphere_like_a_hull(triangles: int) -> None:
    for stepwise in (False, True):
        tr = sphere_trace(triangles, seed=3, stepwise=stepwise)
        S = two_complex("red_black")
        c = replay(tr, S)
        report = check_closed_surface(c)
        want = max(4, triangles + triangles % 2)
        assert report.faces == want and report.is_sphere
        counts = dict.fromkeys(["rem", "replace", "replace.add", "replace.rem", "findi"], 0) | tr.counts()
        grown = (want - 4) // 2  # one new vertex per step, +2 triangles each
        assert counts.get("data", 0) == grown
        added = counts["add"] + counts["replace.add"]
        removed = counts["rem"] + counts["replace.rem"]
        assert added - removed == want
        # One replace per step, or none at all (stepwise: a rem per removed face and an add per tent face).
        assert counts["replace"] == (0 if stepwise else grown)
        assert counts["add"] == (added if stepwise else 4)
        assert counts["findi"] >= 3 * removed  # every removed face looked across its three edges
        assert list(sphere_trace(triangles, seed=3, stepwise=stepwise).events()) == list(tr.events())  # deterministic


def test_the_hull_workload_records_the_bulldozer() -> None:
    tr = hull_trace(60, seed=1)
    S = two_complex("hamt")
    report = check_closed_surface(replay(tr, S))
    assert report.faces == 60 and report.vertices == 32


def test_walk_visits_every_triangle_once() -> None:
    tr = sphere_trace(100, seed=2)
    rp = Replay(tr)
    for name in ("ephemeral", "red_black"):
        S = two_complex(name)
        c = rp.run(S)
        start = next(iter(S.items(c)))[0]
        assert walk(S, c, start) == 100


def test_json_output_has_every_field_for_every_complex_and_size() -> None:
    result = invoke("--sizes", "60,100", "--repeat", "1", "--json")
    assert result.exit_code == 0, result.output
    doc = json.loads(result.output)
    assert doc["benchmark"] == "complex" and doc["workload"] == "sphere" and doc["sizes"] == [60, 100]
    assert set(doc["operations"]) == {"60", "100"}
    records = doc["records"]
    assert [(r["triangles"], r["complex"]) for r in records] == [(t, n) for t in (60, 100) for n in NAMES]
    for r in records:
        assert tuple(r) == RECORD_FIELDS
        assert r["status"] == ("ok" if available(r["complex"]) else "unavailable")
        if r["status"] == "ok":
            assert r["build_s"] > 0 and r["walk_s"] > 0 and r["build_us"] > 0 and r["events"] > 0
            if r["complex"] == "ephemeral":
                assert r["build_vs_ephemeral"] == r["walk_vs_ephemeral"] == r["total_vs_ephemeral"] == 1.0
    assert set(doc["growth"]) == {"assoc_list"}  # measured at both sizes: its growth rate is stated
    assert doc["growth"]["assoc_list"]["from"] == 60 and doc["growth"]["assoc_list"]["to"] == 100


def test_table_output_and_only() -> None:
    result = invoke("--sizes", "40", "--repeat", "1", "--only", "red_black")
    assert result.exit_code == 0, result.output
    assert "ephemeral" in result.output and "red_black" in result.output and "hamt" not in result.output
    assert "40 triangles:" in result.output and "total ×eph" in result.output
    bad = CliRunner().invoke(main, ["bench", "complex", "--sizes", "40", "--only", "btree"])
    assert bad.exit_code == 2 and "unknown complex" in bad.output


def test_the_association_list_is_skipped_above_its_limit() -> None:
    bench = run_complex_bench([40, 80], repeat=1, only=["assoc_list"], assoc_list_max=50)
    small, large = bench.record("assoc_list", 40), bench.record("assoc_list", 80)
    assert small is not None and small.status == "ok"
    assert large is not None and large.status == "skipped" and "50" in large.note and "O(T²)" in large.note
    assert large.build_s is None and large.total_vs_ephemeral is None
    text = complex_text(bench)
    assert "skipped ¹" in text and "¹ assoc_list at 80 triangles: skipped" in text
    assert bench.growth("assoc_list") is None  # measured at one size only


def test_a_saved_trace_is_replayed(tmp_path: Path) -> None:
    path = save_trace(hull_trace(40, seed=5), tmp_path / "hull.npz")
    result = invoke("--trace", str(path), "--repeat", "1", "--only", "hamt", "--json")
    assert result.exit_code == 0, result.output
    doc = json.loads(result.output)
    assert doc["workload"] == "trace" and doc["sizes"] == [40]
    assert {r["complex"]: r["status"] for r in doc["records"]} == {"ephemeral": "ok", "hamt": "ok"}
    (tmp_path / "bad.json").write_text("{}")
    bad = CliRunner().invoke(main, ["bench", "complex", "--trace", str(tmp_path / "bad.json")])
    assert bad.exit_code == 2 and "not a persistri trace" in bad.output


class ForgetfulRem(TwoComplex[Any]):
    """A broken 2-complex: rem does nothing, and replace only adds."""

    def rem(self, c: Any, s: Any, /) -> Any:
        return c

    def replace(self, c: Any, removed: Any, added: Any, /) -> Any:
        return super().replace(c, [], added)


def test_a_wrong_complex_is_an_error_not_a_figure(monkeypatch: pytest.MonkeyPatch) -> None:
    broken = ComplexSubject("red_black", "persistri", "broken", lambda: ForgetfulRem(red_black))
    monkeypatch.setattr(bench_complex, "SUBJECTS", (SUBJECTS[0], broken))
    bench = run_complex_bench([60], repeat=1)
    rec = bench.record("red_black", 60)
    assert rec is not None and rec.status == "error" and "triangles" in rec.note and rec.build_s is None
    assert bench.errors() == [rec]
    result = invoke("--sizes", "60", "--repeat", "1")
    assert result.exit_code == 1


def test_bad_arguments() -> None:
    with pytest.raises(ValueError, match="workload"):
        run_complex_bench([10], workload="torus")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="repeat"):
        run_complex_bench([10], repeat=0)
    with pytest.raises(ValueError, match="triangles"):
        sphere_trace(0)
    assert CliRunner().invoke(main, ["bench", "complex", "--sizes", "ten"]).exit_code == 2
