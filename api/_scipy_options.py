"""scipy.spatial's constructor options, as persistri's ``ConvexHull`` and ``Delaunay`` take them.

scipy's ``ConvexHull(points, incremental=False, qhull_options=None)`` and
``Delaunay(points, furthest_site=False, incremental=False, qhull_options=None)``
are accepted with the same positions and meanings, so code written for scipy
runs unchanged:

* ``incremental=True`` — scipy's incremental mode: ``add_points`` changes the
  object in place (here: it moves to the new version, and the old version stays
  valid underneath — in ``history``, if kept) until ``close()`` ends the mode.
  Without it, persistri's ``add_points`` returns a *new* object and leaves this one
  as it was (scipy would refuse: its ``add_points`` needs incremental mode).
* ``qhull_options`` — persistri runs no Qhull: every decision is exact, so the
  options that tune Qhull's floating-point robustness or its output's shape
  (:data:`MOOT_QHULL_OPTIONS`) change nothing here and are accepted; any other
  option would change what scipy computes in a way persistri does not, and is a
  :class:`ValueError` naming it.

>>> check_qhull_options("Qbb Qc Qz Q12", "Delaunay")
>>> check_qhull_options("QG4", "ConvexHull")
Traceback (most recent call last):
...
ValueError: ConvexHull: qhull_options 'QG4' would change the result, and persistri runs no Qhull (accepted, since exact arithmetic makes them moot: Pp, Q12, QJ, QbB, Qbb, Qc, Qs, Qt, Qx, Qz, Tv)
"""

from __future__ import annotations

from typing import Final

__all__ = ["MOOT_QHULL_OPTIONS", "check_qhull_options", "closed_error"]

MOOT_QHULL_OPTIONS: Final[dict[str, str]] = {
    "Qbb": "scale the last coordinate (Delaunay's lifting) to reduce round-off",
    "Qc": "keep coplanar points with their nearest facet (here every distinct point is a vertex)",
    "Qz": "add a point at infinity, for cospherical input's round-off",
    "Qx": "exact pre-merges of facets that round-off made non-convex",
    "Q12": "allow wide facets and duplicated ridges caused by round-off",
    "Qt": "triangulated output (persistri's output is always triangulated)",
    "QJ": "joggle the input to avoid precision problems (persistri decides degeneracies exactly, by Simulation of Simplicity)",
    "Pp": "do not report precision problems",
    "QbB": "scale the input to the unit cube, for round-off (the input itself is unchanged)",
    "Qs": "search all points for the initial simplex (where the run starts changes no exact result)",
    "Tv": "verify the result (persistri's check=True verifies it exactly)",
}
"""Qhull options that only tune floating-point robustness or ask for triangulated output: moot under exact
arithmetic (option → what it asks of Qhull).  scipy's defaults are among them."""


def check_qhull_options(options: str | bytes | None, what: str) -> None:
    """Accept ``options`` (None, or Qhull options separated by spaces) if every one is in :data:`MOOT_QHULL_OPTIONS`.

    Raises :class:`TypeError` for a non-string, :class:`ValueError` naming the
    options that would change the result.  O(len(options)).
    """
    if options is None:
        return
    if not isinstance(options, (str, bytes)):
        raise TypeError(f"{what}: qhull_options must be a string (or None), not {type(options).__name__}")
    text = options.decode("ascii", "replace") if isinstance(options, bytes) else options
    other = [o for o in text.split() if o not in MOOT_QHULL_OPTIONS]
    if other:
        raise ValueError(
            f"{what}: qhull_options {' '.join(repr(o) for o in other)} would change the result, and persistri runs "
            f"no Qhull (accepted, since exact arithmetic makes them moot: {', '.join(sorted(MOOT_QHULL_OPTIONS))})"
        )


def closed_error(what: str) -> RuntimeError:
    """The error of ``add_points`` on an object whose incremental mode ``close()`` ended (scipy's behaviour)."""
    return RuntimeError(
        f"{what}.add_points: this {what} was made with incremental=True and then closed; close() ends incremental "
        f"mode (as scipy's), so it can no longer change — make a new one, or use one made without incremental=True, "
        f"whose add_points returns a new {what}"
    )
