"""The exact test for many pairs of objects at once (geometry/object_pairs.py) gives ``occludes_one``'s answer to
the bit, on the sweep's shifted edges and on edges in map coordinates with the observer given (the VisiLibity
engine's), over random boxes snapped to coarse grids (shared vertices, edges through the observer, touching and
overlapping boxes)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from omega_prime_visibility.engines.sweep.crossings import prepare_frame
from omega_prime_visibility.engines.sweep.pieces import object_extents, shifted_object_edges
from omega_prime_visibility.geometry.object_pairs import objects_occluded
from omega_prime_visibility.geometry.occlusion import occludes_one
from omega_prime_visibility.geometry.rings import angular_extent, box_rings


@pytest.mark.parametrize("seed", range(4))
def test_on_the_sweeps_shifted_edges_it_is_occludes_one(seed: int) -> None:
    """On the sweep's shifted edges (the observer at the origin) the test gives ``occludes_one``'s answer for every
    pair, also on coordinates snapped to a coarse grid (shared vertices, edges through the observer, touching and
    overlapping boxes)."""
    rng = np.random.default_rng(seed)
    n = 40
    rings = box_rings(
        rng.uniform(-12, 12, n), rng.uniform(-8, 8, n), rng.uniform(1, 6, n), rng.uniform(1, 3, n),
        rng.choice([0.0, 0.5 * math.pi, rng.uniform(-3, 3)], n),
    )  # fmt: skip
    coords = np.round(rings.coords * (2 if seed % 2 else 1e6)) / (2 if seed % 2 else 1e6)
    offsets = rings.offsets.astype(np.int64)
    observer = np.array([[0.0, 0.0]]) if seed < 2 else coords[[3]]  # seeds 2, 3: on a box's corner
    no_statics = np.zeros((0, 2))
    grid = (np.zeros(3), np.ones(2, dtype=np.int64), np.zeros(2, dtype=np.int64), np.zeros(0, dtype=np.int64))
    empty = np.zeros(0, dtype=np.int64)
    nxt, _, _, y, x = prepare_frame(observer, coords, offsets, no_statics, no_statics, *grid, empty, empty)
    seg = shifted_object_edges(coords, nxt, observer[0, 0], observer[0, 1])
    start, width = object_extents(offsets, np.arctan2(y, x)[0])
    target, body = (a.ravel() for a in np.meshgrid(np.arange(n), np.arange(n), indexing="ij"))
    target, body = target[target != body], body[target != body]
    fast = objects_occluded(seg, offsets, start, width, target, body, 0.0, 0.0)
    exact = [
        occludes_one(0.0, 0.0, seg, offsets[j], offsets[j + 1], offsets[t], offsets[t + 1], start[t], width[t])
        for t, j in zip(target.tolist(), body.tolist(), strict=True)
    ]
    assert 0 < np.count_nonzero(exact) < len(exact)
    assert np.array_equal(fast, exact)


@pytest.mark.parametrize("seed", range(4))
def test_in_map_coordinates_with_the_observer_given_it_is_occludes_one(seed: int) -> None:
    rng = np.random.default_rng(seed)
    n = 40
    far = np.array([6.1e5, -5.3e6]) if seed % 2 else np.array([1024.0, 0.0])
    rings = box_rings(
        rng.uniform(-12, 12, n), rng.uniform(-8, 8, n), rng.uniform(1, 6, n), rng.uniform(1, 3, n),
        rng.choice([0.0, 0.5 * math.pi, rng.uniform(-3, 3)], n),
    )  # fmt: skip
    coords = np.round(rings.coords * 4) / 4 + far
    offsets = rings.offsets.astype(np.int64)
    observer = far + (0.0 if seed < 2 else np.round(rng.uniform(-3, 3, 2) * 4) / 4)
    nxt = np.roll(np.arange(4), -1)
    seg = np.concatenate([np.stack([coords[4 * i : 4 * i + 4], coords[4 * i + nxt]], axis=1) for i in range(n)])
    start, width, _ = angular_extent(observer, type(rings)(coords, offsets))
    inside = width >= 2 * math.pi - 1e-9  # boxes holding the observer are no targets
    target, body = (a.ravel() for a in np.meshgrid(np.arange(n), np.arange(n), indexing="ij"))
    keep = (target != body) & ~inside[target]
    target, body = target[keep], body[keep]
    ox, oy = observer.tolist()
    fast = objects_occluded(seg, offsets, start, width, target, body, ox, oy)
    exact = [
        occludes_one(ox, oy, seg, offsets[j], offsets[j + 1], offsets[t], offsets[t + 1], start[t], width[t])
        for t, j in zip(target.tolist(), body.tolist(), strict=True)
    ]
    assert 0 < np.count_nonzero(exact) < len(exact)
    assert np.array_equal(fast, exact)
