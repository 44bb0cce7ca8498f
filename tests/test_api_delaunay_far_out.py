"""``Delaunay``'s float measurements far out (coordinates near 1e300, where ``|x|²`` exceeds the doubles).

Qhull refuses such input (QH6019); persistri's decisions are exact, and its lifting measurements are
computed on the points scaled by a power of two: no numpy warning escapes, and under ``Qbb`` (scipy's
default) they are those of the scaled-down points, scaled back — finite.  Without ``Qbb`` the lifting
``|x|²`` itself is beyond the doubles: infinite, as documented, still without a warning.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import persistri

K = 990  # 2^990 ≈ 1e298: the points below reach about 1e300


def _points(seed: int) -> np.ndarray:
    return np.random.default_rng(seed).random((40, 2)) * 8.0


def _measured(d: persistri.Delaunay, xi: np.ndarray) -> tuple[np.ndarray, ...]:
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the float lifting overflowed with RuntimeWarnings
        return d.equations, d.lift_points(xi), d.plane_distance(xi), np.array([d.paraboloid_scale, d.paraboloid_shift])


@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize("options", [None, "Qbb", "Qbb Qz"])
def test_under_qbb_far_out_is_near_scaled_by_a_power_of_two(seed: int, options: str | None) -> None:
    """Scaling by 2^K is exact and every float step rounds alike at either scale: the measurements far out are
    those near the origin, scaled — normals equal, offsets, lifts and distances times 2^K, scale times 2^-K."""
    near = _points(seed)
    far = np.ldexp(near, K)
    dn, df = persistri.Delaunay(near, qhull_options=options), persistri.Delaunay(far, qhull_options=options)
    assert np.array_equal(dn.simplices, df.simplices)
    en, ln, pn, cn = _measured(dn, near[:5])
    ef, lf, pf, cf = _measured(df, far[:5])
    for a in (ef, lf, pf):
        assert np.isfinite(a).all()
    assert np.array_equal(ef[:, :3], en[:, :3]) and np.array_equal(ef[:, 3], np.ldexp(en[:, 3], K))
    assert np.array_equal(lf, np.ldexp(ln, K)) and np.array_equal(pf, np.ldexp(pn, K))
    assert cf[0] == math.ldexp(cn[0], -K) and cf[1] == math.ldexp(cn[1], K)


def test_near_the_largest_double_as_near_the_origin_scaled() -> None:
    """Up to 1.7e308: the lifting and planes are finite; a distance beyond the doubles is ±inf (never NaN), and
    every one is that of the points scaled by 2^-1024, scaled back — up to rounding: paraboloid_scale, about
    2^-1024, is a subnormal double there, with fewer bits."""
    far = np.array([[-1.7e308, -1.7e308], [1.7e308, -1.7e308], [0.0, 1.7e308], [1e300, 1e300], [-3e307, 5e307]])
    near = np.ldexp(far, -1024)  # exact: 1e300 becomes about 5.6e-9
    ef, lf, pf, cf = _measured(persistri.Delaunay(far), far)
    en, ln, pn, cn = _measured(persistri.Delaunay(near), near)
    assert np.isfinite(ef).all() and np.isfinite(lf).all() and np.isfinite(cf).all()
    assert np.allclose(ef[:, :3], en[:, :3], rtol=1e-9, atol=1e-15)
    assert np.allclose(np.ldexp(ef[:, 3], -1024), en[:, 3], rtol=1e-9, atol=1e-15)
    with np.errstate(over="ignore"):
        beyond = np.abs(np.ldexp(pn, 1024)) > 1.79e308
    assert beyond.any() and np.array_equal(np.isinf(pf), beyond) and not np.isnan(pf).any()
    assert np.allclose(np.ldexp(pf[~beyond], -1024), pn[~beyond], rtol=1e-6, atol=1e-15)


def test_without_qbb_the_lifting_is_infinite_far_out_without_a_warning() -> None:
    """``qhull_options="Qt"`` lifts to ``|x|²`` itself: beyond the doubles at 1e300, so lift_points is inf, and the
    planes and distances are not finite (documented), yet no warning escapes; the exact decisions stand."""
    far = np.ldexp(_points(0), K)
    d = persistri.Delaunay(far, qhull_options="Qt")
    _, lift, dist, consts = _measured(d, far[:5])
    assert consts.tolist() == [1.0, 0.0]
    assert np.isinf(lift[:, 2]).all() and np.array_equal(lift[:, :2], far[:5])
    assert not np.isfinite(dist).any()  # the lifted points are infinite (the planes may be NaN: documented)
    assert np.array_equal(d.simplices, persistri.Delaunay(_points(0), qhull_options="Qt").simplices)
