"""persistri.spec — the signatures of *Persistent Triangulations*, their laws, and a conformance suite.

The paper's SML signatures, transcribed literally as :class:`typing.Protocol` s:

* :class:`OrdKey` / :class:`OrdMap` — the SML/NJ library's ``ORD_KEY`` and ``ORD_MAP``
  (the subset the complexes need);
* :class:`VERTEX`, :class:`SIMPLEX`, :class:`SIMPCOMP` — the paper's Figs. 1–3.

Their laws are executable (:mod:`persistri.spec.ord_map_laws`, …) and the
conformance suite (:mod:`persistri.spec.conformance`) runs them against any
structure.  Nothing in ``spec`` depends on ``persistri.impl``.
"""

from persistri.spec.option import NONE, SOME, Option, isSome, valOf
from persistri.spec.ord_map import ORD_MAP, NotFound, OrdMap
from persistri.spec.order import NATURAL_ORDER, ORD_KEY, Comparable, NaturalOrder, Order, OrdKey
from persistri.spec.simpcomp import SIMPCOMP
from persistri.spec.simplex import SIMPLEX
from persistri.spec.vertex import VERTEX

__all__ = [
    "Order",
    "OrdKey",
    "ORD_KEY",
    "Comparable",
    "NaturalOrder",
    "NATURAL_ORDER",
    "Option",
    "SOME",
    "NONE",
    "isSome",
    "valOf",
    "OrdMap",
    "ORD_MAP",
    "NotFound",
    "VERTEX",
    "SIMPLEX",
    "SIMPCOMP",
]
