"""Yes/no arguments of the public functions, checked: a string such as ``"no"`` is not taken for True.

Python would read any non-empty string, list or number as true, so ``convex_hull(pts, check="no")``
would check every insertion and ``Delaunay(pts, history="no")`` keep every version: a surprising answer
rather than an error.  :func:`flag` accepts ``True``, ``False`` and NumPy's booleans, and raises a
one-line :class:`TypeError` naming the argument otherwise.  O(1).
"""

from __future__ import annotations

__all__ = ["flag", "type_name"]


def type_name(value: object) -> str:
    """The type of ``value`` as a message names it: ``str``, ``numpy.int64`` (qualified outside the builtins)."""
    kind = type(value)
    return kind.__name__ if kind.__module__ == "builtins" else f"{kind.__module__}.{kind.__qualname__}"


def flag(name: str, value: object) -> bool:
    """``value`` as a bool if it is one (or a NumPy bool), else a :class:`TypeError` naming ``name``.

    >>> flag("history", True), flag("check", False)
    (True, False)
    >>> flag("check", "no")
    Traceback (most recent call last):
    ...
    TypeError: check must be True or False, not str 'no'
    """
    if value is True or value is False:
        return value
    if type(value).__module__ == "numpy" and type(value).__name__ in ("bool", "bool_"):
        return bool(value)
    raise TypeError(f"{name} must be True or False, not {type_name(value)} {value!r:.40}")
