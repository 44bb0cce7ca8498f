"""What the ``ORD_MAP`` suite runs against: the structure (checked to have every operation) and its knobs.

:func:`missing_operations` and :func:`as_structure` say whether an object is an
``ORD_MAP`` structure at all; :class:`SuiteConfig` is the structure with the
knobs that say how hard the suite tries.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from persistri.spec.conformance.hidden_state import second_instance

__all__ = ["ORD_MAP_OPERATIONS", "NotAnOrdMap", "SuiteConfig", "as_structure", "describe_missing", "missing_operations", "second_config"]

ORD_MAP_OPERATIONS: tuple[str, ...] = (
    "Key",
    "empty",
    "isEmpty",
    "singleton",
    "insert",
    "insertWith",
    "find",
    "lookup",
    "inDomain",
    "remove",
    "numItems",
    "listItemsi",
    "listKeys",
    "foldli",
)
"""The values of ``signature ORD_MAP``, in the signature's order (``Key`` is a structure with ``compare``)."""


def missing_operations(obj: object) -> list[str]:
    """The ``ORD_MAP`` operations the structure ``obj`` lacks or has as non-callables, in signature order.

    ``Key`` is reported as ``Key.compare`` when ``Key`` exists but has no
    callable ``compare``.  ``obj`` is the structure itself (an instance, not its
    class).  An empty list means every operation is there (not that they are right).
    """
    missing: list[str] = []
    for name in ORD_MAP_OPERATIONS:
        try:
            attr = getattr(obj, name)
        except Exception:  # a missing attribute, or a property that raises: either way unusable
            missing.append(name)
            continue
        if name == "Key":
            if not callable(getattr(attr, "compare", None)):
                missing.append("Key.compare")
        elif not callable(attr):
            missing.append(name)
    return missing


class NotAnOrdMap(TypeError):
    """The object given as a structure is not an ``ORD_MAP`` structure (it lacks operations)."""


def as_structure(obj: object, name: str | None = None) -> Any:
    """``obj`` as a structure: a class is instantiated with no arguments; raises :class:`NotAnOrdMap`
    naming the missing operations (``name`` is how messages call ``obj``)."""
    label = name if name is not None else repr(obj)
    if isinstance(obj, type):
        try:
            obj = obj()
        except TypeError as exc:  # the call's arguments
            raise NotAnOrdMap(f"{label} is a class that cannot be instantiated with no arguments: {exc}") from None
        except Exception as exc:
            raise NotAnOrdMap(
                f"{label}() raised {type(exc).__name__}: {exc} (a structure class is instantiated with no arguments)"
            ) from None
    missing = missing_operations(obj)
    if missing:
        raise NotAnOrdMap(f"{label} is not an ORD_MAP structure: {describe_missing(obj, missing)}")
    return obj


def describe_missing(obj: object, paths: Sequence[str]) -> str:
    """What is wrong with the operations ``paths`` (dotted, from ``obj``) that a missing-operations check
    reported: those absent (or None) are listed as missing; one that exists but is not callable is named
    with its type, since the usual cause is an SML *value* written as a plain attribute (``empty = ...``) where the
    Python signature has a method with no arguments (``def empty(self)``).  For messages only."""
    absent: list[str] = []
    plain: list[str] = []
    for path in paths:
        attr: Any = obj
        try:
            for part in path.split("."):
                attr = getattr(attr, part)
        except Exception:
            absent.append(path)
            continue
        if attr is None:
            absent.append(path)
        else:
            plain.append(f"{path} is not callable ({type(attr).__name__})")
    parts = ([f"missing {', '.join(absent)}"] if absent else []) + plain
    text = "; ".join(parts)
    if plain:
        text += " (a value of the SML signature, such as empty, is a method with no arguments here: empty())"
    return text


@dataclass(frozen=True)
class SuiteConfig:
    """What the suite runs against and how hard.

    ``structure`` — the structure under test; ``hashing`` — also use keys whose
    hashes collide; ``workload_size`` — keys in each workload and in the growth
    workload (0 skips them); ``check`` — call the structure's ``_check(m)`` after
    each step when it has one; ``stateful_steps`` — steps per stateful example;
    ``fresh`` — how to make a second instance of the structure (the class the
    user gave, or :func:`~.hidden_state.snapshots` of the instance; ``None``:
    none can be made), for the ``isolation`` test and the replays that confirm
    a failure.
    """

    structure: Any
    hashing: bool = True
    workload_size: int = 100_000
    check: bool = True
    stateful_steps: int = 25
    fresh: Callable[[], Any] | None = None

    def __post_init__(self) -> None:
        for knob in ("workload_size", "stateful_steps"):
            value = getattr(self, knob)
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise ValueError(f"{knob} must be a non-negative int, got {value!r}")


def second_config(cfg: SuiteConfig, wrap: Callable[[Any], Any] = lambda s: s) -> tuple[SuiteConfig | None, str]:
    """``cfg`` with ``wrap`` of a second instance of its structure (:func:`~.hidden_state.second_instance`),
    and how it was made; ``(None, why not)`` when none can be made."""
    other, how = second_instance(cfg.structure, cfg.fresh)
    return (None if other is None else dataclasses.replace(cfg, structure=wrap(other))), how
