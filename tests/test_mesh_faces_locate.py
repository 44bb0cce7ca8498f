"""Point location in a PSLG's faces takes doubles without Fraction objects (impl/mesh/faces.py).

``PlanarFaces.locate`` scales a pair of doubles to integers directly (``_dyadic``); a pair of
Fractions goes through ``Fraction`` arithmetic.  Both must name the same face, vertex or segment
for the same point: here every point is located both ways, on vertices, on segments, in holes,
outside, and at scales from 2^-300 to 2^400.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from persistri.impl.mesh.faces import _dyadic, planar_faces


@pytest.mark.parametrize("scale", [1.0, 2.0**-300, 3.0, 1e6, 2.0**400])
def test_doubles_and_fractions_locate_alike(scale: float) -> None:
    # a square with a square hole and a crack into it
    V = np.array([[0, 0], [8, 0], [8, 8], [0, 8], [2, 2], [6, 2], [6, 6], [2, 6], [4, 0]], dtype=float) * scale
    S = np.array([[0, 8], [8, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4], [8, 4]])
    faces = planar_faces(V, S)
    rng = np.random.default_rng(3)
    pts = np.vstack([rng.integers(-2, 20, size=(300, 2)) / 2, V / scale, rng.random((100, 2)) * 9 - 0.5]) * scale
    kinds = set()
    for x, y in pts.tolist():
        a = faces.locate(x, y)
        b = faces.locate(Fraction(x), Fraction(y))
        assert a == b
        kinds.add("vertex" if a.vertex is not None else "segment" if a.segment is not None else a.face)
    assert {"vertex", "segment", -1} <= kinds and len(kinds) >= 4  # on the graph, outside, and in faces


def test_dyadic_is_fraction_arithmetic() -> None:
    rng = np.random.default_rng(4)
    xs = [0.0, -0.0, 1.0, -3.5, 0.1, 5e-324, 1.7e308, 4.0] + (rng.standard_normal(200) * 10.0 ** rng.integers(-300, 300, 200)).tolist()
    for x in xs:
        for e in (-1080, -3, 0, 2, 1000):
            f = Fraction(x) / Fraction(2) ** e
            assert _dyadic(x, e) == (f.numerator, f.denominator)


def _nested_squares(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Squares at random places and sizes, none touching another: side by side, nested, or both."""
    V: list[list[float]] = []
    S: list[list[int]] = []
    placed: list[tuple[int, int, int]] = []
    for _ in range(int(rng.integers(2, 9))):
        size = int(rng.integers(1, 6))
        x, y = (int(v) for v in rng.integers(0, 24, size=2))
        box = (x, y, size)

        def apart(a: tuple[int, int, int], b: tuple[int, int, int]) -> bool:
            (ax, ay, asz), (bx, by, bsz) = a, b
            outside = ax + asz < bx or bx + bsz < ax or ay + asz < by or by + bsz < ay
            a_in_b = bx < ax and ax + asz < bx + bsz and by < ay and ay + asz < by + bsz
            b_in_a = ax < bx and bx + bsz < ax + asz and ay < by and by + bsz < ay + asz
            return outside or a_in_b or b_in_a

        if all(apart(box, other) for other in placed):
            placed.append(box)
            k = len(V)
            V += [[x, y], [x + size, y], [x + size, y + size], [x, y + size]]
            S += [[k, k + 1], [k + 1, k + 2], [k + 2, k + 3], [k + 3, k]]
    return np.array(V, dtype=float), np.array(S)


def test_nesting_with_few_and_many_faces_alike(monkeypatch: pytest.MonkeyPatch) -> None:
    """The components' nesting found with the loop over boxes and with numpy's passes: the same faces."""
    from persistri.impl.mesh import faces as faces_module

    rng = np.random.default_rng(6)
    graphs = [_nested_squares(rng) for _ in range(120)]

    def fields(V: np.ndarray, S: np.ndarray) -> tuple[object, ...]:
        f = planar_faces(V, S)
        return (f.walks, f.walk_area2, f.face_of_walk.tolist(), f.face_walk.tolist(), f.face_area2,
                f.component_of_segment.tolist(), f.component_parent.tolist())

    few = [fields(V, S) for V, S in graphs]
    monkeypatch.setattr(faces_module, "FEW_FACES", -1)
    many = [fields(V, S) for V, S in graphs]
    assert few == many
    assert any(max(f[6]) >= 0 for f in few)  # some component nested in a face
