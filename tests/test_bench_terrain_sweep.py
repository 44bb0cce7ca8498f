"""persistri bench terrain's error sweep: the maximum errors of both meshers over many vertex counts."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from persistri.impl.bench.terrain_sweep import ErrorSweep, canonical_mesh, error_sweep, max_error, pydelatin_mesh, sweep_counts
from persistri.impl.cli.main import main
from persistri.impl.terrain.check import mesh_errors
from persistri.impl.terrain.greedy import greedy_insertion
from persistri.impl.terrain.grids import jacksboro
from persistri.impl.terrain.synthetic import synthetic_dem


def test_sweep_counts_are_log_spaced_from_lo_to_hi() -> None:
    ks = sweep_counts(100, 10_000, 5)
    assert ks == [100, 316, 1000, 3162, 10_000]
    assert sweep_counts(10, 12, 10) == [10, 11, 12]  # duplicates merged
    assert sweep_counts(30, 30, 7) == [30] and sweep_counts(20, 40, 1) == [20, 40]
    for lo, hi, n in ((3, 10, 4), (10, 9, 4), (10, 20, 0)):
        with pytest.raises(ValueError):
            sweep_counts(lo, hi, n)


def test_equal_meshes_written_differently_have_the_same_error_bit_for_bit() -> None:
    h = synthetic_dem(33, seed=5).heights  # non-integer heights: the interpolation rounds
    tin = greedy_insertion(h, max_points=60)
    e = max_error(h, tin.vertices, tin.triangles)
    rng = np.random.default_rng(1)
    perm = rng.permutation(tin.n_points)  # the vertices in another order, triangles renumbered
    xy = tin.vertices[perm][:, :2]
    inverse = np.argsort(perm)
    tri = inverse[tin.triangles]
    tri = np.roll(tri, 1, axis=1)  # another starting vertex
    tri[::2] = tri[::2, ::-1]  # half of them clockwise
    tri = tri[rng.permutation(len(tri))]
    assert max_error(h, xy, tri) == e
    # Every sample's error, not only the largest: written as given, 84 of them differ in the last bits.
    assert np.array_equal(mesh_errors(h, *canonical_mesh(h, xy, tri))[0], mesh_errors(h, *canonical_mesh(h, tin.vertices, tin.triangles))[0])
    assert not np.array_equal(mesh_errors(h, tin.vertices[perm], tri)[0], mesh_errors(h, tin.vertices, tin.triangles)[0])
    vertices, canon = canonical_mesh(h, xy, tri)
    assert np.array_equal(vertices[:, 2], h[vertices[:, 1].astype(int), vertices[:, 0].astype(int)])
    samples = (vertices[:, 1] * h.shape[1] + vertices[:, 0]).astype(int)[canon]
    assert (samples[:, 0] < samples[:, 1]).all() and (samples[:, 0] < samples[:, 2]).all()
    x, y = vertices[canon, 0], vertices[canon, 1]
    assert ((x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0]) - (y[:, 1] - y[:, 0]) * (x[:, 2] - x[:, 0]) > 0).all()
    # The same error as the independent measure up to rounding.
    err, cover = mesh_errors(h, tin.vertices, tin.triangles)
    assert (cover > 0).all() and e == pytest.approx(float(err.max()), rel=1e-12)


def test_error_sweep_measures_both_meshers_at_each_count() -> None:
    h = jacksboro().heights[:60, :70]
    counts = sweep_counts(12, 60, 5)
    tin = greedy_insertion(h, max_points=counts[-1])
    assert tin.history is not None
    sweep = error_sweep(h, counts, tin.history)
    assert sweep.counts == tuple(counts)  # pydelatin stops at exactly max_points here
    for k, theirs, ours, best in zip(sweep.counts, sweep.pydelatin, sweep.persistri, sweep.persistri_best):
        # pydelatin's mesh measured independently (its own float32 heights are exact: integer DEM).
        xy, tri = pydelatin_mesh(h, k)
        v = np.column_stack([xy, h[xy[:, 1].astype(int), xy[:, 0].astype(int)]])
        assert theirs == pytest.approx(float(mesh_errors(h, v, tri)[0].max()), rel=1e-12)
        # persistri's level equals a fresh run stopped there.
        assert ours == pytest.approx(greedy_insertion(h, max_points=k).max_error, rel=1e-12)
        assert best <= ours + 1e-12 * ours
        assert best == pytest.approx(float(np.min(tin.history.max_errors[: k - 3])), rel=1e-12)
    r = sweep.ratios()
    assert np.array_equal(r, np.array(sweep.persistri) / np.array(sweep.pydelatin))
    assert sweep.quartiles() == tuple(float(q) for q in np.quantile(r, [0.25, 0.5, 0.75]))
    lower, equal, higher = sweep.shares()
    assert lower + equal + higher == pytest.approx(1.0)
    assert lower == np.mean(np.array(sweep.persistri) < np.array(sweep.pydelatin))
    doc = sweep.as_dict()
    assert doc["counts"] == counts and doc["ratio_median"] == sweep.quartiles()[1]
    assert "5 counts log-spaced from 12 to 60" in sweep.summary()


def test_shares_count_ties_as_ties() -> None:
    s = ErrorSweep((10, 20, 30, 40), (2.0, 2.0, 2.0, 2.0), (1.0, 2.0, 2.0, 3.0), (1.0, 1.5, 2.0, 2.0))
    assert s.shares() == (0.25, 0.5, 0.25)
    assert s.shares(best=True) == (0.5, 0.5, 0.0)
    assert s.quartiles()[1] == 1.0 and s.quartiles(best=True)[1] == 0.875


def test_bench_terrain_prints_and_writes_the_sweep(tmp_path: Path) -> None:
    np.save(tmp_path / "g.npy", jacksboro().heights[:50, :60])
    grid = str(tmp_path / "g.npy")
    result = CliRunner().invoke(main, ["bench", "terrain", "--grid", grid, "--sizes", "12,40", "--sweep", "4", "--json"])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    sweep = doc["sweep"]
    assert sweep["counts"] == sweep_counts(12, 40, 4)
    assert len(sweep["pydelatin_errors"]) == len(sweep["persistri_errors"]) == 4
    # The sizes' own rows are the sweep's end points, measured the same way.
    assert doc["records"][0]["pydelatin_error"] == sweep["pydelatin_errors"][0]
    assert doc["records"][-1]["persistri_error"] == sweep["persistri_errors"][-1]
    table = CliRunner().invoke(main, ["bench", "terrain", "--grid", grid, "--sizes", "12,40", "--sweep", "4"])
    assert table.exit_code == 0, table.output
    assert "max error at equal vertex count, 4 counts log-spaced from 12 to 40" in " ".join(table.stdout.split())
    off = CliRunner().invoke(main, ["bench", "terrain", "--grid", grid, "--sizes", "12", "--sweep", "0", "--json"])
    assert off.exit_code == 0, off.output
    assert "sweep" not in json.loads(off.stdout)
