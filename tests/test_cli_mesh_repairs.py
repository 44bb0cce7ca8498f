"""``persistri mesh`` says what reading the domain repaired: merged duplicate vertices and segments, split segments.

The API keeps them in ``PSLG.notes``; the command printed none of them, so a .poly with a
duplicate vertex meshed silently.  One ``persistri: note:`` line each on stderr (five at
most, then a count), rows said to count from 0 where the file numbers from 1; none with --quiet.
"""

from __future__ import annotations

from pathlib import Path

from cli_contract import invoke

SQUARE_SEGMENTS = "1 1 2\n2 2 3\n3 3 4\n4 4 1\n"


def _notes(stderr: str) -> list[str]:
    return [ln for ln in stderr.splitlines() if ln.startswith("persistri: note: ")]


def test_a_duplicate_vertex_and_segment_are_reported(tmp_path: Path) -> None:
    path = tmp_path / "dup.poly"
    path.write_text("5 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n5 1 0\n5 0\n" + SQUARE_SEGMENTS + "5 5 3\n0\n")
    result, _ = invoke(["mesh", str(path), "-o", str(tmp_path / "m.npz")])
    assert result.exit_code == 0, result.stderr
    assert _notes(result.stderr) == [
        f"persistri: note: {path}: vertices 1 and 4 are the same point (1.0, 0.0): vertex 4 merged into 1 "
        "(rows counted from 0; the file numbers from 1)",
        f"persistri: note: {path}: segment 4 (1–2) repeats segment 1 (1–2): merged (rows counted from 0; the file numbers from 1)",
    ]
    quiet, _ = invoke(["mesh", str(path), "-o", str(tmp_path / "m.npz"), "--quiet"])
    assert quiet.exit_code == 0 and not _notes(quiet.stderr), quiet.stderr


def test_a_file_numbered_from_0_needs_no_translation(tmp_path: Path) -> None:
    path = tmp_path / "split.poly"
    path.write_text("5 2 0 0\n0 0 0\n1 1 0\n2 1 1\n3 0 1\n4 0.5 0\n4 0\n0 0 1\n1 1 2\n2 2 3\n3 3 0\n0\n")
    result, _ = invoke(["mesh", str(path), "-o", str(tmp_path / "m.npz")])
    assert result.exit_code == 0, result.stderr
    assert _notes(result.stderr) == [f"persistri: note: {path}: vertex 4 at (0.5, 0.0) lies on the interior of segment 0 (0–1): split there"]


def test_many_repairs_are_counted_after_five(tmp_path: Path) -> None:
    path = tmp_path / "many.poly"
    extra = "".join(f"{k} 1 0\n" for k in range(5, 12))  # seven copies of vertex 2
    path.write_text("11 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n" + extra + "4 0\n" + SQUARE_SEGMENTS + "0\n")
    result, _ = invoke(["mesh", str(path), "-o", str(tmp_path / "m.npz")])
    notes = _notes(result.stderr)
    assert result.exit_code == 0 and len(notes) == 6, result.stderr
    assert notes[-1] == f"persistri: note: {path}: … and 2 more repairs (read_poly(...).notes lists them)"
