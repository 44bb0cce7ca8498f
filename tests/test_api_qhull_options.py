"""``qhull_options`` side by side with scipy: given options *replace* scipy's defaults.

scipy documents ``Delaunay``'s defaults as ``Qbb Qc Qz Q12`` and says given
options replace them, so ``Delaunay(pts, qhull_options="Qt")`` lifts without
``Qbb`` and ``Qz``: other ``paraboloid_scale``/``paraboloid_shift``, and so other
``equations`` and ``plane_distance``.  persistri follows the same options
(:func:`persistri._scipy_options.delaunay_lifting`), and refuses those whose
scipy results are of a rescaled input (``QbB``; ``Qbb`` on ``ConvexHull``) or an
error in scipy (``Qz`` on ``ConvexHull``).

scipy runs in a subprocess: in scipy 1.17 a ``ConvexHull`` with ``Qbb`` leaves
Qhull's last-coordinate scaling on for every later ``ConvexHull`` of the process
(the default options included), which would leak into other tests.
"""

from __future__ import annotations

import json
import subprocess
import sys
from typing import Any

import numpy as np
import pytest

import persistri

POINTS = (np.random.default_rng(1).random((50, 2)) * 10 + [3, 5]).tolist()
POINTS3 = (np.random.default_rng(1).random((60, 3)) * 10 + [3, 5, 7]).tolist()
DELAUNAY_OPTIONS: list[str | None] = [
    None, "", "Qt", "Qbb", "Qz", "Qbb Qz", "Qz Qbb", "Qbb Qc Qz Q12", "Qbb Qc Qz Qx Q12", "QJ", "QJ Qz", "Qbb Qz QJ",
    "Qc Qx", "Qz Qbb Pp Qs Tv",
]

_SCIPY = """
import json, sys
import numpy as np
from scipy.spatial import ConvexHull, Delaunay
args = json.loads(sys.stdin.read())
out = {"delaunay": [], "hull": {}}
for o in args["options"]:
    d = Delaunay(np.array(args["points"]), qhull_options=o)
    out["delaunay"].append({"scale": d.paraboloid_scale, "shift": d.paraboloid_shift,
                            "simplices": d.simplices.tolist(), "equations": d.equations.tolist()})
pts3 = np.array(args["points3"])
out["hull"]["default"] = ConvexHull(pts3).volume  # first: before the Qbb run below changes later ones
for o in ("Qz", "Qbb", "QbB"):
    try:
        out["hull"][o] = ConvexHull(pts3, qhull_options=o).volume
    except Exception as e:
        out["hull"][o] = "error: " + type(e).__name__
print(json.dumps(out))
"""


@pytest.fixture(scope="module")
def scipy_runs() -> dict[str, Any]:
    data = json.dumps({"options": DELAUNAY_OPTIONS, "points": POINTS, "points3": POINTS3})
    done = subprocess.run([sys.executable, "-c", _SCIPY], input=data, capture_output=True, text=True, timeout=300, check=True)
    result: dict[str, Any] = json.loads(done.stdout)
    return result


@pytest.mark.parametrize("k", range(len(DELAUNAY_OPTIONS)), ids=[repr(o) for o in DELAUNAY_OPTIONS])
def test_delaunay_lifts_as_scipy_under_the_same_options(scipy_runs: dict[str, Any], k: int) -> None:
    options = DELAUNAY_OPTIONS[k]
    ref = scipy_runs["delaunay"][k]
    tri = persistri.Delaunay(POINTS, qhull_options=options)
    joggled = options is not None and "QJ" in options.split()  # scipy's constants are of the joggled input
    rel = 1e-6 if joggled else 1e-13
    assert tri.paraboloid_scale == pytest.approx(ref["scale"], rel=rel)
    assert tri.paraboloid_shift == pytest.approx(ref["shift"], rel=rel, abs=rel)
    # The same triangles (general position), each with scipy's plane through its lifted vertices.
    mine = {tuple(sorted(s)): e for s, e in zip(tri.simplices.tolist(), tri.equations.tolist())}
    theirs = {tuple(sorted(s)): e for s, e in zip(ref["simplices"], ref["equations"])}
    if joggled:  # scipy's triangles are of the joggled input (with Qz, a few more): compare those both have
        common = mine.keys() & theirs.keys()
        assert len(common) >= 0.8 * len(mine)
        theirs = {key: theirs[key] for key in common}
    else:
        assert mine.keys() == theirs.keys()
    for key, e in theirs.items():
        assert mine[key] == pytest.approx(e, rel=1e-6 if joggled else 1e-9, abs=1e-9), key


def test_without_qbb_the_lifting_is_the_squared_norm() -> None:
    tri = persistri.Delaunay(POINTS, qhull_options="Qt")
    x = np.array(POINTS[:3])
    assert (tri.paraboloid_scale, tri.paraboloid_shift) == (1.0, 0.0)
    assert tri.lift_points(x)[:, 2].tolist() == (x * x).sum(axis=1).tolist()
    at = tri.find_simplex(x + 1e-3)
    assert np.all(np.abs(tri.plane_distance(x)[np.arange(3), tri.find_simplex(x)]) < 1e-9)
    assert np.all(at >= 0)


@pytest.mark.parametrize("incremental", [False, True])
def test_add_points_keeps_the_options(incremental: bool) -> None:
    pts = np.array(POINTS)
    for options in ("Qt", "Qbb", None):
        first = persistri.Delaunay(pts[:30], incremental=incremental, qhull_options=options)
        more = first.add_points(pts[30:])
        whole = persistri.Delaunay(pts, qhull_options=options)
        assert (more.paraboloid_scale, more.paraboloid_shift) == (whole.paraboloid_scale, whole.paraboloid_shift)
        again = more.add_points(pts[:1], restart=True)
        assert again.paraboloid_scale == persistri.Delaunay(np.vstack([pts, pts[:1]]), qhull_options=options).paraboloid_scale


def test_options_whose_scipy_results_are_of_a_rescaled_input_are_refused(scipy_runs: dict[str, Any]) -> None:
    hull = scipy_runs["hull"]
    exact = persistri.ConvexHull(POINTS3).volume
    assert hull["default"] == pytest.approx(exact, rel=1e-12)
    assert hull["Qbb"] != pytest.approx(exact, rel=1e-3) and hull["QbB"] != pytest.approx(exact, rel=1e-3)
    assert hull["Qz"].startswith("error")
    for options, why in (("Qbb", "last coordinate rescaled"), ("QbB", "unit cube"), ("Qt Qz", "an error in scipy")):
        with pytest.raises(ValueError, match=f"ConvexHull: qhull_options '{options.split()[-1]}' would change the result: .*{why}"):
            persistri.ConvexHull(POINTS3, qhull_options=options)
    with pytest.raises(ValueError, match="Delaunay: qhull_options 'QbB' would change the result: .*unit cube"):
        persistri.Delaunay(POINTS, qhull_options="Qbb Qz QbB")
    for options in ("Qt", "Qx", "QJ", "Qc Q12 Pp Qs Tv"):  # still moot for the hull
        assert persistri.ConvexHull(POINTS3, qhull_options=options).volume == exact
