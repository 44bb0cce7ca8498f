"""``persistri bench maps`` at tiny sizes: the records, their columns, skipping, failures. Never timing."""

from __future__ import annotations

import gc
import json
from typing import Any

import pytest
from click.testing import CliRunner

from persistri.impl.bench import maps as bench_maps
from persistri.impl.bench.maps import RECORD_FIELDS, SUBJECTS, MapSubject, run_map_bench
from persistri.impl.bench.maps_report import maps_text
from persistri.impl.bench.maps_subjects import ord_map_driver
from persistri.impl.cli.main import main
from persistri.impl.maps import BACKENDS, UnknownBackendError, backend
from persistri.impl.maps.assoc_list import assoc_list

EXPECTED_COLUMNS = (
    "map",
    "kind",
    "description",
    "n",
    "status",
    "insert_us",
    "find_us",
    "remove_us",
    "insert_vs_dict",
    "find_vs_dict",
    "remove_vs_dict",
    "note",
)
SUBJECT_NAMES = [s.name for s in SUBJECTS]


def importable(name: str) -> bool:
    try:
        backend(name)
    except UnknownBackendError:
        return False
    return True


def expected_status(name: str) -> str:
    """A persistri backend or adapter is measured iff its module imports; dict always; peers iff their library does."""
    if name in BACKENDS:
        return "ok" if importable(name) else "unavailable"
    if name == "dict":
        return "ok"
    library = name.split(".")[0]
    return "ok" if importable(library) else "unavailable"


def invoke(*args: str) -> Any:
    return CliRunner().invoke(main, ["bench", "maps", *args], catch_exceptions=False)


def test_json_output_has_every_column_for_every_map_and_size() -> None:
    result = invoke("--sizes", "200,150", "--repeat", "1", "--json")
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert doc["benchmark"] == "maps"
    assert doc["sizes"] == [150, 200]
    assert doc["repeat"] == 1
    assert {"seed", "python", "machine", "unit"} <= doc.keys()
    records = doc["records"]
    assert RECORD_FIELDS == EXPECTED_COLUMNS
    assert [(r["n"], r["map"]) for r in records] == [(n, name) for n in (150, 200) for name in SUBJECT_NAMES]
    for r in records:
        assert tuple(r) == EXPECTED_COLUMNS
        assert r["status"] == expected_status(r["map"]), r
    for n in (150, 200):
        by_name = {r["map"]: r for r in records if r["n"] == n}
        base = by_name["dict"]
        for r in by_name.values():
            if r["status"] != "ok":
                assert all(r[c] is None for c in EXPECTED_COLUMNS if c.endswith(("_us", "_vs_dict"))), r
                assert r["note"], r
                continue
            for op in ("insert", "find", "remove"):
                assert r[f"{op}_us"] > 0
                # The ratio is the time over dict's time for the same n and operation.
                assert r[f"{op}_vs_dict"] == pytest.approx(r[f"{op}_us"] / base[f"{op}_us"], rel=1e-9)
        assert all(base[f"{op}_vs_dict"] == 1.0 for op in ("insert", "find", "remove"))
        for adapter, library in bench_maps.ADAPTED.items():
            if by_name[adapter]["status"] == by_name[library]["status"] == "ok":
                assert by_name[adapter]["note"].startswith(f"adapter overhead, time vs {library}")


def test_table_output_names_every_map_and_what_ran() -> None:
    result = invoke("--sizes", "120", "--repeat", "1")
    assert result.exit_code == 0, result.output
    out = result.stdout
    assert "Persistent maps: µs per operation" in out
    assert "×dict" in out
    for name in SUBJECT_NAMES:
        assert name in out
    measured = [name for name in SUBJECT_NAMES if expected_status(name) == "ok"]
    assert f"measured: {', '.join(measured)}" in out
    if importable("immutables") and importable("pyrsistent"):
        assert "Adapter overhead" in out


def test_assoc_list_is_skipped_above_its_limit_with_the_reason() -> None:
    bench = run_map_bench([40, 90], repeat=1, only=["assoc_list"], assoc_list_max_n=60)
    assert [(r.map, r.n, r.status) for r in bench.records] == [
        ("dict", 40, "ok"),
        ("assoc_list", 40, "ok"),
        ("dict", 90, "ok"),
        ("assoc_list", 90, "skipped"),
    ]
    skipped = bench.records[-1]
    assert "up to 60 keys" in skipped.note and "O(n) per operation" in skipped.note
    assert skipped.insert_us is None and skipped.insert_vs_dict is None
    text = maps_text(bench)
    assert "skipped" in text and "O(n) per operation" in text


class _ForgetfulRemove:
    """The association list with a remove that returns the map unchanged (a broken backend)."""

    def __getattr__(self, name: str) -> Any:
        return getattr(assoc_list, name)

    def remove(self, m: Any, k: Any) -> Any:
        return m, assoc_list.lookup(m, k)


def _load_missing() -> Any:
    raise ImportError("No module named 'not_written_yet'")


def test_failing_and_missing_maps_are_reported_and_the_rest_still_run(monkeypatch: pytest.MonkeyPatch) -> None:
    extra = (
        MapSubject("forgetful", "persistri", "a broken map", lambda: ord_map_driver(_ForgetfulRemove())),
        MapSubject("missing", "peer", "a map that is not installed", _load_missing),
    )
    monkeypatch.setattr(bench_maps, "SUBJECTS", SUBJECTS + extra)
    bench = run_map_bench([30], repeat=1, only=["assoc_list", "forgetful", "missing"])
    status = {r.map: (r.status, r.note) for r in bench.records}
    assert status["dict"][0] == status["assoc_list"][0] == "ok"
    assert status["forgetful"][0] == "error"
    assert "MapBenchError" in status["forgetful"][1] and "removing 30 keys left 30 items" in status["forgetful"][1]
    assert status["missing"] == ("unavailable", "not importable: ImportError: No module named 'not_written_yet'")
    assert bench.measured() == ["dict", "assoc_list"]
    assert bench.unavailable() == ["missing"]
    assert [r.map for r in bench.errors()] == ["forgetful"]

    result = invoke("--sizes", "30", "--repeat", "1", "--only", "forgetful")
    assert result.exit_code == 1
    assert "ERROR" in result.stdout and "removing 30 keys left 30 items" in result.stdout


def test_progress_is_reported_and_the_gc_state_restored() -> None:
    calls: list[tuple[int, int, str]] = []
    gc.disable()
    try:
        run_map_bench([20, 10], repeat=2, only=["assoc_list"], on_progress=lambda *a: calls.append(a))
        assert not gc.isenabled()
    finally:
        gc.enable()
    run_map_bench([10], repeat=1, only=["assoc_list"])
    assert gc.isenabled()
    assert calls == [
        (0, 4, "dict n=10"),
        (1, 4, "assoc_list n=10"),
        (2, 4, "dict n=20"),
        (3, 4, "assoc_list n=20"),
        (4, 4, "done"),
    ]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--only", "nosuchmap"], "unknown map(s) 'nosuchmap'"),
        (["--sizes", "10,x"], "'x' is not a key count"),
        (["--sizes", "0"], "'0' is not a positive integer"),
        (["--repeat", "0"], "--repeat"),
    ],
)
def test_bad_options_are_usage_errors(args: list[str], message: str) -> None:
    result = invoke(*args)
    assert result.exit_code == 2
    assert message in result.output


def test_bad_arguments_to_the_function_raise_ValueError() -> None:
    with pytest.raises(ValueError, match="positive integers"):
        run_map_bench([0])
    with pytest.raises(ValueError, match="at least one"):
        run_map_bench([])
    with pytest.raises(ValueError, match="repeat"):
        run_map_bench([10], repeat=0)
