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

import math
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "MOOT_QHULL_OPTIONS", "LIFTING_OPTIONS", "check_qhull_options", "delaunay_lifting", "keeps_coplanar", "lifting_constants",
    "lifted", "lifted_planes", "closed_error",
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
    itself.  Where some ``|x|²`` is beyond the doubles (coordinates near 1e154 and beyond), the same formulas on
    the points scaled by a power of two, scaled back (``scale`` about ``1/M``, both finite: Qhull itself
    refuses such input).  Where the scaling is undefined (every ``|x|²`` equal: scipy refuses such cocircular
    input under ``Qbb`` alone), ``(1.0, 0.0)``.  O(n).
    """
    from persistri.impl.geometry.barycentric import paraboloid_scaling

    if not qbb:
        return 1.0, 0.0
    with np.errstate(over="ignore", invalid="ignore"):
        sq = (points * points).sum(axis=1)
        over = sq.size > 0 and not bool(np.isfinite(sq).all() and np.isfinite(1.1 * sq.max()))
    if over:  # |x|² (or Qhull's point at infinity, 1.1·max |x|²) beyond the doubles
        return _scaled_constants(points, qz)
    if qz:
        return paraboloid_scaling(points)
    low, high = float(sq.min()), float(sq.max())
    reach = float(np.abs(points).max())
    room = high - low
    if not np.isfinite(room) or room <= 0.0 or reach == 0.0:
        return 1.0, 0.0
    scale = reach / room
    return scale, -low * scale


def _scaled_constants(points: NDArray[Any], qz: bool) -> tuple[float, float]:
    """:func:`lifting_constants` under ``Qbb`` where ``|x|²`` overflows: computed on ``x·2^-k`` (``2^k`` about the
    largest coordinate; each step rounds as the unscaled one would with an unbounded exponent), then
    ``scale·2^-k`` and ``shift·2^k``. O(n)."""
    k = int(np.frexp(np.abs(points).max())[1])
    x = np.ldexp(points, -k)
    with np.errstate(under="ignore"):
        sq = (x * x).sum(axis=1)
    low, high = float(sq.min()), float(sq.max())
    reach = float(np.abs(x).max())
    room = (1.1 * high if qz else high) - low
    if room <= 0.0 or reach == 0.0:
        return 1.0, 0.0
    scale = reach / room
    return math.ldexp(scale, -k), math.ldexp(-low * scale, k)


def lifted(x: NDArray[np.float64], scale: float, shift: float) -> NDArray[np.float64]:
    """``x`` (``(k, 2)``) lifted, ``(k, 3)``: :func:`~persistri.impl.geometry.barycentric.paraboloid_lift`, and for
    the rows whose ``|x|²`` overflows, the lifting of ``x·2^-j`` by ``(scale·2^j, shift·2^-j)`` (which is
    ``2^-j`` times theirs) scaled back: finite wherever the lifted value is a double (under ``Qbb``, always);
    ``±inf`` where it is not (``|x|²`` itself, without ``Qbb``, beyond 1.8e308).  No numpy warning.  O(k).
    """
    from persistri.impl.geometry.barycentric import paraboloid_lift

    with np.errstate(all="ignore"):
        z = paraboloid_lift(x, scale, shift)
        bad = ~np.isfinite(z[:, 2])
        if bad.any():
            j = int(np.frexp(np.abs(x[bad]).max())[1])
            again = paraboloid_lift(np.ldexp(x[bad], -j), math.ldexp(scale, j), math.ldexp(shift, -j))
            z[bad, 2] = np.ldexp(again[:, 2], j)
    return z


def lifted_planes(points: NDArray[np.float64], simplices: NDArray[Any], scale: float, shift: float) -> NDArray[np.float64]:
    """Each triangle's lifted plane (:func:`~persistri.impl.geometry.barycentric.lifted_equations`); for those
    that overflow, the planes of the points scaled by ``2^-j`` with the lifting of :func:`lifted` (the same unit
    normals; the offsets scaled back by ``2^j``): finite under ``Qbb``; without it, where ``|x|²`` is beyond the
    doubles, vertical (a normal's ``z`` is 0: the lifting is steeper than a double resolves).  No numpy warning.
    O(n + m).
    """
    from persistri.impl.geometry.barycentric import lifted_equations

    with np.errstate(all="ignore"):
        eq = lifted_equations(points, simplices, scale, shift)
        if not bool(np.isfinite(eq).all()):  # one flat pass: the row-wise test only where it fails
            bad = ~np.isfinite(eq).all(axis=1)
            j = int(np.frexp(np.abs(points).max())[1])
            again = lifted_equations(np.ldexp(points, -j), simplices[bad], math.ldexp(scale, j), math.ldexp(shift, -j))
            again[:, 3] = np.ldexp(again[:, 3], j)
            eq[bad] = again
    return eq


def closed_error(what: str) -> RuntimeError:
    """The error of ``add_points`` on an object whose incremental mode ``close()`` ended (scipy's behaviour)."""
    return RuntimeError(
        f"{what}.add_points: this {what} was made with incremental=True and then closed; close() ends incremental "
        f"mode (as scipy's), so it can no longer change — make a new one, or use one made without incremental=True, "
        f"whose add_points returns a new {what}"
    )
