"""``collector_paused``: Python's cyclic garbage collector off while a run builds persistent structures.

The nodes, lists and data of a persistent complex form no reference cycles
(a version only points at older, immutable objects), so the cyclic collector
finds nothing in them; it only costs time, and a great deal of it: every
collection of the oldest generation traverses every node of every version
still alive.  A run that builds hundreds of thousands of them pauses it.
Reference counting still frees everything that is dropped.
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["collector_paused"]


@contextmanager
def collector_paused(*, promote: bool = True) -> Iterator[None]:
    """The cyclic collector off for the block and restored (if it was on) however the block ends.

    ``promote``: on leaving, move what the block made to the oldest generation
    (``gc.freeze()`` then ``gc.unfreeze()``: two list splices).  CPython keeps every
    object made meanwhile in the young generation, and the next young collection
    would traverse them all (a third of a 5,000-triangle refinement's time); in the
    oldest generation, where they would be after surviving two collections anyway,
    reference counting still frees them and a full collection still sees them.  O(1).
    """
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            if promote:
                gc.freeze()
                gc.unfreeze()
            gc.enable()
