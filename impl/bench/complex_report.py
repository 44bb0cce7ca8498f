"""Presenting a complex benchmark (:class:`~persistri.impl.bench.complex.ComplexBench`): a rich table and notes.

``persistri bench complex`` prints with :func:`print_complex`; :func:`complex_text`
gives the same as plain text.
"""

from __future__ import annotations

import io

from rich.console import Console, Group, JustifyMethod
from rich.table import Table
from rich.text import Text

from persistri.impl.bench.complex import ComplexBench
from persistri.impl.cli.console import text_console

__all__ = ["complex_table", "complex_notes", "complex_report", "print_complex", "complex_text"]

_STYLE = {"baseline": "bold", "persistri": "cyan", "adapter": "magenta"}
_SHORT = {"skipped": "skipped ¹", "unavailable": "unavailable ¹", "error": "ERROR ¹"}


def _us(x: float | None) -> str:
    if x is None:
        return "—"
    return f"{x:,.0f}" if x >= 100 else f"{x:.1f}" if x >= 10 else f"{x:.2f}"


def _ratio(r: float | None) -> str:
    if r is None:
        return "—"
    return f"{r:,.0f}×" if r >= 100 else f"{r:.1f}×" if r >= 10 else f"{r:.2f}×"


def _secs(x: float | None) -> str:
    return "—" if x is None else f"{x:.2f}"


def complex_table(bench: ComplexBench) -> Table:
    """One row per (sphere size, complex): CPU seconds, µs per operation, and ratios to the ephemeral baseline."""
    table = Table(
        title=f"2-complex on a closed sphere ({bench.workload} workload): cost of persistence (lower is better)",
        caption=(
            f"CPU time, best of {bench.repeat} run(s), cyclic GC off while timing, seed {bench.seed}; "
            f"×eph = time ÷ the ephemeral baseline's on the same sphere; {bench.python} on {bench.machine}"
        ),
        header_style="bold",
    )
    columns: tuple[tuple[str, JustifyMethod], ...] = (
        ("triangles", "right"),
        ("complex", "left"),
        ("kind", "left"),
        ("build s", "right"),
        ("µs/op", "right"),
        ("×eph", "right"),
        ("walk s", "right"),
        ("µs/findi", "right"),
        ("×eph", "right"),
        ("total ×eph", "right"),
        ("note", "left"),
    )
    for name, justify in columns:
        table.add_column(name, justify=justify, no_wrap=True)
    for i, t in enumerate(bench.sizes):
        if i:
            table.add_section()
        for j, r in enumerate(x for x in bench.records if x.triangles == t):
            table.add_row(
                f"{t:,}" if j == 0 else "",
                r.complex,
                r.kind,
                _secs(r.build_s),
                _us(r.build_us),
                _ratio(r.build_vs_ephemeral),
                _secs(r.walk_s),
                _us(r.walk_us),
                _ratio(r.walk_vs_ephemeral),
                _ratio(r.total_vs_ephemeral),
                _SHORT.get(r.status, ""),
                style=_STYLE.get(r.kind) if r.status == "ok" else "dim",
            )
    return table


def complex_notes(bench: ComplexBench) -> str:
    """The workload of each size, the growth of each complex measured at two sizes or more, and ``¹`` reasons."""
    lines = []
    for t, counts in bench.operations:
        mix = ", ".join(f"{name} {n:,}" for name, n in counts.items())
        lines.append(f"{t:,} triangles: {sum(counts.values()):,} operations replayed ({mix}); walk: {3 * t:,} findi")
    for name, (t1, t2, alpha) in bench.growth_notes().items():
        lines.append(
            f"{name}: cost per replayed operation grows as T^{alpha:.2f} from {t1:,} to {t2:,} triangles "
            "(O(V) per map operation predicts T^1)"
        )
    reasons: dict[tuple[str, str], list[int]] = {}
    for r in bench.records:
        if r.status != "ok":
            reasons.setdefault((r.complex, f"{r.status}: {r.note}"), []).append(r.triangles)
    for (name, reason), ts in reasons.items():
        lines.append(f"¹ {name} at {', '.join(f'{t:,}' for t in ts)} triangles: {reason}")
    return "\n".join(lines)


def complex_report(bench: ComplexBench) -> Group:
    """The table and the notes, as one renderable."""
    return Group(complex_table(bench), Text(complex_notes(bench)))


def print_complex(bench: ComplexBench, console: Console) -> None:
    """Print :func:`complex_report` on ``console``."""
    console.print(complex_report(bench))


def complex_text(bench: ComplexBench, width: int | None = None) -> str:
    """What :func:`print_complex` prints, as plain text (no colour); tables at most ``width`` columns wide
    (default: their natural width), lines never folded."""
    buffer = io.StringIO()
    print_complex(bench, text_console(buffer, width))
    return buffer.getvalue()
