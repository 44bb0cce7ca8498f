"""What every experiment writes: a CSV of its records, a PNG of its figure, and a "paper vs ours" table.

Each figure of the paper's §4–§5 that ``persistri experiments`` regenerates
leaves three files in the output directory:

* ``figN.csv`` — one row per measured record (:func:`write_csv`), the raw numbers;
* ``figN.png`` — the figure, drawn with matplotlib's Agg canvas (:func:`new_figure`,
  :func:`save_png`; no display and no global ``pyplot`` state is touched);
* ``figN.md`` — a Markdown page (:func:`write_markdown`): how the run was made,
  the paper's reported claim next to ours for each claim (:class:`Comparison`),
  with the difference explained where they differ, then the data.

The paper's figures did not survive in the text we have: what it "reports" is
what its prose and captions say, plus the scale its axis labels show.
"""

from __future__ import annotations

import csv
import dataclasses
import json
import math
import platform
import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Final, Literal, TypeVar

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = [
    "Progress",
    "Verdict",
    "Comparison",
    "RunInfo",
    "Written",
    "figure_paths",
    "write_csv",
    "read_records",
    "new_figure",
    "save_png",
    "markdown_table",
    "write_markdown",
    "write_run_info",
    "read_run_info",
    "millions",
    "size_label",
    "parse_size",
    "parse_sizes",
]

Progress = Callable[[int, int, str], None]
"""A progress callback: ``(units done, units in all, what runs now)``; each figure states its unit."""

Verdict = Literal["agrees", "differs", "partly", "not comparable"]

VERDICTS: Final[tuple[Verdict, ...]] = ("agrees", "differs", "partly", "not comparable")


@dataclass(frozen=True, slots=True)
class Comparison:
    """One claim of the paper, what it reports, what we measured, and why they differ when they do."""

    claim: str
    paper: str
    ours: str
    verdict: Verdict
    why: str = ""

    def __post_init__(self) -> None:
        if self.verdict not in VERDICTS:
            raise ValueError(f"verdict must be one of {', '.join(VERDICTS)}, got {self.verdict!r}")
        if self.verdict != "agrees" and not self.why:
            raise ValueError(f"a comparison that {self.verdict!r} must say why ({self.claim!r})")


@dataclass(frozen=True, slots=True)
class RunInfo:
    """How a figure was produced: its parameters (shown as a list), its time, and the machine."""

    parameters: Mapping[str, str]
    wall_seconds: float
    cpu_seconds: float
    python: str = field(default_factory=lambda: f"Python {sys.version.split()[0]}")
    machine: str = field(default_factory=lambda: f"{platform.machine()} {platform.system()}")


@dataclass(frozen=True, slots=True)
class Written:
    """The three files one figure wrote."""

    csv: Path
    png: Path
    md: Path


def figure_paths(out: Path, name: str) -> Written:
    """``out/name.csv``, ``out/name.png`` and ``out/name.md`` (the directory is made if missing)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    return Written(out / f"{name}.csv", out / f"{name}.png", out / f"{name}.md")


def write_csv(path: Path, rows: Sequence[Mapping[str, object]]) -> Path:
    """Write ``rows`` (dictionaries with the same keys, in the same order) as CSV with a header; returns ``path``.

    Floats are written with ``repr`` precision (round-trips), ``None`` as an empty cell.
    ValueError if the rows are empty or their keys differ.
    """
    if not rows:
        raise ValueError(f"{path.name}: no records to write")
    header = list(rows[0].keys())
    for k, row in enumerate(rows):
        if list(row.keys()) != header:
            raise ValueError(f"{path.name}: record {k} has fields {list(row.keys())}, expected {header}")
    with path.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for row in rows:
            w.writerow(["" if v is None else repr(v) if isinstance(v, float) else v for v in row.values()])
    return path


R = TypeVar("R")


def read_records(path: Path, cls: type[R]) -> list[R]:
    """The records of ``cls`` (a dataclass of ``int``, ``float``, ``str`` and ``float | None`` fields) from a CSV
    written by :func:`write_csv`; columns that are not fields (derived values) are ignored.

    ValueError names the file and the first problem (a missing column, a value that does not parse).
    """
    if not dataclasses.is_dataclass(cls):
        raise TypeError(f"read_records: {cls!r} is not a dataclass")
    fields = dataclasses.fields(cls)
    with path.open(newline="") as fh:
        reader = csv.DictReader(fh)
        header = reader.fieldnames or []
        missing = [f.name for f in fields if f.name not in header]
        if missing:
            raise ValueError(f"{path}: missing columns {', '.join(missing)}")
        out: list[R] = []
        for k, row in enumerate(reader, start=2):
            values: dict[str, object] = {}
            for f in fields:
                text = row[f.name]
                kind = str(f.type)
                try:
                    if kind == "int":
                        values[f.name] = int(text)
                    elif kind == "float":
                        values[f.name] = float(text)
                    elif kind.startswith("float") and "None" in kind:
                        values[f.name] = None if text == "" else float(text)
                    else:
                        values[f.name] = text
                except ValueError:
                    raise ValueError(f"{path}, line {k}: {f.name} = {text!r} is not a {kind}") from None
            out.append(cls(**values))
    return out


def new_figure(width: float = 7.0, height: float = 4.5) -> tuple[Figure, Axes]:
    """A matplotlib figure on an Agg canvas and its one axes (no ``pyplot``: no display, no global state)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    return fig, ax


def save_png(fig: Figure, path: Path, dpi: int = 110) -> Path:
    """Write ``fig`` to ``path`` as PNG; returns ``path``."""
    fig.savefig(path, dpi=dpi, format="png")
    return path


def _cell(text: str) -> str:
    """A Markdown table cell: pipes escaped, line breaks flattened."""
    return text.replace("|", "\\|").replace("\n", " ")


def markdown_table(headers: Sequence[str], rows: Sequence[Sequence[str]], align: str | None = None) -> str:
    """A GitHub-flavoured Markdown table; ``align`` is one letter per column (``l``/``r``), default left."""
    if align is not None and len(align) != len(headers):
        raise ValueError(f"align has {len(align)} letters for {len(headers)} columns")
    marks = ["---:" if (align or "l" * len(headers))[i] == "r" else "---" for i in range(len(headers))]
    lines = ["| " + " | ".join(_cell(h) for h in headers) + " |", "| " + " | ".join(marks) + " |"]
    for row in rows:
        if len(row) != len(headers):
            raise ValueError(f"a row has {len(row)} cells for {len(headers)} columns")
        lines.append("| " + " | ".join(_cell(c) for c in row) + " |")
    return "\n".join(lines)


def _duration(seconds: float) -> str:
    if seconds < 90:
        return f"{seconds:.1f} s"
    return f"{seconds / 60:.1f} min"


def write_markdown(
    path: Path,
    *,
    title: str,
    intro: str,
    info: RunInfo,
    comparisons: Sequence[Comparison],
    data_headers: Sequence[str],
    data_rows: Sequence[Sequence[str]],
    data_align: str | None = None,
    notes: Sequence[str] = (),
    image: str | None = None,
) -> Path:
    """Write one figure's page: title, intro, how it was run, the paper-vs-ours table, the data, notes.

    ``image`` (a file name beside the page) is linked under the intro when given.  Returns ``path``.
    """
    parts = [f"# {title}", "", intro.strip(), ""]
    if image is not None:
        parts += [f"![{title}]({image})", ""]
    run = "; ".join(f"{k}: {v}" for k, v in info.parameters.items())
    parts += [
        f"**Run:** {run}. Took {_duration(info.wall_seconds)} wall-clock "
        f"({_duration(info.cpu_seconds)} CPU) on {info.python}, {info.machine}.",
        "",
        "## The paper's report next to ours",
        "",
        markdown_table(
            ("claim", "paper", "persistri", "verdict", "why they differ"),
            [(c.claim, c.paper, c.ours, c.verdict, c.why or "—") for c in comparisons],
        ),
        "",
        "## Data",
        "",
        markdown_table(data_headers, data_rows, data_align),
        "",
    ]
    if notes:
        parts += ["## Notes", ""] + [f"- {n}" for n in notes] + [""]
    path.write_text("\n".join(parts))
    write_run_info(path.with_suffix(".json"), info)
    return path


def write_run_info(path: Path, info: RunInfo) -> Path:
    """Save ``info`` as JSON beside a figure's page (``figN.json``), so the page can be redrawn later from the
    CSV without measuring again (:func:`read_run_info`)."""
    path.write_text(json.dumps(asdict(info), indent=2, ensure_ascii=False) + "\n")
    return path


def read_run_info(path: Path) -> RunInfo:
    """The :class:`RunInfo` saved by :func:`write_run_info`; ValueError if the file is not one."""
    try:
        doc = json.loads(path.read_text())
        return RunInfo(
            {str(k): str(v) for k, v in doc["parameters"].items()},
            float(doc["wall_seconds"]),
            float(doc["cpu_seconds"]),
            str(doc["python"]),
            str(doc["machine"]),
        )
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
        raise ValueError(f"{path}: not a saved run description ({exc})") from None


def millions(x: float, digits: int = 2) -> str:
    """``x`` in millions, e.g. ``12_345_678 -> '12.35M'``."""
    return f"{x / 1e6:,.{digits}f}M"


def size_label(n: int) -> str:
    """A point count as the paper labels it: ``131072 -> '128K'``, ``1600 -> '1,600'``."""
    if n >= 1024 and n % 1024 == 0:
        return f"{n // 1024}K"
    return f"{n:,}"


def parse_size(text: str) -> int:
    """``'128K'``/``'128k'`` → 131072 (K = 1024), ``'1600'``/``'1_600'`` → 1600, ``'1e4'`` → 10000.

    ValueError names the bad text; a size is a positive integer.
    """
    t = text.strip().replace("_", "")
    scale = 1
    if t[-1:] in ("K", "k"):
        t, scale = t[:-1], 1024
    try:
        value = float(t) if ("e" in t.lower() or "." in t) else int(t)
    except ValueError:
        raise ValueError(f"{text.strip()!r} is not a size (examples: 1600, 128K, 1e4)") from None
    total = value * scale
    if not math.isfinite(total) or total != int(total) or int(total) < 1:
        raise ValueError(f"{text.strip()!r} is not a positive integer size")
    return int(total)


def parse_sizes(text: str) -> tuple[int, ...]:
    """``'128K,256K, 512K'`` → ``(131072, 262144, 524288)``: sizes separated by commas (:func:`parse_size`),
    returned sorted and without repeats.  ValueError for an empty list or a bad size."""
    items = [s for s in text.split(",") if s.strip()]
    if not items:
        raise ValueError("give at least one size")
    return tuple(sorted({parse_size(s) for s in items}))
