"""The arguments of :func:`~persistri.impl.mesh.api.triangulate` and :func:`~persistri.impl.mesh.api.refine`, checked.

Each check raises the error its docstring names, with one line saying what was
wrong: the domain (:func:`as_domain`: a :class:`~persistri.impl.mesh.domain.PSLG`
or Triangle's dictionary of arrays, validated), the area bound
(:func:`area_bound`), and the refinement's other options
(:func:`refinement_options`).  All O(1) but the domain's validation.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from fractions import Fraction
from typing import Any

from persistri.impl.flags import flag
from persistri.impl.geometry.growing import GrowingPredicates2
from persistri.impl.mesh.domain import PSLG, validate, validate_dict

__all__ = ["area_bound", "as_domain", "refinement_options"]


def as_domain(domain: PSLG | Mapping[str, Any]) -> tuple[PSLG, GrowingPredicates2 | None]:
    """The validated domain, and the predicates its validation made over its vertices (None: it was valid already).

    A :class:`PSLG` that :func:`~persistri.impl.mesh.domain.validate` made is taken as it is (O(1)); any other is
    validated, as a dictionary of arrays is (``PSLG.from_dict``'s checks, errors and repairs).
    """
    if isinstance(domain, PSLG):
        if domain.vertex_map is not None:
            return domain, None
        return validate(domain.vertices, domain.segments, domain.holes, domain.regions)
    if isinstance(domain, Mapping):
        return validate_dict(domain)
    raise TypeError(f"domain must be a PSLG or a dictionary of arrays, not {type(domain).__name__}")


def area_bound(max_area: float | None) -> Fraction | None:
    """``max_area`` as an exact rational (None: no bound); :class:`TypeError` or :class:`ValueError` for a bad one. O(1)."""
    if max_area is None:
        return None
    if isinstance(max_area, bool) or not isinstance(max_area, (int, float)):
        raise TypeError(f"max_area must be a positive real number or None, not {type(max_area).__name__}")
    if not (math.isfinite(max_area) and max_area > 0):
        raise ValueError(f"max_area must be a positive finite number, got {max_area!r}")
    return Fraction(float(max_area))


def refinement_options(max_steiner: object, encroachment: object, **flags: object) -> None:
    """Raise :class:`ValueError` for a ``max_steiner`` or ``encroachment`` that :func:`triangulate` and
    :func:`refine` do not take, and :class:`TypeError` for a yes/no argument (``flags``, by name) that is
    not a bool (:func:`~persistri.impl.flags.flag`). O(1)."""
    for name, value in flags.items():
        flag(name, value)
    if max_steiner is not None and (isinstance(max_steiner, bool) or not isinstance(max_steiner, int) or max_steiner < 0):
        raise ValueError(f"max_steiner must be a nonnegative integer or None, got {max_steiner!r}")
    if encroachment not in ("lens", "circle"):
        raise ValueError(f"encroachment must be 'lens' (Chew's, Triangle's default) or 'circle' (Ruppert's), not {encroachment!r}")
