"""The bench gallery: nine deterministic, valid domains; Triangle's q20/q30/q33 meshes of each pass the checker."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
import triangle

from persistri.impl.mesh.domain import as_pslg, domain_of
from persistri.impl.mesh.gallery import GALLERY, gallery, gallery_domain, star, star_tip_angle
from persistri.impl.mesh.verify import verify_mesh


def test_the_gallery_has_the_issue_s_seven_domains_and_two_sharp_ones() -> None:
    assert GALLERY == ("square-hole", "l-shape", "star", "circle", "crack", "utm-tile", "comb", "needle", "fan")
    for g in gallery():
        assert g.description and "\n" not in g.description
        assert g.pslg.notes == ()  # valid as given: nothing merged, split or outside
        again = as_pslg(g.pslg.vertices, g.pslg.segments, g.pslg.holes, repair=False)
        assert np.array_equal(again.segments, g.pslg.segments)


def test_the_gallery_is_deterministic() -> None:
    for a, b in zip(gallery(), gallery()):
        assert np.array_equal(a.pslg.vertices, b.pslg.vertices) and np.array_equal(a.pslg.segments, b.pslg.segments)


def test_gallery_domains_are_what_they_say() -> None:
    assert domain_of(gallery_domain("square-hole").pslg).area == 96
    assert domain_of(gallery_domain("l-shape").pslg).area == 3
    assert domain_of(gallery_domain("crack").pslg).area == 16  # cracks have no area
    assert domain_of(gallery_domain("comb").pslg).area == 12 + 12 * 3 * Fraction(1, 4)
    circle = domain_of(gallery_domain("circle").pslg).area
    assert abs(float(circle) - 96 / 2 * math.sin(2 * math.pi / 96)) < 1e-12
    tile = gallery_domain("utm-tile").pslg
    assert tile.vertices[:, 0].min() == 500_000.0 and tile.vertices[:, 1].min() == 4_000_000.0
    assert np.any(np.isclose(np.diff(np.sort(np.unique(tile.vertices[:, 1]))), 0.05))  # the 5 cm notch
    assert tile.holes.shape == (1, 2)
    n = gallery_domain("needle").pslg
    assert 2 * math.atan2(float(n.vertices[2, 1]), 1.0) == pytest.approx(1e-6, rel=1e-9)
    f = gallery_domain("fan").pslg
    assert f.segments.shape == (9, 2) and domain_of(f).area == 6
    s = gallery_domain("star").pslg
    assert s.vertices.shape == (10, 2)
    assert star_tip_angle(5, float(np.hypot(*s.vertices[1]))) == pytest.approx(20.0, abs=1e-6)


def test_star_tips_are_sharp() -> None:
    for points, tip in ((5, 15.0), (6, 20.0), (7, 25.0)):
        p = star(points, tip)
        v = p.vertices
        a, b, c = v[-1], v[0], v[1]
        u, w = a - b, c - b
        angle = math.degrees(math.acos(float(u @ w) / (np.linalg.norm(u) * np.linalg.norm(w))))
        assert angle == pytest.approx(tip, abs=1e-6)


def test_an_unknown_name_is_a_clear_error() -> None:
    with pytest.raises(KeyError, match="no gallery domain 'moon'; the domains are square-hole, l-shape"):
        gallery_domain("moon")


@pytest.mark.parametrize("name", GALLERY)
@pytest.mark.parametrize("bound", [20, 30, 33])
def test_triangle_meshes_of_the_gallery_pass_the_checker(name: str, bound: int) -> None:
    g = gallery_domain(name)
    out = triangle.triangulate(g.pslg.to_dict(), f"pq{bound}")
    rep = verify_mesh(g.pslg, out["vertices"], out["triangles"], min_angle=bound, exact_segments=False)
    assert rep.ok, (name, bound, rep.problems)
    assert rep.min_angle_unexempt is not None and rep.min_angle_unexempt >= bound
    if name in ("needle", "fan"):
        assert rep.exempt > 0  # input angles of 1e-6 rad: skinny triangles there are forced, and exempt
    elif name != "star":
        assert rep.exempt == 0 and rep.min_angle is not None and rep.min_angle >= bound
    else:
        assert rep.exempt > 0 or bound == 20  # the 20° tips are exempt below the bound
