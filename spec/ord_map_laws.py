"""The laws of ``signature ORD_MAP``, as executable code.

Each ``law_*`` function checks one law of :class:`~persistri.spec.ord_map.OrdMap`
on the inputs it is given and raises :class:`LawViolation` (an
:class:`AssertionError`, via :class:`persistri.spec.law.LawViolation`, carrying
the law's name and its one-line statement) when the structure breaks it.  :data:`ORD_MAP_LAWS` lists every law by name; the
conformance suite (:mod:`persistri.spec.conformance`) drives these functions
with hypothesis, and its reports name the law that failed.

The laws are stated *algebraically*, in terms of the structure's own
operations (``find(insert(m, k, v), j) = find(m, j)``), so they need no model of
what ``m`` contains; only :func:`law_persistence` compares versions with model
snapshots.  Conventions:

* ``SOME v`` is the 1-tuple ``(v,)`` and ``NONE`` is ``None``
  (:mod:`persistri.spec.option`); a ``find`` that returns anything else breaks
  the law being checked;
* values are compared with ``is`` or ``==``, keys with ``Key.compare`` (and the
  keys the suite uses satisfy ``compare(a, b) = EQUAL`` exactly when ``a == b``:
  :func:`law_key_order` checks it);
* a law that performs the operation itself also checks that the operation left
  its operand unchanged, and reports a change under ``persistence``; the laws
  of ``insert`` accept the operation's ``result`` (as ``SOME m2``) when the
  caller has already computed it, so that one ``insert`` can be checked by
  several laws;
* an unexpected exception from the structure inside a law is reported as a
  violation of that law (the original exception is chained).

Costs are stated per function; ``n`` is ``numItems(m)`` and a ``find`` is
counted as one operation of the structure.

The laws live in modules by group of signature entries, all re-exported here
(import them from this module):

* :mod:`persistri.spec.ord_map_laws_base`: :data:`ORD_MAP_LAWS`,
  :class:`LawViolation` and the helpers the laws share;
* :mod:`persistri.spec.ord_map_laws_insert`: ``Key.compare``, ``empty``,
  ``singleton``, ``insert``/``find``, ``lookup``, ``inDomain``, ``insertWith``,
  ``numItems``;
* :mod:`persistri.spec.ord_map_laws_contents`: ``remove`` and the whole-map
  views ``listItemsi``, ``listKeys``, ``foldli``, ``isEmpty``;
* :mod:`persistri.spec.ord_map_laws_versions`: persistence and ``_check``.
"""

from __future__ import annotations

from persistri.spec.ord_map_laws_base import ORD_MAP_LAWS, LawViolation
from persistri.spec.ord_map_laws_contents import (
    law_foldli,
    law_isEmpty,
    law_listItemsi,
    law_listKeys,
    law_remove,
    law_remove_absent,
)
from persistri.spec.ord_map_laws_insert import (
    law_empty,
    law_find_insert,
    law_find_insert_other,
    law_inDomain,
    law_insertWith,
    law_key_order,
    law_lookup,
    law_numItems_insert,
    law_singleton,
)
from persistri.spec.ord_map_laws_versions import law_invariants, law_persistence

__all__ = [
    "ORD_MAP_LAWS",
    "LawViolation",
    "law_key_order",
    "law_empty",
    "law_singleton",
    "law_find_insert",
    "law_find_insert_other",
    "law_lookup",
    "law_inDomain",
    "law_insertWith",
    "law_numItems_insert",
    "law_remove",
    "law_remove_absent",
    "law_listItemsi",
    "law_listKeys",
    "law_foldli",
    "law_isEmpty",
    "law_persistence",
    "law_invariants",
]
