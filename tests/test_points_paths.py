"""A file name given where an array is expected is named as such, not taken for a 0-d array."""

from __future__ import annotations

import pathlib

import pytest

import persistri


@pytest.mark.parametrize("call", [persistri.convex_hull, persistri.Delaunay], ids=["convex_hull", "Delaunay"])
def test_a_path_is_refused_with_a_hint_to_read_it(call: object, tmp_path: pathlib.Path) -> None:
    path = tmp_path / "points.csv"
    path.write_text("0,0,0\n1,0,0\n0,1,0\n0,0,1\n")
    with pytest.raises(TypeError, match=r"points must be an array of real numbers, not \w*Path \(a file name"):
        call(path)  # type: ignore[operator]
