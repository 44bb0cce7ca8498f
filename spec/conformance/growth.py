"""What the growth workloads of both suites share: where versions are kept, how failures are pinned down.

A *growth workload* (:mod:`.ord_map_growth`, :mod:`.simpcomp_growth`) is a
fixed plan of operations, made before the structure is touched and the same on
every run: grow one structure to a size N operation by operation (the
*trunk*), keep the versions made at the :func:`checkpoints` sizes, then branch
from each kept version with a few mutations, and finally recheck every kept
version against the model it had when it was made.  Every operation is also
spot-checked as it is done — its operand before and after, its result — so a
structure that starts writing into its operand at *any* size up to N is caught
at the first operation that does it, and named with it.

Failures are pinned down by *replays* of the plan (a structure that is
deterministic answers the same way every time):

* a version found changed at a later check is replayed until the first
  operation after which it differs (:func:`first_change`, a bisection of
  O(lg N) replays), so the report names that operation;
* every failure is reproduced once more on another instance of the structure
  (:func:`~.hidden_state.second_instance`) while other objects are kept alive
  between operations (:class:`~.hidden_state.Ballast`), so that freed objects'
  ids are reused differently.  A failure that does not come back depended on
  something other than the versions and arguments (a cache keyed by ``id``,
  say): it is reported under the law ``determinism``, not as the law the first
  run happened to trip over.

Replays run only after a failure; a conforming structure pays for one run.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

__all__ = ["GrowthFailure", "checkpoints", "counted", "first_change"]


def checkpoints(n: int) -> list[int]:
    """The sizes 1, 2, 4, 8, … below ``n``, then ``n`` (empty for ``n`` < 1): where growing versions are kept.

    Geometric, so the kept versions hold fewer than 3n items in all and the
    recheck of every one of them costs O(n) — while each power of two (the
    depth of a balanced tree, a HAMT level at 32 = 2^5, 1,024 = 2^10 and
    32,768 = 2^15 entries) has a version kept just past it.
    """
    out: list[int] = []
    size = 1
    while size < n:
        out.append(size)
        size *= 2
    if n >= 1:
        out.append(n)
    return out


def counted(n: int, noun: str, plural: str | None = None) -> str:
    """``n`` with thousands separators and ``noun``, plural when ``n`` ≠ 1: ``1 item``, ``1,203 items``."""
    word = noun if n == 1 else (plural if plural is not None else noun + "s")
    return f"{n:,} {word}"


def first_change(lo: int, hi: int, changed: Callable[[int], bool]) -> int:
    """The operation index ``t`` in ``(lo, hi]`` with ``changed(t)`` and not ``changed(t - 1)``, by bisection.

    ``changed(t)`` says whether the watched version differs from its model
    after operation ``t`` (by a replay); the caller knows ``changed(lo)`` is
    false and ``changed(hi)`` true.  ``⌈lg(hi − lo)⌉`` calls of ``changed``.
    """
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if changed(mid):
            hi = mid
        else:
            lo = mid
    return hi


@dataclass(frozen=True)
class GrowthFailure:
    """A check of a growth workload that failed: the law, the operation it was checked at, what was seen.

    ``at`` is the index of the operation in the plan (the check ran while or
    right after it was done; ``-1`` for the final recheck), ``key`` says which
    check it was so that a replay can tell the *same* failure from another one,
    and ``detail`` is the report's text (its first line names the law, the
    version and the operation).
    """

    law: str
    at: int
    key: str
    detail: str
