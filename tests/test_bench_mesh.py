"""``persistri bench mesh`` on small domains: the records, the counts, the checker's verdicts, the errors. Never timing."""

from __future__ import annotations

import builtins
import importlib.metadata
import json
from typing import Any

import pytest
import triangle
from cli_contract import assert_one_line_failure, invoke

from persistri.impl.bench.hull import persistri_build
from persistri.impl.bench.mesh import TriangleMissingError, run_mesh_bench, triangle_switches
from persistri.impl.mesh.api import triangulate
from persistri.impl.mesh.domain import domain_of
from persistri.impl.mesh.gallery import GALLERY, gallery_domain
from persistri.impl.mesh.verify import verify_mesh


def _json(*args: str) -> dict[str, Any]:
    result, caught = invoke(["bench", "mesh", *args, "--json"])
    assert result.exit_code == 0 and not caught, (result.output, caught)
    data: dict[str, Any] = json.loads(result.stdout)
    return data


def test_json_records_are_the_meshers_own_counts() -> None:
    data = _json("--domains", "star,crack", "--angles", "20,30", "--repeat", "2")
    assert data["domains"] == ["star", "crack"] and data["angles"] == [20.0, 30.0] and data["repeat"] == 2
    assert data["triangle"] == importlib.metadata.version("triangle") and data["build"] == persistri_build()
    assert [(r["domain"], r["angle"]) for r in data["records"]] == [("star", 20.0), ("star", 30.0), ("crack", 20.0), ("crack", 30.0)]
    for r in data["records"]:
        domain = gallery_domain(r["domain"]).pslg
        t, p = r["triangle"], r["persistri"]
        peer = triangle.triangulate(domain.to_dict(), f"pq{r['angle']:g}")
        ours = triangulate(domain, min_angle=r["angle"])
        assert (t["triangles"], t["vertices"]) == (len(peer["triangles"]), len(peer["vertices"]))
        assert (p["triangles"], p["vertices"]) == (len(ours.triangles), len(ours.vertices))
        assert (p["undos"], p["deletions"], p["insertions"], p["segment_splits"]) == (
            ours.undos, ours.deletions, ours.insertions, ours.segment_splits
        )
        assert t["undos"] is None and t["status"] == p["status"] == "ok"
        assert r["count_ratio"] == pytest.approx(p["triangles"] / t["triangles"])
        assert r["time_ratio"] == pytest.approx(p["seconds"] / t["seconds"])
        # The angles are the exact checker's measure of each mesh, with the exemption at small input angles.
        report = verify_mesh(domain, ours.vertices, ours.triangles, min_angle=r["angle"])
        assert (p["min_angle"], p["min_angle_all"], p["exempt"], p["passes"]) == (
            report.min_angle_unexempt, report.min_angle, report.exempt, True
        )
        peer_report = verify_mesh(domain, peer["vertices"], peer["triangles"], min_angle=r["angle"], exact_segments=False)
        assert (t["min_angle"], t["passes"]) == (peer_report.min_angle_unexempt, peer_report.ok)
        assert p["min_angle"] >= r["angle"] and r["reached_where_triangle_does"] is True
    star30 = data["records"][1]
    assert star30["persistri"]["exempt"] > 0 and star30["persistri"]["min_angle_all"] < 30  # the 20° tips stay


def test_the_table_has_a_row_per_domain_and_bound() -> None:
    result, caught = invoke(["bench", "mesh", "--domains", "l-shape,square-hole", "--angles", "30", "--repeat", "1"])
    assert result.exit_code == 0 and not caught, result.output
    rows = [ln for ln in result.stdout.splitlines() if ln.startswith("│")]
    assert len(rows) == 2 and rows[0].split("│")[1].strip() == "l-shape" and rows[1].split("│")[1].strip() == "square-hole"
    cells = [c.strip() for c in rows[1].split("│")[1:-1]]
    ours = triangulate(gallery_domain("square-hole").pslg, min_angle=30)
    peer = triangle.triangulate(gallery_domain("square-hole").pslg.to_dict(), "pq30")
    assert cells[1:5] == ["30", str(len(peer["triangles"])), str(len(ours.triangles)), f"{len(ours.triangles) / len(peer['triangles']):.2f}"]
    assert cells[9:12] == ["yes", "yes", str(ours.undos)]
    # The build that ran is named: "interpreted", or "compiled twin (…)" when make test runs the suite on the twin.
    assert "Triangle" in result.stdout and f"persistri {persistri_build()}" in result.stdout.replace("\n", " ")


def test_size_bounds_each_domain_by_its_area() -> None:
    data = _json("--domains", "l-shape,circle", "--angles", "25", "--size", "300", "--repeat", "1")
    assert data["size"] == 300 and data["max_area"] is None
    for r in data["records"]:
        domain = gallery_domain(r["domain"]).pslg
        assert r["max_area"] == float(domain_of(domain).area) / 300
        ours = triangulate(domain, min_angle=25, max_area=r["max_area"])
        assert r["persistri"]["triangles"] == len(ours.triangles) >= 300 and r["persistri"]["passes"]
        peer = triangle.triangulate(domain.to_dict(), triangle_switches(25, r["max_area"]))
        assert r["triangle"]["triangles"] == len(peer["triangles"]) >= 300 and r["triangle"]["passes"]


def test_max_area_is_passed_to_both_in_a_form_triangle_reads() -> None:
    assert triangle_switches(30, None) == "pq30"
    assert triangle_switches(0, None) == "p"
    assert triangle_switches(20.5, 1e-7) == "pq20.5a0.0000001"  # Triangle's parser reads no exponent
    data = _json("--domains", "square-hole", "--angles", "0", "--max-area", "0.5", "--repeat", "1")
    (r,) = data["records"]
    assert r["max_area"] == 0.5 and r["persistri"]["passes"] and r["triangle"]["passes"]
    ours = triangulate(gallery_domain("square-hole").pslg, max_area=0.5)
    assert r["persistri"]["triangles"] == len(ours.triangles)


def test_a_precision_limit_is_recorded_not_fatal(monkeypatch: pytest.MonkeyPatch) -> None:
    from persistri.impl.mesh import api
    from persistri.impl.mesh.steiner import PrecisionLimitError

    def limited(*args: object, **kwargs: object) -> None:
        raise PrecisionLimitError("no pair of doubles lies exactly on the segment")

    monkeypatch.setattr(api, "triangulate", limited)
    bench = run_mesh_bench(["l-shape"], [20], repeat=1)
    (r,) = bench.records
    assert r.persistri.status == "limit" and "no pair of doubles" in r.persistri.note
    assert r.count_ratio is None and r.time_ratio is None and not r.reached_where_triangle_does
    assert bench.errors() == []  # a documented limit, not a bug


def test_a_failing_persistri_mesh_exits_1(monkeypatch: pytest.MonkeyPatch) -> None:
    from persistri.impl.mesh import api

    real = api.triangulate

    def broken(*args: Any, **kwargs: Any) -> Any:
        mesh = real(*args, **kwargs)
        return type("Broken", (), {**{k: getattr(mesh, k) for k in ("vertices", "undos", "deletions", "insertions", "segment_splits",
                                                                  "rounded_splits", "exact_segments")},
                                   "triangles": mesh.triangles[1:]})()

    monkeypatch.setattr(api, "triangulate", broken)
    result, _ = invoke(["bench", "mesh", "--domains", "l-shape", "--angles", "20", "--repeat", "1"])
    assert result.exit_code == 1
    assert "l-shape at 20°: persistri's mesh: " in result.stdout and "│ NO " in result.stdout


def test_without_triangle_one_clear_line(monkeypatch: pytest.MonkeyPatch) -> None:
    real_import = builtins.__import__

    def no_triangle(name: str, *args: Any, **kwargs: Any) -> Any:
        if name == "triangle":
            raise ImportError("No module named 'triangle'")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_triangle)
    with pytest.raises(TriangleMissingError):
        run_mesh_bench(["star"], [20], repeat=1)
    result, caught = invoke(["bench", "mesh", "--domains", "star"])
    assert_one_line_failure(result, caught, "Triangle", r"bench mesh compares with Shewchuk's Triangle, which is not installed: pip install triangle")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--domains", "hexagon"], "unknown gallery domain hexagon; the domains are " + ", ".join(GALLERY)),
        (["--domains", ","], "unknown gallery domain (none given)"),
        (["--angles", "20,sixty"], "'sixty' is not a number of degrees"),
        (["--angles", "61"], "61 is not an angle bound in [0, 60) degrees"),
        (["--max-area", "1", "--size", "10"], "give --max-area or --size, not both"),
        (["--max-area", "nan"], "nan is not a finite area"),
        (["--size", "0"], "Invalid value for '--size'"),
    ],
)
def test_bad_options_are_usage_errors(args: list[str], message: str) -> None:
    result, _ = invoke(["bench", "mesh", *args])
    assert result.exit_code == 2 and message in result.stderr, result.stderr
