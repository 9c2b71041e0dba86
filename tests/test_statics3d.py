"""threed.statics: footprints raised to heights (walls from below the ground), heights checked, meshes loaded."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from omega_prime_visibility.inputs.statics import load_static_occluders
from omega_prime_visibility.threed.statics import BASE, DEFAULT_HEIGHT, check_heights, static_solids


def test_footprints_become_walls_of_their_height() -> None:
    statics = load_static_occluders([shapely.box(0, 0, 2, 1), shapely.LineString([(5, 0), (5, 3), (6, 3)])])
    solids = static_solids(statics, heights=[3.0, 1.5])
    tri = solids.triangles
    assert tri.shape == (2 * (4 + 2), 3, 3)  # two triangles per edge: 4 ring edges, 2 wall segments
    assert solids.source.tolist() == [0] * 8 + [1] * 4
    assert tri[solids.source == 0][..., 2].max() == 3.0 and tri[solids.source == 1][..., 2].max() == 1.5
    assert tri[..., 2].min() == BASE
    # every wall stands over its footprint's outline
    outline = shapely.MultiLineString([statics.geometries[0].exterior, statics.geometries[1]])
    assert all(outline.distance(shapely.Point(p[:2])) < 1e-12 for p in tri.reshape(-1, 3))


def test_heights_are_checked() -> None:
    assert check_heights(None, 2).tolist() == [DEFAULT_HEIGHT] * 2
    assert check_heights(2.0, 3).tolist() == [2.0] * 3
    with pytest.raises(ValueError, match="gives 2 height"):
        check_heights([1.0, 2.0], 3)
    with pytest.raises(ValueError, match="static occluder 1 has height nan"):
        check_heights([1.0, np.nan], 2)


def test_meshes_are_numbered_after_the_footprints() -> None:
    import trimesh

    statics = load_static_occluders([shapely.box(0, 0, 1, 1)])
    solids = static_solids(statics, meshes=[trimesh.creation.box(extents=(1, 1, 1))])
    assert solids.n_sources == 2 and (solids.source == 1).sum() == 12
