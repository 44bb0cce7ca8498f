"""Two tools for telling a structure's hidden state from its versions: a second instance, and ballast.

A structure whose answers depend only on the versions and arguments it is given
answers a replay of the same operations the same way — on another instance of
the structure, and whatever other objects are alive at the time.  The suites'
``determinism`` and ``isolation`` tests, and the replays that confirm every
failure of the growth workloads (:mod:`.growth`), vary exactly those two
things:

* :func:`second_instance` — another instance configured like the structure:
  a new one when the user gave a class (the suite instantiates it), else a
  deep copy of a snapshot taken when the suite started (:func:`snapshots`),
  before any test could fill its caches; state kept at class level stays
  shared — that is what the ``isolation`` law is about;
* :class:`Ballast` — objects kept alive between the operations of a replay, so
  that the memory of freed versions, and with it their ``id``, is reused
  differently than in the first run;
* :class:`Holding` — a structure that answers as another one does and keeps
  every version it returns alive, so that no id is reused while a test is
  rerun on it;
* :func:`same_observation` — whether a rerun saw what the first run saw: the
  same text but for the memory addresses of Python's default ``repr``, which a
  rerun moves by design.
"""

from __future__ import annotations

import copy
import inspect
import re
from collections.abc import Callable
from typing import Any

__all__ = ["Ballast", "Holding", "fresh_for", "same_observation", "second_instance", "snapshots"]

_ADDRESS = re.compile(r"\b0x[0-9a-fA-F]+\b")
"""A hexadecimal address, as Python's default ``repr`` prints one (``<Node object at 0x7f3a…>``)."""


def same_observation(first: str, again: str) -> bool:
    """Whether two failure reports say the same once memory addresses are set aside.

    A failure's text shows the values the structure returned, and an outside
    backend's map values often print with Python's default ``repr``, which names
    the object's address.  A rerun makes its objects elsewhere (that is what the
    second instance and the ballast are for), so the addresses differ even when
    the structure gave exactly the same wrong answer; comparing them would report
    a plainly wrong structure under ``determinism``.  Every other character must
    match.  O(len(first) + len(again)).

    >>> same_observation("returned (<Node object at 0x7f01>, None)", "returned (<Node object at 0x7e99>, None)")
    True
    >>> same_observation("returned (<Node object at 0x7f01>, None)", "returned (<Node object at 0x7f01>, 3)")
    False
    """
    return first == again or _ADDRESS.sub("0x…", first) == _ADDRESS.sub("0x…", again)


def snapshots(structure: Any) -> Callable[[], Any] | None:
    """A function making deep copies of ``structure`` as it is *now* (a snapshot is taken at once), or None
    when it cannot be deep-copied.

    A copy keeps the configuration and whatever the instance holds at the time
    of the snapshot (its caches before any test filled them), and shares what
    its class holds.
    """
    try:
        snapshot = copy.deepcopy(structure)
    except Exception:
        return None

    def deep_copy() -> Any:
        return copy.deepcopy(snapshot)

    return deep_copy


def fresh_for(given: object, structure: Any) -> Callable[[], Any] | None:
    """How the suite makes second instances of ``structure``, which the user gave as ``given``: the class
    itself when it is one, else :func:`snapshots` of ``structure`` taken now (None: it cannot be copied)."""
    if isinstance(given, type):
        return given
    return snapshots(structure)


def second_instance(structure: Any, fresh: Callable[[], Any] | None) -> tuple[Any | None, str]:
    """Another instance of the structure and how it was made (for messages), or ``(None, why not)``.

    ``fresh`` makes it: the class the user gave, or :func:`snapshots`'s
    function; None when the structure could not be copied.
    """
    if fresh is None:
        try:
            copy.deepcopy(structure)
        except Exception as exc:
            why = f"{type(exc).__name__}: {exc}"
        else:
            why = "no snapshot was taken"
        return None, (
            f"the structure cannot be deep-copied ({why}); give its class (the suite instantiates it with no "
            "arguments) to test it against a second instance"
        )
    how = (
        f"a second instance, {fresh.__name__}()"
        if isinstance(fresh, type)
        else "a second instance, a deep copy of the structure as it was when the suite started"
    )
    try:
        return fresh(), how
    except Exception as exc:
        return None, f"making {how} raised {type(exc).__name__}: {exc}"


class Ballast:
    """Small objects allocated and kept alive at each :meth:`drop` of a replay, released with the ballast.

    CPython reuses the memory of a freed object for the next object of its
    size, so a run that frees versions as it goes gives later versions the ids
    of earlier ones, in a pattern fixed by the run.  A replay that keeps
    ballast breaks that pattern: a cache keyed by ``id`` that returned a stale
    answer in the first run returns another one, or none, in the replay.
    """

    def __init__(self) -> None:
        self._held: list[object] = []

    def drop(self) -> None:
        """Allocate the objects of one step: tuples of the sizes persistent structures are made of."""
        i = len(self._held)
        self._held.append((i, i))
        self._held.append((i, i, i, i, i))
        self._held.append([i])


class Holding:
    """The structure ``inner``, answering as it does, that keeps alive every value its operations return.

    While a test reruns on it, no version is freed, so no new version takes
    the id of an old one: a structure whose answers depend on ids answers
    correctly (a rerun on a fresh instance that passes where the first run
    failed shows the answers depend on something besides the versions).  At
    most ``bound`` values are held (the memory of a rerun of a large workload
    stays bounded); attributes that are not routines (sub-structures such as
    ``Key`` or ``Simplex``) are the inner structure's own.
    """

    def __init__(self, inner: Any, bound: int = 20_000) -> None:
        self._inner = inner
        self._bound = bound
        self._held: list[object] = []

    def __getattr__(self, name: str) -> Any:
        attr = getattr(self._inner, name)
        if not inspect.isroutine(attr):
            return attr
        held = self._held
        bound = self._bound

        def holding(*args: Any, **kwargs: Any) -> Any:
            out = attr(*args, **kwargs)
            if len(held) < bound:
                held.append(out)
            return out

        return holding

    def __repr__(self) -> str:
        return f"Holding({self._inner!r})"
