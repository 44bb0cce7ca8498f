"""The conformance suites catch what only size, replays or a second instance reveal — at their default settings.

The galleries ``AT_SCALE`` of :mod:`broken_maps` and :mod:`broken_complexes` hold structures that are
persistent while small and write into their operand (or an older version) once they hold 40, 1,000 or
2,000 items; that cache answers by ``id``; that keep their versions in a class-level table.  Each must be
rejected under the right law through the three front ends — :func:`run_conformance` (what ``persistri
conformance`` prints), the pytest base class, and the command line — with the suite's default knobs
(``workload_size`` 100,000 for maps, 300 for complexes).  The tests that find them are selected by name
(``tests=``, ``--test``) to keep this file quick; ``test_a_full_default_run_*`` run whole suites.

Also here: hypothesis's ``Flaky`` reported as the law ``determinism``; the growth engine's pieces (the
kept sizes, the bisection, a failure pinned to the operation that caused it); and the new tests passing
on correct structures.
"""

from __future__ import annotations

from typing import Any

import pytest
from click.testing import CliRunner

import broken_complexes
import broken_maps
from persistri.impl.cli.main import main
from persistri.impl.complex import VertexState, complex_structure
from persistri.impl.maps.red_black import red_black
from persistri.spec.conformance import (
    ORD_MAP_TESTS,
    SIMPCOMP_TESTS,
    OrdMapConformance,
    SimpCompConformance,
    run_conformance,
    run_simpcomp_conformance,
)
from persistri.spec.conformance.growth import checkpoints, counted, first_change
from persistri.spec.conformance.ord_map_growth import growth_plan
from persistri.spec.ord_map_laws import ORD_MAP_LAWS
from persistri.spec.ord_map_laws import LawViolation as MapViolation
from persistri.spec.simpcomp_laws import SIMPCOMP_LAWS
from persistri.spec.simpcomp_laws import LawViolation as ComplexViolation

STATE = "persistri.impl.complex.vertex:VertexState.initial"

HEADLINES: dict[str, str] = {
    # What the first line of each failure's detail says: the law, the version with its size, the operation.
    "maps:grows_mutating": "persistence: version 40 (40 items) changed after insert on version 40",
    "maps:grows_mutating_late": "persistence: version 2000 (2,000 items) changed after insert on version 2000",
    "maps:ancestor_mutating": "persistence: version 1024 (1,024 items) changed after insert on version 1025",
    "maps:stale_find_cache": "determinism: ",
    "maps:shared_table": "isolation: version 1 of the first instance changed after ",
    "complex:grows_mutating": "persistence: version 78 (40 triangles) changed after add on version 78",
    "complex:grows_mutating_late": "persistence: version 3998 (2,000 triangles) changed after add on version 3998",
    "complex:stale_data_cache": "determinism: ",
    "complex:shared_table": "isolation: version 1 (1 triangle) of the first instance changed after ",
}

GALLERY = [f"maps:{name}" for name in broken_maps.AT_SCALE] + [f"complex:{name}" for name in broken_complexes.AT_SCALE]


def _entry(which: str) -> tuple[str, str, Any, str, str]:
    suite, name = which.split(":")
    module = broken_maps if suite == "maps" else broken_complexes
    structure, law, test = module.AT_SCALE[name]
    return suite, f"{module.__name__}:{name}", structure, law, test


def test_every_entry_of_the_galleries_has_its_headline() -> None:
    assert set(HEADLINES) == set(GALLERY)


# -- run_conformance / run_simpcomp_conformance, at the default settings ------------------------------------


@pytest.mark.build_independent
@pytest.mark.parametrize("which", GALLERY)
def test_the_runner_names_the_law_at_default_settings(which: str) -> None:
    suite, target, structure, law, test = _entry(which)
    if suite == "maps":
        report = run_conformance(structure, tests=[test], name=target)
        statement = ORD_MAP_LAWS[law]
    else:
        report = run_simpcomp_conformance(structure, state=VertexState.initial, tests=[test], name=target)
        statement = SIMPCOMP_LAWS[law]
    (failure,) = report.failures
    assert failure.test == test and failure.law == law and failure.statement == statement, failure.format()
    assert failure.detail.startswith(HEADLINES[which]), failure.detail
    text = report.format()
    assert f"FAILED {test} — law {law}: {statement}" in text
    assert "\n  " + HEADLINES[which] in text  # the headline is a line of the report, as printed


# -- the pytest base classes, at their default knobs -------------------------------------------------------


@pytest.mark.build_independent
@pytest.mark.parametrize("which", GALLERY)
def test_the_base_class_raises_the_law_at_its_default_knobs(which: str) -> None:
    suite, _, structure, law, test = _entry(which)
    cls: type[OrdMapConformance] | type[SimpCompConformance]
    if suite == "maps":
        cls = type("TestBroken", (OrdMapConformance,), {"structure": structure})
        violation: type[Exception] = MapViolation
    else:
        cls = type("TestBroken", (SimpCompConformance,), {"structure": structure, "state": VertexState.initial})
        violation = ComplexViolation
    with pytest.raises(violation) as info:
        getattr(cls(), f"test_{test}")()
    assert isinstance(info.value, (MapViolation, ComplexViolation))
    assert info.value.law == law
    assert HEADLINES[which] in str(info.value)  # the assertion message pytest shows


# -- persistri conformance, at the default options -----------------------------------------------------------


@pytest.mark.build_independent
@pytest.mark.parametrize("which", GALLERY)
def test_the_command_names_the_law_at_default_options(which: str) -> None:
    suite, target, _, law, test = _entry(which)
    args = ["conformance", suite, target, "--test", test]
    if suite == "complex":
        args += ["--state", STATE]
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 1, r.output
    laws = ORD_MAP_LAWS if suite == "maps" else SIMPCOMP_LAWS
    assert r.stdout.startswith(f"{target} does NOT conform to ")
    assert f"FAILED {test} — law {law}: {laws[law]}" in r.stdout
    assert "\n  " + HEADLINES[which] in r.stdout


@pytest.mark.build_independent
@pytest.mark.parametrize(
    ("suite", "target", "law"),
    [
        ("maps", "broken_maps:StaleFindCacheMap", "determinism"),
        ("complex", "broken_complexes:StaleDataCacheComplex", "determinism"),
    ],
)
def test_a_full_default_run_names_only_the_right_law(suite: str, target: str, law: str) -> None:
    """The whole suite, every option at its default, on the structures whose hidden state trips many tests
    (about twenty seconds for the map): no other law blamed, and never a bare FlakyFailure.

    The targets are the classes, as the guide advises for a structure with caches: the suite's second
    instances are then new ones.  (Copies of an instance whose memo earlier tests filled carry its stale
    entries, and a rerun on one can, rarely, repeat a failure by the accident of the allocator.)"""
    args = ["conformance", suite, target] + (["--state", STATE] if suite == "complex" else [])
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 1, r.output
    failed = [line for line in r.stdout.splitlines() if line.startswith("FAILED ")]
    assert failed and all(f"— law {law}: " in line for line in failed), "\n".join(failed)
    assert "FlakyFailure:" not in r.stdout and "outside any law" not in r.stdout


def test_the_command_refuses_an_unknown_test_name_in_one_line() -> None:
    r = CliRunner().invoke(main, ["conformance", "maps", "persistri.impl.maps.red_black:red_black", "--test", "grwth"])
    assert r.exit_code == 2 and r.stdout == ""
    assert r.stderr.startswith("persistri: --test: no test named 'grwth'; the tests are: key_order, ")
    assert r.stderr.count("\n") == 1


# -- hypothesis's Flaky is the law determinism -----------------------------------------------------------------


class ColdFindMap(broken_maps.RedBlackDelegate):
    """``find`` of a key it has never been asked about answers NONE ("a cold cache"): a failing example passes
    when hypothesis runs it again, which hypothesis reports as ``Flaky``."""

    def __init__(self) -> None:
        super().__init__()
        self._asked: set[Any] = set()

    def find(self, m: Any, k: Any) -> Any:
        if k not in self._asked:
            self._asked.add(k)
            return None
        return red_black.find(m, k)


@pytest.mark.build_independent
def test_flaky_is_reported_as_determinism_by_the_runner() -> None:
    report = run_conformance(ColdFindMap(), tests=["find_insert"], name="cold")
    (failure,) = report.failures
    assert failure.law == "determinism", failure.format()
    assert "hypothesis found a failing example, ran it again, and it passed (FlakyFailure)" in failure.detail
    assert "the first run: law find_insert: " in failure.detail
    assert "Failing test case: find_insert(" in failure.example


@pytest.mark.build_independent
def test_flaky_is_reported_as_determinism_by_the_base_class() -> None:
    cls = type("TestCold", (OrdMapConformance,), {"structure": ColdFindMap()})
    with pytest.raises(MapViolation) as info:
        cls().test_find_insert()
    assert info.value.law == "determinism" and "FlakyFailure" in info.value.detail


# -- the correct structures pass the new tests --------------------------------------------------------------------


@pytest.mark.parametrize("structure", ["red_black_map", "assoc_list_class", "red_black_2complex", "int_trie_map", "int_trie_2complex"])
def test_correct_structures_pass_the_tests_at_scale(structure: str) -> None:
    tests = ["growth", "determinism", "isolation"]
    if structure == "red_black_map":
        report = run_conformance(red_black, tests=tests, workload_size=5_000)
    elif structure == "int_trie_map":
        from persistri.impl.maps.int_trie import int_trie

        report = run_conformance(int_trie, tests=tests, workload_size=5_000, hashing=False)
    elif structure == "int_trie_2complex":
        report = run_simpcomp_conformance(complex_structure(2, "int_trie"), state=VertexState.initial, tests=tests, dims=(2,))
    elif structure == "assoc_list_class":  # a class: its second instances are new ones, not copies
        from persistri.impl.maps.assoc_list import AssocListMap

        report = run_conformance(AssocListMap, tests=tests, workload_size=1_000)
    else:
        report = run_simpcomp_conformance(complex_structure(2, "red_black"), state=VertexState.initial, tests=tests, dims=(2,))
    assert report.ok and report.count("passed") == 3, report.format()


def test_every_test_has_a_base_class_method() -> None:
    for base, table in ((OrdMapConformance, ORD_MAP_TESTS), (SimpCompConformance, SIMPCOMP_TESTS)):
        assert {"growth", "determinism", "isolation"} <= {t.name for t in table}
        assert all(callable(getattr(base, f"test_{t.name}")) for t in table)


# -- the growth engine's pieces ------------------------------------------------------------------------------------


def test_checkpoints_are_the_powers_of_two_below_n_then_n() -> None:
    assert checkpoints(0) == []
    assert checkpoints(1) == [1]
    assert checkpoints(100_000)[:6] == [1, 2, 4, 8, 16, 32]
    assert checkpoints(100_000)[-3:] == [32_768, 65_536, 100_000]
    assert checkpoints(1_024) == [2**k for k in range(11)]
    assert sum(checkpoints(100_000)) < 3 * 100_000


def test_counted_says_items_with_separators() -> None:
    assert counted(1, "item") == "1 item"
    assert counted(1_203, "item") == "1,203 items"
    assert counted(2, "tetrahedron", "tetrahedra") == "2 tetrahedra"


@pytest.mark.parametrize("at", [1, 2, 17, 63, 64])
def test_first_change_finds_the_operation_in_lg_calls(at: int) -> None:
    calls: list[int] = []

    def changed(t: int) -> bool:
        calls.append(t)
        return t >= at

    assert first_change(0, 64, changed) == at
    assert len(calls) <= 6


def test_the_map_plan_crosses_every_hamt_level_and_is_the_same_every_time() -> None:
    plan = growth_plan(40_000)
    assert plan is growth_plan(40_000)  # cached: made once per size
    sizes = {len(m) for v, m in plan.kept.items() if v <= plan.n}  # the trunk's kept versions
    assert {32, 64, 1_024, 2_048, 32_768, 40_000} <= sizes  # a version kept on each side of every level
    assert plan.ops[0].kind == "insert" and [op.kind for op in plan.ops[:40_000]] == ["insert"] * 40_000
    kinds = {op.kind for op in plan.ops[40_000:]}
    assert kinds == {"insert", "insertWith", "remove", "remove_absent"}
    fresh = growth_plan.__wrapped__(40_000)  # built again from scratch: the same operations
    assert fresh.ops == plan.ops and fresh.kept == plan.kept


def _pinned(structure: Any, **kw: Any) -> str:
    report = run_conformance(structure, tests=["growth"], **kw)
    (failure,) = report.failures
    return failure.detail


@pytest.mark.build_independent
def test_a_change_to_an_older_version_is_pinned_to_the_insert_that_made_it() -> None:
    detail = _pinned(broken_maps.ancestor_mutating, workload_size=3_000)
    lines = detail.splitlines()
    assert lines[0] == "persistence: version 1024 (1,024 items) changed after insert on version 1025"
    assert lines[1].startswith("the operation: insert(version 1025, ") and "which made version 1026" in lines[1]
    assert any(line.startswith("pinned to the operation by ") for line in lines)


@pytest.mark.build_independent
def test_a_threshold_above_the_workload_is_not_reached() -> None:
    """Below its threshold the late map is persistent: a workload that stays under 2,000 items passes."""
    report = run_conformance(broken_maps.grows_mutating_late, tests=["growth"], workload_size=1_990)
    assert report.ok, report.format()


class _Reports:
    """A pytest plugin keeping the report of every test's call phase."""

    def __init__(self) -> None:
        self.reports: dict[str, pytest.TestReport] = {}

    def pytest_runtest_logreport(self, report: pytest.TestReport) -> None:
        if report.when == "call":
            self.reports[report.nodeid.split("::", 1)[1]] = report


@pytest.mark.build_independent
def test_pytest_shows_the_law_and_the_operation_in_the_assertion_message(tmp_path: Any) -> None:
    """As an outsider runs it: pytest collects the base classes, and the failure it prints names the law,
    the version and the operation."""
    (tmp_path / "pytest.ini").write_text("[pytest]\n")
    (tmp_path / "test_outsider_at_scale.py").write_text(
        "from broken_complexes import stale_data_cache\n"
        "from broken_maps import grows_mutating_late\n"
        "from persistri.impl.complex import VertexState\n"
        "from persistri.spec.conformance import OrdMapConformance, SimpCompConformance\n"
        "\n"
        "class TestLate(OrdMapConformance):\n"
        "    structure = grows_mutating_late\n"
        "\n"
        "class TestCache(SimpCompConformance):\n"
        "    structure = stale_data_cache\n"
        "    state = VertexState.initial\n"
    )
    plugin = _Reports()
    code = pytest.main(
        [
            str(tmp_path / "test_outsider_at_scale.py"),
            "-c", str(tmp_path / "pytest.ini"), "--rootdir", str(tmp_path), "-p", "no:cacheprovider",
            "--import-mode=importlib", "-q", "-k", "TestLate and test_growth or TestCache and test_determinism",
        ],
        plugins=[plugin],
    )
    assert code == pytest.ExitCode.TESTS_FAILED
    assert set(plugin.reports) == {"TestLate::test_growth", "TestCache::test_determinism"}
    late = plugin.reports["TestLate::test_growth"]
    assert late.failed and "law 'persistence' violated" in late.longreprtext
    assert HEADLINES["maps:grows_mutating_late"] in late.longreprtext
    cache = plugin.reports["TestCache::test_determinism"]
    assert cache.failed and "law 'determinism' violated" in cache.longreprtext


class _Reversed:
    """Integer keys ordered from the largest down (``Key.compare`` reversed)."""

    @staticmethod
    def compare(a: Any, b: Any) -> Any:
        from persistri.spec.order import NATURAL_ORDER

        return NATURAL_ORDER.compare(b, a)


class ReversedMap(broken_maps.RedBlackDelegate):
    """A correct map whose key order is not Python's ``<``: the red-black tree over the negated keys."""

    Key = _Reversed()

    def insert(self, m: Any, k: Any, v: Any) -> Any:
        return red_black.insert(m, -k, v)

    def insertWith(self, f: Any, m: Any, k: Any, v: Any) -> Any:
        return red_black.insertWith(f, m, -k, v)

    def find(self, m: Any, k: Any) -> Any:
        return red_black.find(m, -k)

    def remove(self, m: Any, k: Any) -> tuple[Any, Any]:
        return red_black.remove(m, -k)

    def singleton(self, k: Any, v: Any) -> Any:
        return red_black.singleton(-k, v)

    def listItemsi(self, m: Any) -> list[tuple[Any, Any]]:
        return [(-k, v) for k, v in red_black.listItemsi(m)]  # increasing negated keys: decreasing keys

    def listKeys(self, m: Any) -> list[Any]:
        return [k for k, _ in self.listItemsi(m)]

    def foldli(self, f: Any, init: Any, m: Any) -> Any:
        for k, v in self.listItemsi(m):
            init = f(k, v, init)
        return init


def test_the_growth_workload_orders_keys_by_the_structures_own_compare() -> None:
    report = run_conformance(ReversedMap(), tests=["growth", "listItemsi", "persistence"], workload_size=3_000, hashing=False)
    assert report.ok, report.format()
