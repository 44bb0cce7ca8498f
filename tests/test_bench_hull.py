"""``persistri bench hull`` at tiny sizes: the records, the ratios, the memory figure and the errors. Never timing."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from persistri.impl.bench.hull import TWIN_MODULES
from persistri.impl.cli.main import main


def invoke(*args: str) -> Any:
    return CliRunner().invoke(main, ["bench", "hull", *args], catch_exceptions=False)


def test_json_records_per_distribution_size_and_complex() -> None:
    result = invoke("--sizes", "120,200", "--dists", "OnSphere,InBall", "--backends", "red_black,hamt", "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.output)
    assert data["sizes"] == [120, 200] and data["dists"] == ["OnSphere", "InBall"]
    assert [(r["dist"], r["n"]) for r in data["records"]] == [
        ("OnSphere", 120), ("OnSphere", 200), ("InBall", 120), ("InBall", 200)
    ]
    for r in data["records"]:
        assert r["qhull_s"] > 0 and 4 <= r["vertices"] <= r["n"] and r["insertions"] >= r["vertices"] - 4
        if r["dist"] == "OnSphere":
            assert r["vertices"] == r["n"]  # every point of a sphere is extreme
        timings = {t["backend"]: t for t in r["timings"]}
        assert list(timings) == ["red_black", "hamt", "ephemeral"]  # the baseline always runs, last
        eph = timings["ephemeral"]["seconds"]
        for t in timings.values():
            assert t["agrees"] is True  # the same vertex set as Qhull
            # Each subject is divided by the Qhull time measured next to its best run; the record keeps the best.
            assert t["vs_qhull"] == pytest.approx(t["seconds"] / t["qhull_s"])
            assert 0 < r["qhull_s"] <= t["qhull_s"]
            assert t["vs_ephemeral"] == pytest.approx(t["seconds"] / eph)
            assert t["us_per_insertion"] == pytest.approx(t["seconds"] / r["insertions"] * 1e6)
    assert "memory" not in data


def test_memory_of_the_history_against_the_final_hull() -> None:
    args = ("--sizes", "60", "--dists", "BordHeavy", "--memory", "--memory-n", "300", "--memory-dist", "OnSphere")
    result = invoke(*args, "--json")
    assert result.exit_code == 0, result.output
    mem = json.loads(result.output)["memory"]
    assert mem["n"] == 300 and mem["backend"] == "red_black" and mem["dist"] == "OnSphere"
    assert mem["versions"] == 297  # the tetrahedron, then one version per insertion: all 300 points are on the sphere
    assert mem["insertions"] == 296
    assert mem["history_kept"] > mem["final_only_kept"] > 0
    # The versions alone hold less than the whole run (which also keeps the points and the final arrays), and more
    # than a run's growth per version: the first tetrahedron and the final version are in them too.
    assert mem["history_kept"] > mem["versions_kept"] > mem["history_kept"] - mem["final_only_kept"]
    assert mem["per_version"] == pytest.approx((mem["history_kept"] - mem["final_only_kept"]) / 296)
    assert mem["per_insertion"] == pytest.approx(mem["versions_kept"] / 296)
    table = " ".join(invoke(*args).output.split())
    assert "memory, OnSphere 300 points on red_black: the full history (297 versions) holds" in table
    assert "KB per inserted point" in table


def test_memory_defaults_to_inball_and_refuses_an_unknown_distribution() -> None:
    result = invoke("--sizes", "40", "--dists", "InBall", "--memory", "--memory-n", "200", "--json")
    assert result.exit_code == 0, result.output
    mem = json.loads(result.output)["memory"]
    assert mem["dist"] == "InBall" and 0 < mem["insertions"] < 196 and mem["versions"] == mem["insertions"] + 1
    bad = CliRunner().invoke(main, ["bench", "hull", "--sizes", "50", "--memory", "--memory-dist", "Cube"])
    assert bad.exit_code != 0 and "unknown distribution 'Cube'" in bad.output


def test_table_and_errors() -> None:
    result = invoke("--sizes", "50", "--dists", "EqHeavy")
    assert result.exit_code == 0, result.output
    assert "EqHeavy" in result.output and "ephemeral" in result.output and "×Qhull" in result.output
    bad = CliRunner().invoke(main, ["bench", "hull", "--sizes", "50", "--dists", "Cube"])
    assert bad.exit_code != 0 and "unknown distribution 'Cube'" in bad.output
    bad = CliRunner().invoke(main, ["bench", "hull", "--sizes", "50", "--backends", "btree"])
    assert bad.exit_code != 0 and "btree" in bad.output
    bad = CliRunner().invoke(main, ["bench", "hull", "--sizes", "3"])
    assert bad.exit_code != 0 and "at least 4" in bad.output


def test_the_report_names_the_build_it_measured() -> None:
    """Interpreted, or the compiled twin.  ``make test`` sets PERSISTRI_TWIN for its run of the suite on the
    twin, so this also checks that that run really executes the compiled modules."""
    result = invoke("--sizes", "60", "--dists", "InBall", "--json")
    assert result.exit_code == 0, result.output
    build = json.loads(result.output)["build"]
    if os.environ.get("PERSISTRI_TWIN"):
        names = ", ".join(m.rsplit(".", 1)[1] for m in TWIN_MODULES)
        assert build == f"compiled twin ({names} by mypyc)"  # every one of them imported compiled
    else:
        assert build == "interpreted"
    assert f"persistri {build}" in " ".join(invoke("--sizes", "60", "--dists", "InBall").output.split())


def test_the_build_label_names_only_modules_the_twin_compiles() -> None:
    """The hull bench's :data:`TWIN_MODULES` is a subset of ``tools/compiled_twin.py``'s ``MODULES``, the hull's
    own modules among them, so the label cannot name a module the twin leaves interpreted."""
    source = (Path(__file__).resolve().parents[1] / "tools" / "compiled_twin.py").read_text(encoding="utf-8")
    compiled = set(re.findall(r'"persistri/([\w/]+)\.py"', source))
    named = {m.removeprefix("persistri.").replace(".", "/") for m in TWIN_MODULES}
    assert named <= compiled, named - compiled
    assert {"impl/hull/bulldozer", "impl/hull/insertion", "impl/geometry/kernel"} <= named
