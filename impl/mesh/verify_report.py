"""What the exact mesh checker reports: the kinds of problem, one problem, the report, and the log that fills it.

:func:`~persistri.impl.mesh.verify.verify_mesh` returns a :class:`MeshReport`: the
problems it found (:class:`MeshProblem`, each of one of :data:`PROBLEM_KINDS`, in the
order the checks run), their counts, and the quality the mesh reaches.  The checks
write into it through a :class:`ProblemLog`.  The names are importable from
:mod:`~persistri.impl.mesh.verify` too, where they were first defined.  Plain
values; O(1) per problem.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import NamedTuple

__all__ = ["PROBLEM_KINDS", "MeshVerificationError", "MeshProblem", "MeshReport", "ProblemLog"]

PROBLEM_KINDS = (
    "input",
    "domain",
    "orientation",
    "missing-vertex",
    "coincident",
    "segment",
    "segment-rounding",
    "edge",
    "boundary",
    "outside",
    "area",
    "delaunay",
    "angle",
    "area-bound",
)
"""The kinds of :class:`MeshProblem`, in the order the checks run (module docstring)."""


class MeshVerificationError(AssertionError):
    """A mesh failed :func:`verify_mesh`; the message lists what is wrong."""


class MeshProblem(NamedTuple):
    """One thing wrong with a mesh: its ``kind`` (one of :data:`PROBLEM_KINDS`) and a message."""

    kind: str
    message: str

    def __str__(self) -> str:
        return f"{self.kind}: {self.message}"


@dataclass
class MeshReport:
    """What :func:`verify_mesh` found: ``ok`` when ``problems`` is empty.

    ``problems`` keeps at most ``max_problems`` of each kind; ``counts`` has
    them all.  Quality: ``min_angle`` over all triangles and
    ``min_angle_unexempt`` over those not exempt (degrees, for reading:
    decisions are exact), ``exempt`` triangles below ``min_angle`` at small
    input angles, ``max_area``.  ``domain_area`` and ``mesh_area`` are exact;
    ``area_rounding`` is the area between the segments and the chains through
    rounded split points (0 for exact meshes).
    """

    triangles: int = 0
    vertices: int = 0
    problems: list[MeshProblem] = field(default_factory=list)
    counts: dict[str, int] = field(default_factory=dict)
    min_angle: float | None = None
    min_angle_unexempt: float | None = None
    exempt: int = 0
    max_area: float | None = None
    domain_area: Fraction | None = None
    mesh_area: Fraction | None = None
    area_rounding: Fraction = Fraction(0)
    split_vertices: int = 0
    rounded_split_vertices: int = 0
    constrained_edges: int = 0

    @property
    def ok(self) -> bool:
        return not self.problems

    def kinds(self) -> set[str]:
        """The kinds of problem found."""
        return set(self.counts)

    def raise_if_failed(self) -> None:
        """Raise :class:`MeshVerificationError` listing the problems, if any."""
        if self.problems:
            raise MeshVerificationError("not a valid mesh of the domain:\n  " + "\n  ".join(map(str, self.problems)))

    def __str__(self) -> str:
        if self.problems:
            total = sum(self.counts.values())
            return f"not a valid mesh ({total} problem{'s' if total != 1 else ''}): {self.problems[0]}"
        quality = ""
        if self.min_angle is not None:
            quality = f", min angle {self.min_angle:.4g}°"
            if self.exempt:
                quality += f" ({self.exempt} exempt at small input angles; {self.min_angle_unexempt:.4g}° elsewhere)"
        if self.max_area is not None:
            quality += f", max area {self.max_area:.4g}"
        rounded = f", {self.rounded_split_vertices} rounded split vertices" if self.rounded_split_vertices else ""
        return f"valid mesh: {self.triangles} triangles, {self.vertices} vertices{quality}{rounded}"


class ProblemLog:
    """Collects the problems of one check into its report: all counted, at most ``limit`` of each kind kept. O(1) each."""

    def __init__(self, rep: MeshReport, limit: int) -> None:
        self.rep = rep
        self.limit = limit

    def problem(self, kind: str, message: str) -> None:
        counts = self.rep.counts
        counts[kind] = counts.get(kind, 0) + 1
        if counts[kind] <= self.limit:
            self.rep.problems.append(MeshProblem(kind, message))

    def any(self, kinds: tuple[str, ...]) -> bool:
        """Whether a problem of one of ``kinds`` was found."""
        return any(k in self.rep.counts for k in kinds)
