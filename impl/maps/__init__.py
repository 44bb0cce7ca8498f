"""Persistent map backends, each an ``ORD_MAP`` structure (:class:`persistri.spec.OrdMap`).

=====================  ==============================================  ============================
name                   structure                                       module
=====================  ==============================================  ============================
``assoc_list``         sorted association list (teaching baseline)     :mod:`.assoc_list`
``red_black``          Okasaki red-black tree, Kahrs deletion          :mod:`.red_black`
``hamt``               Bagwell hash array mapped trie                  :mod:`.hamt`
``red_black_arena``    the red-black tree in an append-only arena      :mod:`.red_black_arena`
                       (compact histories; old nodes never freed)
``immutables``         adapter for ``immutables.Map`` (C HAMT)         :mod:`.immutables_adapter`
``pyrsistent``         adapter for ``pyrsistent.pmap``                 :mod:`.pyrsistent_adapter`
``int_trie``           persistent radix trie over integer keys         :mod:`.int_trie`
                       (no key comparisons; integer keys only)
=====================  ==============================================  ============================

:func:`backend` resolves a name to its structure (importing the module on first use,
so an adapter's third-party package is needed only when it is asked for).
"""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["BACKENDS", "UnknownBackendError", "backend"]

BACKENDS: dict[str, str] = {
    "assoc_list": "persistri.impl.maps.assoc_list:assoc_list",
    "red_black": "persistri.impl.maps.red_black:red_black",
    "hamt": "persistri.impl.maps.hamt:hamt",
    "red_black_arena": "persistri.impl.maps.red_black_arena:red_black_arena",
    "immutables": "persistri.impl.maps.immutables_adapter:immutables_map",
    "pyrsistent": "persistri.impl.maps.pyrsistent_adapter:pyrsistent_map",
    "int_trie": "persistri.impl.maps.int_trie:int_trie",
}
"""Backend name → ``module:attribute`` of its structure."""


class UnknownBackendError(ValueError):
    """A backend name that is not in :data:`BACKENDS`."""


def backend(name: str) -> Any:
    """The ``ORD_MAP`` structure called ``name``; :class:`UnknownBackendError` names the known ones.

    Returns ``Any`` because the structure is polymorphic in keys and values
    (an ``OrdMap[K, V, M]`` for every ``K`` and ``V``).
    """
    try:
        target = BACKENDS[name]
    except KeyError:
        known = ", ".join(sorted(BACKENDS))
        raise UnknownBackendError(f"unknown map backend {name!r}; known backends: {known}") from None
    module_name, attr = target.split(":")
    try:
        module = importlib.import_module(module_name)
    except ImportError as exc:
        raise UnknownBackendError(
            f"map backend {name!r} needs a package that is not installed ({exc.name}); "
            "install persistri[adapters]"
        ) from None
    return getattr(module, attr)
