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
* ``qhull_options`` — as in scipy, given options *replace* scipy's defaults
  (``Delaunay``: ``Qbb Qc Qz Q12``; ``ConvexHull``: none), ``Qt`` always on.
  persistri runs no Qhull: every decision is exact, so the options that tune
  Qhull's floating-point robustness or its output's shape
  (:data:`MOOT_QHULL_OPTIONS`) change nothing here and are accepted.  For
  ``Delaunay``, ``Qbb`` and ``Qz`` (:data:`LIFTING_OPTIONS`) set the lifting's
  constants as they set scipy's (``paraboloid_scale``, ``paraboloid_shift``, and so
  ``equations`` and ``plane_distance``; ``QJ`` implies ``Qbb`` there and
  drops ``Qz``, as in Qhull): ``qhull_options="Qt"`` lifts to ``|x|²`` itself, as
  scipy's does.  Any other option would change what scipy computes in a way
  persistri does not, and is a :class:`ValueError` naming it — among them ``QbB``
  (scipy's measures are then those of the input rescaled to a unit cube), and, for
  ``ConvexHull``, ``Qbb`` (scipy's volume, area and equations are then those of the
  input with its last coordinate rescaled) and ``Qz`` (an error in scipy).

>>> check_qhull_options("Qbb Qc Qz Q12", "Delaunay")
>>> delaunay_lifting(None), delaunay_lifting("Qt"), delaunay_lifting("Qbb"), delaunay_lifting("QJ Qz")
((True, True), (False, False), (True, False), (True, False))
>>> check_qhull_options("QG4", "ConvexHull")
Traceback (most recent call last):
...
ValueError: ConvexHull: qhull_options 'QG4' would change the result, and persistri runs no Qhull (accepted, since exact arithmetic makes them moot: Pp, Q12, QJ, Qc, Qs, Qt, Qx, Tv)
"""

from __future__ import annotations

from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "MOOT_QHULL_OPTIONS", "LIFTING_OPTIONS", "check_qhull_options", "delaunay_lifting", "keeps_coplanar", "lifting_constants",
    "closed_error",
]

MOOT_QHULL_OPTIONS: Final[dict[str, str]] = {
    "Qc": "keep coplanar points with their nearest facet (here every distinct point is a vertex)",
    "Qx": "exact pre-merges of facets that round-off made non-convex",
    "Q12": "allow wide facets and duplicated ridges caused by round-off",
    "Qt": "triangulated output (persistri's output is always triangulated)",
    "QJ": "joggle the input to avoid precision problems (persistri decides degeneracies exactly, by Simulation of Simplicity)",
    "Pp": "do not report precision problems",
    "Qs": "search all points for the initial simplex (where the run starts changes no exact result)",
    "Tv": "verify the result (persistri's check=True verifies it exactly)",
}
"""Qhull options that only tune floating-point robustness or ask for triangulated output: moot under exact
arithmetic (option → what it asks of Qhull)."""

LIFTING_OPTIONS: Final[dict[str, str]] = {
    "Qbb": "scale the lifted coordinate to [0, the largest absolute coordinate]",
    "Qz": "add a point at infinity, 1.1 times the largest lifted coordinate high (with Qbb: part of the scaling)",
}
"""``Delaunay``'s options that set scipy's lifting constants (scipy's defaults among them): accepted there, and
followed (:func:`delaunay_lifting`)."""

_REFUSED: Final[dict[tuple[str, str], str]] = {
    ("QbB", "ConvexHull"): "scipy's volume, area and equations are then those of the input rescaled to a unit cube",
    ("QbB", "Delaunay"): "scipy's equations and lifting are then those of the input rescaled to a unit cube",
    ("Qbb", "ConvexHull"): "scipy's volume, area and equations are then those of the input with its last "
    "coordinate rescaled (Qbb is Delaunay's)",
    ("Qz", "ConvexHull"): "it is an error in scipy (Qhull takes Qz with Delaunay only)",
}


def _options(options: str | bytes | None, what: str) -> list[str]:
    if options is None:
        return []
    if not isinstance(options, (str, bytes)):
        raise TypeError(f"{what}: qhull_options must be a string (or None), not {type(options).__name__}")
    text = options.decode("ascii", "replace") if isinstance(options, bytes) else options
    return text.split()


def check_qhull_options(options: str | bytes | None, what: str) -> None:
    """Accept ``options`` (None, or Qhull options separated by spaces) if every one is in :data:`MOOT_QHULL_OPTIONS`
    (or, for ``what == "Delaunay"``, in :data:`LIFTING_OPTIONS`).

    Raises :class:`TypeError` for a non-string, :class:`ValueError` naming the
    options that would change the result (and why, for those scipy users pass
    believing them harmless).  O(len(options)).
    """
    given = _options(options, what)
    for o in given:
        why = _REFUSED.get((o, what))
        if why is not None:
            raise ValueError(f"{what}: qhull_options {o!r} would change the result: {why}; persistri computes "
                             f"the input's own {'hull' if what == 'ConvexHull' else 'triangulation'}")
    accepted = MOOT_QHULL_OPTIONS.keys() | (LIFTING_OPTIONS.keys() if what == "Delaunay" else set())
    other = [o for o in given if o not in accepted]
    if other:
        raise ValueError(
            f"{what}: qhull_options {' '.join(repr(o) for o in other)} would change the result, and persistri runs "
            f"no Qhull (accepted, since exact arithmetic makes them moot: {', '.join(sorted(accepted))})"
        )


def delaunay_lifting(options: str | bytes | None) -> tuple[bool, bool]:
    """``(Qbb, Qz)``: whether ``Delaunay``'s lifting scales the lifted coordinate, and whether the scaling counts
    Qhull's point at infinity, as scipy's under these ``qhull_options`` (already checked).

    None is scipy's defaults (both); given options replace them.  ``QJ`` implies ``Qbb`` and drops ``Qz``
    (Qhull's rule for a joggled Delaunay triangulation).  O(len(options)).
    """
    if options is None:
        return True, True
    given = set(_options(options, "Delaunay"))
    if "QJ" in given:
        return True, False
    return "Qbb" in given, "Qz" in given


def keeps_coplanar(options: str | bytes | None, what: str) -> bool:
    """Whether scipy's ``coplanar`` lists anything under these ``qhull_options`` (already checked): Qhull keeps
    the points it leaves out only with ``Qc``, among scipy's defaults for ``Delaunay`` but not for ``ConvexHull``.

    None is scipy's defaults; given options replace them.  O(len(options)).

    >>> keeps_coplanar(None, "ConvexHull"), keeps_coplanar("Qc", "ConvexHull"), keeps_coplanar(None, "Delaunay")
    (False, True, True)
    >>> keeps_coplanar("Qt", "Delaunay"), keeps_coplanar("Qbb Qc Qz Q12", "Delaunay")
    (False, True)
    """
    if options is None:
        return what == "Delaunay"
    return "Qc" in _options(options, what)


def lifting_constants(points: NDArray[Any], qbb: bool, qz: bool) -> tuple[float, float]:
    """``(paraboloid_scale, paraboloid_shift)`` of ``points`` (``(n, 2)``) as scipy's under options with or without
    ``Qbb`` and ``Qz`` (:func:`delaunay_lifting`).

    With both (scipy's defaults), :func:`~persistri.impl.geometry.barycentric.paraboloid_scaling`; with ``Qbb``
    alone, ``scale = M / (hi − lo)`` (no point at infinity: ``lo``/``hi`` the least/greatest ``|x|²``, ``M`` the
    largest absolute coordinate) and ``shift = −lo·scale``; without ``Qbb``, ``(1.0, 0.0)``: the lifting is ``|x|²``
    itself.  Where the scaling is undefined (every ``|x|²`` equal: scipy refuses such cocircular input under
    ``Qbb`` alone; overflow), ``(1.0, 0.0)``.  O(n).
    """
    from persistri.impl.geometry.barycentric import paraboloid_scaling

    if not qbb:
        return 1.0, 0.0
    if qz:
        return paraboloid_scaling(points)
    with np.errstate(over="ignore", invalid="ignore"):
        sq = (points * points).sum(axis=1)
        low, high = float(sq.min()), float(sq.max())
        reach = float(np.abs(points).max())
        room = high - low
        if not (np.isfinite(room) and np.isfinite(reach)) or room <= 0.0 or reach == 0.0:
            return 1.0, 0.0
        scale = reach / room
        return scale, -low * scale


def closed_error(what: str) -> RuntimeError:
    """The error of ``add_points`` on an object whose incremental mode ``close()`` ended (scipy's behaviour)."""
    return RuntimeError(
        f"{what}.add_points: this {what} was made with incremental=True and then closed; close() ends incremental "
        f"mode (as scipy's), so it can no longer change — make a new one, or use one made without incremental=True, "
        f"whose add_points returns a new {what}"
    )
