"""``check=True`` catches a bulldozer that goes wrong: faults injected into its geometric kernel or its lists.

Each fault is switched on after the first insertions (so the first hull is
right) and must make ``convex_hull(..., check=True)`` raise
:class:`BulldozerCheckError` naming the theorem that failed — never pass
silently and never fail only later in the final verification.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import pytest

from persistri.impl.geometry.kernel import Indices, Orient3dKernel
from persistri.impl.geometry.kernel_split import composed_split
from persistri.impl.geometry.predicates import Predicates3
from persistri.impl.hull import bulldozer
from persistri.impl.hull.api import convex_hull
from persistri.impl.hull.bulldozer import BulldozerCheckError
from persistri.impl.hull.distributions import generate

POINTS = generate("OnSphere", 300, seed=4)


def _faulty_kernel(inner: Orient3dKernel, what: str, wrap: Callable[[Any], Any], after: int) -> Orient3dKernel:
    """``inner`` with its ``orient3d`` or ``partition`` replaced by ``wrap(original)`` once ``after`` calls were made.

    A faulty ``partition`` is also the kernel's ``split`` (the routing and tent tests in one pass), as the
    partitions it stands for: every plane-side split of a list goes through the fault."""
    original = getattr(inner, what)
    faulty = wrap(original)
    calls = [0]

    def switch(*args: Any) -> Any:
        calls[0] += 1
        return (faulty if calls[0] > after else original)(*args)

    setattr(inner, what, switch)
    if what == "partition":
        inner.split = composed_split(switch)
    return inner


@contextmanager
def faulty(monkeypatch: pytest.MonkeyPatch, what: str, wrap: Callable[[Any], Any], after: int = 400) -> Iterator[None]:
    real = Predicates3.kernel
    monkeypatch.setattr(Predicates3, "kernel", lambda self: _faulty_kernel(real(self), what, wrap, after))
    yield
    monkeypatch.setattr(Predicates3, "kernel", real)


def test_the_unfaulted_run_passes() -> None:
    assert convex_hull(POINTS, check=True, seed=1).vertices.size == 300


def test_a_lost_point_is_caught(monkeypatch: pytest.MonkeyPatch) -> None:
    """A partition that forgets one point of the side that sees the plane: Theorem 6 (or 7) fails."""

    def lose(part: Callable[..., tuple[Indices, Indices]]) -> Callable[..., tuple[Indices, Indices]]:
        def run(a: int, b: int, c: int, qs: Indices) -> tuple[Indices, Indices]:
            minus, plus = part(a, b, c, qs)
            return (list(minus)[1:], plus) if len(minus) > 1 else (minus, plus)

        return run

    with faulty(monkeypatch, "partition", lose), pytest.raises(BulldozerCheckError, match="Theorem [67]|partition|sectors"):
        convex_hull(POINTS, check=True, seed=1)


def test_points_sent_the_wrong_way_are_caught(monkeypatch: pytest.MonkeyPatch) -> None:
    """A partition with its two sides swapped routes points across the wrong edges and keeps interior points."""

    def swap(part: Callable[..., tuple[Indices, Indices]]) -> Callable[..., tuple[Indices, Indices]]:
        def run(a: int, b: int, c: int, qs: Indices) -> tuple[Indices, Indices]:
            minus, plus = part(a, b, c, qs)
            return plus, minus

        return run

    with faulty(monkeypatch, "partition", swap), pytest.raises(BulldozerCheckError):
        convex_hull(POINTS, check=True, seed=1)


def test_a_wrong_visibility_is_caught(monkeypatch: pytest.MonkeyPatch) -> None:
    """An orient3d that calls every face invisible: the walk misses visible faces (Lemma 9) or breaks the graph."""

    def blind(o3: Callable[..., int]) -> Callable[..., int]:
        return lambda a, b, c, d: 1

    with faulty(monkeypatch, "orient3d", blind), pytest.raises(BulldozerCheckError):
        convex_hull(POINTS, check=True, seed=1)


def test_a_reversed_arc_is_caught(monkeypatch: pytest.MonkeyPatch) -> None:
    """An orient3d with the sign of every test through the centre flipped: arcs reverse and the walk breaks."""

    def reverse(o3: Callable[..., int]) -> Callable[..., int]:
        centre = len(POINTS)  # the centre's index: after the input points (no duplicates here)
        return lambda a, b, c, d: -o3(a, b, c, d) if centre in (a, b, c, d) else o3(a, b, c, d)

    with faulty(monkeypatch, "orient3d", reverse), pytest.raises(BulldozerCheckError):
        convex_hull(POINTS, check=True, seed=1)


def test_the_module_exports_its_check_error() -> None:
    assert bulldozer.BulldozerCheckError is BulldozerCheckError
