"""Presenting a map benchmark (:class:`~persistri.impl.bench.maps.MapBench`): rich tables, plain text, a bar chart.

``persistri bench maps`` prints with :func:`print_maps`; ``persistri demo`` also
writes :func:`maps_text` and :func:`save_maps_chart` to files.
"""

from __future__ import annotations

import io
from pathlib import Path

from rich.console import Console, Group, RenderableType
from rich.table import Table
from rich.text import Text

from persistri.impl.bench.maps import ADAPTED, OPERATIONS, MapBench
from persistri.impl.cli.console import text_console

__all__ = ["adapter_table", "maps_notes", "maps_report", "maps_table", "maps_text", "print_maps", "save_maps_chart"]


def _fmt_us(us: float | None) -> str:
    if us is None:
        return "—"
    if us >= 100:
        return f"{us:,.0f}"
    if us >= 10:
        return f"{us:.1f}"
    return f"{us:.2f}" if us >= 1 else f"{us:.3f}"


def _fmt_ratio(r: float | None) -> str:
    if r is None:
        return "—"
    return f"{r:,.0f}×" if r >= 100 else f"{r:.1f}×" if r >= 10 else f"{r:.2f}×"


_STYLE = {"baseline": "bold", "persistri": "cyan", "adapter": "magenta", "peer": "green"}
_SHORT_NOTE = {"skipped": "skipped ¹", "unavailable": "unavailable ¹", "error": "ERROR ¹"}


def maps_table(bench: MapBench) -> Table:
    """The benchmark as one rich table: a section per key count, a row per map, µs/op and the ratio to ``dict``.

    A row that was not measured says so in its ``note``; :func:`maps_notes` gives the reasons.
    """
    table = Table(
        title="Persistent maps: µs per operation (lower is better)",
        caption=(
            f"best of {bench.repeat} run(s), cyclic GC off while timing, seed {bench.seed}; "
            f"×dict = time ÷ dict's time at the same n; {bench.python} on {bench.machine}"
        ),
        header_style="bold",
    )
    table.add_column("n", justify="right", no_wrap=True)
    table.add_column("map", no_wrap=True)
    table.add_column("kind", no_wrap=True)
    for op in OPERATIONS:
        table.add_column(f"{op} µs", justify="right", no_wrap=True)
        table.add_column("×dict", justify="right", no_wrap=True)
    table.add_column("note", no_wrap=True)
    for i, n in enumerate(bench.sizes):
        if i:
            table.add_section()
        for j, rec in enumerate(r for r in bench.records if r.n == n):
            cells: list[str] = [f"{n:,}" if j == 0 else "", rec.map, rec.kind]
            for op in OPERATIONS:
                cells += [_fmt_us(rec.us(op)), _fmt_ratio(rec.vs_dict(op))]
            cells.append(_SHORT_NOTE.get(rec.status, ""))
            table.add_row(*cells, style=_STYLE.get(rec.kind) if rec.status == "ok" else "dim")
    return table


def adapter_table(bench: MapBench) -> Table | None:
    """Each adapter's time divided by its library's own at the same ``n``, per operation; ``None`` if nothing to show."""
    ok = {(r.map, r.n): r for r in bench.records if r.status == "ok"}
    table = Table(title="Adapter overhead: time through ORD_MAP ÷ time of the library's own methods", header_style="bold")
    table.add_column("n", justify="right", no_wrap=True)
    table.add_column("adapter", no_wrap=True)
    table.add_column("library", no_wrap=True)
    for op in OPERATIONS:
        table.add_column(op, justify="right", no_wrap=True)
    for n in bench.sizes:
        for adapter, library in ADAPTED.items():
            mine, theirs = ok.get((adapter, n)), ok.get((library, n))
            if mine is None or theirs is None:
                continue
            ratios = []
            for op in OPERATIONS:
                a, b = mine.us(op), theirs.us(op)
                ratios.append(_fmt_ratio(a / b) if a is not None and b else "—")
            table.add_row(f"{n:,}", adapter, library, *ratios)
    return table if table.row_count else None


def maps_notes(bench: MapBench) -> str:
    """The maps measured, then ``¹`` the reason for each row that was not, one line per map and reason."""
    lines = [f"measured: {', '.join(bench.measured()) or 'none'}"]
    reasons: dict[tuple[str, str], list[int]] = {}
    for rec in bench.records:
        if rec.status != "ok":
            reasons.setdefault((rec.map, f"{rec.status}: {rec.note}"), []).append(rec.n)
    for (name, reason), ns in reasons.items():
        lines.append(f"¹ {name} at n = {', '.join(f'{n:,}' for n in ns)}: {reason}")
    return "\n".join(lines)


def maps_report(bench: MapBench) -> Group:
    """The main table, the adapter-overhead table and the notes, as one renderable."""
    parts: list[RenderableType] = [maps_table(bench)]
    adapters = adapter_table(bench)
    if adapters is not None:
        parts.append(adapters)
    parts.append(Text(maps_notes(bench)))
    return Group(*parts)


def print_maps(bench: MapBench, console: Console) -> None:
    """Print :func:`maps_report` on ``console``."""
    console.print(maps_report(bench))


def maps_text(bench: MapBench, width: int | None = None) -> str:
    """What :func:`print_maps` prints, as plain text (no colour); tables at most ``width`` columns wide
    (default: their natural width), lines never folded."""
    buffer = io.StringIO()
    print_maps(bench, text_console(buffer, width))
    return buffer.getvalue()


def save_maps_chart(bench: MapBench, path: Path) -> None:
    """A PNG bar chart of µs/op (log scale): a panel per key count, a group per operation, a bar per map.

    Only measured figures are drawn; the slot of a map measured at another size
    but not at this one says why (``skipped``, ``error``) instead of leaving a
    silent gap.  matplotlib's Agg canvas is used directly (no pyplot: no global
    state, no display needed).
    """
    from matplotlib.artist import Artist
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.transforms import blended_transform_factory

    names = bench.measured()
    kinds = {r.map: r.kind for r in bench.records}
    colours = {name: f"C{i % 10}" for i, name in enumerate(names)}
    fig = Figure(figsize=(5.0 * len(bench.sizes) + 2.0, 5.0), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, len(bench.sizes), squeeze=False, sharey=True)[0]
    width = 0.8 / max(len(names), 1)
    for ax, n in zip(axes, bench.sizes, strict=True):
        by_name = {r.map: r for r in bench.records if r.n == n}
        for i, name in enumerate(names):
            rec = by_name.get(name)
            xs = [k + (i - (len(names) - 1) / 2) * width for k in range(len(OPERATIONS))]
            if rec is None or rec.status != "ok":
                status = "not run" if rec is None else rec.status
                below = blended_transform_factory(ax.transData, ax.transAxes)  # x in data, y in the panel
                for x in xs:
                    ax.text(x, 0.02, status, transform=below, rotation=90, ha="center", va="bottom",
                            fontsize="x-small", color=colours[name])
                continue
            ys = [rec.us(op) or 0.0 for op in OPERATIONS]
            ax.bar(xs, ys, width=width, color=colours[name], label=f"{name} ({kinds[name]})")
        ax.set_yscale("log")
        ax.set_xticks(range(len(OPERATIONS)), list(OPERATIONS))
        ax.set_title(f"n = {n:,}")
        ax.grid(axis="y", which="both", alpha=0.3)
    axes[0].set_ylabel("µs per operation (log scale)")
    legend: dict[str, Artist] = {}
    for ax in axes:
        handles, labels = ax.get_legend_handles_labels()
        for handle, label in zip(handles, labels, strict=True):
            legend.setdefault(label, handle)
    if legend:
        fig.legend(list(legend.values()), list(legend), loc="outside right center", fontsize="small")
    fig.suptitle(f"Persistent maps: best of {bench.repeat} run(s), {bench.python}")
    fig.savefig(path, format="png", dpi=110)
