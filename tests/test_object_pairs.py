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


@pytest.mark.parametrize("seed", range(3))
def test_a_ray_beyond_the_missed_margin_misses_the_body(seed: int) -> None:
    """``missed_margin``'s bound, which lets the test pass over pieces that miss the body: every ray whose
    direction lies outside a body's angular extent by more than the margin misses it by ``_nearest_edge``, for boxes
    seen from afar, from a micrometre away and from within a ten-thousandth of a millimetre of a corner's line (where
    the edges' slack is felt), in small and in map coordinates; rays just inside the extent hit it."""
    from omega_prime_visibility.geometry.object_pairs import missed_margin
    from omega_prime_visibility.geometry.occlusion import _nearest_edge

    rng = np.random.default_rng(seed)
    far = np.array([6.1e5, -5.3e6]) if seed == 2 else np.zeros(2)
    n = 300
    rings = box_rings(np.zeros(n), np.zeros(n), rng.uniform(0.5, 20, n), rng.uniform(0.5, 3, n), rng.uniform(-3, 3, n))
    gap = 10.0 ** rng.uniform(-7, 2, n)  # the observer this far beyond a random vertex, along a random direction
    tested = 0
    for i in range(n):
        box = rings.coords[4 * i : 4 * i + 4] + far
        seg = np.stack([box, np.roll(box, -1, axis=0)], axis=1)
        turn = rng.uniform(-math.pi, math.pi)
        observer = box[rng.integers(4)] + gap[i] * np.array([math.cos(turn), math.sin(turn)])
        start, width, _ = angular_extent(observer, type(rings)(box, np.array([0, 4])))
        if width[0] >= math.pi:  # (the observer inside the box, or on an edge's line)
            continue
        margin = missed_margin(seg, 0, 4, observer[0], observer[1])
        if not np.isfinite(margin):
            continue
        tested += 1
        for beyond in (1.01, 2.0, 1e3):
            for direction in (start[0] - beyond * margin, start[0] + width[0] + beyond * margin):
                d = (math.cos(direction), math.sin(direction))
                assert _nearest_edge(observer[0], observer[1], *d, seg, 0, 4) == -1
        inside = start[0] + 0.5 * width[0]
        assert _nearest_edge(observer[0], observer[1], math.cos(inside), math.sin(inside), seg, 0, 4) >= 0
    assert tested > n // 2
