"""persistri.maps — the persistent ``ORD_MAP`` backends, as structures over immutable map values.

Each structure is an object whose methods are the SML/NJ signature's operations
(:class:`persistri.spec.OrdMap`); the map values are plain immutable data, and
every operation returns a new one (persistence).

================  ===================  ===============================================================
structure         its class, values    what
================  ===================  ===============================================================
``assoc_list``    ``AssocListMap``,    sorted association list: the teaching baseline, O(n)
                  ``ALMap``
``red_black``     ``RedBlackMap``,     Okasaki's red-black tree with Kahrs' deletion, O(lg n)
                  ``RBMap``
``hamt``          ``HamtMap``,         Bagwell's hash array mapped trie (keys hashable and ordered)
                  ``HMap``
``red_black_      ``ArenaRedBlack      the same red-black tree, its nodes in an append-only arena of
arena``           Map``, ``ArenaMap``  integer indices: a third of the memory for a kept history, but
                                       nodes of dropped versions are never freed (for histories)
``int_trie``      ``IntTrieMap``,      a radix trie on the bits of integer keys (vertex ids): no key
                  ``TrieMap``          comparisons; the scattered Delaunay's default
================  ===================  ===============================================================

``backend(name)`` resolves any name of :data:`BACKENDS` (the adapters for
``immutables`` and ``pyrsistent`` too, with the ``persistri[adapters]`` extra);
``counted(structure, stats)`` counts dictionary operations and key comparisons
into a :class:`persistri.Stats`.  The classes are generic: ``RedBlackMap[int, str]()``
is the structure at those types, for type-checked code.

>>> from persistri.maps import red_black as rb
>>> m1 = rb.insert(rb.empty(), 3, "three")
>>> rb.find(m1, 3), rb.find(rb.remove(m1, 3)[0], 3)
(('three',), None)
"""

from persistri.impl.maps import BACKENDS, UnknownBackendError, backend
from persistri.impl.maps.assoc_list import ALMap, AssocListMap, assoc_list
from persistri.impl.maps.counted import counted
from persistri.impl.maps.hamt import HamtMap, HMap, hamt
from persistri.impl.maps.int_trie import IntTrieMap, TrieMap, int_trie
from persistri.impl.maps.red_black import RBMap, RedBlackMap, red_black
from persistri.impl.maps.red_black_arena import ArenaMap, ArenaRedBlackMap, red_black_arena

__all__ = [
    "assoc_list",
    "red_black",
    "hamt",
    "red_black_arena",
    "int_trie",
    "AssocListMap",
    "ALMap",
    "RedBlackMap",
    "RBMap",
    "HamtMap",
    "HMap",
    "ArenaRedBlackMap",
    "ArenaMap",
    "IntTrieMap",
    "TrieMap",
    "counted",
    "backend",
    "BACKENDS",
    "UnknownBackendError",
]
