"""What the ``SIMPCOMP`` suite runs against: the structure (checked to have every operation), how to make its
vertices, and the knobs that say how hard the suite tries."""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from itertools import combinations
from typing import Any

from persistri.spec.conformance.hidden_state import second_instance
from persistri.spec.conformance.ord_map_config import describe_missing
from persistri.spec.order import Order

__all__ = [
    "SIMPCOMP_OPERATIONS",
    "NotASimpComp",
    "SimpCompSuiteConfig",
    "as_simpcomp",
    "missing_simpcomp_operations",
    "vertex_pool",
    "pool_size",
    "second_config",
    "vertices_from_state",
]

SIMPCOMP_OPERATIONS: tuple[str, ...] = (
    "Simplex",
    "dim",
    "new",
    "isEmpty",
    "vertices",
    "simplices",
    "data",
    "grep",
    "find",
    "add",
    "rem",
    "update",
)
"""The values of ``signature SIMPCOMP``, in the signature's order (``Simplex`` is a structure)."""

_SIMPLEX_OPERATIONS = ("Vertex", "compare", "dim", "vertices", "simplex", "faces", "flip", "down", "join")
_VERTEX_OPERATIONS = ("compare", "new", "loc")


def missing_simpcomp_operations(obj: object) -> list[str]:
    """The operations of ``SIMPCOMP`` (and of its ``Simplex`` and ``Simplex.Vertex``) that ``obj`` lacks or
    has as non-callables, in signature order, named by their path (``Simplex.faces``, ``Simplex.Vertex.new``).

    An empty list means every operation is there (not that they are right).
    """
    missing: list[str] = []

    def walk(o: object, names: Sequence[str], prefix: str, subs: dict[str, tuple[Sequence[str], dict[str, Any]]]) -> None:
        for name in names:
            try:
                attr = getattr(o, name)
            except Exception:  # a missing attribute, or a property that raises: either way unusable
                missing.append(prefix + name)
                continue
            if name in subs:
                sub_names, sub_subs = subs[name]
                walk(attr, sub_names, f"{prefix}{name}.", sub_subs)
            elif not callable(attr):
                missing.append(prefix + name)

    vertex: dict[str, tuple[Sequence[str], dict[str, Any]]] = {"Vertex": (_VERTEX_OPERATIONS, {})}
    walk(obj, SIMPCOMP_OPERATIONS, "", {"Simplex": (_SIMPLEX_OPERATIONS, vertex)})
    return missing


class NotASimpComp(TypeError):
    """The object given as a structure is not a ``SIMPCOMP`` structure (it lacks operations)."""


def as_simpcomp(obj: object, name: str | None = None) -> Any:
    """``obj`` as a structure: a class is instantiated with no arguments; raises :class:`NotASimpComp`
    naming the missing operations (``name`` is how messages call ``obj``)."""
    label = name if name is not None else repr(obj)
    if isinstance(obj, type):
        try:
            obj = obj()
        except TypeError as exc:  # the call's arguments
            raise NotASimpComp(f"{label} is a class that cannot be instantiated with no arguments: {exc}") from None
        except Exception as exc:
            raise NotASimpComp(
                f"{label}() raised {type(exc).__name__}: {exc} (a structure class is instantiated with no arguments)"
            ) from None
    missing = missing_simpcomp_operations(obj)
    if missing:
        raise NotASimpComp(f"{label} is not a SIMPCOMP structure: {describe_missing(obj, missing)}")
    return obj


def vertices_from_state(structure: Any, state: Any) -> Callable[[int], list[Any]]:
    """``make_vertices(k)``: ``k`` vertices made by ``structure.Simplex.Vertex.new`` from ``state`` (or from
    ``state()`` when ``state`` is a function of no arguments), at the points 0 … k−1."""
    V = structure.Simplex.Vertex

    def make(k: int) -> list[Any]:
        s = state() if callable(state) else state
        out = []
        for i in range(k):
            s, v = V.new(s, i)
            out.append(v)
        return out

    return make


@dataclass(frozen=True)
class SimpCompSuiteConfig:
    """What the suite runs against and how hard.

    ``structure`` — the structure under test; ``vertices(k)`` — k distinct
    fresh vertices of the structure; ``state`` — a vertex state (or a function
    returning one) for the ``VERTEX`` laws of ``new`` (None skips them);
    ``dims`` — the dimensions n of the complexes tested; ``check`` — call the
    structure's ``check(c)`` or ``_check(c)`` on every version; ``stateful_steps``
    — steps per stateful example; ``workload_size`` — subdivisions in the workload,
    and a tenth of the n-simplices the growth workload grows to (0 skips both);
    ``fresh`` — how to make a second instance of the structure (the class the
    user gave, or :func:`~.hidden_state.snapshots` of the instance; ``None``:
    none can be made), for the ``isolation`` test and the replays that confirm
    a failure.
    """

    structure: Any
    vertices: Callable[[int], Sequence[Any]]
    state: Any = None
    dims: tuple[int, ...] = (2,)
    check: bool = True
    stateful_steps: int = 25
    workload_size: int = 300
    fresh: Callable[[], Any] | None = None

    def __post_init__(self) -> None:
        if not self.dims or any(isinstance(n, bool) or not isinstance(n, int) or n < 1 for n in self.dims):
            raise ValueError(f"dims must be a non-empty tuple of positive ints, got {self.dims!r}")
        for knob in ("stateful_steps", "workload_size"):
            value = getattr(self, knob)
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise ValueError(f"{knob} must be a non-negative int, got {value!r}")
        if not callable(self.vertices):
            raise TypeError(f"vertices must be a function k -> k vertices, got {type(self.vertices).__name__}")

    @property
    def checker(self) -> Callable[[Any], object] | None:
        """The structure's representation check (``check``, else ``_check``), or None when off or absent."""
        if not self.check:
            return None
        for name in ("check", "_check"):
            fn: Callable[[Any], object] | None = getattr(self.structure, name, None)
            if callable(fn):
                return fn
        return None


# -- shared machinery ----------------------------------------------------------------------


def pool_size(n: int) -> int:
    """How many vertices the complexes of dimension n are built on: n + 4 (C(n+4, n+1) simplices to choose from)."""
    return n + 4


def vertex_pool(cfg: SimpCompSuiteConfig, k: int) -> list[Any]:
    """``k`` vertices from the configuration, checked to be distinct and hashable (a harness error otherwise)."""
    vs = list(cfg.vertices(k))
    if len(vs) != k:
        raise ValueError(f"make_vertices({k}) returned {len(vs)} vertices")
    try:
        distinct = len(set(vs)) == k
    except TypeError as exc:
        raise TypeError(f"the suite needs hashable vertices: {exc}") from None
    cmp = cfg.structure.Simplex.Vertex.compare
    if k <= 64:
        equal = any(cmp(a, b) is Order.EQUAL for a, b in combinations(vs, 2))
    else:  # the growth workload's thousands of vertices: neighbours in compare's order (a total order: law compare_total)
        ordered = sorted(vs, key=functools.cmp_to_key(lambda a, b: int(cmp(a, b).value)))
        equal = any(cmp(a, b) is Order.EQUAL for a, b in zip(ordered, ordered[1:]))
    if not distinct or equal:
        raise ValueError(f"make_vertices({k}) returned vertices that are not distinct: {vs[:12]!r}")
    return vs


def second_config(cfg: SimpCompSuiteConfig, wrap: Callable[[Any], Any] = lambda s: s) -> tuple[SimpCompSuiteConfig | None, str]:
    """``cfg`` with ``wrap`` of a second instance of its structure (:func:`~.hidden_state.second_instance`),
    and how it was made; ``(None, why not)`` when none can be made.  Vertices are made as before."""
    other, how = second_instance(cfg.structure, cfg.fresh)
    return (None if other is None else dataclasses.replace(cfg, structure=wrap(other))), how
