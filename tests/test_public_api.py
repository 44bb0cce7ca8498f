"""``import persistri``: the public names, their laziness, ``__version__``, and which build they come from.

The hull and the triangulation themselves are tested in ``test_public_api_hull.py``
and ``test_public_api_delaunay.py``.
"""

from __future__ import annotations

import doctest
import importlib
import importlib.metadata
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import persistri

HEAVY = ("numpy", "scipy", "matplotlib", "meshio", "hypothesis", "dask", "distributed", "rich", "click", "tifffile")


def fresh(code: str) -> dict[str, list[str]]:
    """Run ``code`` in a new interpreter (this one has imported everything already); it prints a JSON object."""
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True, env=os.environ.copy())
    assert out.stderr == "", out.stderr
    result: dict[str, list[str]] = json.loads(out.stdout)
    return result


PROBE = """
import json, sys
{setup}
heavy = [m for m in {heavy!r} if m in sys.modules]
mine = sorted(m for m in sys.modules if m.startswith("persistri"))
print(json.dumps({{"heavy": heavy, "persistri": mine}}))
"""


def test_import_persistri_imports_nothing_heavy() -> None:
    got = fresh(PROBE.format(setup="import persistri", heavy=HEAVY))
    assert got == {"heavy": [], "persistri": ["persistri"]}


def test_names_load_on_first_use_and_only_what_they_need() -> None:
    got = fresh(PROBE.format(setup="import persistri; persistri.maps.red_black; persistri.conformance", heavy=HEAVY))
    assert got["heavy"] == []  # the maps are pure Python; the suite's module defers hypothesis to its first name
    assert "persistri.spec.conformance" not in got["persistri"] and "persistri.impl.maps.red_black" in got["persistri"]
    got = fresh(PROBE.format(setup="import persistri; persistri.ConvexHull", heavy=HEAVY))
    assert got["heavy"] == ["numpy"]  # the hull needs numpy, and nothing else heavy
    got = fresh(PROBE.format(setup="import persistri; persistri.triangulate; persistri.verify_mesh; persistri.read_poly", heavy=HEAVY))
    assert got["heavy"] == ["numpy"]  # quality meshes need numpy only: Triangle and matplotlib stay out
    assert "persistri.impl.mesh.plot" not in got["persistri"] and "persistri.impl.cli.mesh" not in got["persistri"]
    got = fresh(PROBE.format(setup="import persistri; persistri.__version__", heavy=HEAVY))
    assert got["persistri"] == ["persistri"] and got["heavy"] == []


def test_version_is_the_installed_distributions() -> None:
    assert persistri.__version__ == importlib.metadata.version("persistri")
    assert persistri.__version__.count(".") >= 2


def test_version_falls_back_when_not_installed(monkeypatch: pytest.MonkeyPatch) -> None:
    def missing(name: str) -> str:
        raise importlib.metadata.PackageNotFoundError(name)

    monkeypatch.setattr(importlib.metadata, "version", missing)
    assert persistri._version() == "0+unknown"


def test_all_and_dir_agree_and_every_name_resolves() -> None:
    assert sorted(persistri.__all__) == dir(persistri)
    assert len(set(persistri.__all__)) == len(persistri.__all__)
    for name in persistri.__all__:
        assert getattr(persistri, name) is not None, name
    assert persistri.maps is importlib.import_module("persistri.maps")
    assert persistri.spec is importlib.import_module("persistri.spec")
    assert persistri.convex_hull is importlib.import_module("persistri.impl.hull.api").convex_hull
    with pytest.raises(AttributeError, match="module 'persistri' has no attribute 'ConvexHul'"):
        persistri.ConvexHul  # type: ignore[attr-defined]  # noqa: B018


def test_the_mesh_names_are_the_deep_objects_and_mesh_a_poly_file(tmp_path: Path) -> None:
    from persistri.impl.mesh import api, domain, polyfile, verify

    assert (persistri.triangulate, persistri.refine, persistri.QualityMesh) == (api.triangulate, api.refine, api.QualityMesh)
    assert (persistri.PSLG, persistri.read_poly) == (domain.PSLG, polyfile.read_poly)
    assert (persistri.verify_mesh, persistri.MeshReport) == (verify.verify_mesh, verify.MeshReport)
    # A unit square with a square hole, in Triangle's .poly format (numbered from 1).
    poly = tmp_path / "frame.poly"
    poly.write_text(
        "8 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 0 4\n5 1 1\n6 3 1\n7 3 3\n8 1 3\n"
        "8 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 5 6\n6 6 7\n7 7 8\n8 8 5\n1\n1 2 2\n"
    )
    frame = persistri.read_poly(poly)
    mesh = persistri.triangulate(frame, min_angle=30)
    report = persistri.verify_mesh(frame, mesh.vertices, mesh.triangles, min_angle=30)
    assert report.ok and report.mesh_area == 12
    finer = persistri.refine(mesh, min_angle=30, max_area=0.5)
    assert finer.history[0] is mesh.complex and len(finer.triangles) > len(mesh.triangles)
    assert persistri.verify_mesh(frame, finer.vertices, finer.triangles, min_angle=30, max_area=0.5).ok


def test_star_import_gives_exactly_the_public_names() -> None:
    scope: dict[str, object] = {}
    exec("from persistri import *", scope)
    assert sorted(k for k in scope if k != "__builtins__") == sorted(persistri.__all__)


def test_maps_and_conformance_are_the_deep_objects() -> None:
    from persistri.impl.maps.red_black import red_black
    from persistri.spec.conformance import OrdMapConformance

    assert persistri.maps.red_black is red_black
    assert set(persistri.maps.__all__) <= set(dir(persistri.maps))
    assert persistri.conformance.OrdMapConformance is OrdMapConformance
    assert dir(persistri.conformance) == sorted(importlib.import_module("persistri.spec.conformance").__all__)
    assert persistri.conformance.__all__ == importlib.import_module("persistri.spec.conformance").__all__
    with pytest.raises(AttributeError):
        persistri.conformance.__wrapped__  # type: ignore[attr-defined]  # noqa: B018  - probes of dunders do not import the suite


def test_the_package_is_api_folder_and_typed() -> None:
    """In the strict editable install (or the twin) ``persistri`` is the api/ folder, a regular package, typed."""
    path = Path(persistri.__file__ or "")
    assert path.name == "__init__.py" and (path.parent / "py.typed").exists()
    assert (path.parent / "impl").is_dir() and (path.parent / "spec").is_dir()


def test_the_twin_is_what_runs() -> None:
    """``make test`` runs the suite on the compiled twin with PERSISTRI_TWIN set: then persistri itself, its
    public names included, must come from the twin, and its compiled modules must be extension modules."""
    from persistri.impl.hull import bulldozer

    twin = os.environ.get("PERSISTRI_TWIN")
    if twin:
        root = Path(os.environ["PYTHONPATH"].split(os.pathsep)[0]).resolve()
        assert Path(persistri.__file__ or "").resolve().is_relative_to(root)
        assert Path(sys.modules[persistri.ConvexHull.__module__].__file__ or "").resolve().is_relative_to(root)
        assert not str(bulldozer.__file__).endswith(".py")
    else:
        assert str(bulldozer.__file__).endswith(".py")
    assert persistri.ConvexHull([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]).volume == 1 / 6


@pytest.mark.parametrize("module", ["persistri", "persistri._hull", "persistri._delaunay", "persistri.maps"])
def test_docstring_examples(module: str) -> None:
    """The public modules' examples run (``make test`` runs the doctests of persistri.spec and persistri.impl)."""
    result = doctest.testmod(importlib.import_module(module), optionflags=doctest.ELLIPSIS)
    assert result.failed == 0
    if module != "persistri":
        assert result.attempted > 0


def test_the_typed_consumer_runs() -> None:
    """``tests/typing/consumer.py`` (type-checked by ``make typecheck``) also runs: its asserts hold, it prints nothing."""
    consumer = Path(__file__).resolve().parent / "typing" / "consumer.py"
    out = subprocess.run([sys.executable, str(consumer)], capture_output=True, text=True, env=os.environ.copy())
    assert (out.returncode, out.stdout, out.stderr) == (0, "", "")
