"""A branching history of ``ORD_MAP`` versions, each with its model snapshot (the suite's model machinery).

:class:`History` applies each operation to a chosen version — old ones too,
so the history branches ("multiple futures") — checks it by that operation's
laws, and appends the result with a ``dict`` snapshot of what it must hold;
:meth:`History.check_all` applies the persistence law to every version made.
The random programs and the state machine of :mod:`.ord_map_stateful` drive it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from persistri.spec.conformance.ord_map_config import SuiteConfig
from persistri.spec.conformance.strategies import CollidingKey, KeyKind
from persistri.spec.ord_map_laws import (
    law_empty,
    law_find_insert,
    law_find_insert_other,
    law_foldli,
    law_inDomain,
    law_insertWith,
    law_invariants,
    law_isEmpty,
    law_listItemsi,
    law_listKeys,
    law_lookup,
    law_numItems_insert,
    law_persistence,
    law_remove,
    law_remove_absent,
)

__all__ = ["History", "back", "combine", "extra_probes"]

def combine(old: Any, new: Any) -> Any:
    """The ``insertWith`` function the suite uses: not commutative, so argument order shows."""
    return (old, new)


def extra_probes(kind: KeyKind) -> list[Any]:
    """Two keys outside the generated range (below and above it) to look up in every version."""
    ints = [-(10**6), 10**6]
    return ints if kind == "int" else [CollidingKey(i) for i in ints]


def back(n: int, at: int) -> int:
    """Index of the version ``at`` steps before the latest of ``n`` (wrapping): shrinks to the latest."""
    return n - 1 - at % n


@dataclass
class History:
    """Every version made so far with its model snapshot.

    Each operation is applied to a chosen (possibly old) version, checked by
    the laws of that operation, and its result appended (and checked by the
    query laws): a branching history.
    :meth:`check_all` applies the persistence law to every version.
    """

    cfg: SuiteConfig
    kind: KeyKind
    versions: list[tuple[Any, dict[Any, Any]]] = field(default_factory=list)
    used: list[Any] = field(default_factory=list)

    def __post_init__(self) -> None:
        s = self.cfg.structure
        e = law_empty(s, self.probes())
        self._checked(e, "empty")
        self.versions.append((e, {}))

    def probes(self) -> list[Any]:
        """Every key used so far (the colliding integers among them, once used) and two others."""
        return [*extra_probes(self.kind), *self.used]

    def key(self, i: int) -> Any:
        """The key of kind ``kind`` made from the integer ``i``."""
        return i if self.kind == "int" else CollidingKey(i)

    def nonempty(self) -> list[int]:
        """Indices of the versions that hold at least one item."""
        return [i for i, (_, snap) in enumerate(self.versions) if snap]

    def _checked(self, m: Any, what: str) -> None:
        if self.cfg.check:
            law_invariants(self.cfg.structure, m, f"after {what}")

    def _use(self, k: Any) -> None:
        if k not in self.used:
            self.used.append(k)

    def _add(self, m: Any, snap: dict[Any, Any], k: Any, what: str) -> None:
        """Check the new version ``m`` (made by an operation on key ``k``) and append it."""
        law_listItemsi(self.cfg.structure, m, self.probes())
        self._checked(m, what)
        self.versions.append((m, snap))
        self.observe(len(self.versions) - 1, k)

    def insert(self, i: int, k: Any, v: Any) -> None:
        """``insert`` into version ``i``, checked by find_insert, find_insert_other, numItems_insert, listItemsi."""
        s = self.cfg.structure
        m, snap = self.versions[i]
        self._use(k)
        m2 = s.insert(m, k, v)
        law_numItems_insert(s, m, k, v, result=(m2,))
        law_find_insert(s, m, k, v, result=(m2,))
        law_find_insert_other(s, m, k, v, [*snap, *self.probes()], result=(m2,))
        self._add(m2, {**snap, k: v}, k, f"insert into version {i}")

    def insert_with(self, i: int, k: Any, v: Any) -> None:
        """``insertWith`` into version ``i``, checked by the insertWith law."""
        s = self.cfg.structure
        m, snap = self.versions[i]
        self._use(k)
        m2 = law_insertWith(s, combine, m, k, v, [*snap, *self.probes()])
        self._add(m2, {**snap, k: combine(snap[k], v) if k in snap else v}, k, f"insertWith into version {i}")

    def remove(self, i: int, k: Any) -> None:
        """``remove`` of the present key ``k`` from version ``i``, checked by the remove law."""
        s = self.cfg.structure
        m, snap = self.versions[i]
        m2, _ = law_remove(s, m, k)
        self._add(m2, {kk: vv for kk, vv in snap.items() if kk != k}, k, f"remove from version {i}")

    def remove_absent(self, i: int, k: Any) -> None:
        """``remove`` of the absent key ``k`` from version ``i``: NotFound, version untouched."""
        self._use(k)
        law_remove_absent(self.cfg.structure, self.versions[i][0], k)

    def observe(self, i: int, k: Any) -> None:
        """The query laws (lookup, inDomain, listKeys, foldli, isEmpty) on version ``i`` and key ``k``."""
        s = self.cfg.structure
        m = self.versions[i][0]
        law_lookup(s, m, k)
        law_inDomain(s, m, k)
        law_listKeys(s, m)
        law_foldli(s, m)
        law_isEmpty(s, m)

    def check_all(self) -> None:
        """The persistence law over every version made so far."""
        law_persistence(self.cfg.structure, self.versions, self.probes())

