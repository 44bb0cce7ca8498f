"""``persistri conformance maps MODULE:ATTR``: exit 0 conforms, 1 a law fails, 2 not a loadable ORD_MAP structure."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner, Result

from persistri.impl.cli.main import main

# What these tests check is the conformance engine (persistri.spec), which the compiled twin does not
# compile: they run once, on the interpreted build (tests/conftest.py, ``build_independent``).
pytestmark = pytest.mark.build_independent

QUICK = ["--max-examples", "10", "--workload-size", "200"]


def run(*args: str) -> Result:
    return CliRunner().invoke(main, ["conformance", "maps", *args])


def test_a_conforming_structure_exits_0_with_a_summary() -> None:
    r = run("persistri.impl.maps.assoc_list:assoc_list", *QUICK)
    assert r.exit_code == 0, r.output
    assert r.stdout.splitlines() == [
        "persistri.impl.maps.assoc_list:assoc_list conforms to ORD_MAP: 29 passed, 0 failed, 0 skipped "
        "(max_examples=10, workload_size=200, hashing=True, check=True)"
    ]


def test_a_class_is_instantiated_and_no_hashing_skips_the_collision_test() -> None:
    r = run("persistri.impl.maps.assoc_list:AssocListMap", "--max-examples", "5", "--workload-size", "0", "--no-hashing")
    assert r.exit_code == 0, r.output
    assert "conforms to ORD_MAP: 25 passed, 0 failed, 4 skipped" in r.stdout
    assert "hashing=False" in r.stdout
    assert "skipped edge_colliding_hashes: hashing is off" in r.stdout
    assert "skipped workload_random: workload_size = 0" in r.stdout


def test_a_broken_structure_exits_1_with_law_statement_and_counterexample() -> None:
    r = run("broken_maps:mutating", *QUICK)
    assert r.exit_code == 1, r.output
    out = r.stdout
    assert out.startswith("broken_maps:mutating does NOT conform to ORD_MAP:")
    assert "FAILED persistence — law persistence: every earlier version is unchanged by any later operation" in out
    assert "counterexample:" in out and "Failing test case: persistence(" in out
    assert "FAILED stateful_history — law persistence" in out and "state = OrdMapHistory()" in out


@pytest.mark.parametrize(
    ("target", "line"),
    [
        (
            "builtins:dict",
            "persistri: builtins:dict is not an ORD_MAP structure: missing Key, empty, isEmpty, singleton, insert, "
            "insertWith, find, lookup, inDomain, remove, numItems, listItemsi, listKeys, foldli",
        ),
        ("no_such_module_xyz:thing", "persistri: cannot import module 'no_such_module_xyz': No module named 'no_such_module_xyz'"),
        ("persistri.impl.maps:no_such_thing", "persistri: module 'persistri.impl.maps' has no attribute 'no_such_thing'"),
        ("persistri.impl.maps.assoc_list", "persistri: expected MODULE:ATTR (e.g. persistri.impl.maps.red_black:red_black), got 'persistri.impl.maps.assoc_list'"),
    ],
)
def test_unusable_targets_exit_2_with_one_line(target: str, line: str) -> None:
    r = run(target)
    assert r.exit_code == 2
    assert r.stdout == ""
    assert r.stderr == line + "\n"


def test_a_structure_lacking_some_operations_is_named_in_one_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "partial_map_mod.py").write_text(
        "from persistri.impl.maps.assoc_list import AssocListMap\n"
        "class Partial(AssocListMap):\n"
        "    remove = None\n"
        "    foldli = 3\n"
        "thing = Partial()\n"
        "class ValueEmpty(AssocListMap):\n"
        "    empty = ()\n"
        "class NeedsArgs:\n"
        "    def __init__(self, x):\n"
        "        pass\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    r = run("partial_map_mod:thing")
    assert r.exit_code == 2
    assert r.stderr == (
        "persistri: partial_map_mod:thing is not an ORD_MAP structure: missing remove; foldli is not callable (int) "
        "(a value of the SML signature, such as empty, is a method with no arguments here: empty())\n"
    )
    r = run("partial_map_mod:ValueEmpty")  # SML's `val empty` written as a value: the message says what to write
    assert r.exit_code == 2
    assert r.stderr.startswith("persistri: partial_map_mod:ValueEmpty is not an ORD_MAP structure: empty is not callable (tuple)")
    assert "empty()" in r.stderr and r.stderr.count("\n") == 1
    r = run("partial_map_mod:NeedsArgs")
    assert r.exit_code == 2 and r.stderr.count("\n") == 1
    assert r.stderr.startswith("persistri: partial_map_mod:NeedsArgs is a class that cannot be instantiated with no arguments")


def test_a_module_that_fails_to_import_is_one_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "exploding_mod.py").write_text("raise RuntimeError('boom\\nsecond line')\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    r = run("exploding_mod:x")
    assert r.exit_code == 2
    assert r.stderr == "persistri: importing module 'exploding_mod' failed: RuntimeError: boom\n"


def test_bad_option_values_are_usage_errors() -> None:
    r = run("persistri.impl.maps.assoc_list:assoc_list", "--max-examples", "0")
    assert r.exit_code == 2 and "--max-examples" in r.output


def test_a_module_in_the_current_directory_is_found(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "cwd_map_mod.py").write_text("thing = object()\n")
    monkeypatch.chdir(tmp_path)
    r = run("cwd_map_mod:thing")
    assert r.exit_code == 2
    assert r.stderr.startswith("persistri: cwd_map_mod:thing is not an ORD_MAP structure: missing Key, empty")


def test_the_complex_help_example_runs() -> None:
    # The example in `persistri conformance complex --help`, read from the help itself, passes as written
    # (quick settings added), and no name in the help is broken across lines by the wrapping.
    help_text = CliRunner().invoke(main, ["conformance", "complex", "--help"], terminal_width=80).output
    lines = help_text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.strip().startswith("persistri conformance complex"))
    words: list[str] = []
    for line in lines[start:]:
        words += line.replace("\\", " ").split()
        if not line.rstrip().endswith("\\"):
            break
    assert words[:3] == ["persistri", "conformance", "complex"]
    r = CliRunner().invoke(main, [*words[1:], "--max-examples", "3", "--workload-size", "0", "--stateful-steps", "0"])
    assert r.exit_code == 0, r.output
    assert "conforms to SIMPCOMP" in r.stdout
    assert not any(line.rstrip().endswith(("persis", "persistri.")) for line in lines)


@pytest.mark.parametrize("state", ["os:getcwd", "os:sep"])
def test_a_state_the_structure_cannot_use_exits_2_in_one_line(state: str) -> None:
    # A --state of another kind (a function returning a string, a string) is a set-up mistake: it made every test
    # of the suite fail with the same TypeError and exit 1, as if the structure broke its laws.
    r = CliRunner().invoke(
        main,
        ["conformance", "complex", "persistri.impl.complex.simpcomp:SimpComp", "--state", state, "--dims", "2",
         "--max-examples", "2", "--workload-size", "0", "--stateful-steps", "0"],
    )
    assert r.exit_code == 2, r.output
    assert r.stdout == ""
    (line,) = r.stderr.splitlines()
    assert line.startswith(f"persistri: --state {state}: the structure's Simplex.Vertex.new cannot make vertices from it (TypeError: ")
    assert line.endswith("give a vertex state of its VERTEX structure, or a function of no arguments returning one")


@pytest.mark.parametrize(
    "command",
    [
        ["maps", "persistri.impl.maps.red_black:red_black"],
        ["complex", "persistri.impl.complex.simpcomp:SimpComp", "--state", "persistri.impl.complex.vertex:VertexState.initial"],
    ],
)
def test_a_run_in_which_every_test_was_skipped_is_no_verdict(command: list[str]) -> None:
    # `--test growth --workload-size 0` skipped the one test it ran and printed "conforms ...: 0 passed", exit 0:
    # a verdict no structure could fail.
    r = CliRunner().invoke(main, ["conformance", *command, "--test", "growth", "--workload-size", "0", "--max-examples", "1"])
    assert r.exit_code == 2, r.output
    assert r.stdout == ""
    assert r.stderr.splitlines()[-1] == (
        f"persistri: {command[1]}: nothing was checked, every selected test was skipped (growth: workload_size = 0)"
    )
    other = "empty" if command[0] == "maps" else "new"
    ran = CliRunner().invoke(main, ["conformance", *command[:2], "--test", "growth", "--test", other, "--workload-size", "0",
                                    "--max-examples", "1", *command[2:]])
    assert ran.exit_code == 0 and "1 passed, 0 failed, 1 skipped" in ran.stdout, ran.output
