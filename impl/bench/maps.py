"""The map benchmark: persistri's persistent maps against their peers, measured in one run.

What is measured, for each key count ``n`` and each *subject* (a map):

* ``insert`` — build an ``n``-key map from empty, inserting a random
  permutation of ``range(n)`` (``k ↦ k``);
* ``find`` — look up every key of that map, in another random order;
* ``remove`` — remove every key, in a third random order, down to empty.

Each figure is a per-operation cost in microseconds: the best of ``repeat``
timed runs of the whole loop, divided by ``n``.  The loop's own overhead (about
0.02 µs per iteration) is in every figure alike.  Timing uses
:func:`time.perf_counter` with the cyclic garbage collector disabled during each
timed run and restored afterwards: persistent maps make no reference cycles, so
reference counting frees everything, and a collector pass in the middle of a
run would only add noise proportional to the live heap.  The keys and their
three orders come from a fixed seed, and every subject sees the same ones.
Each run is checked untimed (the built map has ``n`` items, the final one
none), so a benchmark of a broken map reports an error rather than a figure.

The subjects (:data:`SUBJECTS`):

=========================  ==========  ===============================================
name                       kind        what runs
=========================  ==========  ===============================================
``dict``                   baseline    Python's mutable hash table: ``d[k]=v``, ``d[k]``, ``del d[k]``
``red_black``              persistri   the ORD_MAP structure of that name
``hamt``                   persistri   the ORD_MAP structure of that name
``assoc_list``             persistri   the ORD_MAP structure of that name; O(n) per operation,
                                       so skipped above :data:`ASSOC_LIST_MAX_N` keys
``immutables``             adapter     persistri's ORD_MAP adapter over ``immutables.Map``
``pyrsistent``             adapter     persistri's ORD_MAP adapter over ``pyrsistent.pmap``
``immutables.Map``         peer        the C HAMT itself: ``.set``, ``.get``, ``.delete``
``immutables.map.Map``     peer        immutables' pure-Python HAMT: ``.set``, ``.get``, ``.delete``
``pyrsistent.pmap``        peer        pyrsistent's map itself: ``.set``, ``.get``, ``.remove``
=========================  ==========  ===============================================

An adapter next to its library shows the adapter's overhead (the ORD_MAP
calling convention, the option tuple ``find`` returns, the key check).  Every
figure also appears as a ratio to ``dict``'s for the same ``n`` and operation.
A subject whose module cannot be imported (a backend not written yet, a
library not installed) is reported as ``unavailable`` with the reason, and the
others are still measured.

Run it with ``persistri bench maps``; this module is the measuring half and
returns records (:class:`MapBench`), the command prints them.
"""

from __future__ import annotations

import dataclasses
import gc
import math
import platform
import random
import time
from collections.abc import Callable, Collection, Iterable, Sequence
from dataclasses import dataclass
from typing import Any, Final, Literal, TypeVar

from persistri.impl.bench.maps_subjects import ADAPTED, ASSOC_LIST_MAX_N, SUBJECTS, Driver, Kind, MapSubject

__all__ = [
    "ADAPTED",
    "ASSOC_LIST_MAX_N",
    "DEFAULT_REPEAT",
    "DEFAULT_SEED",
    "DEFAULT_SIZES",
    "OPERATIONS",
    "RECORD_FIELDS",
    "SUBJECTS",
    "Kind",
    "MapBench",
    "MapBenchError",
    "MapBenchRecord",
    "MapSubject",
    "ProgressCallback",
    "Status",
    "run_map_bench",
]

Status = Literal["ok", "skipped", "unavailable", "error"]
"""Whether a subject was measured at a size (``ok``) and, if not, why not."""

OPERATIONS: Final = ("insert", "find", "remove")
"""The three measured operations, in table order."""

DEFAULT_SIZES: Final = (1_000, 100_000, 1_000_000)
"""Key counts measured by default."""

DEFAULT_REPEAT: Final = 3
"""Timed runs per figure by default (the best is kept)."""

DEFAULT_SEED: Final = 2001
"""Seed of the key orders (the paper's year)."""

ProgressCallback = Callable[[int, int, str], None]
"""``(steps done, steps in all, what runs next)``: called before each measurement and once at the end."""


class MapBenchError(RuntimeError):
    """A map gave a wrong result during the benchmark (its figures would be meaningless)."""


@dataclass(frozen=True, slots=True)
class MapBenchRecord:
    """The figures of one subject at one key count (µs per operation; ``None`` when not measured)."""

    map: str
    """The subject's name (:data:`SUBJECTS`)."""
    kind: Kind
    description: str
    n: int
    """The number of keys."""
    status: Status
    insert_us: float | None
    find_us: float | None
    remove_us: float | None
    insert_vs_dict: float | None
    """``insert_us`` divided by ``dict``'s at the same ``n``."""
    find_vs_dict: float | None
    remove_vs_dict: float | None
    note: str
    """Why a subject was skipped or unavailable, or what it is compared with; empty when nothing to say."""

    def us(self, op: str) -> float | None:
        """The µs per operation of ``op`` (one of :data:`OPERATIONS`)."""
        value: float | None = getattr(self, f"{_op(op)}_us")
        return value

    def vs_dict(self, op: str) -> float | None:
        """The ratio of ``op``'s cost to ``dict``'s at the same ``n``."""
        value: float | None = getattr(self, f"{_op(op)}_vs_dict")
        return value

    def as_dict(self) -> dict[str, Any]:
        """The record as a JSON-ready dictionary (:data:`RECORD_FIELDS` are its keys)."""
        return dataclasses.asdict(self)


RECORD_FIELDS: Final = tuple(f.name for f in dataclasses.fields(MapBenchRecord))
"""The fields of a :class:`MapBenchRecord`, in order: the columns of the JSON output."""


@dataclass(frozen=True, slots=True)
class MapBench:
    """A finished benchmark: its parameters, the machine, and one record per (size, subject)."""

    sizes: tuple[int, ...]
    repeat: int
    seed: int
    python: str
    """Interpreter and version, e.g. ``CPython 3.11.2``."""
    machine: str
    records: tuple[MapBenchRecord, ...]

    def measured(self) -> list[str]:
        """Names of the subjects measured at one size at least, in table order."""
        return _names(r for r in self.records if r.status == "ok")

    def unavailable(self) -> list[str]:
        """Names of the subjects that could not be loaded."""
        return _names(r for r in self.records if r.status == "unavailable")

    def errors(self) -> list[MapBenchRecord]:
        """The records of subjects that failed while being measured."""
        return [r for r in self.records if r.status == "error"]

    def as_dict(self) -> dict[str, Any]:
        """The whole benchmark as a JSON-ready dictionary; ``records`` is a list of :meth:`MapBenchRecord.as_dict`."""
        return {
            "benchmark": "maps",
            "unit": "microseconds per operation (best of repeat runs)",
            "sizes": list(self.sizes),
            "repeat": self.repeat,
            "seed": self.seed,
            "python": self.python,
            "machine": self.machine,
            "records": [r.as_dict() for r in self.records],
        }


def _names(records: Iterable[MapBenchRecord]) -> list[str]:
    seen: dict[str, None] = {}
    for r in records:
        seen[r.map] = None
    return list(seen)


def _op(op: str) -> str:
    if op not in OPERATIONS:
        raise ValueError(f"unknown operation {op!r}; operations: {', '.join(OPERATIONS)}")
    return op


_BASELINE: Final = "dict"


# -- timing ----------------------------------------------------------------------------

P = TypeVar("P")
R = TypeVar("R")


def _best_seconds(repeat: int, prepare: Callable[[], P], run: Callable[[P], R], check: Callable[[R], None]) -> float:
    """The least wall-clock time of ``repeat`` calls ``run(prepare())``, the cyclic GC off while timing.

    ``prepare`` and ``check`` run untimed, before and after each timed call.
    """
    best = math.inf
    for _ in range(repeat):
        arg = prepare()
        gc_was_enabled = gc.isenabled()
        gc.disable()
        try:
            start = time.perf_counter()
            result = run(arg)
            elapsed = time.perf_counter() - start
        finally:
            if gc_was_enabled:
                gc.enable()
        check(result)
        # Dropping a large map takes time too: do it here, untimed.
        del result, arg
        best = min(best, elapsed)
    return best


def _measure(driver: Driver, keys: _Keys, repeat: int, name: str) -> tuple[float, float, float]:
    """Seconds (best of ``repeat``) of the three loops of ``driver`` over ``keys``."""
    n = len(keys.insert)

    def check_size(expected: int, what: str) -> Callable[[Any], None]:
        def check(m: Any) -> None:
            got = driver.size(m)
            if got != expected:
                raise MapBenchError(f"{name}: {what} left {got} items, expected {expected}")

        return check

    t_insert = _best_seconds(repeat, lambda: keys.insert, driver.insert_all, check_size(n, f"inserting {n} keys"))
    built = driver.insert_all(keys.insert)
    check_size(n, f"inserting {n} keys")(built)

    def find(m: Any) -> Any:
        driver.find_all(m, keys.find)
        return m

    t_find = _best_seconds(repeat, lambda: built, find, check_size(n, "finding every key"))
    t_remove = _best_seconds(
        repeat,
        lambda: driver.for_removal(built),
        lambda m: driver.remove_all(m, keys.remove),
        check_size(0, f"removing {n} keys"),
    )
    # Persistence: removing every key from the built map must have left it whole.
    check_size(n, "removing from the built map (persistence)")(built)
    return t_insert, t_find, t_remove


@dataclass(frozen=True, slots=True)
class _Keys:
    insert: list[int]
    find: list[int]
    remove: list[int]


def _keys(n: int, seed: int) -> _Keys:
    """Three independent random permutations of ``range(n)``, from ``seed`` and ``n`` only."""
    rng = random.Random(f"persistri-bench-maps:{seed}:{n}")
    orders = []
    for _ in range(3):
        order = list(range(n))
        rng.shuffle(order)
        orders.append(order)
    return _Keys(*orders)


# -- the benchmark -----------------------------------------------------------------------


def _subjects(only: Collection[str] | None) -> list[MapSubject]:
    if only is None:
        return list(SUBJECTS)
    known = {s.name for s in SUBJECTS}
    unknown = sorted(set(only) - known)
    if unknown:
        raise ValueError(f"unknown map(s) {', '.join(map(repr, unknown))}; known: {', '.join(s.name for s in SUBJECTS)}")
    # The baseline always runs: every ratio is to it.
    return [s for s in SUBJECTS if s.name in only or s.name == _BASELINE]


def _validate(sizes: Sequence[int], repeat: int) -> tuple[int, ...]:
    if not sizes:
        raise ValueError("sizes: give at least one key count")
    for n in sizes:
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise ValueError(f"sizes: key counts are positive integers, got {n!r}")
    if isinstance(repeat, bool) or not isinstance(repeat, int) or repeat < 1:
        raise ValueError(f"repeat: a positive integer, got {repeat!r}")
    return tuple(sizes)


def run_map_bench(
    sizes: Sequence[int] = DEFAULT_SIZES,
    *,
    repeat: int = DEFAULT_REPEAT,
    seed: int = DEFAULT_SEED,
    only: Collection[str] | None = None,
    assoc_list_max_n: int | None = None,
    on_progress: ProgressCallback | None = None,
) -> MapBench:
    """Measure every subject (or those named in ``only``, plus ``dict``) at every size; see the module docstring.

    ``assoc_list_max_n`` overrides :data:`ASSOC_LIST_MAX_N` (the tests use a small
    one to exercise skipping).  ``on_progress`` is told before each measurement.
    A subject that cannot be loaded is ``unavailable`` at every size; one that
    fails while measured (an exception, or a wrong item count) is ``error`` at
    that size with the reason in ``note``.  Time: ``3 · repeat + 1`` loops of
    ``n`` operations per subject and size; the 10⁶-key size dominates the
    default run, which took 20 CPU-minutes (43 minutes on a loaded 2-core machine).
    """
    sizes_t = _validate(sizes, repeat)
    subjects = _subjects(only)
    drivers: dict[str, Driver | str] = {}
    for subject in subjects:
        try:
            drivers[subject.name] = subject.load()
        except Exception as exc:  # noqa: BLE001 - any failure to load makes the subject unavailable, with its reason
            drivers[subject.name] = f"not importable: {type(exc).__name__}: {exc}"

    total = len(sizes_t) * len(subjects)
    done = 0
    records: list[MapBenchRecord] = []
    for n in sorted(sizes_t):
        keys = _keys(n, seed)
        seconds: dict[str, tuple[float, float, float]] = {}
        outcome: dict[str, tuple[Status, str]] = {}
        for subject in subjects:
            if on_progress is not None:
                on_progress(done, total, f"{subject.name} n={n:,}")
            driver = drivers[subject.name]
            limit = assoc_list_max_n if subject.name == "assoc_list" and assoc_list_max_n is not None else subject.max_n
            if isinstance(driver, str):
                outcome[subject.name] = ("unavailable", driver)
            elif limit is not None and n > limit:
                outcome[subject.name] = ("skipped", subject.skip_note.format(limit=f"{limit:,}"))
            else:
                try:
                    seconds[subject.name] = _measure(driver, keys, repeat, subject.name)
                    outcome[subject.name] = ("ok", "")
                except Exception as exc:  # noqa: BLE001 - a failing subject is reported; the others still run
                    outcome[subject.name] = ("error", f"{type(exc).__name__}: {exc}")
            done += 1
        baseline = seconds.get(_BASELINE)
        for subject in subjects:
            status, note = outcome[subject.name]
            secs = seconds.get(subject.name)
            if secs is not None and subject.compare_with is not None:
                note = _overhead_note(secs, subject.compare_with, seconds.get(subject.compare_with))
            records.append(_record(subject, n, status, note, secs, baseline))
    if on_progress is not None:
        on_progress(total, total, "done")
    return MapBench(
        sizes=tuple(sorted(sizes_t)),
        repeat=repeat,
        seed=seed,
        python=f"{platform.python_implementation()} {platform.python_version()}",
        machine=f"{platform.machine()} {platform.system()}".strip(),
        records=tuple(records),
    )


def _overhead_note(secs: tuple[float, float, float], library: str, lib_secs: tuple[float, float, float] | None) -> str:
    """The adapter's cost relative to the library map it wraps, per operation."""
    if lib_secs is None:
        return f"({library} not measured: no overhead figure)"
    parts = [f"{op} ×{a / b:.2f}" for op, a, b in zip(OPERATIONS, secs, lib_secs, strict=True) if b > 0]
    return f"adapter overhead, time vs {library}: " + ", ".join(parts)


def _record(
    subject: MapSubject,
    n: int,
    status: Status,
    note: str,
    secs: tuple[float, float, float] | None,
    baseline: tuple[float, float, float] | None,
) -> MapBenchRecord:
    us: list[float | None] = [None, None, None]
    ratio: list[float | None] = [None, None, None]
    if secs is not None:
        for i in range(3):
            us[i] = secs[i] / n * 1e6
            if baseline is not None and baseline[i] > 0:
                ratio[i] = secs[i] / baseline[i]
    return MapBenchRecord(
        map=subject.name,
        kind=subject.kind,
        description=subject.description,
        n=n,
        status=status,
        insert_us=us[0],
        find_us=us[1],
        remove_us=us[2],
        insert_vs_dict=ratio[0],
        find_vs_dict=ratio[1],
        remove_vs_dict=ratio[2],
        note=note,
    )
